//! The discrete-time (steady-state) Kalman filter, beside the continuous one of
//! [`super::kalman`]. For x(k+1) = A x(k) + G w(k), y(k) = C x(k) + v(k) with noise covariances
//! Q_n (of w) and R_n (of v), the a-priori error covariance P solves the filter algebraic
//! Riccati equation
//!
//! ```text
//! P = A P Aᵀ − A P Cᵀ (C P Cᵀ + R_n)⁻¹ C P Aᵀ + G Q_n Gᵀ,
//! ```
//!
//! and the prediction gain is L = A P Cᵀ (C P Cᵀ + R_n)⁻¹ (error matrix A − LC); the current
//! (filtered) form corrects with M = P Cᵀ (C P Cᵀ + R_n)⁻¹, L = A M. The equation is solved in
//! f64 by the structured doubling algorithm (quadratically convergent); its residual is reported.
//! Floats are then checked, not trusted: each entry of P is read back as the nearest fraction
//! with a small denominator, and if that rational P satisfies the Riccati equation **exactly**
//! and makes A − LC stable (exact unit-circle test) it is the stabilising solution, exactly.
//!
//! The exact check costs more than the float solution. On a plant whose P is rational (dense
//! A with entries of about 1/(4n), Q_n chosen so that P = I, C = R_n = I), `owb dlqe` took
//! 2.7 ms at n = 20, 18 ms at n = 50 and 144 ms at n = 100 without it, and 5.7, 45 and 322 ms
//! with it (CPU time less the process start, on the 2-core reference machine). So it runs by
//! default only up to [`EXACT_CHECK_ORDER`] states, where it takes milliseconds and the plants
//! of a course live; above that it runs when asked ([`ExactCheckScope::AnyOrder`], `owb dlqe
//! --exact-check`), and the answer says which.

use crate::algebra::{rational_to_f64, Rational};
use crate::linalg::float::{max_or_nan, spectral_radius};
use crate::linalg::{self, LinalgError, Matrix};
use crate::poly::is_schur;
use nalgebra::DMatrix;

/// Why no discrete Kalman filter could be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DiscreteKalmanError {
    /// The matrices do not fit.
    #[error("{0}")]
    Shape(String),
    /// The doubling iteration did not converge (the pair is not detectable, or the noise does
    /// not reach an unstable mode).
    #[error("the Riccati iteration did not converge in {0} doublings: is (A, C) detectable and (A, G Q_n^½) stabilisable?")]
    NoConvergence(usize),
    /// A matrix to invert was singular.
    #[error(transparent)]
    Linalg(#[from] LinalgError),
    /// R_n must be positive definite.
    #[error("C P Cᵀ + R_n is singular: R_n must be positive definite")]
    SingularInnovation,
    /// A covariance that is not one.
    #[error("{name} is not a covariance: {why}")]
    NotCovariance {
        /// `Q_n` or `R_n`.
        name: &'static str,
        /// What fails (symmetry, semidefiniteness, definiteness).
        why: String,
    },
    /// An unobservable mode on or outside the unit circle: no gain makes the filter stable.
    #[error("(A, C) is not detectable: the unobservable eigenvalues {modes} are not all strictly inside the unit circle, so no filter gain stabilises A − LC (no stabilising Riccati solution exists)")]
    NotDetectable {
        /// The unobservable eigenvalues.
        modes: String,
    },
    /// A mode on the unit circle that the process noise does not reach.
    #[error("the process noise G Q_n Gᵀ does not reach the mode(s) {modes} on the unit circle: the Riccati equation has no stabilising solution")]
    UnreachedUnitCircleMode {
        /// The eigenvalues of A that the noise does not excite.
        modes: String,
    },
    /// The float solution failed its check.
    #[error("the computed solution failed its check ({0}): no verified stabilising solution; the problem is too ill-conditioned for f64")]
    Unverified(String),
}

