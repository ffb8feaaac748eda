//! Naming a student's mistake. Each recognised mistake is a *candidate answer* computed from the
//! exercise (the gain for the other convention, the canonical-coordinate gain, the transposed
//! matrix, …); when the student's answer matches a candidate (with the same rounding rules as a
//! correct answer) the mistake is named. For gains, the poles the answer actually places are
//! computed and compared with other observer polynomials (another family, another time
//! constant, mirrored poles).

use super::key::{AnswerKey, KeyPart};
use super::Mistake;
use crate::algebra::{Quadratic, Rational};
use crate::linalg::{characteristic_polynomial, Matrix};
use crate::observer::float_check::companion_roots;
use crate::observer::Family;
use crate::observer::{Convention, ObserverGain};
use crate::poly::Poly;
use crate::syntax::{evaluate_with, parse_matrix_expressions};
use crate::worked::{compare, ClaimSpec, Computation, Identity, Inputs, Value};

/// The largest number (numerator plus denominator bits) in an answer the diagnosis compares
/// with its candidate mistakes.
const MAX_DIAGNOSED_BITS: u64 = 2048;

/// A named mistake with its explanation.
#[derive(Clone, Debug, PartialEq)]
pub struct Diagnosis {
    /// Which mistake.
    pub mistake: Mistake,
    /// What the student did, in words, with the numbers.
    pub message: String,
}

fn matches(key: &AnswerKey, candidate: &Value, answer: &str) -> bool {
    compare(candidate, answer, &key.env).is_ok_and(|a| a.holds())
}

fn convention(part: &KeyPart) -> Convention {
    part.claim
        .convention
        .as_deref()
        .and_then(Convention::parse)
        .unwrap_or(Convention::AMinusKC)
}

/// The student's matrix, exact (decimals as the rationals they denote).
pub fn answer_matrix(key: &AnswerKey, answer: &str) -> Option<Matrix<Quadratic>> {
    crate::syntax::parse_matrix_with(answer, &key.env).ok()
}

fn recompute_as(key: &AnswerKey, part: &KeyPart, what: Computation) -> Option<Value> {
    let claim = ClaimSpec {
        what,
        ..part.claim.clone()
    };
    key.recompute(&claim)
}

/// Candidate wrong answers for this part: (mistake, value, explanation).
fn candidates(
    key: &AnswerKey,
    part: &KeyPart,
    answer: Option<&Matrix<Quadratic>>,
) -> Vec<Candidate> {
    let mut out = Vec::new();
    let conv = convention(part);
    let other = match conv {
        Convention::AMinusKC => "A + LC",
        Convention::APlusLC => "A − KC",
    };
    let asked = match conv {
        Convention::AMinusKC => "A − KC",
        Convention::APlusLC => "A + LC",
    };
    match (&part.value, part.spec.ask) {
        (Value::Matrix(m), ask) => {
            out.extend(matrix_candidates(key, part, m, ask, answer, (other, asked)));
        }
        (Value::Polynomial(p), ask) => {
            out.push((Mistake::Negated, Value::Polynomial(-p.clone()), "your polynomial is the negative of the answer; the characteristic polynomial det(λI − A) is monic (det(A − λI) differs from it by (−1)ⁿ)".into()));
            if ask == Computation::DesiredPolynomial {
                for (family, value) in other_families(key, part) {
                    out.push((
                        Mistake::WrongPolynomial,
                        Value::Polynomial(value),
                        format!(
                            "this is the {family} polynomial; the exercise asks for {}",
                            asked_family(key, part)
                        ),
                    ));
                }
            }
        }
        (Value::Transfer(t), _) => {
            out.push((Mistake::Negated, Value::Transfer(-t.clone()), "your transfer function has the wrong sign: positive instead of negative feedback or the reverse (u = F x̂ with F as given: check the sign of the feedback)".into()));
        }
        _ => {}
    }
    out.extend(other_parts(key, part));
    out
}

/// A candidate wrong answer: (mistake, value, explanation).
type Candidate = (Mistake, Value, String);

