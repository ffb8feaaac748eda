//! Continuous-time Lyapunov equations `F X + X Fᵀ + W = 0`.
//!
//! Two solvers for one equation:
//!
//! * [`lyapunov_exact`]: over any field (rationals, `Q(√d)`), by vectorising to
//!   `(I ⊗ F + F ⊗ I) vec(X) = −vec(W)` and solving fraction-free. Its `n² × n²` system keeps it
//!   to small orders ([`MAX_EXACT_LYAPUNOV_ORDER`]), which is where exact answers are wanted.
//! * [`lyapunov_f64`]: Bartels–Stewart. The real Schur form `F = Q T Qᵀ` turns the equation into
//!   `T Y + Y Tᵀ = −Qᵀ W Q`, solved column block by column block from the last (1×1 blocks are a
//!   shifted triangular solve, 2×2 blocks of complex pairs a coupled `2n` solve). `O(n³)`-ish
//!   and backward stable; the relative residual is returned with the solution.
//!
//! Baranowski's `Fᵀ H + H F = −D` (observability form) is this equation with `Fᵀ` for `F`.
//! A unique solution exists when no two eigenvalues of `F` sum to zero; for stable `F` it is
//! `X = ∫₀^∞ e^{Ft} W e^{Fᵀt} dt`.

use super::{kronecker, vectorize, LinalgError, Matrix};
use crate::algebra::Field;
use nalgebra::{DMatrix, DVector};

/// The largest order [`lyapunov_exact`] accepts (its linear system has `n²` unknowns).
pub const MAX_EXACT_LYAPUNOV_ORDER: usize = 14;

/// Why a Lyapunov equation could not be solved.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LyapunovError {
    /// `F` is not square or `W` does not match it.
    #[error("Lyapunov equation F X + X Fᵀ + W = 0: F is {f_rows}×{f_cols}, W is {w_rows}×{w_cols}; both must be n×n")]
    Shape {
        /// Rows of F.
        f_rows: usize,
        /// Columns of F.
        f_cols: usize,
        /// Rows of W.
        w_rows: usize,
        /// Columns of W.
        w_cols: usize,
    },
    /// Two eigenvalues of `F` sum to zero (e.g. an eigenvalue on the imaginary axis).
    #[error("Lyapunov equation has no unique solution: two eigenvalues of F sum to zero ({0})")]
    NotUnique(String),
    /// The exact solver's `n² × n²` system would be too large.
    #[error("exact Lyapunov solve limited to order {MAX_EXACT_LYAPUNOV_ORDER}; F is {0}×{0} (use the f64 solver)")]
    TooLarge(usize),
    /// Non-finite entries in a float problem.
    #[error("Lyapunov equation: F or W has a non-finite entry")]
    NotFinite,
    /// The real Schur form of `F` could not be computed within its bound.
    #[error("Lyapunov equation: the QR iteration for the real Schur form of F did not converge")]
    NoSchurForm,
}

fn check_shapes(fr: usize, fc: usize, wr: usize, wc: usize) -> Result<(), LyapunovError> {
    if fr != fc || wr != fr || wc != fc {
        return Err(LyapunovError::Shape {
            f_rows: fr,
            f_cols: fc,
            w_rows: wr,
            w_cols: wc,
        });
    }
    Ok(())
}

