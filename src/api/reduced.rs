//! `owb reduced` (a reduced-order observer, Gopinath's construction) and `owb detectable` (an
//! observer for the observable part of an unobservable pair, with the fixed modes named).

use super::args::{json_matrix, json_matrix_shown, Plant, SystemPair};
use super::parametric::{lift, Parametric};
use super::{Outcome, Report};
use crate::algebra::{Fraction, Rational, Ring};
use crate::linalg::Matrix;
use crate::observer::detectability::detectable_design_from;
use crate::observer::reduced_order::{reduced_order_observer, reduced_order_symbolic};
use crate::observer::Convention;
use anyhow::{anyhow, bail, Result};
use serde_json::json;

/// Arguments of `owb reduced`.
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "commands", derive(clap::Args))]
pub struct Args {
    /// The plant's A and C (`a`, `c`).
    #[serde(flatten)]
    #[cfg_attr(feature = "commands", command(flatten))]
    pub system: SystemPair,
    /// The input matrix B (optional: gives the observer's input term H).
    #[cfg_attr(feature = "commands", arg(allow_hyphen_values = true, long))]
    #[serde(default)]
    pub b: Option<String>,
    /// The error polynomial, of degree n − p (the unmeasured states).
    #[serde(flatten)]
    #[cfg_attr(feature = "commands", command(flatten))]
    pub desired: super::args::DesiredArgs,
    /// ackermann (default), bass-gura or canonical.
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, default_value_t = super::args::defaults::method())
    )]
    #[serde(default = "super::args::defaults::method")]
    pub method: String,
    /// a-kc (default: A₂₂ − L A₁₂) or a+lc (A₂₂ + L A₁₂).
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, default_value_t = super::args::defaults::observer_convention())
    )]
    #[serde(default = "super::args::defaults::observer_convention")]
    pub convention: String,
    /// Machine-readable output.
    #[cfg_attr(feature = "commands", arg(long))]
    #[serde(default)]
    pub json: bool,
}

/// `owb reduced`: the reduced-order observer.
///
/// # Errors
///
/// What the request gets wrong (named by its flag) or what the computation refuses.
pub fn run(args: Args, rep: &mut Report) -> Result<Outcome> {
    let b_has_parameters = args
        .b
        .as_deref()
        .is_some_and(super::args::mentions_parameters);
    let (a, c) = match args.system.plant()? {
        Plant::Symbolic(a, c) => return symbolic(&args, &a, &c, rep),
        Plant::Numeric(a, c)
            if args.system.at.is_none()
                && (args.desired.mentions_parameters() || b_has_parameters) =>
        {
            return symbolic(&args, &lift(&a), &lift(&c), rep)
        }
        Plant::Numeric(a, c) => (a, c),
    };
    let b = args.system.input(args.b.as_deref())?;
    super::args::check_plant(&a, b.as_ref(), &c, None)?;
    let (method, convention) = (
        super::args::gain_method(&args.method)?,
        super::args::observer_convention(&args.convention)?,
    );
    let order = a.rows().saturating_sub(c.rows());
    let desired = args.desired.parse_at(order, &args.system.values()?)?;
    let r = reduced_order_observer(&a, b.as_ref(), &c, &desired, method)?;
    if args.json {
        let mut out = super::args::object(vec![
            ("convention", convention.flag().into()),
            ("method", method.flag().into()),
            ("q", json_matrix(&r.q)),
            ("gain", json_matrix(&r.gain(convention))),
            ("f", json_matrix_shown(&r.f, r.derivation.step("F"))),
            ("g", json_matrix(&r.g)),
            ("direct", json_matrix(&r.direct)),
            ("from_w", json_matrix(&r.from_w)),
            ("error_polynomial", r.error_polynomial.to_input().into()),
            (
                "noise_gain",
                crate::algebra::Ring::to_input(&r.noise_gain).into(),
            ),
            ("output", r.output.map(|k| k + 1).into()),
        ]);
        if let Some(h) = &r.h {
            out["h"] = json_matrix(h);
        }
        rep.json_with_steps(out, r.derivation.steps)?;
        return Ok(Outcome::Ok);
    }
    rep.derivation(&r.derivation);
    let letter = if convention == Convention::AMinusKC {
        "L (A₂₂ − L A₁₂)"
    } else {
        "L (A₂₂ + L A₁₂)"
    };
    outln!(
        rep,
        "Result (reduced-order observer of order {order}, {method} method):"
    );
    outln!(rep, "  {letter} = {}", r.gain(convention).to_input());
    if let Some(k) = r.output {
        outln!(rep, "  designed with output {} (the row of A₁₂ that observes the unmeasured states); the other columns of L are zero", k + 1);
    }
    outln!(
        rep,
        "  ẇ = F w + G y{}, x̂ = D_y y + M w, w = z₂ {} L y",
        if r.h.is_some() { " + H u" } else { "" },
        if convention == Convention::AMinusKC {
            "−"
        } else {
            "+"
        }
    );
    outln!(rep, "  error polynomial det(sI − F) = {} (degree {order}; the full-order observer's has degree {})", r.error_polynomial, a.rows());
    outln!(rep,
        "  measurement noise: y reaches x̂ directly through D_y, Σ D_y² = {} (the full-order observer filters y: no direct term)",
        r.noise_gain
    );
    Ok(Outcome::Ok)
}