/// Candidates for a matrix part `m` (`ask` says what it is; `conventions` = (the other, the
/// asked) observer convention in words; `answer` the student's matrix when it reads as one).
fn matrix_candidates(
    key: &AnswerKey,
    part: &KeyPart,
    m: &Matrix<Quadratic>,
    ask: Computation,
    answer: Option<&Matrix<Quadratic>>,
    (other, asked): (&str, &str),
) -> Vec<Candidate> {
    // neighbouring problems first: the same design for another output of the same system
    let mut out = another_output(key, part, ask);
    if ask == Computation::StateFeedback {
        out.push((
            Mistake::FeedbackSign,
            Value::Matrix(m.neg()),
            "your F has the opposite sign: it is K of u = −Kx (negative feedback with the minus written outside); the exercise asks for F in u = Fx, so F = −K".into(),
        ));
    }
    if ask == Computation::DiscreteGain {
        let current = ClaimSpec {
            what: Computation::CurrentGain,
            estimator: Some("current".into()),
            ..part.claim.clone()
        };
        if let Some(Value::Matrix(l_c)) = key.recompute(&current) {
            out.push((
                Mistake::CurrentEstimator,
                Value::Matrix(l_c),
                "this is the current (filtered) estimator's gain L_c = A⁻¹K; the exercise asks for the prediction estimator's K, which multiplies y(k) − C x̄(k) in x̄(k+1)".into(),
            ));
        }
    }
    if matches!(
        ask,
        Computation::Gain
            | Computation::CanonicalGain
            | Computation::DiscreteGain
            | Computation::ReducedOrderGain
            | Computation::DetectableGain
    ) {
        out.push((
            Mistake::SignConvention,
            Value::Matrix(m.neg()),
            format!("your answer is the negative of the gain: it is the gain for the {other} convention, but the exercise asks for {asked}"),
        ));
    }
    if ask == Computation::Gain {
        if let Some(Value::Matrix(k_o)) = recompute_as(key, part, Computation::CanonicalGain) {
            out.push((
                Mistake::CanonicalCoordinates,
                Value::Matrix(k_o.clone()),
                format!("this is the gain in observer-canonical coordinates, K_o = {}; transform it back with T (K = T K_o) to get the gain of the original system", k_o.to_input()),
            ));
            out.push((
                Mistake::CanonicalCoordinates,
                Value::Matrix(k_o.neg()),
                format!("this is −K_o, the canonical-coordinate gain with the other sign convention: transform with T (K = T K_o) and use the {asked} convention"),
            ));
        }
    }
    if matches!(
        ask,
        Computation::CanonicalTransformation | Computation::CanonicalTransformationInverse
    ) {
        if let Ok(inv) = crate::linalg::inverse(m) {
            out.push((
                Mistake::Inverse,
                Value::Matrix(inv),
                "you gave the inverse: the exercise uses x = T x_o (A_o = T⁻¹ A T); check which of T and T⁻¹ is asked".into(),
            ));
        }
    }
    if matches!(
        ask,
        Computation::CanonicalA | Computation::CanonicalC | Computation::CanonicalB
    ) {
        out.push((
            Mistake::OtherCanonicalForm,
            Value::Matrix(m.transpose()),
            "this is the transpose, the controller (companion) canonical form; the observer canonical form is its dual (coefficients in the first column of A_o, C_o = [1 0 … 0])".into(),
        ));
    }
    if m.rows() != m.cols() {
        out.push((
            Mistake::Transposed,
            Value::Matrix(m.transpose()),
            format!("transposed: the answer should be {}×{}", m.rows(), m.cols()),
        ));
    }
    if (m.rows() == 1 || m.cols() == 1) && m.rows() * m.cols() > 1 {
        let entries: Vec<Quadratic> = (0..m.rows()).flat_map(|i| m.row(i).to_vec()).collect();
        let rev: Vec<Quadratic> = entries.into_iter().rev().collect();
        let r = Matrix::from_fn(m.rows(), m.cols(), |i, j| rev[i * m.cols() + j].clone());
        let lemma = key.parts.iter().any(|q| {
            q.claim.method.as_deref() == Some("lemma-3.1")
                || q.claim.identity == Some(Identity::Lemma31GivesCMinusA)
        });
        let why = if lemma {
            "the entries are in reverse order (the state ordering of the other canonical form, or Lemma 3.1's rotation undone)"
        } else {
            "the entries are in reverse order (the state ordering of the other canonical form?)"
        };
        out.push((Mistake::Reversed, Value::Matrix(r), why.into()));
    }
    if let Some(a) = answer {
        out.extend(permuted(m, a));
    }
    if let Some(procedure) = other_procedure(key, part) {
        out.push(procedure);
    }
    out
}

