//! Verdicts: holds, holds approximately (within a documented tolerance, for a documented
//! reason), documented erratum (checked), unreproducible (the document leaves the print
//! undefined; every reading computed), or mismatch.

use super::checking::{check, input_error, parameter_env, Check, ProofNote};
use super::computation::Computation;
use super::format::{ExampleFile, Severity};
use super::inputs::ComputeError;
use super::load::WorkedError;
use super::outcome::{ClaimReport, ExampleReport};
use super::value::Agreement;
use super::verdicts::{verdict, ClaimContext};
use crate::derivation::Derivation;
use std::path::Path;

/// Recomputes every claim of an example.
///
/// # Errors
/// [`WorkedError`] when a claim's inputs are malformed (bad matrix, unknown method…).
pub fn verify_example(
    path: &Path,
    ex: &ExampleFile,
    raw: &str,
) -> Result<ExampleReport, WorkedError> {
    let env = parameter_env(&ex.parameters);
    let file = path.display().to_string();
    let mut claims = Vec::new();
    for claim in &ex.claims {
        let mut env = env.clone();
        for s in &claim.symbols {
            env.remove(s);
        }
        // An identity claim prints a formula; the document asserts that it holds.
        let asserted = if claim.what == Computation::Identity {
            "true"
        } else {
            claim.printed.as_str()
        };
        let cx = ClaimContext {
            ex,
            claim,
            asserted,
            env: &env,
            file: &file,
            raw,
        };
        let primary = match check(ex, claim, asserted, &env) {
            Ok(c) => c,
            Err(ComputeError::Input { field, message }) => {
                return Err(input_error(&file, raw, claim, &field, message))
            }
            Err(e) => Check {
                agreement: Agreement::Differs(format!("could not recompute: {e}")),
                value: None,
                recomputed: "—".into(),
                derivation: Derivation::new(&claim.id),
                sampled: Vec::new(),
                proof: ProofNote::Exact,
            },
        };
        let (verdict, explanation) = verdict(&cx, &primary)?;
        claims.push(ClaimReport {
            id: claim.id.clone(),
            source: claim.source.clone(),
            printed: claim.printed.clone(),
            recomputed: primary.recomputed,
            verdict,
            explanation: if claim.note.is_empty() {
                explanation
            } else {
                format!("{explanation}. Note: {}", claim.note)
            },
            derivation: primary.derivation,
            severity: claim
                .erratum
                .as_ref()
                .map(|e| e.severity.unwrap_or(Severity::ChangesResult)),
        });
    }
    Ok(ExampleReport {
        id: ex.id.clone(),
        title: ex.title.clone(),
        document: ex.document.clone(),
        document_title: super::coverage::document_title(&ex.document).map(str::to_string),
        claims,
        printed_only: ex.printed_only.clone(),
    })
}
