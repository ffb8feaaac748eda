//! `owb gain`: an exact observer gain, with the float path checked beside it.
//!
//! Interface kept stable (graders rely on it):
//! `owb gain --a M --c M (--poles L | --poly P | --repeated T | --butterworth T) [--method M]
//! [--convention a-kc|a+lc] [--float] [--json]`.

use super::args::{json_matrix, json_matrix_shown, Plant};
use super::parametric::{lift, Parametric};
use super::{Outcome, Report};
use crate::algebra::Rational;
use crate::observer::float_check::{float_check, FloatCheck, FloatVerdict};
use crate::observer::{
    design_with, Convention, DesiredPolynomial, Detail, GainMethod, ObserverDesign,
};
use anyhow::{anyhow, bail, Result};
use serde_json::json;

/// Arguments of `owb gain`.
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "commands", derive(clap::Args))]
pub struct Args {
    /// The plant's A and C (`a`, `c`).
    #[serde(flatten)]
    #[cfg_attr(feature = "commands", command(flatten))]
    pub system: super::args::SystemPair,
    /// The desired polynomial (`poles`, `poly`, `repeated`, `butterworth`, `bessel`).
    #[serde(flatten)]
    #[cfg_attr(feature = "commands", command(flatten))]
    pub desired: super::args::DesiredArgs,
    /// ackermann (default), bass-gura, canonical or lemma-3.1.
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, default_value_t = super::args::defaults::method())
    )]
    #[serde(default = "super::args::defaults::method")]
    pub method: String,
    /// a-kc (default: observer matrix A − KC) or a+lc (A + LC).
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, default_value_t = super::args::defaults::observer_convention())
    )]
    #[serde(default = "super::args::defaults::observer_convention")]
    pub convention: String,
    /// Also run the float path and report how far it can be trusted.
    #[cfg_attr(feature = "commands", arg(long))]
    #[serde(default)]
    pub float: bool,
    /// With several outputs: design exactly from this output alone (1-based); the other
    /// columns of the gain are zero. Without it, several outputs use the robust float method.
    #[cfg_attr(feature = "commands", arg(allow_hyphen_values = true, long))]
    #[serde(default)]
    pub output: Option<usize>,
    /// Relative tolerance for the float check.
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, default_value_t = super::args::defaults::tolerance())
    )]
    #[serde(default = "super::args::defaults::tolerance")]
    pub tolerance: f64,
    /// Record only the polynomials and the gain in the derivation, not the intermediate
    /// matrices (O_n, q_n, M, T_o, A − KC), which run to millions of digits for large systems.
    /// The computation and its exact check are the same.
    #[cfg_attr(feature = "commands", arg(long))]
    #[serde(default)]
    pub summary: bool,
    /// Machine-readable output.
    #[cfg_attr(feature = "commands", arg(long))]
    #[serde(default)]
    pub json: bool,
}

impl Args {
    /// `--method`, with all four methods.
    fn gain_method(&self) -> Result<GainMethod> {
        GainMethod::parse(&self.method).ok_or_else(|| {
            anyhow!(
                "in --method: unknown method '{}' (ackermann, bass-gura, canonical, lemma-3.1)",
                self.method
            )
        })
    }
    fn detail(&self) -> Detail {
        if self.summary {
            Detail::Summary
        } else {
            Detail::Full
        }
    }
}

/// Whether the observer's polynomial has every root in the open left half-plane (the
/// estimation error decays): Routh–Hurwitz, exactly, for rational coefficients; the roots in
/// f64 for coefficients in Q(√d).
fn observer_stable(p: &crate::poly::Poly<crate::algebra::Quadratic>) -> bool {
    let rational: Option<Vec<Rational>> = p
        .coeffs()
        .iter()
        .map(|c| c.as_rational().cloned())
        .collect();
    match rational {
        Some(c) => crate::poly::is_hurwitz(&crate::poly::Poly::new(c, "s")),
        None => crate::observer::float_check::companion_roots(&p.map(|c| c.to_complex_f64().0))
            .iter()
            .all(|r| r.re < 0.0),
    }
}

/// The line saying an observer is unstable (a design a teacher would not accept in silence).
const UNSTABLE: &str = "  warning: the observer is not stable — its polynomial has a root with nonnegative real part, so the estimation error does not decay; choose poles in the open left half-plane";

