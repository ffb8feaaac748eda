//! Claims about optimal, noisy and perfect observers (Baranowski §5, Furlan, Sławiński):
//! `dynamical_error_cost`, `minimal_dynamical_error_cost`, `kalman_bandwidth`,
//! `natural_frequency`, `estimation_error_rms`, `perfect_observer_robustness`,
//! `perfect_observer_fits`.

use super::computation::Computation;
use super::inputs::{failed, input_error, ComputeError, Computed, Inputs};
use super::value::Value;
use crate::algebra::{Rational, ToF64};
use crate::derivation::{Derivation, Words};
use crate::linalg::float::{eigenvalues, to_nalgebra};
use crate::linalg::{self, Matrix};
use crate::observer::dynamical_error::{dynamical_error_cost, minimal_dynamical_error};
use crate::observer::kalman::{
    error_covariance, kalman_filter, natural_frequency, NoiseIntensities, Plant,
};
use crate::observer::partial::gain_for_observer_matrix;
use crate::observer::perfect::{perfect_observer, robustness_conditions, robustness_residuals};
use crate::observer::robust::robust_observer_gain;
use crate::observer::search::Multistart;
use crate::observer::weighted::weighted_design;
use nalgebra::DMatrix;

/// Seeded starts of the `J2` search in worked examples.
const DYNAMICAL_ERROR_STARTS: usize = 24;

fn scalar(v: f64, note: String) -> Value {
    Value::Approximate {
        rows: 1,
        cols: 1,
        candidates: vec![vec![v]],
        note,
    }
}

fn float_matrix(m: &DMatrix<f64>) -> Value {
    Value::Approximate {
        rows: m.nrows(),
        cols: m.ncols(),
        candidates: vec![m.transpose().iter().copied().collect()],
        note: "f64".into(),
    }
}

fn poles_text(m: &DMatrix<f64>) -> Words {
    Words(
        eigenvalues(m)
            .iter()
            .map(|z| {
                if z.im.abs() < 1e-12 * z.re.abs().max(1.0) {
                    format!("{:.6}", z.re)
                } else {
                    format!(
                        "{:.6} {} {:.6}i",
                        z.re,
                        if z.im < 0.0 { "−" } else { "+" },
                        z.im.abs()
                    )
                }
            })
            .collect::<Vec<_>>()
            .join(", "),
    )
}

/// `dynamical_error_cost` (J2 of the claim's gain) and `minimal_dynamical_error_cost`.
pub(super) fn dynamical_error(inputs: &Inputs, title: &str) -> Result<Computed, ComputeError> {
    let a = inputs.numeric("A")?;
    let c = inputs.numeric("C")?;
    let weight = inputs.numeric("weight")?;
    let mut d = Derivation::new(title);
    d.push("D", "weight of the error integral", &weight);
    if inputs.claim.what == Computation::DynamicalErrorCost {
        let g = inputs.numeric("gain")?;
        let f = a.sub(&g.mul(&c)?)?;
        let cp = linalg::characteristic_polynomial(&f, "s")?;
        d.push("F", "A − GC", &f);
        d.push("det(sI − F)", "exact", &cp);
        d.push("poles", "eigenvalues of F", &poles_text(&to_nalgebra(&f)));
        let (j, h) = dynamical_error_cost(
            &to_nalgebra(&a),
            &to_nalgebra(&c),
            &to_nalgebra(&g),
            &to_nalgebra(&weight),
        )?;
        d.push("H", "Fᵀ H + H F = −D (Bartels–Stewart)", &float_matrix(&h));
        let value = scalar(j, "λ_max(H) of the given gain".into());
        d.push("J2", "λ_max(H)", &value);
        return Ok(Computed {
            value,
            derivation: d,
        });
    }
    let desired = inputs
        .desired()?
        .rational()
        .ok_or_else(|| failed("the optimal design needs a rational desired polynomial"))?;
    let r = minimal_dynamical_error(
        &a,
        &c,
        &desired,
        &weight,
        0,
        Multistart::new(DYNAMICAL_ERROR_STARTS, OPTIMISER_SEED),
    )?;
    let note = format!(
        "Nelder–Mead over the gains placing the poles exactly (column 1 placed by Ackermann from the others) from {} seeded starts: {} reached the best value; their gains lie up to {:.3} apart; {} flat direction(s) of J2 at the smallest of them{}, so the minimiser is {}",
        r.starts,
        r.reached_best,
        r.spread,
        r.flat_directions,
        r.flat_vectors
            .iter()
            .map(|v| format!(" along ({}) in the free column", v.iter().map(|x| format!("{x:.4}")).collect::<Vec<_>>().join(", ")))
            .collect::<String>(),
        if r.flat_directions > 0 || r.spread > 1e-4 { "not unique" } else { "unique among the starts" }
    );
    let g = DMatrix::from_row_slice(r.rows, r.cols, &r.best.gain);
    d.push("G", "the best gain of smallest norm", &float_matrix(&g));
    d.push(
        "exact",
        "",
        &Words(format!(
            "rebuilt in rationals, that gain places the desired polynomial exactly: {}",
            if r.places_exactly { "yes" } else { "no" }
        )),
    );
    let value = scalar(r.best.cost, note);
    d.push("J2", "minimum of λ_max(H)", &value);
    Ok(Computed {
        value,
        derivation: d,
    })
}

