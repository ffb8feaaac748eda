//! Verdicts: holds, holds approximately (within a documented tolerance, for a documented
//! reason), documented erratum (checked), unreproducible (the document leaves the print
//! undefined; every reading computed), or mismatch.

use super::computation::Computation;
use super::compute::compute;
use super::format::{
    ApproximateSpec, ClaimSpec, ErratumSpec, ExampleFile, PrintedRecord, Severity,
    UnreproducibleSpec,
};
use super::inputs::{ComputeError, Inputs};
use super::value::{compare, Agreement, Value};
use crate::algebra::{Rational, ToF64};
use crate::derivation::Derivation;
use crate::syntax::{evaluate_with, parse_expression, parse_scalar, Environment};
use serde::Serialize;
use std::path::{Path, PathBuf};

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

/// A worked-example file that cannot be used, located by file, line and field.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{file}:{line}: {field}: {message}")]
pub struct WorkedError {
    /// The file.
    pub file: String,
    /// 1-based line (0 when unknown).
    pub line: usize,
    /// The field or claim.
    pub field: String,
    /// What is wrong.
    pub message: String,
}

/// The 1-based line of `field = …` inside the block that starts at the line `key = "value"`
/// (a claim's `id`, a scenario's `name`), or from the top when `block` is `None`; the block's
/// own line when the field is not written there.
pub(crate) fn locate(raw: &str, block: Option<(&str, &str)>, field: &str) -> usize {
    let lines: Vec<&str> = raw.lines().collect();
    let assigns = |l: &str, key: &str| {
        l.trim_start()
            .strip_prefix(key)
            .is_some_and(|r| r.trim_start().starts_with('='))
    };
    let start = match block {
        Some((key, value)) => lines
            .iter()
            .position(|l| assigns(l, key) && l.contains(&format!("\"{value}\"")))
            .unwrap_or(0),
        None => 0,
    };
    lines
        .iter()
        .enumerate()
        .skip(start)
        .find(|(_, l)| assigns(l, field))
        .map_or(start + 1, |(i, _)| i + 1)
}

/// The field a TOML error at 1-based `line` concerns, named as the other errors name fields:
/// `claims.L.what` (the table, the block's `id` or `name`, the key written on that line);
/// `toml` when the line assigns nothing (a syntax error).
pub(crate) fn toml_field(raw: &str, line: usize) -> String {
    let lines: Vec<&str> = raw.lines().collect();
    let Some(here) = line.checked_sub(1).and_then(|i| lines.get(i)) else {
        return "toml".into();
    };
    let key_of = |l: &str| -> Option<String> {
        let (k, _) = l.split_once('=')?;
        let k = k.trim();
        let bare = !k.is_empty()
            && k.chars()
                .all(|c| c.is_alphanumeric() || matches!(c, '_' | '-' | '.'));
        bare.then(|| k.to_string())
    };
    let Some(key) = key_of(here) else {
        return "toml".into();
    };
    let header = (0..line - 1).rev().find_map(|i| {
        let t = lines[i].trim();
        t.starts_with('[')
            .then(|| (i, t.trim_matches(|c| c == '[' || c == ']').to_string()))
    });
    let Some((start, table)) = header else {
        return key;
    };
    // the block's name: its `id` or `name`, wherever in the block it is written
    let end = (start + 1..lines.len())
        .find(|&i| lines[i].trim_start().starts_with('['))
        .unwrap_or(lines.len());
    let name = lines[start + 1..end].iter().find_map(|l| {
        let k = key_of(l)?;
        if k != "id" && k != "name" {
            return None;
        }
        let v = l.split_once('=')?.1.trim();
        Some(v.trim_matches('"').to_string())
    });
    match name {
        Some(n) if key != "id" && key != "name" => format!("{table}.{n}.{key}"),
        _ => format!("{table}.{key}"),
    }
}

