//! Products of integer polynomials by Kronecker substitution.
//!
//! **Algorithm.** Each factor is evaluated at `2^w` — its coefficients laid side by side in
//! slots of `w` bits, a multiple of 64, so that packing is copying limbs — the two big integers
//! are multiplied once (num-bigint: Karatsuba, then Toom-3, as they grow), and the product's
//! coefficients are read back slot by slot from its two's complement, each slot taken in
//! `(−2^(w−1), 2^(w−1)]` with a carry into the next. Small products stay schoolbook
//! ([`SCHOOLBOOK_BELOW`]).
//!
//! **Identity.** For `a(x) = Σ aᵢxⁱ`, `b(x) = Σ bⱼxʲ`, `c = ab` has `|c_k| ≤ min(len a, len b) ·
//! max|aᵢ| · max|bⱼ|`; with `2^(w−1)` above that bound, `c(2^w) = a(2^w) b(2^w)` determines every
//! `c_k` (its balanced digits in base `2^w` are unique). Exact: the same coefficients as the
//! schoolbook sums (a property test compares them, signs and zeros mixed).
//!
//! **Cost.** One product of two `len·w`-bit integers and linear packing, where the schoolbook
//! takes `len_a · len_b` products of `w/2`-bit ones: at degree 60 with 20 000-bit coefficients
//! (an order-60 `control`'s rank-two update), Toom-3's `N^1.46` on the whole against 3 600
//! separate products.

use crate::algebra::gcd::natural_from_limbs;
use crate::algebra::words::negate_limbs;
use num_bigint::{BigInt, Sign};
use num_traits::Zero;

/// Below this many coefficient products (`len_a · len_b`), or when the coefficients are
/// within two limbs, the schoolbook sums are cheaper than packing.
const SCHOOLBOOK_BELOW: usize = 64;

/// `a · b` for ascending integer coefficient lists (empty for an empty factor).
pub(crate) fn mul_integers(a: &[BigInt], b: &[BigInt]) -> Vec<BigInt> {
    if a.is_empty() || b.is_empty() {
        return Vec::new();
    }
    let bits = |p: &[BigInt]| p.iter().map(BigInt::bits).max().unwrap_or(0);
    let (bits_a, bits_b) = (bits(a), bits(b));
    if a.len() * b.len() < SCHOOLBOOK_BELOW || bits_a.max(bits_b) <= 128 {
        return schoolbook(a, b);
    }
    // |c_k| < 2^(bits_a + bits_b + ⌈log₂ min(len)⌉) ≤ 2^(w − 1)
    let terms = a.len().min(b.len()) as u64;
    let log_terms = u64::from(64 - (terms - 1).leading_zeros());
    let w_limbs = (bits_a + bits_b + log_terms + 1).div_ceil(64) as usize;
    let product = pack(a, w_limbs) * pack(b, w_limbs);
    unpack(&product, w_limbs, a.len() + b.len() - 1)
}

/// The schoolbook sums `c_k = Σ aᵢ b_(k−i)`.
fn schoolbook(a: &[BigInt], b: &[BigInt]) -> Vec<BigInt> {
    let mut out = vec![BigInt::zero(); a.len() + b.len() - 1];
    for (i, x) in a.iter().enumerate() {
        if x.is_zero() {
            continue;
        }
        for (j, y) in b.iter().enumerate() {
            if !y.is_zero() {
                out[i + j] += x * y;
            }
        }
    }
    out
}

/// `p(2^(64·w_limbs))`: the positive and the negative coefficients' magnitudes each laid in
/// their slots, the second subtracted from the first.
fn pack(p: &[BigInt], w_limbs: usize) -> BigInt {
    let mut positive = vec![0u64; p.len() * w_limbs];
    let mut negative = vec![0u64; p.len() * w_limbs];
    for (i, c) in p.iter().enumerate() {
        let target = match c.sign() {
            Sign::Minus => &mut negative,
            Sign::Plus | Sign::NoSign => &mut positive,
        };
        for (k, limb) in c.magnitude().iter_u64_digits().enumerate() {
            target[i * w_limbs + k] = limb;
        }
    }
    BigInt::from_biguint(Sign::Plus, natural_from_limbs(&positive))
        - BigInt::from_biguint(Sign::Plus, natural_from_limbs(&negative))
}

