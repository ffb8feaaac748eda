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
use crate::canonical_form::{observer_form_di_ruscio, toeplitz_m, CanonicalFormError};
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

/// Dual Ackermann: `K = P(A) O_n⁻¹ e_n` (A − KC), for one output row `c`.
///
/// Over the rationals from order [`linalg::MODULAR_FROM_ORDER`] on, the gain is computed by
/// [`linalg::modular::ackermann_gain_rational`] (the same formula mod many primes, lifted
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
    if c.rows() != 1 {
        return Err(DesignError::MultiOutput {
            method: GainMethod::Ackermann,
            outputs: c.rows(),
        });
    }
    if n >= linalg::MODULAR_FROM_ORDER {
        if let (Some(qa), Some(qc), Some(qp)) = (
            linalg::as_rational(a),
            linalg::as_rational(c),
            crate::linalg::from_rational::<Poly<Rational>, _>(desired.clone()),
        ) {
            if let Some(k) = linalg::modular::ackermann_gain_rational(qa, qc, qp.coeffs())
                .and_then(crate::linalg::from_rational::<Matrix<F>, _>)
            {
                return Ok(k);
            }
        }
    }
    // Generic path (and the error report when the modular path finds O_n singular).
    let o = require_observable(a, c)?;
    let q = linalg::solve(&o, &Matrix::unit(n, n - 1))?;
    Ok(linalg::polynomial_times_vector(desired, a, &q)?)
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
    let open_loop = linalg::characteristic_polynomial(a, "s")?;
    let m = toeplitz_m(&open_loop);
    let diff = coefficient_difference(desired, &open_loop, n);
    let y = linalg::solve(&m.transpose(), &diff)?;
    Ok(linalg::solve(o, &y)?)
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

/// Canonical-form gain: `K_o = c − a`, `K = T_o K_o` (A − KC).
///
/// # Errors
/// [`DesignError`] for several outputs or an unobservable pair.
pub fn canonical_gain<F: Field>(
    a: &Matrix<F>,
    c: &Matrix<F>,
    desired: &Poly<F>,
) -> Result<CanonicalGain<F>, DesignError> {
    let n = check_desired(a, desired)?;
    let form = observer_form_di_ruscio(a, None, c)?;
    let k_o = coefficient_difference(desired, &form.open_loop, n);
    Ok(CanonicalGain {
        gain: form.t.mul(&k_o)?,
        canonical: k_o,
        transformation: form.t,
    })
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
    let n = check_desired(a, desired)?;
    let form = observer_form_di_ruscio(a, None, c)?;
    let cp = c.mul(&linalg::matrix_polynomial(desired, a)?)?;
    // K̃_o O_n = C P(A)  ⇔  O_nᵀ K̃_oᵀ = (C P(A))ᵀ
    let k_tilde = linalg::solve(&form.test_matrix.transpose(), &cp.transpose())?.transpose();
    let k_o = Matrix::from_fn(n, 1, |i, _| k_tilde.get(0, n - 1 - i).clone());
    Ok((form.t.mul(&k_o)?, k_tilde))
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
    /// The steps.
    pub derivation: Derivation,
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
    if c.rows() != 1 {
        return Err(DesignError::MultiOutput {
            method,
            outputs: c.rows(),
        });
    }
    let (k, derivation, achieved) = match desired.rational() {
        Some(p) => {
            let (k, d, ach) = design_in(a, c, &p, method)?;
            let lift = |x: &Rational| Quadratic::rational(x.clone());
            (k.map(lift), d, ach.map(lift))
        }
        None => {
            let p = desired.exact.clone().ok_or_else(|| {
                DesignError::NotExact(desired.inexact_reason.clone().unwrap_or_default())
            })?;
            let lift = |x: &Rational| Quadratic::rational(x.clone());
            design_in(&a.map(lift), &c.map(lift), &p, method)?
        }
    };
    let gain = ObserverGain {
        matrix: k,
        convention: Convention::AMinusKC,
    }
    .to_convention(convention);
    let mut derivation = derivation;
    if convention == Convention::APlusLC {
        derivation.push("L = −K", "gain for A + LC", &gain.matrix);
    }
    Ok(ObserverDesign {
        method,
        desired: desired.clone(),
        gain,
        achieved,
        derivation,
    })
}

fn design_in<F: Field>(
    a: &Matrix<F>,
    c: &Matrix<F>,
    desired: &Poly<F>,
    method: GainMethod,
) -> Result<(Matrix<F>, Derivation, Poly<F>), DesignError> {
    let n = check_desired(a, desired)?;
    let mut d = Derivation::new(&format!("Observer gain by the {method} method (A − KC)"));
    let o = require_observable(a, c)?;
    d.push("O_n", "[C; CA; …; CA^(n−1)]", &o);
    let open_loop = linalg::characteristic_polynomial(a, "s")?;
    d.push("det(sI − A)", "open-loop polynomial", &open_loop);
    d.push("P(s)", "desired observer polynomial", &desired.clone());
    let k = match method {
        GainMethod::Ackermann => {
            let q = linalg::solve(&o, &Matrix::unit(n, n - 1))?;
            d.push("q_n", "O_n⁻¹ e_n", &q);
            let k = linalg::polynomial_times_vector(desired, a, &q)?;
            d.push("K", "P(A) q_n", &k);
            k
        }
        GainMethod::BassGura => {
            let m = toeplitz_m(&open_loop);
            d.push("M", "Toeplitz of [1 a_1 … a_(n−1)]", &m);
            let diff = coefficient_difference(desired, &open_loop, n);
            d.push("c − a", "coefficient difference", &diff);
            let k = bass_gura_gain(a, &o, desired)?;
            d.push("K", "O_n⁻¹ M⁻ᵀ (c − a)", &k);
            k
        }
        GainMethod::Canonical => {
            let g = canonical_gain(a, c, desired)?;
            d.push("T_o", "(Mᵀ O_n)⁻¹", &g.transformation);
            d.push("K_o", "c − a", &g.canonical);
            d.push("K", "T_o K_o", &g.gain);
            g.gain
        }
        GainMethod::Lemma31 => {
            let (k, k_tilde) = lemma_3_1_gain(a, c, desired)?;
            d.push("K̃_o", "C P(A) O_n⁻¹", &k_tilde);
            d.push("K", "T_o rot90(K̃_o)", &k);
            k
        }
    };
    let observer = a.sub(&k.mul(c)?)?;
    d.push("A − KC", "observer matrix", &observer);
    let achieved = linalg::characteristic_polynomial(&observer, "s")?;
    d.push("det(sI − (A − KC))", "check", &achieved);
    Ok((k, d, achieved))
}

impl ObserverDesign {
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
