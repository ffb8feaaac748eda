//! Numbers that check what a figure shows, per state, for the estimation error
//! `e = x̂ − x`:
//!
//! * `ise`: `∫ e² dt` (trapezoidal rule) — the right-hand side of Baranowski's (22);
//! * `overshoot`: how far the error swings past zero, as a fraction of its initial size
//!   (the estimate overshooting the true state); 0 when it never changes sign;
//! * `settling_time`: from when on `|e|` stays within 2 % of its largest value (plus three times
//!   the steady-state noise RMS, so a noisy run can settle);
//! * `steady_rms`: RMS of `e` over the last quarter of the run (noise let through);
//! * `max_relative_error`: `max |e| / max |x|` over the run (Sławiński's "error below 0.1 %").

use super::run::Trace;
use serde::Serialize;

/// The summary of one state's estimation error.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StateSummary {
    /// State index (1-based).
    pub state: usize,
    /// `∫ e² dt`.
    pub ise: f64,
    /// Swing past zero relative to `|e(0)|`.
    pub overshoot: f64,
    /// `e(0)`: when it is zero the overshoot is undefined (reported as 0).
    pub initial_error: f64,
    /// Settling time (s); the horizon when it never settles.
    pub settling_time: f64,
    /// RMS of `e` over the last quarter.
    pub steady_rms: f64,
    /// `max |e| / max |x|`.
    pub max_relative_error: f64,
}

/// Summaries for every state.
pub fn summarize(trace: &Trace) -> Vec<StateSummary> {
    let n = trace.x.width();
    let len = trace.t.len();
    (0..n)
        .map(|i| {
            let e: Vec<f64> = (0..len).map(|k| trace.xhat[k][i] - trace.x[k][i]).collect();
            let ise = (1..len)
                .map(|k| 0.5 * (e[k] * e[k] + e[k - 1] * e[k - 1]) * (trace.t[k] - trace.t[k - 1]))
                .sum();
            let e0 = e.first().copied().unwrap_or(0.0);
            let overshoot = if e0 == 0.0 {
                0.0
            } else {
                e.iter().map(|v| -v * e0.signum()).fold(0.0, f64::max) / e0.abs()
            };
            let tail = &e[len - len / 4..];
            let steady_rms = if tail.is_empty() {
                0.0
            } else {
                (tail.iter().map(|v| v * v).sum::<f64>() / tail.len() as f64).sqrt()
            };
            let peak = e.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let band = 0.02 * peak + 3.0 * steady_rms;
            let last_out = e.iter().rposition(|v| v.abs() > band);
            let settling_time = match last_out {
                None => 0.0,
                Some(k) if k + 1 < len => trace.t[k + 1],
                Some(_) => trace.t.last().copied().unwrap_or(0.0),
            };
            let xpeak = (0..len).fold(0.0f64, |m, k| m.max(trace.x[k][i].abs()));
            StateSummary {
                state: i + 1,
                ise,
                overshoot,
                initial_error: e0,
                settling_time,
                steady_rms,
                max_relative_error: if xpeak > 0.0 {
                    peak / xpeak
                } else {
                    f64::INFINITY
                },
            }
        })
        .collect()
}
