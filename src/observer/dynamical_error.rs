//! Baranowski's minimal dynamical error design (§5, eq. (19)–(26)): among the gains placing the
//! observer polynomial, minimise `J2(G) = λ_max(H)` where `Fᵀ H + H F = −D`, `F = A − GC`.
//!
//! `x(0)ᵀ H x(0) = ∫₀^∞ eᵀ D e dt` is the integral of the weighted squared estimation error from
//! an initial error `x(0)`, and `λ_max(H)` its worst case over unit initial errors.
//!
//! The constraint set is parametrised exactly (see [`super::partial`]): the columns other than
//! one are free, that column is the unique one placing the polynomial. `J2` is a largest
//! eigenvalue — not smooth where it is multiple — so the search is Nelder–Mead from many seeded
//! starts; the report says how many reached the best value, how far apart the minimisers they
//! found lie, and how many flat directions the cost has there (a numerical Hessian), which
//! decides whether the minimiser is unique.

use super::partial::place_free_column;
use super::search::{nelder_mead, Multistart};
use crate::algebra::{Rational, Ring, ToF64};
use crate::linalg::float::{eigenvalues, to_nalgebra};
use crate::linalg::lyapunov::{lyapunov_f64, lyapunov_f64_with_abscissa, LyapunovError};
use crate::linalg::Matrix;
use crate::poly::Poly;
use nalgebra::DMatrix;
use serde::Serialize;

/// Why `J2` could not be evaluated or minimised.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DynamicalErrorError {
    /// Shapes do not fit.
    #[error("A is {a}, C is {c}, G is {g}, D is {d}: need A n×n, C p×n, G n×p, D n×n")]
    Shape {
        /// Shape of A.
        a: String,
        /// Shape of C.
        c: String,
        /// Shape of G.
        g: String,
        /// Shape of D.
        d: String,
    },
    /// `A − GC` is not stable: the integral (22) diverges.
    #[error(
        "A − GC is not stable (eigenvalue with real part {0:.4}): the error integral diverges"
    )]
    Unstable(f64),
    /// The Lyapunov equation failed.
    #[error(transparent)]
    Lyapunov(#[from] LyapunovError),
    /// The free column could not be placed from any start.
    #[error("no start gave a placing, stable gain: {0}")]
    NoFeasibleStart(String),
    /// The desired polynomial has a root with nonnegative real part: every placing gain leaves
    /// `A − GC` unstable, and `J2` is the integral of a growing error.
    #[error("the desired polynomial {0} is not Hurwitz (a root has nonnegative real part): J2 needs a stable observer")]
    UnstableTarget(String),
    /// The placed output cannot place the polynomial, whatever the other columns are.
    #[error("output {output} cannot place the poles alone: (A − Σ_{{i≠{output}}} g_i c_i, c_{output}) stayed unobservable at {tries} random integer choices of the other columns (its observability determinant is a polynomial in them, so it is almost surely zero everywhere){hint}")]
    PlacedOutputCannotPlace {
        /// The output (1-based).
        output: usize,
        /// Random choices tried.
        tries: usize,
        /// The outputs that can, as advice.
        hint: String,
    },
}

fn shape(m: &DMatrix<f64>) -> String {
    format!("{}×{}", m.nrows(), m.ncols())
}

/// `J2(G) = λ_max(H)` with `Fᵀ H + H F = −D`, `F = A − GC`, and `H`.
///
/// # Errors
/// [`DynamicalErrorError`] for mismatched shapes or an unstable `A − GC`.
pub fn dynamical_error_cost(
    a: &DMatrix<f64>,
    c: &DMatrix<f64>,
    g: &DMatrix<f64>,
    weight: &DMatrix<f64>,
) -> Result<(f64, DMatrix<f64>), DynamicalErrorError> {
    let n = a.nrows();
    let ok = a.ncols() == n
        && c.ncols() == n
        && g.nrows() == n
        && g.ncols() == c.nrows()
        && weight.shape() == (n, n);
    if !ok {
        return Err(DynamicalErrorError::Shape {
            a: shape(a),
            c: shape(c),
            g: shape(g),
            d: shape(weight),
        });
    }
    let f = a - g * c;
    // one real Schur factorisation of Fᵀ gives both the stability test and H
    let ft = f.transpose();
    let h = match lyapunov_f64_with_abscissa(&ft, weight)? {
        Some((_, worst)) if worst >= 0.0 => return Err(DynamicalErrorError::Unstable(worst)),
        Some((solution, _)) => solution.x,
        None => {
            // the bounded Schur iteration stalled: the eigenvalue path decides (with balancing)
            let worst = eigenvalues(&f)
                .iter()
                .map(|z| z.re)
                .fold(f64::NEG_INFINITY, f64::max);
            if worst >= 0.0 {
                return Err(DynamicalErrorError::Unstable(worst));
            }
            lyapunov_f64(&ft, weight)?.x
        }
    };
    // NaN when it cannot be computed, which every comparison downstream counts as failure
    let top = crate::linalg::float::symmetric_eigen(&h).map_or(f64::NAN, |e| e.eigenvalues.max());
    Ok((top, h))
}

