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

use super::words::{negate_limbs, wide_mul};
use super::Rational;
use num_bigint::{BigInt, BigUint, Sign};
use num_integer::Integer;
use num_traits::{One, Signed, Zero};

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

/// `gcd` of two naturals by Lehmer's algorithm, on the numbers' 64-bit limbs in place: each
/// step reads the leading 62 bits, finds the cofactor matrix of the Euclidean steps they
/// determine, and applies it to both numbers in one pass with 128-bit carries — no number is
/// allocated inside the loop (num-bigint would allocate four products and two sums per step).
fn gcd_unsigned(a: &BigUint, b: &BigUint) -> BigUint {
    let mut a = a.to_u64_digits();
    let mut b = b.to_u64_digits();
    loop {
        trim(&mut a);
        trim(&mut b);
        if less_than(&a, &b) {
            std::mem::swap(&mut a, &mut b);
        }
        if b.is_empty() {
            return natural_from_limbs(&a);
        }
        if a.len() <= 2 {
            return BigUint::from(u128_of(&a).gcd(&u128_of(&b)));
        }
        // the leading 62 bits, so that x + s and q·u stay inside i64
        let shift = bit_length(&a) - LEADING_BITS;
        let step = (bit_length(&b) > shift)
            .then(|| lehmer_cofactors(leading_bits(&a, shift), leading_bits(&b, shift)))
            .flatten();
        match step {
            Some(m) => apply_cofactors(&mut a, &mut b, m),
            None => {
                // very different sizes, or not one certain step: one division
                let r = natural_from_limbs(&a) % natural_from_limbs(&b);
                a = std::mem::replace(&mut b, r.to_u64_digits());
            }
        }
    }
}

/// `c · x` for a signed word and an unsigned limb.
#[inline]
fn mixed(c: i64, x: u64) -> i128 {
    let magnitude = wide_mul(c.unsigned_abs(), x) as i128;
    if c < 0 {
        -magnitude
    } else {
        magnitude
    }
}

fn trim(x: &mut Vec<u64>) {
    while x.last() == Some(&0) {
        x.pop();
    }
}

/// `x < y` for trimmed limbs.
fn less_than(x: &[u64], y: &[u64]) -> bool {
    x.len() < y.len() || (x.len() == y.len() && x.iter().rev().lt(y.iter().rev()))
}

fn bit_length(x: &[u64]) -> u64 {
    x.last().map_or(0, |top| {
        64 * x.len() as u64 - u64::from(top.leading_zeros())
    })
}

fn u128_of(x: &[u64]) -> u128 {
    x.iter()
        .rev()
        .fold(0, |acc, &l| (acc << 64) | u128::from(l))
}

/// The natural number with these 64-bit limbs, least significant first (num-bigint builds
/// from 32-bit digits only).
pub(crate) fn natural_from_limbs(x: &[u64]) -> BigUint {
    BigUint::new(
        x.iter()
            .flat_map(|&l| [l as u32, (l >> 32) as u32])
            .collect(),
    )
}

/// `⌊x / 2^shift⌋` for a trimmed `x` below `2^(shift + 128)`.
fn leading_bits(x: &[u64], shift: u64) -> u128 {
    let (k, r) = ((shift / 64) as usize, (shift % 64) as u32);
    let limb = |i: usize| u128::from(x.get(i).copied().unwrap_or(0));
    let low = limb(k) | (limb(k + 1) << 64);
    if r == 0 {
        low
    } else {
        (low >> r) | (limb(k + 2) << (128 - r))
    }
}

