//! The plant and its observer, run side by side.
//!
//! Continuous time: `ẋ = A x + B u`, measured `y = C x + D u + v`, observer
//! `x̂' = A x̂ + B u + L (y − C x̂ − D u)` (A − LC convention), optional state feedback
//! `u = r + F x̂`. The measurement noise `v` is sampled once per output interval `h` and held
//! (as a sampled sensor would); the plant and observer are integrated together, by RK4 with
//! step `h` or by Dormand–Prince between the samples.
//!
//! Discrete time (Di Ruscio §2.2 form): `x[k+1] = A x[k] + B u[k]`,
//! `x̂[k+1] = A x̂[k] + B u[k] + K (y[k] − C x̂[k] − D u[k])`.

use super::integrate::{dopri5, AdaptiveStats};
use super::noise::{Noise, NoiseSpec};
use super::signal::Signal;
use super::SimulationError;
use crate::algebra::ToF64;
use crate::observer::perfect::PerfectObserver;
use nalgebra::{DMatrix, DVector};

/// How to advance in time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Integrator {
    /// Classical RK4, one step per output interval.
    Rk4,
    /// Dormand–Prince 5(4) with error control between output samples.
    DormandPrince {
        /// Relative tolerance.
        rtol: f64,
        /// Absolute tolerance.
        atol: f64,
    },
    /// A discrete-time system: `step` is the sampling period, A and B are the discrete matrices.
    Discrete,
}

/// Plant, observer gain and optional feedback, in `f64`.
#[derive(Clone, Debug)]
pub struct Loop {
    /// A.
    pub a: DMatrix<f64>,
    /// B.
    pub b: DMatrix<f64>,
    /// C.
    pub c: DMatrix<f64>,
    /// D.
    pub d: DMatrix<f64>,
    /// Observer gain `L` in the A − LC convention.
    pub gain: DMatrix<f64>,
    /// State feedback `F` in `u = r + F x̂`.
    pub feedback: Option<DMatrix<f64>>,
}

/// Run settings.
#[derive(Clone, Debug)]
pub struct Setup {
    /// End time.
    pub horizon: f64,
    /// Output interval (and RK4 step / sampling period).
    pub step: f64,
    /// Integration method.
    pub integrator: Integrator,
    /// Reference inputs `r`, one signal per input.
    pub input: Vec<Signal>,
    /// Measurement noise on every output (output `i` uses seed + i).
    pub output_noise: Option<NoiseSpec>,
    /// Noise added to the plant's input, unseen by the observer (input `j` uses seed + 1000 + j).
    pub process_noise: Option<NoiseSpec>,
    /// Plant initial state.
    pub x0: Vec<f64>,
    /// Observer initial state.
    pub xhat0: Vec<f64>,
}

/// Samples of a vector signal, stored flat (one allocation per run, not per sample);
/// `series[k]` is the vector at sample `k`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Series {
    data: Vec<f64>,
    width: usize,
}

impl Series {
    /// An empty series of vectors of `width` entries, room for `samples`.
    pub fn new(width: usize, samples: usize) -> Series {
        Series {
            data: Vec::with_capacity(width * samples),
            width,
        }
    }
    /// Entries per sample.
    pub fn width(&self) -> usize {
        self.width
    }
    /// Number of samples.
    pub fn len(&self) -> usize {
        self.data.len().checked_div(self.width).unwrap_or(0)
    }
    /// Whether there are no samples.
    pub fn is_empty(&self) -> bool {
        self.data.is_empty()
    }
    /// Appends one sample (its length must be the width).
    pub fn push(&mut self, v: &[f64]) {
        debug_assert_eq!(v.len(), self.width);
        self.data.extend_from_slice(v);
    }
}

impl std::ops::Index<usize> for Series {
    type Output = [f64];
    fn index(&self, k: usize) -> &[f64] {
        &self.data[k * self.width..(k + 1) * self.width]
    }
}

