//! `owb observe`: the observability report.

use super::args::json_matrix;
use super::{Outcome, Report};
use crate::observability::observability_report;
use anyhow::Result;
use serde_json::json;

/// Arguments of `owb observe`.
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "commands", derive(clap::Args))]
pub struct Args {
    /// The plant's A and C (`a`, `c`).
    #[serde(flatten)]
    #[cfg_attr(feature = "commands", command(flatten))]
    pub system: super::args::SystemPair,
    /// Machine-readable output.
    #[cfg_attr(feature = "commands", arg(long))]
    #[serde(default)]
    pub json: bool,
}

/// `owb observe`: the observability report.
///
/// # Errors
///
/// What the request gets wrong (named by its flag) or what the computation refuses.
pub fn run(args: Args, rep: &mut Report) -> Result<Outcome> {
    let (a, c) = args.system.parse()?;
    let r = observability_report(&a, &c)?;
    if args.json {
        rep.json(&json!({
            "observability_matrix": json_matrix(&r.matrix),
            "rank": r.rank,
            "order": r.order,
            "observable": r.observable(),
            "determinant": r.determinant.as_ref().map(|d| d.to_string()),
            "unobservable_subspace": r.unobservable_subspace.iter().map(json_matrix).collect::<Vec<_>>(),
            "unobservable_polynomial": r.unobservable_polynomial.to_input(),
            "unobservable_eigenvalues": r.unobservable_eigenvalues.roots.iter().map(|(x, m)| json!({"value": crate::algebra::Ring::to_input(x), "multiplicity": m})).collect::<Vec<_>>(),
            "pbh_confirmed": r.pbh_confirmed,
        }));
    } else {
        outln!(rep, "Observability of (A, C)");
        outln!(rep, "  O_n = [C; CA; …; CA^(n−1)]:");
        for line in r.matrix.render().lines() {
            outln!(rep, "      {line}");
        }
        if let Some(d) = &r.determinant {
            outln!(rep, "  det O_n = {d}");
        }
        outln!(rep, "  rank O_n = {} (order n = {})", r.rank, r.order);
        if r.observable() {
            outln!(rep, "  observable");
        } else {
            outln!(rep, "  NOT observable");
            outln!(rep, "  unobservable subspace ker O_n, basis:");
            for v in &r.unobservable_subspace {
                outln!(rep, "      {}", v.to_input());
            }
            outln!(
                rep,
                "  unobservable modes: det(sI − A|ker O_n) = {}",
                r.unobservable_polynomial
            );
            outln!(
                rep,
                "  unobservable eigenvalues: {}",
                r.unobservable_eigenvalues.render()
            );
            outln!(
                rep,
                "  PBH test rank [λI − A; C] < n at each: {}",
                if r.pbh_confirmed {
                    "confirmed"
                } else {
                    "NOT confirmed"
                }
            );
        }
    }
    Ok(Outcome::Ok)
}
