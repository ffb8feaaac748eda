//! Perfect (descriptor) observers `E x̂' = F x̂ + G_u u + G_y y` for single-output systems
//! (Sławiński, eq. (2), (7)–(8), Example 1 eq. (19)).
//!
//! Construction (our own route to the paper's Lemma 1 form for one output): with `T = O_n`,
//! the coordinates `x̄ = T x` are `x̄ = [Cx; CAx; …]`, so `TAT⁻¹` shifts (`x̄_i' = x̄_(i+1) +
//! (TB)_i u` for `i < n`) and `y = x̄_1 + Du`. The first `n − 1` rows of the observer repeat those
//! shift equations; the last row is the algebraic constraint `0 = C x̂ + D u − y`. Then
//! `det(Es − F)` is a nonzero constant (the observer has no dynamics), and `x̂ = x` for every
//! `t > 0` whatever the initial condition.

use crate::algebra::{One, Rational};
use crate::derivation::Derivation;
use crate::linalg::{self, Matrix};
use crate::observability::{require_observable, ObservabilityError};
use crate::poly::Poly;

/// A perfect observer `E x̂' = F x̂ + G_u u + G_y y`, with its working.
#[derive(Clone, PartialEq, Debug)]
pub struct PerfectObserver {
    /// The transformation `T = O_n`.
    pub t: Matrix<Rational>,
    /// `E` (singular).
    pub e: Matrix<Rational>,
    /// `F`.
    pub f: Matrix<Rational>,
    /// The input matrix `G_u` (multiplies `u`).
    pub input_matrix: Matrix<Rational>,
    /// The output matrix `G_y` (multiplies `y`).
    pub output_matrix: Matrix<Rational>,
    /// `det(Es − F)`.
    pub pencil_determinant: Poly<Rational>,
    /// The steps.
    pub derivation: Derivation,
}

/// Why a perfect observer could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PerfectObserverError {
    /// Only single-output systems here.
    #[error("this construction is for single-output systems; C has {0} rows")]
    MultiOutput(usize),
    /// The pair is not observable: no perfect observer exists.
    #[error(transparent)]
    Observability(#[from] ObservabilityError),
    /// A matrix computation failed.
    #[error(transparent)]
    Linalg(#[from] linalg::LinalgError),
}

/// Builds the perfect observer of an observable single-output system.
///
/// # Example
/// ```
/// use observer_workbench::algebra::Rational;
/// use observer_workbench::observer::perfect::perfect_observer;
/// use observer_workbench::syntax::parse_matrix;
/// let m = |s: &str| parse_matrix::<Rational>(s).unwrap();
/// let p = perfect_observer(&m("[0 1 0; 0 0 1; -6 -11 -6]"), &m("[3; 2; 1]"), &m("[1 0 0]"), None).unwrap();
/// assert_eq!(p.f.to_input(), "[0, 1, 0; 0, 0, 1; 1, 0, 0]");
/// assert_eq!(p.output_matrix.to_input(), "[0; 0; -1]");
/// assert_eq!(p.pencil_determinant.to_string(), "-1");
/// ```
///
/// # Errors
/// [`PerfectObserverError`] for several outputs or an unobservable pair.
pub fn perfect_observer(
    a: &Matrix<Rational>,
    b: &Matrix<Rational>,
    c: &Matrix<Rational>,
    d: Option<&Matrix<Rational>>,
) -> Result<PerfectObserver, PerfectObserverError> {
    if c.rows() != 1 {
        return Err(PerfectObserverError::MultiOutput(c.rows()));
    }
    let n = a.rows();
    let m = b.cols();
    let t = require_observable(a, c)?;
    let tb = t.mul(b)?;
    let d = d.cloned().unwrap_or_else(|| Matrix::zeros(1, m));
    let zero_row = Matrix::zeros(1, n);
    let e = t.block(0, n - 1, 0, n).vstack(&zero_row)?;
    let f = t.block(1, n, 0, n).vstack(c)?;
    let input_matrix = tb.block(0, n - 1, 0, m).vstack(&d)?;
    let output_matrix =
        Matrix::<Rational>::zeros(n - 1, 1).vstack(&Matrix::column(vec![-Rational::one()]))?;
    // det(Es − F) over the polynomials in s: Berkowitz is division-free, so use it on
    // the pencil written with a symbolic s.
    let s = crate::algebra::MultiPoly::var("s");
    let pencil = Matrix::from_fn(n, n, |i, j| {
        s.clone() * crate::algebra::MultiPoly::constant(e.get(i, j).clone())
            - crate::algebra::MultiPoly::constant(f.get(i, j).clone())
    });
    let det = linalg::elimination::determinant_in_domain(&pencil)?;
    let coeffs: Vec<Rational> = det
        .coefficients_in("s")
        .iter()
        .map(|c| c.as_constant().unwrap_or_default())
        .collect();
    let pencil_determinant = Poly::new(coeffs, "s");
    let mut derivation =
        Derivation::new("Perfect observer E x̂' = F x̂ + G_u u + G_y y (single output)");
    derivation.push("T", "O_n = [C; CA; …]", &t);
    derivation.push(
        "T A T⁻¹",
        "shift form",
        &t.mul(a)?.mul(&linalg::inverse(&t)?)?,
    );
    derivation.push("T B", "", &tb);
    derivation.push("E", "[rows 1…n−1 of T; 0]", &e);
    derivation.push("F", "[rows 2…n of T; C]", &f);
    derivation.push("G_u", "[rows 1…n−1 of TB; D]", &input_matrix);
    derivation.push("G_y", "[0; −1]", &output_matrix);
    derivation.push("det(Es − F)", "a nonzero constant", &pencil_determinant);
    Ok(PerfectObserver {
        t,
        e,
        f,
        input_matrix,
        output_matrix,
        pencil_determinant,
        derivation,
    })
}
