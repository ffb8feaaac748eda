//! Furlan et al.'s observer with a weighted measured derivative (§3 of "An Approach to the
//! Optimal Observer Design with Selectable Bandwidth").
//!
//! When an output measures the derivative of a state (acceleration = v̇), the observer can blend
//! the model's derivative with the measured one: `v̂' = (1 − w)·model + w·measurement`. In gain
//! terms the column of `L` (A − LC) for that output is `w·e_k` (`e_k` the state whose derivative
//! is measured), and the other column is then the unique one placing the observer poles
//! ([`super::partial`]). The weight `w ∈ [0, 1]` is chosen to minimise the steady-state
//! estimation-error variance `trace Σ` ([`super::kalman::error_covariance`]): a grid of the
//! interval (the paper's brute force) refined by golden section, then recomputed exactly at a
//! rational weight.

use super::gain::DesignError;
use super::kalman::{
    error_covariance, error_covariance_exact, KalmanError, NoiseIntensities, Plant,
};
use super::partial::place_free_column;
use super::search::golden_section;
use crate::algebra::{Field, Rational, ToF64};
use crate::linalg::float::to_nalgebra;
use crate::linalg::Matrix;
use crate::poly::Poly;
use crate::system::StateSpace;
use nalgebra::DMatrix;
use serde::Serialize;

/// Why the weighted design failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum WeightedError {
    /// The method needs two outputs.
    #[error("the weighted-derivative observer needs exactly two outputs (one of them a measured derivative); C has {0}")]
    Outputs(usize),
    /// An index out of range.
    #[error("{0}")]
    Index(String),
    /// No weight gives a stable placing gain.
    #[error("no weight in [0, 1] gives a stable observer with the requested poles")]
    Infeasible,
    /// The placement failed.
    #[error(transparent)]
    Design(#[from] DesignError),
    /// The noise computation failed.
    #[error(transparent)]
    Noise(#[from] KalmanError),
}

/// The gain with column `derivative_output` equal to `w·e_state` and the other column placing
/// `desired`.
///
/// # Errors
/// [`WeightedError`] for bad indices or an unobservable reduced pair.
pub fn weighted_gain<F: Field>(
    a: &Matrix<F>,
    c: &Matrix<F>,
    desired: &Poly<F>,
    derivative_output: usize,
    state: usize,
    w: F,
) -> Result<Matrix<F>, WeightedError> {
    let (n, p) = (a.rows(), c.rows());
    if p != 2 {
        return Err(WeightedError::Outputs(p));
    }
    if derivative_output >= p || state >= n {
        return Err(WeightedError::Index(format!(
            "output {} / state {} out of range ({p} outputs, {n} states)",
            derivative_output + 1,
            state + 1
        )));
    }
    let mut fixed = Matrix::<F>::zeros(n, p);
    fixed.set(state, derivative_output, w);
    Ok(place_free_column(
        a,
        c,
        &fixed,
        1 - derivative_output,
        desired,
    )?)
}

/// The result of the weight search.
#[derive(Clone, Debug, Serialize)]
pub struct WeightedDesign {
    /// The best weight (rational, six decimals), as text.
    pub weight: String,
    /// The best weight in `f64`.
    pub weight_f64: f64,
    /// The gain at the best weight, exact, in input syntax.
    pub gain_exact: String,
    /// The gain in `f64`, row by row.
    pub gain: Vec<Vec<f64>>,
    /// The exact error covariance at the best weight, converted to `f64`, row by row.
    pub covariance: Vec<Vec<f64>>,
    /// `trace Σ` at the best weight.
    pub variance: f64,
    /// Grid points evaluated (including both ends).
    pub grid_points: usize,
    /// `trace Σ` at `w = 0` (model only) and `w = 1` (measurement only).
    pub variance_at_ends: (f64, f64),
}

/// Searches `w ∈ [0, 1]` for the smallest steady-state `trace Σ`.
///
/// # Errors
/// [`WeightedError`] when no weight gives a stable observer, or for bad shapes.
/// `noise` is `(C_U, C_Y)`; `measured` is `(the output measuring a derivative, the state whose
/// derivative it measures)`, both 0-based.
pub fn weighted_design(
    exact: &StateSpace<Rational>,
    desired: &Poly<Rational>,
    (input_noise, output_noise): (&Matrix<Rational>, &Matrix<Rational>),
    (derivative_output, state): (usize, usize),
    grid: usize,
) -> Result<WeightedDesign, WeightedError> {
    let (a, c) = (exact.a(), exact.c());
    let plant = Plant::from_exact(exact);
    let noise = NoiseIntensities::from_exact(input_noise, output_noise);
    let (af, cf) = (a.map(|x| x.to_f64()), c.map(|x| x.to_f64()));
    let pf = desired.map(ToF64::to_f64);
    let variance = |w: f64| -> f64 {
        weighted_gain(&af, &cf, &pf, derivative_output, state, w)
            .ok()
            .and_then(|g| error_covariance(&plant, &noise, &to_nalgebra(&g)).ok())
            .map_or(f64::INFINITY, |(s, _)| s.trace())
    };
    // check the inputs once, with the error it gives
    weighted_gain(
        a,
        c,
        desired,
        derivative_output,
        state,
        Rational::from_integer(0.into()),
    )?;
    let grid = grid.max(2);
    let values: Vec<f64> = (0..grid)
        .map(|i| variance(i as f64 / (grid - 1) as f64))
        .collect();
    let best = (0..grid)
        .filter(|&i| values[i].is_finite())
        .min_by(|&i, &j| values[i].total_cmp(&values[j]))
        .ok_or(WeightedError::Infeasible)?;
    let step = 1.0 / (grid - 1) as f64;
    let lo = (best as f64 - 1.0).max(0.0) * step;
    let hi = ((best + 1) as f64 * step).min(1.0);
    let (w, _) = golden_section(variance, lo, hi, 1e-9);
    let w_exact = Rational::new(((w * 1e6).round() as i64).into(), 1_000_000.into());
    let g = weighted_gain(a, c, desired, derivative_output, state, w_exact.clone())?;
    let sigma = error_covariance_exact(exact, input_noise, output_noise, &g)?;
    let sf = to_nalgebra(&sigma);
    let rows = |m: &DMatrix<f64>| -> Vec<Vec<f64>> {
        (0..m.nrows())
            .map(|i| m.row(i).iter().copied().collect())
            .collect()
    };
    Ok(WeightedDesign {
        weight: w_exact.to_string(),
        weight_f64: w_exact.to_f64(),
        gain_exact: g.to_input(),
        gain: rows(&to_nalgebra(&g)),
        covariance: rows(&sf),
        variance: sf.trace(),
        grid_points: grid,
        variance_at_ends: (values[0], values[grid - 1]),
    })
}
