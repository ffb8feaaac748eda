//! Greatest common divisors and exact quotients of polynomials over the rationals, computed on
//! integer polynomials: denominators cleared once, Collins' primitive pseudo-remainder sequence
//! with the content divided out at every step. Euclid over `Q` directly makes a gcd per
//! coefficient operation and lets the coefficients of the remainders swell (a transfer function
//! typed with `22e-220` took seconds); here the integers stay the size of the inputs' and one
//! reduction happens per result coefficient. [`Poly::gcd`], [`Poly::divide_exact`] and products
//! dispatch here for rational coefficients (also `Q(√d)` polynomials whose coefficients are rational).

use crate::algebra::gcd::{fraction, gcd, integer_numerators};
use crate::algebra::Rational;
use num_bigint::BigInt;
use num_traits::{One, Signed, Zero};

/// `p = c · P` with `P` a primitive integer polynomial (ascending, positive leading coefficient)
/// and `c` rational; `None` for the zero polynomial.
fn primitive_part(p: &[Rational]) -> Option<(Vec<BigInt>, Rational)> {
    if p.iter().all(Zero::is_zero) {
        return None;
    }
    let (ints, d) = integer_numerators(p);
    let (mut prim, content) = integer_primitive(ints);
    let mut content = fraction(content, d);
    if prim.last().is_some_and(Signed::is_negative) {
        prim.iter_mut().for_each(|c| *c = -&*c);
        content = -content;
    }
    Some((prim, content))
}

/// An integer polynomial divided by the gcd of its coefficients, and that gcd.
fn integer_primitive(mut p: Vec<BigInt>) -> (Vec<BigInt>, BigInt) {
    while p.last().is_some_and(Zero::is_zero) {
        p.pop();
    }
    let mut g = BigInt::zero();
    for c in &p {
        if !c.is_zero() {
            g = if g.is_zero() { c.abs() } else { gcd(&g, c) };
            if g.is_one() {
                return (p, g);
            }
        }
    }
    if g.is_zero() || g.is_one() {
        return (p, BigInt::one());
    }
    (p.into_iter().map(|c| c / &g).collect(), g)
}

/// The pseudo-remainder `lc(b)^(deg a − deg b + 1) · a mod b`, in integers.
fn pseudo_remainder(a: &[BigInt], b: &[BigInt]) -> Vec<BigInt> {
    let mut r = a.to_vec();
    let db = b.len() - 1;
    let lead = &b[db];
    while r.len() > db && !r.is_empty() {
        let top = r.len() - 1;
        let c = r[top].clone();
        // r ← lead · r − c · x^(top − db) · b
        for x in r.iter_mut() {
            *x *= lead;
        }
        for (j, bj) in b.iter().enumerate() {
            r[top - db + j] -= &c * bj;
        }
        r.pop();
        while r.last().is_some_and(Zero::is_zero) {
            r.pop();
        }
    }
    r
}

fn to_rationals(p: &[BigInt], scale: &Rational) -> Vec<Rational> {
    p.iter()
        .map(|c| fraction(c * scale.numer(), scale.denom().clone()))
        .collect()
}

/// The product of two rational polynomials (ascending coefficients, both nonzero): each scaled
/// to integers by the lcm of its denominators, convolved in integers, each result coefficient
/// reduced once.
pub(crate) fn mul_rational(a: &[Rational], b: &[Rational]) -> Vec<Rational> {
    if a.is_empty() || b.is_empty() {
        return Vec::new();
    }
    let ((ia, da), (ib, db)) = (integer_numerators(a), integer_numerators(b));
    let out = super::kronecker::mul_integers(&ia, &ib);
    let d = da * db;
    out.into_iter().map(|n| fraction(n, d.clone())).collect()
}

