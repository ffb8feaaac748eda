//! The observer workbench in the browser. The course book loads this WebAssembly module to check
//! a student's answers in place, to generate each student's own exercise, to run the workbench's
//! commands on a playground page and to verify a worked example — with the same library code as
//! `owb check`, `owb exercise new`, `owb gain` … and `owb verify`, so the browser's feedback is
//! the command line's, word for word.
//!
//! Every function takes and returns strings (JSON out): the page's script stays small and the
//! functions are tested natively (`cargo test -p owb-web`) as well as in a real browser
//! (`book/browser-test/`). Nothing here panics on bad input: every refusal is a JSON
//! `{"error": …}` naming what is wrong and where.

use observer_workbench::cli::{run_captured, Outcome, IN_MEMORY_SUBCOMMANDS};
use observer_workbench::derivation::{Derivation, Step};
use observer_workbench::exercise::check::check_text;
use observer_workbench::exercise::generate::{pole_placement, Kind, Settings};
use observer_workbench::exercise::{answer_key, ExerciseFile};
use observer_workbench::worked::{parse_example, render_table, report_json, verify_example};
use serde_json::{json, Value};
use wasm_bindgen::prelude::wasm_bindgen;

fn error(message: impl std::fmt::Display) -> String {
    json!({ "error": message.to_string() }).to_string()
}

/// The workbench's version (the crate's), to show in the page.
#[wasm_bindgen]
pub fn version() -> String {
    env!("CARGO_PKG_VERSION").to_string()
}

/// Checks answers to an exercise, as `owb check --json` does: `exercise` is the exercise file's
/// TOML, `answers` an answer file's (`[answers]` with one key per part). Returns
/// `{"report": …, "text": …, "read": {part: LaTeX of the answer as read}}` or `{"error": …}`.
#[wasm_bindgen]
pub fn check(exercise: &str, answers: &str) -> String {
    match check_text(("exercise.toml", exercise), ("answers.toml", answers)) {
        Ok(report) => {
            let read: serde_json::Map<String, Value> = parsed_answers(answers)
                .into_iter()
                .map(|(k, v)| (k, Value::String(v)))
                .collect();
            json!({
                "report": report,
                "text": report.text(),
                "all_correct": report.all_correct(),
                "read": read,
            })
            .to_string()
        }
        Err(e) => error(e),
    }
}

/// Each answer as the workbench reads it, in LaTeX (a matrix, a polynomial in s or λ, or a
/// number), for the page to show the student what was understood. Answers that read as none
/// of these are left out (the check's feedback says why).
fn parsed_answers(answers: &str) -> Vec<(String, String)> {
    let Ok(file) = observer_workbench::exercise::format::parse_answers(
        std::path::Path::new("answers.toml"),
        answers,
    ) else {
        return Vec::new();
    };
    file.answers
        .iter()
        .filter_map(|(k, v)| answer_latex(v).map(|l| (k.clone(), l)))
        .collect()
}

/// An answer in LaTeX, as read: a matrix or vector, else a polynomial in s (λ accepted).
fn answer_latex(text: &str) -> Option<String> {
    use observer_workbench::algebra::Quadratic;
    use observer_workbench::syntax::{parse_matrix, parse_polynomial};
    let t = text.trim();
    if t.starts_with('[') {
        return parse_matrix::<Quadratic>(t).ok().map(|m| m.to_latex());
    }
    let in_s = t.replace('λ', "s");
    parse_polynomial::<Quadratic>(&in_s, "s")
        .ok()
        .map(|p| p.to_latex())
}

