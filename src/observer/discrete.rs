//! Discrete-time observers, exact. For x(k+1) = A x(k) + B u(k), y(k) = C x(k) the observer
//! gain formulas are those of continuous time (Di Ruscio §2.2: only where the poles go changes,
//! inside the unit circle instead of the left half-plane), so the design reuses
//! [`design_with`] on the polynomial in z, and adds what is particular to
//! sampled systems:
//!
//! * the **prediction** estimator x̄(k+1) = A x̄(k) + B u(k) + K (y(k) − C x̄(k)), error matrix
//!   A − KC, and the **current** (filtered) estimator x̂(k) = x̄(k) + L_c (y(k) − C x̄(k)),
//!   x̄(k+1) = A x̂(k) + B u(k), whose error matrix is A − L_c C A; with L_c = A⁻¹ K both have
//!   the same error polynomial (A must be invertible);
//! * the **dead-beat** observer, all poles at z = 0: the error matrix is nilpotent, so the error
//!   is exactly zero after at most n steps — proved here by computing its powers exactly;
//! * stability decided exactly (every root inside the unit circle, [`is_schur`]);
//! * poles from a continuous-time specification, z = e^(sT), and a continuous plant sampled
//!   with a zero-order hold ([`zero_order_hold`]): exact where the exponential is a polynomial
//!   (s = 0, a nilpotent A), otherwise in f64 with an error estimate — e^(λT) is transcendental
//!   for every rational λT ≠ 0 (Lindemann), so no exact field holds it.

use super::{design_with, Convention, DesignError, Detail, GainMethod, ObserverDesign};
use super::{DesiredPolynomial, PolynomialFamily};
use crate::algebra::{Field, Quadratic, Rational, Ring, Zero};
use crate::derivation::Derivation;
use crate::linalg::{self, LinalgError, Matrix};
use crate::poly::{is_schur, Poly};
use crate::syntax::WordFractions;

/// Which discrete-time estimator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Estimator {
    /// x̄(k+1) from y(k): the estimate of x(k) uses measurements up to k − 1.
    Prediction,
    /// x̂(k) corrected with y(k) itself.
    Current,
}

impl Estimator {
    /// `prediction` or `current`.
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "prediction" => Some(Estimator::Prediction),
            "current" | "filtered" => Some(Estimator::Current),
            _ => None,
        }
    }
    /// The flag's value.
    pub fn flag(self) -> &'static str {
        match self {
            Estimator::Prediction => "prediction",
            Estimator::Current => "current",
        }
    }
}