/// `(a, b) ← (s·a + t·b, u·a + v·b)` in place; `|s|, |t|, |u|, |v| ≤ 2^61` keeps each limb's
/// sum and carry in an i128.
fn apply_cofactors(a: &mut Vec<u64>, b: &mut Vec<u64>, [s, t, u, v]: [i64; 4]) {
    b.resize(a.len(), 0);
    let (mut ca, mut cb) = (0i128, 0i128);
    for (al, bl) in a.iter_mut().zip(b.iter_mut()) {
        let (x, y) = (*al, *bl);
        let ra = mixed(s, x) + mixed(t, y) + ca;
        let rb = mixed(u, x) + mixed(v, y) + cb;
        *al = ra as u64;
        *bl = rb as u64;
        ca = ra >> 64;
        cb = rb >> 64;
    }
    // Knuth's test makes both results the true remainders (natural, no longer than a); the
    // matrix is unimodular whatever happens, so a carry or a sign would be kept, not lost
    settle(a, ca);
    settle(b, cb);
}

/// The natural number `|x + carry·2^(64·len)|` in `x`.
fn settle(x: &mut Vec<u64>, carry: i128) {
    if carry == 0 {
        return;
    }
    x.extend([carry as u64, (carry >> 64) as u64]);
    if carry < 0 {
        negate_limbs(x);
    }
}