/// Reads and checks one example file.
///
/// # Errors
/// [`WorkedError`] naming file, line and field for malformed TOML, unknown fields, bad
/// parameter values, duplicate or unknown claim kinds.
pub fn load_example(path: &Path) -> Result<(ExampleFile, String), WorkedError> {
    let file = path.display().to_string();
    let raw = std::fs::read_to_string(path).map_err(|e| WorkedError {
        file: file.clone(),
        line: 0,
        field: "file".into(),
        message: e.to_string(),
    })?;
    let ex = parse_example(&file, &raw)?;
    Ok((ex, raw))
}

/// Parses and checks the text of a worked-example file (`file` names it in errors).
///
/// # Errors
/// [`WorkedError`] with file, line and field.
pub fn parse_example(file: &str, raw: &str) -> Result<ExampleFile, WorkedError> {
    let file = file.to_string();
    let raw = raw.to_string();
    let ex: ExampleFile = toml::from_str(&raw).map_err(|e| {
        let line = e.span().map_or(0, |s| {
            raw[..s.start.min(raw.len())].matches('\n').count() + 1
        });
        WorkedError {
            file: file.clone(),
            line,
            field: toml_field(&raw, line),
            message: e.message().to_string(),
        }
    })?;
    for (name, value) in &ex.parameters {
        parse_scalar::<Rational>(value).map_err(|e| WorkedError {
            file: file.clone(),
            line: locate(&raw, None, name),
            field: format!("parameters.{name}"),
            message: e.show_in(value),
        })?;
    }
    let mut seen = std::collections::BTreeSet::new();
    for c in &ex.claims {
        if !seen.insert(c.id.clone()) {
            return Err(WorkedError {
                file: file.clone(),
                line: locate(&raw, Some(("id", &c.id)), "id"),
                field: "id".into(),
                message: format!("claim id '{}' appears twice", c.id),
            });
        }
        let bad = |field: &str, message: String| WorkedError {
            file: file.clone(),
            line: locate(&raw, Some(("id", &c.id)), field),
            field: format!("claims.{}.{field}", c.id),
            message,
        };
        let documented = [
            c.erratum.is_some(),
            c.approximate.is_some(),
            c.unreproducible.is_some(),
        ];
        if documented.iter().filter(|&&d| d).count() > 1 {
            return Err(bad(
                "erratum",
                "give at most one of erratum, approximate and unreproducible".into(),
            ));
        }
        if let Some(a) = &c.approximate {
            Tolerance::parse(&a.tolerance).map_err(|m| bad("tolerance", m))?;
        }
    }
    Ok(ex)
}

/// Every `*.toml` in a folder (not recursive), sorted by file name.
///
/// # Errors
/// [`WorkedError`] for an unreadable folder.
pub fn load_folder(dir: &Path) -> Result<Vec<PathBuf>, WorkedError> {
    let entries = std::fs::read_dir(dir).map_err(|e| WorkedError {
        file: dir.display().to_string(),
        line: 0,
        field: "folder".into(),
        message: e.to_string(),
    })?;
    let mut files: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    Ok(files)
}

fn parameter_env(params: &std::collections::BTreeMap<String, String>) -> Environment {
    params
        .iter()
        .filter_map(|(k, v)| parse_scalar::<Rational>(v).ok().map(|r| (k.clone(), r)))
        .collect()
}

/// Small deterministic generator for sample points (xorshift).
struct Sampler(u64);

impl Sampler {
    fn new(seed: &str) -> Self {
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        for b in seed.bytes() {
            h = (h ^ b as u64).wrapping_mul(0x0100_0000_01b3);
        }
        Sampler(h | 1)
    }
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    /// A nonzero rational p/q, |p| ≤ 9, 1 ≤ q ≤ 4; positive for time constants (`T…`).
    fn value(&mut self, name: &str) -> Rational {
        let p = (self.next() % 9 + 1) as i64;
        let q = (self.next() % 4 + 1) as i64;
        let negative = !name.starts_with('T') && self.next() % 2 == 0;
        Rational::new((if negative { -p } else { p }).into(), q.into())
    }
}