/// Why no discrete-time observer could be designed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DiscreteError {
    /// The gain design failed (unobservable pair, several outputs, bad polynomial).
    #[error(transparent)]
    Design(#[from] DesignError),
    /// A matrix computation failed.
    #[error(transparent)]
    Linalg(#[from] LinalgError),
    /// The current estimator needs A invertible.
    #[error("the current estimator needs A invertible (L_c = A⁻¹ K); A is singular: use the prediction estimator")]
    SingularA,
    /// A sampling period must be positive.
    #[error("the sampling period {0} must be positive")]
    Period(String),
    /// The matrices do not fit.
    #[error("{0}")]
    Shape(String),
    /// A float result beyond the range of f64 (or not computable there).
    #[error("{0}")]
    Float(String),
}

/// A discrete-time observer, designed exactly.
#[derive(Debug, Clone)]
pub struct DiscreteObserver {
    /// Which estimator.
    pub estimator: Estimator,
    /// The prediction gain K (A − KC), with its derivation; in the requested convention.
    pub design: ObserverDesign,
    /// The current estimator's gain L_c = A⁻¹ K (in the requested convention's sign).
    pub current_gain: Option<Matrix<Quadratic>>,
    /// The error matrix: A − KC (prediction) or A − L_c C A (current).
    pub error_matrix: Matrix<Quadratic>,
    /// det(zI − error matrix), recomputed.
    pub error_polynomial: Poly<Quadratic>,
    /// Every root strictly inside the unit circle (exact; `None` when the polynomial has
    /// irrational coefficients).
    pub stable: Option<bool>,
    /// The smallest k with (error matrix)ᵏ = 0, when the matrix is nilpotent (dead-beat).
    pub nilpotent_index: Option<usize>,
    /// The steps (the gain's, then the estimator's and the proofs).
    pub derivation: Derivation,
}

/// The dead-beat polynomial zⁿ.
pub fn deadbeat_polynomial(n: usize) -> DesiredPolynomial {
    DesiredPolynomial::repeated_root(Quadratic::zero(), n)
}

fn lift(m: &Matrix<Rational>) -> Matrix<Quadratic> {
    m.map(|x| Quadratic::rational(x.clone()))
}

/// The gain's steps speak of s; in discrete time the variable is z: the polynomial steps'
/// labels and values renamed. Only the variable is renamed — an `s` standing alone as a name
/// (`9s`, `s^2`, `(s + 1)`), not one inside a word (`sqrt`, `\\cdots`, a parameter `sigma` or
/// `ws`) — and only in the steps whose label is a polynomial in s.
pub(crate) fn speak_of_z(derivation: &mut crate::derivation::Derivation) {
    for step in &mut derivation.steps {
        if step.label.starts_with("det(sI") || step.label.starts_with("P(s)") {
            step.label = step.label.replace("sI", "zI").replace("P(s)", "P(z)");
            for v in [&mut step.text, &mut step.latex, &mut step.input] {
                *v = variable_renamed(v, 's', 'z');
            }
        }
    }
}

/// `text` with every `from` that stands alone as a name replaced by `to`: not preceded by a
/// letter, `_` or `\\`, not followed by a letter, digit or `_` (a coefficient before it, `9s`,
/// is no part of its name).
fn variable_renamed(text: &str, from: char, to: char) -> String {
    let chars: Vec<char> = text.chars().collect();
    let word = |c: char| c.is_alphanumeric() || c == '_';
    chars
        .iter()
        .enumerate()
        .map(|(i, &ch)| {
            let before = i.checked_sub(1).map(|j| chars[j]);
            let after = chars.get(i + 1).copied();
            let alone = before.is_none_or(|b| !(b.is_alphabetic() || b == '_' || b == '\\'))
                && after.is_none_or(|a| !word(a));
            if ch == from && alone {
                to
            } else {
                ch
            }
        })
        .collect()
}

/// Designs a discrete-time observer for (A, C) with the desired polynomial in z.
///
/// # Errors
/// [`DiscreteError`]: the design's own errors, and a singular A for the current estimator.
pub fn discrete_observer(
    a: &Matrix<Rational>,
    c: &Matrix<Rational>,
    desired: &DesiredPolynomial,
    method: GainMethod,
    convention: Convention,
    estimator: Estimator,
    detail: Detail,
) -> Result<DiscreteObserver, DiscreteError> {
    // the polynomial in z, so the derivation speaks of z
    let mut in_z = desired.clone();
    in_z.exact = desired.exact.clone().map(|p| p.with_var("z"));
    let design = design_with(a, c, &in_z, method, convention, detail)?;
    let mut derivation = design.derivation.clone();
    speak_of_z(&mut derivation);
    // the prediction gain in the A − KC sign
    let k = design.gain.to_convention(Convention::AMinusKC).matrix;
    let (aq, cq) = (lift(a), lift(c));
    // A − KC on the rational path when K is rational (no gcd per Q(√d) operation)
    let a_minus_kc = match linalg::rational_entries(&k) {
        Some(kr) => lift(&a.sub(&kr.mul(c)?)?),
        None => aq.sub(&k.mul(&cq)?)?,
    };
    let (error_matrix, current_gain) = match estimator {
        Estimator::Prediction => (a_minus_kc.clone(), None),
        Estimator::Current => {
            let a_inv = linalg::inverse(a).map_err(|_| DiscreteError::SingularA)?;
            let (l_c, m) = match linalg::rational_entries(&k) {
                Some(kr) => {
                    let l = a_inv.mul(&kr)?;
                    // L_c C A = L_c (C A): a column times a row
                    let m = a.sub(&l.mul(&c.mul(a)?)?)?;
                    (lift(&l), lift(&m))
                }
                None => {
                    let l = lift(&a_inv).mul(&k)?;
                    let m = aq.sub(&l.mul(&cq.mul(&aq)?)?)?;
                    (l, m)
                }
            };
            derivation.push("L_c", "A⁻¹ K (current estimator)", &l_c);
            derivation.push("A − L_c C A", "error matrix of x̂", &m);
            (m, Some(convention.from_a_minus_kc(&l_c)))
        }
    };
    // det(zI − (A − KC)) was checked exactly by the design (the rank-one update); the current
    // estimator's error matrix is similar to A − KC, A − L_c C A = A⁻¹(A − KC)A, so both share
    // the polynomial and the nilpotency index
    let error_polynomial = design.achieved.clone().with_var("z");
    if estimator == Estimator::Current {
        derivation.push(
            "det(zI − (A − L_c C A))",
            "the polynomial of A − KC, since A − L_c C A = A⁻¹(A − KC)A (similar matrices)",
            &error_polynomial,
        );
    }
    let stable = rational_poly(&error_polynomial).map(|p| is_schur(&p));
    // the design is single-output and proved (A, C) observable, so (A − KC, C) is observable
    // too (O_n of the pair is T·O_n(A, C), T unit lower triangular) and C's row makes
    // A − KC cyclic: one Jordan block per eigenvalue, so when its polynomial is zⁿ it is
    // nilpotent of index exactly n — no power formed, no cyclicity test needed
    let n = a_minus_kc.require_square("nilpotency")?;
    let nilpotent_index = is_power_of_z(&error_polynomial, n).then_some(n);
    if let Some(k) = nilpotent_index {
        // the power is zero by the argument above; it is recorded, not computed
        let power: Matrix<Quadratic> = Matrix::zeros(n, n);
        derivation.push(
            &format!("power {k} of the error matrix"),
            "zero: the error vanishes after this many steps",
            &power,
        );
    }
    Ok(DiscreteObserver {
        estimator,
        design,
        current_gain,
        error_matrix,
        error_polynomial,
        stable,
        nilpotent_index,
        derivation,
    })
}

fn rational_poly(p: &Poly<Quadratic>) -> Option<Poly<Rational>> {
    let c: Option<Vec<Rational>> = p
        .coeffs()
        .iter()
        .map(|x| x.as_rational().cloned())
        .collect();
    Some(Poly::new(c?, p.var()))
}

/// The smallest k ≤ n with Mᵏ = 0, or `None` when M is not nilpotent (Mⁿ ≠ 0).
///
/// M is nilpotent exactly when det(zI − M) = zⁿ, which the characteristic polynomial decides
/// (multimodular for rational M, O(n³) per prime); only then are powers formed, and for
/// rational M on integers (M scaled by a common denominator D: (DM)ᵏ = 0 ⇔ Mᵏ = 0), so no
/// gcd is taken per operation.
///
/// # Errors
/// A product of mismatched shapes (M not square).
pub fn nilpotent_index(m: &Matrix<Quadratic>) -> Result<Option<usize>, LinalgError> {
    if let Some(r) = linalg::rational_entries(m) {
        return rational_nilpotent_index(&r);
    }
    let chi = linalg::characteristic_polynomial(m, "z")?;
    nilpotent_index_with(m, &chi)
}

/// [`nilpotent_index`] of a rational matrix, on its own entries (a plant sampled by `zoh` is
/// not lifted to Q(√d) to be told, usually by its trace, that it is not nilpotent).
///
/// # Errors
/// M not square.
pub fn rational_nilpotent_index(m: &Matrix<Rational>) -> Result<Option<usize>, LinalgError> {
    let n = m.require_square("nilpotency")?;
    if linalg::modular::surely_not_nilpotent(m) {
        return Ok(None);
    }
    let chi = linalg::characteristic_polynomial(m, "z")?;
    if !is_power_of_z(&chi, n) {
        return Ok(None);
    }
    rational_powers_index(m)
}

/// Whether `chi` is `zⁿ`: the characteristic polynomial of a nilpotent n × n matrix (of index
/// n when the matrix is cyclic, a single Jordan block).
fn is_power_of_z<F: crate::algebra::Field>(chi: &Poly<F>, n: usize) -> bool {
    chi.degree() == Some(n) && (0..n).all(|k| chi.coeff(k).is_zero())
}

/// The index of a rational matrix known to be nilpotent: n when it is cyclic, otherwise the
/// first zero power, formed on integers (M scaled by a common denominator D: (DM)ᵏ = 0 ⇔
/// Mᵏ = 0), so no gcd is taken per operation.
fn rational_powers_index(r: &Matrix<Rational>) -> Result<Option<usize>, LinalgError> {
    let n = r.require_square("nilpotency")?;
    // a cyclic nilpotent matrix is one Jordan block: its index is n (the single-output
    // dead-beat observer always is, (A − KC, C) being observable)
    if linalg::modular::is_cyclic(r) {
        return Ok(Some(n));
    }
    let d = Rational::common_denominator(r.entries());
    let integer = r.map(|x| x.scale_to_integer(&d));
    let mut p = integer.clone();
    for k in 1..=n {
        if p.is_zero() {
            return Ok(Some(k));
        }
        p = p.mul(&integer)?;
    }
    Ok(None)
}

/// [`nilpotent_index`] for a matrix whose characteristic polynomial `chi` is known exactly.
///
/// # Errors
/// A product of mismatched shapes (M not square).
pub fn nilpotent_index_with(
    m: &Matrix<Quadratic>,
    chi: &Poly<Quadratic>,
) -> Result<Option<usize>, LinalgError> {
    let n = m.require_square("nilpotency")?;
    if !is_power_of_z(chi, n) {
        return Ok(None);
    }
    if let Some(r) = linalg::rational_entries(m) {
        return rational_powers_index(&r);
    }
    let mut p = Matrix::identity(n);
    for k in 1..=n {
        p = p.mul(m)?;
        if p.is_zero() {
            return Ok(Some(k));
        }
    }
    Ok(None)
}

/// A continuous pole s mapped to z = e^(sT), in f64 (exact only for s = 0, where z = 1).
pub fn map_pole(s: &Quadratic, t: &Rational) -> (f64, f64) {
    let (re, im) = s.to_complex_f64();
    let t = crate::algebra::rational_to_f64(t);
    let r = (re * t).exp();
    (r * (im * t).cos(), r * (im * t).sin())
}

/// The desired discrete-time polynomial from continuous poles, z = e^(sT): exact when every
/// pole is 0, otherwise known in f64 only (with the reason said).
///
/// # Errors
/// [`DiscreteError::Period`] for T ≤ 0.
pub fn from_continuous_poles(
    poles: &[Quadratic],
    t: &Rational,
) -> Result<DesiredPolynomial, DiscreteError> {
    if *t <= Rational::zero() {
        return Err(DiscreteError::Period(t.to_string()));
    }
    if poles.iter().all(Zero::is_zero) {
        // s = 0 maps to z = 1 exactly: (z − 1)ⁿ
        return Ok(DesiredPolynomial::repeated_root(
            Quadratic::from_i64(1),
            poles.len(),
        ));
    }
    // a real system's poles come in conjugate pairs, each as often as its partner
    for p in poles.iter().filter(|p| !p.is_real()) {
        let count = |x: &Quadratic| poles.iter().filter(|q| *q == x).count();
        if count(p) != count(&p.conjugate()) {
            return Err(DiscreteError::Shape(format!(
                "the pole {p} comes without its conjugate {}: a real system's poles come in conjugate pairs",
                p.conjugate()
            )));
        }
    }
    // ∏ (z − z_i) in f64, complex pairs multiplied out
    let mut coeffs: Vec<(f64, f64)> = vec![(1.0, 0.0)];
    for p in poles {
        let (zr, zi) = map_pole(p, t);
        let mut next = vec![(0.0, 0.0); coeffs.len() + 1];
        for (k, (cr, ci)) in coeffs.iter().enumerate() {
            next[k + 1].0 += cr;
            next[k + 1].1 += ci;
            next[k].0 -= cr * zr - ci * zi;
            next[k].1 -= cr * zi + ci * zr;
        }
        coeffs = next;
    }
    if coeffs
        .iter()
        .any(|(re, im)| !re.is_finite() || !im.is_finite())
    {
        return Err(DiscreteError::Float(format!(
            "z = e^(sT) overflows f64 for these poles at T = {t} (Re(s)·T beyond about 709)"
        )));
    }
    let float = Poly::new(coeffs.iter().map(|c| c.0).collect(), "s");
    Ok(DesiredPolynomial {
        family: PolynomialFamily::Coefficients,
        exact: None,
        float,
        inexact_reason: Some(format!(
            "z = e^(sT) with T = {t} is transcendental for every rational sT ≠ 0 (Lindemann): the poles are known in f64 only"
        )),
    })
}

/// A continuous plant sampled with a zero-order hold: Φ = e^(AT), Γ = ∫₀ᵀ e^(Aτ) dτ B.
#[derive(Debug, Clone)]
pub enum Sampled {
    /// A is nilpotent: e^(AT) = Σ_(k<n) (AT)ᵏ/k! exactly.
    Exact {
        /// Φ.
        phi: Matrix<Rational>,
        /// Γ.
        gamma: Matrix<Rational>,
        /// The index of nilpotency of A.
        index: usize,
    },
    /// Otherwise, in f64.
    Float {
        /// Φ, row by row.
        phi: Vec<Vec<f64>>,
        /// Γ, row by row.
        gamma: Vec<Vec<f64>>,
        /// The largest difference between two independent evaluations (the Padé exponential,
        /// [`linalg::expm::expm`], and a scaled Taylor series of the augmented matrix).
        error_estimate: f64,
    },
}

/// Samples (A, B) with a zero-order hold of period T.
///
/// # Errors
/// [`DiscreteError`]: T ≤ 0, A not square, B with another number of rows.
pub fn zero_order_hold(
    a: &Matrix<Rational>,
    b: &Matrix<Rational>,
    t: &Rational,
) -> Result<Sampled, DiscreteError> {
    check_plant(t, (a.rows(), a.cols()), (b.rows(), b.cols()))?;
    let n = a.rows();
    if let Some(index) = rational_nilpotent_index(a)? {
        // Φ = Σ_(k<index) A^k T^k / k!, Γ = Σ_(k<index) A^k T^(k+1)/(k+1)! B
        let mut phi = Matrix::zeros(n, n);
        let mut integral = Matrix::zeros(n, n);
        let mut power = Matrix::identity(n);
        let mut factor = Rational::from_integer(1.into()); // T^k / k!
        for k in 0..index {
            phi = phi.add(&power.scale(&factor))?;
            let next = factor.clone() * t.clone() / Rational::from_integer((k as i64 + 1).into());
            integral = integral.add(&power.scale(&next))?;
            factor = next;
            power = power.mul(a)?;
        }
        return Ok(Sampled::Exact {
            phi,
            gamma: integral.mul(b)?,
            index,
        });
    }
    let f64_at = |m: &Matrix<Rational>, i, j| crate::algebra::rational_to_f64(m.get(i, j));
    let aug = augmented(
        (n, b.cols()),
        |i, j| f64_at(a, i, j),
        |i, j| f64_at(b, i, j),
        t,
    )?;
    float_zoh(n, aug)
}

/// [`zero_order_hold`] of a plant read as word fractions (the command line's common case,
/// `[8/50 -2/50; 0 1]`): when the trace of A is proved nonzero — A is then not nilpotent — the
/// `f64` work runs on the entries' words, without the exact matrices (at order 100 their 10 000
/// fractions took more time and memory than the exponential); otherwise the exact matrices are
/// made and [`zero_order_hold`] decides. The result is that function's, bit for bit: the same
/// branch is taken, and [`WordFractions::f64_at`] is the exact entry's `f64`.
///
/// # Errors
///
/// As [`zero_order_hold`].
pub(crate) fn zero_order_hold_words(
    a: WordFractions,
    b: WordFractions,
    t: &Rational,
) -> Result<Sampled, DiscreteError> {
    check_plant(t, (a.rows(), a.cols()), (b.rows(), b.cols()))?;
    if !a.trace_is_nonzero() {
        return zero_order_hold(&a.to_rational(), &b.to_rational(), t);
    }
    let aug = augmented(
        (a.rows(), b.cols()),
        |i, j| a.f64_at(i, j),
        |i, j| b.f64_at(i, j),
        t,
    )?;
    let n = a.rows();
    // the words are done with: their room goes to the exponential's matrices
    drop((a, b));
    float_zoh(n, aug)
}

/// A positive period, A square and B with its rows.
fn check_plant(t: &Rational, a: (usize, usize), b: (usize, usize)) -> Result<(), DiscreteError> {
    if *t <= Rational::zero() {
        return Err(DiscreteError::Period(t.to_string()));
    }
    if a.0 != a.1 || b.0 != a.0 {
        return Err(DiscreteError::Shape(format!(
            "A must be square and B have its rows (A {}×{}, B {}×{})",
            a.0, a.1, b.0, b.1
        )));
    }
    Ok(())
}

/// `Σ_(k<16) X^k / k!` by Paterson and Stockmeyer's scheme, from X, X² = X·X and X⁴ = X²·X²:
/// X³ = X²·X formed, then Horner's rule in X⁴ over blocks of four terms — four matrix products
/// here, six with the two powers — then squared `squarings` times; `None` when a square is not
/// finite. Two matrices serve the whole rule and the squarings: each product goes into the
/// other, and each block of terms is added to it entry by entry, summed as a matrix of its own
/// would be (the same bits, and one matrix fewer at the series' peak than with a matrix for
/// each block).
fn taylor_16(
    x: &nalgebra::DMatrix<f64>,
    x2: &nalgebra::DMatrix<f64>,
    x4: &nalgebra::DMatrix<f64>,
    squarings: i32,
) -> Option<nalgebra::DMatrix<f64>> {
    use nalgebra::DMatrix;
    let size = x.nrows();
    let x3 = linalg::gemm::product(x2, x);
    // 1/k! for k < 16
    let mut inverse_factorial = [1.0f64; 16];
    for k in 1..16 {
        inverse_factorial[k] = inverse_factorial[k - 1] / k as f64;
    }
    // block j = c₄ⱼI + c₄ⱼ₊₁X + c₄ⱼ₊₂X² + c₄ⱼ₊₃X³, each entry summed from the identity's term
    // (c on the diagonal, +0 off it) in that order, then added to the product's entry — or,
    // for the first block, the entry itself
    let with_block = |target: &mut DMatrix<f64>, j: usize, add: bool| {
        let c = &inverse_factorial[4 * j..4 * j + 4];
        let columns = target
            .as_mut_slice()
            .chunks_mut(size)
            .zip(x.as_slice().chunks(size))
            .zip(x2.as_slice().chunks(size))
            .zip(x3.as_slice().chunks(size));
        for (col, (((t, p1), p2), p3)) in columns.enumerate() {
            let entries = t.iter_mut().zip(p1).zip(p2).zip(p3);
            for (row, (((t, &a1), &a2), &a3)) in entries.enumerate() {
                let b = if row == col { c[0] } else { 0.0 };
                let b = b + a1 * c[1];
                let b = b + a2 * c[2];
                let b = b + a3 * c[3];
                *t = if add { *t + b } else { b };
            }
        }
    };
    let mut result = DMatrix::<f64>::zeros(size, size);
    with_block(&mut result, 3, false);
    let mut product = DMatrix::<f64>::zeros(size, size);
    for j in (0..3).rev() {
        linalg::gemm::product_into(&mut product, &result, x4);
        with_block(&mut product, j, true);
        std::mem::swap(&mut result, &mut product);
    }
    drop(x3);
    for _ in 0..squarings {
        linalg::gemm::product_into(&mut product, &result, &result);
        std::mem::swap(&mut result, &mut product);
        if result.as_slice().iter().any(|x| !x.is_finite()) {
            return None;
        }
    }
    Some(result)
}

/// The Taylor series' X = A_aug/2^s, X² and X⁴: the last two are the Padé exponential's
/// powers of A_aug scaled by 4^−s and 16^−s where that gives the products' bits exactly
/// ([`scaling_is_exact`]; two matrix products saved), else the products of X. The flag says
/// which.
fn taylor_powers(
    aug: &nalgebra::DMatrix<f64>,
    squarings: i32,
    exponential: linalg::expm::Exponential,
) -> (
    nalgebra::DMatrix<f64>,
    nalgebra::DMatrix<f64>,
    nalgebra::DMatrix<f64>,
    bool,
) {
    let x = aug / 2f64.powi(squarings);
    match (exponential.square, exponential.fourth) {
        (Some(mut x2), Some(mut x4)) if scaling_is_exact(aug, squarings) => {
            x2 *= power_of_two(-2 * squarings);
            x4 *= power_of_two(-4 * squarings);
            (x, x2, x4, true)
        }
        _ => {
            let x2 = linalg::gemm::product(&x, &x);
            let x4 = linalg::gemm::product(&x2, &x2);
            (x, x2, x4, false)
        }
    }
}

/// 2^k, for −1022 ≤ k ≤ 1023.
fn power_of_two(k: i32) -> f64 {
    debug_assert!((-1022..=1023).contains(&k));
    f64::from_bits(((1023 + i64::from(k)) as u64) << 52)
}

/// Whether, for X = M/2^s, the products X·X and X²·X² equal M²/4^s and M⁴/16^s bit for bit.
///
/// Scaling by a power of two commutes with every rounded operation (a product, a sum, a fused
/// multiply-add) as long as no value falls below f64's normal range or overflows. If e is the
/// exponent of M's smallest nonzero entry, every entry is a multiple of 2^(e−52); every partial
/// sum of M² is then a multiple of 2^(2(e−52)) (a rounding keeps a multiple of a power of two
/// that size or coarser), and of M⁴ a multiple of 2^(4(e−52)). Scaled by 2^−s they stay normal
/// when 4(e − 52 − s) ≥ −1022. With |M| ≤ 2^200 and order at most 2^20, no partial sum of M⁴
/// exceeds about 2^860. And s ≤ 255 keeps 2^(−4s) a normal number.
fn scaling_is_exact(m: &nalgebra::DMatrix<f64>, squarings: i32) -> bool {
    if squarings == 0 {
        return true; // the very same products
    }
    let (smallest, largest) = m
        .as_slice()
        .iter()
        .map(|v| v.abs())
        .filter(|&v| v != 0.0)
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if smallest == f64::INFINITY {
        return true; // M = 0: every product is zero either way
    }
    let exponent = |v: f64| ((v.to_bits() >> 52) & 0x7ff) as i64 - 1023;
    let subnormal = smallest < f64::MIN_POSITIVE;
    !subnormal
        && (0..=255).contains(&squarings)
        && m.nrows() <= 1 << 20
        && largest <= power_of_two(200)
        && 4 * (exponent(smallest) - 52 - i64::from(squarings)) >= -1022
}

/// The augmented matrix [A B; 0 0]·T of the n × n A and n × m B whose entries `a(i, j)` and
/// `b(i, j)` give, for the period `t`: its exponential holds Φ and Γ.
fn augmented(
    (n, m): (usize, usize),
    a: impl Fn(usize, usize) -> f64,
    b: impl Fn(usize, usize) -> f64,
    t: &Rational,
) -> Result<nalgebra::DMatrix<f64>, DiscreteError> {
    let t = crate::algebra::rational_to_f64(t);
    let aug = nalgebra::DMatrix::from_fn(n + m, n + m, |i, j| match (i < n, j < n) {
        (true, true) => a(i, j) * t,
        (true, false) => b(i, j - n) * t,
        _ => 0.0,
    });
    if aug.as_slice().iter().any(|x| !x.is_finite()) {
        return Err(DiscreteError::Float(
            "an entry of A·T or B·T is beyond the range of f64 (about 1.8e308)".into(),
        ));
    }
    Ok(aug)
}

/// Φ and Γ in `f64` from the [`augmented`] matrix of a plant with n states, by the Padé
/// approximant, with the error estimate: the largest difference from the scaled Taylor series.
fn float_zoh(n: usize, aug: nalgebra::DMatrix<f64>) -> Result<Sampled, DiscreteError> {
    let m = aug.ncols() - n;
    let overflow = || {
        DiscreteError::Float(
            "e^(AT) overflows f64 (an eigenvalue λ of A with Re(λ)·T beyond about 709): Φ and Γ cannot be represented"
                .into(),
        )
    };
    // scaling and squaring with a Taylor series, independent of the Padé approximant: the
    // matrix scaled by 2^−s to a 1-norm at most 1/2, where the terms after the 16th add less
    // than 0.5¹⁶/16! < 10⁻¹⁸; the squarings are bounded (a norm near f64's limit needs about
    // 1 030)
    let norm = linalg::expm::one_norm(&aug);
    if !norm.is_finite() {
        return Err(overflow());
    }
    let squarings = if norm > 0.5 {
        ((norm / 0.5).log2().ceil() as i32).clamp(0, linalg::expm::MAX_SQUARINGS as i32)
    } else {
        0
    };
    // a singular Padé denominator needs entries beyond f64 (the scaling keeps ‖X/2^s‖ ≤ 4.25,
    // where q_13 is nonsingular), which the checks above have refused
    let mut exponential = linalg::expm::expm_with_powers(&aug).ok_or_else(overflow)?;
    let pade = std::mem::take(&mut exponential.value);
    if pade.as_slice().iter().any(|x| !x.is_finite()) {
        return Err(overflow());
    }
    let (x, x2, x4, _) = taylor_powers(&aug, squarings, exponential);
    drop(aug); // its room to the series' matrices
    let taylor = taylor_16(&x, &x2, &x4, squarings).ok_or_else(overflow)?;
    drop((x, x2, x4));
    // the largest difference, a NaN counted as failure
    let error = linalg::float::max_or_nan(
        pade.as_slice()
            .iter()
            .zip(taylor.as_slice())
            .map(|(p, t)| (p - t).abs()),
    );
    if !error.is_finite() {
        return Err(overflow());
    }
    let phi = rows_of(&pade, n, 0..n);
    let gamma = rows_of(&pade, n, n..n + m);
    Ok(Sampled::Float {
        phi,
        gamma,
        error_estimate: error,
    })
}

/// The first `count` rows of `m`'s columns `columns`, row by row. Column-major `m` is read
/// eight rows at a time, so that each column's eight entries come from one cache line, where
/// a row at a time would take a line for every entry (at order 101 the matrix is larger than
/// the first-level cache).
fn rows_of(
    m: &nalgebra::DMatrix<f64>,
    count: usize,
    columns: std::ops::Range<usize>,
) -> Vec<Vec<f64>> {
    let mut rows: Vec<Vec<f64>> = (0..count)
        .map(|_| Vec::with_capacity(columns.len()))
        .collect();
    let size = m.nrows();
    for (block, first) in rows.chunks_mut(8).zip((0..count).step_by(8)) {
        for j in columns.clone() {
            let column = &m.as_slice()[j * size + first..j * size + first + block.len()];
            for (row, &x) in block.iter_mut().zip(column) {
                row.push(x);
            }
        }
    }
    rows
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_are_read_as_the_entries_are_indexed() {
        for (size, count, columns) in [
            (11, 10, 0..10),
            (11, 10, 10..11),
            (21, 19, 2..21),
            (3, 0, 0..3),
        ] {
            let m = nalgebra::DMatrix::from_fn(size, size, |i, j| (i * 100 + j) as f64);
            let expected: Vec<Vec<f64>> = (0..count)
                .map(|i| columns.clone().map(|j| m[(i, j)]).collect())
                .collect();
            assert_eq!(rows_of(&m, count, columns), expected);
        }
    }

    proptest::proptest! {
        /// The Taylor series' X² and X⁴ taken from the Padé exponential's powers are the
        /// products of X = M/2^s bit for bit, at every scale where [`scaling_is_exact`] allows
        /// it; and it allows it for ordinary plants.
        #[test]
        fn shared_taylor_powers_are_the_products(
            order in 2usize..9,
            entries in proptest::collection::vec((-1.0f64..1.0, 0i32..40, 0u8..6), 64),
            base in -280i32..-180,
            squarings in 0i32..12,
            ordinary in proptest::prelude::any::<bool>(),
        ) {
            // an ordinary plant: entries within 2^±20; else exponents from `base` to 40 above
            // it (across the limit of exactness, near 2^−200, and of range), and some zeros
            let m = nalgebra::DMatrix::from_fn(order, order, |i, j| {
                let (v, e, zero) = entries[i * 8 + j];
                let e = if ordinary { e - 20 } else { base + e };
                if zero == 0 { 0.0 } else { v * power_of_two(e) }
            });
            let Some(exponential) = linalg::expm::expm_with_powers(&m) else {
                // its powers beyond f64: refused, as the zero-order hold refuses it
                proptest::prop_assert!(!ordinary);
                return Ok(());
            };
            let (x, x2, x4, shared) = taylor_powers(&m, squarings, exponential);
            let product2 = &x * &x;
            let product4 = &product2 * &product2;
            let bits = |a: &nalgebra::DMatrix<f64>| a.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            proptest::prop_assert_eq!(bits(&x2), bits(&product2));
            proptest::prop_assert_eq!(bits(&x4), bits(&product4));
            if ordinary {
                proptest::prop_assert!(shared, "an ordinary plant computed its powers afresh");
            }
        }

        /// The dead-beat design's index, taken from cyclicity, is the one the powers of the
        /// error matrix show, for both estimators.
        #[test]
        fn deadbeat_index_is_the_powers_index(
            entries in proptest::collection::vec(-3i64..=3, 9),
            c in proptest::collection::vec(-2i64..=2, 3),
            current in proptest::prelude::any::<bool>(),
        ) {
            let q = |x: i64| Rational::from_integer(x.into());
            let a = Matrix::from_fn(3, 3, |i, j| q(entries[3 * i + j]));
            let c = Matrix::from_fn(1, 3, |_, j| q(c[j]));
            let estimator = if current { Estimator::Current } else { Estimator::Prediction };
            let Ok(d) = discrete_observer(
                &a, &c, &deadbeat_polynomial(3), GainMethod::Ackermann, Convention::AMinusKC,
                estimator, Detail::Full,
            ) else {
                return Ok(()); // unobservable, or A singular for the current estimator
            };
            let by_powers = nilpotent_index_with(&d.error_matrix, &d.error_polynomial).unwrap();
            proptest::prop_assert_eq!(d.nilpotent_index, by_powers);
            proptest::prop_assert_eq!(d.nilpotent_index, Some(3));
        }

        /// The zero-order hold of a plant read as word fractions is the exact plant's, bit for
        /// bit: nilpotent plants (strictly triangular, and similar to one by a shear, their
        /// traces zero) go the exact way, the others the float way with the same `f64`s.
        #[test]
        fn words_hold_as_the_exact_plant(
            entries in proptest::collection::vec((-9i64..=9, 1i64..=12), 9),
            b in proptest::collection::vec((-9i64..=9, 1i64..=12), 3),
            shape in 0usize..3,
            period in 1i64..=20,
        ) {
            // 0: as drawn; 1: strictly upper triangular; 2: that, sheared (S N S⁻¹, S = I + e₁e₂ᵀ)
            let mut a: Vec<(i64, i64)> = entries.clone();
            if shape > 0 {
                for i in 0..3 {
                    for j in 0..=i {
                        a[3 * i + j] = (0, 1);
                    }
                }
            }
            let text = |m: &[(i64, i64)], cols: usize| format!("[{}]", m.chunks(cols)
                .map(|r| r.iter().map(|(n, d)| format!("{n}/{d}")).collect::<Vec<_>>().join(" "))
                .collect::<Vec<_>>().join("; "));
            let exact = |t: &str| crate::syntax::parse_rational_matrix(t).expect("numbers");
            let (mut a_exact, b_text) = (exact(&text(&a, 3)), text(&b, 1));
            if shape == 2 {
                let q = |x: i64| Rational::from_integer(x.into());
                let s = Matrix::from_fn(3, 3, |i, j| q(i64::from(i == j) + i64::from(i == 0 && j == 1)));
                let s_inv = Matrix::from_fn(3, 3, |i, j| q(i64::from(i == j) - i64::from(i == 0 && j == 1)));
                a_exact = s.mul(&a_exact).and_then(|m| m.mul(&s_inv)).expect("3 × 3");
            }
            let a_text = a_exact.to_input();
            let words = |t: &str| crate::syntax::word_fractions(t).expect("numbers");
            let t = Rational::new(1.into(), period.into());
            let by_words = zero_order_hold_words(words(&a_text), words(&b_text), &t);
            let by_exact = zero_order_hold(&exact(&a_text), &exact(&b_text), &t);
            proptest::prop_assert_eq!(format!("{by_words:?}"), format!("{by_exact:?}"));
            let exact_way = matches!(by_words, Ok(Sampled::Exact { .. }));
            proptest::prop_assert!(exact_way || shape == 0, "a nilpotent A held in f64");
        }
    }
}
