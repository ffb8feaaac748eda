//! Entry points for coverage-guided fuzzing (`fuzz/`, cargo fuzz with libFuzzer) and for
//! replaying what the campaigns found (`tests/fuzz_regressions.rs`, on stable).
//!
//! Each function takes arbitrary bytes and must return — no panic, no stack overflow, no hang —
//! whatever they are: the text entry points of the workbench (numbers, matrices, polynomials and
//! transfer functions; answer files checked against an exercise; exercise files turned into an
//! answer key; worked-example files). The fuzz targets and the regression test call the same
//! functions, so a crash found by a campaign is replayed exactly.

use crate::algebra::{MultiPoly, Quadratic, Rational};
use crate::exercise::{answer_key, check_answers, AnswerKey};
use crate::syntax::{
    parse_list, parse_matrix, parse_polynomial, parse_rational_function, parse_scalar,
};
use std::path::Path;

/// Every parser of the syntax module on the same text.
pub fn syntax(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let _ = parse_scalar::<Rational>(&text);
    let _ = parse_scalar::<Quadratic>(&text);
    let _ = parse_scalar::<MultiPoly>(&text);
    let _ = parse_scalar::<f64>(&text);
    // the matrix flags' scanner answers only where the full parser gives the same matrix
    let full = parse_matrix::<Rational>(&text);
    assert_eq!(
        crate::syntax::parse_rational_matrix(&text).ok(),
        full.ok(),
        "the scanner and the parser disagree on {text:?}"
    );
    let _ = parse_matrix::<Quadratic>(&text);
    let _ = parse_list::<Quadratic>(&text);
    let _ = parse_polynomial::<Rational>(&text, "s");
    let _ = parse_polynomial::<Quadratic>(&text, "s");
    let _ = parse_rational_function::<Rational>(&text, "s");
}

/// The exercise every answer is checked against: Stoustrup's pole assignment (gain, canonical
/// form, polynomials — most of the diagnoses).
fn stoustrup_key() -> Option<&'static AnswerKey> {
    static KEY: std::sync::OnceLock<Option<AnswerKey>> = std::sync::OnceLock::new();
    KEY.get_or_init(|| {
        let raw = include_str!("../worked_examples/exercises/stoustrup-pole-assignment.toml");
        let path = Path::new("stoustrup-pole-assignment.toml");
        let ex = crate::exercise::format::parse_exercise(path, raw).ok()?;
        answer_key("stoustrup-pole-assignment.toml", &ex).ok()
    })
    .as_ref()
}

/// An answer file, read and checked (the code `owb check` and the browser run).
pub fn answers(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let Ok(answers) = crate::exercise::format::parse_answers(Path::new("answers.toml"), &text)
    else {
        return;
    };
    if let Some(key) = stoustrup_key() {
        let report = check_answers(key, &answers, "fuzz");
        let _ = report.text();
    }
}

/// An exercise file, read and turned into an answer key.
pub fn exercise(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    if let Ok(ex) = crate::exercise::format::parse_exercise(Path::new("exercise.toml"), &text) {
        let _ = answer_key("exercise.toml", &ex);
    }
}

/// A worked-example file, read and checked (not verified: verification runs optimisations whose
/// cost the file chooses, bounded separately).
pub fn worked_example(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let _ = crate::worked::parse_example("example.toml", &text);
}

/// The subcommands whose argument sets the `cli` target explores: every one. First those that
/// compute from their flags alone ([`crate::api::Command::in_memory`]), then `verify`,
/// `simulate` and `check`, which read files: there every argument naming a path is dropped and
/// every flag that writes (`--out`, `--svg`, `--csv`, `--errata`, `--feedback`) with its value,
/// so a campaign reads only the working folder's files and writes none. Last `grade`, which
/// always writes its CSV report: its flags are explored as given, but the folder it grades and
/// the files it writes are moved into a private temporary folder.
#[cfg(feature = "cli")]
pub const CLI_SUBCOMMANDS: [&str; 18] = {
    // the in-memory commands first (the corpora's first bytes name them), then the readers
    let mut all = [""; 18];
    let mut i = 0;
    while i < crate::api::Command::IN_MEMORY.len() {
        all[i] = crate::api::Command::IN_MEMORY[i];
        i += 1;
    }
    all[14] = "verify";
    all[15] = "simulate";
    all[16] = "check";
    all[17] = "grade";
    all
};

/// The private folder `grade` works in during a campaign: `submissions/` holds a right answer, a
/// wrong one, a student id with a formula and invisible characters, and an unreadable file;
/// the report and the feedback files are written beside it. Made once per process.
#[cfg(feature = "cli")]
fn grading_folder() -> Option<&'static Path> {
    static DIR: std::sync::OnceLock<Option<std::path::PathBuf>> = std::sync::OnceLock::new();
    DIR.get_or_init(|| {
        let dir = std::env::temp_dir().join(format!("owb-fuzz-grade-{}", std::process::id()));
        let submissions = dir.join("submissions");
        std::fs::create_dir_all(&submissions).ok()?;
        let files = [
            (
                "ada.toml",
                "student = \"ada\"\n[answers]\nL = \"[-6; -12]\"\n",
            ),
            (
                "bob.toml",
                "student = \"bob\"\n[answers]\nL = \"[6; 12]\"\n",
            ),
            (
                "eve.toml",
                "student = \"=HYPERLINK(1)\\u202e\"\n[answers]\nL = \"[1;\\u00072]\"\n",
            ),
            ("bad.toml", "[answers\nL = "),
        ];
        for (name, text) in files {
            std::fs::write(submissions.join(name), text).ok()?;
        }
        Some(dir)
    })
    .as_deref()
}

