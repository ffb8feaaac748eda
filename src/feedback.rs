//! State feedback as a design of its own: the gain placing the eigenvalues of the closed loop
//! `ẋ = (A + BF) x` (`u = F x`) or `ẋ = (A − BK) x` (`u = −K x`), both conventions explicit.
//!
//! Feedback and observer gain are dual: `(A − BK)ᵀ = Aᵀ − Kᵀ Bᵀ` is an observer matrix of the
//! pair `(Aᵀ, Bᵀ)`, so `K` is the transpose of the observer gain of the dual pair, by the same
//! formulas (Ackermann, Bass–Gura, canonical form) and with the same exact derivation; the
//! controllability matrix of `(A, B)` is the transpose of the observability matrix of the dual,
//! and an uncontrollable mode is an unobservable mode of the dual (found by the same PBH test).
//! The result is checked by computing `det(sI − (A − BK))` exactly.

use crate::algebra::{Quadratic, Rational};
use crate::derivation::{Derivation, Words};
use crate::linalg::{self, Matrix};
use crate::observability::observability_rank_report;
use crate::observer::{
    design_with, Convention, DesignError, DesiredPolynomial, Detail, GainMethod,
};
use crate::poly::Poly;

/// How the feedback enters: `u = F x` (closed loop `A + BF`) or `u = −K x` (`A − BK`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FeedbackConvention {
    /// `u = F x`, closed loop `A + BF` (Stoustrup's slides).
    UEqualsFx,
    /// `u = −K x`, closed loop `A − BK` (most textbooks).
    UEqualsMinusKx,
}

impl FeedbackConvention {
    /// The command-line spelling, `u=fx` or `u=-kx`.
    pub fn flag(self) -> &'static str {
        match self {
            FeedbackConvention::UEqualsFx => "u=fx",
            FeedbackConvention::UEqualsMinusKx => "u=-kx",
        }
    }
    /// Parses `u=fx` / `u=-kx` (case and spaces ignored, `−` accepted).
    pub fn parse(s: &str) -> Option<Self> {
        let t: String = s
            .chars()
            .filter(|c| !c.is_whitespace())
            .collect::<String>()
            .to_lowercase()
            .replace('−', "-");
        match t.as_str() {
            "u=fx" => Some(FeedbackConvention::UEqualsFx),
            "u=-kx" => Some(FeedbackConvention::UEqualsMinusKx),
            _ => None,
        }
    }
    /// The gain's letter.
    pub fn letter(self) -> &'static str {
        match self {
            FeedbackConvention::UEqualsFx => "F",
            FeedbackConvention::UEqualsMinusKx => "K",
        }
    }
    /// The closed-loop matrix, in words.
    pub fn closed_loop(self) -> &'static str {
        match self {
            FeedbackConvention::UEqualsFx => "A + BF",
            FeedbackConvention::UEqualsMinusKx => "A − BK",
        }
    }
}

