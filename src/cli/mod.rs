//! `owb`, the observer workbench's command line (feature `cli`, on by default): the process's
//! arguments parsed into an [`api::Command`] (clap), the command run by
//! [`api::run`], its report printed. Exit codes: 0 success, 1 a verification
//! found a mismatch (or a check found a wrong answer), 2 bad input (malformed numbers,
//! mismatched dimensions, an unobservable pair…).

#[macro_use]
mod output;
#[cfg(unix)]
mod alarm;
#[cfg(target_os = "linux")]
mod large_pages;
#[cfg(target_os = "linux")]
pub use large_pages::LargePages;

use crate::api::{self, Command, Outcome};
use clap::Parser;
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
    /// Stop a computation running longer than this, with an error (0: no limit)
    ///
    /// Exact work grows fast with the order of the system and the size of its numbers: a command
    /// past this many seconds stops with an error naming this limit instead of running for
    /// minutes. Commands that write files (grade, --csv, --svg, --out, --errata) always run to
    /// the end; `optimal` gets its own --time-limit on top.
    #[arg(long, global = true, allow_hyphen_values = true, value_name = "SECONDS", default_value_t = DEFAULT_TIME_BUDGET)]
    pub time_budget: f64,
}

/// The default of `--time-budget`, in seconds.
pub const DEFAULT_TIME_BUDGET: f64 = 10.0;

/// The stack of the thread that watches a command's time budget where there is no alarm (it
/// only sleeps and prints).
#[cfg(not(unix))]
const WATCHDOG_STACK: usize = 64 << 10;

