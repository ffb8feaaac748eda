//! The workbench's commands as library functions: one request type per command, one
//! [`Report`] back. Every front end calls these — the `owb` command line (which parses the
//! process's arguments into a [`Command`] with clap), the course book's directives and the
//! browser module (which read a [`Command`] from JSON, with no clap compiled in) — so a request
//! gives the same report whoever asks, and each computation runs once.
//!
//! A request holds the values as a user types them (matrices in MATLAB syntax, polynomials,
//! names of methods); each command validates them once, at its start, with errors naming the
//! field (`in --a: …`, the command line's flag — the same name as the JSON key). The report
//! holds the text the command line prints (its JSON when the request asked for `json`), the
//! JSON value itself, the derivation's steps (for the book's and the browser's typeset
//! derivation) and warnings.
//!
//! ```
//! use observer_workbench::api::{run, Command, Outcome};
//! let request = Command::from_json(r#"{"command": "observe", "a": "[1 0; 0 2]", "c": "[1 0]"}"#).unwrap();
//! let report = run(request).unwrap();
//! assert_eq!(report.outcome, Outcome::Ok);
//! assert!(report.text.contains("unobservable eigenvalues: 2"), "{}", report.text);
//! ```

/// `writeln!` into a report.
macro_rules! outln {
    ($r:expr) => { $r.write(format_args!("\n")) };
    ($r:expr, $($t:tt)*) => {{
        $r.write(format_args!($($t)*));
        $r.write(format_args!("\n"));
    }};
}

/// `write!` into a report.
macro_rules! out {
    ($r:expr, $($t:tt)*) => { $r.write(format_args!($($t)*)) };
}

pub mod args;
pub mod canonical;
pub mod control;
pub mod discrete;
pub mod exercise;
pub mod feedback;
pub mod gain;
mod json_text;
pub mod kalman;
pub mod observe;
pub mod optimal;
pub mod parametric;
pub mod perfect;
mod progress;
pub mod reduced;
#[cfg(feature = "plot")]
pub mod simulate;
pub mod verify;

use crate::derivation::{Derivation, Step};
use std::fmt::Write as _;

/// What a command concluded.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Outcome {
    /// All good.
    Ok,
    /// A verification or check found something wrong (the command line's exit status 1).
    Failed,
}

/// What a command reports: the text the command line prints, with the values behind it.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Report {
    /// What the command concluded.
    pub outcome: Outcome,
    /// The report as the command line prints it (the pretty JSON when the request asked for
    /// `json`).
    pub text: String,
    /// The JSON value, when the request asked for `json`.
    pub json: Option<serde_json::Value>,
    /// The derivation's steps, when the command derived something (typeset by the book and the
    /// browser with [`Report::latex`]).
    pub steps: Vec<Step>,
    /// Remarks that are not part of the report (the command line prints them on standard
    /// error).
    pub warnings: Vec<String>,
    /// What the report keeps besides its text.
    #[serde(skip)]
    keep: Keep,
}

/// What a [`Report`] keeps besides its text: everything (the library's [`run`]), or the text
/// alone ([`run_text`], the command line's: it prints the text and nothing else, and an
/// order-60 reduced observer's JSON value and steps are some 200 MB it would build, copy and
/// free for nothing).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Keep {
    /// The text, the JSON value and the steps.
    #[default]
    Everything,
    /// The text only: `json` stays `None` and `steps` empty.
    Text,
}

impl Default for Report {
    fn default() -> Self {
        Report {
            outcome: Outcome::Ok,
            text: String::new(),
            json: None,
            steps: Vec::new(),
            warnings: Vec::new(),
            keep: Keep::Everything,
        }
    }
}

impl std::fmt::Display for Report {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.text)
    }
}

impl Report {
    /// Appends formatted text (what `outln!` and `out!` write).
    pub fn write(&mut self, args: std::fmt::Arguments<'_>) {
        let _ = self.text.write_fmt(args);
    }

