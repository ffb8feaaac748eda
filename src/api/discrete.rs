//! `owb discrete` (a discrete-time observer: prediction or current estimator, dead-beat, poles
//! from a continuous specification) and `owb zoh` (a continuous plant sampled with a
//! zero-order hold).

use super::args::{json_matrix, json_matrix_shown, Plant, SystemPair};
use super::parametric::{lift, Parametric};
use super::{Outcome, Report};
use crate::algebra::{Fraction, Quadratic, Rational};
use crate::linalg::Matrix;
use crate::observer::discrete::{
    deadbeat_polynomial, discrete_observer, from_continuous_poles, map_pole, speak_of_z,
    zero_order_hold, zero_order_hold_words, Estimator, Sampled,
};
use crate::observer::discrete_kalman::READ_BACK_BITS;
use crate::observer::float_check::float_check;
use crate::observer::{Convention, DesiredPolynomial, Detail};
use crate::poly::Poly;
use crate::symbolic::DesiredRequest;
use crate::syntax::{parse_list, parse_polynomial};
use anyhow::{anyhow, bail, Result};
use num_traits::{One, Zero};
use serde_json::json;

/// Arguments of `owb discrete`.
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "commands", derive(clap::Args))]
pub struct Args {
    /// The plant's A and C (`a`, `c`).
    #[serde(flatten)]
    #[cfg_attr(feature = "commands", command(flatten))]
    pub system: SystemPair,
    /// Desired observer poles in the z-plane, e.g. "1/2, 1/4" or "0.5+0.2i, 0.5-0.2i".
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, group = "desired")
    )]
    #[serde(default)]
    pub poles: Option<String>,
    /// Desired observer polynomial in z, e.g. "z^2 - z + 1/4".
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, group = "desired")
    )]
    #[serde(default)]
    pub poly: Option<String>,
    /// Dead-beat: every pole at z = 0 (the error is zero after at most n steps).
    #[cfg_attr(feature = "commands", arg(long, group = "desired"))]
    #[serde(default)]
    pub deadbeat: bool,
    /// Continuous-time poles s, mapped to z = e^(sT) with --period.
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, group = "desired")
    )]
    #[serde(default)]
    pub continuous_poles: Option<String>,
    /// The sampling period T (with --continuous-poles).
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, value_name = "T")
    )]
    #[serde(default)]
    pub period: Option<String>,
    /// prediction (default) or current (filtered: corrects x̂(k) with y(k)).
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, default_value_t = super::args::defaults::estimator())
    )]
    #[serde(default = "super::args::defaults::estimator")]
    pub estimator: String,
    /// ackermann (default), bass-gura or canonical.
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, default_value_t = super::args::defaults::method())
    )]
    #[serde(default = "super::args::defaults::method")]
    pub method: String,
    /// a-kc (default: A − KC) or a+lc (A + LC).
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

