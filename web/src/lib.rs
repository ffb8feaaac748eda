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

use observer_workbench::api::{self, Command, Outcome};
use observer_workbench::exercise::check::check_text;
use observer_workbench::exercise::ExerciseFile;
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
/// --convention C` generates it (the same request, run by the same library function). Returns
/// `{"id", "command", "toml", "title", "statement", "statement_blocks": [{"text"} | {"steps"} |
/// {"math"}], "parts": [{"id", "prompt", "points", "hint"}]}` or `{"error": …}`.
#[wasm_bindgen]
pub fn variant(student: &str, order: &str, convention: &str, kind: &str) -> String {
    if student.trim().is_empty() {
        return error("type your student id first");
    }
    let request = json!({
        "command": "exercise",
        "action": {"new": {
            "student": student, "order": order, "convention": convention, "kind": kind,
            "json": true,
        }},
    });
    let command = match Command::from_value(&request) {
        Ok(c) => c,
        Err(e) => return error(e),
    };
    let report = match api::run(command) {
        Ok(r) => r,
        Err(f) => return error(format!("{:#}", f.error)),
    };
    let Some(text) = report
        .json
        .as_ref()
        .and_then(|j| j["exercise"].as_str())
        .map(str::to_string)
    else {
        return error("the exercise generator gave no exercise (a bug)");
    };
    let ex: ExerciseFile = match toml::from_str(&text) {
        Ok(ex) => ex,
        Err(e) => {
            return error(format!(
                "the generated exercise does not parse (a bug): {e}"
            ))
        }
    };
    json!({
        "id": ex.id,
        "student": student.trim(),
        "command": format!(
            "owb exercise new --kind {kind} --student {:?} --order {order} --convention {convention}",
            student.trim()
        ),
        "toml": text,
        "title": ex.title,
        "statement": ex.statement,
        "statement_blocks": observer_workbench::exercise::statement::blocks(&ex),
        "parts": ex.parts.iter().map(|p| json!({
            "id": p.id, "prompt": p.prompt, "points": p.points,
            "hint": observer_workbench::exercise::hint(p.ask),
        })).collect::<Vec<_>>(),
    })
    .to_string()
}

/// Runs one workbench command that computes from its request alone (observe, canonical, gain,
/// feedback, discrete, zoh, dlqe, reduced, detectable, control, optimal, kalman, perfect,
/// exercise): `request` is the command's JSON request, `{"command": "gain", "a": "[0 1; -2
/// -3]", "c": "[1 0]", "poles": "-4, -5"}` (keys named as the command line's flags). Returns
/// `{"status": 0|1|2, "output": text, "error": text?, "causes": […]?}` and, when the command
/// derives something, `"latex"`: its derivation typeset — from the one computation.
#[wasm_bindgen]
pub fn run(request: &str) -> String {
    let command = match Command::from_json(request) {
        Ok(c) => c,
        Err(e) => return error(e),
    };
    if !command.in_memory() {
        return error(format!(
            "'{}' is not run in the browser (it reads or writes files); here: {}",
            command.name(),
            Command::IN_MEMORY.join(", ")
        ));
    }
    if command.writes_files() {
        return error("out writes a file; the browser shows the result instead");
    }
    match api::run(command) {
        Ok(report) => {
            let status = match report.outcome {
                Outcome::Ok => 0,
                Outcome::Failed => 1,
            };
            let mut out = json!({ "status": status, "output": report.text });
            if status == 0 {
                if let Some(latex) = report.latex() {
                    out["latex"] = Value::String(latex);
                }
            }
            if !report.warnings.is_empty() {
                out["warnings"] = json!(report.warnings);
            }
            out.to_string()
        }
        Err(f) => {
            let causes: Vec<String> = f.error.chain().skip(1).map(|c| c.to_string()).collect();
            json!({ "status": 2, "output": f.partial.text, "error": f.error.to_string(), "causes": causes })
                .to_string()
        }
    }
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