/// The `count` balanced base-`2^(64·w_limbs)` digits of `z`, least significant first.
fn unpack(z: &BigInt, w_limbs: usize, count: usize) -> Vec<BigInt> {
    let total = count * w_limbs;
    // z mod 2^(64·total) in two's complement
    let mut limbs: Vec<u64> = z.magnitude().iter_u64_digits().collect();
    limbs.resize(total.max(limbs.len()), 0);
    limbs.truncate(total);
    if z.sign() == Sign::Minus {
        negate_limbs(&mut limbs);
    }
    let mut carry = false;
    let mut out = Vec::with_capacity(count);
    for slot in limbs.chunks(w_limbs) {
        // slot + carry, as a w-bit word with the carry out kept apart
        let mut digit = slot.to_vec();
        let mut up = carry;
        for limb in &mut digit {
            if !up {
                break;
            }
            let (sum, overflow) = limb.overflowing_add(1);
            *limb = sum;
            up = overflow;
        }
        // the top bit set (or the slot wrapped to zero with a carry): a negative digit,
        // digit − 2^w, and a carry of one into the next slot
        let negative = up || digit.last().is_some_and(|&top| top >> 63 == 1);
        let value = BigInt::from_biguint(Sign::Plus, natural_from_limbs(&digit));
        out.push(if negative && !up {
            value - (BigInt::from(1) << (64 * w_limbs))
        } else {
            value
        });
        carry = negative;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn big(limbs: &[u32], negative: bool, shift: u32) -> BigInt {
        let m = BigInt::from_biguint(Sign::Plus, num_bigint::BigUint::from_slice(limbs)) << shift;
        if negative {
            -m
        } else {
            m
        }
    }

    #[test]
    fn slot_edges_and_cancellation() {
        // coefficients at ±2^k − 1, a product that cancels to zero in the middle, and a
        // factor with zeros
        let two = |k: u32| -> BigInt { BigInt::from(1) << k };
        let a: Vec<BigInt> = (0..12)
            .map(|i| {
                let v: BigInt = two(200 + 7 * i) - 1;
                if i % 3 == 0 {
                    -v
                } else {
                    v
                }
            })
            .collect();
        let mut b = a.clone();
        b[5] = BigInt::zero();
        b.reverse();
        assert_eq!(mul_integers(&a, &b), schoolbook(&a, &b));
        let minus: Vec<BigInt> = a.iter().map(|x| -x).collect();
        assert_eq!(mul_integers(&a, &minus), schoolbook(&a, &minus));
        // (x − 1)(x + 1) with huge equal coefficients: the middle coefficient is zero
        let c = two(300);
        let p = vec![
            -c.clone(),
            c.clone(),
            -c.clone(),
            c.clone(),
            c.clone(),
            -c.clone(),
        ];
        let q: Vec<BigInt> = (0..12)
            .map(|i| if i % 2 == 0 { c.clone() } else { -c.clone() })
            .collect();
        assert_eq!(mul_integers(&p, &q), schoolbook(&p, &q));
    }

    proptest! {
        #[test]
        fn agrees_with_the_schoolbook_sums(
            a in proptest::collection::vec(
                (proptest::collection::vec(any::<u32>(), 0..12), any::<bool>(), 0u32..300), 1..24),
            b in proptest::collection::vec(
                (proptest::collection::vec(any::<u32>(), 0..12), any::<bool>(), 0u32..300), 1..24),
        ) {
            let a: Vec<BigInt> = a.iter().map(|(l, s, k)| big(l, *s, *k)).collect();
            let b: Vec<BigInt> = b.iter().map(|(l, s, k)| big(l, *s, *k)).collect();
            prop_assert_eq!(mul_integers(&a, &b), schoolbook(&a, &b));
        }
    }
}