/// A `grade` request moved into the campaign's private folder: the submissions graded are
/// [`grading_folder`]'s, the report and feedback go there.
#[cfg(feature = "cli")]
fn confined(command: crate::api::Command) -> Option<crate::api::Command> {
    match command {
        crate::api::Command::Grade(mut g) => {
            let dir = grading_folder()?;
            g.submissions = dir.join("submissions");
            g.csv = dir.join("report.csv");
            if g.feedback.is_some() {
                g.feedback = Some(dir.join("feedback"));
            }
            Some(crate::api::Command::Grade(g))
        }
        other => (!other.writes_files()).then_some(other),
    }
}

/// The flags that make a command write a file: dropped (with their value) from campaign inputs.
#[cfg(feature = "cli")]
const WRITING_FLAGS: [&str; 5] = ["--out", "--svg", "--csv", "--errata", "--feedback"];

/// The most work a campaign input may ask for by its counts: seeded starts of `optimal`
/// (40 by default, each a full local optimisation of up to 20 000 evaluations of J2, up to
/// 0.2 s on a third-order system) and grid
/// points of `kalman`'s weighted design. The campaign explores what the arguments *say*; how
/// much work a user may ask for is bounded by the CLI's own limits (`--starts` ≤ 10 000,
/// `--grid` ≤ 100 000), which tests check separately.
#[cfg(feature = "cli")]
fn bound_requested_work(args: &mut Vec<String>) {
    const COUNTS: [(&str, &str, usize); 2] = [("optimal", "--starts", 1), ("kalman", "--grid", 50)];
    let clamp = |v: &str, most: usize| match v.trim().parse::<usize>() {
        Ok(n) if n > most => most.to_string(),
        _ => v.to_string(),
    };
    for (subcommand, flag, most) in COUNTS {
        let joined = format!("{flag}=");
        let mut given = false;
        let mut value_next = false;
        for arg in args.iter_mut() {
            if std::mem::take(&mut value_next) {
                *arg = clamp(arg, most);
            } else if arg == flag {
                given = true;
                value_next = true;
            } else if let Some(v) = arg.strip_prefix(&joined) {
                given = true;
                *arg = format!("{joined}{}", clamp(v, most));
            }
        }
        if args[0] == subcommand && !given {
            args.extend([flag.to_string(), most.to_string()]);
        }
    }
}

/// Builds what the answer and command targets use once, before the campaign's clock runs.
pub fn warm_up() {
    let _ = stoustrup_key();
    #[cfg(feature = "cli")]
    let _ = grading_folder();
}

/// A command line: the first byte picks one of [`CLI_SUBCOMMANDS`], the rest are its arguments,
/// one per line. Arguments that would name a file (a path separator, `--out`) are dropped, so
/// the campaign never writes to the disk. The words are read as the `owb` binary reads them
/// and the request run by the same library function.
#[cfg(feature = "cli")]
pub fn cli(data: &[u8]) {
    let Some((&first, rest)) = data.split_first() else {
        return;
    };
    let sub = CLI_SUBCOMMANDS[usize::from(first) % CLI_SUBCOMMANDS.len()];
    let text = String::from_utf8_lossy(rest);
    let mut args = vec![sub.to_string()];
    let mut skip_value = false;
    for arg in text.split('\n') {
        if std::mem::take(&mut skip_value) {
            continue;
        }
        // grade's writing flags are kept: where they write is moved by `confined`
        if sub != "grade" && WRITING_FLAGS.iter().any(|f| arg.starts_with(f)) {
            // `--out FILE` or `--out=FILE`: not on a campaign's disk
            skip_value = !arg.contains('=');
            continue;
        }
        if arg.contains(['/', '\\']) {
            continue;
        }
        args.push(arg.to_string());
    }
    bound_requested_work(&mut args);
    if let Some(command) = crate::api::Command::from_words(&args)
        .ok()
        .and_then(confined)
    {
        let _ = crate::api::run(command);
    }
}

/// The book preprocessor's input: mdBook's `[context, book]` JSON with `{{#owb …}}` directives
/// in its chapters. The crate root given is empty, so directives that read worked examples or
/// exercises fail quickly, and `run` directives are off (the `cli` target covers commands).
#[cfg(feature = "cli")]
pub fn book(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let root = std::env::temp_dir().join("owb-fuzz-empty-root");
    let _ = crate::book::preprocess_with(&text, Some(&root), false);
}
