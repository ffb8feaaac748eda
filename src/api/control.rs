//! `owb control`: observer-based control of a SISO plant.

use super::args::{matrix, matrix_at, mentions_parameters, polynomial_at, Plant};
use super::parametric::{lift, Parametric};
use super::{Outcome, Report};
use crate::algebra::Field;
use crate::algebra::Fraction;
use crate::control::{observer_based_control, observer_gain, state_feedback, ObserverBasedControl};
use crate::linalg::Matrix;
use crate::observer::Convention;
use crate::symbolic::DesiredRequest;
use crate::system::StateSpace;
use anyhow::{anyhow, bail, Result};
use serde_json::json;

/// Arguments of `owb control`.
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "commands", derive(clap::Args))]
pub struct Args {
    /// The plant's A and C (`a`, `c`).
    #[serde(flatten)]
    #[cfg_attr(feature = "commands", command(flatten))]
    pub system: super::args::SystemPair,
    /// The input matrix B (one column).
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long = "b", required_unless_present = "tf")
    )]
    #[serde(default)]
    pub b: Option<String>,
    /// The observer gain (in the convention of --convention).
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long = "l", group = "observer")
    )]
    #[serde(default)]
    pub l: Option<String>,
    /// Or: the desired polynomial of A + LC, e.g. "s^2 + 12s + 36" (the observer gain
    /// designed exactly, Ackermann's formula).
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long = "observer-poly", group = "observer")
    )]
    #[serde(default)]
    pub observer_poly: Option<String>,
    /// The state feedback row F in u = F x̂.
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long = "f", group = "feedback")
    )]
    #[serde(default)]
    pub f: Option<String>,
    /// Or: the desired polynomial of A + BF, e.g. "s^2 + 9s + 20".
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long = "feedback-poly", group = "feedback")
    )]
    #[serde(default)]
    pub feedback_poly: Option<String>,
    /// Convention of the observer gain: a+lc (default, Stoustrup) or a-kc.
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, default_value_t = super::args::defaults::control_convention())
    )]
    #[serde(default = "super::args::defaults::control_convention")]
    pub convention: String,
    /// Machine-readable output.
    #[cfg_attr(feature = "commands", arg(long))]
    #[serde(default)]
    pub json: bool,
}

/// `owb control`: observer-based control, the separation principle checked.
///
/// # Errors
///
/// What the request gets wrong (named by its flag) or what the computation refuses.
pub fn run(args: Args, rep: &mut Report) -> Result<Outcome> {
    let values = args.system.values()?;
    let others = [args.l.as_ref(), args.b.as_ref(), args.f.as_ref()];
    let polynomials = [args.feedback_poly.as_deref(), args.observer_poly.as_deref()];
    let others_symbolic = values.is_empty()
        && (others.iter().flatten().any(|t| mentions_parameters(t))
            || polynomials
                .iter()
                .flatten()
                .any(|p| DesiredRequest::Poly(p).mentions_parameters(&Default::default())));
    let (a, c) = match args.system.plant()? {
        Plant::Symbolic(a, c) => return symbolic(&args, &a, &c, rep),
        Plant::Numeric(a, c) if others_symbolic => {
            return symbolic(&args, &lift(&a), &lift(&c), rep)
        }
        Plant::Numeric(a, c) => (a, c),
    };
    let b = match (&args.b, values.is_empty()) {
        (Some(b), false) => Some(matrix_at("--b", b, &values)?),
        _ => args.system.input(args.b.as_deref())?,
    }
    .ok_or_else(|| anyhow::anyhow!("give the input matrix --b"))?;
    let given = args
        .l
        .as_ref()
        .map(|l| matrix_at("--l", l, &values))
        .transpose()?;
    super::args::check_plant(&a, Some(&b), &c, None)?;
    let (n, m, p) = (a.rows(), b.cols(), c.rows());
    let l = match (given, &args.observer_poly) {
        // (the command line refuses both; a JSON request is told here)
        (Some(_), Some(_)) => bail!("give --l or --observer-poly, not both"),
        (Some(l), None) => {
            super::args::expect_shape("--l", &l, n, p, "states × outputs")?;
            in_a_plus_lc(l, super::args::observer_convention(&args.convention)?)
        }
        (None, Some(text)) => {
            // L is designed for A + LC whatever --convention says; a wrong spelling is refused
            super::args::observer_convention(&args.convention)?;
            let desired = polynomial_at("--observer-poly", text, &values)?;
            observer_gain(&a, &c, &desired)?
        }
        (None, None) => bail!("give --l or --observer-poly"),
    };
    let f = match (&args.f, &args.feedback_poly) {
        // (the command line refuses both; a JSON request is told here)
        (Some(_), Some(_)) => bail!("give --f or --feedback-poly, not both"),
        (Some(f), None) => {
            let f = matrix_at("--f", f, &values)?;
            super::args::expect_shape("--f", &f, m, n, "inputs × states")?;
            f
        }
        (None, Some(p)) => {
            let p = polynomial_at("--feedback-poly", p, &values)?;
            state_feedback(&a, &b, &p)?
        }
        (None, None) => bail!("give --f or --feedback-poly"),
    };
    let plant = StateSpace::new(a, Some(b), c, None)?;
    let r = observer_based_control(&plant, &f, &l)?;
    if args.json {
        rep.json(control_json(&f, &l, &r)?);
    } else {
        control_text(rep, &f, &l, &r, "");
    }
    Ok(Outcome::Ok)
}