/// Why a state feedback could not be designed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FeedbackError {
    /// `A` and `B` do not fit, or there is more than one input.
    #[error("state feedback needs A n×n and one input column B n×1; A is {a_rows}×{a_cols}, B is {b_rows}×{b_cols}")]
    Shape {
        /// Rows of A.
        a_rows: usize,
        /// Columns of A.
        a_cols: usize,
        /// Rows of B.
        b_rows: usize,
        /// Columns of B.
        b_cols: usize,
    },
    /// `(A, B)` is not controllable.
    #[error("(A, B) is not controllable: rank [B, AB, …] = {rank} < {order}; uncontrollable eigenvalues {modes} (no state feedback moves them; a left direction w with w B = 0, w A = λ w: {direction})")]
    Uncontrollable {
        /// Rank of the controllability matrix.
        rank: usize,
        /// The order.
        order: usize,
        /// The uncontrollable eigenvalues.
        modes: String,
        /// A left eigenvector annihilating B, printed.
        direction: String,
    },
    /// The dual design failed (a polynomial of the wrong degree, not exact…).
    #[error(transparent)]
    Design(#[from] DesignError),
    /// Matrix arithmetic failed.
    #[error(transparent)]
    Linalg(#[from] linalg::LinalgError),
}

/// `n` for a square `A` (n×n) and one input column `B` (n×1).
fn single_input<R: crate::algebra::Ring>(
    a: &Matrix<R>,
    b: &Matrix<R>,
) -> Result<usize, FeedbackError> {
    let n = a.rows();
    if !a.is_square() || b.rows() != n || b.cols() != 1 {
        return Err(FeedbackError::Shape {
            a_rows: a.rows(),
            a_cols: a.cols(),
            b_rows: b.rows(),
            b_cols: b.cols(),
        });
    }
    Ok(n)
}

/// The derivation's title: the convention and the duality it is computed by.
fn titled(convention: FeedbackConvention) -> Derivation {
    Derivation::new(&format!(
        "State feedback u = {} x, closed loop {} (by duality with the observer gain of (Aᵀ, Bᵀ))",
        if convention == FeedbackConvention::UEqualsFx {
            "F"
        } else {
            "−K"
        },
        convention.closed_loop()
    ))
}

/// The gain of `u = −K x` written in `convention` (`F = −K` for `u = F x`, a step recorded).
fn in_convention<R: crate::algebra::Ring>(
    k: &Matrix<R>,
    convention: FeedbackConvention,
    d: &mut Derivation,
) -> Matrix<R> {
    match convention {
        FeedbackConvention::UEqualsMinusKx => k.clone(),
        FeedbackConvention::UEqualsFx => {
            let f = k.neg();
            d.push("F (u = F x, closed loop A + BF)", "−K", &f);
            f
        }
    }
}

/// A state feedback with its working.
#[derive(Clone, Debug)]
pub struct FeedbackDesign {
    /// How the gain enters.
    pub convention: FeedbackConvention,
    /// The gain: `F` (1×n) for `u = F x` or `K` for `u = −K x`.
    pub gain: Matrix<Quadratic>,
    /// `det(sI − closed loop)`, computed from the gain.
    pub achieved: Poly<Quadratic>,
    /// The desired polynomial.
    pub desired: DesiredPolynomial,
    /// The steps: controllability, the dual design, the transposition, the check.
    pub derivation: Derivation,
}

impl FeedbackDesign {
    /// Whether the closed loop has exactly the desired polynomial.
    pub fn places_exactly(&self) -> bool {
        self.desired.exact.as_ref() == Some(&self.achieved)
    }
}

/// The state feedback placing `desired` for the single-input pair `(A, B)`.
///
/// ```
/// use observer_workbench::algebra::{Quadratic, Rational};
/// use observer_workbench::feedback::{design_feedback, FeedbackConvention};
/// use observer_workbench::observer::{DesiredPolynomial, Detail, GainMethod};
/// use observer_workbench::syntax::{parse_list, parse_matrix};
/// let m = |s: &str| parse_matrix::<Rational>(s).unwrap();
/// let p = DesiredPolynomial::from_poles(&parse_list::<Quadratic>("-4, -5").unwrap()).unwrap();
/// let d = design_feedback(&m("[2 -3; 4 -5]"), &m("[2; 3]"), &p, GainMethod::Ackermann,
///     FeedbackConvention::UEqualsFx, Detail::Full).unwrap();
/// assert_eq!(d.gain.to_input(), "[42, -30]"); // Stoustrup's F, u = F x
/// assert!(d.places_exactly());
/// ```
///
/// # Errors
/// [`FeedbackError`] for a shape that does not fit, an uncontrollable pair (its modes named), or
/// a desired polynomial the design refuses.
pub fn design_feedback(
    a: &Matrix<Rational>,
    b: &Matrix<Rational>,
    desired: &DesiredPolynomial,
    method: GainMethod,
    convention: FeedbackConvention,
    detail: Detail,
) -> Result<FeedbackDesign, FeedbackError> {
    let n = single_input(a, b)?;
    let (at, bt) = (a.transpose(), b.transpose());
    let mut d = titled(convention);
    let dual = observability_rank_report(&at, &bt)?;
    d.push(
        "controllability matrix C_n",
        "[B, AB, …, A^(n−1)B]",
        &dual.matrix.transpose(),
    );
    d.push("rank C_n", "", &Words(format!("{} of {n}", dual.rank)));
    if !dual.observable() {
        return Err(FeedbackError::Uncontrollable {
            rank: dual.rank,
            order: n,
            modes: dual.unobservable_eigenvalues.render(),
            direction: dual
                .unobservable_subspace
                .first()
                .map_or_else(String::new, |v| v.transpose().to_input()),
        });
    }
    d.push(
        "the dual pair (Aᵀ, Bᵀ)",
        "the observer design below reads A as Aᵀ and C as Bᵀ",
        &Words(format!("Aᵀ = {}, Bᵀ = {}", at.to_input(), bt.to_input())),
    );
    let observer = design_with(&at, &bt, desired, method, Convention::AMinusKC, detail)?;
    // det(sI − (A − BK)) = det(sI − (Aᵀ − Kᵀ Bᵀ)): the dual observer's polynomial, which its
    // design recomputed from the gain by the rank-one update (only C_nᵀ Kᵀ and det(sI − A)
    // enter, whatever the size of K's numbers) — the check `gain` makes, taken with its
    // rendering rather than made a second time
    let achieved = observer.achieved.clone();
    let check = observer
        .derivation
        .step(crate::observer::CHECK_STEP)
        .cloned();
    d.extend(observer.derivation);
    let k = observer.gain.matrix.transpose();
    d.push("K (u = −K x, closed loop A − BK)", "K_dualᵀ", &k);
    let gain = in_convention(&k, convention, &mut d);
    let label = format!("det(sI − ({})), checked exactly", convention.closed_loop());
    match check {
        Some(step) => d.push_step(step.renamed(&label, "")),
        None => d.push(&label, "", &achieved),
    }
    Ok(FeedbackDesign {
        convention,
        gain,
        achieved,
        desired: desired.clone(),
        derivation: d,
    })
}

/// A state feedback designed with parameters.
#[derive(Clone, Debug)]
pub struct SymbolicFeedback {
    /// The gain (`F` or `K`), entries rational functions of the parameters.
    pub gain: Matrix<crate::algebra::Fraction>,
    /// `det(sI − closed loop)`, computed from the gain.
    pub achieved: Poly<crate::algebra::Fraction>,
    /// Whether it equals the desired polynomial identically in `s` and the parameters.
    pub identity: bool,
    /// The steps.
    pub derivation: Derivation,
}

/// [`design_feedback`] over the rational functions of the parameters: the dual observer design
/// in symbols, the closed loop's polynomial recomputed and compared as an identity.
///
/// # Errors
/// As [`design_feedback`]; uncontrollable means uncontrollable for every value.
pub fn design_feedback_symbolic(
    a: &Matrix<crate::algebra::Fraction>,
    b: &Matrix<crate::algebra::Fraction>,
    desired: &Poly<crate::algebra::Fraction>,
    method: GainMethod,
    convention: FeedbackConvention,
    detail: Detail,
) -> Result<SymbolicFeedback, FeedbackError> {
    let n = single_input(a, b)?;
    let (at, bt) = (a.transpose(), b.transpose());
    let mut d = titled(convention);
    let controllability = crate::observability::observability_matrix(&at, &bt)?;
    let rank = linalg::rank(&controllability);
    d.push(
        "controllability matrix C_n",
        "[B, AB, …, A^(n−1)B]",
        &controllability.transpose(),
    );
    if rank < n {
        let direction = linalg::null_space(&controllability)
            .first()
            .map_or_else(String::new, |v| v.transpose().to_input());
        return Err(FeedbackError::Uncontrollable {
            rank,
            order: n,
            modes: "(for every value of the parameters)".into(),
            direction,
        });
    }
    let observer =
        crate::observer::design_symbolic(&at, &bt, desired, method, Convention::AMinusKC, detail)?;
    d.extend(observer.derivation);
    let k = observer.gain.matrix.transpose();
    d.push("K (u = −K x, closed loop A − BK)", "K_dualᵀ", &k);
    let gain = in_convention(&k, convention, &mut d);
    let closed = a.sub(&b.mul(&k)?)?;
    let achieved = linalg::characteristic_polynomial(&closed, "s")?;
    d.push(
        &format!(
            "det(sI − ({})), checked as an identity",
            convention.closed_loop()
        ),
        "",
        &achieved,
    );
    Ok(SymbolicFeedback {
        identity: &achieved == desired,
        gain,
        achieved,
        derivation: d,
    })
}
