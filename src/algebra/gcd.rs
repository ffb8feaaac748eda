//! Greatest common divisors of big integers by Lehmer's algorithm, and reduced fractions.
//!
//! num-bigint's `gcd` is Stein's binary algorithm: one bit per pass over the whole number, so a
//! gcd of two 10 000-bit numbers costs some 10⁶ word operations, and a gcd of a 10 000-bit number
//! with a small one costs as much (it subtracts the small number bit by bit). Exact linear algebra
//! normalises every entry of a result once, so this is where a profile of a large exact design
//! ends up. Lehmer's algorithm (Knuth, TAOCP vol. 2, §4.5.2, Algorithm L) runs Euclid's
//! algorithm on the leading 126 bits with double-word cofactors and applies the accumulated 2×2
//! matrix to the full numbers once per ~60 bits of quotients; unbalanced operands take one
//! full division step first.
//!
//! The results are the same numbers as num-integer's (a property test compares them); only the
//! cost differs.

use super::Rational;
use num_bigint::{BigInt, BigUint, Sign};
use num_integer::Integer;
use num_traits::{One, Signed, ToPrimitive, Zero};

/// `gcd(a, b) ≥ 0` of two integers (0 when both are 0).
///
/// # Example
/// ```
/// use observer_workbench::algebra::{gcd, BigInt};
/// let a = BigInt::from(2).pow(300) * 15;
/// let b = BigInt::from(2).pow(200) * 21;
/// assert_eq!(gcd(&a, &b), BigInt::from(2).pow(200) * 3);
/// assert_eq!(gcd(&BigInt::from(0), &BigInt::from(-4)), BigInt::from(4));
/// ```
pub fn gcd(a: &BigInt, b: &BigInt) -> BigInt {
    BigInt::from_biguint(Sign::Plus, gcd_unsigned(a.magnitude(), b.magnitude()))
}

/// `gcd` of two naturals by Lehmer's algorithm.
fn gcd_unsigned(a: &BigUint, b: &BigUint) -> BigUint {
    let (mut a, mut b) = if a >= b {
        (a.clone(), b.clone())
    } else {
        (b.clone(), a.clone())
    };
    loop {
        if b.is_zero() {
            return a;
        }
        let bits = a.bits();
        if bits <= 126 {
            let (x, y) = (a.to_u128().unwrap_or(0), b.to_u128().unwrap_or(0));
            return BigUint::from(x.gcd(&y));
        }
        // the leading 126 bits, so that x + s stays inside i128
        let shift = bits - 126;
        if b.bits() <= shift {
            // Very different sizes: one division does what Lehmer's steps cannot.
            let r = &a % &b;
            a = std::mem::replace(&mut b, r);
            continue;
        }
        let x = (&a >> shift).to_u128().unwrap_or(0);
        let y = (&b >> shift).to_u128().unwrap_or(0);
        match lehmer_cofactors(x, y) {
            Some([s, t, u, v]) => {
                let (ai, bi) = (BigInt::from(a), BigInt::from(b));
                let na = &ai * s + &bi * t;
                let nb = &ai * u + &bi * v;
                // The matrix is unimodular, so the gcd is unchanged whatever the signs.
                a = na.into_parts().1;
                b = nb.into_parts().1;
                if a < b {
                    std::mem::swap(&mut a, &mut b);
                }
            }
            None => {
                let r = &a % &b;
                a = std::mem::replace(&mut b, r);
            }
        }
    }
}

/// `a.div_euclid(b)`, with the common small quotients of Euclid's algorithm (0 to 3: about
/// four in five by the Gauss–Kuzmin law) found by subtraction — a 128-bit division is a call
/// into software, the most expensive step of a Lehmer iteration.
#[inline]
fn quotient(a: i128, b: i128) -> i128 {
    if a >= 0 && b > 0 {
        let mut r = a;
        for q in 0..4 {
            if r < b {
                return q;
            }
            r -= b;
        }
        a / b
    } else {
        a.div_euclid(b)
    }
}

