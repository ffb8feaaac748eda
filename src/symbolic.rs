//! Designing with parameters: what a course writes on the board (`A = [0 1; −k/m −c/m]`, poles
//! at `−ω`) computed as formulas, with the values for which the formula breaks.
//!
//! The design kernels are generic over [`Field`](crate::algebra::Field); here they run over
//! [`Fraction`], the rational functions of the parameters in lowest terms. A generic answer
//! holds for every value of the parameters except where one of its denominators vanishes (the
//! plant's own, `det O_n`, the gain's): [`Exceptions`] collects those denominators, splits them
//! into factors ([`factors`]: monomials, contents and square-free parts; a factor of total
//! degree 1 is irreducible, a longer one is not claimed to be) and says "valid for m ≠ 0".
//!
//! Symbolic work can grow fast, so it is bounded: at most [`MAX_PARAMETERS`] parameters, order
//! [`MAX_ORDER`], and [`WORK_BUDGET`] coefficient products on the [`budget`] meter, which the
//! commands open around every symbolic computation.

use crate::algebra::{
    budget, normalised, poly_gcd, Fraction, IntegralDomain, MultiPoly, One, Ring, Zero,
};
use crate::poly::Poly;
use std::collections::BTreeMap;

/// Names that are not parameters: the transform variables and the imaginary unit.
pub const RESERVED: &[&str] = &["s", "z", "λ", "lambda", "i", "j"];
/// The most parameters one command reads.
pub const MAX_PARAMETERS: usize = 12;
/// The largest order of a symbolic plant.
pub const MAX_ORDER: usize = 8;
/// The most coefficient products a symbolic command may spend: about 0.17 s of work in a release
/// build (1 000 000 until session 11, 0.7 s, which a fuzz campaign's instrumented build took
/// past its 1 s timeout). The largest design the tests and the book run, a chain of four masses
/// with eight parameters, spends 36 000.
pub const WORK_BUDGET: u64 = 250_000;

/// Why a symbolic request is refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SymbolicError {
    /// A reserved name used as a parameter.
    #[error("'{name}' is reserved ({why}) and cannot be a parameter; rename it")]
    Reserved {
        /// The name.
        name: String,
        /// What it stands for.
        why: &'static str,
    },
    /// Too many parameters.
    #[error("{found} parameters ({names}); symbolic design takes at most {limit} (give values to some with --at NAME=VALUE)")]
    TooManyParameters {
        /// How many were found.
        found: usize,
        /// Their names.
        names: String,
        /// The limit.
        limit: usize,
    },
    /// A plant too large for symbolic work.
    #[error("a symbolic plant of order {order} is beyond the limit of {limit} (give the parameters values with --at NAME=VALUE)")]
    TooLarge {
        /// The order.
        order: usize,
        /// The limit.
        limit: usize,
    },
    /// The work budget ran out.
    #[error("the symbolic computation needs more than {budget} units of work (coefficient products weighted by their size; the limit of symbolic work, reached in under a second) and was stopped; give some parameters values with --at NAME=VALUE")]
    TooMuchWork {
        /// The budget.
        budget: u64,
    },
}

/// What each reserved name stands for.
fn reserved_meaning(name: &str) -> Option<&'static str> {
    match name {
        "s" | "λ" | "lambda" => Some("the Laplace variable of the polynomials"),
        "z" => Some("the z-transform variable"),
        "i" | "j" => Some("the imaginary unit"),
        _ => None,
    }
}

/// The parameters (symbols) that `values` mention, sorted.
pub fn parameters<'a>(values: impl IntoIterator<Item = &'a Fraction>) -> Vec<String> {
    let mut names: Vec<String> = values.into_iter().flat_map(Fraction::symbols).collect();
    names.sort();
    names.dedup();
    names
}

/// Checks the parameters a request mentions: no reserved name, not too many.
///
/// # Errors
/// [`SymbolicError::Reserved`] or [`SymbolicError::TooManyParameters`].
pub fn check_parameters(names: &[String]) -> Result<(), SymbolicError> {
    if let Some(name) = names.iter().find(|n| reserved_meaning(n).is_some()) {
        return Err(SymbolicError::Reserved {
            name: name.clone(),
            why: reserved_meaning(name).unwrap_or_default(),
        });
    }
    if names.len() > MAX_PARAMETERS {
        return Err(SymbolicError::TooManyParameters {
            found: names.len(),
            names: names.join(", "),
            limit: MAX_PARAMETERS,
        });
    }
    Ok(())
}