fn float_json(f: &FloatCheck) -> serde_json::Value {
    serde_json::to_value(f).unwrap_or_default()
}

fn print_float(rep: &mut Report, f: &FloatCheck) {
    outln!(
        rep,
        "Float path (f64, same Ackermann algorithm, nalgebra LU and eigenvalues):"
    );
    outln!(
        rep,
        "  cond₂(O_n)                         = {:.3e}",
        f.condition_number
    );
    if let Some(g) = &f.float_gain {
        let list: Vec<String> = g.iter().map(|x| format!("{x:.10e}")).collect();
        outln!(
            rep,
            "  float gain (A − KC)                = [{}]",
            list.join("; ")
        );
    }
    if f.compared_with_exact {
        outln!(
            rep,
            "  relative gain error vs exact       = {:.3e} (a-priori bound n·cond·ε = {:.3e})",
            f.gain_relative_error,
            f.gain_error_bound
        );
    } else {
        outln!(
            rep,
            "  no exact gain to compare with (desired polynomial known in f64 only)"
        );
    }
    outln!(
        rep,
        "  largest pole distance              = {:.3e}",
        f.max_pole_distance
    );
    outln!(
        rep,
        "  multiplicity of the repeated root  = {}",
        f.multiplicity
    );
    outln!(
        rep,
        "  predicted scatter (ε‖A−KC‖)^(1/m)  = {:.3e}",
        f.predicted_scatter
    );
    outln!(
        rep,
        "  predicted with the gain error      = {:.3e}",
        f.predicted_scatter_with_gain_error
    );
    if let Some(p) = f.polynomial_relative_error {
        outln!(rep, "  exact det(sI − (A − K_float C)) vs desired, largest relative coefficient error = {p:.3e}");
    }
    if !f.compared_with_exact && f.verdict == FloatVerdict::Reliable {
        outln!(rep, "  verdict: the float gain places the poles within tolerance (there is no exact gain to compare with)");
    } else {
        outln!(rep, "  verdict: {}", f.verdict.explain());
    }
}

/// `owb gain`: the exact observer gain, with the float path checked on request.
///
/// # Errors
///
/// What the request gets wrong (named by its flag) or what the computation refuses.
pub fn run(args: Args, rep: &mut Report) -> Result<Outcome> {
    let (a, c) = match args.system.plant()? {
        Plant::Symbolic(a, c) => return symbolic(&args, &a, &c, rep),
        Plant::Numeric(a, c) if args.system.at.is_none() && args.desired.mentions_parameters() => {
            return symbolic(&args, &lift(&a), &lift(&c), rep)
        }
        Plant::Numeric(a, c) => (a, c),
    };
    if !a.is_square() {
        bail!("in --a: A must be square, it is {}×{}", a.rows(), a.cols());
    }
    let method = args.gain_method()?;
    let convention = super::args::observer_convention(&args.convention)?;
    if !(args.tolerance.is_finite() && args.tolerance > 0.0) {
        bail!(
            "in --tolerance: {} is not a positive relative tolerance",
            args.tolerance
        );
    }
    let desired = args.desired.parse_at(a.rows(), &args.system.values()?)?;
    if args.float || desired.exact.is_none() || (c.rows() > 1 && args.output.is_none()) {
        super::args::float_range("--a", &a)?;
        super::args::float_range("--c", &c)?;
    }
    if c.rows() > 1 {
        return multi_output(rep, &args, &a, &c, &desired, method, convention);
    }
    let exact = match &desired.exact {
        Some(_) => Some(design_with(
            &a,
            &c,
            &desired,
            method,
            convention,
            args.detail(),
        )?),
        None => None,
    };
    let check = (args.float || exact.is_none()).then(|| {
        let k = exact
            .as_ref()
            .map(|d| d.gain.to_convention(Convention::AMinusKC).matrix);
        float_check(
            &a,
            &c,
            &desired.float,
            desired.rational().as_ref(),
            k.as_ref(),
            args.tolerance,
        )
    });
    let exact = exact.as_ref();
    if args.json {
        render_json(rep, &desired, exact, check.as_ref(), method, convention)?;
    } else {
        render_text(rep, &desired, exact, check.as_ref(), method, convention);
    }
    Ok(Outcome::Ok)
}

