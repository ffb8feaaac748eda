//! The steady-state Kalman–Bucy filter and the noise an observer lets through (Furlan et al.).
//!
//! Noise model, stated because the observer sees it: the known input `u` reaches the observer
//! through a measurement with white noise `n_u` (intensity `C_U`), the outputs carry white noise
//! `n_y` (intensity `C_Y`), all independent. With `ẋ = Ax + Bu`, `y = Cx + Du + n_y` and the
//! observer driven by `u + n_u`, the estimation error `e = x̂ − x` obeys
//!
//! `ė = (A − LC) e + (B − LD) n_u + L n_y`,
//!
//! so the input noise is *correlated* between process and measurement when `D ≠ 0` (Furlan's
//! acceleration output): `Q = B C_U Bᵀ`, `R = D C_U Dᵀ + C_Y`, `S = B C_U Dᵀ`. The steady-state
//! error covariance of any stabilising `L` solves the Lyapunov equation
//! `(A − LC) Σ + Σ (A − LC)ᵀ + (B − LD) C_U (B − LD)ᵀ + L C_Y Lᵀ = 0`
//! ([`error_covariance`], exact for rational data in [`error_covariance_exact`]); the Kalman gain
//! minimises it, `L = (P Cᵀ + S) R⁻¹` with `P` the stabilising solution of the filter Riccati
//! equation `A P + P Aᵀ − (P Cᵀ + S) R⁻¹ (C P + Sᵀ) + Q = 0`.
//!
//! Riccati solver: the matrix sign function of the Hamiltonian (Newton iteration with
//! determinant scaling) gives the stable invariant subspace without an ordered Schur form; its
//! `P` then starts Newton–Kleinman (each step a Lyapunov solve, quadratically convergent from a
//! stabilising gain), which repairs the accuracy lost to the bad scaling of problems such as
//! Furlan's (`R` spans ten decades). The relative residual is reported.

use crate::algebra::Field;
use crate::linalg::float::eigenvalues;
use crate::linalg::lyapunov::{lyapunov_exact, lyapunov_f64, LyapunovError};
use crate::linalg::{LinalgError, Matrix};
use crate::system::StateSpace;
use nalgebra::{Complex, DMatrix};
use serde::Serialize;

