//! `owb feedback`: a state feedback designed on its own, with controllability and the exact
//! derivation, in the convention asked for (`u = F x` or `u = −K x`).

use super::args::{json_matrix, matrix, print_json};
use super::Outcome;
use crate::algebra::Rational;
use crate::feedback::{design_feedback, FeedbackConvention, FeedbackError};
use crate::observer::{Detail, GainMethod};
use anyhow::{anyhow, Result};
use serde_json::json;

/// Arguments of `owb feedback`.
#[derive(clap::Args)]
pub struct Args {
    /// The system matrix A (n×n).
    #[arg(allow_hyphen_values = true, long)]
    a: String,
    /// The input matrix B (n×1).
    #[arg(allow_hyphen_values = true, long)]
    b: String,
    #[command(flatten)]
    desired: super::args::DesiredArgs,
    /// ackermann (default), bass-gura or canonical (on the dual pair (Aᵀ, Bᵀ)).
    #[arg(allow_hyphen_values = true, long, default_value = "ackermann")]
    method: String,
    /// u=-kx (default: closed loop A − BK) or u=fx (A + BF).
    #[arg(allow_hyphen_values = true, long, default_value = "u=-kx")]
    convention: String,
    /// Machine-readable output.
    #[arg(long)]
    json: bool,
}

pub fn run(args: Args) -> Result<Outcome> {
    let a = matrix::<Rational>("--a", &args.a)?;
    let b = matrix::<Rational>("--b", &args.b)?;
    super::args::check_plant(
        &a,
        Some(&b),
        &crate::linalg::Matrix::zeros(0, a.cols()),
        None,
    )?;
    let method = GainMethod::parse(&args.method)
        .filter(|m| *m != GainMethod::Lemma31)
        .ok_or_else(|| {
            anyhow!(
                "in --method: unknown method '{}' (ackermann, bass-gura or canonical)",
                args.method
            )
        })?;
    let convention = FeedbackConvention::parse(&args.convention).ok_or_else(|| {
        anyhow!(
            "in --convention: unknown convention '{}' (u=-kx or u=fx)",
            args.convention
        )
    })?;
    let desired = args.desired.parse(a.rows())?;
    let d = design_feedback(&a, &b, &desired, method, convention, Detail::Full).map_err(
        |e| match e {
            FeedbackError::Shape { .. } => anyhow!("in --b: {e}"),
            e => e.into(),
        },
    )?;
    if args.json {
        print_json(&json!({
            "gain": json_matrix(&d.gain),
            "convention": convention.flag(),
            "method": method.flag(),
            "desired": desired.family.to_string(),
            "closed_loop_polynomial": d.achieved.to_input(),
            "places_exactly": d.places_exactly(),
            "controllable": true,
            "steps": serde_json::to_value(&d.derivation.steps)?,
        }));
    } else {
        out!("{}", d.derivation.render());
        outln!(
            "Result (u = {} x, closed loop {}, {method} method on the dual pair):",
            if convention == FeedbackConvention::UEqualsFx {
                "F"
            } else {
                "−K"
            },
            convention.closed_loop()
        );
        outln!("  {} = {}", convention.letter(), d.gain.to_input());
        outln!(
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
