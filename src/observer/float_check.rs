//! The float path, checked against the exact one.
//!
//! The same Ackermann algorithm runs in `f64` (nalgebra LU for `O_n q = e_n`, Horner for
//! `P(A) q`), and the result is compared with the exact gain. For a root of multiplicity `m`,
//! a perturbation `δ` of the observer matrix moves the computed eigenvalues by about `δ^(1/m)`:
//! rounding alone (`δ ≈ ε‖A − KC‖`) scatters a triple root at −4 by ~10⁻⁵, and a float gain that
//! is off by `ΔK` adds `‖ΔK‖‖C‖` to `δ`. The check says which of these explains what the
//! eigenvalue solver shows, so "the scatter is normal, your gain is right" is told apart from
//! "the gain itself is wrong".

use crate::algebra::{rational_to_f64, Quadratic, Rational, ToF64};
use crate::linalg::{self, float, Matrix};
use crate::observability::observability_matrix;
use crate::poly::{exact_roots, Poly};
use nalgebra::{Complex, DMatrix, DVector};
use num_traits::FromPrimitive;
use serde::Serialize;

/// Machine epsilon for `f64`.
const EPS: f64 = f64::EPSILON;

/// What the float check concluded.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FloatVerdict {
    /// The float gain is within tolerance and places the poles within tolerance.
    Reliable,
    /// The float gain is right; the poles scatter as a repeated root must.
    RepeatedRootScatter,
    /// The float gain itself is wrong beyond tolerance: use the exact gain.
    GainUnreliable,
    /// The gain is right — the exact characteristic polynomial of `A − K_float C` matches the
    /// desired one — but the eigenvalue solver cannot resolve the (distinct) poles: the observer
    /// matrix is too ill-conditioned for an eigenvalue check.
    PolesIllConditioned,
    /// The gain is within tolerance but the poles are farther off than rounding explains and
    /// no exact polynomial check clears it.
    PolesUnexplained,
}

impl FloatVerdict {
    /// A sentence for the report.
    pub fn explain(self) -> &'static str {
        match self {
            FloatVerdict::Reliable => "the float gain agrees with the exact gain and places the poles",
            FloatVerdict::RepeatedRootScatter => {
                "the float gain is right (its exact characteristic polynomial matches); the computed poles scatter as a repeated root must (like ε^(1/m)), which is the eigenvalue solver's limit, not an error in the gain"
            }
            FloatVerdict::PolesIllConditioned => {
                "the float gain is right (its exact characteristic polynomial matches), but the observer matrix is too ill-conditioned for its computed eigenvalues to be trusted"
            }
            FloatVerdict::GainUnreliable => {
                "the float gain is NOT reliable (error beyond tolerance): use the exact gain"
            }
            FloatVerdict::PolesUnexplained => {
                "the float poles are farther off than rounding explains: treat the float result as wrong"
            }
        }
    }
}

/// The float path's numbers beside the exact design.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FloatCheck {
    /// 2-norm condition number of `O_n` in `f64`.
    pub condition_number: f64,
    /// The float gain (A − KC), or `None` when the float solve failed.
    pub float_gain: Option<Vec<f64>>,
    /// `‖K_float − K‖ / ‖K‖` (0 when there is no exact gain to compare with).
    pub gain_relative_error: f64,
    /// Whether an exact gain was available for the comparison.
    pub compared_with_exact: bool,
    /// A-priori bound `n · cond(O_n) · ε` on that relative error.
    pub gain_error_bound: f64,
    /// Eigenvalues of `A − K_float C` as `(re, im)`.
    pub eigenvalues: Vec<(f64, f64)>,
    /// Largest distance from a computed eigenvalue to the nearest requested pole.
    pub max_pole_distance: f64,
    /// Largest multiplicity among the requested poles.
    pub multiplicity: u32,
    /// `(ε ‖A − KC‖)^(1/m)`: the scatter rounding alone produces.
    pub predicted_scatter: f64,
    /// `(ε ‖A − KC‖ + ‖ΔK‖ ‖C‖)^(1/m)`: the scatter this float gain produces.
    pub predicted_scatter_with_gain_error: f64,
    /// Largest relative coefficient error of `det(sI − (A − K_float C))`, computed exactly from
    /// the float gain's exact binary value.
    pub polynomial_relative_error: Option<f64>,
    /// The tolerance used for the gain and the poles.
    pub tolerance: f64,
    /// The conclusion.
    pub verdict: FloatVerdict,
}

