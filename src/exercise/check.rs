//! Checking one student's answers against the computed key.

use super::diagnose::diagnose;
use super::format::AnswerFile;
use super::key::AnswerKey;
use crate::worked::{compare, Agreement, Value};
use serde::Serialize;

/// The verdict on one part.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PartVerdict {
    /// Right (exactly, or to the decimals written).
    Correct,
    /// Wrong.
    Wrong,
    /// No answer given.
    Missing,
    /// The answer cannot be read (syntax), with where.
    Unreadable,
}

impl PartVerdict {
    /// ✔ or ✘.
    pub fn mark(self) -> &'static str {
        match self {
            PartVerdict::Correct => "✔",
            _ => "✘",
        }
    }
}

/// One part, checked.
#[derive(Clone, Debug, Serialize)]
pub struct PartResult {
    /// Part id.
    pub id: String,
    /// The question.
    pub prompt: String,
    /// Verdict.
    pub verdict: PartVerdict,
    /// The mistake named, if any.
    pub mistake: Option<String>,
    /// Points earned.
    pub score: f64,
    /// Points possible.
    pub points: f64,
    /// The feedback, computed.
    pub feedback: String,
}

/// A student's checked answers.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    /// The student.
    pub student: String,
    /// The exercise.
    pub exercise: String,
    /// Per part.
    pub parts: Vec<PartResult>,
    /// Total earned.
    pub score: f64,
    /// Total possible.
    pub points: f64,
    /// Answers that match no part.
    pub unknown_answers: Vec<String>,
}

impl Report {
    /// Whether every part is correct.
    pub fn all_correct(&self) -> bool {
        self.parts.iter().all(|p| p.verdict == PartVerdict::Correct)
    }

    /// The feedback as text for the student.
    pub fn text(&self) -> String {
        let mut out = format!("{} — exercise {}\n", self.student, self.exercise);
        for p in &self.parts {
            out.push_str(&format!(
                "{} {} ({}/{} points): {}\n    {}\n",
                p.verdict.mark(),
                p.id,
                trim(p.score),
                trim(p.points),
                p.prompt,
                p.feedback.replace('\n', "\n    ")
            ));
        }
        for a in &self.unknown_answers {
            out.push_str(&format!(
                "! answers.{a} is not a part of this exercise (ignored)\n"
            ));
        }
        out.push_str(&format!(
            "score: {} / {}\n",
            trim(self.score),
            trim(self.points)
        ));
        out
    }
}