    /// The JSON answer: kept, and printed pretty. Its derivation (`"steps"`), if it has one,
    /// is kept for typesetting too.
    pub fn json(&mut self, v: serde_json::Value) {
        self.write_json(&v);
        if self.keep == Keep::Text {
            return;
        }
        // read from the value in place: an order-40 reduced observer's steps are 20 MB
        if let Some(steps) = v
            .get("steps")
            .and_then(|s| <Vec<Step> as serde::Deserialize>::deserialize(s).ok())
        {
            self.steps = steps;
        }
        self.json = Some(v);
    }

    /// [`Report::json`] for an answer whose bulk is float matrices: each `(key, matrix)` is the
    /// value's entry `key`, written as [`args::json_exp_matrix`] gives it. A report that keeps
    /// its text only writes the matrices straight into the text, never making them values;
    /// the text is the same.
    pub fn json_with_exp_matrices(
        &mut self,
        mut v: serde_json::Value,
        matrices: &[(&str, args::ExpMatrix<'_>)],
    ) {
        if self.keep == Keep::Text {
            json_text::write_pretty_with_exp_matrices(&mut self.text, v, matrices);
            self.text.push('\n');
            return;
        }
        if let Some(answer) = v.as_object_mut() {
            for (key, m) in matrices {
                answer.insert((*key).into(), m.value());
            }
        }
        self.json(v);
    }

    /// [`Report::json`] for an answer with a derivation: `steps` become its `"steps"` and are
    /// kept as they are, instead of being read back from the value (at n = 20 a reduced
    /// observer spent a twentieth of its time reading its own steps back).
    ///
    /// # Errors
    /// A step that cannot be serialised (none can: a step is strings).
    pub fn json_with_steps(
        &mut self,
        mut v: serde_json::Value,
        steps: Vec<Step>,
    ) -> serde_json::Result<()> {
        if self.keep == Keep::Text {
            // the steps written into the text one at a time, never all copied into the value
            json_text::write_pretty_with_steps(&mut self.text, v, &steps);
            self.text.push('\n');
            return Ok(());
        }
        if let Some(answer) = v.as_object_mut() {
            answer.insert("steps".into(), serde_json::to_value(&steps)?);
        }
        self.write_json(&v);
        self.steps = steps;
        self.json = Some(v);
        Ok(())
    }

    fn write_json(&mut self, v: &serde_json::Value) {
        json_text::write_pretty(&mut self.text, v);
        self.text.push('\n');
    }

    /// A derivation: its text appended, its steps kept for typesetting.
    pub fn derivation(&mut self, d: &Derivation) {
        out!(self, "{}", d.render());
        if self.keep == Keep::Everything {
            self.steps.clone_from(&d.steps);
        }
    }

    /// One more step for the typeset derivation (kept unless the report keeps its text only).
    pub fn push_step(&mut self, step: Step) {
        if self.keep == Keep::Everything {
            self.steps.push(step);
        }
    }

    /// The derivation typeset in LaTeX, if the command derived something.
    pub fn latex(&self) -> Option<String> {
        (!self.steps.is_empty()).then(|| {
            Derivation {
                title: String::new(),
                steps: self.steps.clone(),
            }
            .to_latex()
        })
    }
}

/// A command that failed: the error, and what it had reported before.
#[derive(Debug)]
pub struct Failure {
    /// Why it failed (with its chain of causes).
    pub error: anyhow::Error,
    /// What the command had reported before it failed.
    pub partial: Report,
}

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.error)
    }
}

impl std::error::Error for Failure {}

