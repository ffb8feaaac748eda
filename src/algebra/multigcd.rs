//! Greatest common divisors of multivariate polynomials over Q, so that a rational function of
//! the plant's parameters is always kept in lowest terms.
//!
//! **Algorithm.** Recursive primitive polynomial remainder sequences (Collins; Knuth, TAOCP
//! vol. 2, §4.6.1, Algorithm E): a polynomial in `x₁, …, x_k` is a polynomial in a main variable
//! `x` whose coefficients lie in `Q[x₂, …]`; `gcd(a, b) = gcd(cont a, cont b) · pp(prs(pp a,
//! pp b))`, where the content is the gcd of the coefficients (computed by the same algorithm
//! one variable down) and each pseudo-remainder is replaced by its primitive part, which keeps
//! the coefficients from growing exponentially. A variable that occurs in one operand only is
//! removed at once (`gcd(a, b) = gcd(cont_x a, b)`), a single-term operand is answered from
//! exponents alone, and an operand that divides the other is the answer.
//!
//! **Cost.** For the teaching sizes it serves (a handful of parameters, degrees below ten) each
//! step is a few polynomial products; in general a primitive PRS costs `O(d²)` pseudo-divisions
//! per level with coefficients whose size grows linearly. Every product is charged to the
//! [`super::budget`] meter, so a gcd that would run for minutes stops early and the command
//! refuses with the limit named.
//!
//! **Identity.** The result `g` divides both operands exactly and `a/g`, `b/g` have no common
//! factor; it is normalised to integer coefficients without common factor and a positive
//! leading coefficient (in the lexicographic term order), so equal inputs give equal outputs.

use super::{budget, IntegralDomain, MultiPoly, Rational};
use num_bigint::BigInt;
use num_traits::{One, Signed, Zero};

/// `gcd(a, b)`, normalised (integer coefficients, content 1, positive leading coefficient);
/// `gcd(0, 0) = 0`.
///
/// # Example
/// ```
/// use observer_workbench::algebra::{poly_gcd, MultiPoly, Ring};
/// let (k, m) = (MultiPoly::var("k"), MultiPoly::var("m"));
/// let common = k.clone() + m.clone();
/// let a = common.clone() * k.clone() * MultiPoly::from_i64(4);
/// let b = common.clone() * (m.clone() - k.clone());
/// assert_eq!(poly_gcd(&a, &b), common);
/// ```
pub fn poly_gcd(a: &MultiPoly, b: &MultiPoly) -> MultiPoly {
    normalised(&gcd_any(a, b))
}

/// `p` scaled by a nonzero rational to integer coefficients without common factor and a
/// positive leading coefficient.
pub fn normalised(p: &MultiPoly) -> MultiPoly {
    let scale = normalising_factor(p);
    if scale.is_one() {
        p.clone()
    } else {
        p.clone() * MultiPoly::constant(scale)
    }
}

/// The rational `f` with `f·p` normalised (1 for the zero polynomial).
pub fn normalising_factor(p: &MultiPoly) -> Rational {
    let coefficients: Vec<&Rational> = p.terms().map(|(_, c)| c).collect();
    scale_to_primitive(&coefficients, p.leading_coefficient())
}

/// The rational `f` that makes `f·c` integers without common factor for every coefficient `c`,
/// with `f·leading` positive (1 when every coefficient is zero): the normal form of a
/// polynomial here, and of a rational function's numerator and denominator taken together.
pub(crate) fn scale_to_primitive(
    coefficients: &[&Rational],
    leading: Option<&Rational>,
) -> Rational {
    let mut den = BigInt::one();
    for c in coefficients {
        den = num_integer::Integer::lcm(&den, c.denom());
    }
    let mut num = BigInt::zero();
    for c in coefficients {
        num = super::gcd(&num, &(c.numer() * (&den / c.denom())));
    }
    if num.is_zero() {
        return Rational::one();
    }
    let f = Rational::new(den, num);
    if leading.is_some_and(Signed::is_negative) {
        -f
    } else {
        f
    }
}

