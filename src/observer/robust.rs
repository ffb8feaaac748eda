//! Robust multi-output observer pole placement in `f64`: Kautsky, Nichols & Van Dooren,
//! "Robust pole assignment in linear state feedback", Int. J. Control 41(5), 1985, method 0.
//!
//! With more than one output the gain is not unique; KNV uses the freedom to make the
//! eigenvectors of the observer matrix as orthogonal as possible, which makes the placed poles
//! as insensitive as possible to perturbations. Applied to the dual: `eig(A − KC) =
//! eig(Aᵀ − CᵀKᵀ)`, so `Kᵀ` is the state feedback of `(Aᵀ, Cᵀ)`.
//!
//! Real poles only, each of multiplicity at most the number of outputs (the method's own limit);
//! complex poles are refused with an error rather than handled approximately. The result reports
//! its residual: the distance of the computed eigenvalues from the requested ones, and the
//! condition number of the eigenvector matrix.

use crate::linalg::float::eigenvalues;
use nalgebra::DMatrix;
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
    /// A complex pole.
    #[error("the robust method here places real poles only; {0} is complex (use an exact design instead)")]
    Complex(String),
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

/// An orthonormal basis of the null space of `m` (r × n), `dim` vectors: the right singular
/// vectors of the smallest singular values (the matrix is padded to square for a full basis).
fn null_basis(m: &DMatrix<f64>, dim: usize) -> DMatrix<f64> {
    let n = m.ncols();
    let mut padded = DMatrix::zeros(n.max(m.nrows()), n);
    padded.view_mut((0, 0), (m.nrows(), n)).copy_from(m);
    let svd = padded.svd(false, true);
    let vt = svd.v_t.expect("requested");
    let mut idx: Vec<usize> = (0..svd.singular_values.len()).collect();
    idx.sort_by(|&a, &b| svd.singular_values[a].total_cmp(&svd.singular_values[b]));
    DMatrix::from_fn(n, dim, |i, j| vt[(idx[j], i)])
}

/// A unit vector orthogonal to the columns of `x` (n × (n − 1)).
fn orthogonal_to(x: &DMatrix<f64>) -> nalgebra::DVector<f64> {
    let n = x.nrows();
    let mut padded = DMatrix::zeros(n, n);
    padded.view_mut((0, 0), (n, x.ncols())).copy_from(x);
    let svd = padded.svd(true, false);
    let u = svd.u.expect("requested");
    let k = (0..n)
        .min_by(|&a, &b| svd.singular_values[a].total_cmp(&svd.singular_values[b]))
        .unwrap_or(0);
    u.column(k).into_owned()
}

/// Places the eigenvalues of `A − KC` at `poles` (real), choosing the free parameters for
/// well-conditioned eigenvectors.
///
/// # Errors
/// [`RobustError`] for mismatched shapes, complex poles, too high multiplicities, or a rank
/// deficient `C`.
pub fn robust_observer_gain(
    a: &DMatrix<f64>,
    c: &DMatrix<f64>,
    poles: &[(f64, f64)],
) -> Result<RobustPlacement, RobustError> {
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
    if let Some(&(re, im)) = poles.iter().find(|(_, im)| *im != 0.0) {
        return Err(RobustError::Complex(format!("{re} + {im}i")));
    }
    let m = c.nrows();
    for &(p, _) in poles {
        let k = poles.iter().filter(|(q, _)| *q == p).count();
        if k > m {
            return Err(RobustError::Multiplicity {
                pole: p,
                multiplicity: k,
                outputs: m,
            });
        }
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
    let proj = DMatrix::<f64>::identity(n, n) - &u0 * u0.transpose();
    let u1 = if m < n {
        let svd = proj.svd(true, false);
        let u = svd.u.expect("requested");
        let mut idx: Vec<usize> = (0..n).collect();
        idx.sort_by(|&x, &y| svd.singular_values[y].total_cmp(&svd.singular_values[x]));
        DMatrix::from_fn(n, n - m, |i, j| u[(i, idx[j])])
    } else {
        DMatrix::zeros(n, 0)
    };
    let lambdas: Vec<f64> = poles.iter().map(|(re, _)| *re).collect();
    let bases: Vec<DMatrix<f64>> = lambdas
        .iter()
        .map(|&l| {
            let shifted = &at - DMatrix::<f64>::identity(n, n) * l;
            if m < n {
                null_basis(&(u1.transpose() * shifted), m)
            } else {
                DMatrix::<f64>::identity(n, n)
            }
        })
        .collect();
    let mut x = DMatrix::from_fn(n, n, |i, j| bases[j][(i, j % bases[j].ncols())]);
    for j in 0..n {
        let nrm = x.column(j).norm();
        if nrm > 0.0 {
            x.column_mut(j).scale_mut(1.0 / nrm);
        }
    }
    let mut sweeps = 0;
    for _ in 0..30 {
        sweeps += 1;
        let before = x.clone();
        for j in 0..n {
            let others = x.clone().remove_column(j);
            let y = if n > 1 {
                orthogonal_to(&others)
            } else {
                x.column(j).into_owned()
            };
            let s = &bases[j];
            let mut v = s * (s.transpose() * y);
            let nrm = v.norm();
            if nrm > 1e-14 {
                v /= nrm;
                x.set_column(j, &v);
            }
        }
        if (&x - &before).norm() < 1e-12 {
            break;
        }
    }
    let x_inv = x
        .clone()
        .try_inverse()
        .ok_or_else(|| RobustError::Failed("the eigenvector matrix is singular".into()))?;
    let lambda = DMatrix::from_diagonal(&nalgebra::DVector::from_vec(lambdas.clone()));
    let target = &x * lambda * &x_inv;
    let zinv = z
        .clone()
        .try_inverse()
        .ok_or_else(|| RobustError::Failed("C does not have full row rank".into()))?;
    let f = zinv * u0.transpose() * (&at - &target);
    let k = f.transpose(); // n × m
    let observer = a - &k * c;
    let ev = eigenvalues(&observer);
    let mut requested = lambdas.clone();
    let mut residual: f64 = 0.0;
    for z in &ev {
        let (pos, d) = requested
            .iter()
            .enumerate()
            .map(|(i, p)| (i, ((z.re - p).powi(2) + z.im.powi(2)).sqrt()))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap_or((0, f64::INFINITY));
        residual = residual.max(d);
        if !requested.is_empty() {
            requested.remove(pos);
        }
    }
    let relative_residual =
        (&observer - target.transpose()).norm() / a.norm().max(f64::MIN_POSITIVE);
    Ok(RobustPlacement {
        gain: (0..n)
            .map(|i| (0..m).map(|j| k[(i, j)]).collect())
            .collect(),
        eigenvalues: ev.iter().map(|z| (z.re, z.im)).collect(),
        residual,
        relative_residual,
        eigenvector_condition: crate::linalg::float::condition_number(&x),
        sweeps,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

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
        assert!(matches!(
            robust_observer_gain(&a, &c, &[(-4.0, 1.0), (-4.0, -1.0), (-6.0, 0.0)]),
            Err(RobustError::Complex(_))
        ));
    }
}
