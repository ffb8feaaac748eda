//! Running a worked example's simulation scenarios and checking what its figures claim.

use super::compute::compute;
use super::format::{CheckSpec, ExampleFile, ScenarioSpec};
use super::inputs::Inputs;
use super::load::WorkedError;
use super::value::Value;
use crate::algebra::{Quadratic, Rational};
use crate::linalg::Matrix;
use crate::observer::perfect::perfect_observer;
use crate::observer::Convention;
use crate::simulation::{self, summarize, Integrator, Loop, Setup, StateSummary, Trace};
use crate::syntax::{parse_matrix_with, parse_scalar, Environment};
use crate::system::StateSpace;
use nalgebra::DMatrix;
use serde::Serialize;
use std::path::Path;

/// One scenario, run.
#[derive(Clone, Debug)]
pub struct ScenarioRun {
    /// Name.
    pub name: String,
    /// The figure(s) it reproduces.
    pub figure: String,
    /// Its stated assumptions.
    pub assumptions: String,
    /// The observer used, in words.
    pub observer: String,
    /// The run.
    pub trace: Trace,
    /// Per-state error summary.
    pub summary: Vec<StateSummary>,
    /// States to plot.
    pub plot: Vec<usize>,
    /// Time unit.
    pub time_unit: String,
}

/// One checked figure statement.
#[derive(Clone, Debug, Serialize)]
pub struct CheckResult {
    /// The scenario.
    pub scenario: String,
    /// What the document says.
    pub source: String,
    /// The metric and state, e.g. `overshoot of e2`.
    pub metric: String,
    /// Its value in this run.
    pub value: f64,
    /// The comparison made, with the numbers.
    pub comparison: String,
    /// Whether it holds.
    pub holds: bool,
    /// The same check from another initial state (`also_from_x0`), when the statement depends
    /// on the one the scenario assumes (absent from the JSON otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub elsewhere: Option<Elsewhere>,
}

/// A check repeated from another initial state.
#[derive(Clone, Debug, Serialize)]
pub struct Elsewhere {
    /// The initial state, as written.
    pub x0: String,
    /// The metric's value there.
    pub value: f64,
    /// The comparison made there, with the numbers.
    pub comparison: String,
    /// Whether it holds there.
    pub holds: bool,
}

impl CheckResult {
    /// The verdict in words: `holds`, `does not hold`, or — for a statement that depends on the
    /// assumed initial state — `holds for the assumed x(0) only (from … it does not: …)`.
    pub fn verdict(&self) -> String {
        match (&self.elsewhere, self.holds) {
            (_, false) => "does not hold".to_string(),
            (None, true) => "holds".to_string(),
            (Some(e), true) if e.holds => format!("holds (also from x(0) = {})", e.x0),
            (Some(e), true) => format!(
                "holds for the assumed x(0) only — from x(0) = {} it does not: {}",
                e.x0, e.comparison
            ),
        }
    }
}

fn metric(s: &StateSummary, name: &str) -> Option<f64> {
    Some(match name {
        "ise" => s.ise,
        "overshoot" => s.overshoot,
        "settling_time" => s.settling_time,
        "steady_rms" => s.steady_rms,
        "max_relative_error" => s.max_relative_error,
        _ => return None,
    })
}

/// The metrics a check may name.
pub const METRICS: &[&str] = &[
    "ise",
    "overshoot",
    "settling_time",
    "steady_rms",
    "max_relative_error",
];

/// A real matrix (square roots allowed) for the simulator.
fn float_matrix(text: &str, env: &Environment) -> Result<DMatrix<f64>, String> {
    let m = parse_matrix_with::<Quadratic>(text, env).map_err(|e| e.show_in(text))?;
    let mut out = DMatrix::zeros(m.rows(), m.cols());
    for i in 0..m.rows() {
        for j in 0..m.cols() {
            let (re, im) = m.get(i, j).to_complex_f64();
            if im != 0.0 {
                return Err(format!("'{}' is not real", m.get(i, j)));
            }
            out[(i, j)] = re;
        }
    }
    Ok(out)
}

fn exact_matrix(text: &str, env: &Environment) -> Result<Matrix<Rational>, String> {
    parse_matrix_with::<Rational>(text, env).map_err(|e| e.show_in(text))
}

