//! Exercises whose answers are formulas: the plant keeps free parameters (`[0 1; -w0^2 0]`
//! with no value for `w0`), the key is computed in the rational functions of them, and a
//! student's formula is checked as an identity — with the mistakes named symbolically (the
//! sign convention, canonical coordinates, transposed, reversed, a slip in one entry) and a
//! verdict of its own for an answer that equals the key only at some values of the parameters.

use super::diagnose::Diagnosis;
use super::format::{ExerciseFile, PartSpec};
use super::Mistake;
use crate::algebra::{Fraction, Ring, Zero};
use crate::derivation::Derivation;
use crate::linalg::Matrix;
use crate::observer::{Convention, Detail, Family, GainMethod};
use crate::poly::Poly;
use crate::syntax::{evaluate_with, parse_matrix_expressions, Environment};
use crate::worked::{Computation, Value};

/// The plant of an exercise with free parameters, read once.
#[derive(Debug, Clone)]
pub struct FormulaPlant {
    /// A.
    pub a: Matrix<Fraction>,
    /// B, when given.
    pub b: Option<Matrix<Fraction>>,
    /// C.
    pub c: Matrix<Fraction>,
    /// The free parameters (those without a value in `[parameters]`).
    pub parameters: Vec<String>,
}

fn read_matrix(text: &str, env: &Environment) -> Result<Matrix<Fraction>, String> {
    let rows = parse_matrix_expressions(text).map_err(|e| e.show_in(text))?;
    let values = rows
        .iter()
        .map(|r| {
            r.iter()
                .map(|e| evaluate_with::<Fraction>(e, env))
                .collect::<Result<Vec<_>, _>>()
        })
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| e.show_in(text))?;
    Matrix::from_rows(values).map_err(|e| e.to_string())
}

/// The plant with its free parameters, or `None` when every symbol has a value (the numeric
/// key applies).
///
/// # Errors
/// A matrix that cannot be read, or too many parameters.
pub fn plant(ex: &ExerciseFile, env: &Environment) -> Result<Option<FormulaPlant>, String> {
    let (Some(a), Some(c)) = (&ex.system.a, &ex.system.c) else {
        return Ok(None);
    };
    let a = read_matrix(a, env)?;
    let c = read_matrix(c, env)?;
    let b = ex
        .system
        .b
        .as_deref()
        .map(|b| read_matrix(b, env))
        .transpose()?;
    let mut all: Vec<&Fraction> = a.entries().iter().chain(c.entries()).collect();
    if let Some(b) = &b {
        all.extend(b.entries());
    }
    let mut design: Vec<Fraction> = Vec::new();
    let d = &ex.design;
    let mut texts: Vec<&String> = [&d.poles, &d.repeated, &d.butterworth, &d.bessel, &d.itae]
        .into_iter()
        .flatten()
        .collect();
    for part in &ex.parts {
        if let Some(o) = &part.design {
            texts.extend(
                [&o.poles, &o.repeated, &o.butterworth, &o.bessel, &o.itae]
                    .into_iter()
                    .flatten(),
            );
        }
    }
    for t in texts {
        if let Ok(rows) = parse_matrix_expressions(t) {
            design.extend(
                rows.iter()
                    .flatten()
                    .filter_map(|e| evaluate_with::<Fraction>(e, env).ok()),
            );
        }
    }
    for p in [&d.poly].into_iter().flatten().chain(
        ex.parts
            .iter()
            .filter_map(|p| p.design.as_ref()?.poly.as_ref()),
    ) {
        if let Ok(e) = crate::syntax::parse_expression(p) {
            if let Ok(x) = evaluate_with::<Fraction>(&e, env) {
                if let Some(cs) = x.coefficients_in("s") {
                    design.extend(cs);
                }
            }
        }
    }
    all.extend(design.iter());
    let parameters = crate::symbolic::parameters(all);
    if parameters.is_empty() {
        return Ok(None);
    }
    crate::symbolic::check_parameters(&parameters).map_err(|e| e.to_string())?;
    Ok(Some(FormulaPlant {
        a,
        b,
        c,
        parameters,
    }))
}

