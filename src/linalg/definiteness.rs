//! Whether a symmetric matrix is positive semidefinite, decided exactly.
//!
//! A symmetric matrix has real eigenvalues, so they are all ≥ 0 exactly when the coefficients of
//! `det(λI − M)` alternate in sign (Descartes' rule is exact for real-rooted polynomials). This
//! needs one characteristic polynomial, no eigenvalues and no tolerance: noise intensities and
//! weighting matrices are checked with it.

use super::{characteristic_polynomial, LinalgError, Matrix};
use crate::algebra::{Rational, Zero};
use crate::poly::Poly;

/// What the test found about a matrix.
#[derive(Debug, Clone, PartialEq)]
pub enum Definiteness {
    /// Not square, or not equal to its transpose.
    NotSymmetric,
    /// Symmetric with a negative eigenvalue: `det(λI − M)`, which has a negative root.
    Indefinite(Poly<Rational>),
    /// Symmetric positive semidefinite.
    PositiveSemidefinite,
}

/// Symmetry and, for a symmetric matrix, positive semidefiniteness.
///
/// # Example
/// ```
/// use observer_workbench::algebra::Rational;
/// use observer_workbench::linalg::definiteness::{definiteness, Definiteness};
/// use observer_workbench::syntax::parse_matrix;
/// let d = parse_matrix::<Rational>("[0 0 0; 0 1 0; 0 0 0]").unwrap();
/// assert_eq!(definiteness(&d).unwrap(), Definiteness::PositiveSemidefinite);
/// let e = parse_matrix::<Rational>("[1 2; 2 1]").unwrap(); // eigenvalues 3 and −1
/// assert!(matches!(definiteness(&e).unwrap(), Definiteness::Indefinite(_)));
/// ```
///
/// # Errors
/// [`LinalgError`] from the characteristic polynomial (a matrix beyond the exact limits).
pub fn definiteness(m: &Matrix<Rational>) -> Result<Definiteness, LinalgError> {
    if !m.is_square() || *m != m.transpose() {
        return Ok(Definiteness::NotSymmetric);
    }
    let n = m.rows();
    let p = characteristic_polynomial(m, "λ")?;
    let zero = Rational::zero();
    let alternates = (0..=n).all(|k| {
        let c = p.coeff(k);
        if (n - k).is_multiple_of(2) {
            c >= zero
        } else {
            c <= zero
        }
    });
    Ok(if alternates {
        Definiteness::PositiveSemidefinite
    } else {
        Definiteness::Indefinite(p)
    })
}