/// The largest order for which the gains of every other output are tried.
const MAX_OUTPUTS_TRIED: usize = 8;

/// The gains of the neighbouring problems that measure another state: for a single-output
/// system, the same design (polynomial, convention, method) with `C = e_jᵀ` for each state `x_j`
/// the exercise does not measure, where that pair is observable.
fn another_output(key: &AnswerKey, part: &KeyPart, ask: Computation) -> Vec<Candidate> {
    if !matches!(ask, Computation::Gain | Computation::DiscreteGain) {
        return Vec::new();
    }
    let Some(c_text) = part.claim.c.as_ref().or(key.example.system.c.as_ref()) else {
        return Vec::new();
    };
    let Some(c) = answer_matrix(key, c_text) else {
        return Vec::new();
    };
    let n = c.cols();
    if c.rows() != 1 || n > MAX_OUTPUTS_TRIED {
        return Vec::new();
    }
    let mut out = Vec::new();
    for j in 0..n {
        let row: Vec<&str> = (0..n).map(|k| if k == j { "1" } else { "0" }).collect();
        let unit = format!("[{}]", row.join(" "));
        if answer_matrix(key, &unit).is_some_and(|e| e == c) {
            continue;
        }
        let claim = ClaimSpec {
            c: Some(unit.clone()),
            ..part.claim.clone()
        };
        if let Some(value @ Value::Matrix(_)) = key.recompute(&claim) {
            out.push((
                Mistake::AnotherOutput,
                value,
                format!(
                    "this is the gain for output x{} (C = {unit}): the right design for another measurement of the same system; this exercise measures y = C x with C = {}",
                    subscript(j + 1),
                    c.to_input()
                ),
            ));
        }
    }
    out
}

fn subscript(k: usize) -> String {
    k.to_string()
        .chars()
        .map(|d| match d {
            '0' => '₀',
            '1' => '₁',
            '2' => '₂',
            '3' => '₃',
            '4' => '₄',
            '5' => '₅',
            '6' => '₆',
            '7' => '₇',
            '8' => '₈',
            '9' => '₉',
            other => other,
        })
        .collect()
}

/// The right answers to the other parts of the same exercise, of the same kind and shape.
fn other_parts(key: &AnswerKey, part: &KeyPart) -> Vec<Candidate> {
    let mut out = Vec::new();
    for q in &key.parts {
        let same_kind = match (&q.value, &part.value) {
            (Value::Matrix(x), Value::Matrix(y)) => x.shape() == y.shape(),
            (Value::Polynomial(_), Value::Polynomial(_))
            | (Value::Transfer(_), Value::Transfer(_)) => true,
            _ => false,
        };
        if q.spec.id != part.spec.id && same_kind && q.value != part.value {
            out.push((
                Mistake::AnotherPart,
                q.value.clone(),
                format!(
                    "this is the answer to part {} ({}), not to part {}",
                    q.spec.id, q.spec.prompt, part.spec.id
                ),
            ));
        }
    }
    out
}