/// A given observer gain in `convention`, written for A + LC (what the analysis and the
/// answer use): the sign flipped, when it flips, by the convention type's one place.
fn in_a_plus_lc<F: Field>(l: Matrix<F>, convention: Convention) -> Matrix<F> {
    crate::observer::ObserverGain {
        matrix: l,
        convention,
    }
    .to_convention(Convention::APlusLC)
    .matrix
}

/// The answer as `--json` gives it (the stable shape), for numbers or formulas.
fn control_json<F: Field>(
    f: &Matrix<F>,
    l: &Matrix<F>,
    r: &ObserverBasedControl<F>,
) -> Result<serde_json::Value> {
    Ok(json!({
        "F": f.to_input(),
        "L": l.to_input(),
        "convention": "a+lc",
        "separation_holds": r.separation_holds,
        "closed_loop_polynomial": r.closed_loop_polynomial.to_input(),
        "plant": r.plant.to_input(),
        "controller": r.controller.to_input(),
        "closed_loop": r.closed_loop.to_input(),
        "steps": serde_json::to_value(&r.derivation.steps)?,
    }))
}

/// The answer as text; `how` qualifies the separation principle's equality.
fn control_text<F: Field>(
    rep: &mut Report,
    f: &Matrix<F>,
    l: &Matrix<F>,
    r: &ObserverBasedControl<F>,
    how: &str,
) {
    outln!(
        rep,
        "F = {} (u = F x̂), L = {} (A + LC)",
        f.to_input(),
        l.to_input()
    );
    rep.derivation(&r.derivation);
    outln!(
        rep,
        "Separation principle: det(sI − A_cl) {} det(sI − (A + BF))·det(sI − (A + LC)){how}",
        if r.separation_holds { "=" } else { "≠" }
    );
}

/// Observer-based control with parameters: the controller K(s) and the closed loop as rational
/// functions of s whose coefficients are rational functions of the parameters.
fn symbolic(
    args: &Args,
    a: &Matrix<Fraction>,
    c: &Matrix<Fraction>,
    rep: &mut Report,
) -> Result<Outcome> {
    let Some(b) = &args.b else {
        bail!("give the input matrix --b");
    };
    let b = matrix::<Fraction>("--b", b)?;
    let given = args
        .l
        .as_ref()
        .map(|l| matrix::<Fraction>("--l", l))
        .transpose()?;
    let (n, p) = (a.rows(), c.rows());
    super::args::expect_shape("--b", &b, n, b.cols(), "states × inputs")?;
    if let Some(l) = &given {
        super::args::expect_shape("--l", l, n, p, "states × outputs")?;
    }
    let convention = super::args::observer_convention(&args.convention)?;
    let mut work = Parametric::new(a)?
        .with(c.entries(), "C")?
        .with(b.entries(), "B")?;
    let l = match (given, &args.observer_poly) {
        // (the command line refuses both; a JSON request is told here)
        (Some(_), Some(_)) => bail!("give --l or --observer-poly, not both"),
        (Some(l), None) => {
            work = work.with(l.entries(), "L")?;
            in_a_plus_lc(l, convention)
        }
        (None, Some(text)) => {
            let desired = DesiredRequest::Poly(text)
                .polynomial(&Default::default(), n)
                .map_err(|e| anyhow!("in --observer-poly: {e}"))?;
            work = work.with(desired.coeffs(), "the observer polynomial")?;
            let design = work.run(|| {
                crate::observer::design_symbolic(
                    a,
                    c,
                    &desired,
                    crate::observer::GainMethod::Ackermann,
                    Convention::APlusLC,
                    crate::observer::Detail::Summary,
                )
            })??;
            if !design.identity {
                bail!(crate::control::ControlError::NotPlaced {
                    what: "A + LC",
                    achieved: design.achieved.to_string(),
                });
            }
            work.observability(a, c)?;
            work.note_denominators(design.gain.matrix.entries(), "a denominator of L")?;
            design.gain.matrix
        }
        (None, None) => bail!("give --l or --observer-poly"),
    };
    let f = match (&args.f, &args.feedback_poly) {
        (Some(_), Some(_)) => bail!("give --f or --feedback-poly, not both"),
        (Some(f), None) => {
            let f = matrix::<Fraction>("--f", f)?;
            super::args::expect_shape("--f", &f, b.cols(), n, "inputs × states")?;
            work = work.with(f.entries(), "F")?;
            f
        }
        (None, Some(text)) => {
            let desired = DesiredRequest::Poly(text)
                .polynomial(&Default::default(), n)
                .map_err(|e| anyhow!("in --feedback-poly: {e}"))?;
            work = work.with(desired.coeffs(), "the feedback polynomial")?;
            let design = work.run(|| {
                crate::feedback::design_feedback_symbolic(
                    a,
                    &b,
                    &desired,
                    crate::observer::GainMethod::Ackermann,
                    crate::feedback::FeedbackConvention::UEqualsFx,
                    crate::observer::Detail::Summary,
                )
            })??;
            work.controllability(a, &b)?;
            work.note_denominators(design.gain.entries(), "a denominator of F")?;
            design.gain
        }
        (None, None) => bail!("give --f or --feedback-poly"),
    };
    let plant = StateSpace::new(a.clone(), Some(b), c.clone(), None)?;
    let r = work.run(|| observer_based_control(&plant, &f, &l))??;
    let json = args.json.then(|| control_json(&f, &l, &r)).transpose()?;
    let how = format!(", identically in s and {}", work.names());
    work.answer(rep, json, |rep| control_text(rep, &f, &l, &r, &how));
    Ok(Outcome::Ok)
}