/// The steady-state discrete Kalman filter.
#[derive(Debug, Clone)]
pub struct DiscreteKalman {
    /// The a-priori error covariance P (f64).
    pub p: DMatrix<f64>,
    /// The prediction gain L = A P Cᵀ (C P Cᵀ + R_n)⁻¹ (what python-control's dlqe returns).
    pub gain: DMatrix<f64>,
    /// The current-form gain M = P Cᵀ (C P Cᵀ + R_n)⁻¹.
    pub current_gain: DMatrix<f64>,
    /// Doublings used.
    pub iterations: usize,
    /// ‖P − Ric(P)‖ / ‖P‖ in f64.
    pub residual: f64,
    /// Eigenvalues of A − LC.
    pub eigenvalues: Vec<(f64, f64)>,
    /// The spectral radius of A − LC (below 1: the solution is the stabilising one).
    pub spectral_radius: f64,
    /// Whether the doubling iteration's result was refined by Hewer's Newton iteration from a
    /// stabilising gain (the doubling alone converges to a non-stabilising solution when the
    /// noise does not reach an unstable mode).
    pub refined: bool,
    /// P read back as fractions, when they satisfy the Riccati equation exactly and give a
    /// stable A − LC: the exact stabilising solution.
    pub exact_p: Option<Matrix<Rational>>,
    /// The exact prediction gain from that P.
    pub exact_gain: Option<Matrix<Rational>>,
    /// How far the exact check went (the reason when it was not tried).
    pub exact_check: ExactCheck,
}

impl DiscreteKalman {
    /// Whether the exact read-back was tried: within [`EXACT_CHECK_ORDER`] states (or when
    /// asked) and only when P's entries, read as the nearest fractions with denominators up to
    /// 10⁶, share a common denominator of at most [`READ_BACK_BITS`] bits (a P with small
    /// rational entries has one; a generic float P has thousands of unrelated denominators,
    /// whose exact check would cost more than the whole float solution).
    pub fn read_back_tried(&self) -> bool {
        match self.exact_check {
            ExactCheck::Holds | ExactCheck::Fails => true,
            ExactCheck::DenominatorOverBudget | ExactCheck::OrderOverDefault => false,
        }
    }
}

/// The largest common denominator, in bits, of a P whose exact read-back is tried.
pub const READ_BACK_BITS: u64 = 256;

/// The largest order whose exact check runs without being asked for (see the module
/// documentation for what it costs).
pub const EXACT_CHECK_ORDER: usize = 10;

crate::names::named_enum! {
    /// How far the exact check of the float P went.
    pub enum ExactCheck ("exact check") {
        /// P read back as fractions satisfies the Riccati equation exactly and A − LC is
        /// stable: the exact stabilising solution.
        Holds = "holds",
        /// P was read back as fractions, but they do not satisfy the equation exactly (or do
        /// not give a stable A − LC): the solution is known in f64.
        Fails = "fails",
        /// Not tried: P's entries as small fractions share no common denominator of at most
        /// [`READ_BACK_BITS`] bits.
        DenominatorOverBudget = "denominator_over_budget",
        /// Not tried: more than [`EXACT_CHECK_ORDER`] states, and the check was not asked for.
        OrderOverDefault = "order_over_default",
    }
}

/// Which orders the exact check runs at.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ExactCheckScope {
    /// Up to [`EXACT_CHECK_ORDER`] states.
    Default,
    /// At every order (`owb dlqe --exact-check`).
    AnyOrder,
}

fn to_f64(m: &Matrix<Rational>) -> DMatrix<f64> {
    DMatrix::from_fn(m.rows(), m.cols(), |i, j| rational_to_f64(m.get(i, j)))
}

/// The largest absolute entry; NaN when any entry is NaN (a NaN never passes for small).
fn norm(m: &DMatrix<f64>) -> f64 {
    max_or_nan(m.iter().map(|x| x.abs()))
}

/// The residual accepted for a verified solution: ‖Ric(P) − P‖ / ‖P‖ (largest entries).
pub const RESIDUAL_TOLERANCE: f64 = 1e-8;