/// `a.div_euclid(b)`, with the common small quotients of Euclid's algorithm (0 to 3: about
/// four in five by the Gauss–Kuzmin law) found by subtraction, the rest by one word division.
#[inline]
fn quotient(a: i64, b: i64) -> i64 {
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

/// How many leading bits of the larger number one Lehmer step reads.
const LEADING_BITS: u64 = 62;

/// Cofactors stay at or below this, so a limb times a cofactor, summed twice with a carry, fits
/// an i128 ([`apply_cofactors`]).
const COFACTOR_LIMIT: i64 = 1 << 61;

/// The cofactor matrix `[s t; u v]` of the Euclidean steps that the leading digits `x ≥ y`
/// (below `2^62`) determine for sure (Knuth's test on `(x + s)/(y + u)` and `(x + t)/(y + v)`),
/// or `None` when not even one step is certain. All in machine words: about 31 bits of
/// quotients per call.
fn lehmer_cofactors(x: u128, y: u128) -> Option<[i64; 4]> {
    let (Ok(mut x), Ok(mut y)) = (i64::try_from(x), i64::try_from(y)) else {
        return None;
    };
    let (mut s, mut t, mut u, mut v) = (1i64, 0i64, 0i64, 1i64);
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
        let (nu, nv) = (s - qu, t - qv);
        if nu.abs() > COFACTOR_LIMIT || nv.abs() > COFACTOR_LIMIT {
            break;
        }
        (s, u) = (u, nu);
        (t, v) = (v, nv);
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
    // an integral quotient (a placed polynomial's coefficients, a checked product): one exact
    // division where the gcd would run its whole course
    if n.bits() >= d.bits() {
        let (q, r) = num_integer::Integer::div_rem(&n, &d);
        if r.is_zero() {
            return Rational::from_integer(q);
        }
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
    // what a typed matrix holds: an integer (no gcd), or a fraction of two words, reduced on
    // u64 magnitudes (num-integer's gcd is Stein's there; on i128 each division is a software
    // routine)
    if d == 1 {
        return Rational::from_integer(BigInt::from(n));
    }
    if let (Ok(nw), Ok(dw)) = (i64::try_from(n), i64::try_from(d)) {
        let (nu, du) = (nw.unsigned_abs(), dw.unsigned_abs());
        let g = num_integer::Integer::gcd(&nu, &du);
        let magnitude = BigInt::from(nu / g);
        let numerator = if (nw < 0) != (dw < 0) {
            -magnitude
        } else {
            magnitude
        };
        return Rational::new_raw(numerator, BigInt::from(du / g));
    }
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
        .map(|x| super::Field::scale_to_integer(x, &d))
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
        /// A typed fraction of words is num-rational's reduced fraction, for any signs, small
        /// and near the limits of i64 (and past them, through the i128 path).
        #[test]
        fn small_ratios_are_num_rationals(
            n in proptest::prelude::any::<i64>(),
            d in proptest::prelude::any::<i64>(),
            shift in 0u32..40,
            wide in proptest::prelude::any::<bool>(),
        ) {
            let d = if d == 0 { 1 } else { d };
            let (n, d) = if wide {
                (i128::from(n) << shift, i128::from(d) << (shift / 2))
            } else {
                (i128::from(n >> shift), i128::from(d >> shift).max(1))
            };
            let r = small_ratio(n, d);
            proptest::prop_assert_eq!(&r, &Rational::new(BigInt::from(n), BigInt::from(d)));
            proptest::prop_assert!(r.denom().is_positive());
            proptest::prop_assert!(gcd(r.numer(), r.denom()).is_one() || r.numer().is_zero() && r.denom().is_one());
        }
    }

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

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(300))]
        /// The limb-level Lehmer gcd is num-integer's on multi-limb operands with a shared
        /// factor, of equal and of very different lengths, and near limb boundaries.
        #[test]
        fn lehmer_on_limbs_agrees_with_num_integer(
            x in proptest::collection::vec(proptest::prelude::any::<u64>(), 1..40),
            y in proptest::collection::vec(proptest::prelude::any::<u64>(), 1..40),
            g in proptest::collection::vec(proptest::prelude::any::<u64>(), 1..6),
            edge in 0u32..4,
        ) {
            let limbs = |v: &[u64]| natural_from_limbs(v).into();
            let common: BigInt = limbs(&g);
            let (mut a, mut b): (BigInt, BigInt) = (limbs(&x) * &common, limbs(&y) * &common);
            match edge {
                1 => a = (BigInt::one() << (64 * x.len() as u32)) - 1,
                2 => b = &a + &common,
                3 => b = -b,
                _ => {}
            }
            proptest::prop_assert_eq!(gcd(&a, &b), a.gcd(&b));
            proptest::prop_assert_eq!(gcd(&b, &a), a.gcd(&b));
        }
    }

    proptest::proptest! {
        /// The signed product through the wide one is the signed product.
        #[test]
        fn mixed_is_the_signed_product(a in proptest::prelude::any::<i64>(), b in proptest::prelude::any::<u64>()) {
            for c in [a, i64::MIN, i64::MAX] {
                proptest::prop_assert_eq!(mixed(c, b), i128::from(c) * i128::from(b));
            }
        }
    }

    #[test]
    fn a_carry_or_a_sign_is_settled_exactly() {
        let mut x = vec![5u64, 0];
        settle(&mut x, 1);
        assert_eq!(
            natural_from_limbs(&x),
            BigUint::from(5u32) + (BigUint::one() << 128u32)
        );
        // x + (−1)·2^128 = 5 − 2^128, whose magnitude is 2^128 − 5
        let mut y = vec![5u64, 0];
        settle(&mut y, -1);
        trim(&mut y);
        assert_eq!(natural_from_limbs(&y), (BigUint::one() << 128u32) - 5u32);
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

    proptest::proptest! {
        /// `fraction` is num-rational's reduction, on quotients that are integers (the exact
        /// division's path) and on those that are not, of either sign and many limbs.
        #[test]
        fn fraction_reduces_as_num_rational_does(
            n in proptest::collection::vec(proptest::prelude::any::<u32>(), 0..6),
            d in proptest::collection::vec(proptest::prelude::any::<u32>(), 1..5),
            signs in (proptest::bool::ANY, proptest::bool::ANY),
            integral in proptest::bool::ANY,
        ) {
            let big = |limbs: Vec<u32>, negative: bool| {
                let x = BigInt::from(num_bigint::BigUint::new(limbs));
                if negative { -x } else { x }
            };
            let d = big(d, signs.1);
            proptest::prop_assume!(!d.is_zero());
            let n = if integral { big(n, signs.0) * &d } else { big(n, signs.0) };
            proptest::prop_assert_eq!(fraction(n.clone(), d.clone()), Rational::new(n, d));
        }
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
