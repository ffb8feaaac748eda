//! Multivariate polynomials with rational coefficients over named symbols.
//!
//! They carry the symbolic side of the workbench: gains `k1…k6`, plant parameters `a1, a2, a3`,
//! the time constant `T`, the Laplace variable `s` or `λ`. Baranowski's characteristic polynomial
//! (9) with symbolic `g1, g2, g3`, his constraints (15) in `k1…k6`, and Di Ruscio's (74) in `a`,
//! `k1`, `k2` are all computed in this ring (by Berkowitz, which never divides).
//!
//! Terms are kept in the lexicographic order of the variable names, which is a term order, so
//! [`IntegralDomain::divide_exact`] (needed by Bareiss elimination) is ordinary multivariate
//! division that fails as soon as a leading term does not divide.

use super::{BigInt, IntegralDomain, Rational, Ring};
use num_traits::{One, Signed, Zero};
use std::cmp::Ordering;
use std::collections::BTreeMap;
use std::fmt;
use std::ops::{Add, Mul, Neg, Sub};

/// A power product `x1^e1 · x2^e2 ⋯`, variables sorted by name, exponents positive.
#[derive(Clone, PartialEq, Eq, Hash, Debug, Default)]
pub struct Monomial(Vec<(String, u32)>);

impl Monomial {
    /// The monomial `1`.
    pub fn one() -> Self {
        Monomial(Vec::new())
    }
    /// The monomial `name^exp` (`1` when `exp = 0`).
    pub fn var(name: &str, exp: u32) -> Self {
        if exp == 0 {
            Monomial::one()
        } else {
            Monomial(vec![(name.to_string(), exp)])
        }
    }
    /// The total degree.
    pub fn degree(&self) -> u32 {
        self.0.iter().map(|(_, e)| e).sum()
    }
    /// The exponent of `name`.
    pub fn exponent(&self, name: &str) -> u32 {
        self.0
            .iter()
            .find(|(v, _)| v == name)
            .map_or(0, |(_, e)| *e)
    }
    /// The (variable, exponent) pairs.
    pub fn factors(&self) -> &[(String, u32)] {
        &self.0
    }
    /// The product of two monomials.
    pub(crate) fn mul(&self, other: &Monomial) -> Monomial {
        let mut out: Vec<(String, u32)> = Vec::with_capacity(self.0.len() + other.0.len());
        let (mut i, mut j) = (0, 0);
        while i < self.0.len() || j < other.0.len() {
            match (self.0.get(i), other.0.get(j)) {
                (Some(a), Some(b)) if a.0 == b.0 => {
                    out.push((a.0.clone(), a.1 + b.1));
                    i += 1;
                    j += 1;
                }
                (Some(a), Some(b)) if a.0 < b.0 => {
                    out.push(a.clone());
                    i += 1;
                }
                (Some(_), Some(b)) | (None, Some(b)) => {
                    out.push(b.clone());
                    j += 1;
                }
                (Some(a), None) => {
                    out.push(a.clone());
                    i += 1;
                }
                (None, None) => break,
            }
        }
        Monomial(out)
    }
    /// `self / other` when `other` divides `self`.
    fn div(&self, other: &Monomial) -> Option<Monomial> {
        let mut out = Vec::new();
        for (v, e) in &self.0 {
            let f = other.exponent(v);
            if f > *e {
                return None;
            }
            if e - f > 0 {
                out.push((v.clone(), e - f));
            }
        }
        other
            .0
            .iter()
            .all(|(v, _)| self.exponent(v) > 0)
            .then_some(Monomial(out))
    }
    /// The monomial with `name` removed.
    fn without(&self, name: &str) -> Monomial {
        Monomial(self.0.iter().filter(|(v, _)| v != name).cloned().collect())
    }
}

