//! Exact factoring over the rationals: square-free parts, then their rational roots.
//!
//! Enough for what observer design needs to say: `(s + 4)^3` for a repeated observer pole,
//! `(s + 1)(s^2 + √2…)` is left as the rational factor times the part without rational roots.
//! Rational roots come from the rational-root theorem (`p | a0`, `q | an`) when both numbers can
//! be factored by trial division below [`RootSearch::TRIAL_LIMIT`]; beyond that the search says it
//! was not exhaustive instead of pretending.

use super::Poly;
use crate::algebra::{Field, Quadratic, Rational, Ring};
use num_bigint::BigInt;
use num_traits::{One, Signed, ToPrimitive, Zero};
use std::fmt;

/// The rational roots found, and whether the search was exhaustive.
#[derive(Debug, Clone, PartialEq)]
pub struct RootSearch {
    /// Distinct rational roots, ascending.
    pub roots: Vec<Rational>,
    /// `false` when a coefficient was too large to enumerate its divisors.
    pub exhaustive: bool,
}

impl RootSearch {
    /// Largest number trial division is run up to when listing divisors.
    pub const TRIAL_LIMIT: u64 = 1 << 40;
    /// Largest number of candidates tried.
    pub const CANDIDATE_LIMIT: usize = 20_000;
}

/// `qⁿ f(p/q)` for integer coefficients `f` (ascending): zero exactly when `p/q` is a root,
/// in integers (Horner on the homogenised polynomial, no fraction reduced).
fn homogeneous_value(f: &[BigInt], p: &BigInt, q: &BigInt) -> BigInt {
    let mut value = BigInt::zero();
    let mut q_power = BigInt::from(1);
    for c in f.iter().rev() {
        value = value * p + c * &q_power;
        q_power *= q;
    }
    value
}

/// The distinct rational roots of a polynomial with rational coefficients.
///
/// ```
/// use observer_workbench::algebra::{Rational, Ring};
/// use observer_workbench::poly::{rational_roots, Poly};
/// // 3s^2 + 5s − 2 = (3s − 1)(s + 2)
/// let p = Poly::from_descending(&[3, 5, -2].map(Rational::from_i64), "s");
/// let found = rational_roots(&p);
/// assert_eq!(found.roots, [Rational::from_i64(-2), Rational::new(1.into(), 3.into())]);
/// assert!(found.exhaustive);
/// ```
pub fn rational_roots(p: &Poly<Rational>) -> RootSearch {
    let mut roots = Vec::new();
    let Some(deg) = p.degree() else {
        return RootSearch {
            roots,
            exhaustive: true,
        };
    };
    if deg == 0 {
        return RootSearch {
            roots,
            exhaustive: true,
        };
    }
    // Integer coefficients, zero roots stripped.
    let den = Rational::common_denominator(p.coeffs());
    let mut ints: Vec<BigInt> = p
        .coeffs()
        .iter()
        .map(|c| c.scale_to_integer(&den))
        .collect();
    if ints[0].is_zero() {
        roots.push(Rational::zero());
        while ints.first().is_some_and(|c| c.is_zero()) {
            ints.remove(0);
        }
    }
    let a0 = ints[0].abs();
    let an = ints[ints.len() - 1].abs();
    let mut exhaustive = true;
    if ints.len() > 1 {
        let (Some(ps), Some(qs)) = (divisors(&a0), divisors(&an)) else {
            return RootSearch {
                roots,
                exhaustive: false,
            };
        };
        if ps.len() * qs.len() > RootSearch::CANDIDATE_LIMIT {
            exhaustive = false;
        }
        // f(1) and f(−1) rule most candidates out: p/q a root ⇒ (q − p) | f(1), (q + p) | f(−1)
        let at_one: BigInt = ints.iter().sum();
        let at_minus_one: BigInt = ints
            .iter()
            .enumerate()
            .map(|(i, c)| if i % 2 == 0 { c.clone() } else { -c })
            .sum();
        let divides = |d: &BigInt, v: &BigInt| {
            if d.is_zero() {
                v.is_zero()
            } else {
                (v % d).is_zero()
            }
        };
        'outer: for q in &qs {
            for pnum in &ps {
                if roots.len() >= deg {
                    break 'outer;
                }
                for sign in [1i64, -1] {
                    let p = pnum * sign;
                    if !divides(&(q - &p), &at_one) || !divides(&(q + &p), &at_minus_one) {
                        continue;
                    }
                    let cand = Rational::new(p.clone(), q.clone());
                    if !roots.contains(&cand) && homogeneous_value(&ints, &p, q).is_zero() {
                        roots.push(cand);
                    }
                }
            }
            if !exhaustive {
                break;
            }
        }
    }
    roots.sort();
    RootSearch { roots, exhaustive }
}