/// A simulated run, sampled every `step`.
#[derive(Clone, Debug, PartialEq)]
pub struct Trace {
    /// Times.
    pub t: Vec<f64>,
    /// Plant states.
    pub x: Series,
    /// Estimates.
    pub xhat: Series,
    /// Measured outputs (with noise).
    pub y: Series,
    /// Applied inputs.
    pub u: Series,
    /// Accepted and rejected adaptive steps (zero for fixed steps).
    pub adaptive_steps: (usize, usize),
}

/// The largest number of samples a run may produce.
pub const MAX_SAMPLES: usize = 10_000_000;

fn check(l: &Loop, s: &Setup) -> Result<(usize, usize, usize), SimulationError> {
    let n = l.a.nrows();
    let (m, p) = (l.b.ncols(), l.c.nrows());
    let shapes_ok = l.a.ncols() == n
        && l.b.nrows() == n
        && l.c.ncols() == n
        && l.d.shape() == (p, m)
        && l.gain.shape() == (n, p)
        && l.feedback.as_ref().is_none_or(|f| f.shape() == (m, n));
    if !shapes_ok {
        return Err(SimulationError::Shape(format!(
            "A {}×{}, B {}×{}, C {}×{}, D {}×{}, L {}×{}: need A n×n, B n×m, C p×n, D p×m, L n×p{}",
            l.a.nrows(),
            l.a.ncols(),
            l.b.nrows(),
            l.b.ncols(),
            l.c.nrows(),
            l.c.ncols(),
            l.d.nrows(),
            l.d.ncols(),
            l.gain.nrows(),
            l.gain.ncols(),
            if l.feedback.is_some() { ", F m×n" } else { "" }
        )));
    }
    if s.x0.len() != n || s.xhat0.len() != n {
        return Err(SimulationError::Shape(format!(
            "initial states have {} and {} entries; the plant has {n} states",
            s.x0.len(),
            s.xhat0.len()
        )));
    }
    if s.input.len() != m {
        return Err(SimulationError::Shape(format!(
            "{} input signals for {m} inputs",
            s.input.len()
        )));
    }
    for (j, sig) in s.input.iter().enumerate() {
        sig.check()
            .map_err(|e| SimulationError::Settings(format!("input {}: {e}", j + 1)))?;
    }
    if !(s.step > 0.0 && s.horizon > 0.0 && s.step.is_finite() && s.horizon.is_finite()) {
        return Err(SimulationError::Settings(format!(
            "step ({}) and horizon ({}) must be positive",
            s.step, s.horizon
        )));
    }
    let samples = (s.horizon / s.step).round();
    if samples > MAX_SAMPLES as f64 {
        return Err(SimulationError::Settings(format!(
            "{samples} samples: more than the limit of {MAX_SAMPLES}; use a larger step or a shorter horizon"
        )));
    }
    Ok((n, m, p))
}

fn noise_sources(spec: &Option<NoiseSpec>, count: usize, offset: u64) -> Vec<Option<Noise>> {
    (0..count)
        .map(|i| {
            spec.as_ref().map(|s| {
                let shifted = match s {
                    NoiseSpec::Uniform { amplitude, seed } => NoiseSpec::Uniform {
                        amplitude: *amplitude,
                        seed: seed.wrapping_add(offset + i as u64),
                    },
                    NoiseSpec::Gaussian { sigma, seed } => NoiseSpec::Gaussian {
                        sigma: *sigma,
                        seed: seed.wrapping_add(offset + i as u64),
                    },
                };
                Noise::new(&shifted)
            })
        })
        .collect()
}

/// `a · b` over the common length (the loop's inner products, in a fixed order).
fn dot(row: &[f64], v: &[f64]) -> f64 {
    let len = row.len().min(v.len());
    let (row, v) = (&row[..len], &v[..len]);
    let mut acc = 0.0;
    for j in 0..len {
        acc += row[j] * v[j];
    }
    acc
}

