//! `owb simulate`: run a worked example's scenarios (the document's figures), write SVG and
//! CSV, and check the figures' statements by numbers.

use super::args::{examples_folder, find_example};
use super::{Outcome, Report};
use crate::files::write_safely;
use crate::simulation::{csv::to_csv, plot::svg};
use crate::worked::{load_example, load_folder, run_scenarios, ScenarioRun};
use anyhow::{bail, Result};
use serde_json::json;
use std::path::{Path, PathBuf};

/// Arguments of `owb simulate`.
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "commands", derive(clap::Args))]
pub struct Args {
    /// The worked example (id or file path).
    pub example: String,
    /// Only this scenario (all are run, since checks may compare them).
    #[cfg_attr(feature = "commands", arg(allow_hyphen_values = true, long))]
    #[serde(default)]
    pub scenario: Option<String>,
    /// Write the figure as SVG (with several scenarios: FILE-stem-NAME.svg each).
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, value_name = "FILE")
    )]
    #[serde(default)]
    pub svg: Option<PathBuf>,
    /// Write the time series as CSV (with several scenarios: one file per scenario, as for --svg).
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, value_name = "FILE")
    )]
    #[serde(default)]
    pub csv: Option<PathBuf>,
    /// The folder of worked examples.
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, default_value_os_t = super::args::defaults::examples_folder())
    )]
    #[serde(default = "super::args::defaults::examples_folder")]
    pub dir: PathBuf,
    /// Machine-readable output.
    #[cfg_attr(feature = "commands", arg(long))]
    #[serde(default)]
    pub json: bool,
}

fn target(path: &Path, name: &str, several: bool) -> PathBuf {
    if !several {
        return path.to_path_buf();
    }
    let stem = path
        .file_stem()
        .map_or_else(|| "figure".into(), |s| s.to_string_lossy().into_owned());
    let ext = path
        .extension()
        .map_or_else(String::new, |e| format!(".{}", e.to_string_lossy()));
    // a scenario's name comes from a file: only letters, digits, '-' and '_' reach a file
    // name (no '/', no '..', nothing invisible)
    let name: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    path.with_file_name(format!("{stem}-{name}{ext}"))
}

fn describe(run: &ScenarioRun) -> String {
    let mut out = format!(
        "{} — {}\n  observer: {}\n",
        run.name, run.figure, run.observer
    );
    if !run.assumptions.is_empty() {
        out.push_str(&format!("  assumptions: {}\n", run.assumptions));
    }
    out.push_str(
        "  state  ∫e² dt        overshoot   settling (s)  steady RMS    max |e|/max |x|\n",
    );
    for s in &run.summary {
        out.push_str(&format!(
            "  e{:<5} {:<13.4e} {:<11.4} {:<13.3} {:<13.4e} {:.4e}\n",
            s.state, s.ise, s.overshoot, s.settling_time, s.steady_rms, s.max_relative_error
        ));
    }
    out
}

/// `owb simulate`: a worked example's scenarios simulated.
///
/// # Errors
///
/// What the request gets wrong (named by its flag) or what the computation refuses.
pub fn run(args: Args, rep: &mut Report) -> Result<Outcome> {
    super::args::distinct_outputs(&[
        ("--svg", args.svg.as_deref()),
        ("--csv", args.csv.as_deref()),
    ])?;
    let dir = examples_folder(&args.dir)?;
    let all = load_folder(&dir)?;
    let path = find_example(&dir, &all, &args.example)?;
    let (ex, raw) = load_example(&path)?;
    if ex.scenarios.is_empty() {
        bail!("{} declares no scenarios", path.display());
    }
    let (runs, checks) = run_scenarios(&path, &ex, &raw)?;
    let chosen: Vec<&ScenarioRun> = match &args.scenario {
        Some(name) => {
            let r = runs.iter().find(|r| &r.name == name);
            match r {
                Some(r) => vec![r],
                None => bail!(
                    "no scenario '{name}' in {}; scenarios: {}",
                    path.display(),
                    runs.iter()
                        .map(|r| r.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            }
        }
        None => runs.iter().collect(),
    };
    let several = chosen.len() > 1;
    for r in &chosen {
        if let Some(p) = &args.svg {
            let title = format!("{} — {}", ex.id, r.figure);
            let figure = svg(&r.trace, &r.plot, &title, &r.time_unit)?;
            write_safely(&target(p, &r.name, several), &[&path], |w| {
                w.write_all(figure.as_bytes())
            })
            .map_err(|e| anyhow::anyhow!("in --svg: {e}"))?;
        }
        if let Some(p) = &args.csv {
            let table = to_csv(&r.trace);
            write_safely(&target(p, &r.name, several), &[&path], |w| {
                w.write_all(table.as_bytes())
            })
            .map_err(|e| anyhow::anyhow!("in --csv: {e}"))?;
        }
    }
    let shown_checks: Vec<_> = checks
        .iter()
        .filter(|c| chosen.iter().any(|r| r.name == c.scenario))
        .collect();
    let failed = shown_checks.iter().any(|c| !c.holds);
    if args.json {
        rep.json(json!({
            "example": ex.id,
            "scenarios": chosen.iter().map(|r| json!({
                "name": r.name,
                "figure": r.figure,
                "assumptions": r.assumptions,
                "observer": r.observer,
                "samples": r.trace.t.len(),
                "summary": r.summary,
            })).collect::<Vec<_>>(),
            "checks": shown_checks,
        }));
    } else {
        for r in &chosen {
            out!(rep, "{}", describe(r));
        }
        if !shown_checks.is_empty() {
            outln!(rep, "Figure statements checked:");
            for c in &shown_checks {
                outln!(
                    rep,
                    "  [{}] {} — {}: {} → {}",
                    c.scenario,
                    c.source,
                    c.metric,
                    c.comparison,
                    if c.holds {
                        c.verdict()
                    } else {
                        "DOES NOT HOLD".to_string()
                    }
                );
            }
        }
    }
    Ok(if failed { Outcome::Failed } else { Outcome::Ok })
}