/// The positive divisors of `n` (`n > 0`), or `None` when `n` is too large to factor quickly.
fn divisors(n: &BigInt) -> Option<Vec<BigInt>> {
    let primes = crate::algebra::factor_small(n.to_u64()?, RootSearch::TRIAL_LIMIT)?;
    let mut divs = vec![BigInt::one()];
    for (p, e) in primes {
        let mut next = Vec::with_capacity(divs.len() * (e as usize + 1));
        for d in &divs {
            let mut m = d.clone();
            for _ in 0..=e {
                next.push(m.clone());
                m *= p;
            }
        }
        divs = next;
    }
    divs.sort();
    Some(divs)
}

/// A polynomial as `constant · ∏ factor^multiplicity`: monic linear factors for the rational
/// roots, and the remaining monic factors that have no rational root.
#[derive(Debug, Clone, PartialEq)]
pub struct Factored {
    /// The leading coefficient.
    pub constant: Rational,
    /// Monic factors with multiplicities; linear factors first, by root.
    pub factors: Vec<(Poly<Rational>, u32)>,
    /// Whether every rational root was searched for.
    pub exhaustive: bool,
}

impl Factored {
    /// Factors `p` over the rationals as far as rational roots go.
    ///
    /// ```
    /// use observer_workbench::algebra::{Rational, Ring};
    /// use observer_workbench::poly::{Factored, Poly};
    /// let p = Poly::from_descending(&[1, 12, 48, 64].map(Rational::from_i64), "s");
    /// assert_eq!(Factored::of(&p).to_string(), "(s + 4)^3");
    /// let q = Poly::from_descending(&[2, 2, 4, 4].map(Rational::from_i64), "s");
    /// assert_eq!(Factored::of(&q).to_string(), "2(s + 1)(s^2 + 2)");
    /// ```
    pub fn of(p: &Poly<Rational>) -> Factored {
        let var = p.var();
        let mut linear: Vec<(Rational, u32)> = Vec::new();
        let mut others = Vec::new();
        let mut exhaustive = true;
        for (part, m) in p.square_free() {
            let found = rational_roots(&part);
            exhaustive &= found.exhaustive;
            let mut rest = part.clone();
            for r in found.roots {
                let lin = Poly::new(vec![-r.clone(), Rational::one()], var);
                rest = rest.divide_exact(&lin).unwrap_or(rest);
                linear.push((r, m));
            }
            if rest.degree().unwrap_or(0) > 0 {
                others.push((rest.monic(), m));
            }
        }
        linear.sort_by(|a, b| b.0.cmp(&a.0));
        let mut factors: Vec<(Poly<Rational>, u32)> = linear
            .into_iter()
            .map(|(r, m)| (Poly::new(vec![-r, Rational::one()], var), m))
            .collect();
        factors.extend(others);
        Factored {
            constant: p.leading(),
            factors,
            exhaustive,
        }
    }

    /// The roots with multiplicities that the factorisation exposes (rational roots only).
    pub fn rational_roots(&self) -> Vec<(Rational, u32)> {
        self.factors
            .iter()
            .filter(|(f, _)| f.degree() == Some(1))
            .map(|(f, m)| (-f.coeff(0), *m))
            .collect()
    }

    /// The product back, expanded.
    pub fn expand(&self) -> Poly<Rational> {
        let var = self.factors.first().map_or("s", |(f, _)| f.var());
        self.factors
            .iter()
            .fold(Poly::constant(self.constant.clone(), var), |acc, (f, m)| {
                acc * f.pow(*m)
            })
    }