impl Ord for Monomial {
    /// Lexicographic order: the first variable (by name) whose exponents differ decides.
    fn cmp(&self, other: &Self) -> Ordering {
        let (mut i, mut j) = (0, 0);
        loop {
            match (self.0.get(i), other.0.get(j)) {
                (None, None) => return Ordering::Equal,
                (Some(_), None) => return Ordering::Greater,
                (None, Some(_)) => return Ordering::Less,
                (Some(a), Some(b)) => match a.0.cmp(&b.0) {
                    Ordering::Less => return Ordering::Greater,
                    Ordering::Greater => return Ordering::Less,
                    Ordering::Equal => match a.1.cmp(&b.1) {
                        Ordering::Equal => {
                            i += 1;
                            j += 1;
                        }
                        o => return o,
                    },
                },
            }
        }
    }
}

impl PartialOrd for Monomial {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// A polynomial in named symbols with rational coefficients.
///
/// # Example
/// ```
/// use observer_workbench::algebra::{MultiPoly, Ring};
/// let k1 = MultiPoly::var("k1");
/// let a = MultiPoly::var("a");
/// let p = (k1.clone() + a.clone()) * (k1 - a);
/// assert_eq!(p.to_string(), "-a^2 + k1^2");
/// assert_eq!(p.to_input(), "-a^2 + k1^2");
/// ```
#[derive(Clone, PartialEq, Eq, Default)]
pub struct MultiPoly {
    terms: BTreeMap<Monomial, Rational>,
}

impl MultiPoly {
    /// The constant polynomial `c`.
    pub fn constant(c: Rational) -> Self {
        let mut terms = BTreeMap::new();
        if !c.is_zero() {
            terms.insert(Monomial::one(), c);
        }
        MultiPoly { terms }
    }
    /// The polynomial `name`.
    pub fn var(name: &str) -> Self {
        let mut terms = BTreeMap::new();
        terms.insert(Monomial::var(name, 1), Rational::one());
        MultiPoly { terms }
    }
    /// `c · m`.
    pub fn term(c: Rational, m: Monomial) -> Self {
        let mut terms = BTreeMap::new();
        if !c.is_zero() {
            terms.insert(m, c);
        }
        MultiPoly { terms }
    }
    /// The terms, in increasing lexicographic order.
    pub fn terms(&self) -> impl Iterator<Item = (&Monomial, &Rational)> {
        self.terms.iter()
    }
    /// `Some(c)` when the polynomial is the constant `c`.
    pub fn as_constant(&self) -> Option<Rational> {
        match self.terms.len() {
            0 => Some(Rational::zero()),
            1 => self.terms.get(&Monomial::one()).cloned(),
            _ => None,
        }
    }
    /// The names of the symbols that occur, sorted.
    pub fn variables(&self) -> Vec<String> {
        let mut v: Vec<String> = self
            .terms
            .keys()
            .flat_map(|m| m.0.iter().map(|(n, _)| n.clone()))
            .collect();
        v.sort();
        v.dedup();
        v
    }
    /// The total degree (0 for constants, including zero).
    pub fn total_degree(&self) -> u32 {
        self.terms.keys().map(Monomial::degree).max().unwrap_or(0)
    }
    /// The degree in one symbol.
    pub fn degree_in(&self, name: &str) -> u32 {
        self.terms
            .keys()
            .map(|m| m.exponent(name))
            .max()
            .unwrap_or(0)
    }
    /// The coefficients of `name^0, name^1, …` as polynomials in the other symbols.
    ///
    /// ```
    /// use observer_workbench::algebra::{MultiPoly, Ring};
    /// let s = MultiPoly::var("s");
    /// let k = MultiPoly::var("k");
    /// let p = s.clone() * s.clone() + k.clone() * s + k;
    /// let c = p.coefficients_in("s");
    /// assert_eq!(c.iter().map(|c| c.to_string()).collect::<Vec<_>>(), ["k", "k", "1"]);
    /// ```
    pub fn coefficients_in(&self, name: &str) -> Vec<MultiPoly> {
        let mut out = vec![MultiPoly::zero(); self.degree_in(name) as usize + 1];
        for (m, c) in &self.terms {
            let e = m.exponent(name) as usize;
            out[e].add_term(m.without(name), c.clone());
        }
        out
    }
    /// Replaces the symbol `name` by `value`.
    pub fn substitute(&self, name: &str, value: &MultiPoly) -> MultiPoly {
        let coeffs = self.coefficients_in(name);
        let mut acc = MultiPoly::zero();
        for c in coeffs.into_iter().rev() {
            acc = acc * value.clone() + c;
        }
        acc
    }
    /// The value for rational values of every symbol; `None` if a symbol is missing.
    pub fn evaluate(&self, values: &BTreeMap<String, Rational>) -> Option<Rational> {
        let mut total = Rational::zero();
        for (m, c) in &self.terms {
            let mut t = c.clone();
            for (v, e) in &m.0 {
                let x = values.get(v)?;
                t *= num_traits::pow(x.clone(), *e as usize);
            }
            total += t;
        }
        Some(total)
    }
    /// The exact value at a point of f64 coordinates for the symbols `variables`, in that
    /// order — each f64 is a rational m·2^e — or `None` when a symbol is not among them or a
    /// coordinate is not finite. The terms are summed as integers over one denominator (the
    /// coefficients' common denominator and a power of two) and reduced once, where
    /// [`MultiPoly::evaluate`] reduces a fraction after every product and sum: the same number.
    pub fn evaluate_at_floats(&self, variables: &[String], x: &[f64]) -> Option<Rational> {
        if variables.len() != x.len() {
            return None;
        }
        let dyadic: Vec<(BigInt, i64)> = x.iter().map(|&v| dyadic(v)).collect::<Option<_>>()?;
        let coefficients: Vec<Rational> = self.terms.values().cloned().collect();
        let (numerators, denominator) = super::gcd::integer_numerators(&coefficients);
        let mut scaled: Vec<(BigInt, i64)> = Vec::with_capacity(numerators.len());
        for (m, mut term) in self.terms.keys().zip(numerators) {
            let mut exponent = 0i64;
            for (v, e) in &m.0 {
                let (mantissa, power) = &dyadic[variables.iter().position(|y| y == v)?];
                term *= num_traits::pow(mantissa.clone(), *e as usize);
                exponent += power * i64::from(*e);
            }
            // a zero term (a coordinate 0) would only lower the common power of two
            if !term.is_zero() {
                scaled.push((term, exponent));
            }
        }
        let low = scaled.iter().map(|t| t.1).min().unwrap_or(0);
        let sum: BigInt = scaled
            .into_iter()
            .map(|(term, exponent)| term << ((exponent - low) as u64))
            .sum();
        Some(if low >= 0 {
            super::fraction(sum << (low as u64), denominator)
        } else {
            super::fraction(sum, denominator << (low.unsigned_abs()))
        })
    }
    /// The partial derivative with respect to `name`.
    pub fn derivative(&self, name: &str) -> MultiPoly {
        let mut out = MultiPoly::zero();
        for (m, c) in &self.terms {
            let e = m.exponent(name);
            if e == 0 {
                continue;
            }
            let rest = m.without(name).mul(&Monomial::var(name, e - 1));
            out.add_term(rest, c.clone() * Rational::from_i64(e as i64));
        }
        out
    }
    /// The polynomial prepared for evaluation at many f64 points whose coordinates are the
    /// symbols `variables`, in that order (symbols not among them count as 0).
    pub fn to_float(&self, variables: &[String]) -> FloatPoly {
        let mut float = FloatPoly {
            coeffs: Vec::with_capacity(self.terms.len()),
            starts: Vec::with_capacity(self.terms.len() + 1),
            factors: Vec::new(),
        };
        float.starts.push(0);
        for (m, c) in &self.terms {
            float.coeffs.push(crate::algebra::rational_to_f64(c));
            float.factors.extend(m.0.iter().map(|(v, e)| {
                let index = variables.iter().position(|x| x == v);
                (index.unwrap_or(usize::MAX), *e as i32)
            }));
            float.starts.push(float.factors.len());
        }
        float
    }
    /// How many terms it has.
    pub fn number_of_terms(&self) -> usize {
        self.terms.len()
    }
    /// The cost of one term in a product, in machine words: the largest coefficient's size
    /// (numerator and denominator), at least 1. A work meter counts products by it, so
    /// polynomials with 300-digit coefficients are not priced as small ones.
    pub fn coefficient_words(&self) -> u64 {
        self.terms
            .values()
            .map(|c| (c.numer().bits() + c.denom().bits()) / 64 + 1)
            .max()
            .unwrap_or(1)
    }
    /// The work of multiplying `self` by `other`, in word operations: terms × terms × words²
    /// (each coefficient product is normalised by a gcd, quadratic in the words).
    pub fn product_work(&self, other: &MultiPoly) -> u64 {
        let words = self
            .coefficient_words()
            .saturating_add(other.coefficient_words());
        (self.terms.len() as u64)
            .saturating_mul(other.terms.len() as u64)
            .saturating_mul(words.saturating_mul(words))
    }
    /// The coefficient of the leading term (the largest monomial in the lexicographic order).
    pub fn leading_coefficient(&self) -> Option<&Rational> {
        self.terms.values().next_back()
    }
    /// The coefficient of the monomial `m`.
    pub fn coefficient(&self, m: &Monomial) -> Rational {
        self.terms.get(m).cloned().unwrap_or_else(Rational::zero)
    }
    /// The sum of the terms `c·m`: equal monomials added, zero coefficients dropped — a
    /// polynomial written down term by term, without the products and sums that would build it.
    pub fn from_terms(terms: impl IntoIterator<Item = (Monomial, Rational)>) -> Self {
        let mut p = MultiPoly::default();
        for (m, c) in terms {
            p.add_term(m, c);
        }
        p
    }

