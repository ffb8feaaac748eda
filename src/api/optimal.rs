//! `owb optimal`: multi-output gains chosen by optimality (Baranowski): minimum norm `J1` or
//! minimal dynamical error `J2 = λ_max(H)`, and the check of a given (printed) gain.

use super::args::matrix;
use super::{Outcome, Report};
use crate::algebra::{Rational, ToF64};
use crate::linalg::definiteness::{definiteness, Definiteness};
use crate::linalg::float::{eigenvalues, to_nalgebra};
use crate::linalg::{characteristic_polynomial, Matrix};
use crate::observer::dynamical_error::{dynamical_error_cost, minimal_dynamical_error};
use crate::observer::optimal::{minimum_norm_gain, pole_placement_constraints};
use crate::observer::search::Multistart;
use crate::poly::{exact_roots, Poly};
use anyhow::{anyhow, bail, Result};
use nalgebra::DMatrix;
use serde_json::json;

/// Arguments of `owb optimal`.
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
    /// j1 (minimum norm Σ k_i², default) or j2 (minimal dynamical error λ_max(H)).
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, default_value_t = super::args::defaults::index())
    )]
    #[serde(default = "super::args::defaults::index")]
    pub index: String,
    /// The weight D of J2 (Fᵀ H + H F = −D), default the identity.
    #[cfg_attr(feature = "commands", arg(allow_hyphen_values = true, long))]
    #[serde(default)]
    pub weight: Option<String>,
    /// For J2: the output whose gain column is placed exactly from the others (1-based).
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, default_value_t = super::args::defaults::placed_output())
    )]
    #[serde(default = "super::args::defaults::placed_output")]
    pub placed_output: usize,
    /// Seeded random starts of the search.
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, default_value_t = super::args::defaults::starts())
    )]
    #[serde(default = "super::args::defaults::starts")]
    pub starts: usize,
    /// Seed of the starts (same seed, same report).
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, default_value_t = super::args::defaults::seed())
    )]
    #[serde(default = "super::args::defaults::seed")]
    pub seed: u64,
    /// No new start after this many seconds (the report says how many starts ran).
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, default_value_t = super::args::defaults::time_limit())
    )]
    #[serde(default = "super::args::defaults::time_limit")]
    pub time_limit: f64,
    /// Check this gain (e.g. a printed one): its exact observer polynomial, its poles, J1 and J2.
    #[cfg_attr(feature = "commands", arg(allow_hyphen_values = true, long))]
    #[serde(default)]
    pub check_gain: Option<String>,
    /// Machine-readable output.
    #[cfg_attr(feature = "commands", arg(long))]
    #[serde(default)]
    pub json: bool,
}

/// The most seeded starts accepted (each is a full local optimisation).
const MAX_STARTS: usize = 10_000;

fn show(m: &DMatrix<f64>) -> String {
    super::args::float_matrix_text(m, |x| format!("{x:.6}"))
}

fn scatter(
    desired: &Poly<Rational>,
    achieved: &Poly<Rational>,
    poles: &[(f64, f64)],
) -> Vec<serde_json::Value> {
    let roots = exact_roots(desired);
    let delta = achieved.clone() - desired.clone();
    let rational: Vec<(Rational, u32)> = roots
        .roots
        .iter()
        .filter_map(|(r, k)| r.as_rational().map(|q| (q.clone(), *k)))
        .collect();
    rational
        .iter()
        .map(|(r, m)| {
            let others: f64 = rational
                .iter()
                .filter(|(q, _)| q != r)
                .map(|(q, k)| (r.to_f64() - q.to_f64()).abs().powi(*k as i32))
                .product();
            let predicted = (delta.eval(r).to_f64().abs() / others).powf(1.0 / f64::from(*m));
            // the poles nearest to this root (each pole goes to its nearest desired root)
            let nearest = |re: f64, im: f64| {
                rational
                    .iter()
                    .map(|(q, _)| ((re - q.to_f64()).powi(2) + im * im).sqrt())
                    .fold(f64::INFINITY, f64::min)
            };
            let nearest_group = poles
                .iter()
                .map(|&(re, im)| (((re - r.to_f64()).powi(2) + im * im).sqrt(), nearest(re, im)))
                .filter(|(d, best)| d <= best)
                .map(|(d, _)| d)
                .fold(0.0, f64::max);
            json!({"root": r.to_string(), "multiplicity": m, "largest_move": nearest_group, "predicted": predicted})
        })
        .collect()
}

