//! An exercise's statement laid out for a page: paragraphs, numbered steps and the system's
//! matrices typeset. The statement stays plain text in the exercise file (what `owb check`
//! and a terminal show); this reads its layout — blank lines between paragraphs, lines opening
//! with `1.`, `2.` … as steps, and a paragraph that only assigns the system's matrices
//! (`A = […], C = […],`) as display math computed from the system itself, never from the text.

use super::format::ExerciseFile;
use crate::algebra::{MultiPoly, Quadratic};
use serde::Serialize;

/// One block of a statement.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Block {
    /// A paragraph of text.
    Text(String),
    /// Numbered steps, in order (the numbers removed).
    Steps(Vec<String>),
    /// Display math (LaTeX): the system's matrices.
    Math(String),
}

/// The blocks of `ex`'s statement.
///
/// ```
/// use observer_workbench::exercise::{generate, statement::{blocks, Block}, parse_exercise};
/// let s = generate::Settings::for_student("ada", 2, 2, "a-kc");
/// let text = generate::pole_placement(&s).unwrap();
/// let ex = parse_exercise(std::path::Path::new("ada.toml"), &text).unwrap();
/// let b = blocks(&ex);
/// assert!(matches!(&b[1], Block::Math(m) if m.starts_with("A = \\begin{bmatrix}")));
/// assert!(matches!(&b[2], Block::Steps(steps) if steps.len() == 5));
/// ```
pub fn blocks(ex: &ExerciseFile) -> Vec<Block> {
    ex.statement
        .trim()
        .split("\n\n")
        .map(str::trim)
        .filter(|p| !p.is_empty())
        .map(|p| {
            if let Some(latex) = system_math(ex, p) {
                return Block::Math(latex);
            }
            let lines: Vec<&str> = p.lines().map(str::trim).collect();
            let numbered: Option<Vec<String>> = lines
                .iter()
                .enumerate()
                .map(|(i, l)| l.strip_prefix(&format!("{}. ", i + 1)).map(str::to_string))
                .collect();
            match numbered {
                Some(steps) => Block::Steps(steps),
                None => Block::Text(lines.join(" ")),
            }
        })
        .collect()
}

/// The paragraph `A = …, C = …` (each value exactly the system's text) typeset from the system.
fn system_math(ex: &ExerciseFile, paragraph: &str) -> Option<String> {
    let mut rest = paragraph.trim().trim_end_matches([',', '.']).trim();
    let mut parts = Vec::new();
    while !rest.is_empty() {
        let (name, after) = rest.split_once(" = ")?;
        let name = name.trim();
        let value = match name {
            "A" => ex.system.a.as_deref(),
            "B" => ex.system.b.as_deref(),
            "C" => ex.system.c.as_deref(),
            "D" => ex.system.d.as_deref(),
            _ => None,
        }?;
        rest = after.strip_prefix(value)?.trim_start();
        rest = rest.strip_prefix(',').unwrap_or(rest).trim_start();
        parts.push(format!("{name} = {}", matrix_latex(value)?));
    }
    (!parts.is_empty()).then(|| parts.join(",\\quad "))
}

/// A matrix of numbers or of polynomials in parameters, in LaTeX.
fn matrix_latex(text: &str) -> Option<String> {
    if let Ok(m) = crate::syntax::parse_matrix::<Quadratic>(text) {
        return Some(m.to_latex());
    }
    crate::syntax::parse_matrix::<MultiPoly>(text)
        .ok()
        .map(|m| m.to_latex())
}