/// The outcome of checking one printed text under one environment.
struct Check {
    agreement: Agreement,
    /// The recomputed value (at the first sample point, when symbols were sampled).
    value: Option<Value>,
    recomputed: String,
    derivation: Derivation,
    sampled: Vec<String>,
    /// For a sampled claim: whether it was also proved over the rational functions.
    proof: ProofNote,
}

/// What stands behind a sampled claim's verdict.
#[derive(Clone, Debug, Default)]
enum ProofNote {
    /// Not sampled: computed exactly at the claim's values.
    #[default]
    Exact,
    /// Proved (or refuted) over the rational functions of the symbols.
    Proved,
    /// Only sampled, and why there is no proof.
    Sampled(String),
}

/// Adds the claim's `where` definitions (evaluated in `env`) to `env`.
fn with_definitions(claim: &ClaimSpec, env: &Environment) -> Result<Environment, String> {
    let mut env = env.clone();
    for _ in 0..=claim.definitions.len() {
        for (name, text) in &claim.definitions {
            if env.contains_key(name) {
                continue;
            }
            let e =
                parse_expression(text).map_err(|e| format!("where.{name}: {}", e.show_in(text)))?;
            if let Ok(v) = evaluate_with::<Rational>(&e, &env) {
                env.insert(name.clone(), v);
            }
        }
    }
    Ok(env)
}

const SAMPLES: usize = 5;
const SAMPLE_ATTEMPTS: usize = 40;

/// Recomputes and compares `printed` in `env`, sampling free symbols when needed.
fn check(
    file: &ExampleFile,
    claim: &ClaimSpec,
    printed: &str,
    env: &Environment,
) -> Result<Check, ComputeError> {
    let attempt = |env: &Environment| -> Result<Check, ComputeError> {
        let computed = compute(&Inputs { file, claim, env })?;
        let penv = with_definitions(claim, env).map_err(ComputeError::Failed)?;
        let agreement =
            compare(&computed.value, printed, &penv).map_err(|m| ComputeError::Input {
                field: "printed".into(),
                message: m.to_string(),
            })?;
        Ok(Check {
            agreement,
            recomputed: computed.value.input(),
            value: Some(computed.value),
            derivation: computed.derivation,
            sampled: Vec::new(),
            proof: ProofNote::Exact,
        })
    };
    // Exact first; free symbols that a division needs are sampled.
    let mut env0 = env.clone();
    let mut sampled: Vec<String> = Vec::new();
    let mut sampler = Sampler::new(&format!("{}/{}", file.id, claim.id));
    for _ in 0..8 {
        match attempt(&env0) {
            Err(ComputeError::NeedsValues(names)) => {
                for n in names {
                    if !env0.contains_key(&n) {
                        let v = sampler.value(&n);
                        env0.insert(n.clone(), v);
                        sampled.push(n);
                    }
                }
            }
            // singular at this point (a sampled value hit a pole): try other values
            Err(e) if !sampled.is_empty() && e.is_failure() => {
                for n in &sampled {
                    let v = sampler.value(n);
                    env0.insert(n.clone(), v);
                }
            }
            other => {
                if sampled.is_empty() {
                    return other;
                }
                break;
            }
        }
    }
    if sampled.is_empty() {
        return attempt(&env0);
    }
    // Sampled: SAMPLES independent points, each exact.
    let mut good = 0;
    let mut first: Option<Check> = None;
    let mut last_error = String::new();
    for _ in 0..SAMPLE_ATTEMPTS {
        let mut e = env.clone();
        for n in &sampled {
            e.insert(n.clone(), sampler.value(n));
        }
        match attempt(&e) {
            Ok(c) => {
                let point: Vec<String> =
                    sampled.iter().map(|n| format!("{n} = {}", e[n])).collect();
                if !c.agreement.holds() {
                    return Ok(with_proof(
                        Check {
                            recomputed: format!("at {}: {}", point.join(", "), c.recomputed),
                            sampled: sampled.clone(),
                            ..c
                        },
                        &Inputs { file, claim, env },
                        printed,
                    ));
                }
                good += 1;
                if first.is_none() {
                    first = Some(Check {
                        recomputed: format!(
                            "agrees exactly at {SAMPLES} random rational points of {}; e.g. at {}: {}",
                            sampled.join(", "),
                            point.join(", "),
                            c.recomputed
                        ),
                        sampled: sampled.clone(),
                        ..c
                    });
                }
                if good == SAMPLES {
                    break;
                }
            }
            Err(ComputeError::Input { field, message }) => {
                return Err(ComputeError::Input { field, message })
            }
            Err(e) => last_error = e.to_string(),
        }
    }
    match first {
        Some(c) if good == SAMPLES => Ok(with_proof(c, &Inputs { file, claim, env }, printed)),
        _ => Err(ComputeError::Failed(format!(
            "could not find {SAMPLES} sample points where the computation is defined ({last_error})"
        ))),
    }
}