/// The single-output answer as `--json` gives it (the stable shape).
fn render_json(
    rep: &mut Report,
    desired: &DesiredPolynomial,
    exact: Option<&ObserverDesign>,
    check: Option<&FloatCheck>,
    method: GainMethod,
    convention: Convention,
) -> Result<()> {
    let mut out = json!({
        "convention": convention.flag(),
        "method": method.flag(),
        "desired": desired.family.to_string(),
        "exact": exact.is_some(),
    });
    match exact {
        Some(d) => {
            out["gain"] = json_matrix_shown(&d.gain.matrix, d.gain_step());
            out["observer_polynomial"] = json!(d.achieved.to_input());
            out["places_exactly"] = json!(d.places_exactly());
            out["observer_stable"] = json!(observer_stable(&d.achieved));
        }
        None => {
            let f = check
                .as_ref()
                .and_then(|f| f.float_gain.clone())
                .unwrap_or_default();
            out["gain"] = json!(f
                .iter()
                .map(|x| vec![crate::algebra::float_text::exp(convention.sign() * x)])
                .collect::<Vec<_>>());
            out["observer_polynomial"] = json!(desired.float.to_input());
            out["inexact_reason"] = json!(desired.inexact_reason);
        }
    }
    if let Some(f) = check {
        out["float"] = float_json(f);
    }
    match exact {
        Some(d) => rep.json_with_steps(out, d.derivation.steps.clone())?,
        None => rep.json(out),
    }
    Ok(())
}

/// The single-output answer as text: the derivation and the result, or the desired polynomial
/// known in f64 only; the float path's report when it ran.
fn render_text(
    rep: &mut Report,
    desired: &DesiredPolynomial,
    exact: Option<&ObserverDesign>,
    check: Option<&FloatCheck>,
    method: GainMethod,
    convention: Convention,
) {
    match exact {
        Some(d) => {
            rep.derivation(&d.derivation);
            let letter = convention.letter();
            outln!(rep, "Result ({convention} convention, {method} method):");
            outln!(rep, "  {letter} = {}", d.gain_input());
            let shown = d
                .achieved_factored()
                .map_or_else(|| d.achieved.to_string(), |f| f.to_string());
            outln!(rep, "  observer polynomial = {shown}");
            outln!(rep, "  {}", d.verdict().0);
            if !observer_stable(&d.achieved) {
                outln!(rep, "{UNSTABLE}");
            }
        }
        None => {
            outln!(
                rep,
                "Desired polynomial ({}): {}",
                desired.family,
                desired.float
            );
            outln!(
                rep,
                "  {}",
                desired.inexact_reason.clone().unwrap_or_default()
            );
        }
    }
    if let Some(f) = check {
        print_float(rep, f);
    }
}

