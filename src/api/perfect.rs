//! `owb perfect`: the perfect (descriptor) observer of an observable system, the
//! reconstruction of x̂ from y, u and their derivatives, and the exact conditions under which
//! the same observer stays perfect for a changed plant.

use super::args::{json_matrix, matrix};
use super::{Outcome, Report};
use crate::algebra::{Rational, Ring};
use crate::derivation::Show;
use crate::linalg::Matrix;
use crate::observer::perfect::{
    perfect_observer, robustness_conditions, robustness_residuals, Reconstruction,
};
use crate::system::StateSpace;
use anyhow::Result;
use serde_json::json;

/// Arguments of `owb perfect`.
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "commands", derive(clap::Args))]
pub struct Args {
    /// The plant's A and C (`a`, `c`).
    #[serde(flatten)]
    #[cfg_attr(feature = "commands", command(flatten))]
    pub system: super::args::SystemPair,
    /// The plant's B and D (`b`, `d`).
    #[serde(flatten)]
    #[cfg_attr(feature = "commands", command(flatten))]
    pub inputs: super::args::InputMatrices,
    /// A changed plant to test the observer on: its A (default: unchanged).
    #[cfg_attr(feature = "commands", arg(allow_hyphen_values = true, long))]
    #[serde(default)]
    pub changed_a: Option<String>,
    /// … its B (default: unchanged).
    #[cfg_attr(feature = "commands", arg(allow_hyphen_values = true, long))]
    #[serde(default)]
    pub changed_b: Option<String>,
    /// … its C (default: unchanged).
    #[cfg_attr(feature = "commands", arg(allow_hyphen_values = true, long))]
    #[serde(default)]
    pub changed_c: Option<String>,
    /// Machine-readable output.
    #[cfg_attr(feature = "commands", arg(long))]
    #[serde(default)]
    pub json: bool,
}

/// A changed plant matrix (`--changed-*`), the original when not given; it must keep the
/// original's shape.
fn changed_matrix(
    flag: &str,
    text: Option<&str>,
    original: &Matrix<Rational>,
) -> Result<Matrix<Rational>> {
    let Some(text) = text else {
        return Ok(original.clone());
    };
    let m = matrix::<Rational>(flag, text)?;
    super::args::expect_shape(
        flag,
        &m,
        original.rows(),
        original.cols(),
        "the shape of the plant's matrix it changes",
    )?;
    Ok(m)
}

/// `owb perfect`: the perfect (descriptor) observer.
///
/// # Errors
///
/// What the request gets wrong (named by its flag) or what the computation refuses.
pub fn run(args: Args, rep: &mut Report) -> Result<Outcome> {
    let (a, c) = args.system.parse()?;
    let (b, d) = args.inputs.parse(&args.system)?;
    super::args::check_plant(&a, Some(&b), &c, d.as_ref())?;
    let plant = StateSpace::new(a.clone(), Some(b.clone()), c.clone(), d)?;
    let p = perfect_observer(&plant)?;
    let conditions = robustness_conditions(&p);
    let changed = args.changed_a.is_some() || args.changed_b.is_some() || args.changed_c.is_some();
    let fit = if changed {
        let a2 = changed_matrix("--changed-a", args.changed_a.as_deref(), &a)?;
        let b2 = changed_matrix("--changed-b", args.changed_b.as_deref(), &b)?;
        let c2 = changed_matrix("--changed-c", args.changed_c.as_deref(), &c)?;
        let changed_plant = StateSpace::new(a2, Some(b2), c2, Some(plant.d().clone()))?;
        Some(robustness_residuals(&p, &changed_plant)?)
    } else {
        None
    };
    let fits = fit.as_ref().map(|(ra, rb)| ra.is_zero() && rb.is_zero());
    if args.json {
        rep.json_with_steps(json!({
            "E": json_matrix(&p.e),
            "F": json_matrix(&p.f),
            "G_u": json_matrix(&p.input_matrix),
            "G_y": json_matrix(&p.output_matrix),
            "T": json_matrix(&p.t),
            "observability_indices": p.indices,
            "pencil_determinant": p.pencil_determinant.to_input(),
            "reconstruction": Reconstruction(&p.reconstruction).input(),
            "robustness_conditions": conditions.iter().map(|c| format!("{} = 0", c.to_input())).collect::<Vec<_>>(),
            "changed_plant_fits": fits,
        }), p.derivation.steps)?;
    } else {
        rep.derivation(&p.derivation);
        outln!(
            rep,
            "The observer stays perfect for a changed plant (A', B', C', D') exactly when:"
        );
        for cond in &conditions {
            outln!(rep, "  {cond} = 0");
        }
        if let Some((ra, rb)) = &fit {
            outln!(
                rep,
                "Changed plant: E A' − F − G_y C' =\n{}\n  E B' − G_u − G_y D' =\n{}",
                ra.render(),
                rb.render()
            );
            outln!(
                rep,
                "  {}",
                if fits == Some(true) {
                    "the observer reconstructs the changed plant's state exactly (error zero for t > 0)"
                } else {
                    "the observer does NOT fit the changed plant: its estimate is wrong"
                }
            );
        }
    }
    Ok(if fits == Some(false) {
        Outcome::Failed
    } else {
        Outcome::Ok
    })
}