fn plant_and_noise(inputs: &Inputs) -> Result<(Plant, NoiseIntensities), ComputeError> {
    let plant = Plant::from_exact(&inputs.plant()?);
    if !inputs.has("input_noise") {
        return Err(input_error("noise", "this claim needs a [noise] section"));
    }
    let noise = NoiseIntensities::from_exact(
        &inputs.numeric("input_noise")?,
        &inputs.numeric("output_noise")?,
    );
    Ok((plant, noise))
}

/// `kalman_bandwidth`, `natural_frequency`, `estimation_error_rms`, `estimation_error_variance`.
pub(super) fn noise(inputs: &Inputs, title: &str) -> Result<Computed, ComputeError> {
    let mut d = Derivation::new(title);
    if inputs.claim.what == Computation::NaturalFrequency {
        return natural_frequency_claim(inputs, d);
    }
    let (plant, noise) = plant_and_noise(inputs)?;
    let (q, r, s) = plant.intensities(&noise);
    d.push("Q", "B C_U Bᵀ", &float_matrix(&q));
    d.push("R", "D C_U Dᵀ + C_Y", &float_matrix(&r));
    d.push(
        "S",
        "B C_U Dᵀ (input noise seen by both)",
        &float_matrix(&s),
    );
    let method = if inputs.claim.what == Computation::KalmanBandwidth {
        "kalman"
    } else {
        inputs.claim.method.as_deref().unwrap_or("kalman")
    };
    let l = match method {
        "kalman" => {
            let k = kalman_filter(&plant, &noise)?;
            d.push(
                "P",
                "stabilising solution of the filter Riccati equation",
                &float_matrix(&rows_matrix(&k.covariance)),
            );
            d.push(
                "residual",
                "relative Riccati residual",
                &Words(format!("{:.2e}", k.residual)),
            );
            rows_matrix(&k.gain)
        }
        "robust" => {
            let poles = float_poles(inputs)?;
            rows_matrix(&robust_observer_gain(&plant.a, &plant.c, &poles)?.gain)
        }
        "diagonal" => diagonal_gain(inputs, &mut d)?,
        "weighted" => weighted_gain(inputs, &mut d)?,
        other => {
            return Err(input_error(
                "method",
                format!("'{other}': use kalman, robust, diagonal or weighted"),
            ))
        }
    };
    let f = &plant.a - &l * &plant.c;
    d.push("L", "observer gain (A − LC)", &float_matrix(&l));
    d.push("poles", "eigenvalues of A − LC", &poles_text(&f));
    let value = if inputs.claim.what == Computation::KalmanBandwidth {
        let w = natural_frequency(&eigenvalues(&f));
        scalar(
            w,
            "natural frequency (Π|λ_i|)^(1/n) of the Kalman poles".into(),
        )
    } else {
        let variance = inputs.claim.what == Computation::EstimationErrorVariance;
        error_statistic(&plant, &noise, &l, variance, &mut d)?
    };
    d.push("result", "", &value);
    Ok(Computed {
        value,
        derivation: d,
    })
}