/// The desired polynomial of a part's design, in the parameters.
fn desired(
    spec: &crate::worked::ClaimSpec,
    env: &Environment,
    n: usize,
) -> Result<Poly<Fraction>, String> {
    let read = |t: &str| -> Result<Fraction, String> {
        let e = crate::syntax::parse_expression(t).map_err(|e| e.show_in(t))?;
        evaluate_with::<Fraction>(&e, env).map_err(|e| e.show_in(t))
    };
    if let Some(p) = &spec.poles {
        let rows = parse_matrix_expressions(p).map_err(|e| e.show_in(p))?;
        let poles = rows
            .iter()
            .flatten()
            .map(|e| evaluate_with::<Fraction>(e, env).map_err(|e| e.show_in(p)))
            .collect::<Result<Vec<_>, _>>()?;
        if poles.len() != n {
            return Err(format!("{} poles for order {n}", poles.len()));
        }
        return Ok(crate::symbolic::poles_polynomial(&poles));
    }
    if let Some(p) = &spec.poly {
        let whole = read(p)?;
        let coeffs = whole
            .coefficients_in("s")
            .ok_or_else(|| "the polynomial has s in a denominator".to_string())?;
        let poly = Poly::new(coeffs, "s");
        if poly.degree() != Some(n) || !poly.is_monic() {
            return Err(format!(
                "the desired polynomial must be monic of degree {n}"
            ));
        }
        return Ok(poly);
    }
    let family = Family::given([
        spec.repeated.as_ref(),
        spec.butterworth.as_ref(),
        spec.bessel.as_ref(),
        spec.itae.as_ref(),
    ]);
    let Some((family, t)) = family else {
        return Err("the design names no desired polynomial".into());
    };
    crate::symbolic::family_polynomial(family, &read(t)?, n)
}

fn convention(spec: &crate::worked::ClaimSpec) -> Convention {
    spec.convention
        .as_deref()
        .and_then(Convention::parse)
        .unwrap_or(Convention::AMinusKC)
}

/// The part's C: its own, or the system's.
fn part_c(
    plant: &FormulaPlant,
    part: &PartSpec,
    env: &Environment,
) -> Result<Matrix<Fraction>, String> {
    part.c
        .as_deref()
        .map_or_else(|| Ok(plant.c.clone()), |c| read_matrix(c, env))
}