/// The exact conditions for a stabilising solution (see [`discrete_kalman`]): covariances,
/// detectability of (A, C) and no unit-circle mode of A unreached by G Q_n Gᵀ. Returns whether
/// the unit-circle question was decided exactly.
fn exact_conditions(
    a: &Matrix<Rational>,
    g: &Matrix<Rational>,
    c: &Matrix<Rational>,
    qn: &Matrix<Rational>,
    rn: &Matrix<Rational>,
) -> Result<bool, DiscreteKalmanError> {
    use crate::linalg::definiteness::{definiteness, Definiteness};
    for (name, m) in [("Q_n", qn), ("R_n", rn)] {
        match definiteness(m)? {
            Definiteness::NotSymmetric => {
                return Err(DiscreteKalmanError::NotCovariance {
                    name,
                    why: "it is not symmetric".into(),
                })
            }
            Definiteness::Indefinite(p) => {
                return Err(DiscreteKalmanError::NotCovariance {
                    name,
                    why: format!("it has a negative eigenvalue (a root of {p})"),
                })
            }
            Definiteness::PositiveSemidefinite => {}
        }
    }
    if linalg::determinant(rn)? == Rational::from_integer(0.into()) {
        return Err(DiscreteKalmanError::NotCovariance {
            name: "R_n",
            why: "it is singular; the measurement noise covariance must be positive definite"
                .into(),
        });
    }
    // an observable pair is detectable, proved modulo a prime without forming O_n
    if !crate::linalg::modular::observable_mod_prime(a, c) {
        let observed = crate::observability::observability_rank_report(a, c)?;
        if !observed.observable() && !is_schur(&observed.unobservable_polynomial) {
            return Err(DiscreteKalmanError::NotDetectable {
                modes: observed.unobservable_eigenvalues.render(),
            });
        }
    }
    // the modes the noise does not reach: the unobservable part of (Aᵀ, G Q_n Gᵀ)
    let w = g.mul(qn)?.mul(&g.transpose())?;
    // a nonsingular G Q_n Gᵀ reaches every mode (its columns alone span the space)
    if crate::linalg::modular::has_full_rank(&w)
        || crate::linalg::modular::observable_mod_prime(&a.transpose(), &w)
    {
        return Ok(true);
    }
    let reached = crate::observability::observability_rank_report(&a.transpose(), &w)?;
    if reached.observable() {
        return Ok(true);
    }
    match crate::poly::has_unit_circle_root(&reached.unobservable_polynomial) {
        Some(true) => Err(DiscreteKalmanError::UnreachedUnitCircleMode {
            modes: reached.unobservable_eigenvalues.render(),
        }),
        Some(false) => Ok(true),
        None => Ok(false),
    }
}

/// A candidate P's pieces: (gain L, current gain M, residual ‖Ric(P) − P‖/‖P‖, A − LC).
type Evaluated = (DMatrix<f64>, DMatrix<f64>, f64, DMatrix<f64>);

/// One candidate P's pieces (see [`Evaluated`]).
fn evaluate(
    af: &DMatrix<f64>,
    cf: &DMatrix<f64>,
    wf: &DMatrix<f64>,
    rf: &DMatrix<f64>,
    pf: &DMatrix<f64>,
) -> Option<Evaluated> {
    let s = cf * pf * cf.transpose() + rf;
    let s_inv = s.try_inverse()?;
    let current = pf * cf.transpose() * &s_inv;
    let gain = af * &current;
    let ric = af * pf * af.transpose() - &gain * cf * pf * af.transpose() + wf;
    let residual = norm(&(&ric - pf)) / norm(pf).max(1e-300);
    let closed = af - &gain * cf;
    Some((gain, current, residual, closed))
}

/// P = M P Mᵀ + Q for ρ(M) < 1, by doubling (Smith): quadratic convergence, bounded.
fn stein(m: &DMatrix<f64>, q: &DMatrix<f64>) -> Option<DMatrix<f64>> {
    let (mut p, mut mk) = (q.clone(), m.clone());
    for _ in 0..64 {
        let next = &p + &mk * &p * mk.transpose();
        let change = norm(&(&next - &p));
        p = next;
        mk = &mk * &mk;
        if !change.is_finite() {
            return None;
        }
        if change <= 1e-16 * norm(&p).max(1e-300) {
            return Some(p);
        }
    }
    (norm(&mk) < 1e-12).then_some(p)
}

