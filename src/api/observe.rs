//! `owb observe`: the observability report.

use super::args::json_matrix;
use super::parametric::Parametric;
use super::{Outcome, Report};
use crate::algebra::{Fraction, MultiPoly, Ring};
use crate::linalg::Matrix;
use crate::observability::observability_report;
use anyhow::Result;
use serde_json::json;

/// Arguments of `owb observe`.
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "commands", derive(clap::Args))]
pub struct Args {
    /// The plant's A and C (`a`, `c`).
    #[serde(flatten)]
    #[cfg_attr(feature = "commands", command(flatten))]
    pub system: super::args::SystemPair,
    /// Machine-readable output.
    #[cfg_attr(feature = "commands", arg(long))]
    #[serde(default)]
    pub json: bool,
}

/// `owb observe`: the observability report.
///
/// # Errors
///
/// What the request gets wrong (named by its flag) or what the computation refuses.
pub fn run(args: Args, rep: &mut Report) -> Result<Outcome> {
    let (a, c) = match args.system.plant()? {
        super::args::Plant::Symbolic(a, c) => return symbolic(&args, &a, &c, rep),
        super::args::Plant::Numeric(a, c) => (a, c),
    };
    let r = observability_report(&a, &c)?;
    if args.json {
        rep.json(&json!({
            "observability_matrix": json_matrix(&r.matrix),
            "rank": r.rank,
            "order": r.order,
            "observable": r.observable(),
            "determinant": r.determinant.as_ref().map(|d| d.to_string()),
            "unobservable_subspace": r.unobservable_subspace.iter().map(json_matrix).collect::<Vec<_>>(),
            "unobservable_polynomial": r.unobservable_polynomial.to_input(),
            "unobservable_eigenvalues": r.unobservable_eigenvalues.roots.iter().map(|(x, m)| json!({"value": crate::algebra::Ring::to_input(x), "multiplicity": m})).collect::<Vec<_>>(),
            "pbh_confirmed": r.pbh_confirmed,
        }));
    } else {
        outln!(rep, "Observability of (A, C)");
        outln!(rep, "  O_n = [C; CA; …; CA^(n−1)]:");
        for line in r.matrix.render().lines() {
            outln!(rep, "      {line}");
        }
        if let Some(d) = &r.determinant {
            outln!(rep, "  det O_n = {d}");
        }
        outln!(rep, "  rank O_n = {} (order n = {})", r.rank, r.order);
        if r.observable() {
            outln!(rep, "  observable");
        } else {
            outln!(rep, "  NOT observable");
            outln!(rep, "  unobservable subspace ker O_n, basis:");
            for v in &r.unobservable_subspace {
                outln!(rep, "      {}", v.to_input());
            }
            outln!(
                rep,
                "  unobservable modes: det(sI − A|ker O_n) = {}",
                r.unobservable_polynomial
            );
            outln!(
                rep,
                "  unobservable eigenvalues: {}",
                r.unobservable_eigenvalues.render()
            );
            outln!(
                rep,
                "  PBH test rank [λI − A; C] < n at each: {}",
                if r.pbh_confirmed {
                    "confirmed"
                } else {
                    "NOT confirmed"
                }
            );
        }
    }
    Ok(Outcome::Ok)
}

/// What is lost where a factor of `det O_n` vanishes: the substitution that makes it vanish,
/// the rank there, the unobservable subspace and the polynomial of the unobservable modes.
#[derive(Debug, Clone, serde::Serialize)]
struct Loss {
    /// The factor, in input syntax.
    factor: String,
    /// The substitution solving `factor = 0` for one parameter (`k = 0`), when one exists.
    substitution: Option<String>,
    /// The rank of O_n there.
    rank: Option<usize>,
    /// A basis of ker O_n there.
    unobservable_subspace: Vec<Vec<Vec<String>>>,
    /// det(sI − A|ker O_n) there.
    unobservable_polynomial: Option<String>,
}

fn substitute(m: &Matrix<Fraction>, name: &str, value: &Fraction) -> Matrix<Fraction> {
    m.map(|x| x.substitute(name, value))
}

/// The restriction of `a` to the span of `basis` (an invariant subspace):
/// `R = (VᵀV)⁻¹ Vᵀ A V`.
fn restriction(a: &Matrix<Fraction>, basis: &[Matrix<Fraction>]) -> Option<Matrix<Fraction>> {
    let mut v = basis.first()?.clone();
    for b in &basis[1..] {
        v = v.hstack(b).ok()?;
    }
    let vt = v.transpose();
    let gram = vt.mul(&v).ok()?;
    let image = vt.mul(&a.mul(&v).ok()?).ok()?;
    crate::linalg::solve(&gram, &image).ok()
}

