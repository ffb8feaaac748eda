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
use crate::symbolic::DesiredRequest;
use crate::syntax::Environment;
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
    crate::syntax::parse_matrix_with::<Fraction>(text, env).map_err(|e| e.show_in(text))
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
    // the design's parameters count too: a numeric plant with poles at −ω asks for formulas
    let designs =
        std::iter::once(&ex.design).chain(ex.parts.iter().filter_map(|p| p.design.as_ref()));
    let design: Vec<Fraction> = designs
        .filter_map(|d| {
            request(
                &d.poles,
                &d.poly,
                [&d.repeated, &d.butterworth, &d.bessel, &d.itae],
            )
        })
        .filter_map(|r| r.values(env).ok())
        .flatten()
        .collect();
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
    request(
        &spec.poles,
        &spec.poly,
        [&spec.repeated, &spec.butterworth, &spec.bessel, &spec.itae],
    )
    .ok_or_else(|| "the design names no desired polynomial".to_string())?
    .polynomial(env, n)
}

/// The desired polynomial a design names.
fn request<'a>(
    poles: &'a Option<String>,
    poly: &'a Option<String>,
    family: [&'a Option<String>; 4],
) -> Option<DesiredRequest<'a>> {
    if let Some(p) = poles {
        return Some(DesiredRequest::Poles(p));
    }
    if let Some(p) = poly {
        return Some(DesiredRequest::Poly(p));
    }
    Family::given(family.map(Option::as_ref)).map(|(f, t)| DesiredRequest::Family(f, t))
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
    let Ok(ans) = crate::worked::read_formula(answer, env) else {
        return (None, notes);
    };
    if let Some(d) = transformed_key(plant, part, key, &ans) {
        return (Some(d), notes);
    }
    if ans.shape() != key.shape() {
        return (None, notes);
    }
    let diagnosis = partly_right(plant, key, &ans, &mut notes);
    if diagnosis.is_none() && part.ask == Computation::Gain {
        notes.extend(placed_polynomial(plant, ex, part, &ans, env));
    }
    (diagnosis, notes)
}

fn named(mistake: Mistake, message: impl Into<String>) -> Option<Diagnosis> {
    Some(Diagnosis {
        mistake,
        message: message.into(),
    })
}

/// The answer is the key transformed by a named mistake: negated, transposed, reversed, or a
/// gain left in observer-canonical coordinates.
fn transformed_key(
    plant: &FormulaPlant,
    part: &PartSpec,
    key: &Matrix<Fraction>,
    ans: &Matrix<Fraction>,
) -> Option<Diagnosis> {
    let same_shape = ans.shape() == key.shape();
    if same_shape && *ans == key.neg() {
        let mistake = match part.ask {
            Computation::Gain => Mistake::SignConvention,
            Computation::StateFeedback => Mistake::FeedbackSign,
            _ => Mistake::Negated,
        };
        return named(mistake, "your formula is the key with the opposite sign");
    }
    if key.rows() != key.cols() && *ans == key.transpose() {
        return named(
            Mistake::Transposed,
            format!(
                "the right entries, as a {}×{} where a {}×{} is asked",
                ans.rows(),
                ans.cols(),
                key.rows(),
                key.cols()
            ),
        );
    }
    let reversed = key.entries().iter().rev();
    if same_shape && ans != key && ans.entries().iter().eq(reversed) {
        return named(Mistake::Reversed, "the right entries in reverse order");
    }
    if same_shape
        && part.ask == Computation::Gain
        && canonical_coordinates(plant, key).as_ref() == Some(ans)
    {
        return named(
            Mistake::CanonicalCoordinates,
            "your gain is K_o, still in observer-canonical coordinates; transform it back with T_o",
        );
    }
    None
}

/// The answer agrees with the key only at some values of the parameters (said, with the
/// values, in `notes`), or in all entries but one.
fn partly_right(
    plant: &FormulaPlant,
    key: &Matrix<Fraction>,
    ans: &Matrix<Fraction>,
    notes: &mut Vec<String>,
) -> Option<Diagnosis> {
    let places = agreement_set(ans, key);
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
        return named(
            Mistake::OnlyAtSomeValues,
            "right at particular values of the parameters, not as a formula",
        );
    }
    let wrong: Vec<usize> = (0..key.entries().len())
        .filter(|&i| ans.entries()[i] != key.entries()[i])
        .collect();
    match wrong.as_slice() {
        [i] if key.entries().len() > 1 => named(
            Mistake::Slip,
            format!(
                "one entry is wrong: ({}, {}) should be {}, everything else is right",
                i / key.cols() + 1,
                i % key.cols() + 1,
                key.entries()[*i].to_input()
            ),
        ),
        _ => None,
    }
}

/// The observer polynomial a wrong gain places, in words.
fn placed_polynomial(
    plant: &FormulaPlant,
    ex: &ExerciseFile,
    part: &PartSpec,
    ans: &Matrix<Fraction>,
    env: &Environment,
) -> Option<String> {
    let spec = super::key::claim_for(ex, part, None);
    let k = convention(&spec).from_a_minus_kc(ans); // self-inverse: L ↦ −L
    let c = part_c(plant, part, env).ok()?;
    let observer = plant.a.sub(&k.mul(&c).ok()?).ok()?;
    let p = crate::linalg::characteristic_polynomial(&observer, "s").ok()?;
    Some(format!("your gain places the observer polynomial {p}"))
}

/// `K_o = T_o⁻¹ K`, the gain in observer-canonical coordinates (for naming that mistake).
fn canonical_coordinates(plant: &FormulaPlant, key: &Matrix<Fraction>) -> Option<Matrix<Fraction>> {
    let form = crate::canonical_form::observer_form_di_ruscio(&plant.a, None, &plant.c).ok()?;
    form.t_inv.mul(key).ok()
}