/// The commands of the workbench, one request each. The command line's subcommands (clap,
/// feature `commands`) and the JSON requests of the book and the browser
/// (`{"command": "gain", "a": …}`, keys named as the flags) are the same type.
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(tag = "command", rename_all = "kebab-case")]
#[cfg_attr(feature = "commands", derive(clap::Subcommand))]
pub enum Command {
    /// Recompute the worked examples of the source documents and compare with what they printed.
    Verify(verify::Args),
    /// Observability report: O_n, rank, unobservable subspace and eigenvalues.
    Observe(observe::Args),
    /// Observer canonical form (Di Ruscio's ss2ocf and Stoustrup's procedure).
    Canonical(canonical::Args),
    /// Observer gain for a desired polynomial, exact, with the float path checked.
    Gain(gain::Args),
    /// State feedback on its own: controllability, the gain by duality (exact derivation), u = Fx or u = −Kx.
    Feedback(feedback::Args),
    /// Discrete-time observer: prediction or current estimator, dead-beat, poles from z = e^(sT).
    Discrete(discrete::Args),
    /// A continuous plant sampled with a zero-order hold (exact for nilpotent A).
    Zoh(discrete::ZohArgs),
    /// The discrete-time steady-state Kalman filter (Riccati equation by doubling, checked, exact when rational).
    Dlqe(discrete::DlqeArgs),
    /// Reduced-order observer (Gopinath): only the n − p unmeasured states, error polynomial of degree n − p.
    Reduced(reduced::Args),
    /// Observer for an unobservable pair: detectability, the observable part placed exactly, the fixed poles named.
    Detectable(reduced::DetectableArgs),
    /// Observer-based control: separation principle, controller and closed-loop transfer functions.
    Control(control::Args),
    /// Multi-output gains chosen by optimality: minimum norm (J1) or minimal dynamical error (J2).
    Optimal(optimal::Args),
    /// Kalman filter versus chosen poles: noise let through, bandwidth, weighted-derivative observer.
    Kalman(kalman::Args),
    /// Perfect (descriptor) observer: construction, reconstruction formula, robustness conditions.
    Perfect(perfect::Args),
    /// Simulate a worked example's scenarios (its figures): SVG, CSV and the figures' claims checked.
    #[cfg(feature = "plot")]
    Simulate(simulate::Args),
    /// Check a student's answers to an exercise: per part ✔/✘ with the mistake named.
    Check(exercise::CheckArgs),
    /// Grade a folder of submissions into a CSV report (and feedback files).
    Grade(exercise::GradeArgs),
    /// Exercises: generate new ones.
    Exercise(exercise::ExerciseArgs),
}