/// Runs the float Ackermann design and compares it with `exact_gain` (A − KC convention).
///
/// `tolerance` is the relative error accepted for the gain (and, scaled by the pole magnitude,
/// for the poles).
pub fn float_check(
    a: &Matrix<Rational>,
    c: &Matrix<Rational>,
    desired: &Poly<f64>,
    desired_exact: Option<&Poly<Rational>>,
    exact_gain: Option<&Matrix<Quadratic>>,
    tolerance: f64,
) -> FloatCheck {
    let n = a.rows();
    let af = float::to_nalgebra(a);
    let cf = float::to_nalgebra(c);
    let of = observability_matrix(&a.map(rational_to_f64), &c.map(rational_to_f64))
        .map(|o| float::to_nalgebra(&o))
        .unwrap_or_else(|_| DMatrix::zeros(n, n));
    let condition_number = float::condition_number(&of);
    let gain_error_bound = n as f64 * condition_number * EPS;

    let mut en = DVector::zeros(n);
    en[n - 1] = 1.0;
    let k_float: Option<DVector<f64>> = of.clone().lu().solve(&en).map(|q| {
        let mut acc = DVector::zeros(n);
        for coef in desired.coeffs().iter().rev() {
            acc = &af * acc + &q * *coef;
        }
        acc
    });
    // Without an exact gain (a desired polynomial known only in f64) the float gain is the
    // reference, and only the poles are checked.
    let k_exact: DVector<f64> = match (exact_gain, &k_float) {
        (Some(g), _) => DVector::from_iterator(n, (0..n).map(|i| g.get(i, 0).to_f64())),
        (None, Some(k)) => k.clone(),
        (None, None) => DVector::zeros(n),
    };
    let k_norm = k_exact.norm().max(f64::MIN_POSITIVE);
    let gain_relative_error = k_float
        .as_ref()
        .map_or(f64::INFINITY, |k| (k - &k_exact).norm() / k_norm);

    // Requested poles with multiplicities.
    let requested: Vec<(Complex<f64>, u32)> = match desired_exact.map(exact_roots) {
        Some(r) if r.complete() => r
            .roots
            .iter()
            .map(|(x, m)| {
                let (re, im) = x.to_complex_f64();
                (Complex::new(re, im), *m)
            })
            .collect(),
        _ => companion_roots(desired)
            .into_iter()
            .map(|z| (z, 1))
            .collect(),
    };
    let multiplicity = requested.iter().map(|(_, m)| *m).max().unwrap_or(1);
    let observer_exact = &af - &k_exact * &cf;
    let norm = observer_exact.norm();
    let predicted_scatter = (EPS * norm).powf(1.0 / multiplicity as f64);
    let dk = gain_relative_error * k_norm * cf.norm();
    let predicted_scatter_with_gain_error = (EPS * norm + dk).powf(1.0 / multiplicity as f64);

    let (eigenvalues, max_pole_distance, polynomial_relative_error) = match &k_float {
        Some(k) => {
            let ev = float::eigenvalues(&(&af - k * &cf));
            let dist = ev
                .iter()
                .map(|z| {
                    requested
                        .iter()
                        .map(|(p, _)| (z - p).norm())
                        .fold(f64::INFINITY, f64::min)
                })
                .fold(0.0, f64::max);
            let poly_err = desired_exact.and_then(|p| exact_polynomial_error(a, c, k, p));
            (ev.iter().map(|z| (z.re, z.im)).collect(), dist, poly_err)
        }
        None => (Vec::new(), f64::INFINITY, None),
    };
    let scale = requested.iter().map(|(p, _)| p.norm()).fold(1.0, f64::max);
    // The exact polynomial check, when available, is the decisive evidence about the gain;
    // the eigenvalue comparison only says what a float eigen-solver can resolve.
    let polynomial_ok = polynomial_relative_error.is_some_and(|e| e <= tolerance);
    let verdict = if gain_relative_error.is_nan() || gain_relative_error > tolerance {
        FloatVerdict::GainUnreliable
    } else if max_pole_distance <= tolerance * scale {
        FloatVerdict::Reliable
    } else if multiplicity > 1
        && (polynomial_ok || max_pole_distance <= 10.0 * predicted_scatter_with_gain_error)
    {
        FloatVerdict::RepeatedRootScatter
    } else if polynomial_ok {
        FloatVerdict::PolesIllConditioned
    } else {
        FloatVerdict::PolesUnexplained
    };
    FloatCheck {
        condition_number,
        float_gain: k_float.map(|k| k.iter().copied().collect()),
        gain_relative_error,
        compared_with_exact: exact_gain.is_some(),
        gain_error_bound,
        eigenvalues,
        max_pole_distance,
        multiplicity,
        predicted_scatter,
        predicted_scatter_with_gain_error,
        polynomial_relative_error,
        tolerance,
        verdict,
    }
}

/// Roots of a float polynomial as companion-matrix eigenvalues (conjugate pairs exact).
pub fn companion_roots(p: &Poly<f64>) -> Vec<Complex<f64>> {
    let n = p.degree().unwrap_or(0);
    if n == 0 {
        return Vec::new();
    }
    let lead = p.leading();
    let comp = DMatrix::from_fn(n, n, |i, j| {
        if i == 0 {
            -p.coeff(n - 1 - j) / lead
        } else if j + 1 == i {
            1.0
        } else {
            0.0
        }
    });
    float::eigenvalues(&comp)
}

/// The float gain read exactly (every `f64` is a rational), `det(sI − (A − K C))` computed
/// exactly, and its largest coefficient error relative to the desired coefficient.
fn exact_polynomial_error(
    a: &Matrix<Rational>,
    c: &Matrix<Rational>,
    k: &DVector<f64>,
    desired: &Poly<Rational>,
) -> Option<f64> {
    let kq = Matrix::from_fn(k.len(), 1, |i, _| {
        Rational::from_f64(k[i]).unwrap_or_default()
    });
    let p = if c.rows() == 1 {
        let o = observability_matrix(a, c).ok()?;
        let open_loop = linalg::characteristic_polynomial(a, "s").ok()?;
        crate::linalg::rank_one_update(&o, &open_loop, &kq).ok()?
    } else {
        let obs = a.sub(&kq.mul(c).ok()?).ok()?;
        linalg::characteristic_polynomial(&obs, "s").ok()?
    };
    let n = desired.degree()?;
    Some(
        (0..n)
            .map(|i| {
                let d = rational_to_f64(&desired.coeff(i));
                let e = rational_to_f64(&(p.coeff(i) - desired.coeff(i)));
                (e / d.abs().max(1.0)).abs()
            })
            .fold(0.0, f64::max),
    )
}
