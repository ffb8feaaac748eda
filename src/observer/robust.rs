//! Robust multi-output observer pole placement in `f64`: Kautsky, Nichols & Van Dooren,
//! "Robust pole assignment in linear state feedback", Int. J. Control 41(5), 1985, method 0.
//!
//! With more than one output the gain is not unique; KNV uses the freedom to make the
//! eigenvectors of the observer matrix as orthogonal as possible, which makes the placed poles
//! as insensitive as possible to perturbations. Applied to the dual: `eig(A − KC) =
//! eig(Aᵀ − CᵀKᵀ)`, so `Kᵀ` is the state feedback of `(Aᵀ, Cᵀ)`.
//!
//! Poles are real or come in complex-conjugate pairs; the iteration runs in complex arithmetic
//! and keeps the eigenvectors of a pair conjugate, so `XΛX⁻¹` is real. Each pole may repeat at
//! most as often as there are outputs (the method's own limit). The result reports its residual:
//! the distance of the computed eigenvalues from the requested ones, and the condition number
//! of the eigenvector matrix.

use crate::linalg::float::eigenvalues;
use nalgebra::{Complex, DMatrix, DVector};
use serde::Serialize;

/// Why a robust placement could not be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RobustError {
    /// Shapes do not fit.
    #[error("A is {a_rows}×{a_cols} and C is {c_rows}×{c_cols}: C must have as many columns as A has rows, A square")]
    Shape {
        /// Rows of A.
        a_rows: usize,
        /// Columns of A.
        a_cols: usize,
        /// Rows of C.
        c_rows: usize,
        /// Columns of C.
        c_cols: usize,
    },
    /// Wrong number of poles.
    #[error("{found} poles given for order {order}")]
    PoleCount {
        /// Poles given.
        found: usize,
        /// Order n.
        order: usize,
    },
    /// A complex pole without its conjugate.
    #[error("the complex pole {0} has no conjugate partner: the gain would not be real")]
    Unpaired(String),
    /// A pole repeated more often than there are outputs.
    #[error("the pole {pole} is repeated {multiplicity} times but there are only {outputs} outputs: no diagonalisable observer matrix has it")]
    Multiplicity {
        /// The pole.
        pole: f64,
        /// How often.
        multiplicity: usize,
        /// Rows of C.
        outputs: usize,
    },
    /// C does not have full row rank, or the eigenvector matrix became singular.
    #[error("the placement failed: {0}")]
    Failed(String),
}

/// A robust placement with its residual.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RobustPlacement {
    /// The gain `K` (n × p) for `A − KC`, row-major.
    pub gain: Vec<Vec<f64>>,
    /// Eigenvalues of `A − KC` as `(re, im)`.
    pub eigenvalues: Vec<(f64, f64)>,
    /// Largest distance between a computed eigenvalue and its requested pole.
    pub residual: f64,
    /// `‖(A − KC) − X Λ X⁻¹‖_F / ‖A‖_F`.
    pub relative_residual: f64,
    /// 2-norm condition number of the eigenvector matrix (smaller is more robust).
    pub eigenvector_condition: f64,
    /// Sweeps of the orthogonalisation performed.
    pub sweeps: usize,
}

type C64 = Complex<f64>;

/// An orthonormal basis of the null space of `m` (r × n), `dim` vectors: the right singular
/// vectors of the smallest singular values (the matrix is padded to square for a full basis).
fn null_basis(m: &DMatrix<C64>, dim: usize) -> Result<DMatrix<C64>, RobustError> {
    let n = m.ncols();
    let mut padded = DMatrix::zeros(n.max(m.nrows()), n);
    padded.view_mut((0, 0), (m.nrows(), n)).copy_from(m);
    let svd = svd(&padded, false, true)?;
    let vt = svd.v_t.ok_or_else(no_svd)?;
    let mut idx: Vec<usize> = (0..svd.singular_values.len()).collect();
    idx.sort_by(|&a, &b| svd.singular_values[a].total_cmp(&svd.singular_values[b]));
    // rows of Vᴴ are conjugated right singular vectors
    Ok(DMatrix::from_fn(n, dim, |i, j| vt[(idx[j], i)].conj()))
}