/// Why a Kalman filter or a noise covariance could not be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum KalmanError {
    /// Shapes do not fit.
    #[error("{0}")]
    Shape(String),
    /// The measurement noise intensity `R = D C_U Dᵀ + C_Y` is singular.
    #[error("the measurement noise intensity R = D C_U Dᵀ + C_Y is singular: every output needs noise for a Kalman filter")]
    SingularR,
    /// The observer matrix is not stable: the steady-state covariance does not exist.
    #[error(
        "A − LC is not stable (eigenvalue with real part {0:.4e}): no steady-state covariance"
    )]
    Unstable(f64),
    /// The Riccati iteration did not converge to a stabilising solution.
    #[error("the Riccati equation solver did not converge: {0}")]
    NoConvergence(String),
    /// The float solution failed its check: reported as a failure, never as a filter.
    #[error("the computed Riccati solution failed its check ({0}): no verified stabilising solution; the problem is too ill-conditioned for f64")]
    Unverified(String),
    /// A Lyapunov solve failed.
    #[error(transparent)]
    Lyapunov(#[from] LyapunovError),
    /// An exact matrix computation failed.
    #[error(transparent)]
    Linalg(#[from] LinalgError),
}

/// The relative Riccati residual accepted for a verified filter (see
/// [`KalmanFilter::residual`]).
pub const RESIDUAL_TOLERANCE: f64 = 1e-8;

/// White-noise intensities: on the measured input (`C_U`, m×m) and the outputs (`C_Y`, p×p).
#[derive(Clone, Debug)]
pub struct NoiseIntensities {
    /// `C_U`.
    pub input: DMatrix<f64>,
    /// `C_Y`.
    pub output: DMatrix<f64>,
}

impl NoiseIntensities {
    /// The f64 image of exact intensities `C_U`, `C_Y`.
    pub fn from_exact(
        input: &Matrix<crate::algebra::Rational>,
        output: &Matrix<crate::algebra::Rational>,
    ) -> Self {
        use crate::linalg::float::to_nalgebra;
        NoiseIntensities {
            input: to_nalgebra(input),
            output: to_nalgebra(output),
        }
    }
}

/// A plant for noise computations: `(A, B, C, D)` in `f64`.
#[derive(Clone, Debug)]
pub struct Plant {
    /// A.
    pub a: DMatrix<f64>,
    /// B.
    pub b: DMatrix<f64>,
    /// C.
    pub c: DMatrix<f64>,
    /// D.
    pub d: DMatrix<f64>,
}

impl Plant {
    /// The f64 image of an exact plant.
    pub fn from_exact(plant: &StateSpace<crate::algebra::Rational>) -> Self {
        use crate::linalg::float::to_nalgebra;
        Plant {
            a: to_nalgebra(plant.a()),
            b: to_nalgebra(plant.b()),
            c: to_nalgebra(plant.c()),
            d: to_nalgebra(plant.d()),
        }
    }
    fn check(&self, noise: &NoiseIntensities) -> Result<(), KalmanError> {
        let n = self.a.nrows();
        let (m, p) = (self.b.ncols(), self.c.nrows());
        let ok = self.a.ncols() == n
            && self.b.nrows() == n
            && self.c.ncols() == n
            && self.d.shape() == (p, m)
            && noise.input.shape() == (m, m)
            && noise.output.shape() == (p, p);
        if ok {
            Ok(())
        } else {
            Err(KalmanError::Shape(format!(
                "A {}×{}, B {}×{}, C {}×{}, D {}×{}, C_U {}×{}, C_Y {}×{}: need A n×n, B n×m, C p×n, D p×m, C_U m×m, C_Y p×p",
                self.a.nrows(), self.a.ncols(), self.b.nrows(), self.b.ncols(),
                self.c.nrows(), self.c.ncols(), self.d.nrows(), self.d.ncols(),
                noise.input.nrows(), noise.input.ncols(), noise.output.nrows(), noise.output.ncols()
            )))
        }
    }
    /// `(Q, R, S)` of the noise model.
    pub fn intensities(
        &self,
        noise: &NoiseIntensities,
    ) -> (DMatrix<f64>, DMatrix<f64>, DMatrix<f64>) {
        let q = &self.b * &noise.input * self.b.transpose();
        let r = &self.d * &noise.input * self.d.transpose() + &noise.output;
        let s = &self.b * &noise.input * self.d.transpose();
        (q, r, s)
    }
}

/// A filter is reported only when verified: its relative Riccati residual within
/// [`RESIDUAL_TOLERANCE`] and its A − LC (`f`) stable; a NaN fails both.
fn verified(residual: f64, f: &DMatrix<f64>) -> Result<(), KalmanError> {
    if residual.is_nan() || residual > RESIDUAL_TOLERANCE {
        return Err(KalmanError::Unverified(format!(
            "relative Riccati residual {residual:.3e} above {RESIDUAL_TOLERANCE:.0e}"
        )));
    }
    let largest = largest_real_part(f);
    if largest.is_nan() || largest >= 0.0 {
        return Err(KalmanError::Unverified(format!(
            "A − LC has an eigenvalue with real part {largest:.4e}, not below 0"
        )));
    }
    Ok(())
}

/// The largest real part of `f`'s eigenvalues, NaN when any is NaN (a NaN never passes for
/// stable: `fold(…, f64::max)` would skip it).
fn largest_real_part(f: &DMatrix<f64>) -> f64 {
    eigenvalues(f)
        .iter()
        .map(|z| z.re)
        .fold(f64::NEG_INFINITY, |acc, x| {
            if acc.is_nan() || x.is_nan() {
                f64::NAN
            } else {
                acc.max(x)
            }
        })
}

/// The steady-state covariance of the estimation error of the observer with gain `L`
/// (A − LC), in `f64`, with the Lyapunov residual.
///
/// # Errors
/// [`KalmanError`] for bad shapes or an unstable `A − LC`.
pub fn error_covariance(
    plant: &Plant,
    noise: &NoiseIntensities,
    l: &DMatrix<f64>,
) -> Result<(DMatrix<f64>, f64), KalmanError> {
    plant.check(noise)?;
    if l.shape() != (plant.a.nrows(), plant.c.nrows()) {
        return Err(KalmanError::Shape(format!(
            "L is {}×{}, must be {}×{}",
            l.nrows(),
            l.ncols(),
            plant.a.nrows(),
            plant.c.nrows()
        )));
    }
    let f = &plant.a - l * &plant.c;
    let worst = largest_real_part(&f);
    if worst.is_nan() || worst >= 0.0 {
        return Err(KalmanError::Unstable(worst));
    }
    let g = &plant.b - l * &plant.d;
    let w = &g * &noise.input * g.transpose() + l * &noise.output * l.transpose();
    let sol = lyapunov_f64(&f, &w)?;
    Ok((sol.x, sol.residual))
}

/// [`error_covariance`] exactly, for a gain and data in a field (the rationals).
///
/// # Errors
/// [`KalmanError`] for bad shapes or when two eigenvalues of `A − LC` sum to zero.
pub fn error_covariance_exact<F: Field>(
    plant: &StateSpace<F>,
    input_noise: &Matrix<F>,
    output_noise: &Matrix<F>,
    l: &Matrix<F>,
) -> Result<Matrix<F>, KalmanError> {
    let f = plant.a().sub(&l.mul(plant.c())?)?;
    let g = plant.b().sub(&l.mul(plant.d())?)?;
    let w = g
        .mul(input_noise)?
        .mul(&g.transpose())?
        .add(&l.mul(output_noise)?.mul(&l.transpose())?)?;
    Ok(lyapunov_exact(&f, &w)?)
}

/// A steady-state Kalman filter.
#[derive(Clone, Debug, Serialize)]
pub struct KalmanFilter {
    /// The gain `L` (A − LC), row by row.
    pub gain: Vec<Vec<f64>>,
    /// The error covariance `P`, row by row.
    pub covariance: Vec<Vec<f64>>,
    /// The observer poles, eigenvalues of `A − LC`, as `(re, im)`.
    pub poles: Vec<(f64, f64)>,
    /// Relative Riccati residual `‖A P + P Aᵀ − (PCᵀ+S)R⁻¹(CP+Sᵀ) + Q‖ / (2‖A‖‖P‖ + ‖(PCᵀ+S)R⁻¹(CP+Sᵀ)‖ + ‖Q‖)`.
    pub residual: f64,
    /// Sign-function iterations used.
    pub sign_iterations: usize,
    /// Newton–Kleinman refinement steps used.
    pub newton_steps: usize,
}

fn rows(m: &DMatrix<f64>) -> Vec<Vec<f64>> {
    (0..m.nrows())
        .map(|i| m.row(i).iter().copied().collect())
        .collect()
}

/// The natural frequency of an observer: `(Π |λ_i|)^(1/n)`, for two poles `√(λ₁λ₂) = ω_n`.
/// (Furlan et al. do not define their "bandwidth"; this reading reproduces their Kalman value.)
pub fn natural_frequency(poles: &[Complex<f64>]) -> f64 {
    if poles.is_empty() {
        return 0.0;
    }
    let log: f64 = poles.iter().map(|z| z.norm().ln()).sum();
    (log / poles.len() as f64).exp()
}

/// The steady-state Kalman filter of the plant under the noise model of this module.
///
/// # Errors
/// [`KalmanError`] for bad shapes, a singular `R`, or no convergence (an undetectable or
/// unstabilisable problem has no stabilising solution).
pub fn kalman_filter(plant: &Plant, noise: &NoiseIntensities) -> Result<KalmanFilter, KalmanError> {
    kalman_filter_with(plant, noise, true)
}

/// The Kalman filter a designer gets by ignoring the correlation `S = B C_U Dᵀ` between process
/// and measurement noise (same `Q` and `R`): not optimal for the true model, which
/// [`error_covariance`] of its gain shows.
///
/// # Errors
/// As [`kalman_filter`].
pub fn kalman_filter_ignoring_correlation(
    plant: &Plant,
    noise: &NoiseIntensities,
) -> Result<KalmanFilter, KalmanError> {
    kalman_filter_with(plant, noise, false)
}

fn kalman_filter_with(
    plant: &Plant,
    noise: &NoiseIntensities,
    correlated: bool,
) -> Result<KalmanFilter, KalmanError> {
    plant.check(noise)?;
    let n = plant.a.nrows();
    let (q, r, s) = plant.intensities(noise);
    let s = if correlated { s } else { s * 0.0 };
    let r_inv = r.clone().try_inverse().ok_or(KalmanError::SingularR)?;
    if !r_inv.iter().all(|x| x.is_finite()) {
        return Err(KalmanError::SingularR);
    }
    let c = &plant.c;
    let a_bar = &plant.a - &s * &r_inv * c;
    let q_bar = &q - &s * &r_inv * s.transpose();
    let g = c.transpose() * &r_inv * c;
    // Hamiltonian of the dual (control) Riccati equation in Āᵀ.
    let mut z = DMatrix::<f64>::zeros(2 * n, 2 * n);
    z.view_mut((0, 0), (n, n)).copy_from(&a_bar.transpose());
    z.view_mut((0, n), (n, n)).copy_from(&(-&g));
    z.view_mut((n, 0), (n, n)).copy_from(&(-&q_bar));
    z.view_mut((n, n), (n, n)).copy_from(&(-&a_bar));
    let (z, sign_iterations) = matrix_sign(z)?;
    let w11 = z.view((0, 0), (n, n)).clone_owned();
    let w12 = z.view((0, n), (n, n)).clone_owned();
    let w21 = z.view((n, 0), (n, n)).clone_owned();
    let w22 = z.view((n, n), (n, n)).clone_owned();
    let eye = DMatrix::<f64>::identity(n, n);
    let mut lhs = DMatrix::<f64>::zeros(2 * n, n);
    lhs.view_mut((0, 0), (n, n)).copy_from(&w12);
    lhs.view_mut((n, 0), (n, n)).copy_from(&(&w22 + &eye));
    let mut rhs = DMatrix::<f64>::zeros(2 * n, n);
    rhs.view_mut((0, 0), (n, n)).copy_from(&(-(&w11 + &eye)));
    rhs.view_mut((n, 0), (n, n)).copy_from(&(-&w21));
    let mut p = crate::linalg::float::try_svd(&lhs, true, true)
        .ok_or_else(|| {
            KalmanError::NoConvergence(
                "the sign iteration's result has infinite or NaN entries (overflow)".into(),
            )
        })?
        .solve(&rhs, 1e-14)
        .map_err(|e| KalmanError::NoConvergence(e.to_string()))?;
    p = (&p + p.transpose()) * 0.5;
    let gain_of = |p: &DMatrix<f64>| (p * c.transpose() + &s) * &r_inv;
    // Newton–Kleinman refinement: P ← covariance of the gain of P.
    let mut newton_steps = 0;
    let residual_of = |p: &DMatrix<f64>| {
        let k = p * c.transpose() + &s;
        let quad = &k * &r_inv * k.transpose();
        let res = &plant.a * p + p * plant.a.transpose() - &quad + &q;
        let scale = 2.0 * plant.a.norm() * p.norm() + quad.norm() + q.norm();
        if scale > 0.0 {
            res.norm() / scale
        } else {
            res.norm()
        }
    };
    let mut residual = residual_of(&p);
    for _ in 0..50 {
        let l = gain_of(&p);
        let f = &plant.a - &l * c;
        let worst = largest_real_part(&f);
        if worst.is_nan() || worst >= 0.0 {
            return Err(KalmanError::NoConvergence(
                "the sign-function solution is not stabilising".into(),
            ));
        }
        let w = &q - &s * l.transpose() - &l * s.transpose() + &l * &r * l.transpose();
        let next = lyapunov_f64(&f, &w)?.x;
        let next = (&next + next.transpose()) * 0.5;
        let next_residual = residual_of(&next);
        let change = (&next - &p).norm() / next.norm().max(f64::MIN_POSITIVE);
        newton_steps += 1;
        if next_residual <= residual || change > 1e-12 {
            p = next;
            residual = next_residual;
        }
        if change < 1e-14 || next_residual > residual {
            break;
        }
    }
    let l = gain_of(&p);
    let f = &plant.a - &l * c;
    let poles = eigenvalues(&f).iter().map(|z| (z.re, z.im)).collect();
    if !residual.is_finite() {
        return Err(KalmanError::NoConvergence("non-finite residual".into()));
    }
    verified(residual, &f)?;
    Ok(KalmanFilter {
        gain: rows(&l),
        covariance: rows(&p),
        poles,
        residual,
        sign_iterations,
        newton_steps,
    })
}

/// The matrix sign function of the Hamiltonian `z` (2n × 2n) by Newton's iteration
/// `Z ← (c Z + Z⁻¹/c)/2` with determinantal scaling `c = |det Z|^(−1/2n)`, and the number of
/// iterations taken (at most 100; relative change below 10⁻¹³).
fn matrix_sign(mut z: DMatrix<f64>) -> Result<(DMatrix<f64>, usize), KalmanError> {
    let n = z.nrows() / 2;
    let mut sign_iterations = 0;
    for _ in 0..100 {
        sign_iterations += 1;
        // one LU factorisation for both the inverse and the determinant; up to 4×4 (a plant
        // of order 2) nalgebra inverts by cofactors, kept there: with the LU's inverse the
        // printed residuals of Furlan's filters (10⁻²⁰) move in their second digit
        let (inv, det) = if 2 * n > 4 {
            let lu = z.clone().lu();
            (lu.try_inverse(), lu.determinant().abs())
        } else {
            (z.clone().try_inverse(), z.clone().lu().determinant().abs())
        };
        let inv = inv.ok_or_else(|| {
            KalmanError::NoConvergence(
                "the Hamiltonian has an eigenvalue on the imaginary axis".into(),
            )
        })?;
        let scale = if det.is_finite() && det > 0.0 {
            det.powf(-1.0 / (2 * n) as f64)
        } else {
            1.0
        };
        let next = (&z * scale + inv / scale) * 0.5;
        let change = (&next - &z).norm() / next.norm();
        z = next;
        if change < 1e-13 {
            break;
        }
    }
    Ok((z, sign_iterations))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scalar_kalman_filter_matches_the_closed_form() {
        // ẋ = −x + u, y = x: P solves −2P − P²/r + q = 0.
        let plant = Plant {
            a: DMatrix::from_element(1, 1, -1.0),
            b: DMatrix::from_element(1, 1, 1.0),
            c: DMatrix::from_element(1, 1, 1.0),
            d: DMatrix::from_element(1, 1, 0.0),
        };
        let noise = NoiseIntensities {
            input: DMatrix::from_element(1, 1, 3.0),
            output: DMatrix::from_element(1, 1, 0.5),
        };
        let k = kalman_filter(&plant, &noise).unwrap();
        let (q, r) = (3.0, 0.5);
        let p = r * (-1.0 + (1.0f64 + q / r).sqrt());
        assert!((k.covariance[0][0] - p).abs() < 1e-12, "{k:?}");
        assert!(k.residual < 1e-14);
        let (sigma, _) =
            error_covariance(&plant, &noise, &DMatrix::from_element(1, 1, p / r)).unwrap();
        assert!((sigma[(0, 0)] - p).abs() < 1e-12);
    }
}