/// One run of the search, ended at a local minimum.
#[derive(Clone, Debug, Serialize)]
pub struct DynamicalErrorMinimum {
    /// The gain, row by row (`n × p`).
    pub gain: Vec<f64>,
    /// `J2` there.
    pub cost: f64,
}

/// The multistart search for the minimal dynamical error gain.
#[derive(Clone, Debug, Serialize)]
pub struct DynamicalErrorReport {
    /// Rows of the gain.
    pub rows: usize,
    /// Columns of the gain.
    pub cols: usize,
    /// The output whose gain column is computed from the others (0-based).
    pub placed_column: usize,
    /// Seeded starts tried.
    pub starts: usize,
    /// Starts whose simplex converged.
    pub converged: usize,
    /// The best minimum; among runs reaching the best cost, the one of smallest gain norm.
    pub best: DynamicalErrorMinimum,
    /// Runs that reached the best cost within `1e-9` (relative).
    pub reached_best: usize,
    /// The largest distance (max-norm on the gain) between minimisers reaching the best cost.
    pub spread: f64,
    /// Eigenvalues of the numerical Hessian of `J2` in the free parameters at the best point.
    pub hessian_eigenvalues: Vec<f64>,
    /// Directions in which `J2` is flat there (Hessian eigenvalue below `1e-5` of the largest):
    /// more than zero means the minimiser is not unique.
    pub flat_directions: usize,
    /// Those flat directions, in the free gain entries (unit vectors).
    pub flat_vectors: Vec<Vec<f64>>,
    /// Every converged run, best first.
    pub runs: Vec<DynamicalErrorMinimum>,
    /// Whether the best gain, rebuilt in rationals (free entries as printed binary fractions,
    /// placed column exact), has exactly the desired characteristic polynomial.
    pub places_exactly: bool,
}