/// The key's matrix with its rows (or columns) in the order the student's answer has them,
/// when the answer holds the right rows (columns) in another order — found by matching
/// entries in f64, then confirmed exactly by the comparison like any other candidate.
fn permuted(m: &Matrix<Quadratic>, a: &Matrix<Quadratic>) -> Vec<Candidate> {
    if a.shape() != m.shape() {
        return Vec::new();
    }
    let close = |x: &Quadratic, y: &Quadratic| {
        let (x, y) = (
            crate::algebra::ToF64::to_f64(x),
            crate::algebra::ToF64::to_f64(y),
        );
        (x - y).abs() <= 5e-3 * y.abs().max(1e-9)
    };
    // order[i] = the key's line that the answer's line i is
    let order = |lines: usize, line: &dyn Fn(&Matrix<Quadratic>, usize) -> Vec<Quadratic>| {
        let mut used = vec![false; lines];
        let mut order = Vec::with_capacity(lines);
        for i in 0..lines {
            let ours = line(a, i);
            let j = (0..lines)
                .find(|&j| !used[j] && line(m, j).iter().zip(&ours).all(|(x, y)| close(y, x)))?;
            used[j] = true;
            order.push(j);
        }
        (order.iter().enumerate().any(|(i, &j)| i != j)).then_some(order)
    };
    let mut out = Vec::new();
    let rows = |x: &Matrix<Quadratic>, i: usize| x.row(i).to_vec();
    let cols = |x: &Matrix<Quadratic>, j: usize| x.col(j);
    if m.rows() > 1 {
        if let Some(o) = order(m.rows(), &rows) {
            let p = Matrix::from_fn(m.rows(), m.cols(), |i, j| m.get(o[i], j).clone());
            let shown: Vec<String> = o.iter().map(|j| (j + 1).to_string()).collect();
            out.push((Mistake::Permuted, Value::Matrix(p), format!("the right rows in another order (yours are rows {} of the answer): check the ordering of the states", shown.join(", "))));
        }
    }
    if m.cols() > 1 {
        if let Some(o) = order(m.cols(), &cols) {
            let p = Matrix::from_fn(m.rows(), m.cols(), |i, j| m.get(i, o[j]).clone());
            let shown: Vec<String> = o.iter().map(|j| (j + 1).to_string()).collect();
            out.push((Mistake::Permuted, Value::Matrix(p), format!("the right columns in another order (yours are columns {} of the answer): check the ordering of the states or outputs", shown.join(", "))));
        }
    }
    out
}

/// A canonical-form part answered with the other procedure's transformation (Di Ruscio's
/// ss2ocf or Stoustrup's recursion), when the two differ for this system.
fn other_procedure(key: &AnswerKey, part: &KeyPart) -> Option<Candidate> {
    if !matches!(
        part.spec.ask,
        Computation::CanonicalTransformation
            | Computation::CanonicalTransformationInverse
            | Computation::CanonicalA
            | Computation::CanonicalB
            | Computation::CanonicalC
    ) {
        return None;
    }
    let ours = part.claim.procedure.as_deref().unwrap_or("stoustrup");
    let (other, other_name, our_name) = match ours {
        "di-ruscio" => ("stoustrup", "Stoustrup's", "Di Ruscio's"),
        _ => ("di-ruscio", "Di Ruscio's", "Stoustrup's"),
    };
    let claim = ClaimSpec {
        procedure: Some(other.into()),
        ..part.claim.clone()
    };
    let value = key.recompute(&claim)?;
    (value != part.value).then(|| {
        (
            Mistake::OtherProcedure,
            value,
            format!("this is what {other_name} procedure gives; the exercise asks for {our_name}, whose transformation differs for this system"),
        )
    })
}

/// The design's time constant, evaluated with the exercise's parameters.
fn time_constant(key: &AnswerKey, text: &str) -> Option<Rational> {
    let e = crate::syntax::parse_expression(text).ok()?;
    evaluate_with::<Rational>(&e, &key.env).ok()
}

fn asked_family(key: &AnswerKey, part: &KeyPart) -> String {
    let c = &part.claim;
    let t =
        |text: &String| time_constant(key, text).map_or_else(|| text.clone(), |r| r.to_string());
    if let Some((family, x)) = c.family() {
        format!("{} with T = {}", family.indefinite(), t(x))
    } else if let Some(p) = &c.poles {
        format!("the poles {p}")
    } else {
        c.poly.clone().unwrap_or_default()
    }
}