fn desired(
    args: &Args,
    n: usize,
    values: &crate::syntax::Environment,
) -> Result<DesiredPolynomial> {
    if args.period.is_some() && args.continuous_poles.is_none() {
        bail!("in --period: the period maps --continuous-poles; give them too");
    }
    let none = crate::syntax::Environment::new();
    Ok(
        if let Some(p) = args
            .poles
            .as_ref()
            .filter(|p| !values.is_empty() && DesiredRequest::Poles(p).mentions_parameters(&none))
        {
            // parameters with values from --at
            let read = DesiredRequest::Poles(p)
                .values(values)
                .map_err(|e| anyhow!("in --poles: {e}"))?;
            if read.len() != n {
                bail!(
                    "in --poles: {} poles given, the system has order {n}",
                    read.len()
                );
            }
            DesiredPolynomial::from_poles(&super::args::numbers("--poles", read)?)?
        } else if let Some(p) = args.poly.as_ref().filter(|p| {
            !values.is_empty() && !crate::symbolic::polynomial_parameters(p, "z").is_empty()
        }) {
            let read = crate::symbolic::coefficients_in(p, "z", values)
                .map_err(|e| anyhow!("in --poly: {e}"))?;
            DesiredPolynomial::from_polynomial(
                Poly::new(super::args::numbers("--poly", read)?, "s"),
                n,
            )?
        } else if let Some(p) = &args.poles {
            super::args::poles_flag("--poles", p, n)?
        } else if let Some(p) = &args.poly {
            let poly = parse_polynomial::<Quadratic>(p, "z")
                .map_err(|e| anyhow!("in --poly: {}", e.show_in(p)))?
                .with_var("s");
            DesiredPolynomial::from_polynomial(poly, n)?
        } else if args.deadbeat {
            deadbeat_polynomial(n)
        } else if let Some(p) = &args.continuous_poles {
            let poles = parse_list::<Quadratic>(p)
                .map_err(|e| anyhow!("in --continuous-poles: {}", e.show_in(p)))?;
            if poles.len() != n {
                bail!(
                    "in --continuous-poles: {} poles given, the system has order {n}",
                    poles.len()
                );
            }
            let t = args.period.as_deref().ok_or_else(|| {
                anyhow!("in --continuous-poles: give the sampling period --period T")
            })?;
            let t = super::args::rational("--period", t)?;
            from_continuous_poles(&poles, &t).map_err(|e| anyhow!("in --period: {e}"))?
        } else {
            bail!("give the desired polynomial in z: --poles, --poly, --deadbeat or --continuous-poles with --period")
        },
    )
}

/// `--estimator`.
fn estimator(args: &Args) -> Result<Estimator> {
    Estimator::parse(&args.estimator).ok_or_else(|| {
        anyhow!(
            "in --estimator: unknown estimator '{}' (prediction or current)",
            args.estimator
        )
    })
}

/// Whether `--poles` or `--poly` mentions a parameter (`z` of the polynomial is its variable).
fn desired_mentions_parameters(args: &Args) -> bool {
    let env = crate::syntax::Environment::new();
    args.poles
        .as_deref()
        .is_some_and(|p| DesiredRequest::Poles(p).mentions_parameters(&env))
        || args
            .poly
            .as_deref()
            .is_some_and(|p| !crate::symbolic::polynomial_parameters(p, "z").is_empty())
}

/// `owb discrete`: a discrete-time observer.
///
/// # Errors
///
/// What the request gets wrong (named by its flag) or what the computation refuses.
pub fn run(args: Args, rep: &mut Report) -> Result<Outcome> {
    let (a, c) = match args.system.plant()? {
        Plant::Symbolic(a, c) => return symbolic(&args, &a, &c, rep),
        Plant::Numeric(a, c) if args.system.at.is_none() && desired_mentions_parameters(&args) => {
            return symbolic(&args, &lift(&a), &lift(&c), rep)
        }
        Plant::Numeric(a, c) => (a, c),
    };
    if !a.is_square() || c.cols() != a.rows() {
        bail!(
            "in --a/--c: A must be square and C have as many columns (A {}×{}, C {}×{})",
            a.rows(),
            a.cols(),
            c.rows(),
            c.cols()
        );
    }
    let method = super::args::gain_method(&args.method)?;
    let convention = super::args::observer_convention(&args.convention)?;
    let estimator = estimator(&args)?;
    let desired = desired(&args, a.rows(), &args.system.values()?)?;
    if desired.exact.is_none() {
        return float_only(rep, &args, &a, &c, &desired, convention);
    }
    let d = discrete_observer(
        &a,
        &c,
        &desired,
        method,
        convention,
        estimator,
        Detail::Full,
    )?;
    let polynomial = d.error_polynomial.to_input();
    if args.json {
        let mut out = json!({
            "estimator": estimator.flag(),
            "convention": convention.flag(),
            "method": method.flag(),
            "gain": json_matrix_shown(&d.design.gain.matrix, d.design.gain_step()),
            "error_polynomial": polynomial,
            "schur_stable": d.stable,
            "deadbeat_steps": d.nilpotent_index,
            "error_matrix": json_matrix(&d.error_matrix),
        });
        if let Some(l) = &d.current_gain {
            out["current_gain"] = json_matrix(l);
        }
        rep.json_with_steps(out, d.derivation.steps)?;
        return Ok(Outcome::Ok);
    }
    rep.derivation(&d.derivation);
    result_lines(
        rep,
        (estimator, convention, method),
        &d.design.gain_input(),
        d.current_gain.as_ref().map(|l| l.to_input()),
        &d.error_polynomial,
    );
    stability_line(
        rep,
        d.stable,
        "not decided exactly (irrational coefficients)",
    );
    if let Some(k) = d.nilpotent_index {
        outln!(rep, "  dead-beat: the error matrix is nilpotent, (error matrix)^{k} = 0 exactly, so e({k}) = 0 for every initial error");
    }
    Ok(Outcome::Ok)
}