impl Command {
    /// The command's name (the subcommand of `owb`, the `"command"` of a JSON request).
    pub fn name(&self) -> &'static str {
        match self {
            Command::Verify(_) => "verify",
            Command::Observe(_) => "observe",
            Command::Canonical(_) => "canonical",
            Command::Gain(_) => "gain",
            Command::Feedback(_) => "feedback",
            Command::Discrete(_) => "discrete",
            Command::Zoh(_) => "zoh",
            Command::Dlqe(_) => "dlqe",
            Command::Reduced(_) => "reduced",
            Command::Detectable(_) => "detectable",
            Command::Control(_) => "control",
            Command::Optimal(_) => "optimal",
            Command::Kalman(_) => "kalman",
            Command::Perfect(_) => "perfect",
            #[cfg(feature = "plot")]
            Command::Simulate(_) => "simulate",
            Command::Check(_) => "check",
            Command::Grade(_) => "grade",
            Command::Exercise(_) => "exercise",
        }
    }

    /// Whether the command computes from its request alone, reading and writing no file (what
    /// the browser runs and what the command fuzz target explores). `exercise new` writes a
    /// file only when asked (`out`), which [`Command::writes_files`] tells.
    pub fn in_memory(&self) -> bool {
        Command::IN_MEMORY.contains(&self.name())
    }

    /// The plant's A and C (or transfer function) of the request, for the commands that take
    /// one.
    pub fn system(&self) -> Option<&args::SystemPair> {
        match self {
            Command::Observe(a) => Some(&a.system),
            Command::Canonical(a) => Some(&a.system),
            Command::Gain(a) => Some(&a.system),
            Command::Discrete(a) => Some(&a.system),
            Command::Reduced(a) => Some(&a.system),
            Command::Detectable(a) => Some(&a.system),
            Command::Control(a) => Some(&a.system),
            Command::Optimal(a) => Some(&a.system),
            Command::Kalman(a) => Some(&a.system),
            Command::Perfect(a) => Some(&a.system),
            #[cfg(feature = "plot")]
            Command::Simulate(_) => None,
            Command::Verify(_)
            | Command::Feedback(_)
            | Command::Zoh(_)
            | Command::Dlqe(_)
            | Command::Check(_)
            | Command::Grade(_)
            | Command::Exercise(_) => None,
        }
    }

    /// Whether this request would write a file (`exercise new --out`).
    pub fn writes_files(&self) -> bool {
        match self {
            Command::Exercise(e) => e.writes_file(),
            #[cfg(feature = "plot")]
            Command::Simulate(s) => s.svg.is_some() || s.csv.is_some(),
            Command::Grade(_) => true,
            Command::Verify(v) => v.errata.is_some(),
            Command::Observe(_)
            | Command::Canonical(_)
            | Command::Gain(_)
            | Command::Feedback(_)
            | Command::Discrete(_)
            | Command::Zoh(_)
            | Command::Dlqe(_)
            | Command::Reduced(_)
            | Command::Detectable(_)
            | Command::Control(_)
            | Command::Optimal(_)
            | Command::Kalman(_)
            | Command::Perfect(_)
            | Command::Check(_) => false,
        }
    }

    /// The names of the commands that compute in memory ([`Command::in_memory`]).
    pub const IN_MEMORY: [&'static str; 14] = [
        "observe",
        "canonical",
        "gain",
        "control",
        "optimal",
        "kalman",
        "perfect",
        "exercise",
        "feedback",
        "discrete",
        "zoh",
        "reduced",
        "detectable",
        "dlqe",
    ];

    /// A request from JSON: `{"command": NAME, key: value…}`, the keys named as the command
    /// line's flags (`"a"`, `"poles"`, `"input-noise"`). An unknown key is refused, naming it.
    ///
    /// # Errors
    ///
    /// Malformed JSON, an unknown command, a missing or unknown key, a value of the wrong type.
    pub fn from_json(text: &str) -> Result<Command, RequestError> {
        let value: serde_json::Value =
            serde_json::from_str(text).map_err(|e| RequestError(format!("not JSON: {e}")))?;
        Command::from_value(&value)
    }

    /// [`Command::from_json`] for a parsed value.
    ///
    /// # Errors
    ///
    /// As [`Command::from_json`].
    pub fn from_value(value: &serde_json::Value) -> Result<Command, RequestError> {
        let object = value
            .as_object()
            .ok_or_else(|| RequestError("a request is a JSON object".into()))?;
        let name = object
            .get("command")
            .and_then(serde_json::Value::as_str)
            .ok_or_else(|| {
                RequestError(format!(
                    "the request names no \"command\" (one of: {})",
                    Command::IN_MEMORY.join(", ")
                ))
            })?;
        let command: Command = serde_json::from_value(value.clone())
            .map_err(|e| RequestError(format!("in the {name} request: {e}")))?;
        // every key given must be one the command reads (a misspelt key is not ignored)
        let known = serde_json::to_value(&command).unwrap_or_default();
        unknown_keys(value, &known, name)?;
        Ok(command)
    }

    /// A request from a command line's words (after `owb`), as the command line reads it —
    /// for front ends whose requests are written as command lines (the book's `run` directive).
    ///
    /// # Errors
    ///
    /// clap's message for a refused command line.
    #[cfg(feature = "commands")]
    pub fn from_words<S: AsRef<str>>(words: &[S]) -> Result<Command, RequestError> {
        #[derive(clap::Parser)]
        #[command(name = "owb")]
        struct Words {
            #[command(subcommand)]
            command: Command,
        }
        let argv = std::iter::once("owb").chain(words.iter().map(AsRef::as_ref));
        <Words as clap::Parser>::try_parse_from(argv)
            .map(|w| w.command)
            .map_err(|e| RequestError(e.render().to_string()))
    }
}

