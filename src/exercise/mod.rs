//! Exercises for students: the statement and the parts to answer are data, the answer key is
//! computed by the workbench (never typed), and a student's answers are checked with feedback
//! that names the mistake — computed, not canned.
//!
//! * [`format`](mod@format): exercise files (`worked_examples/exercises/*.toml`) and answer files.
//! * [`key`]: the answer key, each part recomputed through the worked-example computations.
//! * [`check`]: one student's answers — verdict, score (partial credit per diagnosed mistake)
//!   and feedback per part.
//! * [`diagnose`]: the mistakes recognised: sign convention, gain left in canonical
//!   coordinates, transposed or reversed vector, the wrong observer polynomial (another family or
//!   another time constant, found from the poles the answer actually places), a single slip, an
//!   answer for another canonical-form convention, a negated polynomial or transfer function.
//! * [`generate`]: fresh pole-placement exercises whose hand computation stays in small integers.
//! * [`formula`]: exercises with free parameters — the key a formula, answers checked as
//!   identities, mistakes named symbolically, right-only-at-some-values said with the values.

pub mod check;
pub mod diagnose;
pub mod format;
pub mod formula;
pub mod generate;
pub mod key;
pub mod mistake;

pub use check::{check_answers, PartResult, PartVerdict, Report};
pub use format::{
    load_answers, load_exercise, parse_answers, parse_exercise, AnswerFile, ExerciseFile, PartSpec,
};
pub use key::{answer_key, AnswerKey};
pub use mistake::Mistake;

/// A file that cannot be used, located by file, line and field.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{file}:{line}: {field}: {message}")]
pub struct ExerciseError {
    /// The file.
    pub file: String,
    /// 1-based line (0 when unknown).
    pub line: usize,
    /// The field.
    pub field: String,
    /// What is wrong.
    pub message: String,
}

// `BUILTIN_EXERCISES`, written by build.rs from worked_examples/exercises/*.toml
include!(concat!(env!("OUT_DIR"), "/builtin_exercises.rs"));

/// A built-in exercise by id: `(id, text)`.
pub fn builtin(id: &str) -> Option<(&'static str, &'static str)> {
    BUILTIN_EXERCISES.iter().copied().find(|(i, _)| *i == id)
}