/// Minimises `J2` over the gains placing `desired` for `(A, C)`, from `starts` seeded starts
/// (free entries uniform in `[−5, 5]`).
///
/// # Errors
/// [`DynamicalErrorError`] for bad shapes or when no start gives a stable placing gain.
pub fn minimal_dynamical_error(
    a: &Matrix<Rational>,
    c: &Matrix<Rational>,
    desired: &Poly<Rational>,
    weight: &Matrix<Rational>,
    placed_column: usize,
    search: Multistart,
) -> Result<DynamicalErrorReport, DynamicalErrorError> {
    let (n, p) = (a.rows(), c.rows());
    let (af, cf, wf) = (to_nalgebra(a), to_nalgebra(c), to_nalgebra(weight));
    if placed_column >= p || wf.shape() != (n, n) || a.cols() != n || c.cols() != n {
        return Err(DynamicalErrorError::Shape {
            a: shape(&af),
            c: shape(&cf),
            g: format!("{n}×{p} (placed column {})", placed_column + 1),
            d: shape(&wf),
        });
    }
    if !crate::poly::is_hurwitz(desired) {
        return Err(DynamicalErrorError::UnstableTarget(desired.to_string()));
    }
    require_placing_output(a, c, desired, placed_column)?;
    let am = a.map(|x| x.to_f64());
    let cm = c.map(|x| x.to_f64());
    let dp = desired.map(ToF64::to_f64);
    let free: Vec<(usize, usize)> = (0..p)
        .filter(|&j| j != placed_column)
        .flat_map(|j| (0..n).map(move |i| (i, j)))
        .collect();
    let gain_of = |x: &[f64]| -> Option<DMatrix<f64>> {
        let mut fixed = Matrix::<f64>::zeros(n, p);
        for (v, &(i, j)) in x.iter().zip(&free) {
            fixed.set(i, j, *v);
        }
        let g = place_free_column(&am, &cm, &fixed, placed_column, &dp).ok()?;
        Some(to_nalgebra(&g))
    };
    let cost = |x: &[f64]| -> f64 {
        gain_of(x)
            .and_then(|g| dynamical_error_cost(&af, &cf, &g, &wf).ok())
            .map_or(f64::INFINITY, |(j, _)| j)
    };
    let mut uniform = super::search::seeded_uniform(search.seed);
    let mut runs: Vec<(Vec<f64>, DynamicalErrorMinimum)> = Vec::new();
    let mut converged = 0;
    let mut starts = 0;
    for _ in 0..search.starts {
        if search.out_of_time() {
            break;
        }
        starts += 1;
        let start: Vec<f64> = free.iter().map(|_| 10.0 * uniform() - 5.0).collect();
        if !cost(&start).is_finite() {
            search.started();
            continue;
        }
        let r = nelder_mead(cost, &start, 0.5, 1e-9, 1e-15, 20_000);
        search.started();
        if !r.value.is_finite() {
            continue;
        }
        converged += usize::from(r.converged);
        let Some(g) = gain_of(&r.x) else { continue };
        runs.push((
            r.x.clone(),
            DynamicalErrorMinimum {
                gain: g.transpose().iter().copied().collect(),
                cost: r.value,
            },
        ));
    }
    runs.sort_by(|x, y| x.1.cost.total_cmp(&y.1.cost));
    let Some(top) = runs.first().map(|r| r.1.cost) else {
        return Err(DynamicalErrorError::NoFeasibleStart(format!(
            "{starts} starts"
        )));
    };
    let at_best = |r: &DynamicalErrorMinimum| (r.cost - top).abs() <= 1e-9 * top.abs().max(1e-300);
    let norm = |g: &[f64]| g.iter().map(|x| x * x).sum::<f64>();
    let (best_x, best) = runs
        .iter()
        .filter(|r| at_best(&r.1))
        .min_by(|x, y| norm(&x.1.gain).total_cmp(&norm(&y.1.gain)))
        .cloned()
        .ok_or_else(|| DynamicalErrorError::NoFeasibleStart("no best run".into()))?;
    let near: Vec<&DynamicalErrorMinimum> =
        runs.iter().map(|r| &r.1).filter(|r| at_best(r)).collect();
    let spread = near
        .iter()
        .flat_map(|x| near.iter().map(move |y| (x, y)))
        .map(|(x, y)| {
            x.gain
                .iter()
                .zip(&y.gain)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max)
        })
        .fold(0.0, f64::max);
    let (hessian_eigenvalues, flat_directions, flat_vectors) = flatness(&cost, &best_x);
    let places_exactly = places_exactly(a, c, desired, placed_column, &free, &best_x);
    Ok(DynamicalErrorReport {
        rows: n,
        cols: p,
        placed_column,
        starts,
        converged,
        reached_best: near.len(),
        spread,
        hessian_eigenvalues,
        flat_directions,
        flat_vectors,
        best,
        runs: runs.into_iter().map(|r| r.1).collect(),
        places_exactly,
    })
}

/// Random integer choices of the other columns tried before an output is declared unable to
/// place the polynomial.
const PLACING_TRIES: usize = 3;

/// Whether output `j` can place `desired` for some choice of the other gain columns, tried
/// exactly at a few seeded random integer choices (the reduced pair's observability is a
/// polynomial condition on them: true at one point, true almost everywhere).
fn output_can_place(
    a: &Matrix<Rational>,
    c: &Matrix<Rational>,
    desired: &Poly<Rational>,
    j: usize,
) -> bool {
    let (n, p) = (a.rows(), c.rows());
    let mut uniform = super::search::seeded_uniform(7 + j as u64);
    (0..PLACING_TRIES).any(|_| {
        let fixed = Matrix::from_fn(n, p, |_, _| {
            Rational::from_i64((uniform() * 19.0).floor() as i64 - 9)
        });
        place_free_column(a, c, &fixed, j, desired).is_ok()
    })
}