fn loss(a: &Matrix<Fraction>, c: &Matrix<Fraction>, factor: &MultiPoly) -> Loss {
    let mut out = Loss {
        factor: factor.to_input(),
        substitution: None,
        rank: None,
        unobservable_subspace: Vec::new(),
        unobservable_polynomial: None,
    };
    let Some((name, value)) = crate::symbolic::solve_for(factor) else {
        return out;
    };
    out.substitution = Some(format!("{name} = {}", value.to_input()));
    let (a, c) = (substitute(a, &name, &value), substitute(c, &name, &value));
    let Ok(o) = crate::observability::observability_matrix(&a, &c) else {
        return out;
    };
    out.rank = Some(crate::linalg::rank(&o));
    let basis = crate::linalg::null_space(&o);
    out.unobservable_subspace = basis
        .iter()
        .map(|v| match json_matrix(v) {
            serde_json::Value::Array(rows) => rows
                .into_iter()
                .map(|r| match r {
                    serde_json::Value::Array(x) => x
                        .into_iter()
                        .map(|e| e.as_str().unwrap_or_default().to_string())
                        .collect(),
                    _ => Vec::new(),
                })
                .collect(),
            _ => Vec::new(),
        })
        .collect();
    out.unobservable_polynomial = restriction(&a, &basis)
        .and_then(|r| crate::linalg::characteristic_polynomial(&r, "s").ok())
        .map(|p| p.to_input());
    out
}

/// Observability with parameters: O_n in symbols, det O_n factored, and for each factor what
/// is lost where it vanishes.
fn symbolic(
    args: &Args,
    a: &Matrix<Fraction>,
    c: &Matrix<Fraction>,
    rep: &mut Report,
) -> Result<Outcome> {
    let work = Parametric::new(a, c, &[])?;
    let o = work.run(|| crate::observability::observability_matrix(a, c))??;
    let n = a.rows();
    let rank = work.run(|| crate::linalg::rank(&o))?;
    let det = work.run(|| super::parametric::observability_determinant(a, c))?;
    let factors = det
        .as_ref()
        .map(|d| crate::symbolic::factors(d.numerator()))
        .unwrap_or_default();
    let losses = work.run(|| {
        factors
            .iter()
            .map(|(f, _)| loss(a, c, f))
            .collect::<Vec<_>>()
    })?;
    let generic_basis = if rank < n {
        work.run(|| crate::linalg::null_space(&o))?
    } else {
        Vec::new()
    };
    let generic_modes = if rank < n {
        work.run(|| {
            restriction(a, &generic_basis)
                .and_then(|r| crate::linalg::characteristic_polynomial(&r, "s").ok())
        })?
    } else {
        None
    };
    let unless: Vec<String> = factors
        .iter()
        .map(|(f, _)| format!("{} = 0", f.to_input().replace('*', " ")))
        .collect();
    if args.json {
        let mut out = json!({
            "observability_matrix": json_matrix(&o),
            "rank": rank,
            "order": n,
            "observable": rank == n,
            "determinant": det.as_ref().map(|d| d.to_input()),
            "unobservable_where": losses,
            "unobservable_subspace": generic_basis.iter().map(json_matrix).collect::<Vec<_>>(),
            "unobservable_polynomial": generic_modes.as_ref().map(|p| p.to_input()),
        });
        work.add_json(&mut out);
        rep.json(&out);
        return Ok(Outcome::Ok);
    }
    work.describe(rep);
    outln!(rep, "Observability of (A, C)");
    outln!(rep, "  O_n = [C; CA; …; CA^(n−1)]:");
    for line in o.render().lines() {
        outln!(rep, "      {line}");
    }
    if let Some(d) = &det {
        let label = if o.rows() == n {
            "det O_n"
        } else {
            "det(O_nᵀ O_n)"
        };
        outln!(rep, "  {label} = {d}");
    }
    if factors.is_empty() {
        outln!(rep, "  rank O_n = {rank} (order n = {n})");
    } else {
        outln!(
            rep,
            "  rank O_n = {rank} for all but special values (order n = {n})"
        );
    }
    if rank < n {
        outln!(rep, "  NOT observable, for any value of the parameters");
        outln!(rep, "  unobservable subspace ker O_n, basis:");
        for v in &generic_basis {
            outln!(rep, "      {}", v.to_input());
        }
        if let Some(p) = &generic_modes {
            outln!(rep, "  unobservable modes: det(sI − A|ker O_n) = {p}");
        }
    } else if unless.is_empty() {
        outln!(rep, "  observable for every value of the parameters");
    } else {
        outln!(rep, "  observable unless {}", unless.join(" or "));
        for l in &losses {
            let Some(s) = &l.substitution else {
                outln!(
                    rep,
                    "    where {} = 0: the rank drops (no parameter to solve for)",
                    l.factor
                );
                continue;
            };
            outln!(
                rep,
                "    at {s}: rank O_n = {}, unobservable subspace {}",
                l.rank.unwrap_or(n),
                l.unobservable_subspace
                    .iter()
                    .map(|v| format!(
                        "[{}]",
                        v.iter()
                            .map(|r| r.join(", "))
                            .collect::<Vec<_>>()
                            .join("; ")
                    ))
                    .collect::<Vec<_>>()
                    .join(", ")
            );
            if let Some(p) = &l.unobservable_polynomial {
                outln!(rep, "      the mode lost: det(sI − A|ker O_n) = {p}");
            }
        }
    }
    work.validity(rep);
    Ok(Outcome::Ok)
}
