//! Rational functions of named symbols (the plant's parameters `k`, `m`, `ω`, a time constant
//! `T`, the proofs' `a`, `a₁`), with at most one square root carried as the symbol `√d`
//! (reduced by `√d² = d`): the field the symbolic commands and the worked examples' proofs
//! compute in.
//!
//! Every value is kept in **lowest terms**: the denominator is free of `√d` (rationalised by
//! its conjugate), numerator and denominator have no common factor (a multivariate gcd,
//! [`super::poly_gcd`]), their coefficients are integers without common factor and the
//! denominator's leading coefficient is positive. The form is unique, so equality is equality
//! of the parts and the printed form is stable. One radicand per value keeps it unique (the
//! commands and the proofs read one quadratic field at a time).

use super::{
    budget, poly_gcd, Field, IntegralDomain, MultiPoly, One, Quadratic, Rational, Ring, Zero,
};
use std::fmt;
use std::ops::{Add, Mul, Neg, Sub};

/// A rational function `num / den` of named symbols over Q (or Q(√d)), in lowest terms.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Fraction {
    pub(crate) num: MultiPoly,
    pub(crate) den: MultiPoly,
}

/// The symbol standing for `√d`.
fn radical(d: i64) -> String {
    format!("√{d}")
}

/// The radicand of a radical symbol.
fn radicand(name: &str) -> Option<i64> {
    name.strip_prefix('√')?.parse().ok()
}

/// `p` with every `√d^e` replaced by `d^(e div 2) √d^(e mod 2)`.
fn reduce(p: MultiPoly) -> MultiPoly {
    let mut p = p;
    for name in p.variables() {
        let Some(d) = radicand(&name) else { continue };
        if p.degree_in(&name) < 2 {
            continue;
        }
        let d = MultiPoly::constant(Rational::from_integer(d.into()));
        let root = MultiPoly::var(&name);
        let mut even = MultiPoly::zero();
        let mut odd = MultiPoly::zero();
        let mut power = MultiPoly::one();
        for (k, c) in p.coefficients_in(&name).into_iter().enumerate() {
            if k % 2 == 0 {
                even = even + c * power.clone();
            } else {
                odd = odd + c * power.clone();
                power = power * d.clone();
            }
        }
        p = even + odd * root;
    }
    p
}

/// `p·(p̄)` and `p̄` for the conjugate `p̄` of `p` under `√d ↦ −√d` (`p` with `√d` of degree
/// at most 1): the product is free of `√d`.
fn rationalising(p: &MultiPoly) -> Option<MultiPoly> {
    let name = p.variables().into_iter().find(|v| radicand(v).is_some())?;
    let parts = p.coefficients_in(&name);
    let mut conjugate = MultiPoly::zero();
    for (k, c) in parts.into_iter().enumerate() {
        let term = c * MultiPoly::term(Rational::one(), super::Monomial::var(&name, k as u32));
        conjugate = if k % 2 == 0 {
            conjugate + term
        } else {
            conjugate - term
        };
    }
    Some(conjugate)
}

impl Fraction {
    /// A polynomial as a rational function (over 1).
    pub fn of(num: MultiPoly) -> Self {
        Fraction::new(num, MultiPoly::one())
    }

    /// `num / den` in lowest terms (`den` nonzero).
    pub(crate) fn new(num: MultiPoly, den: MultiPoly) -> Self {
        if budget::exhausted() {
            // the result will not be shown (see `budget`): stop doing work
            return Fraction::one();
        }
        let (mut num, mut den) = (reduce(num), reduce(den));
        if num.is_zero() {
            return Fraction {
                num,
                den: MultiPoly::one(),
            };
        }
        while let Some(conjugate) = rationalising(&den) {
            budget::charge(num.product_work(&conjugate) + den.product_work(&conjugate));
            if budget::exhausted() {
                return Fraction::one();
            }
            num = reduce(num * conjugate.clone());
            den = reduce(den * conjugate);
        }
        if den.as_constant().is_none() {
            let g = poly_gcd(&num, &den);
            if g.as_constant().is_none() {
                budget::charge(num.product_work(&g) + den.product_work(&g));
                if let (Some(n), Some(d)) = (num.divide_exact(&g), den.divide_exact(&g)) {
                    num = n;
                    den = d;
                }
            }
        }
        // integers without common factor across both parts, the denominator's leading
        // coefficient positive
        let both: Vec<&Rational> = num.terms().chain(den.terms()).map(|(_, c)| c).collect();
        let f = super::multigcd::scale_to_primitive(&both, den.leading_coefficient());
        if !f.is_one() {
            let f = MultiPoly::constant(f);
            num = num * f.clone();
            den = den * f;
        }
        Fraction { num, den }
    }