/// The singular value decomposition, bounded ([`crate::linalg::float::try_svd_to`]) at the
/// tolerance of nalgebra's own `svd` (5ε), which this method has always used.
fn svd<T: nalgebra::ComplexField<RealField = f64>>(
    m: &DMatrix<T>,
    compute_u: bool,
    compute_v: bool,
) -> Result<nalgebra::SVD<T, nalgebra::Dyn, nalgebra::Dyn>, RobustError> {
    crate::linalg::float::try_svd_to(m, compute_u, compute_v, 5.0 * f64::EPSILON).ok_or_else(no_svd)
}

/// A singular value decomposition that could not be computed (an entry not finite, or the
/// iteration not converging within its bound).
fn no_svd() -> RobustError {
    RobustError::Failed("a singular value decomposition did not converge".into())
}

/// A unit vector orthogonal to the columns of `x` (n × (n − 1)).
fn orthogonal_to(x: &DMatrix<C64>) -> Result<DVector<C64>, RobustError> {
    let n = x.nrows();
    let mut padded = DMatrix::zeros(n, n);
    padded.view_mut((0, 0), (n, x.ncols())).copy_from(x);
    let svd = svd(&padded, true, false)?;
    let u = svd.u.ok_or_else(no_svd)?;
    let k = (0..n)
        .min_by(|&a, &b| svd.singular_values[a].total_cmp(&svd.singular_values[b]))
        .unwrap_or(0);
    Ok(u.column(k).into_owned())
}

/// For each pole, the index of its conjugate partner (itself when real).
fn partners(poles: &[(f64, f64)]) -> Result<Vec<usize>, RobustError> {
    let n = poles.len();
    let mut partner: Vec<Option<usize>> = vec![None; n];
    for j in 0..n {
        let (re, im) = poles[j];
        if im == 0.0 {
            partner[j] = Some(j);
            continue;
        }
        if partner[j].is_some() {
            continue;
        }
        let k = (0..n)
            .find(|&k| k != j && partner[k].is_none() && poles[k] == (re, -im))
            .ok_or_else(|| RobustError::Unpaired(format!("{re} + {im}i")))?;
        partner[j] = Some(k);
        partner[k] = Some(j);
    }
    Ok(partner.into_iter().map(|p| p.unwrap_or(0)).collect())
}

/// Shapes, the pole count, conjugate partners (returned) and multiplicities at most the number
/// of outputs.
fn check_request(
    a: &DMatrix<f64>,
    c: &DMatrix<f64>,
    poles: &[(f64, f64)],
) -> Result<Vec<usize>, RobustError> {
    let n = a.nrows();
    if a.ncols() != n || c.ncols() != n {
        return Err(RobustError::Shape {
            a_rows: a.nrows(),
            a_cols: a.ncols(),
            c_rows: c.nrows(),
            c_cols: c.ncols(),
        });
    }
    if poles.len() != n {
        return Err(RobustError::PoleCount {
            found: poles.len(),
            order: n,
        });
    }
    let partner = partners(poles)?;
    let m = c.nrows();
    for &(re, im) in poles {
        let k = poles.iter().filter(|q| **q == (re, im)).count();
        if k > m {
            return Err(RobustError::Multiplicity {
                pole: re,
                multiplicity: k,
                outputs: m,
            });
        }
    }
    Ok(partner)
}

/// Kautsky–Nichols–Van Dooren sweeps: each eigenvector in turn made as orthogonal to the
/// others as its allowable subspace (`bases[j]`) permits, conjugate partners kept conjugate;
/// returns the sweeps made (at most 30).
fn orthogonalise(
    x: &mut DMatrix<C64>,
    bases: &[DMatrix<C64>],
    partner: &[usize],
) -> Result<usize, RobustError> {
    let n = x.ncols();
    let mut sweeps = 0;
    for _ in 0..30 {
        sweeps += 1;
        let before = x.clone();
        for j in 0..n {
            if partner[j] < j {
                continue; // set from its partner
            }
            let others = x.clone().remove_column(j);
            let y = if n > 1 {
                orthogonal_to(&others)?
            } else {
                x.column(j).into_owned()
            };
            let s = &bases[j];
            let mut v = s * (s.adjoint() * y);
            let nrm = v.norm();
            if nrm > 1e-14 {
                v /= C64::new(nrm, 0.0);
                x.set_column(j, &v);
                if partner[j] != j {
                    let conj = v.map(|e| e.conj());
                    x.set_column(partner[j], &conj);
                }
            }
        }
        if (&*x - &before).norm() < 1e-12 {
            break;
        }
    }
    Ok(sweeps)
}