/// The other families with the asked time constant (exact where possible).
fn other_families(key: &AnswerKey, part: &KeyPart) -> Vec<(String, Poly<Quadratic>)> {
    let c = &part.claim;
    let Ok(n) = Inputs {
        file: &key.example,
        claim: c,
        env: &key.env,
    }
    .numeric("A")
    .map(|a| a.rows()) else {
        return Vec::new();
    };
    let Some((asked, t)) = c.family() else {
        return Vec::new();
    };
    let Some(t) = time_constant(key, t) else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for family in Family::ALL.iter().copied().filter(|f| *f != asked) {
        if let Ok(Some(p)) = family.polynomial(&t, n).map(|d| d.exact) {
            out.push((format!("{} (T = {t})", family.title()), p));
        }
    }
    out
}

/// The observer polynomial the student's gain actually gives, and a diagnosis when it is another
/// recognisable polynomial. `None` when the answer is not a gain of the right shape.
pub fn placed_polynomial(
    key: &AnswerKey,
    part: &KeyPart,
    answer: &str,
) -> Option<(Poly<Quadratic>, String, Option<Diagnosis>)> {
    let discrete = part.spec.ask == Computation::DiscreteGain;
    if !matches!(
        part.spec.ask,
        Computation::Gain | Computation::DiscreteGain | Computation::DetectableGain
    ) {
        return None;
    }
    let inputs = Inputs {
        file: &key.example,
        claim: &part.claim,
        env: &key.env,
    };
    let lift = |m: Matrix<Rational>| m.map(|x| Quadratic::rational(x.clone()));
    let a = lift(inputs.numeric("A").ok()?);
    let c = lift(inputs.numeric("C").ok()?);
    let k = answer_matrix(key, answer)?;
    if k.rows() != a.rows() || k.cols() != c.rows() {
        return None;
    }
    let obs = ObserverGain {
        matrix: k,
        convention: convention(part),
    }
    .observer_matrix(&a, &c)
    .ok()?;
    let p = characteristic_polynomial(&obs, if discrete { "z" } else { "s" }).ok()?;
    let pf = p.map(|x| x.to_complex_f64().0);
    let zs = companion_roots(&pf);
    let rightmost = zs.iter().map(|z| z.re).fold(f64::NEG_INFINITY, f64::max);
    let largest = zs.iter().map(|z| z.norm()).fold(0.0, f64::max);
    let stability = if discrete {
        if largest < 1.0 - 1e-9 {
            "the observer is stable (every pole inside the unit circle)"
        } else if largest > 1.0 + 1e-9 {
            "the observer is unstable: a pole lies outside the unit circle, its error grows"
        } else {
            "the observer is on the stability boundary (a pole on the unit circle): its error does not decay"
        }
    } else if rightmost < -1e-9 {
        "the observer is stable"
    } else if rightmost > 1e-9 {
        "the observer is unstable: its error grows"
    } else {
        "the observer is on the stability boundary: its error does not decay"
    };
    let roots: Vec<String> = zs
        .iter()
        .map(|z| {
            if z.im.abs() < 1e-9 {
                format!("{:.4}", z.re)
            } else {
                format!(
                    "{:.4} {} {:.4}i",
                    z.re,
                    if z.im < 0.0 { "−" } else { "+" },
                    z.im.abs()
                )
            }
        })
        .collect();
    let text = format!(
        "your gain gives the observer polynomial {p} (poles {}); {stability}",
        roots.join(", ")
    );
    if discrete {
        // the continuous families below do not apply in the z-plane
        return Some((p, text, None));
    }
    let n = a.rows();
    let close = |q: &Poly<f64>| {
        (0..=n).all(|i| {
            let (x, y) = (pf.coeff(i), q.coeff(i));
            (x - y).abs() <= 2e-3 * y.abs().max(1.0)
        })
    };
    let mut diagnosis = identify_family(key, part, &pf, n, "your gain places");
    // mirrored poles: the desired polynomial at −s
    if diagnosis.is_none() {
        if let Value::Matrix(_) = &part.value {
            if let Some(Value::Polynomial(d)) = {
                let claim = ClaimSpec {
                    what: Computation::DesiredPolynomial,
                    ..part.claim.clone()
                };
                key.recompute(&claim)
            } {
                let df = d.map(|x| x.to_complex_f64().0);
                let mirrored = Poly::new(
                    (0..=n)
                        .map(|i| {
                            if (n - i) % 2 == 0 {
                                df.coeff(i)
                            } else {
                                -df.coeff(i)
                            }
                        })
                        .collect(),
                    "s",
                );
                if close(&mirrored) && !close(&df) {
                    diagnosis = Some(Diagnosis {
                        mistake: Mistake::WrongPolynomial,
                        message: "your gain places the poles mirrored into the right half-plane (s − p instead of s + p): the observer would be unstable".into(),
                    });
                }
            }
        }
    }
    Some((p, text, diagnosis))
}