    fn add_term(&mut self, m: Monomial, c: Rational) {
        if c.is_zero() {
            return;
        }
        let entry = self.terms.entry(m);
        match entry {
            std::collections::btree_map::Entry::Vacant(v) => {
                v.insert(c);
            }
            std::collections::btree_map::Entry::Occupied(mut o) => {
                *o.get_mut() += c;
                if o.get().is_zero() {
                    o.remove();
                }
            }
        }
    }

    fn leading(&self) -> Option<(&Monomial, &Rational)> {
        self.terms.iter().next_back()
    }

    /// Terms in display order: total degree descending, then lexicographic descending.
    fn display_terms(&self) -> Vec<(&Monomial, &Rational)> {
        let mut t: Vec<_> = self.terms.iter().collect();
        t.sort_by(|a, b| b.0.degree().cmp(&a.0.degree()).then(b.0.cmp(a.0)));
        t
    }

    fn render(&self, style: Style) -> String {
        if self.terms.is_empty() {
            return "0".into();
        }
        let mut out = String::new();
        for (i, (m, c)) in self.display_terms().into_iter().enumerate() {
            let neg = c.is_negative();
            if i == 0 {
                if neg {
                    out.push('-');
                }
            } else {
                out.push_str(match (neg, style) {
                    (false, _) => " + ",
                    (true, Style::Human) => " − ",
                    (true, _) => " - ",
                });
            }
            let abs = c.abs();
            let vars: Vec<String> = m.0.iter().map(|(v, e)| style.power(v, *e)).collect();
            let coeff = if m.0.is_empty() || !abs.is_one() {
                Some(match style {
                    Style::Latex => abs.to_latex(),
                    _ => abs.to_string(),
                })
            } else {
                None
            };
            let sep = match style {
                Style::Human | Style::Latex => " ",
                Style::Input => "*",
            };
            let mut parts: Vec<String> = coeff.into_iter().collect();
            parts.extend(vars);
            out.push_str(&parts.join(sep));
        }
        out
    }
}

#[derive(Clone, Copy, PartialEq)]
enum Style {
    Human,
    Input,
    Latex,
}

impl Style {
    fn power(self, v: &str, e: u32) -> String {
        let name = match self {
            Style::Latex => latex_symbol(v),
            _ => v.to_string(),
        };
        match (e, self) {
            (1, _) => name,
            (e, Style::Latex) => format!("{name}^{{{e}}}"),
            (e, _) => format!("{name}^{e}"),
        }
    }
}

/// LaTeX for a symbol name: `k1` → `k_{1}`, `lambda`/`λ` → `\lambda`, Greek letters typed as
/// words (`zeta` → `\zeta`, `omega` and `w` → `\omega`, so `w0` → `\omega_{0}`).
pub(crate) fn latex_symbol(name: &str) -> String {
    let greek = [
        ("lambda", "\\lambda"),
        ("λ", "\\lambda"),
        ("omega", "\\omega"),
        ("ω", "\\omega"),
        ("w", "\\omega"),
        ("alpha", "\\alpha"),
        ("beta", "\\beta"),
        ("gamma", "\\gamma"),
        ("delta", "\\delta"),
        ("epsilon", "\\varepsilon"),
        ("zeta", "\\zeta"),
        ("eta", "\\eta"),
        ("theta", "\\theta"),
        ("kappa", "\\kappa"),
        ("mu", "\\mu"),
        ("nu", "\\nu"),
        ("xi", "\\xi"),
        ("rho", "\\rho"),
        ("sigma", "\\sigma"),
        ("tau", "\\tau"),
        ("phi", "\\phi"),
        ("psi", "\\psi"),
        ("ζ", "\\zeta"),
        ("γ", "\\gamma"),
        ("τ", "\\tau"),
    ];
    let split = name
        .char_indices()
        .find(|(_, c)| c.is_ascii_digit())
        .map_or(name.len(), |(i, _)| i);
    let (stem, digits) = name.split_at(split);
    let stem = greek
        .iter()
        .find(|(g, _)| *g == stem)
        .map_or(stem.to_string(), |(_, l)| l.to_string());
    if digits.is_empty() {
        stem
    } else {
        format!("{stem}_{{{digits}}}")
    }
}

impl Add for MultiPoly {
    type Output = MultiPoly;
    fn add(mut self, rhs: Self) -> Self {
        for (m, c) in rhs.terms {
            self.add_term(m, c);
        }
        self
    }
}

impl Sub for MultiPoly {
    type Output = MultiPoly;
    fn sub(mut self, rhs: Self) -> Self {
        for (m, c) in rhs.terms {
            self.add_term(m, -c);
        }
        self
    }
}

impl Mul for MultiPoly {
    type Output = MultiPoly;
    /// Fraction-free: both factors are scaled to integer coefficients (by the lcm of their
    /// denominators), the products summed in integers, and each result coefficient reduced
    /// once — no gcd per product term.
    fn mul(self, rhs: Self) -> Self {
        fn integer(p: &MultiPoly) -> (Vec<(&Monomial, BigInt)>, BigInt) {
            let coefficients: Vec<Rational> = p.terms.values().cloned().collect();
            let (ints, d) = crate::algebra::gcd::integer_numerators(&coefficients);
            (p.terms.keys().zip(ints).collect(), d)
        }
        let (left, d1) = integer(&self);
        let (right, d2) = integer(&rhs);
        let mut sums: BTreeMap<Monomial, BigInt> = BTreeMap::new();
        for (m1, n1) in &left {
            for (m2, n2) in &right {
                *sums.entry(m1.mul(m2)).or_default() += n1 * n2;
            }
        }
        let d = d1 * d2;
        let terms = sums
            .into_iter()
            .filter(|(_, n)| !num_traits::Zero::is_zero(n))
            .map(|(m, n)| (m, crate::algebra::gcd::fraction(n, d.clone())))
            .collect();
        MultiPoly { terms }
    }
}

impl Neg for MultiPoly {
    type Output = MultiPoly;
    fn neg(mut self) -> Self {
        for c in self.terms.values_mut() {
            *c = -c.clone();
        }
        self
    }
}

impl fmt::Display for MultiPoly {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.render(Style::Human))
    }
}