/// A validated `owb optimal` request.
struct Request {
    a: Matrix<Rational>,
    c: Matrix<Rational>,
    /// The desired polynomial.
    p: Poly<Rational>,
    /// D, the weight of J2.
    weight: Matrix<Rational>,
}

fn request(args: &Args) -> Result<Request> {
    let (a, c) = args.system.parse()?;
    super::args::float_range("--a", &a)?;
    super::args::float_range("--c", &c)?;
    if !a.is_square() || c.cols() != a.rows() {
        bail!(
            "in --a/--c: A must be square and C must have as many columns ({}×{} and {}×{})",
            a.rows(),
            a.cols(),
            c.rows(),
            c.cols()
        );
    }
    let n = a.rows();
    if c.rows() < 2 {
        bail!(
            "nothing to optimise: with {} output the gain that places the poles is unique (owb gain computes it exactly)",
            c.rows()
        );
    }
    if !(args.time_limit.is_finite() && args.time_limit > 0.0 && args.time_limit <= 86_400.0) {
        bail!(
            "in --time-limit: {} s; give a number of seconds between 0 and 86400",
            args.time_limit
        );
    }
    if args.starts == 0 || args.starts > MAX_STARTS {
        bail!(
            "in --starts: {} starts; give between 1 and {MAX_STARTS}",
            args.starts
        );
    }
    crate::observability::require_observable(&a, &c)?;
    let values = args.system.values()?;
    let p = args
        .desired
        .parse_at(n, &values)?
        .rational()
        .ok_or_else(|| {
            anyhow!("the optimal designs need a desired polynomial with rational coefficients")
        })?;
    let weight = match &args.weight {
        Some(w) => super::args::matrix_at("--weight", w, &values)?,
        None => Matrix::identity(n),
    };
    if weight.rows() != n || weight.cols() != n {
        bail!(
            "in --weight: D must be {n}×{n}, it is {}×{}",
            weight.rows(),
            weight.cols()
        );
    }
    require_weight(&weight)?;
    Ok(Request { a, c, p, weight })
}

/// D weighs the error in J2 = λ_max(H): it must be symmetric positive semidefinite and not zero,
/// or the "best" J2 can be negative.
fn require_weight(weight: &Matrix<Rational>) -> Result<()> {
    let found = definiteness(weight)?;
    if found == Definiteness::NotSymmetric {
        bail!("in --weight: D must be symmetric");
    }
    if weight.is_zero() {
        bail!("in --weight: D is zero, so every gain has J2 = 0");
    }
    if let Definiteness::Indefinite(charpoly) = found {
        bail!(
            "in --weight: D must be positive semidefinite; det(λI − D) = {charpoly} has a negative root"
        );
    }
    Ok(())
}

/// A line saying the time limit cut the starts short, or nothing.
fn stopped_early(args: &Args, ran: usize) -> String {
    if ran < args.starts {
        format!(
            "  (stopped at the time limit of {} s: {ran} of the {} starts asked ran)\n",
            args.time_limit, args.starts
        )
    } else {
        String::new()
    }
}