/// Hewer's Newton iteration for the filter Riccati equation from a stabilising gain: each step
/// solves the Stein equation of A − LC and updates L; it converges to the stabilising solution
/// whenever one exists.
fn hewer(
    af: &DMatrix<f64>,
    cf: &DMatrix<f64>,
    wf: &DMatrix<f64>,
    rf: &DMatrix<f64>,
    mut gain: DMatrix<f64>,
) -> Option<DMatrix<f64>> {
    let mut p_prev: Option<DMatrix<f64>> = None;
    for _ in 0..100 {
        let closed = af - &gain * cf;
        let q = wf + &gain * rf * gain.transpose();
        let p = stein(&closed, &q)?;
        let p = (&p + p.transpose()) / 2.0;
        let s_inv = (cf * &p * cf.transpose() + rf).try_inverse()?;
        gain = af * &p * cf.transpose() * s_inv;
        if let Some(prev) = &p_prev {
            if norm(&(&p - prev)) <= 1e-15 * norm(&p).max(1e-300) {
                return Some(p);
            }
        }
        p_prev = Some(p);
    }
    p_prev
}

/// Structured doubling for the filter Riccati equation with noise W: P, or `None` when it does
/// not converge within its bound.
fn doubling(
    af: &DMatrix<f64>,
    cf: &DMatrix<f64>,
    wf: &DMatrix<f64>,
    r_inv: &DMatrix<f64>,
) -> (Option<DMatrix<f64>>, usize) {
    let n = af.nrows();
    // on the dual of the control equation: A₀ = Aᵀ, G₀ = Cᵀ R⁻¹ C, H₀ = W
    let mut ak = af.transpose();
    let mut gk = cf.transpose() * r_inv * cf;
    let mut hk = wf.clone();
    let identity = DMatrix::<f64>::identity(n, n);
    let mut iterations = 0;
    loop {
        iterations += 1;
        let Some(w) = (&identity + &gk * &hk).try_inverse() else {
            return (None, iterations);
        };
        let a_next = &ak * &w * &ak;
        let g_next = &gk + &ak * &w * &gk * ak.transpose();
        let h_next = &hk + ak.transpose() * &hk * &w * &ak;
        let change = norm(&(&h_next - &hk));
        (ak, gk, hk) = (a_next, g_next, h_next);
        if change <= 1e-15 * norm(&hk).max(1e-300) {
            return (Some((&hk + hk.transpose()) / 2.0), iterations);
        }
        if iterations >= 60 || !change.is_finite() {
            return (None, iterations);
        }
    }
}

/// The nearest fraction with denominator at most `max_den` (continued fractions).
fn nearest_fraction(x: f64, max_den: i64) -> Option<Rational> {
    if !x.is_finite() {
        return None;
    }
    let (mut h0, mut h1, mut k0, mut k1) = (0i64, 1i64, 1i64, 0i64);
    let mut v = x;
    for _ in 0..64 {
        let a = v.floor();
        if a.abs() > 1e15 {
            break;
        }
        let a = a as i64;
        let (h2, k2) = (
            a.checked_mul(h1)?.checked_add(h0)?,
            a.checked_mul(k1)?.checked_add(k0)?,
        );
        if k2 > max_den {
            break;
        }
        (h0, h1, k0, k1) = (h1, h2, k1, k2);
        let frac = v - a as f64;
        if frac.abs() < 1e-12 {
            break;
        }
        v = 1.0 / frac;
    }
    (k1 != 0).then(|| Rational::new(h1.into(), k1.into()))
}

/// Solves the filter Riccati equation and forms the gains, checking P exactly up to
/// [`EXACT_CHECK_ORDER`] states ([`discrete_kalman_checked`] with [`ExactCheckScope::Default`]).
///
/// # Errors
/// [`DiscreteKalmanError`]: mismatched shapes, no convergence, a singular innovation covariance.
pub fn discrete_kalman(
    a: &Matrix<Rational>,
    g: &Matrix<Rational>,
    c: &Matrix<Rational>,
    qn: &Matrix<Rational>,
    rn: &Matrix<Rational>,
) -> Result<DiscreteKalman, DiscreteKalmanError> {
    discrete_kalman_checked(a, g, c, qn, rn, ExactCheckScope::Default)
}

