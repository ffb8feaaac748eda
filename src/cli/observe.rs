//! `owb observe`: the observability report.

use super::args::{json_matrix, print_json};
use super::Outcome;
use crate::observability::observability_report;
use anyhow::Result;
use serde_json::json;

/// Arguments of `owb observe`.
#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    system: super::args::SystemPair,
    /// Machine-readable output.
    #[arg(long)]
    json: bool,
}

pub fn run(args: Args) -> Result<Outcome> {
    let (a, c) = args.system.parse()?;
    let r = observability_report(&a, &c)?;
    if args.json {
        print_json(&json!({
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
        outln!("Observability of (A, C)");
        outln!("  O_n = [C; CA; …; CA^(n−1)]:");
        for line in r.matrix.render().lines() {
            outln!("      {line}");
        }
        if let Some(d) = &r.determinant {
            outln!("  det O_n = {d}");
        }
        outln!("  rank O_n = {} (order n = {})", r.rank, r.order);
        if r.observable() {
            outln!("  observable");
        } else {
            outln!("  NOT observable");
            outln!("  unobservable subspace ker O_n, basis:");
            for v in &r.unobservable_subspace {
                outln!("      {}", v.to_input());
            }
            outln!(
                "  unobservable modes: det(sI − A|ker O_n) = {}",
                r.unobservable_polynomial
            );
            outln!(
                "  unobservable eigenvalues: {}",
                r.unobservable_eigenvalues.render()
            );
            outln!(
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