/// The result's opening lines, numbers or formulas alike: the title, the prediction gain, the
/// current estimator's gain (when asked) and the error polynomial.
fn result_lines(
    rep: &mut Report,
    (estimator, convention, method): (Estimator, Convention, crate::observer::GainMethod),
    gain: &str,
    current_gain: Option<String>,
    error_polynomial: &dyn std::fmt::Display,
) {
    let letter = convention.letter();
    outln!(
        rep,
        "Result (discrete time, {} estimator, {convention} convention, {method} method):",
        estimator.flag()
    );
    outln!(rep, "  {letter} = {gain} (prediction gain)");
    if let Some(l) = current_gain {
        outln!(rep, "  {letter}_c = {l} (current estimator: x̂(k) = x̄(k) + {letter}_c (y(k) − C x̄(k)) in the A − KC sign)");
    }
    outln!(
        rep,
        "  error polynomial det(zI − {}) = {error_polynomial}",
        if estimator == Estimator::Current {
            "(A − L_c C A)"
        } else {
            "(A − KC)"
        }
    );
}

/// Whether the error decays, decided exactly; `undecided` says why it was not.
fn stability_line(rep: &mut Report, stable: Option<bool>, undecided: &str) {
    match stable {
        Some(true) => outln!(rep, "  every root strictly inside the unit circle (exact test): the estimation error decays"),
        Some(false) => outln!(rep, "  NOT every root inside the unit circle (exact test): the estimation error does not decay"),
        None => outln!(rep, "  stability {undecided}"),
    }
}

/// The desired polynomial in z of a design with parameters, as a polynomial in `s` over the
/// rational functions of them (the variable the design speaks of; the steps are renamed).
fn symbolic_desired(args: &Args, n: usize) -> Result<Poly<Fraction>> {
    let env = crate::syntax::Environment::new();
    if args.continuous_poles.is_some() {
        bail!("in --continuous-poles: z = e^(sT) is not a rational function of the parameters; give them values with --at NAME=VALUE");
    }
    if let Some(p) = &args.poles {
        DesiredRequest::Poles(p)
            .polynomial(&env, n)
            .map_err(|e| anyhow!("in --poles: {e}"))
    } else if let Some(p) = &args.poly {
        crate::symbolic::polynomial_in(p, "z", n).map_err(|e| anyhow!("in --poly: {e}"))
    } else if args.deadbeat {
        let mut coeffs = vec![Fraction::zero(); n];
        coeffs.push(Fraction::one());
        Ok(Poly::new(coeffs, "s"))
    } else {
        bail!("give the desired polynomial in z: --poles, --poly or --deadbeat")
    }
}

/// The smallest k ≤ n with Mᵏ = 0, by exact powers over the rational functions (a plant with
/// parameters is of order at most 8), or `None`.
fn symbolic_nilpotent_index(m: &Matrix<Fraction>) -> Result<Option<usize>> {
    let mut power = m.clone();
    for k in 1..=m.rows() {
        if power.entries().iter().all(Fraction::is_zero) {
            return Ok(Some(k));
        }
        power = power.mul(m)?;
    }
    Ok(None)
}

/// The error matrix of the estimator asked for (A − KC, or A − L_c C A with L_c = A⁻¹K), the
/// current gain L_c, and the dead-beat index, over the rational functions of the parameters.
type SymbolicError = (Matrix<Fraction>, Option<Matrix<Fraction>>, Option<usize>);