/// Solves `F X + X Fᵀ + W = 0` exactly.
///
/// # Example
/// ```
/// use observer_workbench::algebra::Rational;
/// use observer_workbench::linalg::lyapunov::lyapunov_exact;
/// use observer_workbench::syntax::parse_matrix;
/// let m = |s: &str| parse_matrix::<Rational>(s).unwrap();
/// let x = lyapunov_exact(&m("[-1 0; 0 -2]"), &m("[2 0; 0 4]")).unwrap();
/// assert_eq!(x.to_input(), "[1, 0; 0, 1]");
/// ```
///
/// # Errors
/// [`LyapunovError`] for mismatched shapes, orders above [`MAX_EXACT_LYAPUNOV_ORDER`], or when
/// two eigenvalues of `F` sum to zero.
pub fn lyapunov_exact<F: Field>(f: &Matrix<F>, w: &Matrix<F>) -> Result<Matrix<F>, LyapunovError> {
    check_shapes(f.rows(), f.cols(), w.rows(), w.cols())?;
    let n = f.rows();
    if n > MAX_EXACT_LYAPUNOV_ORDER {
        return Err(LyapunovError::TooLarge(n));
    }
    let eye = Matrix::<F>::identity(n);
    let op = kronecker(&eye, f)
        .add(&kronecker(f, &eye))
        .map_err(|e| LyapunovError::NotUnique(e.to_string()))?;
    let rhs = vectorize(w).scale(&(F::zero() - F::one()));
    let v = super::solve(&op, &rhs).map_err(|e| match e {
        LinalgError::Singular { .. } => {
            LyapunovError::NotUnique("I ⊗ F + F ⊗ I is singular".into())
        }
        other => LyapunovError::NotUnique(other.to_string()),
    })?;
    Ok(super::kronecker::unvectorize(&v, n))
}

/// A float solution with its relative residual
/// `‖F X + X Fᵀ + W‖_F / (2‖F‖_F ‖X‖_F + ‖W‖_F)`.
#[derive(Clone, Debug)]
pub struct LyapunovSolution {
    /// The solution `X` (symmetrised when `W` is symmetric).
    pub x: DMatrix<f64>,
    /// The relative residual.
    pub residual: f64,
}

/// The relative residual of `X` in `F X + X Fᵀ + W = 0`.
pub fn lyapunov_residual(f: &DMatrix<f64>, w: &DMatrix<f64>, x: &DMatrix<f64>) -> f64 {
    let r = f * x + x * f.transpose() + w;
    let scale = 2.0 * f.norm() * x.norm() + w.norm();
    if scale == 0.0 {
        r.norm()
    } else {
        r.norm() / scale
    }
}

/// Shapes fit and every entry is finite.
fn check_f64_inputs(f: &DMatrix<f64>, w: &DMatrix<f64>) -> Result<(), LyapunovError> {
    check_shapes(f.nrows(), f.ncols(), w.nrows(), w.ncols())?;
    if f.iter().chain(w.iter()).any(|x| !x.is_finite()) {
        return Err(LyapunovError::NotFinite);
    }
    Ok(())
}

/// Solves `F X + X Fᵀ + W = 0` in `f64` by Bartels–Stewart.
///
/// # Errors
/// [`LyapunovError`] for mismatched shapes, non-finite entries, or a (numerically) singular
/// block system — two eigenvalues of `F` summing to zero.
pub fn lyapunov_f64(f: &DMatrix<f64>, w: &DMatrix<f64>) -> Result<LyapunovSolution, LyapunovError> {
    check_f64_inputs(f, w)?;
    let n = f.nrows();
    if n == 0 {
        return Ok(LyapunovSolution {
            x: DMatrix::zeros(0, 0),
            residual: 0.0,
        });
    }
    let (q, t) = super::float::real_schur(f).ok_or(LyapunovError::NoSchurForm)?;
    lyapunov_from_schur(f, w, &q, &t)
}

/// The largest real part of the eigenvalues of a real Schur form `T` (1×1 and 2×2 diagonal
/// blocks): the stability margin of `F = Q T Qᵀ`, read off the factorisation
/// [`lyapunov_f64_with_abscissa`] computes anyway.
fn spectral_abscissa(t: &DMatrix<f64>) -> f64 {
    let n = t.nrows();
    let small = f64::EPSILON * t.norm().max(f64::MIN_POSITIVE);
    let mut worst = f64::NEG_INFINITY;
    let mut j = 0;
    while j < n {
        if j + 1 < n && t[(j + 1, j)].abs() > small {
            // a complex pair: real part of both eigenvalues is the block's half trace
            worst = worst.max(0.5 * (t[(j, j)] + t[(j + 1, j + 1)]));
            j += 2;
        } else {
            worst = worst.max(t[(j, j)]);
            j += 1;
        }
    }
    worst
}