/// The monic gcd of two rational polynomials (ascending coefficients); empty when both are zero.
pub(crate) fn gcd_rational(a: &[Rational], b: &[Rational]) -> Vec<Rational> {
    let (pa, pb) = (primitive_part(a), primitive_part(b));
    let (mut x, mut y) = match (pa, pb) {
        (None, None) => return Vec::new(),
        (Some((p, _)), None) | (None, Some((p, _))) => (p, Vec::new()),
        (Some((p, _)), Some((q, _))) => (p, q),
    };
    if x.len() < y.len() {
        std::mem::swap(&mut x, &mut y);
    }
    if y.len() > 1 && coprime_modulo_a_prime(&x, &y) {
        return vec![Rational::one()];
    }
    while !y.is_empty() {
        let r = pseudo_remainder(&x, &y);
        x = y;
        y = integer_primitive(r).0;
    }
    let lead = x.last().cloned().unwrap_or_else(BigInt::one);
    x.iter()
        .map(|c| fraction(c.clone(), lead.clone()))
        .collect()
}

/// Whether two nonconstant integer polynomials are certainly coprime over `Q`, decided modulo a
/// prime that divides neither leading coefficient: then the degree of the gcd modulo `p` is at
/// least the degree of the gcd over `Q` (the images of the cofactors keep their degrees), so a
/// constant gcd modulo `p` proves the gcd over `Q` is 1. `false` means "not decided here" (an
/// unlucky prime, or a true common factor): the remainder sequence runs. Most fractions a
/// person or a fuzzer types are already in lowest terms, and the primitive remainder sequence,
/// whose pseudo-remainders swell before their content is divided out, cost 0.19 s on a
/// degree-50 fraction with 200-bit coefficients that this settles in microseconds.
fn coprime_modulo_a_prime(x: &[BigInt], y: &[BigInt]) -> bool {
    use crate::linalg::modular::{int_mod, primes};
    // up to three primes, skipping one that divides a leading coefficient
    primes().take(3).any(|p| {
        let reduce = |v: &[BigInt]| v.iter().map(|c| int_mod(c, p)).collect::<Vec<u64>>();
        let (a, b) = (reduce(x), reduce(y));
        if a.last() == Some(&0) || b.last() == Some(&0) {
            return false; // p divides a leading coefficient: unlucky, try the next
        }
        gcd_degree_mod(a, b, p) == Some(0)
    })
}

/// The degree of the gcd of two nonzero polynomials modulo the prime `p` (Euclid in `Z/p`);
/// `None` if a leading coefficient has no inverse (cannot happen for trimmed inputs mod a prime).
fn gcd_degree_mod(mut a: Vec<u64>, mut b: Vec<u64>, p: u64) -> Option<usize> {
    let trim = |v: &mut Vec<u64>| {
        while v.last() == Some(&0) {
            v.pop();
        }
    };
    trim(&mut a);
    trim(&mut b);
    if a.len() < b.len() {
        std::mem::swap(&mut a, &mut b);
    }
    while !b.is_empty() {
        // a ← a mod b
        let lead_inv = crate::linalg::modular::inv_mod(b[b.len() - 1], p)?;
        while a.len() >= b.len() {
            let top = a.len() - 1;
            let q = a[top] * lead_inv % p;
            let shift = top + 1 - b.len();
            for (j, bj) in b.iter().enumerate() {
                a[shift + j] = (a[shift + j] + (p - q) * bj) % p;
            }
            trim(&mut a);
        }
        std::mem::swap(&mut a, &mut b);
    }
    Some(a.len().saturating_sub(1))
}

/// `p / d` when `d` divides `p` exactly over the rationals; `None` otherwise (or `d = 0`).
pub(crate) fn divide_exact_rational(p: &[Rational], d: &[Rational]) -> Option<Vec<Rational>> {
    let (dp, cd) = primitive_part(d)?;
    let Some((r, cp)) = primitive_part(p) else {
        return Some(Vec::new());
    };
    // Gauss: a primitive divisor over Q divides over Z, so every step divides exactly
    let q = divide_exact_integers(r, &dp)?;
    Some(to_rationals(&q, &(cp / cd)))
}

