//! Exercise and answer files (TOML), documented for teachers in
//! `worked_examples/exercises/README.md`.

use super::ExerciseError;
use crate::worked::SystemSpec;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::Path;

/// An exercise: a statement, a system, a design, and the parts to answer.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExerciseFile {
    /// Identifier.
    pub id: String,
    /// Title.
    pub title: String,
    /// Where it comes from (document and place), or "generated".
    pub source: String,
    /// The statement, in markdown (used by the book).
    pub statement: String,
    /// Exact parameter values.
    #[serde(default)]
    pub parameters: BTreeMap<String, String>,
    /// The system.
    pub system: SystemSpec,
    /// The design asked for.
    #[serde(default)]
    pub design: DesignSpec,
    /// The parts to answer.
    pub parts: Vec<PartSpec>,
}

impl DesignSpec {
    /// Whether the design names a desired polynomial (poles, coefficients or a family).
    pub fn names_desired(&self) -> bool {
        self.poles.is_some()
            || self.poly.is_some()
            || crate::observer::Family::given([
                self.repeated.as_ref(),
                self.butterworth.as_ref(),
                self.bessel.as_ref(),
                self.itae.as_ref(),
            ])
            .is_some()
    }
}

/// The design the parts refer to.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DesignSpec {
    /// `a-kc` or `a+lc`: the convention the answers must use.
    pub convention: Option<String>,
    /// Canonical-form procedure (`di-ruscio`, `stoustrup`).
    pub procedure: Option<String>,
    /// Desired observer poles.
    pub poles: Option<String>,
    /// Desired observer polynomial.
    pub poly: Option<String>,
    /// Repeated root with time constant T.
    pub repeated: Option<String>,
    /// Butterworth with time constant T.
    pub butterworth: Option<String>,
    /// Bessel with time constant T.
    pub bessel: Option<String>,
    /// ITAE with time constant T.
    pub itae: Option<String>,
    /// State feedback `F` for control parts (u = F x̂).
    pub feedback: Option<String>,
    /// The observer gain for control parts (default: the computed `gain` part).
    pub gain: Option<String>,
}

/// One part to answer.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PartSpec {
    /// The key of the answer (`O`, `T`, `K`…).
    pub id: String,
    /// What is asked: a worked-example computation (`observability_matrix`, `gain`, …).
    pub ask: crate::worked::Computation,
    /// The question, for the student.
    pub prompt: String,
    /// Points for a correct answer.
    #[serde(default = "one")]
    pub points: f64,
    /// Partial credit (fraction of `points`) per diagnosed mistake, e.g. `{ sign_convention = 0.5 }`.
    #[serde(default)]
    pub partial: BTreeMap<super::Mistake, f64>,
    /// A C for this part only (e.g. one output).
    #[serde(rename = "C")]
    pub c: Option<String>,
    /// Design settings for this part only (override the exercise's `[design]`).
    pub design: Option<DesignSpec>,
}

fn one() -> f64 {
    1.0
}

/// A student's answers: `answers.K = "[-6; -12]"`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AnswerFile {
    /// The student (defaults to the file name).
    pub student: Option<String>,
    /// The exercise id these answers are for (checked when given).
    pub exercise: Option<String>,
    /// Part id → answer text in the input syntax.
    #[serde(default)]
    pub answers: BTreeMap<String, String>,
}

/// The largest exercise or answer file read (a class's answers are a few hundred bytes each;
/// a 10 MB "answer" is refused before it is read, and never echoed).
pub const MAX_FILE_BYTES: u64 = 1 << 20;

fn read(path: &Path) -> Result<String, ExerciseError> {
    crate::files::read_untrusted(path, MAX_FILE_BYTES).map_err(|e| ExerciseError {
        file: crate::files::escape_untrusted(&path.display().to_string()),
        line: 0,
        field: "file".into(),
        message: match e {
            crate::files::FileError::TooLarge { .. } => {
                format!("the file has more than {MAX_FILE_BYTES} bytes (1 MiB), the most accepted")
            }
            e => e.to_string(),
        },
    })
}

fn toml_error(path: &Path, raw: &str, e: &toml::de::Error) -> ExerciseError {
    let line = e.span().map_or(0, |s| {
        raw[..s.start.min(raw.len())].matches('\n').count() + 1
    });
    let mut message = e.message().to_string();
    if let Some(at) = raw
        .lines()
        .nth(line.saturating_sub(1))
        .and_then(crate::files::first_invisible)
    {
        message.push_str(&format!(
            " (line {line} holds an invisible or control character, {at}: retype it)"
        ));
    }
    ExerciseError {
        file: crate::files::escape_untrusted(&path.display().to_string()),
        line,
        field: crate::files::escape_untrusted(&crate::worked::toml_field(raw, line)),
        message: crate::files::escape_untrusted(&message),
    }
}

/// Reads an exercise file and checks its parts.
///
/// # Errors
/// [`ExerciseError`] with file, line and field.
pub fn load_exercise(path: &Path) -> Result<(ExerciseFile, String), ExerciseError> {
    let raw = read(path)?;
    let ex = parse_exercise(path, &raw)?;
    Ok((ex, raw))
}

/// Parses and checks the text of an exercise file (`path` names it in errors).
///
/// # Errors
/// [`ExerciseError`] with file, line and field.
pub fn parse_exercise(path: &Path, raw: &str) -> Result<ExerciseFile, ExerciseError> {
    let raw = raw.to_string();
    let ex: ExerciseFile = toml::from_str(&raw).map_err(|e| toml_error(path, &raw, &e))?;
    let mut seen = std::collections::BTreeSet::new();
    for p in &ex.parts {
        let bad = |field: &str, message: String| ExerciseError {
            file: path.display().to_string(),
            line: crate::worked::locate(&raw, Some(("id", &p.id)), field),
            field: format!("parts.{}.{field}", p.id),
            message,
        };
        if !seen.insert(p.id.clone()) {
            return Err(bad("id", format!("part '{}' appears twice", p.id)));
        }
        if !p.ask.askable() {
            return Err(bad(
                "ask",
                format!(
                    "'{}' cannot be asked of a student; askable: {}",
                    p.ask,
                    crate::worked::Computation::known_askable()
                ),
            ));
        }
        if !(p.points.is_finite() && p.points >= 0.0) {
            return Err(bad("points", "points must be a non-negative number".into()));
        }
        if let Some((k, v)) = p.partial.iter().find(|(_, v)| !(0.0..=1.0).contains(*v)) {
            return Err(bad(
                "partial",
                format!("{k} = {v}: a fraction of the points, between 0 and 1"),
            ));
        }
    }
    Ok(ex)
}

/// Reads an answer file.
///
/// # Errors
/// [`ExerciseError`] with file, line and field.
pub fn load_answers(path: &Path) -> Result<(AnswerFile, String), ExerciseError> {
    let raw = read(path)?;
    let a = parse_answers(path, &raw)?;
    Ok((a, raw))
}

/// Parses the text of an answer file (`path` names it in errors).
///
/// # Errors
/// [`ExerciseError`] with file, line and field.
pub fn parse_answers(path: &Path, raw: &str) -> Result<AnswerFile, ExerciseError> {
    toml::from_str(raw).map_err(|e| toml_error(path, raw, &e))
}
