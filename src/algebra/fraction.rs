//! Rational functions of named symbols, not reduced by a gcd, with at most one square root
//! carried as the symbol `√d` (reduced by `√d² = d`): what the worked examples' proofs compute
//! in (`worked::proof` proves a document's formula in T, a, a₁ over them). Equality is tested
//! by cross-multiplication, which needs no gcd; one radicand per claim keeps the normal form
//! unique, so equality is exact.

use super::{MultiPoly, One, Quadratic, Rational, Ring, Zero};
use std::fmt;
use std::ops::{Add, Mul, Neg, Sub};

/// A rational function `num / den` of the claim's symbols, with rational coefficients and at
/// most one square root carried as the symbol `√d`. Not reduced by a gcd: equality is tested
/// by cross-multiplication, which needs none.
#[derive(Clone, Debug)]
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

impl Fraction {
    /// A polynomial as a fraction over 1.
    pub(crate) fn of(num: MultiPoly) -> Self {
        Fraction {
            num,
            den: MultiPoly::one(),
        }
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

    /// The symbol `name`.
    pub fn symbol(name: &str) -> Self {
        Fraction::of(MultiPoly::var(name))
    }

    /// `self / other`, or `None` when `other` is the zero function.
    pub fn checked_div(&self, other: &Self) -> Option<Self> {
        (!other.num.is_zero()).then(|| Fraction {
            num: reduce(self.num.clone() * other.den.clone()),
            den: reduce(self.den.clone() * other.num.clone()),
        })
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
        Fraction {
            num: reduce(num * q(dd)),
            den: reduce(den * q(dn)),
        }
    }

    /// The common monomial factor of numerator and denominator divided out, for showing.
    fn cancelled(&self) -> Fraction {
        let mut common: Option<Vec<(String, u32)>> = None;
        for (m, _) in self.num.terms().chain(self.den.terms()) {
            let here: Vec<(String, u32)> = m.factors().to_vec();
            common = Some(match common {
                None => here,
                Some(c) => c
                    .into_iter()
                    .filter_map(|(v, e)| {
                        let f = m.exponent(&v);
                        (f > 0).then(|| (v, e.min(f)))
                    })
                    .collect(),
            });
        }
        let common = common.unwrap_or_default();
        if common.is_empty() {
            return self.clone();
        }
        let divide = |p: &MultiPoly| -> MultiPoly {
            p.terms()
                .map(|(m, c)| {
                    let mut t = MultiPoly::constant(c.clone());
                    for (v, e) in m.factors() {
                        let left = e - common.iter().find(|(w, _)| w == v).map_or(0, |(_, k)| *k);
                        for _ in 0..left {
                            t = t * MultiPoly::var(v);
                        }
                    }
                    t
                })
                .fold(MultiPoly::zero(), |a, b| a + b)
        };
        Fraction {
            num: divide(&self.num),
            den: divide(&self.den),
        }
    }

    /// The coefficients of `var` (lowest power first), when `var` does not occur in the
    /// denominator.
    pub fn coefficients_in(&self, var: &str) -> Option<Vec<Fraction>> {
        (self.den.degree_in(var) == 0).then(|| {
            self.num
                .coefficients_in(var)
                .into_iter()
                .map(|c| Fraction {
                    num: c,
                    den: self.den.clone(),
                })
                .collect()
        })
    }
}

impl PartialEq for Fraction {
    fn eq(&self, other: &Self) -> bool {
        reduce(self.num.clone() * other.den.clone() - other.num.clone() * self.den.clone())
            .is_zero()
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

impl fmt::Display for Fraction {
    /// `num/den` with the common monomial factor cancelled; a constant denominator divided in;
    /// a single-term denominator shown under each term of the numerator.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let c = self.cancelled();
        if let Some(d) = c.den.as_constant() {
            return write!(f, "{}", show(&(c.num * MultiPoly::constant(d.recip()))));
        }
        let mut den_terms = c.den.terms();
        if let (Some((m, k)), None) = (den_terms.next(), den_terms.next()) {
            let terms: Vec<String> = c.num.terms().map(|(n, a)| over(a / k, n, m)).collect();
            return write!(f, "{}", terms.join(" + ").replace("+ -", "- "));
        }
        write!(f, "({}) / ({})", show(&c.num), show(&c.den))
    }
}

impl Add for Fraction {
    type Output = Fraction;
    fn add(self, o: Fraction) -> Fraction {
        if self.den == o.den {
            return Fraction {
                num: self.num + o.num,
                den: self.den,
            };
        }
        Fraction {
            num: reduce(self.num * o.den.clone() + o.num * self.den.clone()),
            den: reduce(self.den * o.den),
        }
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
        Fraction {
            num: reduce(self.num * o.num),
            den: reduce(self.den * o.den),
        }
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
        Fraction::of(MultiPoly::zero())
    }
    fn is_zero(&self) -> bool {
        self.num.is_zero()
    }
}

impl One for Fraction {
    fn one() -> Self {
        Fraction::of(MultiPoly::one())
    }
}

impl Ring for Fraction {
    fn from_i64(n: i64) -> Self {
        Fraction::of(MultiPoly::from_i64(n))
    }
    fn to_latex(&self) -> String {
        match self.den.as_constant() {
            Some(c) if c.is_one() => self.num.to_latex(),
            _ => format!(
                "\\frac{{{}}}{{{}}}",
                self.num.to_latex(),
                self.den.to_latex()
            ),
        }
    }
    fn to_input(&self) -> String {
        self.to_string()
    }
}