/// The loop is linear and time-invariant: with `z = (x, x̂)`,
/// `z' = [A, BF; LC, A + BF − LC] z + [B; B] r + [B w; L v]` — the system and drive matrices,
/// row-major.
struct Augmented {
    n: usize,
    m: usize,
    system: Vec<f64>,
    drive: Vec<f64>,
}

/// The stages of one RK4 step.
struct Rk4Scratch {
    k: [Vec<f64>; 4],
    tmp: Vec<f64>,
}

impl Rk4Scratch {
    fn new(len: usize) -> Self {
        Rk4Scratch {
            k: std::array::from_fn(|_| vec![0.0; len]),
            tmp: vec![0.0; len],
        }
    }
}

impl Augmented {
    fn of(l: &Loop, n: usize, m: usize) -> Self {
        let bf = match &l.feedback {
            Some(f) => &l.b * f,
            None => DMatrix::zeros(n, n),
        };
        let lc = &l.gain * &l.c;
        let mut big = DMatrix::<f64>::zeros(2 * n, 2 * n);
        big.view_mut((0, 0), (n, n)).copy_from(&l.a);
        big.view_mut((0, n), (n, n)).copy_from(&bf);
        big.view_mut((n, 0), (n, n)).copy_from(&lc);
        big.view_mut((n, n), (n, n)).copy_from(&(&l.a + &bf - &lc));
        let mut p_mat = DMatrix::<f64>::zeros(2 * n, m);
        p_mat.view_mut((0, 0), (n, m)).copy_from(&l.b);
        p_mat.view_mut((n, 0), (n, m)).copy_from(&l.b);
        Augmented {
            n,
            m,
            system: big.transpose().iter().copied().collect(),
            drive: p_mat.transpose().iter().copied().collect(),
        }
    }

    /// `z'` given the reference `r` already evaluated at the stage time.
    fn deriv_at(&self, zz: &[f64], constant: &[f64], r: &[f64], out: &mut [f64]) {
        let (n2, m) = (2 * self.n, self.m);
        for i in 0..n2 {
            out[i] = constant[i]
                + dot(&self.system[i * n2..(i + 1) * n2], zz)
                + dot(&self.drive[i * m..(i + 1) * m], r);
        }
    }