/// `owb reduced` with parameters in A, B or the desired polynomial (C in numbers: the measured
/// combinations fix Q): the same construction in symbols, the error polynomial an identity,
/// and where the design breaks.
fn symbolic(
    args: &Args,
    a: &Matrix<Fraction>,
    c: &Matrix<Fraction>,
    rep: &mut Report,
) -> Result<Outcome> {
    let (method, convention) = (
        super::args::gain_method(&args.method)?,
        super::args::observer_convention(&args.convention)?,
    );
    let c_numbers: Matrix<Rational> = match c
        .entries()
        .iter()
        .map(Fraction::as_rational)
        .collect::<Option<Vec<_>>>()
    {
        Some(entries) => Matrix::from_fn(c.rows(), c.cols(), |i, j| {
            entries[i * c.cols() + j].clone()
        }),
        None => bail!("in --c: a reduced-order design with parameters needs C in numbers (C fixes the coordinates z = Q x); give the parameters in C values with --at NAME=VALUE"),
    };
    let b = args
        .b
        .as_deref()
        .map(|t| super::args::matrix::<Fraction>("--b", t))
        .transpose()?;
    let zeros = |m: &Matrix<Fraction>| m.map(|_| Rational::from_integer(0.into()));
    super::args::check_plant(&zeros(a), b.as_ref().map(zeros).as_ref(), &c_numbers, None)?;
    let order = a.rows().saturating_sub(c.rows());
    let desired = args.desired.symbolic(order)?;
    let mut work = Parametric::new(a)?
        .with(b.as_ref().map_or(&[][..], Matrix::entries), "B")?
        .with(desired.coeffs(), "the desired polynomial")?;
    let r = work.run(|| reduced_order_symbolic(a, b.as_ref(), &c_numbers, &desired, method))??;
    let (a22, row) = &r.reduced_pair;
    if let Some(det) = work.run(|| super::parametric::observability_determinant(a22, row))? {
        work.note(
            det.numerator(),
            "det O of the reduced pair (A₂₂, A₁₂): unobservable there",
        )?;
    }
    work.note_denominators(r.l.entries(), "a denominator of the gain")?;
    let gain = convention.from_a_minus_kc(&r.l);
    let json = args
        .json
        .then(|| -> Result<serde_json::Value> {
            let mut out = json!({
                "convention": convention.flag(),
                "method": method.flag(),
                "q": json_matrix(&r.q),
                "gain": json_matrix(&gain),
                "f": json_matrix_shown(&r.f, r.derivation.step("F")),
                "g": json_matrix(&r.g),
                "direct": json_matrix(&r.direct),
                "from_w": json_matrix(&r.from_w),
                "error_polynomial": r.error_polynomial.to_input(),
                "places_exactly": r.identity,
                "noise_gain": crate::algebra::Ring::to_input(&r.noise_gain),
                "output": r.output.map(|k| k + 1),
                "steps": serde_json::to_value(&r.derivation.steps)?,
            });
            if let Some(h) = &r.h {
                out["h"] = json_matrix(h);
            }
            Ok(out)
        })
        .transpose()?;
    work.answer(rep, json, |rep| {
        rep.derivation(&r.derivation);
        let letter = if convention == Convention::AMinusKC {
            "L (A₂₂ − L A₁₂)"
        } else {
            "L (A₂₂ + L A₁₂)"
        };
        outln!(
            rep,
            "Result (reduced-order observer of order {order}, {method} method):"
        );
        outln!(rep, "  {letter} = {}", gain.to_input());
        if let Some(k) = r.output {
            outln!(rep, "  designed with output {} (the row of A₁₂ that observes the unmeasured states); the other columns of L are zero", k + 1);
        }
        outln!(
            rep,
            "  ẇ = F w + G y{}, x̂ = D_y y + M w, w = z₂ {} L y",
            if r.h.is_some() { " + H u" } else { "" },
            if convention == Convention::AMinusKC {
                "−"
            } else {
                "+"
            }
        );
        outln!(
            rep,
            "  error polynomial det(sI − F) = {} (degree {order})",
            r.error_polynomial
        );
        outln!(
            rep,
            "  {}",
            if r.identity {
                format!(
                    "the error polynomial equals the desired polynomial identically in s and {}",
                    work.names()
                )
            } else {
                "the error polynomial differs from the desired polynomial".to_string()
            }
        );
        outln!(
            rep,
            "  measurement noise: y reaches x̂ directly through D_y, Σ D_y² = {}",
            crate::algebra::Ring::to_input(&r.noise_gain)
        );
    });
    Ok(Outcome::Ok)
}

