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
    let _ = parse_matrix::<Rational>(&text);
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