/// Which family and time constant a polynomial is, if any (compared to 0.2 % in each
/// coefficient, so rounded answers are recognised).
fn identify_family(
    key: &AnswerKey,
    part: &KeyPart,
    pf: &Poly<f64>,
    n: usize,
    lead: &str,
) -> Option<Diagnosis> {
    let close = |q: &Poly<f64>| {
        (0..=n).all(|i| {
            let (x, y) = (pf.coeff(i), q.coeff(i));
            (x - y).abs() <= 2e-3 * y.abs().max(1.0)
        })
    };
    let c0 = pf.coeff(0).abs();
    if c0 <= 0.0 || pf.degree() != Some(n) {
        return None;
    }
    for family in Family::ALL.iter().copied() {
        let (name, make) = (family.described(), |t: &Rational, n| {
            family.polynomial(t, n)
        });
        let Ok(unit) = make(&Rational::from_integer(1.into()), n) else {
            continue;
        };
        let t = (unit.float.coeff(0).abs() / c0).powf(1.0 / n as f64);
        let Some(tq) = num_rational::BigRational::from_float(t) else {
            continue;
        };
        if let Ok(q) = make(&tq, n) {
            if close(&q.float) {
                return Some(Diagnosis {
                    mistake: Mistake::WrongPolynomial,
                    message: format!(
                        "{lead} {name} with time constant T ≈ {t:.4}; the exercise asks for {}",
                        asked_family(key, part)
                    ),
                });
            }
        }
    }
    None
}

/// A desired-polynomial answer that is another family or time constant.
fn polynomial_family(key: &AnswerKey, part: &KeyPart, answer: &str) -> Option<Diagnosis> {
    let Value::Polynomial(q) = &part.value else {
        return None;
    };
    if part.spec.ask != Computation::DesiredPolynomial {
        return None;
    }
    let e = crate::syntax::parse_expression(answer).ok()?;
    let rf =
        crate::syntax::rational_function_with::<Quadratic>(&e, q.var(), Some(&key.env)).ok()?;
    let p = rf.numerator().map(|x| x.to_complex_f64().0);
    let d = rf.denominator().map(|x| x.to_complex_f64().0);
    let scale = d.coeff(0);
    if d.degree() != Some(0) || scale == 0.0 {
        return None;
    }
    let p = p.map(|x| x / scale);
    identify_family(key, part, &p, q.degree()?, "this is")
}

/// A single wrong entry, when everything else matches.
fn single_slip(key: &AnswerKey, part: &KeyPart, answer: &str) -> Option<Diagnosis> {
    let Value::Matrix(m) = &part.value else {
        return None;
    };
    let rows = parse_matrix_expressions(answer).ok()?;
    if rows.len() != m.rows() || rows.iter().any(|r| r.len() != m.cols()) {
        return None;
    }
    let mut wrong = Vec::new();
    for (i, row) in rows.iter().enumerate() {
        for (j, _) in row.iter().enumerate() {
            // compare entry by entry with the same rounding rules
            let entry_text = answer_entry(answer, i, j)?;
            let cell = Value::Matrix(Matrix::from_fn(1, 1, |_, _| m.get(i, j).clone()));
            if !matches(key, &cell, &entry_text) {
                wrong.push((i, j, entry_text));
            }
        }
    }
    if let [(i, j, text)] = wrong.as_slice() {
        return Some(Diagnosis {
            mistake: Mistake::Slip,
            message: format!(
                "one slip: entry ({}, {}) is {text}, it should be {}; everything else is right",
                i + 1,
                j + 1,
                m.get(*i, *j)
            ),
        });
    }
    None
}

