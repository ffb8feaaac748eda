//! How much of each source document the worked examples check. A coverage file
//! (`worked_examples/coverage/*.toml`) goes through one document equation by equation, slide by
//! slide, and lists every statement that could be checked — numbers, matrices, polynomials,
//! identities, and the text's own statements about them (cross-references, index ranges, task
//! lists, "k1 = 0") — each either recorded (the claims or simulated figures that check it),
//! taken as input data (the example's system or parameters), or not checked, with the reason.
//!
//! The lists are checked against the examples: every claim and figure a list names exists and
//! belongs to that document, and every claim and figure of the document's examples is listed,
//! so the list cannot silently fall behind the examples. `owb verify` prints the totals.

use super::format::ExampleFile;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Why a statement is not checked.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum NotChecked {
    /// A definition or notation: nothing to compute.
    Definition,
    /// A qualitative remark (advice, motivation, a judgement) with no computable content.
    Qualitative,
    /// A step of a derivation whose result is checked (the step itself is not recorded).
    DerivationStep,
    /// An equation cross-reference or index range: read and judged, not computed.
    CrossReference,
    /// A figure, table or value the text lacks (lost in conversion, or never given).
    Missing,
    /// Checkable with the workbench's computations, not yet recorded as a claim.
    NotYetRecorded,
}

impl NotChecked {
    /// In words, for one statement.
    pub fn word(self) -> &'static str {
        match self {
            NotChecked::Definition => "a definition",
            NotChecked::Qualitative => "a qualitative remark",
            NotChecked::DerivationStep => "a derivation step",
            NotChecked::CrossReference => "a cross-reference, read and judged",
            NotChecked::Missing => "missing from the text",
            NotChecked::NotYetRecorded => "checkable, not yet recorded",
        }
    }

    /// In words, for the totals.
    pub fn words(self) -> &'static str {
        match self {
            NotChecked::Definition => "definitions",
            NotChecked::Qualitative => "qualitative remarks",
            NotChecked::DerivationStep => "derivation steps",
            NotChecked::CrossReference => "cross-references (read, not computed)",
            NotChecked::Missing => "missing from the text",
            NotChecked::NotYetRecorded => "checkable, not yet recorded",
        }
    }
}

/// One statement of the document.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Statement {
    /// Where: equation, slide, section, line.
    #[serde(rename = "where")]
    pub location: String,
    /// The statement, in our words.
    pub statement: String,
    /// The claims (`example/claim`) or simulated figures (`example/scenario`) that check it.
    #[serde(default)]
    pub recorded: Vec<String>,
    /// The example that takes it as input data (system, parameters, noise).
    pub input: Option<String>,
    /// Why it is not checked.
    pub not_checked: Option<NotChecked>,
    /// What we found or why, in our words.
    pub note: Option<String>,
}

/// The coverage list of one document.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CoverageFile {
    /// The document's file in `../shared/seeds/`.
    pub document: String,
    /// Author and title.
    pub title: String,
    /// Every checkable statement, in the document's order.
    pub statements: Vec<Statement>,
}

/// The totals of one document's list.
#[derive(Clone, Debug, Serialize)]
pub struct Totals {
    /// The document's file.
    pub document: String,
    /// Author and title.
    pub title: String,
    /// Statements listed.
    pub statements: usize,
    /// Checked by claims or figures.
    pub recorded: usize,
    /// Taken as input data.
    pub inputs: usize,
    /// Not checked, per reason.
    pub not_checked: BTreeMap<NotChecked, usize>,
}

impl Totals {
    /// One line: `Di Ruscio (…): 60 statements — 40 checked by claims or figures, …`.
    pub fn line(&self) -> String {
        format!("{}: {}", self.title, self.counts())
    }

    /// The counts: `60 statements — 40 checked by claims or figures, …`.
    pub fn counts(&self) -> String {
        let mut parts = vec![
            format!("{} checked by claims or figures", self.recorded),
            format!("{} input data", self.inputs),
        ];
        for (why, n) in &self.not_checked {
            parts.push(format!("{n} {}", why.words()));
        }
        format!("{} statements — {}", self.statements, parts.join(", "))
    }
}

/// A list that does not fit the examples.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{file}: {message}")]
pub struct CoverageError {
    /// The coverage file.
    pub file: String,
    /// What is wrong.
    pub message: String,
}