/// The minimum-norm gain (J1), told in `text`; its report as JSON.
fn j1(args: &Args, req: &Request, text: &mut String) -> Result<serde_json::Value> {
    let Request { a, c, p, .. } = req;
    let n = a.rows();
    let cons = pole_placement_constraints(a, c, p)?;
    let bar = super::progress::Progress::new("seeded starts", args.starts);
    let tell = || bar.inc();
    let r = minimum_norm_gain(
        &cons,
        Multistart::new(args.starts, args.seed)
            .within(std::time::Duration::from_secs_f64(args.time_limit))
            .reporting(&tell),
    );
    bar.finish();
    text.push_str(&format!(
            "Minimum-norm gain: minimise J1 = Σ k_i² subject to det(sI − (A − GC)) = {p}\n  constraints (G = [k1 k{}…] column by column):\n",
            n + 1
        ));
    for e in &cons.equations {
        text.push_str(&format!("    {e} = 0\n"));
    }
    if r.descended == 0 {
        text.push_str(&format!(
            "  {} seeded starts (seed {}), {} converged to a local minimum (Newton on the KKT system, second-order check)\n",
            r.starts, args.seed, r.converged
        ));
    } else {
        text.push_str(&format!(
            "  {} seeded starts (seed {}): none converged from where it began (Newton's steps left the constraint set)\n  the same {} starts, each first moved by a descent on the constraint set, then Newton on the KKT system: {} converged to a local minimum (second-order check)\n",
            r.starts, args.seed, r.descended, r.converged
        ));
    }
    // the starts taken again stop at the time limit too
    let ran = if r.descended > 0 {
        r.descended
    } else {
        r.starts
    };
    text.push_str(&stopped_early(args, ran));
    for (i, m) in r.minima.iter().enumerate() {
        let g = DMatrix::from_fn(n, c.rows(), |row, col| m.gain[col * n + row]);
        text.push_str(&format!(
            "  {} J1 = {:.6}, reached by {} start(s): G = {}\n",
            if i < r.best_count { "best" } else { "    " },
            m.cost,
            m.starts,
            show(&g)
        ));
    }
    if r.converged == 0 || r.minima.is_empty() {
        if let Some(error) = r.unplaced {
            bail!(
                "no minimum-norm gain is reported ({} seeded starts, seed {}): starts reached the resolution of f64 for this plant's terms, but their gains place the polynomial's coefficients only to {error:.1e} (relative, computed exactly), beyond 1e-6 — the plant's numbers are too large for an f64 gain; scale the plant (units of time or of the states) so that its entries are near 1",
                r.starts,
                args.seed
            );
        }
        if r.out_of_time {
            bail!(
                "no start converged to a local minimum ({} of the {} seeded starts ran, seed {}, and {} of them were taken again with a descent on the constraint set first) before the time limit of {} s: no minimum-norm gain is reported; raise --time-limit",
                r.starts,
                args.starts,
                args.seed,
                r.descended,
                args.time_limit
            );
        }
        bail!(
            "no start converged to a local minimum ({} seeded starts, seed {}): no minimum-norm gain is reported; try more --starts or another --seed",
            r.starts,
            args.seed
        );
    }
    text.push_str(&format!(
        "  the best value is attained by {} gain(s): {}\n",
        r.best_count,
        if r.best_count > 1 {
            "the minimiser is not unique"
        } else {
            "unique among the minima found"
        }
    ));
    // Newton stopped at f64's resolution for this plant's terms, not at the absolute
    // tolerance: the reader is told how closely the printed gain places the polynomial
    if let Some(error) = r.minima.first().and_then(|m| m.placement_error) {
        text.push_str(&format!(
            "  the best gain places each coefficient of the polynomial within {error:.1e} of the desired one (relative, computed exactly from the f64 gain, whose every digit --json gives): f64 cannot bring this plant's constraints to 10⁻¹³\n"
        ));
    }
    Ok(serde_json::to_value(&r)?)
}

/// The minimal-dynamical-error gain (J2), told in `text`; its report as JSON.
fn j2(args: &Args, req: &Request, text: &mut String) -> Result<serde_json::Value> {
    let Request { a, c, p, weight } = req;
    let n = a.rows();
    if args.placed_output == 0 || args.placed_output > c.rows() {
        bail!(
            "in --placed-output: {} is not an output (1…{})",
            args.placed_output,
            c.rows()
        );
    }
    let bar = super::progress::Progress::new("seeded starts", args.starts);
    let tell = || bar.inc();
    let r = minimal_dynamical_error(
        a,
        c,
        p,
        weight,
        args.placed_output - 1,
        Multistart::new(args.starts, args.seed)
            .within(std::time::Duration::from_secs_f64(args.time_limit))
            .reporting(&tell),
    );
    bar.finish();
    let r = r?;
    let g = DMatrix::from_row_slice(r.rows, r.cols, &r.best.gain);
    text.push_str(&format!(
            "Minimal dynamical error: minimise J2 = λ_max(H), Fᵀ H + H F = −D, F = A − GC, over the gains with det(sI − F) = {p}\n  D = {}\n  column {} of G placed exactly (dual Ackermann) from the others; Nelder–Mead over the other {} entries\n",
            weight.to_input(),
            args.placed_output,
            n * (c.rows() - 1)
        ));
    text.push_str(&format!(
            "  {} seeded starts (seed {}): {} reached the best J2 = {:.8}\n  their gains lie up to {:.4} apart (max-norm); Hessian eigenvalues at the smallest: [{}]\n",
            r.starts,
            args.seed,
            r.reached_best,
            r.best.cost,
            r.spread,
            r.hessian_eigenvalues.iter().map(|x| format!("{x:.3e}")).collect::<Vec<_>>().join(", ")
        ));
    text.push_str(&stopped_early(args, r.starts));
    text.push_str(&format!(
            "  flat directions: {}{} → the minimiser is {}\n  smallest-norm minimiser G = {}\n  rebuilt in rationals it places the polynomial exactly: {}\n",
            r.flat_directions,
            r.flat_vectors.iter().map(|v| format!(" ({})", v.iter().map(|x| format!("{x:.4}")).collect::<Vec<_>>().join(", "))).collect::<String>(),
            if r.flat_directions > 0 { "not unique".to_string() } else if r.spread > 1e-4 { format!("not unique (no flat Hessian direction, but the best gains found lie {:.4} apart)", r.spread) } else { "unique among the starts".to_string() },
            show(&g),
            if r.places_exactly { "yes" } else { "no" }
        ));
    Ok(serde_json::to_value(&r)?)
}