/// The key of one part, computed in the parameters, with its derivation.
///
/// # Errors
/// A part that cannot be asked with free parameters, or a design that fails (named).
pub fn key(
    ex: &ExerciseFile,
    plant: &FormulaPlant,
    part: &PartSpec,
    env: &Environment,
) -> Result<(Value, Derivation), String> {
    let spec = super::key::claim_for(ex, part, None);
    let c = part_c(plant, part, env)?;
    let (a, n) = (&plant.a, plant.a.rows());
    let one =
        |x: Fraction| Matrix::from_rows(vec![vec![x]]).unwrap_or_else(|_| Matrix::zeros(1, 1));
    let run = |work: &dyn Fn() -> Result<(Value, Derivation), String>| {
        crate::symbolic::within_budget(work).map_err(|e| e.to_string())?
    };
    let titled = |t: &str| Derivation::new(t);
    match part.ask {
        Computation::Gain => run(&|| {
            let p = desired(&spec, env, n)?;
            let d = crate::observer::design_symbolic(a, &c, &p, GainMethod::Ackermann, convention(&spec), Detail::Full)
                .map_err(|e| e.to_string())?;
            Ok((Value::Formula(d.gain.matrix), d.derivation))
        }),
        Computation::StateFeedback => run(&|| {
            let b = plant.b.as_ref().ok_or("state feedback needs B")?;
            let p = desired(&spec, env, n)?;
            let d = crate::feedback::design_feedback_symbolic(
                a,
                b,
                &p,
                GainMethod::Ackermann,
                crate::feedback::FeedbackConvention::UEqualsFx,
                Detail::Full,
            )
            .map_err(|e| e.to_string())?;
            Ok((Value::Formula(d.gain), d.derivation))
        }),
        Computation::ObservabilityMatrix => run(&|| {
            let o = crate::observability::observability_matrix(a, &c).map_err(|e| e.to_string())?;
            let mut d = titled("Observability matrix");
            d.push("O_n", "[C; CA; …; CA^(n−1)]", &o);
            Ok((Value::Formula(o), d))
        }),
        Computation::ObservabilityDeterminant => run(&|| {
            let o = crate::observability::observability_matrix(a, &c).map_err(|e| e.to_string())?;
            let det = crate::linalg::determinant(&o).map_err(|e| e.to_string())?;
            let mut d = titled("Determinant of the observability matrix");
            d.push("O_n", "[C; CA; …; CA^(n−1)]", &o);
            let m = one(det);
            d.push("det O_n", "", &m);
            Ok((Value::Formula(m), d))
        }),
        Computation::CharacteristicPolynomial => run(&|| {
            let p = crate::linalg::characteristic_polynomial(a, "s").map_err(|e| e.to_string())?;
            let mut d = titled("Characteristic polynomial");
            d.push("det(sI − A)", "", &p);
            Ok((Value::Formula(one(crate::symbolic::as_fraction(&p))), d))
        }),
        Computation::DesiredPolynomial => run(&|| {
            let p = desired(&spec, env, n)?;
            let mut d = titled("Desired polynomial");
            d.push("P(s)", "", &p);
            Ok((Value::Formula(one(crate::symbolic::as_fraction(&p))), d))
        }),
        other => Err(format!(
            "'{other}' cannot be asked with free parameters ({}); give them values in [parameters] or ask for gain, state_feedback, observability_matrix, observability_determinant, characteristic_polynomial or desired_polynomial",
            plant.parameters.join(", ")
        )),
    }
}

/// The student's answer read as a matrix of formulas (values of `env` substituted); one
/// formula (not in brackets) is one expression.
fn read_answer(answer: &str, env: &Environment) -> Option<Matrix<Fraction>> {
    if !answer.trim_start().starts_with('[') {
        let e = crate::syntax::parse_expression(answer).ok()?;
        let x = evaluate_with::<Fraction>(&e, env).ok()?;
        return Matrix::from_rows(vec![vec![x]]).ok();
    }
    let m = read_matrix(answer, env).ok()?;
    (m.rows() > 0 && m.cols() > 0).then_some(m)
}

/// Where two formulas agree, when they differ: the factors of the gcd of the numerators of
/// the differences, and a value of one parameter that makes each vanish.
fn agreement_set(
    answer: &Matrix<Fraction>,
    key: &Matrix<Fraction>,
) -> Vec<(String, Option<String>)> {
    let mut g: Option<crate::algebra::MultiPoly> = None;
    for (x, y) in answer.entries().iter().zip(key.entries()) {
        let diff = x.clone() - y.clone();
        if diff.is_zero() {
            continue;
        }
        g = Some(match g {
            None => diff.numerator().clone(),
            Some(g) => crate::algebra::poly_gcd(&g, diff.numerator()),
        });
    }
    let Some(g) = g.filter(|g| g.as_constant().is_none()) else {
        return Vec::new();
    };
    crate::symbolic::factors(&g)
        .into_iter()
        // a factor in square roots alone (√2 − 2) is a nonzero number, not a condition
        .filter(|(f, _)| f.variables().iter().any(|v| !v.starts_with('√')))
        .map(|(f, _)| {
            let solved =
                crate::symbolic::solve_for(&f).map(|(v, x)| format!("{v} = {}", x.to_input()));
            (f.to_input(), solved)
        })
        .collect()
}