/// Runs a symbolic computation under the work budget: its result, or
/// [`SymbolicError::TooMuchWork`] when the meter ran out (whatever the computation returned).
/// Inside a computation already under a budget, `work` shares it (so nested steps cannot each
/// spend a whole budget).
///
/// # Errors
/// [`SymbolicError::TooMuchWork`].
pub fn within_budget<T>(work: impl FnOnce() -> T) -> Result<T, SymbolicError> {
    if budget::is_open() {
        let out = work();
        if budget::exhausted() {
            return Err(SymbolicError::TooMuchWork {
                budget: WORK_BUDGET,
            });
        }
        return Ok(out);
    }
    within_budget_left(&std::cell::Cell::new(WORK_BUDGET), work)
}

/// Runs `work` under what is `left` of a budget shared by several steps (a command's), and
/// keeps what it did not spend in `left`: the steps together spend at most [`WORK_BUDGET`].
///
/// # Errors
/// [`SymbolicError::TooMuchWork`] when the budget ran out.
pub fn within_budget_left<T>(
    left: &std::cell::Cell<u64>,
    work: impl FnOnce() -> T,
) -> Result<T, SymbolicError> {
    let meter = budget::Meter::open(left.get());
    let out = work();
    left.set(budget::left().unwrap_or(0));
    if meter.exhausted() {
        return Err(SymbolicError::TooMuchWork {
            budget: WORK_BUDGET,
        });
    }
    Ok(out)
}

/// `p` split into factors with multiplicities: the single variables of its monomial content,
/// then, variable by variable, the content and the square-free parts (Yun's algorithm) of the
/// primitive part. Constant factors are dropped; each factor is normalised (integer
/// coefficients, positive leading coefficient); the order is by total degree, then text.
pub fn factors(p: &MultiPoly) -> Vec<(MultiPoly, u32)> {
    let mut out: Vec<(MultiPoly, u32)> = Vec::new();
    if !p.is_zero() {
        split(normalised(p), 1, &mut out);
    }
    let mut merged: BTreeMap<(u32, String), (MultiPoly, u32)> = BTreeMap::new();
    for (f, e) in out {
        let key = (f.total_degree(), f.to_input());
        merged.entry(key).or_insert((f, 0)).1 += e;
    }
    merged.into_values().collect()
}

fn power(x: &str, e: u32) -> MultiPoly {
    MultiPoly::term(
        crate::algebra::Rational::from_i64(1),
        crate::algebra::Monomial::var(x, e),
    )
}

fn split(p: MultiPoly, times: u32, out: &mut Vec<(MultiPoly, u32)>) {
    if p.as_constant().is_some() || budget::exhausted() {
        return;
    }
    let mut p = p;
    for v in p.variables() {
        let e = p.terms().map(|(m, _)| m.exponent(&v)).min().unwrap_or(0);
        if e > 0 {
            out.push((MultiPoly::var(&v), e * times));
            p = p.divide_exact(&power(&v, e)).unwrap_or(p);
        }
    }
    if p.as_constant().is_some() {
        return;
    }
    let Some(x) = p.variables().into_iter().next() else {
        return;
    };
    let coefficients = p.coefficients_in(&x);
    let content = coefficients
        .iter()
        .fold(MultiPoly::zero(), |g, c| poly_gcd(&g, c));
    if content.as_constant().is_none() {
        split(content.clone(), times, out);
        p = p.divide_exact(&content).unwrap_or(p);
    }
    square_free(p, &x, times, out);
}

/// Yun's square-free decomposition of `p` (primitive in `x`, depending on `x`).
fn square_free(p: MultiPoly, x: &str, times: u32, out: &mut Vec<(MultiPoly, u32)>) {
    let derivative = p.derivative(x);
    let mut c = poly_gcd(&p, &derivative);
    let mut w = p.divide_exact(&c).unwrap_or_else(|| p.clone());
    let mut i = 1;
    while w.as_constant().is_none() && !budget::exhausted() {
        let y = poly_gcd(&w, &c);
        let z = w.divide_exact(&y).unwrap_or_else(|| w.clone());
        if z.as_constant().is_none() {
            out.push((normalised(&z), i * times));
        }
        i += 1;
        c = c.divide_exact(&y).unwrap_or(c);
        w = y;
    }
}

/// `x` with the parameters that have values in `values` substituted.
pub fn substitute_values(x: &Fraction, values: &crate::syntax::Environment) -> Fraction {
    let mut out = x.clone();
    for name in x.symbols() {
        if let Some(v) = values.get(&name) {
            out = out.substitute(&name, &Fraction::constant(v.clone()));
        }
    }
    out
}