    /// The numerator (lowest terms, integer coefficients).
    pub fn numerator(&self) -> &MultiPoly {
        &self.num
    }

    /// The denominator (lowest terms, integer coefficients, positive leading coefficient).
    pub fn denominator(&self) -> &MultiPoly {
        &self.den
    }

    /// `a + b√d`.
    pub fn quadratic(q: &Quadratic) -> Self {
        let a = MultiPoly::constant(q.rational_part().clone());
        if q.radical_part().is_zero() {
            return Fraction::of(a);
        }
        let b = MultiPoly::constant(q.radical_part().clone());
        Fraction::of(a + b * MultiPoly::var(&radical(q.radicand())))
    }

    /// The rational number `c`.
    pub fn constant(c: Rational) -> Self {
        Fraction::of(MultiPoly::constant(c))
    }

    /// The symbol `name`.
    pub fn symbol(name: &str) -> Self {
        Fraction::of(MultiPoly::var(name))
    }

    /// `self / other`, or `None` when `other` is the zero function.
    pub fn checked_div(&self, other: &Self) -> Option<Self> {
        if other.num.is_zero() {
            return None;
        }
        // charged before the products are formed, like every other operation (a fuzz finding:
        // divisions in an elimination ran on, uncharged, seconds after the meter ran out)
        budget::charge(self.num.product_work(&other.den) + self.den.product_work(&other.num));
        if budget::exhausted() {
            return Some(Fraction::one());
        }
        Some(Fraction::new(
            self.num.clone() * other.den.clone(),
            self.den.clone() * other.num.clone(),
        ))
    }

    /// The radicands of the square roots it holds.
    pub(crate) fn radicands(&self) -> Vec<i64> {
        let mut r: Vec<i64> = self
            .num
            .variables()
            .iter()
            .chain(self.den.variables().iter())
            .filter_map(|v| radicand(v))
            .collect();
        r.sort_unstable();
        r.dedup();
        r
    }

    /// Whether it holds a square root `√d` (a symbol reduced by `√d² = d`, which a
    /// multivariate gcd would take for a free symbol).
    pub(crate) fn has_radical(&self) -> bool {
        let radical = |p: &MultiPoly| p.variables().iter().any(|v| radicand(v).is_some());
        radical(&self.num) || radical(&self.den)
    }

    /// The symbols it depends on (square roots excluded).
    pub fn symbols(&self) -> Vec<String> {
        let mut v: Vec<String> = self
            .num
            .variables()
            .into_iter()
            .chain(self.den.variables())
            .filter(|v| radicand(v).is_none())
            .collect();
        v.sort();
        v.dedup();
        v
    }

    /// `self` with the symbol `name` replaced by `value`.
    pub fn substitute(&self, name: &str, value: &Fraction) -> Fraction {
        // N(p/q) = Σ n_j p^j q^(d-j) / q^d for N of degree d in `name`
        let homogenised = |poly: &MultiPoly| -> (MultiPoly, usize) {
            let parts = poly.coefficients_in(name);
            let d = parts.len().saturating_sub(1);
            let mut out = MultiPoly::zero();
            for (j, c) in parts.into_iter().enumerate() {
                let mut t = c;
                for _ in 0..j {
                    t = reduce(t * value.num.clone());
                }
                for _ in j..d {
                    t = reduce(t * value.den.clone());
                }
                out = out + t;
            }
            (out, d)
        };
        let (num, dn) = homogenised(&self.num);
        let (den, dd) = homogenised(&self.den);
        let q = |k: usize| (0..k).fold(MultiPoly::one(), |acc, _| reduce(acc * value.den.clone()));
        // (num / q^dn) / (den / q^dd)
        Fraction::new(num * q(dd), den * q(dn))
    }

    /// The coefficients of `var` (lowest power first), when `var` does not occur in the
    /// denominator.
    pub fn coefficients_in(&self, var: &str) -> Option<Vec<Fraction>> {
        (self.den.degree_in(var) == 0).then(|| {
            self.num
                .coefficients_in(var)
                .into_iter()
                .map(|c| Fraction::new(c, self.den.clone()))
                .collect()
        })
    }
}

