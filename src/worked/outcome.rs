//! What verifying a worked example reports: a verdict per claim, the claims of an example, the
//! totals.

use super::format::{PrintedRecord, Severity};
use crate::derivation::Derivation;
use serde::Serialize;

/// A verdict on one printed claim.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// The print is right (exactly, or to the precision printed).
    Holds,
    /// The print is a design target, a graph reading or a rounded value, and the recomputed
    /// value is within the tolerance the example states for it.
    HoldsApproximately,
    /// The print is wrong, and the example documents why; the explanation was checked.
    Erratum,
    /// The document leaves undefined what the print is; no reading reproduces it (each is shown).
    Unreproducible,
    /// The print is wrong and unexplained (or the explanation does not check).
    Mismatch,
}

impl Verdict {
    /// The word used in reports.
    pub fn word(self) -> &'static str {
        match self {
            Verdict::Holds => "holds",
            Verdict::HoldsApproximately => "holds approximately",
            Verdict::Erratum => "erratum",
            Verdict::Unreproducible => "unreproducible",
            Verdict::Mismatch => "mismatch",
        }
    }
    /// The value of `verdict` in `--json` (snake case).
    pub fn key(self) -> &'static str {
        match self {
            Verdict::HoldsApproximately => "holds_approximately",
            other => other.word(),
        }
    }
}

/// One claim, recomputed and judged.
#[derive(Debug, Clone, Serialize)]
pub struct ClaimReport {
    /// Claim identifier.
    pub id: String,
    /// Where the document prints it.
    pub source: String,
    /// As printed.
    pub printed: String,
    /// As recomputed (input syntax), or how it was checked.
    pub recomputed: String,
    /// The verdict.
    pub verdict: Verdict,
    /// Why (precision, erratum and its check, or the difference).
    pub explanation: String,
    /// The computation's working.
    #[serde(skip)]
    pub derivation: Derivation,
    /// For an erratum, how much it matters.
    #[serde(skip)]
    pub severity: Option<Severity>,
}

/// One example, verified.
#[derive(Debug, Clone, Serialize)]
pub struct ExampleReport {
    /// Example identifier.
    pub id: String,
    /// Title.
    #[serde(skip)]
    pub title: String,
    /// Source document file name.
    pub document: String,
    /// The source document's author and title (`null` for the course's cross-checks, which
    /// have no document).
    pub document_title: Option<String>,
    /// The claims.
    pub claims: Vec<ClaimReport>,
    /// Printed values awaiting another part of the workbench.
    #[serde(skip)]
    pub printed_only: Vec<PrintedRecord>,
}

/// Counts of verdicts.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct Summary {
    /// Claims that hold.
    pub holds: usize,
    /// Claims that hold within a documented tolerance.
    pub holds_approximately: usize,
    /// Documented errata.
    pub erratum: usize,
    /// Claims the documents leave undefined.
    pub unreproducible: usize,
    /// Mismatches.
    pub mismatch: usize,
}

impl Summary {
    /// Counts over reports.
    pub fn of(reports: &[ExampleReport]) -> Summary {
        let mut s = Summary::default();
        for c in reports.iter().flat_map(|r| &r.claims) {
            match c.verdict {
                Verdict::Holds => s.holds += 1,
                Verdict::HoldsApproximately => s.holds_approximately += 1,
                Verdict::Erratum => s.erratum += 1,
                Verdict::Unreproducible => s.unreproducible += 1,
                Verdict::Mismatch => s.mismatch += 1,
            }
        }
        s
    }
}