/// The coverage files of a worked-example folder (`DIR/coverage/*.toml`), sorted; none when
/// the folder has no coverage.
///
/// # Errors
/// [`CoverageError`] for a file that cannot be read or parsed (with its line).
pub fn load(dir: &Path) -> Result<Vec<(PathBuf, CoverageFile)>, CoverageError> {
    let folder = dir.join("coverage");
    let Ok(entries) = std::fs::read_dir(&folder) else {
        return Ok(Vec::new());
    };
    let mut paths: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    paths.sort();
    paths
        .into_iter()
        .map(|p| {
            let error = |message: String| CoverageError {
                file: p.display().to_string(),
                message,
            };
            let raw = std::fs::read_to_string(&p).map_err(|e| error(e.to_string()))?;
            let file: CoverageFile = toml::from_str(&raw).map_err(|e| {
                let line = e.span().map_or(0, |s| {
                    raw[..s.start.min(raw.len())].matches('\n').count() + 1
                });
                error(format!("line {line}: {}", e.message()))
            })?;
            Ok((p, file))
        })
        .collect()
}

/// Checks one list against the examples and counts it.
///
/// # Errors
/// [`CoverageError`]: a statement recorded nowhere and not explained, a reference to a claim or
/// figure that does not exist or belongs to another document, or a claim or figure of this
/// document that no statement lists.
pub fn check(
    path: &Path,
    list: &CoverageFile,
    examples: &[ExampleFile],
) -> Result<Totals, CoverageError> {
    let error = |message: String| CoverageError {
        file: path.display().to_string(),
        message,
    };
    let mine: Vec<&ExampleFile> = examples
        .iter()
        .filter(|e| e.document == list.document)
        .collect();
    let mut listed: Vec<String> = Vec::new();
    let mut totals = Totals {
        document: list.document.clone(),
        title: list.title.clone(),
        statements: list.statements.len(),
        recorded: 0,
        inputs: 0,
        not_checked: BTreeMap::new(),
    };
    for s in &list.statements {
        let at = format!("statement at {} ('{}')", s.location, s.statement);
        let ways = usize::from(!s.recorded.is_empty())
            + usize::from(s.input.is_some())
            + usize::from(s.not_checked.is_some());
        if ways != 1 {
            return Err(error(format!(
                "{at}: give exactly one of recorded, input or not_checked"
            )));
        }
        for r in &s.recorded {
            let (ex, item) = r
                .split_once('/')
                .ok_or_else(|| error(format!("{at}: '{r}' is not example/claim")))?;
            let e = mine.iter().find(|e| e.id == ex).ok_or_else(|| {
                error(format!(
                    "{at}: no example '{ex}' of {} (recorded '{r}')",
                    list.document
                ))
            })?;
            let exists = e.claims.iter().any(|c| c.id == item)
                || e.scenarios.iter().any(|sc| sc.name == item);
            if !exists {
                return Err(error(format!(
                    "{at}: example '{ex}' has no claim or figure '{item}'"
                )));
            }
            listed.push(r.clone());
        }
        if let Some(ex) = &s.input {
            if !mine.iter().any(|e| e.id == *ex) {
                return Err(error(format!(
                    "{at}: no example '{ex}' of {}",
                    list.document
                )));
            }
        }
        totals.recorded += usize::from(!s.recorded.is_empty());
        totals.inputs += usize::from(s.input.is_some());
        if let Some(why) = s.not_checked {
            *totals.not_checked.entry(why).or_default() += 1;
        }
    }
    for e in &mine {
        let items = e
            .claims
            .iter()
            .map(|c| &c.id)
            .chain(e.scenarios.iter().map(|s| &s.name));
        for item in items {
            let r = format!("{}/{item}", e.id);
            if !listed.contains(&r) {
                return Err(error(format!(
                    "'{r}' checks {} but no statement of the list records it",
                    list.document
                )));
            }
        }
    }
    Ok(totals)
}

// `BUILTIN_DOCUMENT_TITLES`, written by build.rs from worked_examples/coverage/*.toml
include!(concat!(env!("OUT_DIR"), "/builtin_document_titles.rs"));

/// The author and title of a source document (by its file name) as the project's coverage lists
/// record them, built into the program; `None` for a document without a list (the course's
/// cross-checks against python-control).
///
/// ```
/// use observer_workbench::worked::coverage::document_title;
/// assert!(document_title("001_7629475c4a00cd3e.txt").is_some_and(|t| t.starts_with("Stoustrup")));
/// assert_eq!(document_title("elsewhere.txt"), None);
/// ```
pub fn document_title(document: &str) -> Option<&'static str> {
    BUILTIN_DOCUMENT_TITLES
        .iter()
        .find(|(file, _)| *file == document)
        .map(|(_, title)| *title)
}

/// Document file → author and title: the built-in titles, then the coverage lists of `dir`
/// (a list there wins; titles only label reports, so a list that cannot be read is skipped).
pub fn titles(dir: &Path) -> BTreeMap<String, String> {
    BUILTIN_DOCUMENT_TITLES
        .iter()
        .map(|(d, t)| ((*d).to_string(), (*t).to_string()))
        .chain(
            load(dir)
                .unwrap_or_default()
                .into_iter()
                .map(|(_, l)| (l.document, l.title)),
        )
        .collect()
}
