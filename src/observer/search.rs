//! Derivative-free minimisation for design indices that are not smooth enough for Newton
//! (a largest eigenvalue) or are only evaluated: Nelder–Mead on `Rⁿ` and golden-section search
//! on an interval. Both are deterministic: same start, same result.

/// How a multistart search runs: how many seeded starts, the seed, and whom to tell after each
/// start (a progress bar; nobody by default).
///
/// ```
/// use observer_workbench::observer::search::Multistart;
/// use std::cell::Cell;
/// let done = Cell::new(0);
/// let tell = || done.set(done.get() + 1);
/// let m = Multistart::new(3, 2024).reporting(&tell);
/// (0..m.starts).for_each(|_| m.started());
/// assert_eq!(done.get(), 3);
/// ```
#[derive(Clone, Copy)]
pub struct Multistart<'a> {
    /// Seeded random starts.
    pub starts: usize,
    /// Seed of the starts: same seed, same result.
    pub seed: u64,
    on_start: &'a dyn Fn(),
    /// No new start after this instant (the starts run so far are reported): a search is
    /// bounded by time as well as by count.
    deadline: Option<std::time::Instant>,
}

impl Multistart<'static> {
    /// `starts` starts from `seed`, telling nobody.
    pub fn new(starts: usize, seed: u64) -> Self {
        Multistart {
            starts,
            seed,
            on_start: &|| {},
            deadline: None,
        }
    }
}

impl<'a> Multistart<'a> {
    /// The same search, calling `tell` after each start.
    pub fn reporting<'b>(self, tell: &'b dyn Fn()) -> Multistart<'b> {
        Multistart {
            starts: self.starts,
            seed: self.seed,
            on_start: tell,
            deadline: self.deadline,
        }
    }

    /// The same search, starting no new start once `budget` has passed (from now). Where there
    /// is no clock — the core's WebAssembly build, which the browser runs without JavaScript
    /// bindings, where `Instant::now` panics — the count of starts alone bounds the search.
    #[must_use]
    pub fn within(mut self, budget: std::time::Duration) -> Self {
        self.deadline = now().and_then(|t| t.checked_add(budget));
        self
    }

    /// Whether the time budget is spent: no further start may begin.
    pub fn out_of_time(&self) -> bool {
        match (self.deadline, now()) {
            (Some(d), Some(t)) => t >= d,
            _ => false,
        }
    }

    /// Called by the search after each start.
    pub fn started(&self) {
        (self.on_start)();
    }
}

/// The time now, where the platform has a clock.
fn now() -> Option<std::time::Instant> {
    #[cfg(all(target_arch = "wasm32", target_os = "unknown"))]
    {
        None
    }
    #[cfg(not(all(target_arch = "wasm32", target_os = "unknown")))]
    {
        Some(std::time::Instant::now())
    }
}

