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
//!
//! **Counted strictly: one statement, one check.** `recorded` names only what checks exactly
//! that statement. A claim recorded for several statements must list each of them (their
//! `where`) in its own `checks`, so crediting one claim to several statements is a decision
//! written beside the claim, not an accident of the list; a simulated figure is recorded only
//! when it has checks of its own (an overshoot, a settling time), since a figure without them
//! checks nothing. What bears on a statement without checking it — a theorem's instance, a
//! value the statement is used for — goes under `related`: shown with the statement, never
//! counted. A statement is *checkable* when it is recorded or `not_yet_recorded`; `owb verify`
//! prints the share recorded.

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
    /// The claims (`example/claim`) or simulated figures (`example/scenario`) that check
    /// exactly this statement.
    #[serde(default)]
    pub recorded: Vec<String>,
    /// Claims or figures that bear on the statement without checking exactly it (shown, not
    /// counted).
    #[serde(default)]
    pub related: Vec<String>,
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
    /// Checked by claims or figures, strictly: each names exactly this statement.
    pub recorded: usize,
    /// Checkable: recorded, or checkable and not yet recorded.
    pub checkable: usize,
    /// The claims of the document's worked examples.
    pub claims: usize,
    /// Taken as input data.
    pub inputs: usize,
    /// Not checked, per reason.
    pub not_checked: BTreeMap<NotChecked, usize>,
}

impl Totals {
    /// One line: `Di Ruscio (…): 62 statements — 46 of 47 checkable checked strictly by claims or
    /// figures (97.9 %), …`.
    pub fn line(&self) -> String {
        format!("{}: {}", self.title, self.counts())
    }

    /// The counts: `62 statements — 46 of 47 checkable checked strictly by claims or figures
    /// (97.9 %), 3 input data, …`.
    pub fn counts(&self) -> String {
        let mut parts = vec![
            format!(
                "{} of {} checkable checked strictly by claims or figures ({})",
                self.recorded,
                self.checkable,
                percent(self.recorded, self.checkable)
            ),
            format!("{} input data", self.inputs),
        ];
        for (why, n) in &self.not_checked {
            parts.push(format!("{n} {}", why.words()));
        }
        format!("{} statements — {}", self.statements, parts.join(", "))
    }
}

/// `part` of `whole` as a percentage with one decimal (`92.1 %`; `—` of nothing).
pub fn percent(part: usize, whole: usize) -> String {
    if whole == 0 {
        return "—".to_string();
    }
    #[allow(clippy::cast_precision_loss)] // counts of statements, far below 2^52
    let p = 100.0 * part as f64 / whole as f64;
    format!("{p:.1} %")
}

/// The totals over every list: recorded strictly, checkable, claims about the documents.
pub fn overall(totals: &[Totals]) -> String {
    let recorded: usize = totals.iter().map(|t| t.recorded).sum();
    let checkable: usize = totals.iter().map(|t| t.checkable).sum();
    let claims: usize = totals.iter().map(|t| t.claims).sum();
    let statements: usize = totals.iter().map(|t| t.statements).sum();
    format!(
        "Counted strictly (one statement, one check): {recorded} of {checkable} checkable statements recorded ({}), of {statements} statements listed; {claims} claims about the documents",
        percent(recorded, checkable)
    )
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
    let mut refs = References::default();
    let mut totals = Totals {
        document: list.document.clone(),
        title: list.title.clone(),
        statements: list.statements.len(),
        recorded: 0,
        checkable: 0,
        inputs: 0,
        claims: mine.iter().map(|e| e.claims.len()).sum(),
        not_checked: BTreeMap::new(),
    };
    for s in &list.statements {
        refs.read(s, &mine, &list.document).map_err(error)?;
        totals.recorded += usize::from(!s.recorded.is_empty());
        totals.inputs += usize::from(s.input.is_some());
        if let Some(why) = s.not_checked {
            *totals.not_checked.entry(why).or_default() += 1;
        }
    }
    totals.checkable = totals.recorded
        + totals
            .not_checked
            .get(&NotChecked::NotYetRecorded)
            .copied()
            .unwrap_or(0);
    refs.every_item_listed(&mine, &list.document)
        .map_err(error)?;
    refs.shared_credits_listed(&mine).map_err(error)?;
    Ok(totals)
}