/// `p / d` over the integers (ascending coefficients, `d`'s leading one nonzero), when every
/// step divides exactly and no remainder is left; `None` otherwise.
pub(crate) fn divide_exact_integers(mut r: Vec<BigInt>, d: &[BigInt]) -> Option<Vec<BigInt>> {
    while r.last().is_some_and(Zero::is_zero) {
        r.pop();
    }
    let db = d.len().checked_sub(1)?;
    if r.len() <= db {
        return r.is_empty().then(Vec::new);
    }
    let mut q = vec![BigInt::zero(); r.len() - db];
    while r.len() > db {
        let top = r.len() - 1;
        let (c, rem) = num_integer::Integer::div_rem(&r[top], &d[db]);
        if !rem.is_zero() {
            return None;
        }
        for (j, dj) in d.iter().enumerate() {
            r[top - db + j] -= &c * dj;
        }
        q[top - db] = c;
        r.pop();
    }
    r.iter().all(Zero::is_zero).then_some(q)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algebra::Ring;

    fn q(v: &[i64]) -> Vec<Rational> {
        v.iter().map(|&x| Rational::from_i64(x)).collect()
    }

    #[test]
    fn gcd_and_quotients_of_products() {
        // (s + 1)(s − 2)/3 and (s + 1)(2s + 5)/7 share s + 1
        let a: Vec<Rational> = q(&[-2, -1, 1])
            .into_iter()
            .map(|c| c / Rational::from_i64(3))
            .collect();
        let b: Vec<Rational> = q(&[5, 7, 2])
            .into_iter()
            .map(|c| c / Rational::from_i64(7))
            .collect();
        assert_eq!(gcd_rational(&a, &b), q(&[1, 1]));
        let quotient = divide_exact_rational(&a, &q(&[1, 1])).unwrap();
        assert_eq!(
            quotient,
            vec![
                Rational::from_i64(-2) / Rational::from_i64(3),
                Rational::from_i64(1) / Rational::from_i64(3)
            ]
        );
        assert!(divide_exact_rational(&a, &q(&[3, 1])).is_none());
        assert!(gcd_rational(&[], &[]).is_empty());
    }

    proptest::proptest! {
        /// Against Euclid over Q (`div_rem` is not dispatched): the same monic gcd, and the
        /// quotients multiply back.
        #[test]
        fn agrees_with_euclid_over_q(
            f in proptest::collection::vec(-20i64..20, 1..5),
            g in proptest::collection::vec(-20i64..20, 1..5),
            h in proptest::collection::vec(-20i64..20, 1..4),
            den in 1i64..50,
        ) {
            use crate::poly::Poly;
            let poly = |v: &[i64]| {
                Poly::new(v.iter().map(|&x| Rational::from_i64(x) / Rational::from_i64(den)).collect(), "s")
            };
            let (a, b) = (poly(&f) * poly(&h), poly(&g) * poly(&h));
            let (mut x, mut y) = (a.clone(), b.clone());
            while !y.is_zero() {
                let r = x.div_rem(&y).unwrap().1;
                x = y;
                y = r;
            }
            let euclid = x.monic();
            let fast = Poly::new(gcd_rational(a.coeffs(), b.coeffs()), "s");
            proptest::prop_assert_eq!(&fast, &euclid);
            // the fraction-free product against the schoolbook one in rationals
            if !a.is_zero() && !b.is_zero() {
                let (x, y) = (a.coeffs(), b.coeffs());
                let school: Vec<Rational> = (0..x.len() + y.len() - 1)
                    .map(|k| {
                        (0..=k)
                            .filter(|&i| i < x.len() && k - i < y.len())
                            .fold(Rational::zero(), |acc, i| acc + &x[i] * &y[k - i])
                    })
                    .collect();
                proptest::prop_assert_eq!(
                    Poly::new(mul_rational(x, y), "s"),
                    Poly::new(school, "s")
                );
            }
            if !fast.is_zero() {
                let q = Poly::new(divide_exact_rational(a.coeffs(), fast.coeffs()).unwrap(), "s");
                proptest::prop_assert_eq!(q * fast, a);
            }
        }
    }
}