/// A sampled check, proved or refuted over the rational functions of its symbols where the
/// computation allows ([`super::proof`]); otherwise it says why it stays sampled.
fn with_proof(c: Check, inputs: &Inputs<'_>, printed: &str) -> Check {
    let proof = with_definitions(inputs.claim, inputs.env)
        .map_err(super::proof::NoProof::from)
        .and_then(|penv| super::proof::prove(inputs, printed, &penv));
    let symbols = |p: &super::proof::Proof| {
        if p.symbols.is_empty() {
            c.sampled.join(", ")
        } else {
            p.symbols.join(", ")
        }
    };
    match (proof, &c.agreement) {
        (Err(why), _) => Check {
            proof: ProofNote::Sampled(why.to_string()),
            ..c
        },
        (Ok(_), Agreement::Rounded { .. }) => Check {
            proof: ProofNote::Sampled("the print is rounded, so it is no identity to prove".into()),
            ..c
        },
        (Ok(p), Agreement::Exact) if p.holds => Check {
            recomputed: format!(
                "{} — proved over the rational functions of {} by {}; {}",
                p.value,
                symbols(&p),
                p.method,
                c.recomputed
            ),
            proof: ProofNote::Proved,
            ..c
        },
        (Ok(p), a) => Check {
            agreement: Agreement::Differs(format!(
                "{}as rational functions of {} the print differs from {} ({})",
                match a {
                    Agreement::Differs(d) => format!("{d}; "),
                    _ => String::new(),
                },
                symbols(&p),
                p.value,
                p.method
            )),
            recomputed: format!("{} — {}", p.value, c.recomputed),
            proof: ProofNote::Proved,
            ..c
        },
    }
}

fn how(a: &Agreement, c: &Check) -> String {
    let sampled = &c.sampled;
    let base = match a {
        Agreement::Exact => "exactly".to_string(),
        Agreement::Rounded { digits } if *digits >= 0 => {
            format!("to the {digits} decimals printed (rounding)")
        }
        Agreement::Rounded { digits } => {
            format!(
                "to the precision printed (units of 1e{}, rounding)",
                -digits
            )
        }
        Agreement::Differs(d) => d.clone(),
    };
    if sampled.is_empty() {
        base
    } else {
        match &c.proof {
            ProofNote::Proved => format!(
                "{base}, proved as an identity in {} (over the rational functions)",
                sampled.join(", ")
            ),
            ProofNote::Sampled(why) => format!(
                "{base}, as an identity in {} (exact at {SAMPLES} random rational points; not proved: {why})",
                sampled.join(", ")
            ),
            ProofNote::Exact => base,
        }
    }
}

/// Where a claim's input error is reported: the claim's own field, or the `[system]` matrix
/// it did not override.
fn input_error(
    file: &str,
    raw: &str,
    claim: &ClaimSpec,
    field: &str,
    message: String,
) -> WorkedError {
    let key = field.split('.').next().unwrap_or(field);
    // A matrix the claim does not override comes from [system].
    let in_claim = match key {
        "A" => claim.a.is_some(),
        "B" => claim.b.is_some(),
        "C" => claim.c.is_some(),
        "D" => false,
        _ => true,
    };
    if in_claim {
        WorkedError {
            file: file.into(),
            line: locate(raw, Some(("id", &claim.id)), key),
            field: format!("claims.{}.{field}", claim.id),
            message,
        }
    } else {
        WorkedError {
            file: file.into(),
            line: locate(raw, None, key),
            field: format!("system.{field} (used by claim {})", claim.id),
            message,
        }
    }
}