/// A polynomial with its square-root symbols written as `sqrt(d)`.
fn show(p: &MultiPoly) -> String {
    let mut text = p.to_string();
    for v in p.variables() {
        if let Some(d) = radicand(&v) {
            text = text.replace(&v, &format!("sqrt({d})"));
        }
    }
    text
}

/// A polynomial with its square-root symbols written as `sqrt(d)`, in input syntax.
fn show_input(p: &MultiPoly) -> String {
    let mut text = p.to_input();
    for v in p.variables() {
        if let Some(d) = radicand(&v) {
            text = text.replace(&v, &format!("sqrt({d})"));
        }
    }
    text
}

/// `num/den` from the parts' texts: parentheses around a numerator or denominator of several
/// terms, a constant denominator divided in.
fn quotient(num: String, den: String, several: (bool, bool)) -> String {
    let num = if several.0 { format!("({num})") } else { num };
    let den = if several.1 { format!("({den})") } else { den };
    format!("{num}/{den}")
}

impl Fraction {
    /// `(num, den)` shown by `show`, with a constant denominator divided into the numerator.
    fn parts(&self, show: fn(&MultiPoly) -> String) -> String {
        if let Some(d) = self.den.as_constant() {
            return show(&(self.num.clone() * MultiPoly::constant(d.recip())));
        }
        // a denominator needs parentheses unless it is one power of one symbol
        let several = |p: &MultiPoly| {
            p.number_of_terms() > 1 || p.terms().any(|(m, c)| m.factors().len() > 1 || !c.is_one())
        };
        quotient(
            show(&self.num),
            show(&self.den),
            (self.num.number_of_terms() > 1, several(&self.den)),
        )
    }

    /// The value when it is a rational number.
    pub fn as_rational(&self) -> Option<Rational> {
        let d = self.den.as_constant()?;
        Some(self.num.as_constant()? / d)
    }

    /// The value when it is a number of a quadratic field (`a + b√d`).
    pub fn as_quadratic(&self) -> Option<Quadratic> {
        let d = self.den.as_constant()?;
        let names = self.num.variables();
        match names.as_slice() {
            [] => Some(Quadratic::rational(self.num.as_constant()? / d)),
            [r] => {
                let radicand = radicand(r)?;
                let parts = self.num.coefficients_in(r);
                let a = parts.first()?.as_constant()? / d.clone();
                let b = parts.get(1)?.as_constant()? / d;
                Quadratic::new(a, b, radicand)
            }
            _ => None,
        }
    }
}

/// The term `c·n/m` of monomials, cancelled: `2/T`, `a1`, `-1/(a T^2)`.
fn over(c: Rational, n: &crate::algebra::Monomial, m: &crate::algebra::Monomial) -> String {
    let mut up = MultiPoly::constant(c);
    let mut down = MultiPoly::one();
    let mut names: Vec<&String> = n
        .factors()
        .iter()
        .chain(m.factors())
        .map(|(v, _)| v)
        .collect();
    names.sort();
    names.dedup();
    for v in names {
        let (e, f) = (n.exponent(v), m.exponent(v));
        for _ in f..e {
            up = up * MultiPoly::var(v);
        }
        for _ in e..f {
            down = down * MultiPoly::var(v);
        }
    }
    let up = show(&up);
    if down.as_constant().is_some() {
        return up;
    }
    let down = show(&down);
    let down = if down.contains(' ') {
        format!("({down})")
    } else {
        down
    };
    match up.strip_prefix('-') {
        Some(rest) if !rest.contains([' ', '+']) => format!("-{rest}/{down}"),
        _ if up.contains(' ') => format!("({up})/{down}"),
        _ => format!("{up}/{down}"),
    }
}

impl Fraction {
    /// The value written term by term when the denominator is a single term, each term of the
    /// numerator over it and cancelled (`a1 + sqrt(2)/T`, how documents print a formula in T);
    /// otherwise as [`Display`](fmt::Display).
    pub fn termwise(&self) -> String {
        let mut den_terms = self.den.terms();
        match (den_terms.next(), den_terms.next()) {
            (Some((m, k)), None) if self.den.as_constant().is_none() => {
                let terms: Vec<String> = self.num.terms().map(|(n, a)| over(a / k, n, m)).collect();
                terms.join(" + ").replace("+ -", "- ")
            }
            _ => self.to_string(),
        }
    }
}