/// Runs every scenario of an example (all are run, since checks may compare scenarios) and
/// checks the figures' statements.
///
/// # Errors
/// [`WorkedError`] naming the file, line and field of a malformed scenario, or a simulation that
/// cannot run.
pub fn run_scenarios(
    path: &Path,
    ex: &ExampleFile,
    raw: &str,
) -> Result<(Vec<ScenarioRun>, Vec<CheckResult>), WorkedError> {
    let file = path.display().to_string();
    let mut runs: Vec<ScenarioRun> = Vec::new();
    for sc in &ex.scenarios {
        if runs.iter().any(|r| r.name == sc.name) {
            return Err(error(
                &file,
                raw,
                &sc.name,
                "name",
                format!("scenario '{}' appears twice", sc.name),
            ));
        }
        runs.push(run_one(&file, raw, ex, sc)?);
    }
    let mut checks = Vec::new();
    // runs from another initial state, made once per (scenario, x(0))
    let mut moved: Vec<(String, String, ScenarioRun)> = Vec::new();
    for (sc, run) in ex.scenarios.iter().zip(&runs) {
        for c in &sc.checks {
            let bad = |m: String| error(&file, raw, &sc.name, "checks", m);
            if !METRICS.contains(&c.metric.as_str()) {
                return Err(bad(format!(
                    "unknown metric '{}'; known: {}",
                    c.metric,
                    METRICS.join(", ")
                )));
            }
            if run.summary.get(c.state.wrapping_sub(1)).is_none() {
                return Err(bad(format!("state {} does not exist", c.state)));
            }
            let (value, comparison, holds) = compare_check(c, run, &runs).map_err(bad)?;
            let elsewhere = match &c.also_from_x0 {
                None => None,
                Some(x0) => {
                    let mut names = vec![sc.name.clone()];
                    names.extend(c.less_than.iter().chain(&c.greater_than).cloned());
                    for name in names {
                        if moved.iter().any(|(n, x, _)| *n == name && x == x0) {
                            continue;
                        }
                        let spec = ex
                            .scenarios
                            .iter()
                            .find(|s| s.name == name)
                            .ok_or_else(|| bad(format!("no scenario named '{name}'")))?;
                        let shifted = ScenarioSpec {
                            x0: Some(x0.clone()),
                            ..spec.clone()
                        };
                        let r = run_one(&file, raw, ex, &shifted)?;
                        moved.push((name, x0.clone(), r));
                    }
                    let there: Vec<ScenarioRun> = moved
                        .iter()
                        .filter(|(_, x, _)| x == x0)
                        .map(|(_, _, r)| r.clone())
                        .collect();
                    let own = there
                        .iter()
                        .find(|r| r.name == sc.name)
                        .ok_or_else(|| bad(format!("no run of '{}'", sc.name)))?;
                    let (value, comparison, holds) = compare_check(c, own, &there).map_err(bad)?;
                    Some(Elsewhere {
                        x0: x0.clone(),
                        value,
                        comparison,
                        holds,
                    })
                }
            };
            checks.push(CheckResult {
                scenario: sc.name.clone(),
                source: c.source.clone(),
                metric: format!("{} of e{}", c.metric, c.state),
                value,
                comparison,
                holds,
                elsewhere,
            });
        }
    }
    Ok((runs, checks))
}

/// One check on one run, against the runs it names: `(value, comparison in numbers, holds)`.
fn compare_check(
    c: &CheckSpec,
    run: &ScenarioRun,
    runs: &[ScenarioRun],
) -> Result<(f64, String, bool), String> {
    let value = run
        .summary
        .get(c.state.wrapping_sub(1))
        .and_then(|s| metric(s, &c.metric))
        .unwrap_or(f64::NAN);
    let mut parts = Vec::new();
    let mut holds = true;
    if let Some(b) = c.below {
        holds &= value < b;
        parts.push(format!("{value:.4e} < {b:.4e}"));
    }
    if let Some(b) = c.above {
        holds &= value > b;
        parts.push(format!("{value:.4e} > {b:.4e}"));
    }
    for (others, less) in [(&c.less_than, true), (&c.greater_than, false)] {
        for other in others {
            let o = runs
                .iter()
                .find(|r| &r.name == other)
                .ok_or_else(|| format!("no scenario named '{other}'"))?;
            let ov = o
                .summary
                .get(c.state.wrapping_sub(1))
                .and_then(|s| metric(s, &c.metric))
                .unwrap_or(f64::NAN);
            holds &= if less { value < ov } else { value > ov };
            parts.push(format!(
                "{value:.4e} {} {ov:.4e} ({other})",
                if less { "<" } else { ">" }
            ));
        }
    }
    if parts.is_empty() {
        return Err("a check needs below, above, less_than or greater_than".into());
    }
    Ok((value, parts.join(", "), holds))
}

fn error(file: &str, raw: &str, scenario: &str, field: &str, message: String) -> WorkedError {
    WorkedError {
        file: file.to_string(),
        line: super::load::locate(raw, Some(("name", scenario)), field),
        field: format!("scenarios.{scenario}.{field}"),
        message,
    }
}