/// `∏ (s − pᵢ)` for poles that may hold parameters (`−ω`, `−ζω`).
pub fn poles_polynomial(poles: &[Fraction]) -> Poly<Fraction> {
    let mut coeffs = vec![Fraction::one()];
    for root in poles {
        let mut next = vec![Fraction::zero(); coeffs.len() + 1];
        for (k, c) in coeffs.iter().enumerate() {
            next[k + 1] = next[k + 1].clone() + c.clone();
            next[k] = next[k].clone() - c.clone() * root.clone();
        }
        coeffs = next;
    }
    Poly::new(coeffs, "s")
}

/// The polynomial of `family` of degree `n` with a time constant `t` that may be a parameter:
/// `P_T(s) = T⁻ⁿ P₁(T s)`, the coefficient of `sᵏ` being `cₖ T^(k − n)`.
///
/// # Errors
/// The family has no exact form at this order, or `t` is zero (named in words).
pub fn family_polynomial(
    family: crate::observer::Family,
    t: &Fraction,
    n: usize,
) -> Result<Poly<Fraction>, String> {
    let normalised = family
        .polynomial(&crate::algebra::Rational::one(), n)
        .map_err(|e| e.to_string())?;
    let Some(p1) = normalised.exact else {
        return Err(format!(
            "the {family} polynomial has no exact form at order {n}"
        ));
    };
    let inverse = Fraction::one()
        .checked_div(t)
        .ok_or_else(|| "the time constant is zero".to_string())?;
    let mut coeffs = Vec::with_capacity(n + 1);
    for k in 0..=n {
        let mut c = Fraction::quadratic(&p1.coeff(k));
        for _ in k..n {
            c = c * inverse.clone();
        }
        coeffs.push(c);
    }
    Ok(Poly::new(coeffs, "s"))
}