/// Solves the filter Riccati equation and forms the gains; `scope` says at which orders P is
/// checked exactly.
///
/// # Errors
/// [`DiscreteKalmanError`]: mismatched shapes, no convergence, a singular innovation covariance.
pub fn discrete_kalman_checked(
    a: &Matrix<Rational>,
    g: &Matrix<Rational>,
    c: &Matrix<Rational>,
    qn: &Matrix<Rational>,
    rn: &Matrix<Rational>,
    scope: ExactCheckScope,
) -> Result<DiscreteKalman, DiscreteKalmanError> {
    let (n, p, m) = (a.rows(), c.rows(), g.cols());
    let fits = a.is_square()
        && g.rows() == n
        && c.cols() == n
        && qn.rows() == m
        && qn.cols() == m
        && rn.rows() == p
        && rn.cols() == p;
    if !fits {
        return Err(DiscreteKalmanError::Shape(format!(
            "A must be n×n, G n×m, C p×n, Q_n m×m, R_n p×p (A {}×{}, G {}×{}, C {}×{}, Q_n {}×{}, R_n {}×{})",
            a.rows(), a.cols(), g.rows(), g.cols(), c.rows(), c.cols(), qn.rows(), qn.cols(), rn.rows(), rn.cols()
        )));
    }
    if n == 0 || p == 0 {
        return Err(DiscreteKalmanError::Shape(
            "A and C must have at least one state and one output".into(),
        ));
    }
    let exactly_decided = exact_conditions(a, g, c, qn, rn)?;
    let (af, gf, cf, qf, rf) = (to_f64(a), to_f64(g), to_f64(c), to_f64(qn), to_f64(rn));
    let wf = &gf * &qf * gf.transpose();
    let r_inv = rf
        .clone()
        .try_inverse()
        .ok_or(DiscreteKalmanError::SingularInnovation)?;
    let (pf, iterations, refined) = stabilising_solution(&af, &cf, &wf, &rf, &r_inv)?;
    let (gain, current_gain, residual, closed) =
        evaluate(&af, &cf, &wf, &rf, &pf).ok_or(DiscreteKalmanError::SingularInnovation)?;
    let spectral_radius = spectral_radius(&closed);
    // verified, or refused: a NaN fails both tests
    if residual.is_nan() || residual > RESIDUAL_TOLERANCE {
        return Err(DiscreteKalmanError::Unverified(format!(
            "Riccati residual {residual:.3e} above {RESIDUAL_TOLERANCE:.0e}"
        )));
    }
    if spectral_radius.is_nan() || spectral_radius >= 1.0 {
        return Err(DiscreteKalmanError::Unverified(format!(
            "A − LC has spectral radius {spectral_radius:.6}, not below 1{}",
            if exactly_decided {
                ""
            } else {
                " (whether a unit-circle mode is unreached by the noise could not be decided exactly)"
            }
        )));
    }
    // bounded, as the spectral radius above was (nalgebra's own `complex_eigenvalues` iterates
    // without bound, and stalls on a scaled cyclic shift)
    let eigenvalues = linalg::float::eigenvalues_in_schur_order(&closed)
        .iter()
        .map(|z| (z.re, z.im))
        .collect();
    let (exact_check, exact) = check_exactly(&pf, (a, g, c, qn, rn), scope);
    let (exact_p, exact_gain) = exact.unzip();
    Ok(DiscreteKalman {
        p: pf,
        gain,
        current_gain,
        iterations,
        residual,
        spectral_radius,
        refined,
        eigenvalues,
        exact_p,
        exact_gain,
        exact_check,
    })
}

/// The stabilising solution P in f64, the doublings used, and whether Hewer's iteration refined
/// it: the doubling's solution when it is the stabilising one; otherwise Hewer's Newton
/// iteration from the gain of the same filter with noise W + I (which always has a stabilising
/// solution for a detectable pair); otherwise the doubling's solution as it is, for the checks
/// to judge.
fn stabilising_solution(
    af: &DMatrix<f64>,
    cf: &DMatrix<f64>,
    wf: &DMatrix<f64>,
    rf: &DMatrix<f64>,
    r_inv: &DMatrix<f64>,
) -> Result<(DMatrix<f64>, usize, bool), DiscreteKalmanError> {
    let (doubled, iterations) = doubling(af, cf, wf, r_inv);
    let stabilising = |p: &DMatrix<f64>| {
        evaluate(af, cf, wf, rf, p).is_some_and(|(_, _, res, closed)| {
            res <= RESIDUAL_TOLERANCE && spectral_radius(&closed) < 1.0
        })
    };
    match doubled {
        Some(p) if stabilising(&p) => Ok((p, iterations, false)),
        other => {
            let full_noise = wf + DMatrix::identity(af.nrows(), af.nrows());
            let start = doubling(af, cf, &full_noise, r_inv)
                .0
                .and_then(|p| evaluate(af, cf, &full_noise, rf, &p))
                .map(|(gain, ..)| gain)
                .filter(|gain| spectral_radius(&(af - gain * cf)) < 1.0);
            match (start.and_then(|gain| hewer(af, cf, wf, rf, gain)), other) {
                (Some(p), _) => Ok((p, iterations, true)),
                (None, Some(p)) => Ok((p, iterations, false)),
                (None, None) => Err(DiscreteKalmanError::NoConvergence(iterations)),
            }
        }
    }
}

