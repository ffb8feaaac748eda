//! Checking one claim against its print: the recomputation, at sample points of its symbols
//! when it has some (proved over the rational functions where it can be), and the agreement
//! with the print.

use super::compute::compute;
use super::format::{ClaimSpec, ExampleFile};
use super::inputs::{ComputeError, Inputs};
use super::load::{locate, WorkedError};
use super::value::{compare, Agreement, Value};

use crate::algebra::Rational;
use crate::derivation::Derivation;
use crate::syntax::{evaluate_with, parse_expression, parse_scalar, Environment};

pub(super) fn parameter_env(params: &std::collections::BTreeMap<String, String>) -> Environment {
    params
        .iter()
        .filter_map(|(k, v)| parse_scalar::<Rational>(v).ok().map(|r| (k.clone(), r)))
        .collect()
}

/// Small deterministic generator for sample points (xorshift).
pub(super) struct Sampler(u64);

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
        let negative = !name.starts_with('T') && self.next().is_multiple_of(2);
        Rational::new((if negative { -p } else { p }).into(), q.into())
    }
}

/// The outcome of checking one printed text under one environment.
pub(super) struct Check {
    pub(super) agreement: Agreement,
    /// The recomputed value (at the first sample point, when symbols were sampled).
    pub(super) value: Option<Value>,
    pub(super) recomputed: String,
    pub(super) derivation: Derivation,
    pub(super) sampled: Vec<String>,
    /// For a sampled claim: whether it was also proved over the rational functions.
    pub(super) proof: ProofNote,
}

/// What stands behind a sampled claim's verdict.
#[derive(Clone, Debug, Default)]
pub(super) enum ProofNote {
    /// Not sampled: computed exactly at the claim's values.
    #[default]
    Exact,
    /// Proved (or refuted) over the rational functions of the symbols.
    Proved,
    /// Only sampled, and why there is no proof.
    Sampled(String),
}

/// Adds the claim's `where` definitions (evaluated in `env`) to `env`.
pub(super) fn with_definitions(
    claim: &ClaimSpec,
    env: &Environment,
) -> Result<Environment, String> {
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
pub(super) fn check(
    file: &ExampleFile,
    claim: &ClaimSpec,
    printed: &str,
    env: &Environment,
) -> Result<Check, ComputeError> {
    // a printed equality evaluates its printed side: checking another text (an erratum's
    // correction) evaluates that text
    let owned;
    let claim = if claim.what == super::Computation::MatrixIdentity && claim.printed != printed {
        owned = ClaimSpec {
            printed: printed.to_string(),
            ..claim.clone()
        };
        &owned
    } else {
        claim
    };
    let at = Attempt {
        file,
        claim,
        printed,
    };
    let mut sampler = Sampler::new(&format!("{}/{}", file.id, claim.id));
    match at.symbols_to_sample(env, &mut sampler) {
        FirstTry::Done(result) => *result,
        FirstTry::Sample(sampled) => at.sampled(env, &sampled, &mut sampler),
    }
}

/// One claim checked against one printed text, at the symbol values given.
struct Attempt<'a> {
    file: &'a ExampleFile,
    claim: &'a ClaimSpec,
    printed: &'a str,
}

/// The outcome of the exact attempts: a result, or the symbols a division needs sampled.
enum FirstTry {
    Done(Box<Result<Check, ComputeError>>),
    Sample(Vec<String>),
}

impl Attempt<'_> {
    fn at(&self, env: &Environment) -> Result<Check, ComputeError> {
        let (file, claim) = (self.file, self.claim);
        let computed = compute(&Inputs { file, claim, env })?;
        let penv = with_definitions(claim, env).map_err(ComputeError::Failed)?;
        let agreement =
            compare(&computed.value, self.printed, &penv).map_err(|m| ComputeError::Input {
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
    }

    /// Exact first; the free symbols that a division needs are collected for sampling.
    fn symbols_to_sample(&self, env: &Environment, sampler: &mut Sampler) -> FirstTry {
        let mut env0 = env.clone();
        let mut sampled: Vec<String> = Vec::new();
        for _ in 0..8 {
            match self.at(&env0) {
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
                        return FirstTry::Done(Box::new(other));
                    }
                    break;
                }
            }
        }
        if sampled.is_empty() {
            FirstTry::Done(Box::new(self.at(&env0)))
        } else {
            FirstTry::Sample(sampled)
        }
    }

    /// SAMPLES independent points of the sampled symbols, each exact; the first disagreement
    /// refutes, shown at the example's own values when it has them.
    fn sampled(
        &self,
        env: &Environment,
        sampled: &[String],
        sampler: &mut Sampler,
    ) -> Result<Check, ComputeError> {
        let inputs = Inputs {
            file: self.file,
            claim: self.claim,
            env,
        };
        let point = |e: &Environment| -> Vec<String> {
            sampled.iter().map(|n| format!("{n} = {}", e[n])).collect()
        };
        let mut good = 0;
        let mut first: Option<Check> = None;
        let mut last_error = String::new();
        for _ in 0..SAMPLE_ATTEMPTS {
            let mut e = env.clone();
            for n in sampled {
                e.insert(n.clone(), sampler.value(n));
            }
            match self.at(&e) {
                Ok(c) if !c.agreement.holds() => {
                    let (shown, c, whose) = match self.disagreement_at_own_values(env, sampled) {
                        Some((o, c)) if sampled.len() == 1 => {
                            (point(&o), c, " (the example's value)")
                        }
                        Some((o, c)) => (point(&o), c, " (the example's values)"),
                        None => (point(&e), c, ""),
                    };
                    return Ok(with_proof(
                        Check {
                            recomputed: format!("at {}{whose}: {}", shown.join(", "), c.recomputed),
                            sampled: sampled.to_vec(),
                            ..c
                        },
                        &inputs,
                        self.printed,
                    ));
                }
                Ok(c) => {
                    good += 1;
                    if first.is_none() {
                        first = Some(Check {
                            recomputed: format!(
                                "agrees exactly at {SAMPLES} random rational points of {}; e.g. at {}: {}",
                                sampled.join(", "),
                                point(&e).join(", "),
                                c.recomputed
                            ),
                            sampled: sampled.to_vec(),
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
            Some(c) if good == SAMPLES => Ok(with_proof(c, &inputs, self.printed)),
            _ => Err(ComputeError::Failed(format!(
                "could not find {SAMPLES} sample points where the computation is defined ({last_error})"
            ))),
        }
    }

    /// The check at the example's own values of the sampled symbols (Example 7.1's T = 1/8),
    /// when it gives every one and the print disagrees there too.
    fn disagreement_at_own_values(
        &self,
        env: &Environment,
        sampled: &[String],
    ) -> Option<(Environment, Check)> {
        let own = parameter_env(&self.file.parameters);
        if !sampled.iter().all(|n| own.contains_key(n)) {
            return None;
        }
        let mut o = env.clone();
        for n in sampled {
            o.insert(n.clone(), own[n].clone());
        }
        let c = self.at(&o).ok().filter(|c| !c.agreement.holds())?;
        Some((o, c))
    }
}

/// A sampled check, proved or refuted over the rational functions of its symbols where the
/// computation allows ([`super::proof`]); otherwise it says why it stays sampled.
pub(super) fn with_proof(c: Check, inputs: &Inputs<'_>, printed: &str) -> Check {
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

pub(super) fn how(a: &Agreement, c: &Check) -> String {
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
pub(super) fn input_error(
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