/// The cofactor matrix `[s t; u v]` of the Euclidean steps that the leading digits `x ≥ y`
/// determine for sure (Knuth's test on `(x + s)/(y + u)` and `(x + t)/(y + v)`), or `None` when
/// not even one step is certain.
fn lehmer_cofactors(x: u128, y: u128) -> Option<[i128; 4]> {
    let (Ok(mut x), Ok(mut y)) = (i128::try_from(x), i128::try_from(y)) else {
        return None;
    };
    let (mut s, mut t, mut u, mut v) = (1i128, 0i128, 0i128, 1i128);
    while let (Some(du), Some(dv), Some(xs), Some(xt)) = (
        y.checked_add(u),
        y.checked_add(v),
        x.checked_add(s),
        x.checked_add(t),
    ) {
        if du == 0 || dv == 0 {
            break;
        }
        let q = quotient(xs, du);
        if q != quotient(xt, dv) || q < 0 {
            break;
        }
        let (Some(qu), Some(qv), Some(qy)) = (q.checked_mul(u), q.checked_mul(v), q.checked_mul(y))
        else {
            break;
        };
        (s, u) = (u, s - qu);
        (t, v) = (v, t - qv);
        (x, y) = (y, x - qy);
    }
    (t != 0).then_some([s, t, u, v])
}

/// The reduced fraction `n / d` (`d ≠ 0`), normalised with [`gcd`]: the one place where an
/// exact kernel's integer result becomes a rational.
///
/// # Panics
/// Never for `d ≠ 0`; a zero `d` gives `0` (callers check it first).
///
/// # Example
/// ```
/// use observer_workbench::algebra::{fraction, BigInt, Rational};
/// let r = fraction(BigInt::from(6), BigInt::from(-4));
/// assert_eq!(r, Rational::new(BigInt::from(-3), BigInt::from(2)));
/// ```
pub fn fraction(n: BigInt, d: BigInt) -> Rational {
    if d.is_zero() || n.is_zero() {
        return Rational::zero();
    }
    let (n, d) = if d.is_negative() { (-n, -d) } else { (n, d) };
    if d.is_one() {
        return Rational::from_integer(n);
    }
    let g = gcd(&n, &d);
    if g.is_one() {
        Rational::new_raw(n, d)
    } else {
        Rational::new_raw(n / &g, d / g)
    }
}

/// `n / d` for machine-word integers (`d ≠ 0`), reduced by one word gcd: what a typed `8/50`
/// costs, instead of two big-integer gcds.
pub fn small_ratio(n: i128, d: i128) -> Rational {
    debug_assert!(d != 0, "small_ratio: zero denominator");
    let g = num_integer::Integer::gcd(&n, &d);
    let (n, d) = if g == 0 { (n, d) } else { (n / g, d / g) };
    let (n, d) = if d < 0 { (-n, -d) } else { (n, d) };
    Rational::new_raw(BigInt::from(n), BigInt::from(d))
}

/// `x + y`, reduced by Lehmer's gcd (num-rational's `+` reduces by num-bigint's binary gcd, a
/// pass per bit: a sum of two 12 000-bit fractions spent most of its time there). Zero and
/// integer operands and equal denominators take shortcuts; otherwise Knuth's form, which reduces
/// by `gcd(x.den, y.den)` first so the final gcd works on smaller numbers.
pub(crate) fn add(x: &Rational, y: &Rational) -> Rational {
    if x.is_zero() {
        return y.clone();
    }
    if y.is_zero() {
        return x.clone();
    }
    let (xd, yd) = (x.denom(), y.denom());
    if xd.is_one() && yd.is_one() {
        return Rational::from_integer(x.numer() + y.numer());
    }
    if xd == yd {
        return fraction(x.numer() + y.numer(), xd.clone());
    }
    let g = gcd(xd, yd);
    if g.is_one() {
        // coprime denominators: the sum's gcd with xd·yd is 1 (Knuth, §4.5.1)
        let n = x.numer() * yd + y.numer() * xd;
        return Rational::new_raw(n, xd * yd);
    }
    let (xd_g, yd_g) = (xd / &g, yd / &g);
    let n = x.numer() * &yd_g + y.numer() * &xd_g;
    let g2 = gcd(&n, &g);
    if n.is_zero() {
        return Rational::zero();
    }
    Rational::new_raw(&n / &g2, &xd_g * (yd / &g2))
}