/// Keys of `given` (an object, recursively) that `known` (the same request written back) does
/// not have.
fn unknown_keys(
    given: &serde_json::Value,
    known: &serde_json::Value,
    at: &str,
) -> Result<(), RequestError> {
    if let (Some(g), Some(k)) = (given.as_object(), known.as_object()) {
        for (key, value) in g {
            match k.get(key) {
                None => {
                    let mut names: Vec<&str> = k
                        .keys()
                        .map(String::as_str)
                        .filter(|n| *n != "command")
                        .collect();
                    names.sort_unstable();
                    return Err(RequestError(format!(
                        "in the {at} request: unknown key \"{}\" (known: {})",
                        crate::files::escape_untrusted(key),
                        names.join(", ")
                    )));
                }
                Some(inner) => unknown_keys(value, inner, at)?,
            }
        }
    }
    Ok(())
}

/// A request that could not be read (malformed JSON, an unknown key, a refused command line).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct RequestError(pub String);

/// Runs one command.
///
/// # Errors
///
/// What the command refuses (bad input, an impossible design, an unreadable file), with what it
/// had reported before.
pub fn run(command: Command) -> Result<Report, Failure> {
    run_keeping(command, Keep::Everything)
}

/// [`run`] for a front end that shows the report's text only (the command line): the same
/// text, without the JSON value and the steps beside it ([`Keep::Text`]).
///
/// # Errors
///
/// As [`run`].
pub fn run_text(command: Command) -> Result<Report, Failure> {
    run_keeping(command, Keep::Text)
}

fn run_keeping(command: Command, keep: Keep) -> Result<Report, Failure> {
    let mut report = Report::default();
    // a plant given as a transfer function: the report states its realisation
    let realisation = match command.system().map(args::SystemPair::realisation) {
        Some(Ok(r)) => r,
        Some(Err(error)) => {
            return Err(Failure {
                error,
                partial: report,
            })
        }
        None => None,
    };
    // a realisation is added to the JSON value once the command has written it: kept whole
    report.keep = match realisation {
        Some(_) => Keep::Everything,
        None => keep,
    };
    let rep = &mut report;
    let result = match command {
        Command::Verify(a) => verify::run(a, rep),
        Command::Observe(a) => observe::run(a, rep),
        Command::Canonical(a) => canonical::run(a, rep),
        Command::Gain(a) => gain::run(a, rep),
        Command::Feedback(a) => feedback::run(a, rep),
        Command::Control(a) => control::run(a, rep),
        Command::Discrete(a) => discrete::run(a, rep),
        Command::Zoh(a) => discrete::zoh(a, rep),
        Command::Dlqe(a) => discrete::dlqe(a, rep),
        Command::Reduced(a) => reduced::run(a, rep),
        Command::Detectable(a) => reduced::detectable(a, rep),
        Command::Optimal(a) => optimal::run(a, rep),
        Command::Kalman(a) => kalman::run(a, rep),
        Command::Perfect(a) => perfect::run(a, rep),
        #[cfg(feature = "plot")]
        Command::Simulate(a) => simulate::run(a, rep),
        Command::Check(a) => exercise::check(a, rep),
        Command::Grade(a) => exercise::grade(a, rep),
        Command::Exercise(a) => exercise::exercise(a, rep),
    };
    if let (Ok(_), Some(r)) = (&result, &realisation) {
        match report.json.take() {
            // the JSON answer carries it as one more key
            Some(mut v) => {
                if let Some(o) = v.as_object_mut() {
                    o.insert("realisation".into(), r.json());
                }
                report.text.clear();
                report.json(v);
            }
            // the text opens with it
            None => report.text.insert_str(0, &r.describe()),
        }
    }
    match result {
        Ok(outcome) => {
            report.outcome = outcome;
            Ok(report)
        }
        Err(error) => Err(Failure {
            error,
            partial: report,
        }),
    }
}