fn gcd_any(a: &MultiPoly, b: &MultiPoly) -> MultiPoly {
    if a.is_zero() {
        return b.clone();
    }
    if b.is_zero() {
        return a.clone();
    }
    if budget::exhausted() {
        return MultiPoly::one();
    }
    if a.as_constant().is_some() || b.as_constant().is_some() {
        return MultiPoly::one();
    }
    if a.number_of_terms() == 1 {
        return monomial_gcd(a, b);
    }
    if b.number_of_terms() == 1 {
        return monomial_gcd(b, a);
    }
    let (va, vb) = (a.variables(), b.variables());
    // a variable of one operand only: it divides out of every common factor
    if let Some(x) = va.iter().find(|v| !vb.contains(v)) {
        return gcd_any(&content_in(a, x), b);
    }
    if let Some(x) = vb.iter().find(|v| !va.contains(v)) {
        return gcd_any(a, &content_in(b, x));
    }
    // the main variable: the one of least degree keeps the remainder sequence short
    let x = va
        .iter()
        .min_by_key(|v| a.degree_in(v).max(b.degree_in(v)))
        .cloned()
        .unwrap_or_default();
    // a divisor of the other is the answer (cheap, and common: m against m²·(…))
    let (small, large) = if a.number_of_terms() <= b.number_of_terms() {
        (a, b)
    } else {
        (b, a)
    };
    budget::charge(small.product_work(large));
    if large.divide_exact(small).is_some() {
        return small.clone();
    }
    let (ca, pa) = split_content(a, &x);
    let (cb, pb) = split_content(b, &x);
    let c = gcd_any(&ca, &cb);
    let g = primitive_prs(pa, pb);
    let g = primitive_part(&g).1;
    c * from_coefficients(&g, &x)
}

/// `gcd(m, p)` for a single term `m`: the monomial of the least exponents.
fn monomial_gcd(m: &MultiPoly, p: &MultiPoly) -> MultiPoly {
    let mut out = MultiPoly::one();
    for v in m.variables() {
        let e = p
            .terms()
            .map(|(t, _)| t.exponent(&v))
            .min()
            .unwrap_or(0)
            .min(m.degree_in(&v));
        if e > 0 {
            out = out * MultiPoly::term(Rational::one(), super::Monomial::var(&v, e));
        }
    }
    out
}

/// The content of `p` as a polynomial in `x`: the gcd of its coefficients.
fn content_in(p: &MultiPoly, x: &str) -> MultiPoly {
    content(&p.coefficients_in(x))
}

fn content(coefficients: &[MultiPoly]) -> MultiPoly {
    let mut g = MultiPoly::zero();
    // the shortest coefficients first: the gcd is found (or reaches 1) sooner
    let mut sorted: Vec<&MultiPoly> = coefficients.iter().filter(|c| !c.is_zero()).collect();
    sorted.sort_by_key(|c| c.number_of_terms());
    for c in sorted {
        g = gcd_any(&g, c);
        if g.as_constant().is_some() {
            return MultiPoly::one();
        }
    }
    g
}

/// `(content, primitive part)` of `p` in `x`, the primitive part as coefficients of `x`.
fn split_content(p: &MultiPoly, x: &str) -> (MultiPoly, Vec<MultiPoly>) {
    primitive_part(&p.coefficients_in(x))
}

fn primitive_part(coefficients: &[MultiPoly]) -> (MultiPoly, Vec<MultiPoly>) {
    let c = content(coefficients);
    if c.as_constant().is_some() {
        return (MultiPoly::one(), coefficients.to_vec());
    }
    let parts = coefficients
        .iter()
        .map(|k| k.divide_exact(&c).unwrap_or_else(|| k.clone()))
        .collect();
    (c, parts)
}

fn from_coefficients(coefficients: &[MultiPoly], x: &str) -> MultiPoly {
    let mut out = MultiPoly::zero();
    for (k, c) in coefficients.iter().enumerate() {
        if c.is_zero() {
            continue;
        }
        let power = MultiPoly::term(Rational::one(), super::Monomial::var(x, k as u32));
        out = out + c.clone() * power;
    }
    out
}

fn trimmed(mut p: Vec<MultiPoly>) -> Vec<MultiPoly> {
    while p.last().is_some_and(Zero::is_zero) {
        p.pop();
    }
    p
}