/// The exact P and its prediction gain L.
type ExactSolution = (Matrix<Rational>, Matrix<Rational>);

/// How far the exact check of the float `pf` goes under `scope`, and the exact P and gain when
/// it holds: not tried above [`EXACT_CHECK_ORDER`] states unless asked, nor when P's fractions
/// share no small common denominator ([`read_back`]).
fn check_exactly(
    pf: &DMatrix<f64>,
    plant: Plant<'_>,
    scope: ExactCheckScope,
) -> (ExactCheck, Option<ExactSolution>) {
    let in_scope = match scope {
        ExactCheckScope::Default => pf.nrows() <= EXACT_CHECK_ORDER,
        ExactCheckScope::AnyOrder => true,
    };
    if !in_scope {
        return (ExactCheck::OrderOverDefault, None);
    }
    match read_back(pf) {
        None => (ExactCheck::DenominatorOverBudget, None),
        Some(p) => match exact_solution(p, plant) {
            Some(found) => (ExactCheck::Holds, Some(found)),
            None => (ExactCheck::Fails, None),
        },
    }
}

type Plant<'a> = (
    &'a Matrix<Rational>,
    &'a Matrix<Rational>,
    &'a Matrix<Rational>,
    &'a Matrix<Rational>,
    &'a Matrix<Rational>,
);

/// P read back as the nearest fractions with denominators up to 10⁶, when they share a common
/// denominator of at most [`READ_BACK_BITS`] bits (the work budget of the exact check: its
/// products grow with that denominator); `None` otherwise.
fn read_back(pf: &DMatrix<f64>) -> Option<Matrix<Rational>> {
    let n = pf.nrows();
    let mut common = num_bigint::BigInt::from(1);
    let mut rows = Vec::with_capacity(n);
    for i in 0..n {
        let mut row = Vec::with_capacity(n);
        for j in 0..n {
            let x = nearest_fraction(pf[(i, j)], 1_000_000)?;
            common = num_integer::Integer::lcm(&common, x.denom());
            if common.bits() > READ_BACK_BITS {
                return None;
            }
            row.push(x);
        }
        rows.push(row);
    }
    Matrix::from_rows(rows).ok()
}

/// P read back as small fractions ([`read_back`]); kept only if it satisfies the Riccati
/// equation exactly and A − LC is stable (every root of its characteristic polynomial inside
/// the unit circle, exact).
fn exact_solution(p: Matrix<Rational>, (a, g, c, qn, rn): Plant<'_>) -> Option<ExactSolution> {
    let s = c.mul(&p).ok()?.mul(&c.transpose()).ok()?.add(rn).ok()?;
    let s_inv = linalg::inverse(&s).ok()?;
    let apc = a.mul(&p).ok()?.mul(&c.transpose()).ok()?;
    let l = apc.mul(&s_inv).ok()?;
    let ric = a
        .mul(&p)
        .ok()?
        .mul(&a.transpose())
        .ok()?
        .sub(&l.mul(c).ok()?.mul(&p).ok()?.mul(&a.transpose()).ok()?)
        .ok()?
        .add(&g.mul(qn).ok()?.mul(&g.transpose()).ok()?)
        .ok()?;
    if ric != p {
        return None;
    }
    let closed = a.sub(&l.mul(c).ok()?).ok()?;
    let chi = linalg::characteristic_polynomial(&closed, "z").ok()?;
    is_schur(&chi).then_some((p, l))
}
