//! `owb`, the observer workbench's command line (feature `cli`, on by default). One file per
//! subcommand: parse the flags, call the library, render. The binary `src/bin/owb.rs` calls
//! [`main`]; the book preprocessor and the CLI fuzz target call [`run_captured`], which runs the
//! same code with the report captured in a string. Exit codes: 0 success, 1 a verification found
//! a mismatch (or a check found a wrong answer), 2 bad input (malformed numbers, mismatched
//! dimensions, an unobservable pair…).
//!
//! ```
//! use observer_workbench::cli::{run_captured, Outcome};
//! let (outcome, report) = run_captured(&["observe", "--a", "[0 1; -2 -3]", "--c", "[1 0]"]);
//! assert!(matches!(outcome, Ok(Outcome::Ok)));
//! assert!(report.contains("observable"));
//! ```

#[macro_use]
mod output;

mod args;
mod canonical;
mod control;
mod discrete;
mod exercise;
mod feedback;
mod gain;
mod kalman;
mod observe;
mod optimal;
mod perfect;
mod progress;
mod reduced;
#[cfg(feature = "cli")]
mod simulate;
mod verify;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// The command line: one subcommand.
#[derive(Parser)]
#[command(
    name = "owb",
    version,
    about = "Exact design and verification of state observers"
)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands of `owb`.
#[derive(Subcommand)]
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
    #[cfg(feature = "cli")]
    Simulate(simulate::Args),
    /// Check a student's answers to an exercise: per part ✔/✘ with the mistake named.
    Check(exercise::CheckArgs),
    /// Grade a folder of submissions into a CSV report (and feedback files).
    Grade(exercise::GradeArgs),
    /// Exercises: generate new ones.
    Exercise(exercise::ExerciseArgs),
}

/// The subcommands that compute from their flags alone, reading and writing no file (but
/// `exercise new --out`): what the browser runs and what the CLI fuzz target explores.
pub const IN_MEMORY_SUBCOMMANDS: [&str; 14] = [
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

/// What a subcommand reports back.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    /// All good.
    Ok,
    /// A verification or check found something wrong.
    Failed,
}

/// Whether a panic is `println!` finding its reader gone (`owb verify | head -1`).
fn is_closed_output(info: &std::panic::PanicHookInfo<'_>) -> bool {
    let payload = info.payload();
    let text = payload
        .downcast_ref::<String>()
        .map(String::as_str)
        .or_else(|| payload.downcast_ref::<&str>().copied())
        .unwrap_or("");
    text.starts_with("failed printing to std") && text.contains("Broken pipe")
}

/// Whether the command line asked for `--json`.
fn json_requested() -> bool {
    std::env::args().skip(1).any(|a| a == "--json")
}

/// Runs a parsed command line, its report going to the current output.
///
/// # Errors
///
/// Whatever the subcommand refuses: bad input, an impossible design, an unreadable file.
pub fn dispatch(command: Command) -> anyhow::Result<Outcome> {
    match command {
        Command::Verify(a) => verify::run(a),
        Command::Observe(a) => observe::run(a),
        Command::Canonical(a) => canonical::run(a),
        Command::Gain(a) => gain::run(a),
        Command::Feedback(a) => feedback::run(a),
        Command::Control(a) => control::run(a),
        Command::Discrete(a) => discrete::run(a),
        Command::Zoh(a) => discrete::zoh(a),
        Command::Dlqe(a) => discrete::dlqe(a),
        Command::Reduced(a) => reduced::run(a),
        Command::Detectable(a) => reduced::detectable(a),
        Command::Optimal(a) => optimal::run(a),
        Command::Kalman(a) => kalman::run(a),
        Command::Perfect(a) => perfect::run(a),
        #[cfg(feature = "cli")]
        Command::Simulate(a) => simulate::run(a),
        Command::Check(a) => exercise::check(a),
        Command::Grade(a) => exercise::grade(a),
        Command::Exercise(a) => exercise::exercise(a),
    }
}

/// Runs `owb` with these arguments (without the program name) and returns the outcome with
/// the report it printed. A command line clap refuses is an error whose text is clap's message.
pub fn run_captured<S: AsRef<str>>(args: &[S]) -> (anyhow::Result<Outcome>, String) {
    let argv = std::iter::once("owb").chain(args.iter().map(AsRef::as_ref));
    match Cli::try_parse_from(argv) {
        Ok(cli) => output::capture(|| dispatch(cli.command)),
        Err(e) => (Err(anyhow::anyhow!("{}", e.render())), String::new()),
    }
}

/// The program `owb`: parses the process's arguments, runs, prints errors, returns the status.
pub fn main() -> ExitCode {
    // A closed output ends the program quietly, with the status a shell gives a process
    // stopped by SIGPIPE (128 + 13), instead of a panic message.
    let default_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        if is_closed_output(info) {
            std::process::exit(141);
        }
        default_hook(info);
    }));
    if let Err(e) = output::standard_output_open() {
        eprintln!("error: {e}");
        return ExitCode::from(2);
    }
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if e.use_stderr() && json_requested() => {
            // a script asked for JSON: a refused command line is the same JSON object as
            // any other refusal
            let text = crate::files::escape_untrusted(&e.render().to_string());
            let first = text.lines().next().unwrap_or_default();
            let message = first.strip_prefix("error: ").unwrap_or(first).to_string();
            let causes: Vec<String> = text
                .lines()
                .skip(1)
                .map(str::trim)
                .filter(|l| !l.is_empty())
                .map(String::from)
                .collect();
            outln!(
                "{}",
                serde_json::json!({"error": message, "causes": causes, "exit_status": 2})
            );
            eprintln!("{text}");
            return match output::finish() {
                Ok(()) => ExitCode::from(2),
                Err(std::io::ErrorKind::BrokenPipe) => ExitCode::from(141),
                Err(_) => ExitCode::from(2),
            };
        }
        Err(e) => e.exit(),
    };
    let result = dispatch(cli.command);
    let status = report(result);
    // what was written must have arrived: a full disk or a closed standard output is an
    // error with a non-zero status, a reader gone away the status of SIGPIPE
    match output::finish() {
        Ok(()) => status,
        Err(std::io::ErrorKind::BrokenPipe) => ExitCode::from(141),
        Err(kind) => {
            eprintln!(
                "error: writing standard output failed ({}): the report is incomplete",
                std::io::Error::from(kind)
            );
            ExitCode::from(2)
        }
    }
}

/// The status of a finished command, its error printed (as JSON too when asked).
fn report(result: anyhow::Result<Outcome>) -> ExitCode {
    // an error may quote what the user typed: nothing invisible reaches the terminal or a script
    let safe = |t: String| crate::files::escape_untrusted(&t);
    match result {
        Ok(Outcome::Ok) => ExitCode::SUCCESS,
        Ok(Outcome::Failed) => ExitCode::from(1),
        Err(e) if json_requested() => {
            // a script asked for JSON: it gets a JSON error object (and the status)
            let causes: Vec<String> = e.chain().skip(1).map(|c| safe(c.to_string())).collect();
            outln!(
                "{}",
                serde_json::json!({"error": safe(e.to_string()), "causes": causes, "exit_status": 2})
            );
            eprintln!("error: {}", safe(e.to_string()));
            ExitCode::from(2)
        }
        Err(e) => {
            eprintln!("error: {}", safe(e.to_string()));
            for cause in e.chain().skip(1) {
                eprintln!("  caused by: {}", safe(cause.to_string()));
            }
            ExitCode::from(2)
        }
    }
}