fn symbolic_error_matrix(
    a: &Matrix<Fraction>,
    c: &Matrix<Fraction>,
    k: &Matrix<Fraction>,
    estimator: Estimator,
) -> Result<SymbolicError> {
    let (m, l_c) = match estimator {
        Estimator::Prediction => (a.sub(&k.mul(c)?)?, None),
        Estimator::Current => {
            let a_inv = crate::linalg::inverse(a).map_err(|_| {
                anyhow!("the current estimator needs A invertible: det A is zero for every value of the parameters")
            })?;
            let l_c = a_inv.mul(k)?;
            let m = a.sub(&l_c.mul(&c.mul(a)?)?)?;
            (m, Some(l_c))
        }
    };
    let nilpotent = symbolic_nilpotent_index(&m)?;
    Ok((m, l_c, nilpotent))
}

/// `owb discrete` with parameters: the gain's steps in symbols (renamed to z), the error
/// polynomial checked as an identity, the current estimator's A⁻¹K where det A ≠ 0, dead-beat
/// proved by the powers of the error matrix, and where the result breaks.
fn symbolic(
    args: &Args,
    a: &Matrix<Fraction>,
    c: &Matrix<Fraction>,
    rep: &mut Report,
) -> Result<Outcome> {
    let method = super::args::gain_method(&args.method)?;
    let convention = super::args::observer_convention(&args.convention)?;
    let estimator = estimator(args)?;
    if c.rows() != 1 {
        bail!(
            "in --c: C has {} outputs; a design with parameters uses one output",
            c.rows()
        );
    }
    let n = a.rows();
    let desired = symbolic_desired(args, n)?;
    let mut work = Parametric::new(a)?
        .with(c.entries(), "C")?
        .with(desired.coeffs(), "the desired polynomial")?;
    let design = work.run(|| {
        crate::observer::design_symbolic(a, c, &desired, method, convention, Detail::Full)
    })??;
    work.observability(a, c)?;
    work.exceptions
        .add_denominators(design.gain.matrix.entries(), "a denominator of the gain");
    let mut derivation = design.derivation.clone();
    speak_of_z(&mut derivation);
    let k = design.gain.to_convention(Convention::AMinusKC).matrix;
    let (error_matrix, current_gain, nilpotent) =
        work.run(|| symbolic_error_matrix(a, c, &k, estimator))??;
    if let Some(l_c) = &current_gain {
        let det = work.run(|| crate::linalg::determinant(a))??;
        work.note(
            det.numerator(),
            "det A: the current estimator needs A invertible",
        )?;
        work.note_denominators(l_c.entries(), "a denominator of L_c")?;
        derivation.push("L_c", "A⁻¹ K (current estimator)", l_c);
        derivation.push("A − L_c C A", "error matrix of x̂", &error_matrix);
    }
    let error_polynomial = design.achieved.clone().with_var("z");
    if let Some(k) = nilpotent {
        derivation.push(
            &format!("power {k} of the error matrix"),
            "zero identically: the error vanishes after this many steps",
            &Matrix::<Fraction>::zeros(n, n),
        );
    }
    // stability is decided when the polynomial's coefficients are numbers
    let constant: Option<Vec<Rational>> = error_polynomial
        .coeffs()
        .iter()
        .map(Fraction::as_rational)
        .collect();
    let stable = constant.map(|c| crate::poly::is_schur(&Poly::new(c, "z")));
    let shown_current = current_gain.map(|l| convention.from_a_minus_kc(&l));
    let json = args
        .json
        .then(|| -> Result<serde_json::Value> {
            let mut out = json!({
                "estimator": estimator.flag(),
                "convention": convention.flag(),
                "method": method.flag(),
                "gain": json_matrix(&design.gain.matrix),
                "error_polynomial": error_polynomial.to_input(),
                "places_exactly": design.identity,
                "schur_stable": stable,
                "deadbeat_steps": nilpotent,
                "error_matrix": json_matrix(&error_matrix),
                "steps": serde_json::to_value(&derivation.steps)?,
            });
            if let Some(l) = &shown_current {
                out["current_gain"] = json_matrix(l);
            }
            Ok(out)
        })
        .transpose()?;
    work.answer(rep, json, |rep| {
        rep.derivation(&derivation);
        result_lines(
            rep,
            (estimator, convention, method),
            &design.gain.matrix.to_input(),
            shown_current.as_ref().map(|l| l.to_input()),
            &error_polynomial,
        );
        outln!(
            rep,
            "  {}",
            if design.identity {
                format!(
                    "the error polynomial equals the desired polynomial identically in z and {}",
                    work.names()
                )
            } else {
                "the error polynomial differs from the desired polynomial".to_string()
            }
        );
        stability_line(
            rep,
            stable,
            "depends on the parameters (the polynomial's coefficients are not numbers)",
        );
        if let Some(k) = nilpotent {
            outln!(rep, "  dead-beat: (error matrix)^{k} = 0 identically in the parameters, so e({k}) = 0 for every initial error");
        }
    });
    Ok(Outcome::Ok)
}