/// One claim of an example, with what it is checked against.
struct ClaimContext<'a> {
    ex: &'a ExampleFile,
    claim: &'a ClaimSpec,
    /// What the document asserts (`"true"` for an identity).
    asserted: &'a str,
    env: &'a Environment,
    file: &'a str,
    raw: &'a str,
}

/// Whether the print is reproduced with the erratum's changed inputs (`list`, in words), and
/// what the check found.
fn reproduced_with(list: &[String], result: Result<Check, ComputeError>) -> (bool, String) {
    match result {
        Ok(c) if c.agreement.holds() => (
            true,
            format!(
                "checked: with {} the print is reproduced {}",
                list.join(", "),
                how(&c.agreement, &c)
            ),
        ),
        Ok(c) => (
            false,
            format!(
                "NOT confirmed: with {} the print is still not reproduced ({})",
                list.join(", "),
                how(&c.agreement, &c)
            ),
        ),
        Err(e) => (false, format!("NOT confirmed: {e}")),
    }
}

/// The checks of a documented erratum: the print reproduced with the erratum's parameters, the
/// corrected value holding. `(all confirmed, what each check found)`.
fn erratum_checks(
    cx: &ClaimContext<'_>,
    err: &ErratumSpec,
) -> Result<(bool, Vec<String>), WorkedError> {
    let ClaimContext {
        ex,
        claim,
        asserted,
        env,
        ..
    } = *cx;
    let mut checks = Vec::new();
    let mut ok = true;
    if !err.parameters.is_empty() {
        let mut env2 = env.clone();
        env2.extend(parameter_env(&err.parameters));
        let list: Vec<String> = err
            .parameters
            .iter()
            .map(|(k, v)| format!("{k} = {v}"))
            .collect();
        let (confirmed, said) = reproduced_with(&list, check(ex, claim, asserted, &env2));
        ok &= confirmed;
        checks.push(said);
    }
    if !err.matrices.is_empty() {
        let mut fixed = claim.clone();
        fixed.matrices.extend(err.matrices.clone());
        let list: Vec<String> = err
            .matrices
            .iter()
            .map(|(k, v)| format!("{k} = {v}"))
            .collect();
        let (confirmed, said) = reproduced_with(&list, check(ex, &fixed, asserted, env));
        ok &= confirmed;
        checks.push(said);
    }
    if let Some(corrected) = &err.corrected {
        match check(ex, claim, corrected, env) {
            Ok(c) if c.agreement.holds() => checks.push(format!(
                "checked: the corrected value {corrected} holds {}",
                how(&c.agreement, &c)
            )),
            Ok(c) => {
                ok = false;
                checks.push(format!(
                    "NOT confirmed: the corrected value {corrected} does not hold either ({})",
                    how(&c.agreement, &c)
                ));
            }
            Err(ComputeError::Input { message, .. }) => {
                return Err(input_error(
                    cx.file,
                    cx.raw,
                    claim,
                    "erratum.corrected",
                    message,
                ))
            }
            Err(e) => {
                ok = false;
                checks.push(format!("NOT confirmed: {e}"));
            }
        }
    }
    if checks.is_empty() {
        ok = false;
        checks
            .push("the erratum gives nothing to check (parameters, matrices or corrected)".into());
    }
    Ok((ok, checks))
}