/// A desired polynomial as requested, in text: a pole list, a polynomial in `s`, or a family
/// with a time constant — any of them with parameters. One reader for the commands' flags and
/// the exercises' designs.
#[derive(Debug, Clone, Copy)]
pub enum DesiredRequest<'a> {
    /// `-w, -w`.
    Poles(&'a str),
    /// `s^2 + 2*zeta*w*s + w^2`.
    Poly(&'a str),
    /// A family and its time constant `T`.
    Family(crate::observer::Family, &'a str),
}

/// Whether a text is plain numbers — digits, signs, fraction bars, decimal points, brackets and
/// separators: it names no parameter and is read at the cost of its length, so
/// [`DesiredRequest::mentions_parameters`] need not read it (at n = 20, reading twenty poles
/// as rational functions was a twentieth of a dead-beat design).
fn plainly_numeric(text: &str) -> bool {
    text.chars()
        .all(|c| c.is_ascii_digit() || " \t\r\n.,;/+-−()".contains(c))
}

/// Reads one formula, values of `env` substituted.
fn formula(text: &str, env: &crate::syntax::Environment) -> Result<Fraction, String> {
    let e = crate::syntax::parse_expression(text).map_err(|e| e.show_in(text))?;
    crate::syntax::evaluate_with::<Fraction>(&e, env).map_err(|e| e.show_in(text))
}

impl DesiredRequest<'_> {
    /// The poles of a pole list, values of `env` substituted.
    ///
    /// # Errors
    /// The text shown where it cannot be read.
    pub fn poles(text: &str, env: &crate::syntax::Environment) -> Result<Vec<Fraction>, String> {
        crate::syntax::parse_list_with::<Fraction>(text, env).map_err(|e| e.show_in(text))
    }

    /// The values the request is read into (the poles, the polynomial's coefficients, or the
    /// time constant), values of `env` substituted.
    ///
    /// # Errors
    /// The text shown where it cannot be read.
    pub fn values(&self, env: &crate::syntax::Environment) -> Result<Vec<Fraction>, String> {
        match *self {
            DesiredRequest::Poles(text) => Self::poles(text, env),
            DesiredRequest::Poly(text) => formula(text, env)?
                .coefficients_in("s")
                .ok_or_else(|| "s appears in a denominator; give a polynomial in s".to_string()),
            DesiredRequest::Family(_, t) => Ok(vec![formula(t, env)?]),
        }
    }

    /// The parameters it mentions (`s` of a polynomial is its variable, not a parameter).
    pub fn parameters(&self, env: &crate::syntax::Environment) -> Vec<String> {
        within_budget(|| self.values(env).map(|v| parameters(&v)).unwrap_or_default())
            .unwrap_or_default()
    }

    /// Whether the request mentions parameters, read under the symbolic work budget: a text too
    /// costly to read counts as mentioning them, so that the symbolic path reads it again and
    /// refuses it naming the limit (found by fuzzing: a `--poly` of degree-25 fractions was read
    /// without a budget to decide which path to take, and ran into the 10 s time budget).
    pub fn mentions_parameters(&self, env: &crate::syntax::Environment) -> bool {
        let (DesiredRequest::Poles(text)
        | DesiredRequest::Poly(text)
        | DesiredRequest::Family(_, text)) = *self;
        if plainly_numeric(text) {
            return false;
        }
        match within_budget(|| self.values(env).map(|v| parameters(&v))) {
            Ok(Ok(names)) => !names.is_empty(),
            Ok(Err(_)) => false,
            Err(_) => true,
        }
    }

    /// The polynomial of degree `n` in `s` over the rational functions of the parameters.
    ///
    /// # Errors
    /// A text that cannot be read, the wrong number of poles, a polynomial that is not monic
    /// of degree `n`, a family without an exact form (in words; the caller names the flag).
    pub fn polynomial(
        &self,
        env: &crate::syntax::Environment,
        n: usize,
    ) -> Result<Poly<Fraction>, String> {
        // under the symbolic work budget (found by fuzzing: a Butterworth polynomial whose time
        // constant was a sum of ten parameters was built before any budget was open, 1.1 s)
        within_budget(|| self.polynomial_within(env, n)).map_err(|e| e.to_string())?
    }

    fn polynomial_within(
        &self,
        env: &crate::syntax::Environment,
        n: usize,
    ) -> Result<Poly<Fraction>, String> {
        let values = self.values(env)?;
        match *self {
            DesiredRequest::Poles(_) if values.len() != n => Err(format!(
                "{} poles given, the system has order {n}",
                values.len()
            )),
            DesiredRequest::Poles(_) => Ok(poles_polynomial(&values)),
            DesiredRequest::Poly(_) => {
                let poly = Poly::new(values, "s");
                if poly.degree() != Some(n) || !poly.is_monic() {
                    return Err(format!(
                        "the desired polynomial must be monic of degree {n} (the order of A), it is {poly}"
                    ));
                }
                Ok(poly)
            }
            DesiredRequest::Family(family, _) => family_polynomial(family, &values[0], n),
        }
    }
}

/// A desired polynomial written in another variable (`z^2 - a*z + 1/4` in discrete time),
/// monic of degree `n`, as a polynomial in `s` over the rational functions of the parameters
/// (the variable the designs speak of); the parameters it mentions beside the variable.
///
/// # Errors
/// A text that cannot be read, the variable in a denominator, a polynomial that is not monic
/// of degree `n` (in words; the caller names the flag).
pub fn polynomial_in(text: &str, var: &str, n: usize) -> Result<Poly<Fraction>, String> {
    let env = crate::syntax::Environment::new();
    let coeffs =
        within_budget(|| coefficients_in(text, var, &env)).map_err(|e| e.to_string())??;
    let poly = Poly::new(coeffs, "s");
    if poly.degree() != Some(n) || !poly.is_monic() {
        return Err(format!(
            "the desired polynomial must be monic of degree {n} (the order of A), it is {}",
            poly.clone().with_var(var)
        ));
    }
    Ok(poly)
}

/// The coefficients (ascending) of a polynomial in `var`, values of `env` substituted.
///
/// # Errors
/// A text that cannot be read, the variable in a denominator.
pub fn coefficients_in(
    text: &str,
    var: &str,
    env: &crate::syntax::Environment,
) -> Result<Vec<Fraction>, String> {
    formula(text, env)?
        .coefficients_in(var)
        .ok_or_else(|| format!("{var} appears in a denominator; give a polynomial in {var}"))
}

/// The parameters a polynomial in `var` mentions (none when it cannot be read: the reader
/// that designs with it says why).
pub fn polynomial_parameters(text: &str, var: &str) -> Vec<String> {
    let env = crate::syntax::Environment::new();
    within_budget(|| {
        coefficients_in(text, var, &env)
            .map(|c| parameters(&c))
            .unwrap_or_default()
    })
    .unwrap_or_default()
}

/// A polynomial in `s` as one rational function of `s` and the parameters.
pub fn as_fraction(p: &Poly<Fraction>) -> Fraction {
    let s = Fraction::symbol(p.var());
    p.coeffs()
        .iter()
        .rev()
        .fold(Fraction::zero(), |acc, c| acc * s.clone() + c.clone())
}

/// Solves `factor = 0` for a parameter of degree 1 in it (one with a constant coefficient
/// first): `(name, value)`.
pub fn solve_for(factor: &MultiPoly) -> Option<(String, Fraction)> {
    let mut candidates: Vec<(bool, String)> = factor
        .variables()
        .into_iter()
        .filter(|v| factor.degree_in(v) == 1)
        .map(|v| (factor.coefficients_in(&v)[1].as_constant().is_none(), v))
        .collect();
    candidates.sort();
    let (_, name) = candidates.into_iter().next()?;
    let parts = factor.coefficients_in(&name);
    let value = Fraction::of(-parts[0].clone()).checked_div(&Fraction::of(parts[1].clone()))?;
    Some((name, value))
}

/// A factor whose vanishing breaks a formula, and what breaks.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Exception {
    /// The factor, in input syntax.
    pub factor: String,
    /// The factor in LaTeX.
    #[serde(skip)]
    pub latex: String,
    /// Why it matters ("a denominator of A", "det O_n", "a denominator of the gain").
    pub reason: String,
    /// Whether the factor is known to be irreducible (total degree 1).
    pub irreducible: bool,
}