/// Poles mapped from continuous time are known in f64 only: the gain by the float path, checked.
fn float_only(
    rep: &mut Report,
    args: &Args,
    a: &crate::linalg::Matrix<Rational>,
    c: &crate::linalg::Matrix<Rational>,
    desired: &DesiredPolynomial,
    convention: Convention,
) -> Result<Outcome> {
    if c.rows() != 1 {
        bail!("in --c: the float path designs single-output observers");
    }
    let poles = args.continuous_poles.as_deref().unwrap_or_default();
    let s = parse_list::<Quadratic>(poles).map_err(|e| anyhow!("in --continuous-poles: {e}"))?;
    let t = super::args::rational("--period", args.period.as_deref().unwrap_or("0"))?;
    let z: Vec<(f64, f64)> = s.iter().map(|p| map_pole(p, &t)).collect();
    super::args::float_range("--a", a)?;
    super::args::float_range("--c", c)?;
    // the float path needs an observable pair, decided exactly
    crate::observability::require_observable(a, c)?;
    let check = float_check(a, c, &desired.float, None, None, 1e-6);
    if check.float_gain.is_none() {
        bail!("the float gain could not be computed (O_n is numerically singular, cond₂ = {:.3e}): no gain is reported", check.condition_number);
    }
    let gain: Vec<f64> = check
        .float_gain
        .clone()
        .unwrap_or_default()
        .iter()
        .map(|x| convention.sign() * x)
        .collect();
    if args.json {
        rep.json(json!({
            "convention": convention.flag(),
            "exact": false,
            "z_poles": z.iter().map(|(re, im)| json!({"re": re, "im": im})).collect::<Vec<_>>(),
            "error_polynomial": desired.float.to_input(),
            "gain": gain.iter().map(|x| vec![crate::algebra::float_text::exp(*x)]).collect::<Vec<_>>(),
            "inexact_reason": desired.inexact_reason,
            "float": serde_json::to_value(&check)?,
        }));
        return Ok(Outcome::Ok);
    }
    outln!(
        rep,
        "Poles mapped from continuous time, z = e^(sT), T = {t}:"
    );
    for (p, (re, im)) in s.iter().zip(&z) {
        outln!(
            rep,
            "  s = {p}  →  z = {re:.12} {} {:.12}i",
            if *im < 0.0 { "−" } else { "+" },
            im.abs()
        );
    }
    outln!(
        rep,
        "  {}",
        desired.inexact_reason.clone().unwrap_or_default()
    );
    outln!(
        rep,
        "  desired polynomial (f64): {}",
        desired.float.to_string().replace('s', "z")
    );
    let letter = convention.letter();
    let list: Vec<String> = gain.iter().map(|x| format!("{x:.10e}")).collect();
    outln!(
        rep,
        "  {letter} (f64, prediction estimator) = [{}]",
        list.join("; ")
    );
    outln!(
        rep,
        "  largest distance of the placed poles from the mapped ones = {:.3e}",
        check.max_pole_distance
    );
    if check.verdict == crate::observer::float_check::FloatVerdict::Reliable {
        outln!(rep, "  verdict: the float gain places the poles within tolerance (there is no exact gain to compare with)");
    } else {
        outln!(rep, "  verdict: {}", check.verdict.explain());
    }
    Ok(Outcome::Ok)
}

