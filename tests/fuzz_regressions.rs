//! Every input a fuzzing campaign ever flagged (crash or timeout), replayed on stable through the
//! same entry points the fuzz targets call (`observer_workbench::fuzzing`). The campaigns run by
//! hand (README, "Fuzzing"); their findings live in `fuzz/regressions/<target>/`.

use std::path::Path;

fn replay(target: &str, run: fn(&[u8])) -> usize {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("fuzz/regressions")
        .join(target);
    let mut count = 0;
    for entry in std::fs::read_dir(&dir).expect("regression folder") {
        let path = entry.expect("entry").path();
        if path
            .file_name()
            .is_some_and(|n| n.to_string_lossy().starts_with('.'))
        {
            continue;
        }
        let data = std::fs::read(&path).expect("readable");
        let start = std::time::Instant::now();
        run(&data);
        // the campaigns flag an input past 1 s in an optimised build with debug assertions;
        // replayed here (opt-level 1, a loaded machine) each must still end well within the
        // commands' default time budget
        let took = start.elapsed();
        assert!(
            took < std::time::Duration::from_secs(5),
            "{} took {took:?}",
            path.display()
        );
        count += 1;
    }
    count
}

#[test]
fn syntax_findings_are_refused_quickly() {
    // `s^4 s^499` took 0.4 s (a product of powers grew without bound): now a degree limit;
    // `2(s--poles+6+s6)^26` took 2.6 s (a gcd per product term): multiplication now fraction-free
    // `(33848^-845 - s + 263 - 12)^111` built 1.4 Mbit coefficients: powers of transfer functions
    // now bound the size of the coefficients they build
    // `(s--dir+21.72e-86)^53--chin10` (session 10) did 170 000 products of coefficients of up to
    // 16 000 bits, 1.3 s: the work bound now weighs each product by the coefficients' size
    assert!(replay("syntax", observer_workbench::fuzzing::syntax) >= 1);
}

#[test]
fn answer_file_findings_are_checked() {
    // `-0/-11110131761244566941^231/…` (session 10) kept the value 0 through divisions by
    // 15 000-bit powers, 1.4 s: numbers are now raised without a gcd per squaring, a rational
    // divisor in Q(√d) is inverted without its norm, and an expression's arithmetic on large
    // numbers is bounded as a whole
    assert!(replay("answers", observer_workbench::fuzzing::answers) >= 1);
}

#[test]
fn command_line_findings_end() {
    // `optimal --index j2` with its default 40 starts ran past the campaign's 1 s: the target
    // now bounds the work an input asks for by counts (see `fuzzing::cli`)
    // `observe` with ten parameters in A (session 10, 1.35 s) factored det O_n outside the
    // symbolic work budget: every step of a command with parameters now spends from one budget
    assert!(replay("cli", observer_workbench::fuzzing::cli) >= 1);
    replay("book", observer_workbench::fuzzing::book);
}

#[test]
fn exercise_and_example_findings_are_read() {
    replay("exercise", observer_workbench::fuzzing::exercise);
    replay(
        "worked_example",
        observer_workbench::fuzzing::worked_example,
    );
}

/// Garbage never panics, for every entry point (a property, beside the campaign's corpus).
mod garbage {
    use proptest::prelude::*;
    proptest! {
        #![proptest_config(ProptestConfig::with_cases(200))]
        #[test]
        fn never_panics(data in proptest::collection::vec(any::<u8>(), 0..200), text in "[-+*/^()\\[\\];, 0-9sk√.ie]{0,60}") {
            observer_workbench::fuzzing::syntax(&data);
            observer_workbench::fuzzing::syntax(text.as_bytes());
            observer_workbench::fuzzing::answers(format!("[answers]\nL = \"{text}\"\ndesired = \"{text}\"\n").as_bytes());
            observer_workbench::fuzzing::worked_example(&data);
            observer_workbench::fuzzing::exercise(&data);
            observer_workbench::fuzzing::cli(&data);
            observer_workbench::fuzzing::book(&data);
        }
    }
}

/// The command target reaches `grade` too, confined to its private folder: the request's own
/// folder and report names are replaced, the class in that folder is graded and its report
/// written there (and nowhere the input named).
#[test]
fn command_target_grades_in_its_private_folder() {
    let index = observer_workbench::fuzzing::CLI_SUBCOMMANDS
        .iter()
        .position(|s| *s == "grade")
        .expect("grade is a fuzzed subcommand");
    let mut input = vec![u8::try_from(index).unwrap()];
    input.extend_from_slice(b"stoustrup-pole-assignment\nelsewhere\n--csv\nnot-here.csv");
    observer_workbench::fuzzing::cli(&input);
    assert!(!Path::new("elsewhere").exists() && !Path::new("not-here.csv").exists());
    let folder = std::env::temp_dir().join(format!("owb-fuzz-grade-{}", std::process::id()));
    let report = std::fs::read_to_string(folder.join("report.csv")).expect("the report is written");
    assert!(report.contains("ada") && report.contains("bob"), "{report}");
    // the formula a student named themselves is not a live cell
    assert!(!report.contains(",=HYPERLINK"), "{report}");
    let _ = std::fs::remove_dir_all(folder);
}
