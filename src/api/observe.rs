//! `owb observe`: the observability report.

use super::args::json_matrix;
use super::parametric::Parametric;
use super::{Outcome, Report};
use crate::algebra::{Fraction, MultiPoly, Ring};
use crate::linalg::Matrix;
use crate::observability::observability_report;
use crate::poly::Poly;
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
        rep.json(json!({
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

/// The unobservable part of a symbolic pair: a basis of ker O_n and det(sI − A|ker O_n).
struct Unobservable {
    rank: usize,
    basis: Vec<Matrix<Fraction>>,
    polynomial: Poly<Fraction>,
}

impl Unobservable {
    fn of(a: &Matrix<Fraction>, o: &Matrix<Fraction>) -> Option<Self> {
        let rank = crate::linalg::rank(o);
        let (basis, polynomial) = crate::observability::unobservable_part(a, o, rank).ok()?;
        Some(Unobservable {
            rank,
            basis,
            polynomial,
        })
    }
    fn subspace_text(&self) -> String {
        let v: Vec<String> = self.basis.iter().map(|v| v.to_input()).collect();
        v.join(", ")
    }
}

/// What is lost where a factor of `det O_n` vanishes: the substitution that makes it vanish
/// (solving the factor for one parameter) and the unobservable part there.
struct Loss {
    factor: MultiPoly,
    at: Option<(String, Fraction)>,
    there: Option<Unobservable>,
}

impl Loss {
    fn of(a: &Matrix<Fraction>, c: &Matrix<Fraction>, factor: &MultiPoly) -> Loss {
        let at = crate::symbolic::solve_for(factor);
        let there = at.as_ref().and_then(|(name, value)| {
            let put = |m: &Matrix<Fraction>| m.map(|x| x.substitute(name, value));
            let (a, c) = (put(a), put(c));
            let o = crate::observability::observability_matrix(&a, &c).ok()?;
            Unobservable::of(&a, &o)
        });
        Loss {
            factor: factor.clone(),
            at,
            there,
        }
    }
    fn substitution(&self) -> Option<String> {
        self.at
            .as_ref()
            .map(|(name, value)| format!("{name} = {}", value.to_input()))
    }
    fn json(&self) -> serde_json::Value {
        json!({
            "factor": self.factor.to_input(),
            "substitution": self.substitution(),
            "rank": self.there.as_ref().map(|u| u.rank),
            "unobservable_subspace": self.there.as_ref().map_or_else(Vec::new, |u| u.basis.iter().map(json_matrix).collect()),
            "unobservable_polynomial": self.there.as_ref().filter(|u| !u.basis.is_empty()).map(|u| u.polynomial.to_input()),
        })
    }
    fn report(&self, rep: &mut Report) {
        let (Some(s), Some(u)) = (self.substitution(), &self.there) else {
            outln!(
                rep,
                "    where {} = 0: the rank drops (no parameter to solve for)",
                self.factor.to_input()
            );
            return;
        };
        outln!(
            rep,
            "    at {s}: rank O_n = {}, unobservable subspace {}",
            u.rank,
            u.subspace_text()
        );
        if !u.basis.is_empty() {
            outln!(
                rep,
                "      the mode lost: det(sI − A|ker O_n) = {}",
                u.polynomial.to_input()
            );
        }
    }
}

/// Observability with parameters, computed: O_n in symbols, det O_n and its factors, the
/// generic unobservable part, and what is lost where each factor vanishes.
struct SymbolicObservability {
    o: Matrix<Fraction>,
    det: Option<Fraction>,
    generic: Unobservable,
    losses: Vec<Loss>,
}

impl SymbolicObservability {
    fn of(work: &Parametric, a: &Matrix<Fraction>, c: &Matrix<Fraction>) -> Result<Self> {
        let o = work.run(|| crate::observability::observability_matrix(a, c))??;
        let generic = work
            .run(|| Unobservable::of(a, &o))?
            .ok_or_else(|| anyhow::anyhow!("in --a: the unobservable part cannot be computed"))?;
        let det = work.run(|| super::parametric::observability_determinant(a, c))?;
        let factors = work.run(|| {
            det.as_ref()
                .map(|d| crate::symbolic::factors(d.numerator()))
                .unwrap_or_default()
        })?;
        let losses = work.run(|| factors.iter().map(|(f, _)| Loss::of(a, c, f)).collect())?;
        Ok(SymbolicObservability {
            o,
            det,
            generic,
            losses,
        })
    }
    fn json(&self, n: usize) -> serde_json::Value {
        let unobservable = self.generic.rank < n;
        json!({
            "observability_matrix": json_matrix(&self.o),
            "rank": self.generic.rank,
            "order": n,
            "observable": !unobservable,
            "determinant": self.det.as_ref().map(|d| d.to_input()),
            "unobservable_where": self.losses.iter().map(Loss::json).collect::<Vec<_>>(),
            "unobservable_subspace": self.generic.basis.iter().map(json_matrix).collect::<Vec<_>>(),
            "unobservable_polynomial": unobservable.then(|| self.generic.polynomial.to_input()),
        })
    }
    fn report(&self, rep: &mut Report, n: usize) {
        outln!(rep, "Observability of (A, C)");
        outln!(rep, "  O_n = [C; CA; …; CA^(n−1)]:");
        for line in self.o.render().lines() {
            outln!(rep, "      {line}");
        }
        if let Some(d) = &self.det {
            let label = if self.o.rows() == n {
                "det O_n"
            } else {
                "det(O_nᵀ O_n)"
            };
            outln!(rep, "  {label} = {d}");
        }
        let rank = self.generic.rank;
        if self.losses.is_empty() {
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
            for v in &self.generic.basis {
                outln!(rep, "      {}", v.to_input());
            }
            outln!(
                rep,
                "  unobservable modes: det(sI − A|ker O_n) = {}",
                self.generic.polynomial.to_input()
            );
        } else if self.losses.is_empty() {
            outln!(rep, "  observable for every value of the parameters");
        } else {
            let unless: Vec<String> = self
                .losses
                .iter()
                .map(|l| format!("{} = 0", l.factor.to_input().replace('*', " ")))
                .collect();
            outln!(rep, "  observable unless {}", unless.join(" or "));
            for l in &self.losses {
                l.report(rep);
            }
        }
    }
}

/// Observability with parameters: O_n in symbols, det O_n factored, and for each factor what
/// is lost where it vanishes.
fn symbolic(
    args: &Args,
    a: &Matrix<Fraction>,
    c: &Matrix<Fraction>,
    rep: &mut Report,
) -> Result<Outcome> {
    let work = Parametric::new(a)?.with(c.entries(), "C")?;
    let found = SymbolicObservability::of(&work, a, c)?;
    let json = args.json.then(|| found.json(a.rows()));
    work.answer(rep, json, |rep| found.report(rep, a.rows()));
    Ok(Outcome::Ok)
}