/// [`lyapunov_f64`] and the spectral abscissa of `F` (largest real part of its eigenvalues)
/// from the same real Schur factorisation, for callers that need both (a stability test and
/// the solution: the J2 cost of a multi-output design, evaluated thousands of times).
/// Returns `None` when the Schur form cannot be computed ([`super::float::real_schur`]).
///
/// # Errors
/// As [`lyapunov_f64`].
pub fn lyapunov_f64_with_abscissa(
    f: &DMatrix<f64>,
    w: &DMatrix<f64>,
) -> Result<Option<(LyapunovSolution, f64)>, LyapunovError> {
    check_f64_inputs(f, w)?;
    let Some((q, t)) = super::float::real_schur(f) else {
        return Ok(None);
    };
    let abscissa = spectral_abscissa(&t);
    Ok(Some((lyapunov_from_schur(f, w, &q, &t)?, abscissa)))
}

/// The diagonal blocks of a real Schur form: `(start, size)`, size 1 or 2 (a 2×2 block where
/// the subdiagonal entry exceeds `small`).
fn diagonal_blocks(t: &DMatrix<f64>, small: f64) -> Vec<(usize, usize)> {
    let n = t.nrows();
    let mut blocks = Vec::new();
    let mut i = 0;
    while i < n {
        if i + 1 < n && t[(i + 1, i)].abs() > small {
            blocks.push((i, 2));
            i += 2;
        } else {
            blocks.push((i, 1));
            i += 1;
        }
    }
    blocks
}

/// Solves `T y_j + Σ_l G_(j,l) y_l = r_j` for one or two columns (`columns.len()`; `G` its
/// leading k×k part) with `T` upper quasi-triangular: from the last diagonal block up, each
/// block's k·size unknowns from a system of at most 4×4, then the columns above updated —
/// O(n²) per column. `None` when a block's system is singular.
fn quasi_triangular_solve(
    t: &DMatrix<f64>,
    blocks: &[(usize, usize)],
    coupling: &[[f64; 2]; 2],
    mut columns: Vec<DVector<f64>>,
) -> Option<Vec<DVector<f64>>> {
    let k = columns.len();
    let n = t.nrows();
    let mut out = vec![DVector::<f64>::zeros(n); k];
    for &(s, size) in blocks.iter().rev() {
        let m = k * size;
        let mut system = DMatrix::<f64>::zeros(m, m);
        let mut rhs = DVector::<f64>::zeros(m);
        for j in 0..k {
            for a in 0..size {
                let row = j * size + a;
                rhs[row] = columns[j][s + a];
                for b in 0..size {
                    system[(row, j * size + b)] += t[(s + a, s + b)];
                }
                for (l, g) in coupling[j].iter().enumerate().take(k) {
                    system[(row, l * size + a)] += g;
                }
            }
        }
        let z = system.lu().solve(&rhs)?;
        if z.iter().any(|v| !v.is_finite()) {
            return None;
        }
        for j in 0..k {
            for a in 0..size {
                let value = z[j * size + a];
                out[j][s + a] = value;
                if value != 0.0 {
                    for i in 0..s {
                        columns[j][i] -= t[(i, s + a)] * value;
                    }
                }
            }
        }
    }
    Some(out)
}

/// From this order on the block columns are solved by [`quasi_triangular_solve`]; below it by
/// [`dense_block_solve`], as before the structured solve existed. The two agree to rounding,
/// but rounding is what the optimal-gain search's flat minimum is made of: with the structured
/// solve at every order, `owb optimal`'s J2 minimiser for Stoustrup's plant (a Hessian
/// eigenvalue of 6·10⁻⁸) moves in its sixth digit. Below order 16 the dense solve costs
/// nothing that shows.
const STRUCTURED_FROM: usize = 16;

/// [`quasi_triangular_solve`]'s system as one dense matrix (`T + G_(l,l) I` blocks, `G_(j,l) I`
/// couplings), solved by LU: O(n³) per block column.
fn dense_block_solve(
    t: &DMatrix<f64>,
    coupling: &[[f64; 2]; 2],
    columns: Vec<DVector<f64>>,
) -> Option<Vec<DVector<f64>>> {
    let (k, n) = (columns.len(), t.nrows());
    let mut m = DMatrix::<f64>::zeros(k * n, k * n);
    let mut rhs = DVector::<f64>::zeros(k * n);
    for j in 0..k {
        m.view_mut((j * n, j * n), (n, n)).copy_from(t);
        rhs.rows_mut(j * n, n).copy_from(&columns[j]);
        for (l, g) in coupling[j].iter().enumerate().take(k) {
            for i in 0..n {
                m[(j * n + i, l * n + i)] += g;
            }
        }
    }
    let z = m.lu().solve(&rhs)?;
    Some((0..k).map(|j| z.rows(j * n, n).clone_owned()).collect())
}

