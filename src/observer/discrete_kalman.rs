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

use crate::algebra::{rational_to_f64, Rational};
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
    /// P read back as fractions, when they satisfy the Riccati equation exactly and give a
    /// stable A − LC: the exact stabilising solution.
    pub exact_p: Option<Matrix<Rational>>,
    /// The exact prediction gain from that P.
    pub exact_gain: Option<Matrix<Rational>>,
}

fn to_f64(m: &Matrix<Rational>) -> DMatrix<f64> {
    DMatrix::from_fn(m.rows(), m.cols(), |i, j| rational_to_f64(m.get(i, j)))
}

fn norm(m: &DMatrix<f64>) -> f64 {
    m.iter().map(|x| x.abs()).fold(0.0, f64::max)
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

/// Solves the filter Riccati equation and forms the gains.
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
    let (af, gf, cf, qf, rf) = (to_f64(a), to_f64(g), to_f64(c), to_f64(qn), to_f64(rn));
    let r_inv = rf
        .clone()
        .try_inverse()
        .ok_or(DiscreteKalmanError::SingularInnovation)?;
    // structured doubling on the dual of the control equation: A₀ = Aᵀ, G₀ = Cᵀ R⁻¹ C, H₀ = G Q Gᵀ
    let mut ak = af.transpose();
    let mut gk = cf.transpose() * &r_inv * &cf;
    let mut hk = &gf * &qf * gf.transpose();
    let identity = DMatrix::<f64>::identity(n, n);
    let mut iterations = 0;
    loop {
        iterations += 1;
        let w = (&identity + &gk * &hk)
            .try_inverse()
            .ok_or(DiscreteKalmanError::NoConvergence(iterations))?;
        let a_next = &ak * &w * &ak;
        let g_next = &gk + &ak * &w * &gk * ak.transpose();
        let h_next = &hk + ak.transpose() * &hk * &w * &ak;
        let change = norm(&(&h_next - &hk));
        (ak, gk, hk) = (a_next, g_next, h_next);
        if change <= 1e-15 * norm(&hk).max(1e-300) {
            break;
        }
        if iterations >= 60 || !change.is_finite() {
            return Err(DiscreteKalmanError::NoConvergence(iterations));
        }
    }
    let pf = (&hk + hk.transpose()) / 2.0;
    let s = &cf * &pf * cf.transpose() + &rf;
    let s_inv = s
        .try_inverse()
        .ok_or(DiscreteKalmanError::SingularInnovation)?;
    let current_gain = &pf * cf.transpose() * &s_inv;
    let gain = &af * &current_gain;
    let ric = &af * &pf * af.transpose()
        - &af * &pf * cf.transpose() * &s_inv * &cf * &pf * af.transpose()
        + &gf * &qf * gf.transpose();
    let residual = norm(&(&ric - &pf)) / norm(&pf).max(1e-300);
    let closed = &af - &gain * &cf;
    let eigenvalues = closed
        .complex_eigenvalues()
        .iter()
        .map(|z| (z.re, z.im))
        .collect();
    let (exact_p, exact_gain) = match exact_solution(&pf, (a, g, c, qn, rn)) {
        Some((p, l)) => (Some(p), Some(l)),
        None => (None, None),
    };
    Ok(DiscreteKalman {
        p: pf,
        gain,
        current_gain,
        iterations,
        residual,
        eigenvalues,
        exact_p,
        exact_gain,
    })
}

type Plant<'a> = (
    &'a Matrix<Rational>,
    &'a Matrix<Rational>,
    &'a Matrix<Rational>,
    &'a Matrix<Rational>,
    &'a Matrix<Rational>,
);

/// P read back as small fractions; kept only if it satisfies the Riccati equation exactly and
/// A − LC is stable (every root of its characteristic polynomial inside the unit circle, exact).
fn exact_solution(
    pf: &DMatrix<f64>,
    (a, g, c, qn, rn): Plant<'_>,
) -> Option<(Matrix<Rational>, Matrix<Rational>)> {
    let n = pf.nrows();
    let mut rows = Vec::with_capacity(n);
    for i in 0..n {
        let row: Option<Vec<Rational>> = (0..n)
            .map(|j| nearest_fraction(pf[(i, j)], 1_000_000))
            .collect();
        rows.push(row?);
    }
    let p = Matrix::from_rows(rows).ok()?;
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