/// The pseudo-remainder of `f` by `g` (coefficients lowest power first, `g` nonzero).
fn pseudo_remainder(f: Vec<MultiPoly>, g: &[MultiPoly]) -> Vec<MultiPoly> {
    let dg = g.len() - 1;
    let lead = &g[dg];
    let mut f = trimmed(f);
    while f.len() > dg && !budget::exhausted() {
        let top = f.len() - 1;
        let lf = f[top].clone();
        let shift = top - dg;
        let work: u64 = f.iter().map(|c| c.product_work(lead)).sum::<u64>()
            + g.iter().map(|c| c.product_work(&lf)).sum::<u64>();
        budget::charge(work);
        // charged before the products are formed: once the meter is out, no more work
        if budget::exhausted() {
            break;
        }
        for c in f.iter_mut() {
            *c = std::mem::take(c) * lead.clone();
        }
        for (i, gi) in g.iter().enumerate() {
            f[shift + i] = std::mem::take(&mut f[shift + i]) - lf.clone() * gi.clone();
        }
        f.pop();
        f = trimmed(f);
    }
    f
}

/// The last nonzero term of the primitive remainder sequence of `a` and `b` (both primitive,
/// as coefficient vectors in the main variable).
fn primitive_prs(a: Vec<MultiPoly>, b: Vec<MultiPoly>) -> Vec<MultiPoly> {
    let (mut f, mut g) = if a.len() >= b.len() { (a, b) } else { (b, a) };
    loop {
        if budget::exhausted() {
            return vec![MultiPoly::one()];
        }
        let r = pseudo_remainder(f, &g);
        if r.is_empty() {
            return g;
        }
        if r.len() == 1 {
            return vec![MultiPoly::one()];
        }
        f = g;
        g = primitive_part(&r).1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algebra::Ring;
    use proptest::prelude::*;

    fn v(name: &str) -> MultiPoly {
        MultiPoly::var(name)
    }
    fn c(n: i64) -> MultiPoly {
        MultiPoly::from_i64(n)
    }

    #[test]
    fn common_factors_are_found() {
        let (k, m, w) = (v("k"), v("m"), v("w"));
        let f = k.clone() * m.clone() + w.clone() * w.clone() - c(3);
        let a = f.clone() * (k.clone() - m.clone()) * c(6);
        let b = f.clone() * (k.clone() + w.clone()) * m.clone();
        assert_eq!(poly_gcd(&a, &b), normalised(&f));
        assert_eq!(
            poly_gcd(&(m.clone() * m.clone() * k.clone()), &(m.clone() * w)),
            m
        );
        assert_eq!(poly_gcd(&c(4), &k), c(1));
        assert_eq!(poly_gcd(&-k.clone(), &MultiPoly::zero()), k);
    }

    #[test]
    fn normal_form_is_integer_primitive_positive() {
        let p = v("m") * MultiPoly::constant(Rational::new((-2).into(), 3.into()))
            + MultiPoly::constant(Rational::new(4.into(), 9.into()));
        assert_eq!(normalised(&p).to_input(), "3*m - 2");
    }

    fn small_poly() -> impl Strategy<Value = MultiPoly> {
        let term = (-3i64..=3, 0u32..3, 0u32..3, 0u32..2);
        proptest::collection::vec(term, 1..4).prop_map(|ts| {
            ts.into_iter()
                .fold(MultiPoly::zero(), |acc, (k, e1, e2, e3)| {
                    let mut t = MultiPoly::from_i64(k);
                    for (name, e) in [("a", e1), ("b", e2), ("c", e3)] {
                        for _ in 0..e {
                            t = t * MultiPoly::var(name);
                        }
                    }
                    acc + t
                })
        })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(200))]
        /// The gcd of `f·g` and `f·h` is a multiple of `f`, divides both, and leaves coprime
        /// cofactors.
        #[test]
        fn gcd_divides_and_is_greatest(f in small_poly(), g in small_poly(), h in small_poly()) {
            prop_assume!(!f.is_zero() && !g.is_zero() && !h.is_zero());
            let (a, b) = (f.clone() * g, f.clone() * h);
            let d = poly_gcd(&a, &b);
            prop_assert!(a.divide_exact(&d).is_some());
            prop_assert!(b.divide_exact(&d).is_some());
            prop_assert!(d.divide_exact(&normalised(&f)).is_some());
            let (x, y) = (a.divide_exact(&d).unwrap(), b.divide_exact(&d).unwrap());
            prop_assert_eq!(poly_gcd(&x, &y), MultiPoly::one());
        }
    }
}