impl fmt::Debug for MultiPoly {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.render(Style::Input))
    }
}

impl Zero for MultiPoly {
    fn zero() -> Self {
        MultiPoly::default()
    }
    fn is_zero(&self) -> bool {
        self.terms.is_empty()
    }
}

impl One for MultiPoly {
    fn one() -> Self {
        MultiPoly::constant(Rational::one())
    }
}

impl Ring for MultiPoly {
    fn from_i64(n: i64) -> Self {
        MultiPoly::constant(Rational::from_i64(n))
    }
    fn pivot_weight(&self) -> f64 {
        if self.terms.is_empty() {
            0.0
        } else {
            1.0 / self.terms.len() as f64
        }
    }
    fn to_latex(&self) -> String {
        self.render(Style::Latex)
    }
    fn to_input(&self) -> String {
        self.render(Style::Input)
    }
}

/// An exact division stopped because it would cost more than its budget.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DivisionTooCostly {
    /// The budget, in term operations.
    pub budget: u64,
}

impl MultiPoly {
    /// `self / divisor` when it is exact (`Ok(None)` when it is not), giving up with
    /// [`DivisionTooCostly`] once the long division has cost `budget` term operations (each
    /// step subtracts a multiple of the divisor from the remainder). A divisor whose degree in
    /// some variable exceeds the dividend's cannot divide it, and is refused at once.
    ///
    /// ```
    /// use observer_workbench::algebra::MultiPoly;
    /// let (s, u) = (MultiPoly::var("s"), MultiPoly::var("u"));
    /// let p = (s.clone() + u.clone()) * (s.clone() - u.clone());
    /// assert_eq!(p.divide_exact_within(&(s.clone() - u.clone()), 1_000), Ok(Some(s.clone() + u.clone())));
    /// assert_eq!(s.divide_exact_within(&u, 1_000), Ok(None));
    /// ```
    ///
    /// # Errors
    /// [`DivisionTooCostly`] when the budget runs out.
    pub fn divide_exact_within(
        &self,
        divisor: &Self,
        budget: u64,
    ) -> Result<Option<Self>, DivisionTooCostly> {
        let Some((lm, lc)) = divisor.leading() else {
            return Ok(None);
        };
        if !self.is_zero()
            && divisor
                .variables()
                .iter()
                .any(|v| divisor.degree_in(v) > self.degree_in(v))
        {
            return Ok(None);
        }
        let (lm, lc) = (lm.clone(), lc.clone());
        let step = divisor.terms.len() as u64;
        let bits = |c: &Rational| c.numer().bits() + c.denom().bits();
        let divisor_bits = divisor.terms.values().map(bits).max().unwrap_or(0);
        let mut spent = 0u64;
        let mut rest = self.clone();
        let mut quotient = MultiPoly::zero();
        while let Some((m, c)) = rest.leading() {
            let Some(qm) = m.div(&lm) else {
                return Ok(None);
            };
            let qc = c.clone() / lc.clone();
            // each term operation reduces a product of the quotient's coefficient with one of the
            // divisor's: a binary gcd, about words² / 16 times a small one (found by fuzzing:
            // dividing s^688 + … by (s + 2e-5)^2 (8s + 4)^2 grew 11 000-bit coefficients, 7.9 s
            // with debug assertions within a budget that counted terms only)
            let words = (bits(&qc) + divisor_bits) / 64 + 1;
            let weight = 1 + words.saturating_mul(words) / 16;
            spent = spent.saturating_add((step + rest.terms.len() as u64).saturating_mul(weight));
            if spent > budget {
                return Err(DivisionTooCostly { budget });
            }
            let t = MultiPoly::term(qc, qm);
            rest = rest - t.clone() * divisor.clone();
            quotient = quotient + t;
        }
        Ok(Some(quotient))
    }
}