/// Arguments of `owb zoh`.
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "commands", derive(clap::Args))]
pub struct ZohArgs {
    /// The continuous system matrix A.
    #[cfg_attr(feature = "commands", arg(allow_hyphen_values = true, long))]
    pub a: String,
    /// The input matrix B.
    #[cfg_attr(feature = "commands", arg(allow_hyphen_values = true, long))]
    pub b: String,
    /// The sampling period T.
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, value_name = "T")
    )]
    pub period: String,
    /// Values for the parameters, e.g. "k=2, T=1/10": entries with letters are evaluated there.
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, value_name = "NAME=VALUE,…")
    )]
    #[serde(default)]
    pub at: Option<String>,
    /// Machine-readable output.
    #[cfg_attr(feature = "commands", arg(long))]
    #[serde(default)]
    pub json: bool,
}

/// `owb zoh`: a continuous plant sampled with a zero-order hold.
///
/// # Errors
///
/// What the request gets wrong (named by its flag) or what the computation refuses.
pub fn zoh(args: ZohArgs, rep: &mut Report) -> Result<Outcome> {
    let values = super::args::parameter_values(args.at.as_deref())?;
    let (s, t) = match (
        crate::syntax::word_fractions(&args.a),
        crate::syntax::word_fractions(&args.b),
    ) {
        // numbers the plain scanner reads: within f64's range, as the checks below find
        (Some(a), Some(b)) => {
            let t = super::args::rational_at("--period", &args.period, &values)?;
            (zero_order_hold_words(a, b, &t), t)
        }
        _ => {
            let a = super::args::matrix_at("--a", &args.a, &values)?;
            let b = super::args::matrix_at("--b", &args.b, &values)?;
            super::args::float_range("--a", &a)?;
            super::args::float_range("--b", &b)?;
            let t = super::args::rational_at("--period", &args.period, &values)?;
            // the plant's fractions are freed here, at the block's end, before the answer's
            // strings take their room
            (zero_order_hold(&a, &b, &t), t)
        }
    };
    let s = s.map_err(|e| anyhow!("in --a/--b/--period: {e}"))?;
    match (&s, args.json) {
        (Sampled::Exact { phi, gamma, index }, true) => rep.json(super::args::object(vec![
            ("exact", true.into()),
            ("phi", json_matrix(phi)),
            ("gamma", json_matrix(gamma)),
            ("nilpotent_index", (*index).into()),
        ])),
        (
            Sampled::Float {
                phi,
                gamma,
                error_estimate,
            },
            true,
        ) => rep.json_with_exp_matrices(
            super::args::object(vec![
                ("exact", false.into()),
                ("error_estimate", (*error_estimate).into()),
            ]),
            &[
                ("phi", super::args::ExpMatrix::Rows(phi)),
                ("gamma", super::args::ExpMatrix::Rows(gamma)),
            ],
        ),
        (Sampled::Exact { phi, gamma, index }, false) => {
            outln!(rep, "Zero-order hold, T = {t}: exact (A is nilpotent, A^{index} = 0, so e^(AT) = Σ_(k<{index}) (AT)^k/k!)");
            outln!(rep, "  Φ = e^(AT) = {}", phi.to_input());
            outln!(rep, "  Γ = ∫_0^T e^(Aτ) dτ B = {}", gamma.to_input());
        }
        (
            Sampled::Float {
                phi,
                gamma,
                error_estimate,
            },
            false,
        ) => {
            outln!(rep, "Zero-order hold, T = {t}: f64 (A is not nilpotent; e^(λT) is transcendental for rational λT ≠ 0)");
            let show = |m: &[Vec<f64>]| {
                m.iter()
                    .map(|r| {
                        r.iter()
                            .map(|x| format!("{x:.12e}"))
                            .collect::<Vec<_>>()
                            .join(" ")
                    })
                    .collect::<Vec<_>>()
                    .join("; ")
            };
            outln!(rep, "  Φ = e^(AT) ≈ [{}]", show(phi));
            outln!(rep, "  Γ = ∫_0^T e^(Aτ) dτ B ≈ [{}]", show(gamma));
            outln!(rep, "  two independent evaluations (Padé, scaled Taylor) differ by at most {error_estimate:.3e}");
        }
    }
    Ok(Outcome::Ok)
}