/// The values of the parameters for which a generic result does not hold: the factors of the
/// denominators it divided by, each with its reason (the first reason found is kept).
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize)]
#[serde(transparent)]
pub struct Exceptions(pub Vec<Exception>);

impl Exceptions {
    /// Records the factors of `p` with `reason`.
    pub fn add(&mut self, p: &MultiPoly, reason: &str) {
        for (f, _) in factors(p) {
            let text = f.to_input();
            if self.0.iter().any(|e| e.factor == text) {
                continue;
            }
            self.0.push(Exception {
                factor: text,
                latex: f.to_latex(),
                reason: reason.to_string(),
                irreducible: f.total_degree() == 1,
            });
        }
    }
    /// Adds the exceptions of `other` that are not here yet.
    pub fn merge(&mut self, other: Exceptions) {
        for e in other.0 {
            if !self.0.iter().any(|x| x.factor == e.factor) {
                self.0.push(e);
            }
        }
    }
    /// Records the denominators of `values` with `reason`.
    pub fn add_denominators<'a>(
        &mut self,
        values: impl IntoIterator<Item = &'a Fraction>,
        reason: &str,
    ) {
        for v in values {
            self.add(v.denominator(), reason);
        }
    }
    /// Whether nothing can break.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
    /// "m ≠ 0, k·m − c² ≠ 0" (or "every value of the parameters").
    pub fn text(&self) -> String {
        if self.0.is_empty() {
            return "every value of the parameters".into();
        }
        self.0
            .iter()
            .map(|e| format!("{} ≠ 0", e.factor.replace('*', " ").replace(" - ", " − ")))
            .collect::<Vec<_>>()
            .join(", ")
    }
    /// The same in LaTeX.
    pub fn latex(&self) -> String {
        if self.0.is_empty() {
            return "\\text{every value of the parameters}".into();
        }
        self.0
            .iter()
            .map(|e| format!("{} \\neq 0", e.latex))
            .collect::<Vec<_>>()
            .join(",\\quad ")
    }
}

impl crate::derivation::Show for Exceptions {
    fn text(&self) -> String {
        Exceptions::text(self)
    }
    fn latex(&self) -> String {
        Exceptions::latex(self)
    }
    fn input(&self) -> String {
        Exceptions::text(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn poly(text: &str) -> MultiPoly {
        crate::syntax::parse_scalar::<MultiPoly>(text).unwrap()
    }

    #[test]
    fn factors_split_monomials_contents_and_squares() {
        let f = factors(&poly("-4*m^3*k*(c^2 - 4*k*m)^2*(w + 1)"));
        let shown: Vec<(String, u32)> = f.iter().map(|(p, e)| (p.to_input(), *e)).collect();
        assert_eq!(
            shown,
            [
                ("k".to_string(), 1),
                ("m".to_string(), 3),
                ("w + 1".to_string(), 1),
                ("c^2 - 4*k*m".to_string(), 2)
            ]
        );
        assert!(factors(&poly("7")).is_empty());
    }

    #[test]
    fn exceptions_name_each_factor_once() {
        let mut e = Exceptions::default();
        e.add(&poly("m^2"), "a denominator of A");
        e.add(&poly("2*m*k"), "det O_n");
        assert_eq!(e.text(), "m ≠ 0, k ≠ 0");
        assert_eq!(e.0[1].reason, "det O_n");
    }

    #[test]
    fn reserved_names_and_limits() {
        assert!(check_parameters(&["s".into()]).is_err());
        let many: Vec<String> = (0..=MAX_PARAMETERS).map(|i| format!("p{i}")).collect();
        assert!(matches!(
            check_parameters(&many),
            Err(SymbolicError::TooManyParameters { .. })
        ));
        assert!(check_parameters(&["k".into(), "m".into()]).is_ok());
    }
}
