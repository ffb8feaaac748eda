//! The adaptive Dormand–Prince 5(4) pair with error control, for fast (stiff-ish) observers
//! such as Furlan's 600 rad/s one. (The documents' fixed-step RK4 is written into the
//! simulator's loop in [`super::run`], where the loop's linearity lets it reuse buffers.)

/// Statistics of an adaptive run.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AdaptiveStats {
    /// Accepted steps.
    pub accepted: usize,
    /// Rejected steps.
    pub rejected: usize,
}

/// Integrates from `t0` to `t1` with Dormand–Prince 5(4), local error per component below
/// `atol + rtol·|x|`. `h` is the first trial step and is updated for the next call.
///
/// # Errors
/// A message when the step size underflows (the problem is too stiff for an explicit method at
/// these tolerances) or the state becomes non-finite.
#[allow(clippy::too_many_arguments)]
pub fn dopri5(
    f: &mut impl FnMut(f64, &[f64]) -> Vec<f64>,
    t0: f64,
    x0: &[f64],
    t1: f64,
    rtol: f64,
    atol: f64,
    h: &mut f64,
    stats: &mut AdaptiveStats,
) -> Result<Vec<f64>, String> {
    const C: [f64; 6] = [1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0];
    const A: [[f64; 6]; 6] = [
        [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
        [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
        [
            19372.0 / 6561.0,
            -25360.0 / 2187.0,
            64448.0 / 6561.0,
            -212.0 / 729.0,
            0.0,
            0.0,
        ],
        [
            9017.0 / 3168.0,
            -355.0 / 33.0,
            46732.0 / 5247.0,
            49.0 / 176.0,
            -5103.0 / 18656.0,
            0.0,
        ],
        [
            35.0 / 384.0,
            0.0,
            500.0 / 1113.0,
            125.0 / 192.0,
            -2187.0 / 6784.0,
            11.0 / 84.0,
        ],
    ];
    const E: [f64; 7] = [
        71.0 / 57600.0,
        0.0,
        -71.0 / 16695.0,
        71.0 / 1920.0,
        -17253.0 / 339200.0,
        22.0 / 525.0,
        -1.0 / 40.0,
    ];
    let mut t = t0;
    let mut x = x0.to_vec();
    let n = x.len();
    while t < t1 {
        let step = h.min(t1 - t);
        if step <= 1e-14 * t1.abs().max(1.0) {
            if t1 - t <= 1e-14 * t1.abs().max(1.0) {
                break;
            }
            return Err(format!("step size underflow at t = {t}"));
        }
        let mut k: Vec<Vec<f64>> = Vec::with_capacity(7);
        k.push(f(t, &x));
        for s in 0..6 {
            let mut xs = x.clone();
            for (j, kj) in k.iter().enumerate() {
                let a = A[s][j];
                if a != 0.0 {
                    for i in 0..n {
                        xs[i] += step * a * kj[i];
                    }
                }
            }
            k.push(f(t + C[s] * step, &xs));
        }
        // 5th-order solution = the stage-7 argument (FSAL)
        let mut x5 = x.clone();
        for (j, kj) in k.iter().take(6).enumerate() {
            for i in 0..n {
                x5[i] += step * A[5][j] * kj[i];
            }
        }
        let mut err = 0.0f64;
        for i in 0..n {
            let e: f64 = (0..7).map(|j| E[j] * k[j][i]).sum::<f64>() * step;
            let scale = atol + rtol * x[i].abs().max(x5[i].abs());
            err = err.max((e / scale).abs());
        }
        if !err.is_finite() || x5.iter().any(|v| !v.is_finite()) {
            return Err(format!("non-finite state at t = {t}"));
        }
        if err <= 1.0 {
            t += step;
            x = x5;
            stats.accepted += 1;
        } else {
            stats.rejected += 1;
        }
        let factor = if err == 0.0 {
            5.0
        } else {
            (0.9 * err.powf(-0.2)).clamp(0.2, 5.0)
        };
        *h = step * factor;
    }
    Ok(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dopri_integrates_an_oscillator_to_tolerance() {
        let mut f = |_t: f64, x: &[f64]| vec![x[1], -x[0]];
        let mut h = 0.1;
        let mut stats = AdaptiveStats::default();
        let x = dopri5(
            &mut f,
            0.0,
            &[1.0, 0.0],
            10.0,
            1e-10,
            1e-12,
            &mut h,
            &mut stats,
        )
        .unwrap();
        assert!((x[0] - 10f64.cos()).abs() < 1e-8 && (x[1] + 10f64.sin()).abs() < 1e-8);
        assert!(stats.accepted > 10);
    }
}