/// The verdict on one claim and its explanation, from the recomputation.
fn verdict(cx: &ClaimContext<'_>, primary: &Check) -> Result<(Verdict, String), WorkedError> {
    let claim = cx.claim;
    let documented = [
        claim.erratum.as_ref().map(|_| "an erratum"),
        claim.approximate.as_ref().map(|_| "an approximation"),
        claim.unreproducible.as_ref().map(|_| "an undefined print"),
    ]
    .into_iter()
    .flatten()
    .next();
    let d = match &primary.agreement {
        a if a.holds() => {
            return Ok(match documented {
                None => (Verdict::Holds, how(a, primary)),
                Some(what) => (
                    Verdict::Mismatch,
                    format!(
                        "{what} is documented, but the print holds ({})",
                        how(a, primary)
                    ),
                ),
            })
        }
        Agreement::Differs(d) => d,
        Agreement::Exact | Agreement::Rounded { .. } => unreachable!("holds() covers them"),
    };
    if let Some(err) = &claim.erratum {
        let (ok, checks) = erratum_checks(cx, err)?;
        let text = format!(
            "{} Printed vs recomputed: {d}. {}",
            err.explanation.trim(),
            checks.join("; ")
        );
        return Ok((
            if ok {
                Verdict::Erratum
            } else {
                Verdict::Mismatch
            },
            text,
        ));
    }
    if let Some(spec) = &claim.approximate {
        return Ok(approximate_verdict(cx, primary, spec, d));
    }
    if let Some(spec) = &claim.unreproducible {
        return Ok(unreproducible_verdict(cx, primary, spec));
    }
    Ok((Verdict::Mismatch, d.clone()))
}

/// A tolerance on every entry: relative (`"1.5%"`) or absolute (`"0.5"`).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Tolerance {
    Relative(f64),
    Absolute(f64),
}

impl Tolerance {
    fn parse(text: &str) -> Result<Tolerance, String> {
        let t = text.trim();
        let (number, relative) = match t.strip_suffix('%') {
            Some(n) => (n, true),
            None => (t, false),
        };
        let x = parse_scalar::<Rational>(number.trim())
            .map_err(|e| e.show_in(number))?
            .to_f64();
        if !(x.is_finite() && x > 0.0) {
            return Err(format!("'{text}': a tolerance must be positive"));
        }
        Ok(if relative {
            Tolerance::Relative(x / 100.0)
        } else {
            Tolerance::Absolute(x)
        })
    }
    fn admits(self, (absolute, relative): (f64, f64)) -> bool {
        match self {
            Tolerance::Relative(r) => relative <= r,
            Tolerance::Absolute(a) => absolute <= a,
        }
    }
    fn show(self) -> String {
        match self {
            Tolerance::Relative(r) => format!("{}%", r * 100.0),
            Tolerance::Absolute(a) => format!("{a}"),
        }
    }
}

/// The largest distance `(absolute, relative to the print)` between the print and the
/// recomputed value, entry by entry (the nearest of the recomputed candidates), for numeric
/// values; `None` for values that are not lists of numbers.
fn deviation(value: &Value, printed: &str, env: &Environment) -> Option<(f64, f64)> {
    let candidates: Vec<Vec<f64>> = match value {
        Value::Approximate { candidates, .. } => candidates.clone(),
        Value::Scalar(x) => vec![vec![x.to_complex_f64().0]],
        Value::Matrix(m) => vec![m.entries().iter().map(|x| x.to_complex_f64().0).collect()],
        _ => return None,
    };
    let rows = crate::syntax::parse_matrix_expressions(printed).ok()?;
    let p: Vec<f64> = rows
        .iter()
        .flatten()
        .map(|e| evaluate_with::<crate::algebra::Quadratic>(e, env).map(|x| x.to_complex_f64().0))
        .collect::<Result<_, _>>()
        .ok()?;
    candidates
        .iter()
        .filter(|c| c.len() == p.len())
        .map(|c| {
            c.iter().zip(&p).fold((0.0f64, 0.0f64), |(a, r), (x, y)| {
                let d = (x - y).abs();
                (a.max(d), r.max(d / y.abs().max(f64::MIN_POSITIVE)))
            })
        })
        .min_by(|x, y| x.1.total_cmp(&y.1))
}

fn show_deviation((absolute, relative): (f64, f64)) -> String {
    let absolute = if absolute != 0.0 && !(1e-3..1e6).contains(&absolute) {
        format!("{absolute:.3e}")
    } else {
        format!("{absolute:.4}")
    };
    if relative < 10.0 {
        format!("off by {absolute} ({:.2}% of the print)", relative * 100.0)
    } else {
        format!("off by {absolute} ({relative:.0} times the print)")
    }
}

