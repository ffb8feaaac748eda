//! `owb feedback`: a state feedback designed on its own, with controllability and the exact
//! derivation, in the convention asked for (`u = F x` or `u = −K x`).

use super::args::{json_matrix, Plant};
use super::parametric::{lift, Parametric};
use super::{Outcome, Report};
use crate::algebra::Fraction;
use crate::feedback::{
    design_feedback, design_feedback_symbolic, FeedbackConvention, FeedbackError,
};
use crate::linalg::Matrix;
use crate::observer::Detail;
use anyhow::{anyhow, Result};
use serde_json::json;

/// Arguments of `owb feedback`.
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "commands", derive(clap::Args))]
pub struct Args {
    /// The system matrix A (n×n).
    #[cfg_attr(feature = "commands", arg(allow_hyphen_values = true, long))]
    pub a: String,
    /// The input matrix B (n×1).
    #[cfg_attr(feature = "commands", arg(allow_hyphen_values = true, long))]
    pub b: String,
    /// Values for the parameters, e.g. "k=2, m=1/2".
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, value_name = "NAME=VALUE,…")
    )]
    #[serde(default)]
    pub at: Option<String>,
    /// The desired polynomial (`poles`, `poly`, `repeated`, `butterworth`, `bessel`).
    #[serde(flatten)]
    #[cfg_attr(feature = "commands", command(flatten))]
    pub desired: super::args::DesiredArgs,
    /// ackermann (default), bass-gura or canonical (on the dual pair (Aᵀ, Bᵀ)).
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, default_value_t = super::args::defaults::method())
    )]
    #[serde(default = "super::args::defaults::method")]
    pub method: String,
    /// u=-kx (default: closed loop A − BK) or u=fx (A + BF).
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, default_value_t = super::args::defaults::feedback_convention())
    )]
    #[serde(default = "super::args::defaults::feedback_convention")]
    pub convention: String,
    /// Machine-readable output.
    #[cfg_attr(feature = "commands", arg(long))]
    #[serde(default)]
    pub json: bool,
}

impl Args {
    /// `--convention`.
    fn feedback_convention(&self) -> Result<FeedbackConvention> {
        FeedbackConvention::parse(&self.convention).ok_or_else(|| {
            anyhow!(
                "in --convention: unknown convention '{}' (u=-kx or u=fx)",
                self.convention
            )
        })
    }
}

/// `owb feedback`: state feedback by duality.
///
/// # Errors
///
/// What the request gets wrong (named by its flag) or what the computation refuses.
pub fn run(args: Args, rep: &mut Report) -> Result<Outcome> {
    let pair = super::args::SystemPair {
        a: Some(args.a.clone()),
        c: Some(args.b.clone()),
        tf: None,
        at: args.at.clone(),
    };
    let (a, b) = match pair.plant_named("--b")? {
        Plant::Symbolic(a, b) => return symbolic(&args, &a, &b, rep),
        Plant::Numeric(a, b) if args.at.is_none() && args.desired.mentions_parameters() => {
            return symbolic(&args, &lift(&a), &lift(&b), rep)
        }
        Plant::Numeric(a, b) => (a, b),
    };
    super::args::check_plant(
        &a,
        Some(&b),
        &crate::linalg::Matrix::zeros(0, a.cols()),
        None,
    )?;
    let method = super::args::gain_method(&args.method)?;
    let convention = args.feedback_convention()?;
    let desired = args.desired.parse_at(a.rows(), &pair.values()?)?;
    let d = design_feedback(&a, &b, &desired, method, convention, Detail::Full).map_err(
        |e| match e {
            FeedbackError::Shape { .. } => anyhow!("in --b: {e}"),
            e => e.into(),
        },
    )?;
    if args.json {
        rep.json_with_steps(
            json!({
                "gain": json_matrix(&d.gain),
                "convention": convention.flag(),
                "method": method.flag(),
                "desired": desired.family.to_string(),
                "closed_loop_polynomial": d.achieved.to_input(),
                "places_exactly": d.places_exactly(),
                "controllable": true,
            }),
            d.derivation.steps,
        )?;
    } else {
        rep.derivation(&d.derivation);
        outln!(
            rep,
            "Result (u = {} x, closed loop {}, {method} method on the dual pair):",
            if convention == FeedbackConvention::UEqualsFx {
                "F"
            } else {
                "−K"
            },
            convention.closed_loop()
        );
        outln!(rep, "  {} = {}", convention.letter(), d.gain.to_input());
        outln!(
            rep,
            "  closed-loop polynomial = {} ({})",
            d.achieved,
            if d.places_exactly() {
                "the desired polynomial, exactly"
            } else {
                "NOT the desired polynomial"
            }
        );
    }
    Ok(Outcome::Ok)
}

/// State feedback as a formula in the parameters.
fn symbolic(
    args: &Args,
    a: &Matrix<Fraction>,
    b: &Matrix<Fraction>,
    rep: &mut Report,
) -> Result<Outcome> {
    let method = super::args::gain_method(&args.method)?;
    let convention = args.feedback_convention()?;
    let desired = args.desired.symbolic(a.rows())?;
    let mut work = Parametric::new(a)?
        .with(b.entries(), "B")?
        .with(desired.coeffs(), "the desired polynomial")?;
    let d = work
        .run(|| design_feedback_symbolic(a, b, &desired, method, convention, Detail::Full))?
        .map_err(|e| match e {
            FeedbackError::Shape { .. } => anyhow!("in --b: {e}"),
            e => e.into(),
        })?;
    work.controllability(a, b)?;
    work.note_denominators(d.gain.entries(), "a denominator of the gain")?;
    let json = args
        .json
        .then(|| -> Result<serde_json::Value> {
            Ok(json!({
                "gain": json_matrix(&d.gain),
                "convention": convention.flag(),
                "method": method.flag(),
                "desired": args.desired.describe(),
                "closed_loop_polynomial": d.achieved.to_input(),
                "places_exactly": d.identity,
                "controllable": true,
                "steps": serde_json::to_value(&d.derivation.steps)?,
            }))
        })
        .transpose()?;
    work.answer(rep, json, |rep| {
        rep.derivation(&d.derivation);
        outln!(
            rep,
            "Result (closed loop {}, {method} method on the dual pair):",
            convention.closed_loop()
        );
        outln!(rep, "  {} = {}", convention.letter(), d.gain.to_input());
        outln!(
            rep,
            "  closed-loop polynomial = {} ({})",
            d.achieved,
            if d.identity {
                format!(
                    "the desired polynomial, identically in s and {}",
                    work.names()
                )
            } else {
                "NOT the desired polynomial".to_string()
            }
        );
    });
    Ok(Outcome::Ok)
}