/// One scenario being read: where errors point, and the symbol values in force.
struct ScenarioContext<'a> {
    file: &'a str,
    raw: &'a str,
    ex: &'a ExampleFile,
    sc: &'a ScenarioSpec,
    env: Environment,
}

impl ScenarioContext<'_> {
    fn bad(&self, field: &str, m: String) -> WorkedError {
        error(self.file, self.raw, &self.sc.name, field, m)
    }

    fn float(&self, text: &str, field: &str) -> Result<DMatrix<f64>, WorkedError> {
        float_matrix(text, &self.env).map_err(|m| self.bad(field, m))
    }

    /// A, B, C, D as floats: the scenario's matrices first, else `[system]`'s (D only with
    /// the system's own C).
    #[allow(clippy::type_complexity)]
    fn plant(
        &self,
    ) -> Result<(DMatrix<f64>, DMatrix<f64>, DMatrix<f64>, DMatrix<f64>), WorkedError> {
        let (sc, sys) = (self.sc, &self.ex.system);
        let own = [&sc.a, &sc.b, &sc.c];
        let text = |name: &str| {
            sys.resolve(own, name).ok_or_else(|| {
                self.bad(
                    name,
                    format!("{name} is missing (in the scenario or [system])"),
                )
            })
        };
        let a = self.float(text("A")?, "A")?;
        let b = self.float(text("B")?, "B")?;
        let c = self.float(text("C")?, "C")?;
        let d = match sys.resolve(own, "D") {
            Some(t) => self.float(t, "D")?,
            None => DMatrix::zeros(c.nrows(), b.ncols()),
        };
        Ok((a, b, c, d))
    }

    /// The gain in A − KC form and how the report names it.
    fn gain(&self, n: usize, p: usize) -> Result<(DMatrix<f64>, String), WorkedError> {
        let sc = self.sc;
        let convention = match &sc.convention {
            None => Convention::AMinusKC,
            Some(t) => Convention::parse(t)
                .ok_or_else(|| self.bad("convention", format!("'{t}' is neither a-kc nor a+lc")))?,
        };
        let (gain, observer) = if sc.perfect {
            return Ok((
                DMatrix::zeros(n, p),
                "perfect observer of [system]".to_string(),
            ));
        } else if let Some(g) = &sc.gain {
            (self.float(g, "gain")?, format!("gain {g}"))
        } else if let Some(id) = &sc.gain_claim {
            self.claimed_gain(id)?
        } else {
            return Err(self.bad("gain", "give gain, gain_claim or perfect = true".into()));
        };
        // the loop is simulated with A − KC
        let gain = gain * convention.sign();
        Ok((gain, observer))
    }

    /// The gain a claim of the example recomputes, in A − KC form.
    fn claimed_gain(&self, id: &str) -> Result<(DMatrix<f64>, String), WorkedError> {
        let claim = self
            .ex
            .claims
            .iter()
            .find(|c| c.id == id)
            .ok_or_else(|| self.bad("gain_claim", format!("no claim with id '{id}'")))?;
        let computed = compute(&Inputs {
            file: self.ex,
            claim,
            env: &self.env,
        })
        .map_err(|e| {
            self.bad(
                "gain_claim",
                format!("claim '{id}' could not be recomputed: {e}"),
            )
        })?;
        let g = match computed.value {
            Value::Matrix(mq) => {
                DMatrix::from_fn(mq.rows(), mq.cols(), |i, j| mq.get(i, j).to_complex_f64().0)
            }
            Value::Approximate {
                rows,
                cols,
                candidates,
                ..
            } if !candidates.is_empty() => DMatrix::from_row_slice(rows, cols, &candidates[0]),
            other => {
                return Err(self.bad(
                    "gain_claim",
                    format!("claim '{id}' is not a gain ({})", other.input()),
                ))
            }
        };
        let claim_convention = claim
            .convention
            .as_deref()
            .and_then(Convention::parse)
            .unwrap_or(Convention::AMinusKC);
        let g = g * claim_convention.sign();
        let shown = g
            .transpose()
            .iter()
            .map(|x| format!("{x:.4}"))
            .collect::<Vec<_>>()
            .join(", ");
        Ok((
            g,
            format!("gain of claim '{id}' (recomputed; entries row by row: {shown})"),
        ))
    }

    fn vector(&self, t: &Option<String>, field: &str, n: usize) -> Result<Vec<f64>, WorkedError> {
        match t {
            None => Ok(vec![0.0; n]),
            Some(t) => Ok(self.float(t, field)?.iter().copied().collect()),
        }
    }

    fn integrator(&self) -> Result<Integrator, WorkedError> {
        Ok(match self.sc.integrator.as_deref() {
            None | Some("rk4") => Integrator::Rk4,
            Some("dormand-prince") => Integrator::DormandPrince {
                rtol: 1e-9,
                atol: 1e-12,
            },
            Some("discrete") => Integrator::Discrete,
            Some(o) => {
                return Err(self.bad(
                    "integrator",
                    format!("'{o}': use rk4, dormand-prince or discrete"),
                ))
            }
        })
    }

    /// The input signals: written in the scenario, read from CSV files beside the example,
    /// or zero.
    fn inputs(&self, m: usize) -> Result<Vec<simulation::Signal>, WorkedError> {
        let sc = self.sc;
        let mut input = sc.input.clone();
        if !sc.input_csv.is_empty() {
            if !input.is_empty() {
                return Err(self.bad("input_csv", "give input or input_csv, not both".into()));
            }
            let base = Path::new(self.file)
                .parent()
                .unwrap_or_else(|| Path::new("."));
            for f in &sc.input_csv {
                let path = base.join(f);
                let read = |e: String| self.bad("input_csv", format!("{}: {e}", path.display()));
                let text = std::fs::read_to_string(&path).map_err(|e| read(e.to_string()))?;
                input.push(simulation::Signal::from_csv(&text).map_err(|e| read(e.to_string()))?);
            }
        }
        if input.is_empty() {
            input = vec![simulation::Signal::Zero; m];
        }
        Ok(input)
    }

    /// The perfect observer of `[system]`, exactly.
    fn perfect(&self) -> Result<crate::observer::perfect::PerfectObserver, WorkedError> {
        let system = &self.ex.system;
        let sys = |t: &Option<String>, name: &str| -> Result<Matrix<Rational>, WorkedError> {
            let t = t.as_ref().ok_or_else(|| {
                self.bad(
                    name,
                    format!("[system] {name} is needed for the perfect observer"),
                )
            })?;
            exact_matrix(t, &self.env).map_err(|m| self.bad(name, m))
        };
        let d_sys = system
            .d
            .as_ref()
            .map(|t| exact_matrix(t, &self.env).map_err(|m| self.bad("D", m)))
            .transpose()?;
        let plant = StateSpace::new(
            sys(&system.a, "A")?,
            Some(sys(&system.b, "B")?),
            sys(&system.c, "C")?,
            d_sys,
        )
        .map_err(|e| self.bad("perfect", e.to_string()))?;
        perfect_observer(&plant).map_err(|e| self.bad("perfect", e.to_string()))
    }
}