/// A student's own exercise, as `owb exercise new --kind KIND --student ID --order ORDER
/// --convention C` generates it. Returns `{"id", "command", "toml", "title", "statement", "parts": [{"id",
/// "prompt", "points"}]}` or `{"error": …}`.
#[wasm_bindgen]
pub fn variant(student: &str, order: &str, convention: &str, kind: &str) -> String {
    if student.trim().is_empty() {
        return error("type your student id first");
    }
    let (lo, hi) = match order.split_once("..") {
        Some((l, h)) => (l.trim().parse::<usize>(), h.trim().parse::<usize>()),
        None => (order.trim().parse::<usize>(), order.trim().parse::<usize>()),
    };
    let (Ok(lo), Ok(hi)) = (lo, hi) else {
        return error(format!("order '{order}': give N or N..M"));
    };
    let Some(kind) = Kind::parse(kind) else {
        return error(format!(
            "kind '{kind}': {}",
            Kind::ALL.map(Kind::name).join(", ")
        ));
    };
    let settings = Settings {
        kind,
        ..Settings::for_student(student, lo, hi, convention)
    };
    let text = match pole_placement(&settings) {
        Ok(t) => t,
        Err(e) => return error(e),
    };
    let ex: ExerciseFile = match toml::from_str(&text) {
        Ok(ex) => ex,
        Err(e) => {
            return error(format!(
                "the generated exercise does not parse (a bug): {e}"
            ))
        }
    };
    // the key must be computable, as `owb exercise new` insists
    if let Err(e) = answer_key(&settings.id(), &ex) {
        return error(e);
    }
    json!({
        "id": settings.id(),
        "student": student.trim(),
        "command": format!(
            "owb exercise new --kind {} --student {:?} --order {order} --convention {convention}",
            kind.name(),
            student.trim()
        ),
        "toml": text,
        "title": ex.title,
        "statement": ex.statement,
        "parts": ex.parts.iter().map(|p| json!({
            "id": p.id, "prompt": p.prompt, "points": p.points
        })).collect::<Vec<_>>(),
    })
    .to_string()
}

/// Runs one `owb` subcommand that computes from its flags alone (observe, canonical, gain,
/// feedback, control, optimal, kalman, perfect, exercise): `args` is a JSON array of strings,
/// the command line after `owb`. Returns `{"status": 0|1|2, "output": text, "error": text?}`
/// and, when the command derives something, `"latex"`: its derivation typeset (the same steps
/// as `--json`'s).
#[wasm_bindgen]
pub fn run(args: &str) -> String {
    let args: Vec<String> = match serde_json::from_str(args) {
        Ok(a) => a,
        Err(e) => {
            return error(format!(
                "the command line is not a JSON list of strings: {e}"
            ))
        }
    };
    let Some(sub) = args.first() else {
        return error("no subcommand");
    };
    if !IN_MEMORY_SUBCOMMANDS.contains(&sub.as_str()) {
        return error(format!(
            "'{sub}' is not run in the browser (it reads or writes files); here: {}",
            IN_MEMORY_SUBCOMMANDS.join(", ")
        ));
    }
    if args.iter().any(|a| a.starts_with("--out")) {
        return error("--out writes a file; the browser shows the result instead");
    }
    let (outcome, text) = run_captured(&args);
    let mut out = match outcome {
        Ok(Outcome::Ok) => json!({ "status": 0, "output": text }),
        Ok(Outcome::Failed) => json!({ "status": 1, "output": text }),
        Err(e) => {
            let causes: Vec<String> = e.chain().skip(1).map(|c| c.to_string()).collect();
            json!({ "status": 2, "output": text, "error": e.to_string(), "causes": causes })
        }
    };
    if out["status"] == 0 {
        if let Some(latex) = derivation_latex(&args) {
            out["latex"] = Value::String(latex);
        }
    }
    out.to_string()
}

/// The derivation of a command, typeset: the command run again with `--json`, its `steps`.
fn derivation_latex(args: &[String]) -> Option<String> {
    if args.iter().any(|a| a == "--json") {
        return None;
    }
    let mut with_json = args.to_vec();
    with_json.push("--json".into());
    let (outcome, text) = run_captured(&with_json);
    outcome.ok()?;
    let v: Value = serde_json::from_str(&text).ok()?;
    let steps: Vec<Step> = serde_json::from_value(v.get("steps")?.clone()).ok()?;
    (!steps.is_empty()).then(|| {
        Derivation {
            title: String::new(),
            steps,
        }
        .to_latex()
    })
}

/// Verifies a worked example (its TOML), as `owb verify` does for one file: returns
/// `{"text": the table, "json": owb verify --json's object}` or `{"error": …}`. Files a
/// scenario would read are not available in the browser; such claims report that.
#[wasm_bindgen]
pub fn verify(name: &str, example: &str) -> String {
    let file = format!("{name}.toml");
    let ex = match parse_example(&file, example) {
        Ok(ex) => ex,
        Err(e) => return error(e),
    };
    match verify_example(std::path::Path::new(&file), &ex, example) {
        Ok(report) => {
            let reports = [report];
            json!({
                "text": render_table(&reports[0]),
                "json": report_json(&reports),
            })
            .to_string()
        }
        Err(e) => error(e),
    }
}