/// Arguments of `owb dlqe`.
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "commands", derive(clap::Args))]
pub struct DlqeArgs {
    /// The discrete system matrix A.
    #[cfg_attr(feature = "commands", arg(allow_hyphen_values = true, long))]
    pub a: String,
    /// The output matrix C.
    #[cfg_attr(feature = "commands", arg(allow_hyphen_values = true, long))]
    pub c: String,
    /// How the process noise enters, x(k+1) = A x(k) + G w(k) (default: the identity).
    #[cfg_attr(feature = "commands", arg(allow_hyphen_values = true, long))]
    #[serde(default)]
    pub g: Option<String>,
    /// The process-noise covariance Q_n.
    #[cfg_attr(feature = "commands", arg(allow_hyphen_values = true, long))]
    pub qn: String,
    /// The measurement-noise covariance R_n.
    #[cfg_attr(feature = "commands", arg(allow_hyphen_values = true, long))]
    pub rn: String,
    /// Values for the parameters, e.g. "k=2, T=1/10": entries with letters are evaluated there.
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, value_name = "NAME=VALUE,…")
    )]
    #[serde(default)]
    pub at: Option<String>,
    /// Check P exactly at every order (by default only up to 10 states: above that the exact
    /// check costs more than the float solution).
    #[cfg_attr(feature = "commands", arg(long))]
    #[serde(default)]
    pub exact_check: bool,
    /// Machine-readable output.
    #[cfg_attr(feature = "commands", arg(long))]
    #[serde(default)]
    pub json: bool,
}

/// `owb dlqe`: the discrete-time steady-state Kalman filter.
///
/// # Errors
///
/// What the request gets wrong (named by its flag) or what the computation refuses.
pub fn dlqe(args: DlqeArgs, rep: &mut Report) -> Result<Outcome> {
    use crate::observer::discrete_kalman::{discrete_kalman_checked, ExactCheckScope};
    let values = super::args::parameter_values(args.at.as_deref())?;
    let read = |flag: &str, text: &str| super::args::matrix_at(flag, text, &values);
    let a = read("--a", &args.a)?;
    let c = read("--c", &args.c)?;
    let g = match &args.g {
        Some(t) => read("--g", t)?,
        None => crate::linalg::Matrix::identity(a.rows()),
    };
    let qn = read("--qn", &args.qn)?;
    let rn = read("--rn", &args.rn)?;
    for (flag, m) in [
        ("--a", &a),
        ("--c", &c),
        ("--g", &g),
        ("--qn", &qn),
        ("--rn", &rn),
    ] {
        super::args::float_range(flag, m)?;
    }
    let scope = if args.exact_check {
        ExactCheckScope::AnyOrder
    } else {
        ExactCheckScope::Default
    };
    let k = discrete_kalman_checked(&a, &g, &c, &qn, &rn, scope)?;
    if args.json {
        dlqe_json(&k, rep);
    } else {
        dlqe_text(&k, rep);
    }
    Ok(Outcome::Ok)
}