fn run_one(
    file: &str,
    raw: &str,
    ex: &ExampleFile,
    sc: &ScenarioSpec,
) -> Result<ScenarioRun, WorkedError> {
    let mut cx = ScenarioContext {
        file,
        raw,
        ex,
        sc,
        env: Environment::new(),
    };
    for (k, v) in ex.parameters.iter().chain(&sc.parameters) {
        let r = parse_scalar::<Rational>(v)
            .map_err(|e| cx.bad("parameters", format!("{k}: {}", e.show_in(v))))?;
        cx.env.insert(k.clone(), r);
    }
    let (a, b, c, d) = cx.plant()?;
    let (n, m, p) = (a.nrows(), b.ncols(), c.nrows());
    let (gain, observer) = cx.gain(n, p)?;
    let feedback = sc
        .feedback
        .as_ref()
        .map(|f| cx.float(f, "feedback"))
        .transpose()?;
    let setup = Setup {
        horizon: sc.horizon,
        step: sc.step,
        integrator: cx.integrator()?,
        input: cx.inputs(m)?,
        output_noise: sc.output_noise.clone(),
        process_noise: sc.process_noise.clone(),
        x0: cx.vector(&sc.x0, "x0", n)?,
        xhat0: cx.vector(&sc.xhat0, "xhat0", n)?,
    };
    let lp = Loop {
        a,
        b,
        c,
        d,
        gain,
        feedback,
    };
    let trace = if sc.perfect {
        simulation::simulate_perfect(&lp, &cx.perfect()?, &setup)
    } else {
        simulation::simulate(&lp, &setup)
    }
    .map_err(|e| cx.bad("horizon", e.to_string()))?;
    let summary = summarize(&trace);
    let plot = if sc.plot.is_empty() {
        (1..=n).collect()
    } else {
        sc.plot.clone()
    };
    if let Some(bad_state) = plot.iter().find(|&&s| s == 0 || s > n) {
        return Err(cx.bad("plot", format!("state {bad_state} does not exist (1…{n})")));
    }
    Ok(ScenarioRun {
        name: sc.name.clone(),
        figure: sc.figure.clone(),
        assumptions: sc.assumptions.clone(),
        observer,
        trace,
        summary,
        plot,
        time_unit: sc.time_unit.clone().unwrap_or_else(|| "s".into()),
    })
}