    /// LaTeX, `(s + 4)^{3}`.
    pub fn to_latex(&self) -> String {
        self.render(true)
    }

    fn render(&self, latex: bool) -> String {
        let mut out = String::new();
        let c = &self.constant;
        if self.factors.is_empty() {
            return if latex { c.to_latex() } else { c.to_string() };
        }
        if c == &-Rational::one() {
            out.push('-');
        } else if !c.is_one() {
            out.push_str(&if latex { c.to_latex() } else { c.to_string() });
        }
        let single = self.factors.len() == 1 && self.factors[0].1 == 1 && c.is_one();
        for (f, m) in &self.factors {
            let body = if latex { f.to_latex() } else { f.render() };
            if single {
                out.push_str(&body);
            } else {
                out.push_str(&format!("({body})"));
            }
            if *m > 1 {
                out.push_str(&if latex {
                    format!("^{{{m}}}")
                } else {
                    format!("^{m}")
                });
            }
        }
        out
    }
}

impl fmt::Display for Factored {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.render(false))
    }
}

/// Roots of a rational polynomial, exact where they are rational or lie in a quadratic field.
#[derive(Debug, Clone, PartialEq)]
pub struct ExactRoots {
    /// Exact roots with multiplicities (rational roots first, descending; then quadratic pairs).
    pub roots: Vec<(Quadratic, u32)>,
    /// Factors of degree ≥ 3 (or too large to split) whose roots are not given exactly.
    pub unresolved: Vec<(Poly<Rational>, u32)>,
}

impl ExactRoots {
    /// Whether every root is given exactly.
    pub fn complete(&self) -> bool {
        self.unresolved.is_empty()
    }
    /// The roots as text, `-2 (×2), √2 − 2, -√2 − 2`.
    pub fn render(&self) -> String {
        let mut parts: Vec<String> = self
            .roots
            .iter()
            .map(|(r, m)| {
                if *m > 1 {
                    format!("{r} (×{m})")
                } else {
                    r.to_string()
                }
            })
            .collect();
        parts.extend(self.unresolved.iter().map(|(f, m)| {
            format!(
                "roots of {f}{}",
                if *m > 1 {
                    format!(" (×{m})")
                } else {
                    String::new()
                }
            )
        }));
        if parts.is_empty() {
            "none".into()
        } else {
            parts.join(", ")
        }
    }
}

/// The roots of `p`: rational roots, then the roots of quadratic factors in Q(√d).
///
/// ```
/// use observer_workbench::algebra::{Rational, Ring};
/// use observer_workbench::poly::{exact_roots, Poly};
/// // RC ladder n = 3: (s + 2)(s^2 + 4s + 2)
/// let p = Poly::from_descending(&[1, 6, 10, 4].map(Rational::from_i64), "s");
/// assert_eq!(exact_roots(&p).render(), "-2, √2 − 2, -√2 − 2");
/// ```
pub fn exact_roots(p: &Poly<Rational>) -> ExactRoots {
    let f = Factored::of(p);
    let mut roots = Vec::new();
    let mut unresolved = Vec::new();
    for (factor, m) in &f.factors {
        match factor.degree() {
            Some(1) => roots.push((Quadratic::rational(-factor.coeff(0)), *m)),
            Some(2) => {
                // s^2 + b s + c (monic): (−b ± √(b² − 4c)) / 2
                let b = factor.coeff(1);
                let c = factor.coeff(0);
                let disc = b.clone() * b.clone() - Rational::from_i64(4) * c;
                match Quadratic::sqrt_of_rational(&disc) {
                    Ok(root) => {
                        let half = Quadratic::rational(Rational::new(1.into(), 2.into()));
                        let minus_b = Quadratic::rational(-b);
                        roots.push(((minus_b.clone() + root.clone()) * half.clone(), *m));
                        roots.push(((minus_b - root) * half, *m));
                    }
                    Err(_) => unresolved.push((factor.clone(), *m)),
                }
            }
            _ => unresolved.push((factor.clone(), *m)),
        }
    }
    ExactRoots { roots, unresolved }
}