impl IntegralDomain for MultiPoly {
    fn divide_exact(&self, divisor: &Self) -> Option<Self> {
        self.divide_exact_within(divisor, u64::MAX).ok().flatten()
    }
}

/// A finite f64 as the exact rational m·2^e it is, `(m, e)`: num-rational's exact reading of
/// it ([`Rational::from_f64`](num_traits::FromPrimitive::from_f64)), whose denominator is a
/// power of two.
fn dyadic(v: f64) -> Option<(BigInt, i64)> {
    let r = <Rational as num_traits::FromPrimitive>::from_f64(v)?;
    let power = r.denom().trailing_zeros().unwrap_or(0);
    Some((r.numer().clone(), -(power as i64)))
}

/// A [`MultiPoly`] compiled for evaluation at f64 points ([`MultiPoly::to_float`]): each
/// coefficient converted to f64 once and each symbol replaced by its coordinate's index, so that
/// a Newton iteration over a few thousand derivatives (`optimal`'s Hessians), which evaluates
/// them at every step, neither converts a coefficient nor looks a symbol up by name there. Each
/// term is its coefficient times its factors' powers, left to right, and the terms are summed
/// in the polynomial's order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FloatPoly {
    /// Each term's coefficient, in the polynomial's term order.
    coeffs: Vec<f64>,
    /// Where each term's factors start in `factors`; one entry more than there are terms.
    starts: Vec<usize>,
    /// Every term's (coordinate, exponent) pairs, term after term; a symbol that is not a
    /// coordinate has the index `usize::MAX`, and its value is 0.
    factors: Vec<(usize, i32)>,
}