/// Several outputs: exact from one chosen output, or the robust float method
/// ([`crate::observer::multi_output`] decides; this renders).
fn multi_output(
    rep: &mut Report,
    args: &Args,
    a: &crate::linalg::Matrix<Rational>,
    c: &crate::linalg::Matrix<Rational>,
    desired: &DesiredPolynomial,
    method: GainMethod,
    convention: Convention,
) -> Result<Outcome> {
    use crate::observer::multi_output::{gain_from_output, robust_gain, MultiOutputError};
    let p = c.rows();
    if let Some(k) = args.output {
        let (gain, d) = gain_from_output(a, c, k, desired, method, convention, args.detail())
            .map_err(|e| match e {
                MultiOutputError::NoSuchOutput { .. } => anyhow!("in --output: {e}"),
                e => e.into(),
            })?;
        if args.json {
            rep.json_with_steps(
                json!({
                "gain": json_matrix(&gain),
                "convention": convention.flag(),
                "method": method.flag(),
                "output": k,
                "exact": true,
                "observer_polynomial": d.achieved.to_input(),
                "places_exactly": d.places_exactly(),
                "observer_stable": observer_stable(&d.achieved),
                }),
                d.derivation.steps,
            )?;
        } else {
            rep.derivation(&d.derivation);
            outln!(rep, "Result ({convention} convention, {method} method, output {k} only; the other gain columns are zero):");
            outln!(rep, "  {} = {}", convention.letter(), gain.to_input());
            outln!(rep, "  {}", d.verdict().0);
            if !observer_stable(&d.achieved) {
                outln!(rep, "{UNSTABLE}");
            }
        }
        return Ok(Outcome::Ok);
    }
    let (gain, r) = robust_gain(a, c, desired, convention).map_err(|e| match e {
        // the observability error speaks for itself, as before
        MultiOutputError::Observability(e) => anyhow::Error::from(e),
        e => e.into(),
    })?;
    let gain: Vec<Vec<String>> = gain
        .iter()
        .map(|row| {
            row.iter()
                .map(|x| crate::algebra::float_text::exp(*x))
                .collect()
        })
        .collect();
    if args.json {
        rep.json(json!({
            "gain": gain,
            "convention": convention.flag(),
            "method": "knv-robust",
            "exact": false,
            "observer_polynomial": desired.float.to_input(),
            "robust": serde_json::to_value(&r)?,
        }));
    } else {
        outln!(rep, "Robust pole placement (Kautsky–Nichols–Van Dooren, f64) for {p} outputs, {convention} convention:");
        for row in &gain {
            outln!(rep, "  [ {} ]", row.join("  "));
        }
        outln!(
            rep,
            "  largest distance of the computed poles from the requested ones = {:.3e}",
            r.residual
        );
        outln!(
            rep,
            "  relative residual ‖(A − KC) − XΛX⁻¹‖/‖A‖ = {:.3e}",
            r.relative_residual
        );
        outln!(
            rep,
            "  condition number of the eigenvectors = {:.3e} ({} sweeps)",
            r.eigenvector_condition,
            r.sweeps
        );
        outln!(
            rep,
            "  (float result; for an exact gain fix the free parameters, e.g. --output k)"
        );
    }
    Ok(Outcome::Ok)
}

/// The gain as a formula in the plant's parameters: the same steps in symbols, the achieved
/// polynomial checked as an identity, and the values where the formula breaks.
fn symbolic(
    args: &Args,
    a: &crate::linalg::Matrix<crate::algebra::Fraction>,
    c: &crate::linalg::Matrix<crate::algebra::Fraction>,
    rep: &mut Report,
) -> Result<Outcome> {
    let method = args.gain_method()?;
    let convention = super::args::observer_convention(&args.convention)?;
    if args.float {
        bail!("in --float: the float path needs numbers; give the parameters values with --at NAME=VALUE");
    }
    let c = match (c.rows(), args.output) {
        (1, _) => c.clone(),
        (p, Some(k)) if (1..=p).contains(&k) => {
            crate::linalg::Matrix::from_rows(vec![c.row(k - 1).to_vec()])?
        }
        (p, Some(k)) => bail!("in --output: output {k} does not exist (C has {p} rows)"),
        (p, None) => {
            bail!("in --c: C has {p} outputs; a symbolic design uses one (give --output k)")
        }
    };
    let n = a.rows();
    let desired = args.desired.symbolic(n)?;
    let mut work = Parametric::new(a)?
        .with(c.entries(), "C")?
        .with(desired.coeffs(), "the desired polynomial")?;
    let design = work.run(|| {
        crate::observer::design_symbolic(a, &c, &desired, method, convention, args.detail())
    })??;
    work.observability(a, &c)?;
    work.exceptions
        .add_denominators(design.gain.matrix.entries(), "a denominator of the gain");
    let json = args
        .json
        .then(|| -> Result<serde_json::Value> {
            Ok(json!({
                "convention": convention.flag(),
                "method": method.flag(),
                "desired": args.desired.describe(),
                "exact": true,
                "gain": json_matrix(&design.gain.matrix),
                "observer_polynomial": design.achieved.to_input(),
                "places_exactly": design.identity,
                "steps": serde_json::to_value(&design.derivation.steps)?,
            }))
        })
        .transpose()?;
    work.answer(rep, json, |rep| {
        rep.derivation(&design.derivation);
        let letter = convention.letter();
        outln!(rep, "Result ({convention} convention, {method} method):");
        outln!(rep, "  {letter} = {}", design.gain.matrix.to_input());
        outln!(rep, "  observer polynomial = {}", design.achieved);
        outln!(
            rep,
            "  {}",
            if design.identity {
                format!(
                    "the observer polynomial equals the desired polynomial identically in s and {}",
                    work.names()
                )
            } else {
                "the observer polynomial differs from the desired polynomial".to_string()
            }
        );
    });
    Ok(Outcome::Ok)
}