/// Arguments of `owb detectable`.
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "commands", derive(clap::Args))]
pub struct DetectableArgs {
    /// The plant's A and C (`a`, `c`).
    #[serde(flatten)]
    #[cfg_attr(feature = "commands", command(flatten))]
    pub system: SystemPair,
    /// The polynomial of the observable part, of degree r = rank O_n.
    #[serde(flatten)]
    #[cfg_attr(feature = "commands", command(flatten))]
    pub desired: super::args::DesiredArgs,
    /// ackermann (default), bass-gura or canonical.
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, default_value_t = super::args::defaults::method())
    )]
    #[serde(default = "super::args::defaults::method")]
    pub method: String,
    /// a-kc (default) or a+lc.
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, default_value_t = super::args::defaults::observer_convention())
    )]
    #[serde(default = "super::args::defaults::observer_convention")]
    pub convention: String,
    /// Machine-readable output.
    #[cfg_attr(feature = "commands", arg(long))]
    #[serde(default)]
    pub json: bool,
}

/// `owb detectable`: an observer for an unobservable but detectable pair.
///
/// # Errors
///
/// What the request gets wrong (named by its flag) or what the computation refuses.
pub fn detectable(args: DetectableArgs, rep: &mut Report) -> Result<Outcome> {
    let (a, c) = match args.system.plant()? {
        Plant::Symbolic(a, c) => return detectable_with_parameters(&args, &a, &c, rep),
        Plant::Numeric(a, c) if args.system.at.is_none() && args.desired.mentions_parameters() => {
            return detectable_with_parameters(&args, &lift(&a), &lift(&c), rep)
        }
        Plant::Numeric(a, c) => (a, c),
    };
    super::args::check_plant(&a, None, &c, None)?;
    let (method, convention) = (
        super::args::gain_method(&args.method)?,
        super::args::observer_convention(&args.convention)?,
    );
    let report = crate::observability::observability_rank_report(&a, &c)?;
    let rank = report.rank;
    if rank == 0 {
        anyhow::bail!(
            "no mode is observable (O_n = 0): every observer keeps the poles of A, {}",
            report.unobservable_eigenvalues.render()
        );
    }
    let desired = args
        .desired
        .parse_at(rank, &args.system.values()?)
        .map_err(|e| anyhow!("{e} (here: the observable part, rank O_n = {rank})"))?;
    let d = detectable_design_from(report, &a, &c, &desired, method, convention)?;
    let fixed = d.report.unobservable_eigenvalues.render();
    if args.json {
        rep.json_with_steps(
            json!({
                "convention": convention.flag(),
                "method": method.flag(),
                "rank": rank,
                "order": a.rows(),
                "detectable": d.detectable,
                "fixed_poles": fixed,
                "unobservable_polynomial": d.report.unobservable_polynomial.to_input(),
                "t": json_matrix(&d.t),
                "decomposed_a": json_matrix(&d.a_decomposed),
                "gain": json_matrix(&d.gain),
                "observer_polynomial": d.observer_polynomial.to_input(),
                "polynomial_checks": d.polynomial_checks(),
            }),
            d.derivation.steps,
        )?;
        return Ok(Outcome::Ok);
    }
    rep.derivation(&d.derivation);
    outln!(rep, "Result ({convention} convention, {method} method):");
    outln!(
        rep,
        "  rank O_n = {rank} of {}: {} observable mode(s) placed, {} fixed",
        a.rows(),
        rank,
        a.rows() - rank
    );
    outln!(rep, "  fixed (unobservable) poles: {fixed}");
    outln!(rep, "  {} = {}", convention.letter(), d.gain.to_input());
    outln!(
        rep,
        "  observer polynomial = {} = desired × det(sI − A_uu): {}",
        d.observer_polynomial,
        if d.polynomial_checks() {
            "checked exactly"
        } else {
            "NOT equal"
        }
    );
    if d.detectable {
        outln!(
            rep,
            "  detectable: every unobservable mode is stable, so this observer's error decays"
        );
    } else {
        outln!(
            rep,
            "  NOT detectable: an unobservable mode is not stable; no gain makes the error decay"
        );
    }
    Ok(Outcome::Ok)
}