/// The text of entry (i, j) of a matrix answer, split on MATLAB rules.
fn answer_entry(answer: &str, i: usize, j: usize) -> Option<String> {
    let inner = answer.trim().trim_start_matches('[').trim_end_matches(']');
    let row = inner.split(';').nth(i)?;
    let parts: Vec<&str> = if row.contains(',') {
        row.split(',')
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .collect()
    } else {
        row.split_whitespace().collect()
    };
    parts.get(j).map(|s| (*s).to_string())
}

/// Names the mistake in a wrong answer, if it is one the workbench recognises, and says what the
/// answer does (for gains: the poles it places).
pub fn diagnose(key: &AnswerKey, part: &KeyPart, answer: &str) -> (Option<Diagnosis>, Vec<String>) {
    let mut notes = Vec::new();
    // the student's matrix, read once for every use below
    let parsed = answer_matrix(key, answer);
    // Every candidate mistake is the key's value or a small transformation of it; an answer
    // holding numbers of thousands of bits matches none of them, and comparing it with each
    // (dozens of exact evaluations) is what would take long.
    if let Some(a) = &parsed {
        // a matrix of a real system has real entries: an imaginary entry is no slip of a
        // real answer, and no named mistake gets credit for it
        let key_real = answer_matrix(key, &part.value.input())
            .is_some_and(|m| m.entries().iter().all(Quadratic::is_real));
        if let Some((k, _)) = a
            .entries()
            .iter()
            .enumerate()
            .find(|(_, x)| key_real && !x.is_real())
        {
            let (i, j) = (k / a.cols().max(1) + 1, k % a.cols().max(1) + 1);
            notes.push(format!(
                "entry ({i}, {j}) of your answer is not real; every entry of this answer is a real number"
            ));
            return (None, notes);
        }
        let largest = a
            .entries()
            .iter()
            .map(crate::syntax::FromExpr::size_bits)
            .max()
            .unwrap_or(0);
        if largest > MAX_DIAGNOSED_BITS {
            notes.push(format!(
                "your answer holds a number of {largest} bits; answers that large are not compared with the usual mistakes"
            ));
            return (None, notes);
        }
    }
    for (mistake, value, message) in candidates(key, part, parsed.as_ref()) {
        if matches(key, &value, answer) {
            // a named mistake never hides what the answer does: the poles a gain places
            if let Some((_, text, _)) = placed_polynomial(key, part, answer) {
                notes.push(text);
            }
            return (Some(Diagnosis { mistake, message }), notes);
        }
    }
    let mut found = None;
    if let Some((_, text, d)) = placed_polynomial(key, part, answer) {
        notes.push(text);
        found = d;
    }
    if found.is_none() {
        found = polynomial_family(key, part, answer);
    }
    if found.is_none() {
        found = single_slip(key, part, answer);
    }
    if found.is_none() {
        if let Value::Matrix(m) = &part.value {
            // the shape as written, also for an answer too large to be read as a matrix
            // (a 1×10 000 row is refused by the reader, but its shape is still what to say)
            let shape = parsed.as_ref().map(|a| (a.rows(), a.cols())).or_else(|| {
                crate::syntax::parse_matrix_expressions(answer)
                    .ok()
                    .map(|rows| (rows.len(), rows.first().map_or(0, Vec::len)))
            });
            if let Some((rows, cols)) = shape.filter(|s| *s != (m.rows(), m.cols())) {
                notes.push(format!(
                    "your answer is {rows}×{cols}, the answer is {}×{}",
                    m.rows(),
                    m.cols()
                ));
            }
        }
    }
    (found, notes)
}