/// `owb dlqe --json`.
fn dlqe_json(k: &crate::observer::discrete_kalman::DiscreteKalman, rep: &mut Report) {
    let mut out = json!({
        "eigenvalues": k.eigenvalues.iter().map(|(re, im)| json!({"re": re, "im": im})).collect::<Vec<_>>(),
        "iterations": k.iterations,
        "residual": k.residual,
        "spectral_radius": k.spectral_radius,
        "refined": k.refined,
        "exact": k.exact_p.is_some(),
        "exact_read_back_tried": k.read_back_tried(),
        "exact_check": k.exact_check.name(),
    });
    // moved in, not serialised again by `json!`
    if let (Some(p), Some(l)) = (&k.exact_p, &k.exact_gain) {
        out["exact_p"] = json_matrix(p);
        out["exact_gain"] = json_matrix(l);
    }
    rep.json_with_exp_matrices(
        out,
        &[
            ("p", super::args::ExpMatrix::Dense(&k.p)),
            ("gain", super::args::ExpMatrix::Dense(&k.gain)),
            (
                "current_gain",
                super::args::ExpMatrix::Dense(&k.current_gain),
            ),
        ],
    );
}

/// `owb dlqe`'s text.
fn dlqe_text(k: &crate::observer::discrete_kalman::DiscreteKalman, rep: &mut Report) {
    use crate::observer::discrete_kalman::{ExactCheck, EXACT_CHECK_ORDER};
    let show = |m: &nalgebra::DMatrix<f64>| {
        (0..m.nrows())
            .map(|i| {
                (0..m.ncols())
                    .map(|j| format!("{:.10e}", m[(i, j)]))
                    .collect::<Vec<_>>()
                    .join(" ")
            })
            .collect::<Vec<_>>()
            .join("; ")
    };
    outln!(rep, "Discrete Kalman filter (steady state), P = A P Aᵀ − A P Cᵀ (C P Cᵀ + R_n)⁻¹ C P Aᵀ + G Q_n Gᵀ:");
    outln!(
        rep,
        "  P (a-priori error covariance, f64) = [{}]",
        show(&k.p)
    );
    outln!(
        rep,
        "  L = A P Cᵀ (C P Cᵀ + R_n)⁻¹ (prediction gain, A − LC) = [{}]",
        show(&k.gain)
    );
    outln!(
        rep,
        "  M = P Cᵀ (C P Cᵀ + R_n)⁻¹ (current-form gain, L = A M) = [{}]",
        show(&k.current_gain)
    );
    let eig: Vec<String> = k
        .eigenvalues
        .iter()
        .map(|(re, im)| {
            format!(
                "{re:.6} {} {:.6}i",
                if *im < 0.0 { "−" } else { "+" },
                im.abs()
            )
        })
        .collect();
    outln!(rep, "  eigenvalues of A − LC: {}", eig.join(", "));
    outln!(
        rep,
        "  {} doublings{}, Riccati residual ‖Ric(P) − P‖/‖P‖ = {:.3e}",
        k.iterations,
        if k.refined {
            " then Hewer's Newton iteration from a stabilising gain (the doubling alone did not give the stabilising solution)"
        } else {
            ""
        },
        k.residual
    );
    outln!(
        rep,
        "  spectral radius of A − LC = {:.6} < 1: the stabilising solution (checked)",
        k.spectral_radius
    );
    match (k.exact_check, &k.exact_p, &k.exact_gain) {
        (ExactCheck::Holds, Some(p), Some(l)) => {
            outln!(rep, "  exact: P read back as fractions satisfies the Riccati equation exactly, and A − LC is stable (exact test):");
            outln!(rep, "    P = {}", p.to_input());
            outln!(rep, "    L = {}", l.to_input());
        }
        (ExactCheck::Holds | ExactCheck::Fails, ..) => outln!(rep, "  no small-fraction P satisfies the equation exactly: the solution is known in f64 (residual above)"),
        (ExactCheck::DenominatorOverBudget, ..) => outln!(rep, "  exact read-back not tried: P's entries as fractions with denominators up to 10⁶ have no common denominator of at most {READ_BACK_BITS} bits (the exact check's work budget); the solution is known in f64 (residual above)"),
        (ExactCheck::OrderOverDefault, ..) => outln!(rep, "  exact read-back not tried: {} states is above {EXACT_CHECK_ORDER}, where the exact check costs more than the float solution (--exact-check runs it); the solution is known in f64 (residual above)", k.p.nrows()),
    }
}