/// What a list's statements name, gathered statement by statement.
#[derive(Default)]
struct References<'l> {
    /// Every claim or figure named (recorded or related), as `example/item`.
    listed: Vec<String>,
    /// Claim → the statements (their `where`) that record it.
    credited: BTreeMap<String, Vec<&'l str>>,
}

impl<'l> References<'l> {
    /// One statement: exactly one way of being accounted for, every name existing in this
    /// document's examples, no figure without checks recorded as a check.
    fn read(
        &mut self,
        s: &'l Statement,
        mine: &[&ExampleFile],
        document: &str,
    ) -> Result<(), String> {
        let at = format!("statement at {} ('{}')", s.location, s.statement);
        let ways = usize::from(!s.recorded.is_empty())
            + usize::from(s.input.is_some())
            + usize::from(s.not_checked.is_some());
        if ways != 1 {
            return Err(format!(
                "{at}: give exactly one of recorded, input or not_checked"
            ));
        }
        for (r, strict) in s
            .recorded
            .iter()
            .map(|r| (r, true))
            .chain(s.related.iter().map(|r| (r, false)))
        {
            let (ex, item) = r
                .split_once('/')
                .ok_or_else(|| format!("{at}: '{r}' is not example/claim"))?;
            let e = mine
                .iter()
                .find(|e| e.id == ex)
                .ok_or_else(|| format!("{at}: no example '{ex}' of {document} (named '{r}')"))?;
            let claim = e.claims.iter().any(|c| c.id == item);
            let figure = e.scenarios.iter().find(|sc| sc.name == item);
            if !claim && figure.is_none() {
                return Err(format!(
                    "{at}: example '{ex}' has no claim or figure '{item}'"
                ));
            }
            if strict {
                if figure.is_some_and(|f| f.checks.is_empty()) {
                    return Err(format!(
                        "{at}: figure '{r}' has no checks of its own, so it checks nothing: name it under related"
                    ));
                }
                if claim {
                    self.credited
                        .entry(r.clone())
                        .or_default()
                        .push(&s.location);
                }
            }
            self.listed.push(r.clone());
        }
        if let Some(ex) = &s.input {
            if !mine.iter().any(|e| e.id == *ex) {
                return Err(format!("{at}: no example '{ex}' of {document}"));
            }
        }
        Ok(())
    }

    /// Every claim and figure of the document's examples is named by some statement.
    fn every_item_listed(&self, mine: &[&ExampleFile], document: &str) -> Result<(), String> {
        for e in mine {
            let items = e
                .claims
                .iter()
                .map(|c| &c.id)
                .chain(e.scenarios.iter().map(|s| &s.name));
            for item in items {
                let r = format!("{}/{item}", e.id);
                if !self.listed.contains(&r) {
                    return Err(format!(
                        "'{r}' checks {document} but no statement of the list records it"
                    ));
                }
            }
        }
        Ok(())
    }

    /// One statement, one check: a claim credited to several statements lists each of them in
    /// its `checks`, and a claim's `checks` names exactly the statements that record it.
    fn shared_credits_listed(&self, mine: &[&ExampleFile]) -> Result<(), String> {
        for e in mine {
            for c in &e.claims {
                let r = format!("{}/{}", e.id, c.id);
                let by = self.credited.get(&r).cloned().unwrap_or_default();
                let mut wanted: Vec<&str> = c.checks.iter().map(String::as_str).collect();
                wanted.sort_unstable();
                let mut got = by.clone();
                got.sort_unstable();
                if by.len() > 1 && wanted != got {
                    return Err(format!(
                        "'{r}' is recorded for {} statements ({}); a claim checks several only when its `checks` lists each of them",
                        by.len(),
                        by.join("; ")
                    ));
                }
                if !c.checks.is_empty() && wanted != got {
                    return Err(format!(
                        "'{r}' lists checks [{}] but is recorded for [{}]",
                        c.checks.join("; "),
                        by.join("; ")
                    ));
                }
            }
        }
        Ok(())
    }
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