/// Bartels–Stewart's second half, `F = Q T Qᵀ` given: `T Y + Y Tᵀ = C` (C = −Qᵀ W Q) column
/// block by column block from the last, each block (one column, or two for a 2×2 diagonal
/// block of T) by [`quasi_triangular_solve`] — O(n³) in all — or, below [`STRUCTURED_FROM`],
/// [`dense_block_solve`].
fn lyapunov_from_schur(
    f: &DMatrix<f64>,
    w: &DMatrix<f64>,
    q: &DMatrix<f64>,
    t: &DMatrix<f64>,
) -> Result<LyapunovSolution, LyapunovError> {
    let n = f.nrows();
    let c = -(q.transpose() * w * q);
    let mut y = DMatrix::<f64>::zeros(n, n);
    let small = f64::EPSILON * t.norm().max(f64::MIN_POSITIVE);
    let singular = || LyapunovError::NotUnique("T Y + Y Tᵀ block system is singular".into());
    let blocks = diagonal_blocks(t, small);
    for &(first, size) in blocks.iter().rev() {
        let last = first + size - 1;
        // right-hand sides of the block's columns, with the known columns k > last moved over
        let columns = (first..=last)
            .map(|col| {
                let mut r = c.column(col).clone_owned();
                for k in last + 1..n {
                    r -= y.column(k) * t[(col, k)];
                }
                r
            })
            .collect();
        let coupling = [
            [t[(first, first)], t[(first, last)]],
            [t[(last, first)], t[(last, last)]],
        ];
        let solution = if n > STRUCTURED_FROM {
            quasi_triangular_solve(t, &blocks, &coupling, columns)
        } else {
            dense_block_solve(t, &coupling, columns)
        }
        .ok_or_else(singular)?;
        for (k, column) in solution.iter().enumerate() {
            y.set_column(first + k, column);
        }
    }
    let mut x = q * y * q.transpose();
    if (w - w.transpose()).norm() <= f64::EPSILON * w.norm() {
        x = (&x + x.transpose()) * 0.5;
    }
    if x.iter().any(|v| !v.is_finite()) {
        return Err(singular());
    }
    let residual = lyapunov_residual(f, w, &x);
    Ok(LyapunovSolution { x, residual })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algebra::Rational;
    use crate::linalg::float::to_nalgebra;
    use crate::syntax::parse_matrix;

    fn m(s: &str) -> Matrix<Rational> {
        parse_matrix(s).unwrap()
    }

    #[test]
    fn exact_solution_satisfies_the_equation() {
        let f = m("[0 1 0; 0 0 1; -6 -11 -6]");
        let w = m("[1 0 0; 0 2 1; 0 1 3]");
        let x = lyapunov_exact(&f, &w).unwrap();
        let lhs = f
            .mul(&x)
            .unwrap()
            .add(&x.mul(&f.transpose()).unwrap())
            .unwrap()
            .add(&w)
            .unwrap();
        assert_eq!(lhs, Matrix::zeros(3, 3));
        let xf = lyapunov_f64(&to_nalgebra(&f), &to_nalgebra(&w)).unwrap();
        assert!(xf.residual < 1e-14, "{}", xf.residual);
        assert!((xf.x - to_nalgebra(&x)).norm() < 1e-12);
    }

    #[test]
    fn eigenvalues_summing_to_zero_are_refused() {
        let f = m("[0 1; -1 0]");
        assert!(matches!(
            lyapunov_exact(&f, &m("[1 0; 0 1]")),
            Err(LyapunovError::NotUnique(_))
        ));
        assert!(lyapunov_exact(&f, &m("[1 0 0]")).is_err());
    }

    /// Above `STRUCTURED_FROM` the columns are solved by quasi-triangular back-substitution,
    /// checked against the dense Kronecker system (I ⊗ F + F ⊗ I) vec X = −vec W, on a plant
    /// with complex pairs (2×2 Schur blocks) and real eigenvalues.
    #[test]
    fn structured_columns_match_the_kronecker_system() {
        let n = STRUCTURED_FROM + 5;
        let mut seed: u64 = 0x2545_f491_4f6c_dd1d;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed % 2001) as f64 / 1000.0 - 1.0
        };
        let f = DMatrix::<f64>::from_fn(n, n, |i, j| next() - if i == j { 4.0 } else { 0.0 });
        let g = DMatrix::<f64>::from_fn(n, n, |_, _| next());
        let w = &g * g.transpose();
        let fl = lyapunov_f64(&f, &w).unwrap();
        let eye = DMatrix::<f64>::identity(n, n);
        let kron = eye.kronecker(&f) + f.kronecker(&eye);
        let rhs = -DVector::<f64>::from_column_slice(w.as_slice());
        let vec_x = kron.lu().solve(&rhs).unwrap();
        let dense = DMatrix::<f64>::from_column_slice(n, n, vec_x.as_slice());
        assert!(
            (&fl.x - &dense).norm() <= 1e-11 * dense.norm(),
            "{}",
            (&fl.x - &dense).norm()
        );
        assert!(fl.residual < 1e-14, "{}", fl.residual);
        let schur = nalgebra::linalg::Schur::new(f.clone()).unpack().1;
        let small = f64::EPSILON * schur.norm();
        assert!(diagonal_blocks(&schur, small)
            .iter()
            .any(|&(_, size)| size == 2));
    }

    #[test]
    fn complex_pairs_use_two_by_two_blocks() {
        let f = m("[-1 5 0 0; -5 -1 0 0; 1 0 -2 3; 0 1 -3 -2]");
        let w = m("[1 0 0 0; 0 1 0 0; 0 0 1 0; 0 0 0 1]");
        let exact = to_nalgebra(&lyapunov_exact(&f, &w).unwrap());
        let fl = lyapunov_f64(&to_nalgebra(&f), &to_nalgebra(&w)).unwrap();
        assert!((fl.x - exact).norm() < 1e-12);
    }

    /// F = S/4 (S the 4 × 4 cyclic shift) has the eigenvalues ±1/4, ±i/4, all of one modulus,
    /// on which nalgebra's unbounded Schur iteration never stopped (the test of
    /// `float::real_schur` shows the stall): the solver now returns, its Schur form reached
    /// through the shift. (The equation is singular, 1/4 + (−1/4) = 0, but rounded to
    /// ±1e-17, not zero: what it returns is the caller's to judge, as for any near-singular
    /// equation.) Of order 5, where no two eigenvalues sum to zero, the solution agrees with
    /// the exact one.
    #[test]
    fn f64_solver_handles_a_scaled_cyclic_shift() {
        let f = m("[0 1/4 0 0; 0 0 1/4 0; 0 0 0 1/4; 1/4 0 0 0]");
        let w = to_nalgebra(&Matrix::<Rational>::identity(4));
        let started = std::time::Instant::now();
        let _ = lyapunov_f64(&to_nalgebra(&f), &w);
        assert!(started.elapsed() < std::time::Duration::from_secs(5));
        let f = m("[0 1/4 0 0 0; 0 0 1/4 0 0; 0 0 0 1/4 0; 0 0 0 0 1/4; 1/4 0 0 0 0]");
        let w = Matrix::<Rational>::identity(5);
        let exact = to_nalgebra(&lyapunov_exact(&f, &w).unwrap());
        let fl = lyapunov_f64(&to_nalgebra(&f), &to_nalgebra(&w)).unwrap();
        assert!((&fl.x - &exact).norm() < 1e-12, "{}", (fl.x - exact).norm());
        let (with_abscissa, abscissa) =
            lyapunov_f64_with_abscissa(&to_nalgebra(&f), &to_nalgebra(&w))
                .unwrap()
                .unwrap();
        assert!((with_abscissa.x - exact).norm() < 1e-12);
        // the largest real part: 1/4 (k = 0)
        assert!((abscissa - 0.25).abs() < 1e-12, "{abscissa}");
    }
}