/// The largest distance from a computed eigenvalue to the requested pole it is matched with
/// (greedily, nearest first).
fn farthest_pole(ev: &[C64], lambdas: &[C64]) -> f64 {
    let mut requested = lambdas.to_vec();
    let mut residual: f64 = 0.0;
    for z in ev {
        let (pos, d) = requested
            .iter()
            .enumerate()
            .map(|(i, p)| (i, (z - p).norm()))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap_or((0, f64::INFINITY));
        residual = residual.max(d);
        if !requested.is_empty() {
            requested.remove(pos);
        }
    }
    residual
}

/// Places the eigenvalues of `A − KC` at `poles` (real or in conjugate pairs, as `(re, im)`),
/// choosing the free parameters for well-conditioned eigenvectors.
///
/// # Errors
/// [`RobustError`] for mismatched shapes, unpaired complex poles, too high multiplicities, or a
/// rank-deficient `C`.
pub fn robust_observer_gain(
    a: &DMatrix<f64>,
    c: &DMatrix<f64>,
    poles: &[(f64, f64)],
) -> Result<RobustPlacement, RobustError> {
    let n = a.nrows();
    let m = c.nrows();
    let partner = check_request(a, c, poles)?;
    // Past 1e150 the products below overflow f64; a NaN would reach the SVDs.
    let finite = |x: f64| x.is_finite() && x.abs() <= 1e150;
    if !(a.iter().all(|x| finite(*x))
        && c.iter().all(|x| finite(*x))
        && poles.iter().all(|(re, im)| finite(*re) && finite(*im)))
    {
        return Err(RobustError::Failed(
            "an entry of A, C or the poles is beyond 1e150 in magnitude (or not finite): the float method would overflow".into(),
        ));
    }
    // Dual problem: state feedback F for (Aᵀ, B = Cᵀ), eig(Aᵀ − B F) = poles, K = Fᵀ.
    let at = a.transpose();
    let b = c.transpose();
    let qr = b.clone().qr();
    let u0 = qr.q(); // n × m
    let z = qr.r(); // m × m
    if (0..m).any(|i| z[(i, i)].abs() <= 1e-12 * z.norm().max(1.0)) {
        return Err(RobustError::Failed("C does not have full row rank".into()));
    }
    let u1 = if m < n {
        let proj = DMatrix::<f64>::identity(n, n) - &u0 * u0.transpose();
        let svd = svd(&proj, true, false)?;
        let u = svd.u.ok_or_else(no_svd)?;
        let mut idx: Vec<usize> = (0..n).collect();
        idx.sort_by(|&x, &y| svd.singular_values[y].total_cmp(&svd.singular_values[x]));
        DMatrix::from_fn(n, n - m, |i, j| u[(i, idx[j])])
    } else {
        DMatrix::zeros(n, 0)
    };
    let cx = |mat: &DMatrix<f64>| mat.map(|x| C64::new(x, 0.0));
    let lambdas: Vec<C64> = poles.iter().map(|&(re, im)| C64::new(re, im)).collect();
    let bases: Vec<DMatrix<C64>> = lambdas
        .iter()
        .map(|&l| {
            let shifted = cx(&at) - DMatrix::<C64>::identity(n, n) * l;
            if m < n {
                null_basis(&(cx(&u1.transpose()) * shifted), m)
            } else {
                Ok(DMatrix::<C64>::identity(n, n))
            }
        })
        .collect::<Result<_, _>>()?;
    let mut x = DMatrix::from_fn(n, n, |i, j| bases[j][(i, j % bases[j].ncols())]);
    for j in 0..n {
        if partner[j] < j {
            let conj = x.column(partner[j]).map(|v| v.conj());
            x.set_column(j, &conj);
        }
        let nrm = x.column(j).norm();
        if nrm > 0.0 {
            x.column_mut(j).scale_mut(1.0 / nrm);
        }
    }
    let sweeps = orthogonalise(&mut x, &bases, &partner)?;
    let x_inv = x
        .clone()
        .try_inverse()
        .ok_or_else(|| RobustError::Failed("the eigenvector matrix is singular".into()))?;
    let lambda = DMatrix::from_diagonal(&DVector::from_vec(lambdas.clone()));
    let target_c = &x * lambda * &x_inv;
    let imaginary = target_c.map(|v| v.im).norm();
    let target = target_c.map(|v| v.re);
    if imaginary > 1e-8 * target.norm().max(1.0) {
        return Err(RobustError::Failed(format!(
            "X Λ X⁻¹ is not real (imaginary part {imaginary:.1e})"
        )));
    }
    let zinv = z
        .clone()
        .try_inverse()
        .ok_or_else(|| RobustError::Failed("C does not have full row rank".into()))?;
    let f = zinv * u0.transpose() * (&at - &target);
    let k = f.transpose(); // n × m
    let observer = a - &k * c;
    let ev = eigenvalues(&observer);
    let residual = farthest_pole(&ev, &lambdas);
    let relative_residual =
        (&observer - target.transpose()).norm() / a.norm().max(f64::MIN_POSITIVE);
    let svd = svd(&x, false, false)?;
    let (hi, lo) = (svd.singular_values.max(), svd.singular_values.min());
    Ok(RobustPlacement {
        gain: (0..n)
            .map(|i| (0..m).map(|j| k[(i, j)]).collect())
            .collect(),
        eigenvalues: ev.iter().map(|z| (z.re, z.im)).collect(),
        residual,
        relative_residual,
        eigenvector_condition: if lo > 0.0 { hi / lo } else { f64::INFINITY },
        sweeps,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_random_four_state_system_with_two_outputs_and_complex_poles() {
        let a = DMatrix::from_row_slice(
            4,
            4,
            &[
                0.0, 1.0, 0.0, 0.0, -2.0, -0.5, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 0.0, -3.0, -0.2,
            ],
        );
        let c = DMatrix::from_row_slice(2, 4, &[1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
        let poles = [(-2.0, 3.0), (-2.0, -3.0), (-5.0, 1.0), (-5.0, -1.0)];
        let r = robust_observer_gain(&a, &c, &poles).unwrap();
        assert!(r.residual < 1e-8, "{r:?}");
        assert!(r.eigenvector_condition < 1e3, "{r:?}");
    }

    #[test]
    fn places_the_rc_ladder_with_two_outputs() {
        let a = DMatrix::from_row_slice(3, 3, &[-2.0, 1.0, 0.0, 1.0, -2.0, 1.0, 0.0, 1.0, -2.0]);
        let c = DMatrix::from_row_slice(2, 3, &[1.0, 0.0, 0.0, 0.0, 0.0, 1.0]);
        let r = robust_observer_gain(&a, &c, &[(-4.0, 0.0), (-5.0, 0.0), (-6.0, 0.0)]).unwrap();
        assert!(r.residual < 1e-9, "{r:?}");
        // a double pole is possible with two outputs, a triple one is not
        assert!(
            robust_observer_gain(&a, &c, &[(-4.0, 0.0), (-4.0, 0.0), (-6.0, 0.0)])
                .unwrap()
                .residual
                < 1e-6
        );
        assert!(matches!(
            robust_observer_gain(&a, &c, &[(-4.0, 0.0); 3]),
            Err(RobustError::Multiplicity { .. })
        ));
        let pair = robust_observer_gain(&a, &c, &[(-4.0, 1.0), (-4.0, -1.0), (-6.0, 0.0)]).unwrap();
        assert!(pair.residual < 1e-9, "{pair:?}");
        assert!(matches!(
            robust_observer_gain(&a, &c, &[(-4.0, 1.0), (-5.0, 0.0), (-6.0, 0.0)]),
            Err(RobustError::Unpaired(_))
        ));
    }
}