impl fmt::Display for Fraction {
    /// `num/den` in lowest terms, `(2 m w − c)/m`; a constant denominator divided in.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.parts(show))
    }
}

impl Add for Fraction {
    type Output = Fraction;
    fn add(self, o: Fraction) -> Fraction {
        if budget::exhausted() {
            return Fraction::one();
        }
        if self.num.is_zero() {
            return o;
        }
        if o.num.is_zero() {
            return self;
        }
        if self.den == o.den {
            return Fraction::new(self.num + o.num, self.den);
        }
        budget::charge(self.num.product_work(&o.den) + o.num.product_work(&self.den));
        if budget::exhausted() {
            return Fraction::one();
        }
        // over the lcm of the denominators, not their product
        let g = poly_gcd(&self.den, &o.den);
        let (Some(left), Some(right)) = (o.den.divide_exact(&g), self.den.divide_exact(&g)) else {
            return Fraction::new(
                self.num * o.den.clone() + o.num * self.den.clone(),
                self.den * o.den,
            );
        };
        Fraction::new(self.num * left.clone() + o.num * right, self.den * left)
    }
}

impl Sub for Fraction {
    type Output = Fraction;
    fn sub(self, o: Fraction) -> Fraction {
        self + (-o)
    }
}

impl Mul for Fraction {
    type Output = Fraction;
    fn mul(self, o: Fraction) -> Fraction {
        if budget::exhausted() {
            return Fraction::one();
        }
        if self.num.is_zero() || o.num.is_zero() {
            return Fraction::zero();
        }
        budget::charge(self.num.product_work(&o.num) + self.den.product_work(&o.den));
        if budget::exhausted() {
            return Fraction::one();
        }
        Fraction::new(self.num * o.num, self.den * o.den)
    }
}

impl Neg for Fraction {
    type Output = Fraction;
    fn neg(self) -> Fraction {
        Fraction {
            num: -self.num,
            den: self.den,
        }
    }
}

impl Zero for Fraction {
    fn zero() -> Self {
        Fraction {
            num: MultiPoly::zero(),
            den: MultiPoly::one(),
        }
    }
    fn is_zero(&self) -> bool {
        self.num.is_zero()
    }
}

impl One for Fraction {
    fn one() -> Self {
        Fraction {
            num: MultiPoly::one(),
            den: MultiPoly::one(),
        }
    }
}

impl IntegralDomain for Fraction {
    fn divide_exact(&self, divisor: &Self) -> Option<Self> {
        self.checked_div(divisor)
    }
}

impl Field for Fraction {
    /// A field of fractions of polynomials: elimination runs in the field itself, every entry
    /// in lowest terms.
    type Integers = Fraction;
    fn common_denominator(_: &[Self]) -> Fraction {
        Fraction::one()
    }
    fn scale_to_integer(&self, d: &Fraction) -> Fraction {
        self.clone() * d.clone()
    }
    fn from_integer_ratio(n: Fraction, d: Fraction) -> Option<Self> {
        n.checked_div(&d)
    }
    fn inverse(&self) -> Option<Self> {
        Fraction::one().checked_div(self)
    }
}

impl Ring for Fraction {
    fn from_i64(n: i64) -> Self {
        Fraction::of(MultiPoly::from_i64(n))
    }
    /// Short entries make good pivots: they keep the eliminated entries short.
    fn pivot_weight(&self) -> f64 {
        if self.num.is_zero() {
            0.0
        } else {
            1.0 / (self.num.number_of_terms() + self.den.number_of_terms()) as f64
        }
    }
    fn to_latex(&self) -> String {
        let latex = |p: &MultiPoly| {
            let mut text = p.to_latex();
            for v in p.variables() {
                if let Some(d) = radicand(&v) {
                    text = text.replace(&v, &format!("\\sqrt{{{d}}}"));
                }
            }
            text
        };
        match self.den.as_constant() {
            Some(c) if c.is_one() => latex(&self.num),
            _ => format!("\\frac{{{}}}{{{}}}", latex(&self.num), latex(&self.den)),
        }
    }
    fn to_input(&self) -> String {
        self.parts(show_input)
    }
}