fn trim(x: f64) -> String {
    let s = format!("{x:.2}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// Checks `answers` against the key.
pub fn check_answers(key: &AnswerKey, answers: &AnswerFile, student: &str) -> Report {
    let mut parts = Vec::new();
    for part in &key.parts {
        // a part named with an invisible character pasted into it (`L\u{200b}`): the answer
        // is the student's, the name is not readable as typed — said at the part itself
        let lookalike = answers.answers.keys().find(|k| {
            k.as_str() != part.spec.id
                && k.chars().any(crate::files::is_invisible)
                && k.chars()
                    .filter(|c| !crate::files::is_invisible(*c))
                    .eq(part.spec.id.chars())
        });
        // each answer is read, compared and diagnosed under one symbolic work budget: a
        // student's formula cannot make the check run for minutes
        let checked = crate::symbolic::within_budget(|| check_part(key, answers, part, lookalike));
        let result =
            checked.unwrap_or_else(|e| unreadable(part, format!("cannot check the answer: {e}")));
        parts.push(result);
    }
    let unknown_answers = answers
        .answers
        .keys()
        .filter(|k| key.part(k).is_none())
        .map(|k| crate::files::escape_untrusted(k))
        .collect();
    Report {
        // a student's name is echoed to terminals, feedback files and reports: nothing in it
        // may act on them
        student: crate::files::escape_untrusted(student),
        exercise: key.example.id.clone(),
        score: parts.iter().map(|p| p.score).sum(),
        points: parts.iter().map(|p| p.points).sum(),
        parts,
        unknown_answers,
    }
}

/// One part's result: its answer read, compared with the key, and diagnosed when wrong.
fn check_part(
    key: &AnswerKey,
    answers: &AnswerFile,
    part: &super::key::KeyPart,
    lookalike: Option<&String>,
) -> PartResult {
    let points = part.spec.points;
    {
        match answers.answers.get(&part.spec.id) {
            None if lookalike.is_some() => unreadable(
                part,
                format!(
                    "the answer's name, {}, holds an invisible or control character ({}), often pasted from a PDF; retype the name {}",
                    crate::files::escape_untrusted(lookalike.map_or("", String::as_str)),
                    lookalike
                        .and_then(|k| crate::files::first_invisible(k))
                        .unwrap_or_default(),
                    part.spec.id
                ),
            ),
            None => PartResult {
                id: part.spec.id.clone(),
                prompt: part.spec.prompt.clone(),
                verdict: PartVerdict::Missing,
                mistake: None,
                score: 0.0,
                points,
                feedback: "no answer given".into(),
            },
            Some(text) => match crate::files::first_invisible(text)
                .map(|at| {
                    Err(crate::worked::PrintError::Form(format!(
                        "the answer holds an invisible or control character ({at}), often pasted from a PDF; retype it"
                    )))
                })
                .unwrap_or_else(|| compare(&part.value, text, &key.env))
            {
                Err(message) => unreadable(part, format!("cannot read the answer: {message}")),
                Ok(agreement) if agreement.holds() => PartResult {
                    id: part.spec.id.clone(),
                    prompt: part.spec.prompt.clone(),
                    verdict: PartVerdict::Correct,
                    mistake: None,
                    score: points,
                    points,
                    feedback: match agreement {
                        Agreement::Rounded { digits } => format!(
                            "correct to the {digits} decimals you wrote (your numbers are the exact answer rounded, not truncated); exactly: {}",
                            part.value.input()
                        ),
                        _ => "correct".into(),
                    },
                },
                Ok(_) => {
                    let (diagnosis, notes) = match (&key.formula, &part.value) {
                        (Some(plant), Value::Formula(k)) => super::formula::diagnose(
                            plant,
                            &key.exercise,
                            &part.spec,
                            k,
                            text,
                            &key.env,
                        ),
                        _ => diagnose(key, part, text),
                    };
                    let credit = diagnosis
                        .as_ref()
                        .and_then(|d| part.spec.partial.get(&d.mistake))
                        .copied()
                        .unwrap_or(0.0);
                    let mut lines = Vec::new();
                    if let Some(d) = &diagnosis {
                        lines.push(format!("{} — {}", d.mistake.words(), d.message));
                    } else {
                        lines.push("not the answer, and not a mistake the workbench recognises".into());
                    }
                    lines.extend(notes);
                    if credit > 0.0 {
                        lines.push(format!("partial credit for this mistake: {}", trim(credit * points)));
                    }
                    PartResult {
                        id: part.spec.id.clone(),
                        prompt: part.spec.prompt.clone(),
                        verdict: PartVerdict::Wrong,
                        mistake: diagnosis.map(|d| d.mistake.to_string()),
                        score: credit * points,
                        points,
                        feedback: lines.join("\n"),
                    }
                }
            },
        }
    }
}

/// A part whose answer cannot be read, with why.
fn unreadable(part: &super::key::KeyPart, feedback: String) -> PartResult {
    PartResult {
        id: part.spec.id.clone(),
        prompt: part.spec.prompt.clone(),
        verdict: PartVerdict::Unreadable,
        mistake: None,
        score: 0.0,
        points: part.spec.points,
        feedback,
    }
}

/// Checks answers given as text: the exercise file's and the answer file's contents, each
/// named for error messages. The path the course book takes in the browser (no files there);
/// `owb check` reads the same two files and runs the same functions.
///
/// # Errors
/// [`ExerciseError`](super::ExerciseError) for an unreadable exercise or answer file, a key that cannot be computed,
/// or answers written for another exercise.
pub fn check_text(
    exercise: (&str, &str),
    answers: (&str, &str),
) -> Result<Report, super::ExerciseError> {
    let (ex_name, ex_raw) = exercise;
    let (ans_name, ans_raw) = answers;
    let ex = super::format::parse_exercise(std::path::Path::new(ex_name), ex_raw)?;
    let key = super::answer_key(ex_name, &ex)?;
    let answers = super::format::parse_answers(std::path::Path::new(ans_name), ans_raw)?;
    if let Some(id) = answers.exercise.as_ref().filter(|id| **id != ex.id) {
        return Err(super::ExerciseError {
            file: ans_name.to_string(),
            line: crate::worked::locate(ans_raw, None, "exercise"),
            field: "exercise".into(),
            message: format!("these answers are for exercise '{id}', not '{}'", ex.id),
        });
    }
    let student = answers.student.clone().unwrap_or_else(|| "student".into());
    Ok(check_answers(&key, &answers, &student))
}