impl FloatPoly {
    /// The value at `x`: Σ c Π x_v^e (a coordinate beyond `x` counts as 0).
    pub fn evaluate(&self, x: &[f64]) -> f64 {
        self.terms()
            .map(|(c, factors)| {
                factors.iter().fold(c, |acc, &(v, e)| {
                    acc * x.get(v).copied().unwrap_or(0.0).powi(e)
                })
            })
            .sum()
    }
    /// The size of its terms at `x`, Σ |c| Π |x_v|^e: what the rounding error of
    /// [`FloatPoly::evaluate`] is a small multiple of.
    pub fn evaluate_abs(&self, x: &[f64]) -> f64 {
        self.terms()
            .map(|(c, factors)| {
                factors.iter().fold(c.abs(), |acc, &(v, e)| {
                    acc * x.get(v).copied().unwrap_or(0.0).abs().powi(e)
                })
            })
            .sum()
    }
    /// Each term's coefficient with its factors.
    fn terms(&self) -> impl Iterator<Item = (f64, &[(usize, i32)])> {
        self.coeffs
            .iter()
            .zip(self.starts.windows(2))
            .map(|(&c, w)| (c, &self.factors[w[0]..w[1]]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(n: &str) -> MultiPoly {
        MultiPoly::var(n)
    }

    #[test]
    fn exact_division_recovers_the_factor() {
        let p = v("a") * v("b") + v("k1") - MultiPoly::from_i64(3);
        let q = v("a") - v("b") * v("b");
        let prod = p.clone() * q.clone();
        assert_eq!(prod.divide_exact(&q), Some(p.clone()));
        assert_eq!(prod.divide_exact(&p), Some(q));
        assert_eq!(p.divide_exact(&v("a")), None);
    }

    #[test]
    fn printing_in_three_styles() {
        let p = MultiPoly::from_i64(2) * v("k1") * v("k2") * v("k2")
            - MultiPoly::constant(Rational::new(3.into(), 2.into()));
        assert_eq!(p.to_string(), "2 k1 k2^2 − 3/2");
        assert_eq!(p.to_input(), "2*k1*k2^2 - 3/2");
        assert_eq!(p.to_latex(), "2 k_{1} k_{2}^{2} - \\frac{3}{2}");
    }

    #[test]
    fn substitution_and_evaluation() {
        let p = v("s") * v("s") + v("a") * v("s");
        let q = p.substitute("a", &MultiPoly::from_i64(9));
        let mut vals = BTreeMap::new();
        vals.insert("s".to_string(), Rational::from_i64(-4));
        assert_eq!(q.evaluate(&vals), Some(Rational::from_i64(-20)));
        assert_eq!(p.evaluate(&vals), None);
    }
}

#[cfg(test)]
mod float_tests {
    use super::*;
    use proptest::prelude::*;

    const NAMES: [&str; 4] = ["a", "k1", "k2", "s"];

    /// A polynomial from (coefficient numerator, denominator, exponents of the four names).
    fn poly(terms: &[(i64, i64, [u32; 4])]) -> MultiPoly {
        let mut p = MultiPoly::zero();
        for (num, den, exps) in terms {
            let m = NAMES
                .iter()
                .zip(exps)
                .fold(Monomial::one(), |m, (name, &e)| {
                    m.mul(&Monomial::var(name, e))
                });
            p = p + MultiPoly::term(Rational::new((*num).into(), (*den).into()), m);
        }
        p
    }

    /// Up to twelve terms: a coefficient n/d and the exponents of the four names.
    fn terms() -> impl Strategy<Value = Vec<(i64, i64, [u32; 4])>> {
        prop::collection::vec(
            (-50i64..50, 1i64..20, prop::array::uniform4(0u32..4)),
            0..12,
        )
    }

    /// Σ f(c) Π f(x_v)^e with every coefficient converted and every symbol looked up by name
    /// at the point (missing ones 0), term after term: the value (f the identity) or the size
    /// of the terms (f the absolute value).
    fn looked_up(p: &MultiPoly, values: &BTreeMap<String, f64>, f: fn(f64) -> f64) -> f64 {
        p.terms()
            .map(|(m, c)| {
                m.factors()
                    .iter()
                    .fold(f(crate::algebra::rational_to_f64(c)), |acc, (v, e)| {
                        acc * f(values.get(v).copied().unwrap_or(0.0)).powi(*e as i32)
                    })
            })
            .sum()
    }

    #[test]
    fn exact_value_needs_every_symbol_and_finite_coordinates() {
        let p = poly(&[(3, 2, [1, 0, 2, 0])]);
        let names: Vec<String> = ["a", "k2"].iter().map(|s| s.to_string()).collect();
        let exact: BTreeMap<String, Rational> = names
            .iter()
            .cloned()
            .zip([Rational::new(1.into(), 2.into()), Rational::from_i64(-3)])
            .collect();
        assert_eq!(
            p.evaluate_at_floats(&names, &[0.5, -3.0]),
            p.evaluate(&exact)
        );
        assert_eq!(p.evaluate_at_floats(&names[..1], &[0.5]), None);
        assert_eq!(p.evaluate_at_floats(&names, &[f64::NAN, 1.0]), None);
        assert_eq!(p.evaluate_at_floats(&names, &[1.0]), None);
    }

    proptest! {
        /// The exact value at f64 coordinates, summed over one denominator, is the value
        /// evaluate gives with every f64 read as its rational, including zeros, negative
        /// numbers, subnormals and large exponents.
        #[test]
        fn exact_value_at_floats_is_the_rational_evaluation(
            terms in terms(),
            mantissas in prop::array::uniform4(-1.0f64..1.0),
            exponents in prop::array::uniform4(-1080i32..60),
        ) {
            let p = poly(&terms);
            let x: Vec<f64> = mantissas.iter().zip(&exponents).map(|(m, e)| m * 2f64.powi(*e)).collect();
            let names: Vec<String> = NAMES.iter().map(|s| s.to_string()).collect();
            let exact: BTreeMap<String, Rational> = names
                .iter()
                .cloned()
                .zip(x.iter().map(|v| <Rational as num_traits::FromPrimitive>::from_f64(*v).unwrap()))
                .collect();
            prop_assert_eq!(p.evaluate_at_floats(&names, &x), p.evaluate(&exact));
        }

        /// The compiled form gives the bits of the evaluation that converts each coefficient
        /// and looks each symbol up by name at the point (what `optimal` did before), for the
        /// size of the terms too, with symbols left out of the coordinates counting as 0.
        #[test]
        fn compiled_evaluation_is_the_same_bits(
            terms in terms(),
            x in prop::array::uniform4(-3.0f64..3.0),
            kept in 1usize..=4,
        ) {
            let p = poly(&terms);
            let coordinates: Vec<String> = NAMES[..kept].iter().map(|s| s.to_string()).collect();
            let by_name: BTreeMap<String, f64> =
                coordinates.iter().cloned().zip(x.iter().copied()).collect();
            let compiled = p.to_float(&coordinates);
            prop_assert_eq!(compiled.evaluate(&x[..kept]).to_bits(), looked_up(&p, &by_name, f64::from).to_bits());
            prop_assert_eq!(compiled.evaluate_abs(&x[..kept]).to_bits(), looked_up(&p, &by_name, f64::abs).to_bits());
        }
    }
}