/// `owb detectable` with parameters in A, C or the desired polynomial: the decomposition for
/// generic values of the parameters, the observable part's gain in symbols, the observer
/// polynomial an identity, and detectability as conditions on the parameters (the Hurwitz
/// determinants of the unobservable polynomial); where the design breaks, as for the others.
fn detectable_with_parameters(
    args: &DetectableArgs,
    a: &Matrix<Fraction>,
    c: &Matrix<Fraction>,
    rep: &mut Report,
) -> Result<Outcome> {
    let (method, convention) = (
        super::args::gain_method(&args.method)?,
        super::args::observer_convention(&args.convention)?,
    );
    let zeros = |m: &Matrix<Fraction>| m.map(|_| Rational::from_integer(0.into()));
    super::args::check_plant(&zeros(a), None, &zeros(c), None)?;
    let work = Parametric::new(a)?.with(c.entries(), "C")?;
    let o = work.run(|| crate::observability::observability_matrix(a, c))??;
    let rank = work.run(|| crate::linalg::rank(&o))?;
    let desired = args
        .desired
        .symbolic(rank)
        .map_err(|e| anyhow!("{e} (here: the observable part, rank O_n = {rank} for generic values of the parameters)"))?;
    let mut work = work.with(desired.coeffs(), "the desired polynomial")?;
    let d = work.run(|| {
        crate::observer::detectability::detectable_symbolic(a, c, &desired, method, convention)
    })??;
    let (a_oo, c_o) = &d.observable_pair;
    if let Some(det) = work.run(|| super::parametric::observability_determinant(a_oo, c_o))? {
        work.note(
            det.numerator(),
            "det O of the observable part (A_oo, C_o): fewer modes observable there",
        )?;
    }
    work.note_denominators(d.t.entries(), "a denominator of T")?;
    work.note_denominators(d.gain.entries(), "a denominator of the gain")?;
    let (detectable, conditions) = d.verdict();
    let json = args
        .json
        .then(|| detectable_json(&d, convention, method, a.rows(), detectable, &conditions))
        .transpose()?;
    work.answer(rep, json, |rep| {
        detectable_text(
            rep,
            &d,
            &work,
            (convention, method),
            a.rows(),
            detectable,
            &conditions,
        );
    });
    Ok(Outcome::Ok)
}

/// `owb detectable --json` with parameters.
fn detectable_json(
    d: &crate::observer::detectability::SymbolicDetectable,
    convention: Convention,
    method: crate::observer::GainMethod,
    order: usize,
    detectable: Option<bool>,
    conditions: &[&Fraction],
) -> Result<serde_json::Value> {
    Ok(json!({
        "convention": convention.flag(),
        "method": method.flag(),
        "rank": d.rank,
        "order": order,
        "detectable": detectable,
        "detectable_when": conditions.iter().map(|x| format!("{} > 0", x.to_input())).collect::<Vec<_>>(),
        "unobservable_polynomial": d.unobservable_polynomial.to_input(),
        "t": json_matrix(&d.t),
        "decomposed_a": json_matrix(&d.a_decomposed),
        "gain": json_matrix(&d.gain),
        "observer_polynomial": d.observer_polynomial.to_input(),
        "polynomial_checks": d.identity,
        "steps": serde_json::to_value(&d.derivation.steps)?,
    }))
}

/// The text of `owb detectable` with parameters, after the derivation.
fn detectable_text(
    rep: &mut Report,
    d: &crate::observer::detectability::SymbolicDetectable,
    work: &Parametric,
    (convention, method): (Convention, crate::observer::GainMethod),
    n: usize,
    detectable: Option<bool>,
    conditions: &[&Fraction],
) {
    rep.derivation(&d.derivation);
    outln!(rep, "Result ({convention} convention, {method} method):");
    outln!(
            rep,
            "  rank O_n = {} of {n} for generic values of the parameters: {} observable mode(s) placed, {} fixed",
            d.rank,
            d.rank,
            n - d.rank
        );
    if d.rank == n {
        outln!(
            rep,
            "  fixed (unobservable) modes: none (observable for generic values of the parameters)"
        );
    } else {
        outln!(
            rep,
            "  fixed (unobservable) modes: the roots of det(sI − A_uu) = {}",
            d.unobservable_polynomial
        );
    }
    outln!(rep, "  {} = {}", convention.letter(), d.gain.to_input());
    outln!(
        rep,
        "  observer polynomial = {} = desired × det(sI − A_uu): {}",
        d.observer_polynomial,
        if d.identity {
            format!("an identity in s and {}", work.names())
        } else {
            "NOT equal".to_string()
        }
    );
    match detectable {
            Some(true) => outln!(
                rep,
                "  detectable for every value: every unobservable mode is stable, so this observer's error decays"
            ),
            Some(false) => outln!(
                rep,
                "  NOT detectable for any value: an unobservable mode is not stable; no gain makes the error decay"
            ),
            None => outln!(
                rep,
                "  detectable exactly when {} (Routh–Hurwitz on det(sI − A_uu)): then this observer's error decays; otherwise no gain makes it decay",
                conditions
                    .iter()
                    .map(|x| format!("{x} > 0"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        }
}