/// A given gain checked: exact polynomial, poles and how far they moved, J1, J2.
fn check_gain(gtext: &str, req: &Request, text: &mut String) -> Result<serde_json::Value> {
    let Request { a, c, p, weight } = req;
    let n = a.rows();
    let g = matrix::<Rational>("--check-gain", gtext)?;
    if g.rows() != n || g.cols() != c.rows() {
        bail!(
            "in --check-gain: G must be {n}×{}, it is {}×{}",
            c.rows(),
            g.rows(),
            g.cols()
        );
    }
    let f = a.sub(&g.mul(c)?)?;
    let achieved = characteristic_polynomial(&f, "s")?;
    let poles: Vec<(f64, f64)> = eigenvalues(&to_nalgebra(&f))
        .iter()
        .map(|z| (z.re, z.im))
        .collect();
    let j1: f64 = (0..n)
        .flat_map(|i| (0..c.rows()).map(move |j| (i, j)))
        .map(|(i, j)| g.get(i, j).to_f64().powi(2))
        .sum();
    let j2 = dynamical_error_cost(
        &to_nalgebra(a),
        &to_nalgebra(c),
        &to_nalgebra(&g),
        &to_nalgebra(weight),
    )
    .ok()
    .map(|(j, _)| j);
    let moves = scatter(p, &achieved, &poles);
    text.push_str(&format!(
        "Given gain G = {}\n  det(sI − (A − GC)) = {achieved} ({})\n  poles: {}\n",
        gtext.trim(),
        if achieved == *p {
            "places the desired polynomial exactly"
        } else {
            "not the desired polynomial"
        },
        poles
            .iter()
            .map(|(re, im)| if im.abs() > 0.0 {
                format!(
                    "{re:.6} {} {:.6}i",
                    if *im < 0.0 { "−" } else { "+" },
                    im.abs()
                )
            } else {
                format!("{re:.6}")
            })
            .collect::<Vec<_>>()
            .join(", ")
    ));
    for m in &moves {
        text.push_str(&format!(
            "  root {} (multiplicity {}): the poles moved by up to {:.4}; predicted (|δ(λ0)|/Π|λ0 − λj|)^(1/m) = {:.4} — an m-fold root moves like the m-th root of the coefficient error\n",
            m["root"].as_str().unwrap_or(""),
            m["multiplicity"],
            m["largest_move"].as_f64().unwrap_or(f64::NAN),
            m["predicted"].as_f64().unwrap_or(f64::NAN)
        ));
    }
    text.push_str(&format!("  J1 = {j1:.6}\n"));
    match j2 {
        Some(j) => text.push_str(&format!(
            "  J2 = λ_max(H) = {j:.8} (D = {})\n",
            weight.to_input()
        )),
        None => text.push_str("  J2 undefined: A − GC is not stable\n"),
    }
    Ok(json!({
        "gain": super::args::json_matrix(&g),
        "observer_polynomial": achieved.to_input(),
        "places_exactly": achieved == *p,
        "poles": poles,
        "root_moves": moves,
        "j1": j1,
        "j2": j2,
    }))
}

/// `owb optimal`: multi-output gains chosen by optimality.
///
/// # Errors
///
/// What the request gets wrong (named by its flag) or what the computation refuses.
pub fn run(args: Args, rep: &mut Report) -> Result<Outcome> {
    let r = request(&args)?;
    let mut out = json!({"desired": r.p.to_string(), "convention": "a-kc", "index": args.index});
    let mut text = String::new();
    out["report"] = match args.index.as_str() {
        "j1" => j1(&args, &r, &mut text)?,
        "j2" => j2(&args, &r, &mut text)?,
        other => bail!("in --index: unknown index '{other}' (j1 or j2)"),
    };
    if let Some(gtext) = &args.check_gain {
        out["check"] = check_gain(gtext, &r, &mut text)?;
    }
    if args.json {
        rep.json(out);
    } else {
        out!(rep, "{text}");
    }
    Ok(Outcome::Ok)
}