/// A print that should hold within a tolerance: holds approximately, or a mismatch.
fn approximate_verdict(
    cx: &ClaimContext<'_>,
    primary: &Check,
    spec: &ApproximateSpec,
    differs: &str,
) -> (Verdict, String) {
    // the tolerance was checked when the file was read
    let Ok(tolerance) = Tolerance::parse(&spec.tolerance) else {
        return (
            Verdict::Mismatch,
            format!("bad tolerance '{}'", spec.tolerance),
        );
    };
    let found = primary
        .value
        .as_ref()
        .and_then(|v| deviation(v, cx.asserted, cx.env));
    let why = format!(
        "the print is {}: {}",
        spec.kind.words(),
        spec.reason.trim().trim_end_matches('.')
    );
    match found {
        Some(dev) if tolerance.admits(dev) => (
            Verdict::HoldsApproximately,
            format!(
                "within {} ({}); recomputed {}, {}",
                tolerance.show(),
                why,
                primary.recomputed,
                show_deviation(dev)
            ),
        ),
        Some(dev) => (
            Verdict::Mismatch,
            format!(
                "outside the documented tolerance {} ({}): {}",
                tolerance.show(),
                why,
                show_deviation(dev)
            ),
        ),
        None => (
            Verdict::Mismatch,
            format!("an approximation is documented, but the value is not numeric: {differs}"),
        ),
    }
}

/// A print the document leaves undefined: every reading computed; unreproducible unless one of
/// them reproduces the print (then the claim should be recorded as that reading).
fn unreproducible_verdict(
    cx: &ClaimContext<'_>,
    primary: &Check,
    spec: &UnreproducibleSpec,
) -> (Verdict, String) {
    let describe = |c: &Check| match c
        .value
        .as_ref()
        .and_then(|v| deviation(v, cx.asserted, cx.env))
    {
        Some(dev) => format!("{} ({})", c.recomputed, show_deviation(dev)),
        None => c.recomputed.clone(),
    };
    let mut readings = vec![format!(
        "as recorded ({}): {}",
        cx.claim.what,
        describe(primary)
    )];
    for r in &spec.readings {
        let variant = ClaimSpec {
            what: r.what,
            ..cx.claim.clone()
        };
        match check(cx.ex, &variant, cx.asserted, cx.env) {
            Ok(c) if c.agreement.holds() => {
                return (
                    Verdict::Mismatch,
                    format!(
                        "the reading '{}' ({}) reproduces the print {}: record the claim as that computation",
                        r.reading,
                        r.what,
                        how(&c.agreement, &c)
                    ),
                )
            }
            Ok(c) => readings.push(format!("{} ({}): {}", r.reading, r.what, describe(&c))),
            Err(e) => readings.push(format!("{} ({}): could not recompute: {e}", r.reading, r.what)),
        }
    }
    (
        Verdict::Unreproducible,
        format!(
            "the document does not define {}; no reading reproduces the print. Readings: {}",
            spec.undefined.trim(),
            readings.join("; ")
        ),
    )
}

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
        claims,
        printed_only: ex.printed_only.clone(),
    })
}

#[cfg(test)]
mod tests {
    use super::toml_field;

    #[test]
    fn toml_errors_name_the_field_of_their_line() {
        let raw = "id = \"x\"\n\n[[claims]]\nid = \"L\"\nwhat = \"gian\"\n\n[system]\nA = \"[1\"\n";
        assert_eq!(toml_field(raw, 1), "id");
        assert_eq!(toml_field(raw, 5), "claims.L.what");
        assert_eq!(toml_field(raw, 4), "claims.id");
        assert_eq!(toml_field(raw, 8), "system.A");
        assert_eq!(toml_field(raw, 3), "toml");
        assert_eq!(toml_field(raw, 0), "toml");
        assert_eq!(toml_field(raw, 99), "toml");
    }
}
