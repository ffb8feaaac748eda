//! Multi-output gains with all columns but one chosen freely.
//!
//! With `p` outputs the gain `K = [k_1 … k_p]` (A − KC) has `n·p` entries for `n` coefficient
//! equations. Fix every column but the `j`-th: then
//! `A − KC = (A − Σ_{i≠j} k_i c_i) − k_j c_j` is a single-output problem in `k_j`, and the
//! characteristic polynomial is *affine* in `k_j` (a rank-one update), so the column placing a
//! desired polynomial is unique and exact: the dual Ackermann formula on the pair
//! `(A − Σ_{i≠j} k_i c_i, c_j)`. This parametrises the whole set of placing gains (where that
//! pair is observable) by the other columns — the search space of Baranowski's optimal gains and
//! of Furlan's weighted-measurement observer.

use super::gain::{ackermann_gain, DesignError};
use crate::algebra::Field;
use crate::linalg::Matrix;
use crate::poly::Poly;

/// The gain (A − KC) whose columns other than `free` are taken from `fixed`, and whose column
/// `free` places `desired` exactly.
///
/// # Example
/// ```
/// use observer_workbench::algebra::Rational;
/// use observer_workbench::observer::partial::place_free_column;
/// use observer_workbench::syntax::{parse_matrix, parse_polynomial};
/// let m = |s: &str| parse_matrix::<Rational>(s).unwrap();
/// let p = parse_polynomial::<Rational>("(s + 4)^3", "s").unwrap();
/// // RC ladder: with the x3 column zero, the x1 column is Baranowski's G1 (eq. (10a))
/// let k = place_free_column(&m("[-2 1 0; 1 -2 1; 0 1 -2]"), &m("[1 0 0; 0 0 1]"), &m("[0 0; 0 0; 0 0]"), 0, &p).unwrap();
/// assert_eq!(k.to_input(), "[6, 0; 14, 0; 14, 0]");
/// ```
///
/// # Errors
/// [`DesignError`] when shapes do not fit, `free` is not an output, or the reduced pair is not
/// observable (then no column places the polynomial).
pub fn place_free_column<F: Field>(
    a: &Matrix<F>,
    c: &Matrix<F>,
    fixed: &Matrix<F>,
    free: usize,
    desired: &Poly<F>,
) -> Result<Matrix<F>, DesignError> {
    let (n, p) = (a.rows(), c.rows());
    if fixed.rows() != n || fixed.cols() != p || free >= p {
        return Err(DesignError::Linalg(
            crate::linalg::LinalgError::DimensionMismatch {
                operation: "gain with a free column",
                left_rows: n,
                left_cols: p,
                right_rows: fixed.rows(),
                right_cols: fixed.cols(),
            },
        ));
    }
    let mut others = fixed.clone();
    for i in 0..n {
        others.set(i, free, F::zero());
    }
    let reduced = a.sub(&others.mul(c)?)?;
    let row = Matrix::from_fn(1, c.cols(), |_, k| c.get(free, k).clone());
    let column = ackermann_gain(&reduced, &row, desired)?;
    for i in 0..n {
        others.set(i, free, column.get(i, 0).clone());
    }
    Ok(others)
}

/// With as many independent outputs as states every observer matrix is reachable:
/// `A − KC = M` for `K = (A − M) C⁻¹`. With `M = diag(λ_1, …, λ_n)` the eigenvectors are the
/// state axes, orthogonal, so this is one of the (many, equally) robust placements.
///
/// # Example
/// ```
/// use observer_workbench::algebra::Rational;
/// use observer_workbench::observer::partial::gain_for_observer_matrix;
/// use observer_workbench::syntax::parse_matrix;
/// let m = |s: &str| parse_matrix::<Rational>(s).unwrap();
/// let k = gain_for_observer_matrix(&m("[0 1; -2 -3]"), &m("[1 0; 0 1]"), &m("[-5 0; 0 -6]")).unwrap();
/// assert_eq!(k.to_input(), "[5, 1; -2, 3]");
/// ```
///
/// # Errors
/// [`DesignError`] when `C` is not square and invertible or shapes differ.
pub fn gain_for_observer_matrix<F: Field>(
    a: &Matrix<F>,
    c: &Matrix<F>,
    m: &Matrix<F>,
) -> Result<Matrix<F>, DesignError> {
    let c_inv = crate::linalg::inverse(c)?;
    Ok(a.sub(m)?.mul(&c_inv)?)
}