/// `x · y`, reduced by Lehmer's gcd: cross-cancels `gcd(x.num, y.den)` and `gcd(y.num, x.den)`
/// first, so the product needs no further reduction (Knuth, §4.5.1).
pub(crate) fn mul(x: &Rational, y: &Rational) -> Rational {
    if x.is_zero() || y.is_zero() {
        return Rational::zero();
    }
    if x.denom().is_one() && y.denom().is_one() {
        return Rational::from_integer(x.numer() * y.numer());
    }
    let g1 = gcd(x.numer(), y.denom());
    let g2 = gcd(y.numer(), x.denom());
    let n = (x.numer() / &g1) * (y.numer() / &g2);
    let d = (x.denom() / &g2) * (y.denom() / &g1);
    if d.is_negative() {
        Rational::new_raw(-n, -d)
    } else {
        Rational::new_raw(n, d)
    }
}

/// `values` times their common denominator: `(integers, denominator)` — the one place
/// fraction-free code (matrix products, polynomial products and gcds) clears denominators.
pub(crate) fn integer_numerators(values: &[Rational]) -> (Vec<BigInt>, BigInt) {
    let d = lcm_of_denominators(values);
    let ints = values
        .iter()
        .map(|x| {
            if x.denom() == &d {
                x.numer().clone()
            } else {
                x.numer() * (&d / x.denom())
            }
        })
        .collect();
    (ints, d)
}

/// The least common multiple of the denominators of `values` (1 for none).
pub fn lcm_of_denominators(values: &[Rational]) -> BigInt {
    let mut acc = BigInt::one();
    for v in values {
        let d = v.denom();
        if d.is_one() || *d == acc {
            continue;
        }
        let g = gcd(&acc, d);
        acc = acc / g * d;
    }
    acc
}

#[cfg(test)]
mod tests {
    use super::*;

    proptest::proptest! {
        /// The Lehmer-reduced sum and product are num-rational's, in lowest terms with a
        /// positive denominator (`==` on `Ratio` compares the reduced parts).
        #[test]
        fn sums_and_products_agree_with_num_rational(
            a in -10_000i64..10_000, b in 1i64..10_000, c in -10_000i64..10_000, d in 1i64..10_000,
            k in 0u32..40,
        ) {
            let big = BigInt::from(6).pow(k);
            let x = Rational::new(BigInt::from(a) * &big, BigInt::from(b));
            let y = Rational::new(BigInt::from(c), BigInt::from(d) * &big);
            for (p, q) in [(&x, &y), (&y, &x), (&x, &x), (&x, &-x.clone())] {
                let (s, m) = (add(p, q), mul(p, q));
                proptest::prop_assert_eq!(&s, &(p + q));
                proptest::prop_assert_eq!(&m, &(p * q));
                for r in [&s, &m] {
                    proptest::prop_assert!(r.denom().is_positive());
                    proptest::prop_assert!(gcd(r.numer(), r.denom()).is_one() || r.numer().is_zero() && r.denom().is_one());
                }
            }
        }
    }

    #[test]
    fn agrees_with_stein_on_large_and_unbalanced_operands() {
        let big = BigInt::from(3).pow(4000) * BigInt::from(7).pow(50);
        let other = BigInt::from(3).pow(2500) * BigInt::from(11).pow(900) * 7;
        assert_eq!(gcd(&big, &other), big.gcd(&other));
        let small = BigInt::from(21);
        assert_eq!(gcd(&big, &small), BigInt::from(21));
        let fib = |k: usize| {
            let (mut a, mut b) = (BigInt::zero(), BigInt::one());
            for _ in 0..k {
                (a, b) = (b.clone(), a + b);
            }
            a
        };
        // consecutive Fibonacci numbers: the worst case, every quotient 1
        assert_eq!(gcd(&fib(3001), &fib(3000)), BigInt::one());
    }

    #[test]
    fn fractions_are_reduced_with_a_positive_denominator() {
        let r = fraction(BigInt::from(-10), BigInt::from(-4));
        assert_eq!((r.numer().clone(), r.denom().clone()), (5.into(), 2.into()));
        assert_eq!(
            fraction(BigInt::from(0), BigInt::from(-4)),
            Rational::zero()
        );
    }
}