/// `ω_n = |p(0)|^(1/n)` of the desired polynomial.
fn natural_frequency_claim(inputs: &Inputs, mut d: Derivation) -> Result<Computed, ComputeError> {
    let p = inputs
        .desired()?
        .rational()
        .ok_or_else(|| failed("natural frequency of a rational polynomial only"))?;
    let n = p.degree().unwrap_or(0).max(1);
    d.push("desired", "observer polynomial", &p);
    let w = p.coeff(0).to_f64().abs().powf(1.0 / n as f64);
    let value = scalar(w, "(Π|λ_i|)^(1/n) = |p(0)|^(1/n)".into());
    d.push("ω_n", "|p(0)|^(1/n)", &value);
    Ok(Computed {
        value,
        derivation: d,
    })
}

/// `L = (A − diag(poles)) C⁻¹`, exact: the observer matrix diagonal, poles in the given order.
fn diagonal_gain(inputs: &Inputs, d: &mut Derivation) -> Result<DMatrix<f64>, ComputeError> {
    let text = inputs
        .claim
        .poles
        .as_deref()
        .ok_or_else(|| input_error("poles", "the diagonal method needs poles, in order"))?;
    let poles = crate::syntax::parse_list::<Rational>(text)
        .map_err(|e| input_error("poles", e.show_in(text)))?;
    let a = inputs.numeric("A")?;
    if poles.len() != a.rows() {
        return Err(input_error(
            "poles",
            format!("{} poles for order {}", poles.len(), a.rows()),
        ));
    }
    let m = Matrix::from_fn(a.rows(), a.rows(), |i, j| {
        if i == j {
            poles[i].clone()
        } else {
            Rational::from_integer(0.into())
        }
    });
    let l = gain_for_observer_matrix(&a, &inputs.numeric("C")?, &m)?;
    d.push("L", "(A − diag(poles)) C⁻¹, exact", &l);
    Ok(to_nalgebra(&l))
}

/// Furlan's weighted-measurement observer: the weight minimising the error variance.
fn weighted_gain(inputs: &Inputs, d: &mut Derivation) -> Result<DMatrix<f64>, ComputeError> {
    let (out, state) = match (
        inputs.claim.derivative_output,
        inputs.claim.derivative_state,
    ) {
        (Some(o), Some(s)) if o >= 1 && s >= 1 => (o - 1, s - 1),
        _ => {
            return Err(input_error(
                "derivative_output",
                "the weighted method needs derivative_output and derivative_state (1-based)",
            ))
        }
    };
    let desired = inputs
        .desired()?
        .rational()
        .ok_or_else(|| failed("the weighted method needs rational poles"))?;
    let noise = (
        &inputs.numeric("input_noise")?,
        &inputs.numeric("output_noise")?,
    );
    let w = weighted_design(&inputs.plant()?, &desired, noise, (out, state), 1001)?;
    d.push(
        "w",
        "weight minimising trace Σ (grid of 1001 points, golden section)",
        &Words(format!("{} ≈ {:.6}", w.weight, w.weight_f64)),
    );
    Ok(rows_matrix(&w.gain))
}

/// `√(trace Σ)` (or `trace Σ` when `variance`) from the error covariance's Lyapunov equation,
/// with its working.
fn error_statistic(
    plant: &Plant,
    noise: &NoiseIntensities,
    l: &DMatrix<f64>,
    variance: bool,
    d: &mut Derivation,
) -> Result<Value, ComputeError> {
    let (sigma, residual) = error_covariance(plant, noise, l)?;
    d.push(
        "Σ",
        "(A − LC)Σ + Σ(A − LC)ᵀ + (B − LD)C_U(B − LD)ᵀ + L C_Y Lᵀ = 0",
        &float_matrix(&sigma),
    );
    d.push(
        "residual",
        "relative Lyapunov residual",
        &Words(format!("{residual:.2e}")),
    );
    d.push(
        "trace Σ",
        "variance of the error, summed over states",
        &scalar(sigma.trace(), String::new()),
    );
    if variance {
        return Ok(scalar(
            sigma.trace(),
            "steady-state error variance trace Σ, noise covariances read as white-noise intensities"
                .into(),
        ));
    }
    Ok(scalar(
        sigma.trace().sqrt(),
        "RMS estimation error √(trace Σ), noise covariances read as white-noise intensities".into(),
    ))
}

fn rows_matrix(rows: &[Vec<f64>]) -> DMatrix<f64> {
    let n = rows.len();
    let m = rows.first().map_or(0, Vec::len);
    DMatrix::from_fn(n, m, |i, j| rows[i][j])
}

