//! The computations of the course's topics beyond the five documents — discrete-time
//! observers, sampling with a zero-order hold, reduced-order observers and observers for
//! detectable pairs — as claims, so that their worked examples are verified like the documents'.

use super::inputs::{failed, input_error, lift, ComputeError, Computed, Inputs};
use super::{Computation, Value};
use crate::algebra::{Quadratic, Rational};
use crate::observer::detectability::detectable_design;
use crate::observer::discrete::{discrete_observer, zero_order_hold, Estimator, Sampled};
use crate::observer::reduced_order::reduced_order_observer;
use crate::observer::{Convention, Detail};

fn estimator(inputs: &Inputs) -> Result<Estimator, ComputeError> {
    match &inputs.claim.estimator {
        None => Ok(Estimator::Prediction),
        Some(e) => Estimator::parse(e).ok_or_else(|| {
            input_error(
                "estimator",
                format!("'{e}' is neither prediction nor current"),
            )
        }),
    }
}

/// What of a discrete-time observer a claim asks for.
#[derive(Clone, Copy)]
pub enum DiscretePart {
    /// `discrete_gain`.
    Gain,
    /// `current_gain`.
    CurrentGain,
    /// `discrete_error_polynomial`.
    ErrorPolynomial,
    /// `deadbeat_steps`.
    DeadbeatSteps,
}

/// Which matrix of the sampled plant.
#[derive(Clone, Copy)]
pub enum ZohPart {
    /// `zoh_phi`.
    Phi,
    /// `zoh_gamma`.
    Gamma,
}

/// What of a reduced-order observer.
#[derive(Clone, Copy)]
pub enum ReducedPart {
    /// `reduced_order_gain`.
    Gain,
    /// `reduced_order_error_polynomial`.
    ErrorPolynomial,
    /// `reduced_order_noise_gain`.
    NoiseGain,
}

/// What of a detectability design.
#[derive(Clone, Copy)]
pub enum DetectablePart {
    /// `detectable`.
    Verdict,
    /// `detectable_gain`.
    Gain,
    /// `detectable_observer_polynomial`.
    ObserverPolynomial,
}

/// What of the discrete Kalman filter.
#[derive(Clone, Copy)]
pub enum KalmanPart {
    /// `discrete_kalman_gain`.
    Gain,
    /// `discrete_kalman_covariance`.
    Covariance,
}

/// `discrete_gain`, `current_gain`, `deadbeat_steps`, `discrete_error_polynomial`.
pub fn discrete(
    inputs: &Inputs,
    title: &str,
    part: DiscretePart,
) -> Result<Computed, ComputeError> {
    let (a, c) = (inputs.numeric("A")?, inputs.numeric("C")?);
    let convention = inputs.convention(Convention::AMinusKC)?;
    let d = discrete_observer(
        &a,
        &c,
        &inputs.desired()?,
        inputs.method()?,
        convention,
        estimator(inputs)?,
        Detail::Full,
    )
    .map_err(|e| failed(e.to_string()))?;
    let value = match part {
        DiscretePart::Gain => Value::Matrix(d.design.gain.matrix.clone()),
        DiscretePart::CurrentGain => Value::Matrix(d.current_gain.clone().ok_or_else(|| {
            input_error("estimator", "current_gain needs estimator = \"current\"")
        })?),
        DiscretePart::DeadbeatSteps => Value::Scalar(Quadratic::rational(Rational::from_integer(
            d.nilpotent_index
                .ok_or_else(|| failed("the error matrix is not nilpotent: no dead-beat"))?
                .into(),
        ))),
        DiscretePart::ErrorPolynomial => {
            Value::Polynomial(d.error_polynomial.with_var(&inputs.var()))
        }
    };
    let mut derivation = d.derivation;
    derivation.title = title.to_string();
    Ok(Computed { value, derivation })
}

/// `zoh_phi`, `zoh_gamma`: exact when A is nilpotent.
pub fn zoh(inputs: &Inputs, title: &str, part: ZohPart) -> Result<Computed, ComputeError> {
    let t = inputs
        .claim
        .period
        .as_deref()
        .ok_or_else(|| input_error("period", "give the sampling period"))?;
    let t = inputs.rational("period", t)?;
    match zero_order_hold(&inputs.numeric("A")?, &inputs.numeric("B")?, &t)
        .map_err(|e| failed(e.to_string()))?
    {
        Sampled::Exact { phi, gamma, index } => {
            let m = match part {
                ZohPart::Phi => phi,
                ZohPart::Gamma => gamma,
            };
            let mut d = crate::derivation::Derivation::new(title);
            d.push(
                &format!("A^{index}"),
                "zero: e^(AT) is the finite sum Σ_(k<index) (AT)^k/k!",
                &crate::linalg::Matrix::<Rational>::zeros(1, 1),
            );
            d.push("result", "", &m);
            Ok(Computed {
                value: Value::Matrix(lift(&m)),
                derivation: d,
            })
        }
        Sampled::Float { .. } => Err(failed(
            "A is not nilpotent: e^(AT) is known in f64 only (owb zoh prints it with its error estimate)",
        )),
    }
}