/// A seeded generator of uniform numbers in `[0, 1)` (xorshift64), for the starts of multistart
/// searches: the same seed gives the same starts on every platform.
pub fn seeded_uniform(seed: u64) -> impl FnMut() -> f64 {
    let mut state = seed | 1;
    move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The result of a Nelder–Mead run.
#[derive(Clone, Debug)]
pub struct SimplexResult {
    /// The best point.
    pub x: Vec<f64>,
    /// Its value.
    pub value: f64,
    /// Function evaluations used.
    pub evaluations: usize,
    /// Whether the simplex shrank below the tolerances before the evaluation budget ran out.
    pub converged: bool,
}

/// Minimises `f` from `start` with an initial simplex of edge `step`, until the simplex's
/// values differ by less than `f_tol` and its points by less than `x_tol` (or `budget`
/// evaluations). Non-finite values count as +∞ (a wall).
pub fn nelder_mead(
    mut f: impl FnMut(&[f64]) -> f64,
    start: &[f64],
    step: f64,
    x_tol: f64,
    f_tol: f64,
    budget: usize,
) -> SimplexResult {
    let n = start.len();
    let mut eval = |x: &[f64], count: &mut usize| {
        *count += 1;
        let v = f(x);
        if v.is_finite() {
            v
        } else {
            f64::INFINITY
        }
    };
    let mut count = 0;
    let mut pts: Vec<Vec<f64>> = vec![start.to_vec()];
    for i in 0..n {
        let mut p = start.to_vec();
        p[i] += step;
        pts.push(p);
    }
    let mut vals: Vec<f64> = pts.iter().map(|p| eval(p, &mut count)).collect();
    let combine = |a: &[f64], b: &[f64], t: f64| -> Vec<f64> {
        a.iter().zip(b).map(|(x, y)| x + t * (y - x)).collect()
    };
    let mut converged = false;
    while count < budget {
        let mut order: Vec<usize> = (0..=n).collect();
        order.sort_by(|&i, &j| vals[i].total_cmp(&vals[j]));
        pts = order.iter().map(|&i| pts[i].clone()).collect();
        vals = order.iter().map(|&i| vals[i]).collect();
        let spread = pts[1..]
            .iter()
            .flat_map(|p| p.iter().zip(&pts[0]).map(|(a, b)| (a - b).abs()))
            .fold(0.0, f64::max);
        if (vals[n] - vals[0]).abs() <= f_tol && spread <= x_tol {
            converged = true;
            break;
        }
        let centroid: Vec<f64> = (0..n)
            .map(|k| pts[..n].iter().map(|p| p[k]).sum::<f64>() / n as f64)
            .collect();
        let reflected = combine(&centroid, &pts[n], -1.0);
        let fr = eval(&reflected, &mut count);
        if fr < vals[0] {
            let expanded = combine(&centroid, &pts[n], -2.0);
            let fe = eval(&expanded, &mut count);
            (pts[n], vals[n]) = if fe < fr {
                (expanded, fe)
            } else {
                (reflected, fr)
            };
        } else if fr < vals[n - 1] {
            (pts[n], vals[n]) = (reflected, fr);
        } else {
            let (towards, ft) = if fr < vals[n] {
                (reflected.clone(), fr)
            } else {
                (pts[n].clone(), vals[n])
            };
            let contracted = combine(&centroid, &towards, 0.5);
            let fc = eval(&contracted, &mut count);
            if fc < ft {
                (pts[n], vals[n]) = (contracted, fc);
            } else {
                for i in 1..=n {
                    pts[i] = combine(&pts[0], &pts[i], 0.5);
                    vals[i] = eval(&pts[i], &mut count);
                }
            }
        }
    }
    let best = (0..=n)
        .min_by(|&i, &j| vals[i].total_cmp(&vals[j]))
        .unwrap_or(0);
    SimplexResult {
        x: pts[best].clone(),
        value: vals[best],
        evaluations: count,
        converged,
    }
}

/// Golden-section search for a minimum of a unimodal `f` on `[lo, hi]`, to width `tol`.
/// Returns `(x, f(x))`.
pub fn golden_section(mut f: impl FnMut(f64) -> f64, lo: f64, hi: f64, tol: f64) -> (f64, f64) {
    let r = (5f64.sqrt() - 1.0) / 2.0;
    let (mut a, mut b) = (lo, hi);
    let mut x1 = b - r * (b - a);
    let mut x2 = a + r * (b - a);
    let (mut f1, mut f2) = (f(x1), f(x2));
    for _ in 0..200 {
        if (b - a).abs() <= tol {
            break;
        }
        if f1 <= f2 {
            b = x2;
            (x2, f2) = (x1, f1);
            x1 = b - r * (b - a);
            f1 = f(x1);
        } else {
            a = x1;
            (x1, f1) = (x2, f2);
            x2 = a + r * (b - a);
            f2 = f(x2);
        }
    }
    if f1 <= f2 {
        (x1, f1)
    } else {
        (x2, f2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rosenbrock_minimum() {
        let r = nelder_mead(
            |x| (1.0 - x[0]).powi(2) + 100.0 * (x[1] - x[0] * x[0]).powi(2),
            &[-1.2, 1.0],
            0.5,
            1e-10,
            1e-20,
            20_000,
        );
        assert!(r.converged);
        assert!(
            (r.x[0] - 1.0).abs() < 1e-7 && (r.x[1] - 1.0).abs() < 1e-7,
            "{:?}",
            r.x
        );
    }

    #[test]
    fn golden_section_finds_a_parabola_minimum() {
        // no constant offset: near a minimum of f + 2 the values agree to √ε in x, not better
        let (x, v) = golden_section(|x| (x - 0.3).powi(2), 0.0, 1.0, 1e-10);
        assert!((x - 0.3).abs() < 1e-9 && v < 1e-18, "{x} {v}");
    }
}