fn require_placing_output(
    a: &Matrix<Rational>,
    c: &Matrix<Rational>,
    desired: &Poly<Rational>,
    placed_column: usize,
) -> Result<(), DynamicalErrorError> {
    if output_can_place(a, c, desired, placed_column) {
        return Ok(());
    }
    let able: Vec<String> = (0..c.rows())
        .filter(|&j| j != placed_column && output_can_place(a, c, desired, j))
        .map(|j| (j + 1).to_string())
        .collect();
    Err(DynamicalErrorError::PlacedOutputCannotPlace {
        output: placed_column + 1,
        tries: PLACING_TRIES,
        hint: if able.is_empty() {
            String::new()
        } else {
            format!("; output(s) {} can (--placed-output)", able.join(", "))
        },
    })
}

/// The Hessian's eigenvalues at the minimiser `x`, how many directions are flat there
/// (eigenvalue below `1e-5` of the largest), and those directions (largest entry positive).
fn flatness(cost: &impl Fn(&[f64]) -> f64, x: &[f64]) -> (Vec<f64>, usize, Vec<Vec<f64>>) {
    let hessian = numerical_hessian(cost, x);
    let Some(eigen) = crate::linalg::float::symmetric_eigen(&hessian) else {
        // an infinite or NaN second difference (a neighbour outside the stable set): the
        // curvature is unknown, and no direction is called flat
        return (vec![f64::NAN; hessian.nrows()], 0, Vec::new());
    };
    let hessian_eigenvalues: Vec<f64> = eigen.eigenvalues.iter().copied().collect();
    // relative to the largest curvature, or to the cost itself where the Hessian vanishes
    // (a cost constant on the whole constraint set: every direction is flat)
    let largest = hessian_eigenvalues.iter().copied().fold(0.0, f64::max);
    let scale = largest.max(cost(x).abs());
    let flat: Vec<usize> = (0..hessian_eigenvalues.len())
        .filter(|&k| hessian_eigenvalues[k].abs() <= 1e-5 * scale)
        .collect();
    let flat_directions = flat.len();
    let flat_vectors = flat
        .iter()
        .map(|&k| {
            let v: Vec<f64> = eigen.eigenvectors.column(k).iter().copied().collect();
            // sign convention: largest entry positive
            let big = v
                .iter()
                .copied()
                .fold(0.0, |m: f64, x| if x.abs() > m.abs() { x } else { m });
            v.iter().map(|x| if big < 0.0 { -x } else { *x }).collect()
        })
        .collect();
    (hessian_eigenvalues, flat_directions, flat_vectors)
}

/// Whether the minimiser, its free entries read as the exact binary fractions they are and the
/// placed column computed exactly, has exactly the desired characteristic polynomial.
fn places_exactly(
    a: &Matrix<Rational>,
    c: &Matrix<Rational>,
    desired: &Poly<Rational>,
    placed_column: usize,
    free: &[(usize, usize)],
    x: &[f64],
) -> bool {
    let (n, p) = (a.rows(), c.rows());
    let mut fixed = Matrix::<Rational>::zeros(n, p);
    for (v, &(i, j)) in x.iter().zip(free) {
        if let Some(r) = num_rational::BigRational::from_float(*v) {
            fixed.set(i, j, r);
        }
    }
    place_free_column(a, c, &fixed, placed_column, desired)
        .ok()
        .and_then(|g| a.sub(&g.mul(c).ok()?).ok())
        .and_then(|f| crate::linalg::characteristic_polynomial(&f, "s").ok())
        .is_some_and(|cp| cp.coeffs() == desired.coeffs())
}

/// Central-difference Hessian with step `1e-4`.
fn numerical_hessian(f: &impl Fn(&[f64]) -> f64, x: &[f64]) -> DMatrix<f64> {
    let m = x.len();
    let h = 1e-4;
    let at = |di: usize, si: f64, dj: usize, sj: f64| {
        let mut y = x.to_vec();
        y[di] += si * h;
        y[dj] += sj * h;
        f(&y)
    };
    let mut out = DMatrix::zeros(m, m);
    for i in 0..m {
        for j in 0..m {
            out[(i, j)] = (at(i, 1.0, j, 1.0) - at(i, 1.0, j, -1.0) - at(i, -1.0, j, 1.0)
                + at(i, -1.0, j, -1.0))
                / (4.0 * h * h);
        }
    }
    (&out + out.transpose()) * 0.5
}