fn float_poles(inputs: &Inputs) -> Result<Vec<(f64, f64)>, ComputeError> {
    let p = inputs
        .desired()?
        .rational()
        .ok_or_else(|| failed("rational poles needed"))?;
    let roots = crate::poly::exact_roots(&p);
    let list: Vec<(f64, f64)> = roots
        .roots
        .iter()
        .flat_map(|(r, k)| std::iter::repeat_n(r.to_complex_f64(), *k as usize))
        .collect();
    if list.len() != p.degree().unwrap_or(0) {
        return Err(failed("the desired polynomial has roots outside Q(√d)"));
    }
    Ok(list)
}

/// `perfect_observer_robustness` and `perfect_observer_fits`.
pub(super) fn perfect_robustness(inputs: &Inputs, title: &str) -> Result<Computed, ComputeError> {
    let mut d = Derivation::new(title);
    // The observer is always the one of [system]; a claim's A, B, C describe a changed plant.
    let plain = crate::worked::ClaimSpec {
        a: None,
        b: None,
        c: None,
        ..inputs.claim.clone()
    };
    let system = Inputs {
        file: inputs.file,
        claim: &plain,
        env: inputs.env,
    };
    let observer = perfect_observer(&system.plant()?)?;
    d.extend(observer.derivation.clone());
    let value = if inputs.claim.what == Computation::PerfectObserverRobustness {
        let conds = robustness_conditions(&observer);
        let v = Value::Conditions(conds);
        d.push(
            "conditions",
            "E A' = F + G_y C', E B' = G_u + G_y D' for a plant with symbolic entries",
            &v,
        );
        v
    } else {
        let (ra, rb) = robustness_residuals(&observer, &inputs.plant()?)?;
        d.push("E A' − F − G_y C'", "zero iff the state equations fit", &ra);
        d.push("E B' − G_u − G_y D'", "zero iff the input terms fit", &rb);
        Value::Bool(ra.is_zero() && rb.is_zero())
    };
    Ok(Computed {
        value,
        derivation: d,
    })
}

/// Seeded starts of the minimum-norm search (documented in the report).
const OPTIMISER_STARTS: usize = 60;
const OPTIMISER_SEED: u64 = 2024;

pub(super) fn minimum_norm(inputs: &Inputs, title: &str) -> Result<Computed, ComputeError> {
    use crate::observer::optimal::{minimum_norm_gain, pole_placement_constraints};
    let a = inputs.numeric("A")?;
    let c = inputs.numeric("C")?;
    let desired = inputs
        .desired()?
        .rational()
        .ok_or_else(|| failed("the optimal design needs a rational desired polynomial"))?;
    let cons = pole_placement_constraints(&a, &c, &desired)?;
    let r = minimum_norm_gain(&cons, Multistart::new(OPTIMISER_STARTS, OPTIMISER_SEED));
    let best: Vec<_> = r.minima.iter().take(r.best_count).collect();
    if best.is_empty() {
        return Err(failed("no start converged to a minimum"));
    }
    let (n, p) = (a.rows(), c.rows());
    let note = format!(
        "J1 minimised by Newton on the KKT system with exact constraint derivatives from {} seeded starts: {} converged; {} equally good minimiser(s), reached by {} start(s); {} other local minima",
        r.starts,
        r.converged,
        best.len(),
        best.iter().map(|m| m.starts.to_string()).collect::<Vec<_>>().join(" + "),
        r.minima.len() - best.len()
    );
    let mut d = Derivation::new(title);
    d.push(
        "constraints",
        "coefficients of det(λI − (A − GC)) = desired",
        &Value::Equations(cons.equations.clone()),
    );
    let value = if inputs.claim.what == Computation::MinimumNormGain {
        Value::Approximate {
            rows: n,
            cols: p,
            candidates: best
                .iter()
                .map(|m| (0..n * p).map(|k| m.gain[(k % p) * n + k / p]).collect())
                .collect(),
            note,
        }
    } else {
        Value::Approximate {
            rows: 1,
            cols: 1,
            candidates: vec![vec![best[0].cost]],
            note,
        }
    };
    d.push("minimisers", "", &value);
    Ok(Computed {
        value,
        derivation: d,
    })
}
