//! From a recomputation to a verdict: how an erratum, a documented approximation or an
//! unreproducible print is checked, and how far a value is from its print.

use super::checking::{check, how, input_error, parameter_env, Check};
use super::format::{ApproximateSpec, ClaimSpec, ErratumSpec, ExampleFile, UnreproducibleSpec};
use super::inputs::ComputeError;
use super::load::Tolerance;
use super::load::WorkedError;
use super::outcome::Verdict;
use super::value::{Agreement, Value};
use crate::syntax::{evaluate_with, Environment};

/// One claim of an example, with what it is checked against.
pub(super) struct ClaimContext<'a> {
    pub(super) ex: &'a ExampleFile,
    pub(super) claim: &'a ClaimSpec,
    /// What the document asserts (`"true"` for an identity).
    pub(super) asserted: &'a str,
    pub(super) env: &'a Environment,
    pub(super) file: &'a str,
    pub(super) raw: &'a str,
}

/// Whether the print is reproduced with the erratum's changed inputs (`list`, in words), and
/// what the check found.
pub(super) fn reproduced_with(
    list: &[String],
    result: Result<Check, ComputeError>,
) -> (bool, String) {
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
pub(super) fn erratum_checks(
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
pub(super) fn verdict(
    cx: &ClaimContext<'_>,
    primary: &Check,
) -> Result<(Verdict, String), WorkedError> {
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

/// The largest distance `(absolute, relative to the print)` between the print and the
/// recomputed value, entry by entry (the nearest of the recomputed candidates), for numeric
/// values; `None` for values that are not lists of numbers.
pub(super) fn deviation(value: &Value, printed: &str, env: &Environment) -> Option<(f64, f64)> {
    let candidates: Vec<Vec<f64>> = match value {
        Value::Approximate { candidates, .. } => candidates.clone(),
        Value::Scalar(x) => vec![vec![x.to_complex_f64().0]],
        Value::Matrix(m) => vec![m.entries().iter().map(|x| x.to_complex_f64().0).collect()],
        Value::Polynomial(q) => return polynomial_deviation(q, printed, env),
        // a polynomial in its variable only (no other symbol): its numeric coefficients
        Value::SymbolicPolynomial(q, var) => {
            let coefficients = q
                .coefficients_in(var)
                .iter()
                .map(|c| c.as_constant().map(crate::algebra::Quadratic::rational))
                .collect::<Option<Vec<_>>>()?;
            let q = crate::poly::Poly::new(coefficients, var);
            return polynomial_deviation(&q, printed, env);
        }
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

/// The largest deviation of a recomputed polynomial's coefficients from the printed ones (a
/// polynomial printed factored, `(λ + 4)^3`, is expanded first).
fn polynomial_deviation(
    q: &crate::poly::Poly<crate::algebra::Quadratic>,
    printed: &str,
    env: &Environment,
) -> Option<(f64, f64)> {
    let p = super::value::printed_polynomial(printed, q.var(), env).ok()?;
    let n = p.degree()?.max(q.degree()?);
    Some((0..=n).fold((0.0f64, 0.0f64), |(a, r), k| {
        let (x, y) = (q.coeff(k).to_complex_f64().0, p.coeff(k).to_complex_f64().0);
        let d = (x - y).abs();
        (a.max(d), r.max(d / y.abs().max(f64::MIN_POSITIVE)))
    }))
}

pub(super) fn show_deviation((absolute, relative): (f64, f64)) -> String {
    let absolute = if absolute != 0.0 && !(1e-3..1e6).contains(&absolute) {
        format!("{absolute:.3e}")
    } else {
        format!("{absolute:.4}")
    };
    if relative != 0.0 && relative < 5e-5 {
        // below what two decimals of a percentage show
        format!("off by {absolute} ({relative:.1e} of the print)")
    } else if relative < 10.0 {
        format!("off by {absolute} ({:.2}% of the print)", relative * 100.0)
    } else {
        format!("off by {absolute} ({relative:.0} times the print)")
    }
}

/// A print that should hold within a tolerance: holds approximately, or a mismatch.
pub(super) fn approximate_verdict(
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
pub(super) fn unreproducible_verdict(
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
