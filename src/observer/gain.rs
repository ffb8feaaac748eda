//! Single-output observer gains, each method its own function, all exact (`A − KC` convention;
//! [`ObserverGain::to_convention`] gives Stoustrup's `L = −K`).
//!
//! * canonical: `K_o = c − a` in observer canonical form, `K = T_o K_o` (Di Ruscio eq. (29),
//!   (40); Stoustrup's "observer pole assignment" steps 1–5);
//! * Bass–Gura dual: `K = O_n⁻¹ M⁻ᵀ (c − a)` (Di Ruscio eq. (42));
//! * Ackermann dual: `K = P(A) O_n⁻¹ e_n` (Di Ruscio Lemma 4.1, eq. (45)–(47)), computed as
//!   `P(A)·q_n` with `q_n` solved from `O_n q_n = e_n` — never forming `O_n⁻¹` or `P(A)`;
//! * Lemma 3.1: `K̃_o = C P(A) O_n⁻¹`, reversed to `K_o`, then `K = T_o K_o` (eq. (30)–(31)).

use super::{Convention, DesiredPolynomial, ObserverGain};
use crate::algebra::{Field, Quadratic, Rational};
use crate::canonical_form::{toeplitz_m, CanonicalFormError};
use crate::derivation::{Derivation, Words};
use crate::linalg::{self, LinalgError, Matrix};
use crate::observability::{require_observable, ObservabilityError};
use crate::poly::{Factored, Poly};
use std::fmt;

/// A gain design method.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum GainMethod {
    /// Observer canonical form, `K = T_o (c − a)`.
    Canonical,
    /// `K = O_n⁻¹ M⁻ᵀ (c − a)`.
    BassGura,
    /// `K = P(A) O_n⁻¹ e_n`.
    Ackermann,
    /// `K_o = rot90(C P(A) O_n⁻¹)`, `K = T_o K_o`.
    Lemma31,
}

impl GainMethod {
    /// The command-line spelling.
    pub fn flag(self) -> &'static str {
        match self {
            GainMethod::Canonical => "canonical",
            GainMethod::BassGura => "bass-gura",
            GainMethod::Ackermann => "ackermann",
            GainMethod::Lemma31 => "lemma-3.1",
        }
    }
    /// Parses the command-line spelling.
    pub fn parse(s: &str) -> Option<Self> {
        match s.to_lowercase().as_str() {
            "canonical" => Some(GainMethod::Canonical),
            "bass-gura" | "bassgura" => Some(GainMethod::BassGura),
            "ackermann" => Some(GainMethod::Ackermann),
            "lemma-3.1" | "lemma31" => Some(GainMethod::Lemma31),
            _ => None,
        }
    }
    /// All methods.
    pub const ALL: [GainMethod; 4] = [
        GainMethod::Canonical,
        GainMethod::BassGura,
        GainMethod::Ackermann,
        GainMethod::Lemma31,
    ];
}

impl fmt::Display for GainMethod {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.flag())
    }
}