/// Why a command did not finish.
#[derive(Debug, thiserror::Error)]
pub enum Stopped {
    /// The time budget ran out.
    #[error("stopped after {0} s, the time budget (--time-budget SECONDS raises it, 0 removes it): the computation grows fast with the order of the system and the size of its numbers; the README's \"Commands\" section says what each command finishes within 10 s")]
    TimeBudget(f64),
    /// The budget given is not a number of seconds.
    #[error("in --time-budget: {0} is not a number of seconds from 0 (no limit) to 86400")]
    BadBudget(f64),
    /// The alarm (or thread) watching the time budget could not start.
    #[error("the command could not be started (its time budget could not be watched): {0}")]
    Spawn(std::io::Error),
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

/// Runs a command within a time budget (seconds, 0 for none): on this thread, watched by an
/// alarm ([`watch`]) that ends the process with the budget's error when the budget runs out
/// first. A command that writes files runs to the end unwatched, so that no half-written file
/// is left.
///
/// The command keeps the main thread (its caches warm, no stack of its own to fault in): a
/// worker thread for the command cost about 0.15 ms of CPU per process, as much as a whole
/// 10-state design.
fn run_within(command: Command, budget: f64) -> anyhow::Result<Result<api::Report, api::Failure>> {
    if !(budget.is_finite() && (0.0..=86_400.0).contains(&budget)) {
        return Err(Stopped::BadBudget(budget).into());
    }
    if budget == 0.0 || command.writes_files() {
        return Ok(api::run_text(command));
    }
    // optimal's search has its own limit: the budget comes on top of it
    let budget = match &command {
        Command::Optimal(a) if a.time_limit.is_finite() && a.time_limit > 0.0 => {
            budget + a.time_limit.min(86_400.0)
        }
        _ => budget,
    };
    watch(budget)?;
    let result = api::run_text(command);
    if !Race::claim(Race::Finished) {
        // the budget ran out first: the watchdog is printing its error and ends the process
        loop {
            std::thread::park();
        }
    }
    #[cfg(unix)]
    alarm::disarm();
    Ok(result)
}

/// Starts watching the time budget: on Unix an alarm (the kernel's timer and a signal
/// handler, [`alarm`]), elsewhere a thread that sleeps. Either ends the process with the
/// budget's error — [`Ending`]'s, as a finished command's error path prints it — when the
/// budget runs out before the command claims its end.
fn watch(budget: f64) -> anyhow::Result<()> {
    #[cfg(unix)]
    {
        let ending = Ending::of(Err(Stopped::TimeBudget(budget).into()));
        alarm::arm(budget, ending.out, ending.err).map_err(Stopped::Spawn)?;
    }
    #[cfg(not(unix))]
    {
        std::thread::Builder::new()
            .name("owb-watchdog".into())
            .stack_size(WATCHDOG_STACK)
            .spawn(move || {
                std::thread::sleep(std::time::Duration::from_secs_f64(budget));
                if Race::claim(Race::TimedOut) {
                    let _ = report(Err(Stopped::TimeBudget(budget).into()));
                    std::process::exit(match output::finish() {
                        Err(std::io::ErrorKind::BrokenPipe) => 141,
                        Ok(()) | Err(_) => 2,
                    });
                }
            })
            .map_err(Stopped::Spawn)?;
    }
    Ok(())
}

/// Who ends a watched command: it finishing, or its budget running out. The first to claim
/// wins, so that a report and the budget's error are never both printed.
#[derive(Clone, Copy)]
#[repr(u8)]
enum Race {
    Finished = 1,
    TimedOut = 2,
}

impl Race {
    /// Claims the end of the command for `who`: true when no one had.
    fn claim(who: Race) -> bool {
        static WINNER: std::sync::atomic::AtomicU8 = std::sync::atomic::AtomicU8::new(0);
        WINNER
            .compare_exchange(
                0,
                who as u8,
                std::sync::atomic::Ordering::SeqCst,
                std::sync::atomic::Ordering::SeqCst,
            )
            .is_ok()
    }
}

/// Runs a parsed command: its report printed (warnings on standard error), its outcome
/// returned. A failure's partial report is printed before the error.
fn dispatch(command: Command, budget: f64) -> anyhow::Result<Outcome> {
    let print = |r: &api::Report| {
        out!("{}", r.text);
        for w in &r.warnings {
            eprintln!("{w}");
        }
    };
    match run_within(command, budget)? {
        Ok(report) => {
            print(&report);
            Ok(report.outcome)
        }
        Err(failure) => {
            print(&failure.partial);
            Err(failure.error)
        }
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
    let result = dispatch(cli.command, cli.time_budget);
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
    let ending = Ending::of(result);
    out!("{}", ending.out);
    eprint!("{}", ending.err);
    ExitCode::from(ending.status)
}

/// What a finished command prints after its report, and its status.
struct Ending {
    /// For standard output: the error as a JSON object when `--json` was asked, else nothing.
    out: String,
    /// For standard error: the error and its causes.
    err: String,
    /// 0 success, 1 a mismatch found, 2 an error.
    status: u8,
}

impl Ending {
    fn of(result: anyhow::Result<Outcome>) -> Ending {
        // an error may quote what the user typed: nothing invisible reaches the terminal or a
        // script
        let safe = |t: String| crate::files::escape_untrusted(&t);
        let ending = |out: String, err: String, status: u8| Ending { out, err, status };
        match result {
            Ok(Outcome::Ok) => ending(String::new(), String::new(), 0),
            Ok(Outcome::Failed) => ending(String::new(), String::new(), 1),
            Err(e) if json_requested() => {
                // a script asked for JSON: it gets a JSON error object (and the status)
                let causes: Vec<String> = e.chain().skip(1).map(|c| safe(c.to_string())).collect();
                // the message made safe once, for both streams (the time budget's ending is made
                // in advance by every command)
                let message = safe(e.to_string());
                let err = format!("error: {message}\n");
                let json =
                    serde_json::json!({"error": message, "causes": causes, "exit_status": 2});
                ending(format!("{json}\n"), err, 2)
            }
            Err(e) => {
                let mut err = format!("error: {}\n", safe(e.to_string()));
                for cause in e.chain().skip(1) {
                    err.push_str(&format!("  caused by: {}\n", safe(cause.to_string())));
                }
                ending(String::new(), err, 2)
            }
        }
    }
}