/// Names the mistake in a wrong formula: the key transformed as each mistake would, compared
/// as identities; then the values where the answer is right after all; and, for a gain, the
/// polynomial the answer places.
pub fn diagnose(
    plant: &FormulaPlant,
    ex: &ExerciseFile,
    part: &PartSpec,
    key: &Matrix<Fraction>,
    answer: &str,
    env: &Environment,
) -> (Option<Diagnosis>, Vec<String>) {
    let mut notes = Vec::new();
    let Some(ans) = read_answer(answer, env) else {
        return (None, notes);
    };
    let found = |mistake: Mistake, message: String| Some(Diagnosis { mistake, message });
    let is_gain = matches!(part.ask, Computation::Gain | Computation::StateFeedback);
    if ans.shape() == key.shape() && ans == key.neg() {
        let mistake = if is_gain {
            if part.ask == Computation::Gain {
                Mistake::SignConvention
            } else {
                Mistake::FeedbackSign
            }
        } else {
            Mistake::Negated
        };
        return (
            found(
                mistake,
                "your formula is the key with the opposite sign".into(),
            ),
            notes,
        );
    }
    if ans.shape() == (key.cols(), key.rows()) && key.rows() != key.cols() && ans == key.transpose()
    {
        return (
            found(
                Mistake::Transposed,
                format!(
                    "the right entries, as a {}×{} where a {}×{} is asked",
                    ans.rows(),
                    ans.cols(),
                    key.rows(),
                    key.cols()
                ),
            ),
            notes,
        );
    }
    if ans.shape() == key.shape() && key.entries().len() > 1 {
        let reversed: Vec<Fraction> = key.entries().iter().rev().cloned().collect();
        if ans.entries() == reversed.as_slice() && ans != *key {
            return (
                found(
                    Mistake::Reversed,
                    "the right entries in reverse order".into(),
                ),
                notes,
            );
        }
    }
    if part.ask == Computation::Gain && ans.shape() == key.shape() {
        if let Some(k_o) = canonical_coordinates(plant, key) {
            if ans == k_o {
                return (
                    found(
                        Mistake::CanonicalCoordinates,
                        "your gain is K_o, still in observer-canonical coordinates; transform it back with T_o".into(),
                    ),
                    notes,
                );
            }
        }
    }
    if ans.shape() == key.shape() {
        let wrong: Vec<usize> = (0..key.entries().len())
            .filter(|&i| ans.entries()[i] != key.entries()[i])
            .collect();
        let places = agreement_set(&ans, key);
        if !places.is_empty() {
            let list: Vec<String> = places
                .iter()
                .map(|(f, s)| match s {
                    Some(s) => format!("{} = 0 (e.g. {s})", f.replace('*', " ")),
                    None => format!("{} = 0", f.replace('*', " ")),
                })
                .collect();
            notes.push(format!(
                "your formula equals the key only where {}, not for every value of {}",
                list.join(" or "),
                plant.parameters.join(", ")
            ));
        }
        if !places.is_empty() {
            return (
                found(
                    Mistake::OnlyAtSomeValues,
                    "right at particular values of the parameters, not as a formula".into(),
                ),
                notes,
            );
        }
        if wrong.len() == 1 && key.entries().len() > 1 {
            let i = wrong[0];
            let (r, c) = (i / key.cols() + 1, i % key.cols() + 1);
            return (
                found(
                    Mistake::Slip,
                    format!(
                        "one entry is wrong: ({r}, {c}) should be {}, everything else is right",
                        key.entries()[i].to_input()
                    ),
                ),
                notes,
            );
        }
    }
    if part.ask == Computation::Gain && ans.shape() == key.shape() {
        let spec = super::key::claim_for(ex, part, None);
        let k = convention(&spec).from_a_minus_kc(&ans); // self-inverse: L ↦ −L
        let placed = part_c(plant, part, env).ok().and_then(|c| {
            let observer = plant.a.sub(&k.mul(&c).ok()?).ok()?;
            crate::linalg::characteristic_polynomial(&observer, "s").ok()
        });
        if let Some(p) = placed {
            notes.push(format!("your gain places the observer polynomial {p}"));
        }
    }
    (None, notes)
}

/// `K_o = T_o⁻¹ K`, the gain in observer-canonical coordinates (for naming that mistake).
fn canonical_coordinates(plant: &FormulaPlant, key: &Matrix<Fraction>) -> Option<Matrix<Fraction>> {
    let form = crate::canonical_form::observer_form_di_ruscio(&plant.a, None, &plant.c).ok()?;
    form.t_inv.mul(key).ok()
}