/// Why a gain could not be designed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DesignError {
    /// The pair is not observable.
    #[error(transparent)]
    Observability(#[from] ObservabilityError),
    /// The canonical form failed.
    #[error(transparent)]
    Canonical(#[from] CanonicalFormError),
    /// A matrix computation failed.
    #[error(transparent)]
    Linalg(#[from] LinalgError),
    /// These methods are for one output.
    #[error("the {method} method designs single-output observers; C has {outputs} rows")]
    MultiOutput {
        /// The method.
        method: GainMethod,
        /// Rows of C.
        outputs: usize,
    },
    /// Desired polynomial of the wrong degree or not monic.
    #[error("the desired polynomial {found} must be monic of degree {expected} (the order of A)")]
    DesiredPolynomial {
        /// The order.
        expected: usize,
        /// The polynomial.
        found: String,
    },
    /// The desired polynomial is only known in floating point.
    #[error("the desired polynomial has no exact form ({0}); use the float path")]
    NotExact(String),
}

/// These methods design for one output row.
fn single_output<F: Field>(c: &Matrix<F>, method: GainMethod) -> Result<(), DesignError> {
    if c.rows() == 1 {
        Ok(())
    } else {
        Err(DesignError::MultiOutput {
            method,
            outputs: c.rows(),
        })
    }
}

fn check_desired<F: Field>(a: &Matrix<F>, desired: &Poly<F>) -> Result<usize, DesignError> {
    let n = a.rows();
    if desired.degree() != Some(n) || !desired.is_monic() {
        return Err(DesignError::DesiredPolynomial {
            expected: n,
            found: desired.to_string(),
        });
    }
    Ok(n)
}

/// `c − a` as a column: `c_i − a_i`, the coefficients of `s^(n−i)`.
fn coefficient_difference<F: Field>(desired: &Poly<F>, open_loop: &Poly<F>, n: usize) -> Matrix<F> {
    Matrix::from_fn(n, 1, |i, _| {
        desired.coeff(n - 1 - i) - open_loop.coeff(n - 1 - i)
    })
}

/// What every method shares, computed once: `O_n` (observability certified) and `det(sI − A)`.
struct Shared<F: Field> {
    n: usize,
    o: Matrix<F>,
    open_loop: Poly<F>,
}

impl<F: Field> Shared<F> {
    fn new(
        a: &Matrix<F>,
        c: &Matrix<F>,
        desired: &Poly<F>,
        method: GainMethod,
    ) -> Result<Self, DesignError> {
        let n = check_desired(a, desired)?;
        single_output(c, method)?;
        let o = require_observable(a, c)?;
        let open_loop = linalg::characteristic_polynomial(a, "s")?;
        Ok(Shared { n, o, open_loop })
    }
    /// `M`, the Toeplitz matrix of `[1 a_1 … a_(n−1)]`.
    fn toeplitz(&self) -> Matrix<F> {
        toeplitz_m(&self.open_loop)
    }
    /// `T_o = (Mᵀ O_n)⁻¹`.
    fn transformation(&self, m: &Matrix<F>) -> Result<Matrix<F>, DesignError> {
        Ok(linalg::inverse(&m.transpose().mul(&self.o)?)?)
    }
    /// Ackermann's `K = P(A) q_n` with `q_n = O_n⁻¹ e_n`, and `q_n` itself when the working
    /// shows it (otherwise it is never reduced to lowest terms: see
    /// [`linalg::polynomial_times_solution`]).
    fn ackermann(
        &self,
        a: &Matrix<F>,
        desired: &Poly<F>,
        show_q: bool,
    ) -> Result<(Matrix<F>, Option<Matrix<F>>), DesignError> {
        let e_n = Matrix::unit(self.n, self.n - 1);
        Ok(linalg::polynomial_times_solution(
            desired, a, &self.o, &e_n, show_q,
        )?)
    }
    /// `K = O_n⁻¹ M⁻ᵀ (c − a)`.
    fn bass_gura(&self, m: &Matrix<F>, diff: &Matrix<F>) -> Result<Matrix<F>, DesignError> {
        let y = linalg::solve(&m.transpose(), diff)?;
        Ok(linalg::solve(&self.o, &y)?)
    }
    /// `K̃_o = C P(A) O_n⁻¹`, with `C P(A) = (P(Aᵀ) Cᵀ)ᵀ` by Horner on vectors.
    fn lemma_3_1_row(
        &self,
        a: &Matrix<F>,
        c: &Matrix<F>,
        desired: &Poly<F>,
    ) -> Result<Matrix<F>, DesignError> {
        let cp = linalg::polynomial_times_vector(desired, &a.transpose(), &c.transpose())?;
        // K̃_o O_n = C P(A)  ⇔  O_nᵀ K̃_oᵀ = (C P(A))ᵀ
        Ok(linalg::solve(&self.o.transpose(), &cp)?.transpose())
    }
    fn observer_polynomial(&self, k: &Matrix<F>) -> Result<Poly<F>, DesignError> {
        Ok(linalg::rank_one_update(&self.o, &self.open_loop, k)?)
    }
}

/// Dual Ackermann: `K = P(A) O_n⁻¹ e_n` (A − KC), for one output row `c`.
///
/// Over the rationals from order [`linalg::MODULAR_FROM_ORDER`] on, the gain is computed by
/// [`super::ackermann_exact::ackermann_gain_rational`] (the same formula mod many primes, lifted
/// exactly by Chinese remaindering up to Hadamard bounds) without ever forming `O_n`.
///
/// # Example
/// ```
/// use observer_workbench::algebra::Rational;
/// use observer_workbench::observer::ackermann_gain;
/// use observer_workbench::syntax::{parse_matrix, parse_polynomial};
/// let a = parse_matrix::<Rational>("[2 -3; 4 -5]").unwrap();
/// let c = parse_matrix::<Rational>("[-3 2]").unwrap();
/// let p = parse_polynomial::<Rational>("s^2 + 9s + 20", "s").unwrap();
/// // Stoustrup's L = (−6, −12) in A + LC is K = (6, 12) in A − KC
/// assert_eq!(ackermann_gain(&a, &c, &p).unwrap().to_input(), "[6; 12]");
/// // an unobservable pair is an error with its evidence, not a wrong gain
/// let c2 = parse_matrix::<Rational>("[1 0]").unwrap();
/// let a2 = parse_matrix::<Rational>("[-1 0; 1 -1]").unwrap();
/// assert!(ackermann_gain(&a2, &c2, &p).is_err());
/// ```
///
/// # Errors
/// [`DesignError`] for several outputs, an unobservable pair or a desired polynomial of the
/// wrong degree.
pub fn ackermann_gain<F: Field>(
    a: &Matrix<F>,
    c: &Matrix<F>,
    desired: &Poly<F>,
) -> Result<Matrix<F>, DesignError> {
    let n = check_desired(a, desired)?;
    single_output(c, GainMethod::Ackermann)?;
    if n >= linalg::MODULAR_FROM_ORDER {
        if let (Some(qa), Some(qc), Some(qp)) = (
            linalg::as_rational(a),
            linalg::as_rational(c),
            crate::algebra::from_concrete::<Poly<Rational>, _>(desired.clone()),
        ) {
            if let Some(k) = super::ackermann_exact::ackermann_gain_rational(qa, qc, qp.coeffs())
                .and_then(crate::algebra::from_concrete::<Matrix<F>, _>)
            {
                return Ok(k);
            }
        }
    }
    // Generic path (and the error report when the modular path finds O_n singular).
    let s = Shared::new(a, c, desired, GainMethod::Ackermann)?;
    Ok(s.ackermann(a, desired, false)?.0)
}

/// Dual Bass–Gura: `K = O_n⁻¹ M⁻ᵀ (c − a)` (A − KC).
///
/// # Errors
/// [`DesignError`] for a singular `O_n` or a desired polynomial of the wrong degree.
pub fn bass_gura_gain<F: Field>(
    a: &Matrix<F>,
    o: &Matrix<F>,
    desired: &Poly<F>,
) -> Result<Matrix<F>, DesignError> {
    let n = check_desired(a, desired)?;
    let s = Shared {
        n,
        o: o.clone(),
        open_loop: linalg::characteristic_polynomial(a, "s")?,
    };
    let m = s.toeplitz();
    s.bass_gura(&m, &coefficient_difference(desired, &s.open_loop, n))
}

/// The canonical-form design with its intermediate values.
#[derive(Clone, PartialEq, Debug)]
pub struct CanonicalGain<F: Field> {
    /// `K = T_o K_o`.
    pub gain: Matrix<F>,
    /// `K_o = c − a`, the gain in canonical coordinates.
    pub canonical: Matrix<F>,
    /// `T_o`.
    pub transformation: Matrix<F>,
}

fn canonical_from<F: Field>(
    s: &Shared<F>,
    desired: &Poly<F>,
) -> Result<CanonicalGain<F>, DesignError> {
    let t = s.transformation(&s.toeplitz())?;
    let k_o = coefficient_difference(desired, &s.open_loop, s.n);
    Ok(CanonicalGain {
        gain: t.mul(&k_o)?,
        canonical: k_o,
        transformation: t,
    })
}

/// Canonical-form gain: `K_o = c − a`, `K = T_o K_o` (A − KC), with `T_o = (Mᵀ O_n)⁻¹` as in
/// [`observer_form_di_ruscio`](crate::canonical_form::observer_form_di_ruscio).
///
/// # Errors
/// [`DesignError`] for several outputs or an unobservable pair.
pub fn canonical_gain<F: Field>(
    a: &Matrix<F>,
    c: &Matrix<F>,
    desired: &Poly<F>,
) -> Result<CanonicalGain<F>, DesignError> {
    canonical_from(&Shared::new(a, c, desired, GainMethod::Canonical)?, desired)
}

fn lemma_3_1_from<F: Field>(
    s: &Shared<F>,
    a: &Matrix<F>,
    c: &Matrix<F>,
    desired: &Poly<F>,
) -> Result<(Matrix<F>, Matrix<F>), DesignError> {
    let t = s.transformation(&s.toeplitz())?;
    let k_tilde = s.lemma_3_1_row(a, c, desired)?;
    let n = s.n;
    let k_o = Matrix::from_fn(n, 1, |i, _| k_tilde.get(0, n - 1 - i).clone());
    Ok((t.mul(&k_o)?, k_tilde))
}

/// Lemma 3.1: `K̃_o = C P(A) O_n⁻¹`, `K_o = rot90(K̃_o)`, `K = T_o K_o`. Returns `(K, K̃_o)`.
///
/// # Errors
/// [`DesignError`] for several outputs or an unobservable pair.
pub fn lemma_3_1_gain<F: Field>(
    a: &Matrix<F>,
    c: &Matrix<F>,
    desired: &Poly<F>,
) -> Result<(Matrix<F>, Matrix<F>), DesignError> {
    let s = Shared::new(a, c, desired, GainMethod::Lemma31)?;
    lemma_3_1_from(&s, a, c, desired)
}

/// A finished exact design with its working.
#[derive(Clone, PartialEq, Debug)]
pub struct ObserverDesign {
    /// The method used.
    pub method: GainMethod,
    /// The desired polynomial.
    pub desired: DesiredPolynomial,
    /// The gain, in the requested convention.
    pub gain: ObserverGain<Quadratic>,
    /// `det(sI − observer matrix)`, recomputed from the gain (equals the desired polynomial).
    pub achieved: Poly<Quadratic>,
    /// The observer matrix A − KC (in that sign whatever the convention), when the steps show
    /// it ([`Detail::Full`]).
    pub observer_matrix: Option<Matrix<Quadratic>>,
    /// The steps.
    pub derivation: Derivation,
}

/// How much of the working a design records.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Detail {
    /// Every intermediate matrix (the default; what a student reads).
    #[default]
    Full,
    /// Only the polynomials and the gain: for large systems, whose intermediate matrices
    /// (`O_n`, `q_n`, `A − KC`) run to millions of digits. The computation is the same.
    Summary,
}

/// Designs an exact single-output observer gain with `method`, reported in `convention`.
///
/// The arithmetic runs over the rationals when the desired polynomial is rational, otherwise in
/// the quadratic field of its coefficients (Butterworth order 2: Q(√2)).
///
/// # Errors
/// [`DesignError`]: several outputs, an unobservable pair, a polynomial of the wrong degree or
/// without an exact form.
pub fn design(
    a: &Matrix<Rational>,
    c: &Matrix<Rational>,
    desired: &DesiredPolynomial,
    method: GainMethod,
    convention: Convention,
) -> Result<ObserverDesign, DesignError> {
    design_with(a, c, desired, method, convention, Detail::Full)
}

/// [`design`] with the amount of recorded working chosen.
///
/// # Errors
/// As [`design`].
pub fn design_with(
    a: &Matrix<Rational>,
    c: &Matrix<Rational>,
    desired: &DesiredPolynomial,
    method: GainMethod,
    convention: Convention,
    detail: Detail,
) -> Result<ObserverDesign, DesignError> {
    single_output(c, method)?;
    let lift = |x: &Rational| Quadratic::rational(x.clone());
    let Designed {
        gain: k,
        derivation,
        achieved,
        observer,
    } = match desired.rational() {
        Some(p) => {
            let d = design_in(a, c, &p, method, detail)?;
            Designed {
                gain: d.gain.map(lift),
                derivation: d.derivation,
                achieved: d.achieved.map(lift),
                observer: d.observer.map(|o| o.map(lift)),
            }
        }
        None => {
            let p = desired.exact.clone().ok_or_else(|| {
                DesignError::NotExact(desired.inexact_reason.clone().unwrap_or_default())
            })?;
            design_in(&a.map(lift), &c.map(lift), &p, method, detail)?
        }
    };
    let gain = ObserverGain {
        matrix: k,
        convention: Convention::AMinusKC,
    }
    .to_convention(convention);
    let mut derivation = derivation;
    if convention == Convention::APlusLC {
        derivation.push(convention.gain_step(), "gain for A + LC", &gain.matrix);
    }
    Ok(ObserverDesign {
        method,
        desired: desired.clone(),
        gain,
        achieved,
        observer_matrix: observer,
        derivation,
    })
}

/// An observer gain designed with parameters: every entry a rational function of them.
#[derive(Debug, Clone)]
pub struct SymbolicDesign {
    /// The gain, in the requested convention.
    pub gain: ObserverGain<crate::algebra::Fraction>,
    /// `det(sI − observer matrix)`, recomputed from the gain by the rank-one update.
    pub achieved: Poly<crate::algebra::Fraction>,
    /// Whether `achieved` equals the desired polynomial identically, as a polynomial in `s`
    /// whose coefficients are rational functions of the parameters (in lowest terms, so
    /// equality is exact, not checked at sample points).
    pub identity: bool,
    /// The steps, in symbols.
    pub derivation: Derivation,
}

/// [`design_with`] over the rational functions of the plant's parameters: the same formulas
/// (the steps of `design_in`), every entry in lowest terms, and the achieved polynomial
/// compared with the desired one as an identity in `s` and the parameters.
///
/// # Errors
/// As [`design`]; an unobservable pair means unobservable for *every* value of the
/// parameters (det O_n is the zero function).
pub fn design_symbolic(
    a: &Matrix<crate::algebra::Fraction>,
    c: &Matrix<crate::algebra::Fraction>,
    desired: &Poly<crate::algebra::Fraction>,
    method: GainMethod,
    convention: Convention,
    detail: Detail,
) -> Result<SymbolicDesign, DesignError> {
    single_output(c, method)?;
    let Designed {
        gain: k,
        mut derivation,
        achieved,
        observer: _,
    } = design_in(a, c, desired, method, detail)?;
    let gain = ObserverGain {
        matrix: k,
        convention: Convention::AMinusKC,
    }
    .to_convention(convention);
    if convention == Convention::APlusLC {
        derivation.push(convention.gain_step(), "gain for A + LC", &gain.matrix);
    }
    Ok(SymbolicDesign {
        identity: &achieved == desired,
        gain,
        achieved,
        derivation,
    })
}

/// The label of a full design's step showing the observer matrix `A − KC`.
pub(crate) const OBSERVER_MATRIX_STEP: &str = "A − KC";

/// The label of a design's check, `det(sI − (A − KC))` recomputed from the gain (a state
/// feedback takes it from its dual design).
pub(crate) const CHECK_STEP: &str = "det(sI − (A − KC))";

/// A derivation that records a step only when the detail asks for it.
struct Steps {
    d: Derivation,
    full: bool,
}

impl Steps {
    fn push(&mut self, label: &str, formula: &str, value: &dyn crate::derivation::Show) {
        self.d.push(label, formula, value);
    }
    fn intermediate(&mut self, label: &str, formula: &str, value: &dyn crate::derivation::Show) {
        if self.full {
            self.d.push(label, formula, value);
        }
    }
}

/// What [`design_in`] finds: the gain (in the A − KC sign), the steps, the achieved
/// polynomial, and the observer matrix A − KC when the steps show it (a reduced-order
/// observer's F is that matrix: kept, it is not formed a second time).
struct Designed<F> {
    gain: Matrix<F>,
    derivation: Derivation,
    achieved: Poly<F>,
    observer: Option<Matrix<F>>,
}

fn design_in<F: Field>(
    a: &Matrix<F>,
    c: &Matrix<F>,
    desired: &Poly<F>,
    method: GainMethod,
    detail: Detail,
) -> Result<Designed<F>, DesignError> {
    let mut d = Steps {
        d: Derivation::new(&format!("Observer gain by the {method} method (A − KC)")),
        full: detail == Detail::Full,
    };
    let s = Shared::new(a, c, desired, method)?;
    d.intermediate("O_n", "[C; CA; …; CA^(n−1)]", &s.o);
    d.push("det(sI − A)", "open-loop polynomial", &s.open_loop);
    d.push("P(s)", "desired observer polynomial", &desired.clone());
    let k = match method {
        GainMethod::Ackermann => {
            let (k, q) = s.ackermann(a, desired, d.full)?;
            if let Some(q) = q {
                d.intermediate("q_n", "O_n⁻¹ e_n", &q);
            }
            d.push("K", "P(A) q_n", &k);
            k
        }
        GainMethod::BassGura => {
            let m = s.toeplitz();
            d.intermediate("M", "Toeplitz of [1 a_1 … a_(n−1)]", &m);
            let diff = coefficient_difference(desired, &s.open_loop, s.n);
            d.push("c − a", "coefficient difference", &diff);
            let k = s.bass_gura(&m, &diff)?;
            d.push("K", "O_n⁻¹ M⁻ᵀ (c − a)", &k);
            k
        }
        GainMethod::Canonical => {
            let g = canonical_from(&s, desired)?;
            d.intermediate("T_o", "(Mᵀ O_n)⁻¹", &g.transformation);
            d.push("K_o", "c − a", &g.canonical);
            d.push("K", "T_o K_o", &g.gain);
            g.gain
        }
        GainMethod::Lemma31 => {
            let (k, k_tilde) = lemma_3_1_from(&s, a, c, desired)?;
            d.push("K̃_o", "C P(A) O_n⁻¹", &k_tilde);
            d.push("K", "T_o rot90(K̃_o)", &k);
            k
        }
    };
    let observer = if d.full {
        let observer = a.sub(&k.mul(c)?)?;
        d.push(OBSERVER_MATRIX_STEP, "observer matrix", &observer);
        Some(observer)
    } else {
        None
    };
    let achieved = s.observer_polynomial(&k)?;
    d.push(CHECK_STEP, "check", &achieved);
    Ok(Designed {
        gain: k,
        derivation: d.d,
        achieved,
        observer,
    })
}

impl ObserverDesign {
    /// The step that showed the gain in its convention (the last so labelled): its text and
    /// cells are the gain's, rendered once for the working, the result and `--json` alike.
    pub fn gain_step(&self) -> Option<&crate::derivation::Step> {
        let label = self.gain.convention.gain_step();
        self.derivation
            .steps
            .iter()
            .rev()
            .find(|s| s.label == label)
    }
    /// The gain in input syntax (`[k1; k2; …]`), as its step rendered it.
    pub fn gain_input(&self) -> String {
        self.gain_step()
            .map_or_else(|| self.gain.matrix.to_input(), |s| s.input.clone())
    }
    /// Whether the achieved polynomial equals the desired one exactly.
    pub fn places_exactly(&self) -> bool {
        self.desired.exact.as_ref() == Some(&self.achieved)
    }
    /// The achieved polynomial factored over Q, when rational.
    pub fn achieved_factored(&self) -> Option<Factored> {
        let c: Option<Vec<Rational>> = self
            .achieved
            .coeffs()
            .iter()
            .map(|c| c.as_rational().cloned())
            .collect();
        Some(Factored::of(&Poly::new(c?, "s")))
    }
    /// A remark on the result, for the derivation.
    pub fn verdict(&self) -> Words {
        Words(if self.places_exactly() {
            "the observer polynomial equals the desired polynomial exactly".into()
        } else {
            "the observer polynomial differs from the desired polynomial".into()
        })
    }
}