/// `reduced_order_gain`, `reduced_order_error_polynomial`, `reduced_order_noise_gain`.
pub fn reduced(inputs: &Inputs, title: &str, part: ReducedPart) -> Result<Computed, ComputeError> {
    let b = if inputs.has("B") {
        Some(inputs.numeric("B")?)
    } else {
        None
    };
    let (a, c) = (inputs.numeric("A")?, inputs.numeric("C")?);
    let r = reduced_order_observer(
        &a,
        b.as_ref(),
        &c,
        &inputs.desired_of_order(a.rows() - c.rows().min(a.rows()))?,
        inputs.method()?,
    )
    .map_err(|e| failed(e.to_string()))?;
    let convention = inputs.convention(Convention::AMinusKC)?;
    let value = match part {
        ReducedPart::Gain => Value::Matrix(r.gain(convention)),
        ReducedPart::NoiseGain => Value::Scalar(r.noise_gain.clone()),
        ReducedPart::ErrorPolynomial => {
            Value::Polynomial(r.error_polynomial.with_var(&inputs.var()))
        }
    };
    let mut derivation = r.derivation;
    derivation.title = title.to_string();
    Ok(Computed { value, derivation })
}

/// `detectable`, `fixed_poles`, `detectable_gain`.
pub fn detectable(
    inputs: &Inputs,
    title: &str,
    part: DetectablePart,
) -> Result<Computed, ComputeError> {
    let (a, c) = (inputs.numeric("A")?, inputs.numeric("C")?);
    let report = crate::observability::observability_report(&a, &c)?;
    if inputs.claim.what == Computation::Detectable {
        // every unobservable mode stable: Routh–Hurwitz on their polynomial, exact
        let detectable = crate::poly::is_hurwitz(&report.unobservable_polynomial);
        let mut d = crate::derivation::Derivation::new(title);
        d.push(
            "det(sI − A|ker O_n)",
            "the unobservable modes' polynomial",
            &report.unobservable_polynomial,
        );
        return Ok(Computed {
            value: Value::Bool(detectable),
            derivation: d,
        });
    }
    let rank = report.rank;
    let d = detectable_design(
        &a,
        &c,
        &inputs.desired_of_order(rank)?,
        inputs.method()?,
        inputs.convention(Convention::AMinusKC)?,
    )
    .map_err(|e| failed(e.to_string()))?;
    let value = match part {
        DetectablePart::Verdict => Value::Bool(d.detectable),
        DetectablePart::Gain => Value::Matrix(d.gain.clone()),
        DetectablePart::ObserverPolynomial => {
            Value::Polynomial(d.observer_polynomial.with_var(&inputs.var()))
        }
    };
    let mut derivation = d.derivation;
    derivation.title = title.to_string();
    Ok(Computed { value, derivation })
}

/// `discrete_kalman_gain`, `discrete_kalman_covariance`: exact when the Riccati solution read
/// back as fractions satisfies the equation exactly, otherwise the f64 solution.
pub fn discrete_kalman(
    inputs: &Inputs,
    title: &str,
    part: KalmanPart,
) -> Result<Computed, ComputeError> {
    let k = crate::observer::discrete_kalman::discrete_kalman(
        &inputs.numeric("A")?,
        &inputs.numeric("G")?,
        &inputs.numeric("C")?,
        &inputs.numeric("Qn")?,
        &inputs.numeric("Rn")?,
    )
    .map_err(|e| failed(e.to_string()))?;
    let gain = match part {
        KalmanPart::Gain => true,
        KalmanPart::Covariance => false,
    };
    let mut d = crate::derivation::Derivation::new(title);
    let value = match (&k.exact_p, &k.exact_gain) {
        (Some(p), Some(l)) => {
            d.push(
                "P",
                "the Riccati solution read back as fractions, satisfying it exactly",
                p,
            );
            d.push("L", "A P Cᵀ (C P Cᵀ + R_n)⁻¹", l);
            Value::Matrix(lift(if gain { l } else { p }))
        }
        _ => {
            let m = if gain { &k.gain } else { &k.p };
            Value::Approximate {
                rows: m.nrows(),
                cols: m.ncols(),
                candidates: vec![(0..m.nrows())
                    .flat_map(|i| (0..m.ncols()).map(move |j| m[(i, j)]))
                    .collect()],
                note: format!(
                    "f64 by structured doubling ({} doublings, Riccati residual {:.1e}); no small-fraction solution satisfies the equation exactly",
                    k.iterations, k.residual
                ),
            }
        }
    };
    Ok(Computed {
        value,
        derivation: d,
    })
}
