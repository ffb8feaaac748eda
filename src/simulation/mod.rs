//! Simulation of a plant with an observer in parallel (and optional state feedback), as the
//! documents show their observers: Di Ruscio's Figures 1–2, Baranowski's Figures 2–10 (RK4,
//! step 0.01, uniform output noise), Sławiński's perfect observer (Figures 1–5).
//!
//! * [`signal`]: inputs — step, sine, square, piecewise, samples (from CSV).
//! * [`noise`]: seeded measurement and process noise, uniform or Gaussian, from our own
//!   SplitMix64 generator so runs are reproducible bit for bit.
//! * [`integrate`]: adaptive Dormand–Prince 5(4) (the fixed-step RK4 lives in [`run`]).
//! * [`run`]: continuous and discrete-time plant + observer loops, and the perfect observer's
//!   reconstruction from sampled `y`, `u` with causal finite-difference derivatives.
//! * [`metrics`]: numbers that check a figure's claim — integral of squared error, overshoot,
//!   settling time, steady-state noise RMS, largest relative error.
//! * [`plot`], [`csv`]: SVG figures (plotters) and CSV time series.

pub mod csv;
pub mod integrate;
pub mod metrics;
pub mod noise;
#[cfg(feature = "plot")]
pub mod plot;
pub mod run;
pub mod signal;

pub use metrics::{summarize, StateSummary};
pub use run::{simulate, simulate_perfect, Integrator, Loop, Setup, Trace};
pub use signal::Signal;

/// What went wrong in a simulation.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SimulationError {
    /// Shapes of the matrices, gains or initial states do not fit.
    #[error("{0}")]
    Shape(String),
    /// Bad settings (step, horizon, tolerances, signal parameters).
    #[error("{0}")]
    Settings(String),
    /// The run produced non-finite values (an unstable loop or too large a step).
    #[error(
        "the simulation diverged at t = {0} (non-finite state): unstable loop or too large a step"
    )]
    Diverged(f64),
    /// Writing a figure failed.
    #[error("plotting failed: {0}")]
    Plot(String),
}