    /// One classical RK4 step of length `h`; `r` holds the reference at t, t + h/2, t + h.
    fn rk4_step(
        &self,
        z: &mut [f64],
        constant: &[f64],
        [r0, r_half, r1]: [&[f64]; 3],
        h: f64,
        s: &mut Rk4Scratch,
    ) {
        let n2 = 2 * self.n;
        let [k1, k2, k3, k4] = &mut s.k;
        let tmp = &mut s.tmp;
        self.deriv_at(z, constant, r0, k1);
        for i in 0..n2 {
            tmp[i] = z[i] + 0.5 * h * k1[i];
        }
        self.deriv_at(tmp, constant, r_half, k2);
        for i in 0..n2 {
            tmp[i] = z[i] + 0.5 * h * k2[i];
        }
        self.deriv_at(tmp, constant, r_half, k3);
        for i in 0..n2 {
            tmp[i] = z[i] + h * k3[i];
        }
        self.deriv_at(tmp, constant, r1, k4);
        for i in 0..n2 {
            z[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
    }
}

/// One step of the discrete-time loop: `x[k+1] = A x + B(u + w)`,
/// `x̂[k+1] = A x̂ + B u + L(y − C x̂ − D u)`.
fn discrete_step(l: &Loop, z: &[f64], u: &[f64], w: &[f64], y: &[f64]) -> Vec<f64> {
    let n = l.a.nrows();
    let (x, xhat) = z.split_at(n);
    let ax = DVector::from_column_slice(x);
    let axh = DVector::from_column_slice(xhat);
    let ud = DVector::from_column_slice(u);
    let wd = DVector::from_column_slice(w);
    let yd = DVector::from_column_slice(y);
    let xn = &l.a * &ax + &l.b * (&ud + &wd);
    let xhn = &l.a * &axh + &l.b * &ud + &l.gain * (yd - &l.c * &axh - &l.d * &ud);
    xn.iter().chain(xhn.iter()).copied().collect()
}

/// Runs the loop.
///
/// # Errors
/// [`SimulationError`] for mismatched shapes, bad settings or a diverging run.
pub fn simulate(l: &Loop, s: &Setup) -> Result<Trace, SimulationError> {
    let (n, m, _p) = check(l, s)?;
    let samples = (s.horizon / s.step).round() as usize;
    let mut out_noise = noise_sources(&s.output_noise, l.c.nrows(), 0);
    let mut in_noise = noise_sources(&s.process_noise, m, 1000);
    let mut z: Vec<f64> = s.x0.iter().chain(&s.xhat0).copied().collect();
    let mut trace = Trace {
        t: Vec::with_capacity(samples + 1),
        x: Series::new(n, samples + 1),
        xhat: Series::new(n, samples + 1),
        y: Series::new(l.c.nrows(), samples + 1),
        u: Series::new(m, samples + 1),
        adaptive_steps: (0, 0),
    };
    let aug = Augmented::of(l, n, m);
    let row_major = |x: &DMatrix<f64>| -> Vec<f64> { x.transpose().iter().copied().collect() };
    let (cm, dm, bm, lm) = (
        row_major(&l.c),
        row_major(&l.d),
        row_major(&l.b),
        row_major(&l.gain),
    );
    let fm = l.feedback.as_ref().map(row_major);
    let p = l.c.nrows();
    let reference = |t: f64, r: &mut [f64]| {
        for (rk, sig) in r.iter_mut().zip(&s.input) {
            *rk = sig.value(t);
        }
    };
    // RK4 needs r at t, t + h/2 and t + h; r(t + h) is the next step's r(t)
    let (mut r0, mut r_half, mut r1) = (vec![0.0; m], vec![0.0; m], vec![0.0; m]);
    reference(0.0, &mut r0);
    let mut h_adaptive = s.step;
    let mut stats = AdaptiveStats::default();
    let mut constant = vec![0.0; 2 * n];
    let mut scratch = Rk4Scratch::new(2 * n);
    let (mut u, mut v, mut w, mut y) = (vec![0.0; m], vec![0.0; p], vec![0.0; m], vec![0.0; p]);
    for k in 0..=samples {
        let t = k as f64 * s.step;
        let (x, xhat) = z.split_at(n);
        for (uj, sig) in u.iter_mut().zip(&s.input) {
            *uj = sig.value(t);
        }
        if let Some(f) = &fm {
            for (j, uj) in u.iter_mut().enumerate() {
                *uj += dot(&f[j * n..(j + 1) * n], xhat);
            }
        }
        for (vi, src) in v.iter_mut().zip(out_noise.iter_mut()) {
            *vi = src.as_mut().map_or(0.0, Noise::sample);
        }
        for (wi, src) in w.iter_mut().zip(in_noise.iter_mut()) {
            *wi = src.as_mut().map_or(0.0, Noise::sample);
        }
        for (i, yi) in y.iter_mut().enumerate() {
            *yi = dot(&cm[i * n..(i + 1) * n], x) + dot(&dm[i * m..(i + 1) * m], &u) + v[i];
        }
        trace.t.push(t);
        trace.x.push(x);
        trace.xhat.push(xhat);
        if z.iter().any(|v| !v.is_finite()) {
            return Err(SimulationError::Diverged(t));
        }
        if k == samples {
            trace.y.push(&y);
            trace.u.push(&u);
            break;
        }
        for i in 0..n {
            constant[i] = dot(&bm[i * m..(i + 1) * m], &w);
            constant[n + i] = dot(&lm[i * p..(i + 1) * p], &v);
        }
        match s.integrator {
            Integrator::Rk4 => {
                let h = s.step;
                reference(t + 0.5 * h, &mut r_half);
                reference(t + h, &mut r1);
                aug.rk4_step(&mut z, &constant, [&r0, &r_half, &r1], h, &mut scratch);
                std::mem::swap(&mut r0, &mut r1);
            }
            Integrator::DormandPrince { rtol, atol } => {
                let mut f = |tt: f64, zz: &[f64]| -> Vec<f64> {
                    let mut out = vec![0.0; 2 * n];
                    let mut rr = vec![0.0; m];
                    reference(tt, &mut rr);
                    aug.deriv_at(zz, &constant, &rr, &mut out);
                    out
                };
                z = dopri5(
                    &mut f,
                    t,
                    &z,
                    t + s.step,
                    rtol,
                    atol,
                    &mut h_adaptive,
                    &mut stats,
                )
                .map_err(|_| SimulationError::Diverged(t))?;
            }
            Integrator::Discrete => z = discrete_step(l, &z, &u, &w, &y),
        }
        trace.y.push(&y);
        trace.u.push(&u);
    }
    trace.adaptive_steps = (stats.accepted, stats.rejected);
    Ok(trace)
}

/// The perfect observer at work: the plant is integrated by RK4 with the given step, `y` and
/// `u` are sampled every step (with noise if given), and `x̂ = Σ_k (U_k u^(k) + Y_k y^(k))` is
/// evaluated with causal backward differences, `s^(k)(t_j) ≈ h^(−k) Σ_i (−1)^i C(k,i) s_(j−i)` —
/// what a real implementation can do. The trace starts once enough samples exist.
///
/// # Errors
/// [`SimulationError`] for mismatched shapes or bad settings.
pub fn simulate_perfect(
    l: &Loop,
    observer: &PerfectObserver,
    s: &Setup,
) -> Result<Trace, SimulationError> {
    let (n, m, p) = check(l, s)?;
    let plant_only = Loop {
        gain: DMatrix::zeros(n, p),
        feedback: None,
        ..l.clone()
    };
    let raw = simulate(&plant_only, s)?;
    let order = observer.reconstruction.len().saturating_sub(1);
    let terms: Vec<(DMatrix<f64>, DMatrix<f64>)> = observer
        .reconstruction
        .iter()
        .map(|(u, y)| {
            (
                DMatrix::from_fn(u.rows(), u.cols(), |i, j| u.get(i, j).to_f64()),
                DMatrix::from_fn(y.rows(), y.cols(), |i, j| y.get(i, j).to_f64()),
            )
        })
        .collect();
    let binomial = |k: usize, i: usize| -> f64 {
        (0..i).fold(1.0, |acc, j| acc * (k - j) as f64 / (j + 1) as f64)
    };
    let derivative = |series: &Series, j: usize, k: usize, dim: usize| -> DVector<f64> {
        let mut d = DVector::zeros(dim);
        for i in 0..=k {
            let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
            d += DVector::from_column_slice(&series[j - i]) * (sign * binomial(k, i));
        }
        d / s.step.powi(k as i32)
    };
    let mut trace = Trace {
        t: Vec::new(),
        x: Series::new(n, raw.t.len()),
        xhat: Series::new(n, raw.t.len()),
        y: Series::new(p, raw.t.len()),
        u: Series::new(m, raw.t.len()),
        adaptive_steps: raw.adaptive_steps,
    };
    for j in order..raw.t.len() {
        let mut xhat = DVector::zeros(n);
        for (k, (uk, yk)) in terms.iter().enumerate() {
            xhat += uk * derivative(&raw.u, j, k, m) + yk * derivative(&raw.y, j, k, p);
        }
        trace.t.push(raw.t[j]);
        trace.x.push(&raw.x[j]);
        trace.xhat.push(xhat.as_slice());
        trace.y.push(&raw.y[j]);
        trace.u.push(&raw.u[j]);
    }
    Ok(trace)
}
