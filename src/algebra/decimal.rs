//! Big integers in decimal, by division with a precomputed reciprocal.
//!
//! **Algorithm.** The magnitude's 64-bit limbs are divided by `D = 10¹⁹` from the top, limb by
//! limb, each remainder carried into the next; the quotient replaces the number and the last
//! remainder is the next 19 digits. Each two-limb by one-limb step uses Möller and Granlund's
//! division by an invariant integer ("Improved division by invariant integers", IEEE Trans.
//! Computers 60(2), 2011, Algorithm 4): with `v = ⌊(2¹²⁸ − 1)/D⌋ − 2⁶⁴` computed once, a quotient
//! digit costs one 64 × 64 → 128-bit product, a 64-bit product and two rare corrections, where
//! num-bigint's loop issues a hardware 128 ÷ 64-bit division per limb (tens of cycles). `D` has
//! its top bit set (10¹⁹ > 2⁶³), as the algorithm requires, so no normalising shift is needed.
//!
//! Above [`QUADRATIC_LIMIT`] limbs the number is split first, divide and conquer: `x = q·P + r`
//! with `P = D^(2^j)` about half of `x`'s chunks (the powers squared once per number), the
//! division num-bigint's (Burnikel and Ziegler's above its threshold), and each part converted
//! the same way down to the limit.
//!
//! **Identity.** With `x = q·D + r`, `0 ≤ r < D`, the digits of `x` are those of `q` followed by
//! `r` padded to 19 digits; the most significant chunk is written without padding. Likewise with
//! `x = q·P + r`, `r` padded to `2^j` chunks.
//!
//! **Cost.** `w²/2` two-by-one steps for `w` limbs up to the limit (quadratic, as num-bigint's
//! loop below its own divide-and-conquer threshold, but several times cheaper a step); above it
//! one division of `w` by `w/2` limbs and the two halves, a quarter of the quadratic work each.
//! Measured against num-bigint's `to_string` (release build, the least of five passes over 300
//! numbers each): 3.7 against 7.3 µs at 40 limbs, 7.4 against 13.5 µs at 64, 24 against 36 µs
//! at 140 (the 2 700-digit entries of an order-60 reduced observer's F), 70 against 92 µs at
//! 280 — num-bigint's own divide and conquer bottoms out in a hardware division per limb. The
//! limit of 32 limbs measured 10 % faster than 64 at 140 and 280 limbs, the same below, and 16
//! no better. A property test compares every result with num-bigint's, up to 350 limbs (three
//! levels of splitting).

use num_bigint::{BigInt, BigUint, Sign};
use num_integer::Integer;
use num_traits::Zero;

/// `10¹⁹`, the largest power of ten in a word.
const D: u64 = 10_000_000_000_000_000_000;

/// Up to this many limbs the quadratic loop; above, a split first ([`chunks_into`]).
const QUADRATIC_LIMIT: usize = 32;

/// `⌊(2¹²⁸ − 1)/D⌋ − 2⁶⁴`, the reciprocal of `D` (fits a word because `D ≥ 2⁶³`).
const RECIPROCAL: u64 = (u128::MAX / D as u128 - (1u128 << 64)) as u64;

/// `(⌊(u1·2⁶⁴ + u0)/D⌋, remainder)` for `u1 < D`.
#[inline]
fn divide_two_by_one(u1: u64, u0: u64) -> (u64, u64) {
    // (a software routine in WebAssembly, four word products there: `wide_mul`)
    let product = super::words::wide_mul(RECIPROCAL, u1);
    let sum = product.wrapping_add((u128::from(u1) << 64) | u128::from(u0));
    let (mut q1, q0) = ((sum >> 64) as u64, sum as u64);
    q1 = q1.wrapping_add(1);
    let mut r = u0.wrapping_sub(q1.wrapping_mul(D));
    if r > q0 {
        q1 = q1.wrapping_sub(1);
        r = r.wrapping_add(D);
    }
    if r >= D {
        q1 += 1;
        r -= D;
    }
    (q1, r)
}

/// `x` in decimal, as `x.to_string()` writes it: a machine word through core's formatting,
/// several times faster than num-bigint's general conversion for the small entries most
/// matrices hold, a longer number by [`long_decimal`].
pub fn decimal(x: &BigInt) -> String {
    use num_traits::ToPrimitive;
    match x.to_i64() {
        Some(v) => v.to_string(),
        None => long_decimal(x),
    }
}

/// The two digits of 0, 1, …, 99, in order.
const PAIRS: [u8; 200] = {
    let mut t = [0u8; 200];
    let mut i = 0;
    while i < 100 {
        t[2 * i] = b'0' + (i / 10) as u8;
        t[2 * i + 1] = b'0' + (i % 10) as u8;
        i += 1;
    }
    t
};

/// `x < 10⁸` as exactly 8 digits, two at a time from [`PAIRS`] in 32-bit arithmetic.
#[inline]
fn eight_digits(x: u32) -> [u8; 8] {
    let (high, low) = ((x / 10_000) as usize, (x % 10_000) as usize);
    let mut out = [0u8; 8];
    for (slot, pair) in out
        .chunks_exact_mut(2)
        .zip([high / 100, high % 100, low / 100, low % 100])
    {
        slot.copy_from_slice(&PAIRS[2 * pair..2 * pair + 2]);
    }
    out
}

/// `v < 10¹⁹` as exactly 19 digits (zero-padded), appended to `out`: split once into
/// `a·10¹⁶ + b·10⁸ + c`, the parts written by [`eight_digits`]. Core's `write!("{v:019}")`
/// took about 300 instructions a chunk through its formatting machinery, a third of the
/// conversion of the reduced-order observer's working at order 40.
fn push_chunk(out: &mut Vec<u8>, v: u64) {
    let (high, c) = (v / 100_000_000, (v % 100_000_000) as u32);
    let (a, b) = ((high / 100_000_000) as u32, (high % 100_000_000) as u32);
    out.extend_from_slice(&eight_digits(a)[5..]);
    out.extend_from_slice(&eight_digits(b));
    out.extend_from_slice(&eight_digits(c));
}

/// `x` in decimal, as `x.to_string()` writes it: its 19-digit chunks ([`chunks_into`]) written
/// out, the most significant without its leading zeros.
fn long_decimal(x: &BigInt) -> String {
    let mut chunks = Vec::new();
    chunks_into(x.magnitude(), 0, &mut Vec::new(), &mut chunks);
    while chunks.len() > 1 && chunks.last() == Some(&0) {
        chunks.pop();
    }
    let mut out: Vec<u8> = Vec::with_capacity(chunks.len() * 19 + 1);
    if x.sign() == Sign::Minus {
        out.push(b'-');
    }
    match chunks.split_last() {
        None => out.push(b'0'),
        Some((top, rest)) => {
            // the top chunk without its leading zeros
            let start = out.len();
            push_chunk(&mut out, *top);
            let zeros = out[start..]
                .iter()
                .take_while(|&&d| d == b'0')
                .count()
                .min(18);
            out.drain(start..start + zeros);
            for chunk in rest.iter().rev() {
                push_chunk(&mut out, *chunk);
            }
        }
    }
    // ASCII digits and a sign: one validation of the whole text
    String::from_utf8(out).unwrap_or_default()
}

/// Appends the 19-digit chunks of `x` to `out`, least significant first, at least `pad` of
/// them (zero chunks above the number's own). Up to [`QUADRATIC_LIMIT`] limbs by repeated
/// division by `D` ([`divide_two_by_one`]); above, `x = q·D^(2^j) + r` with `D^(2^j)` about
/// half of `x`'s chunks (`powers[j]`, squared as needed), `r` written as exactly `2^j` chunks
/// and `q` after it — the division num-bigint's own (Burnikel and Ziegler's above its
/// threshold), the two halves a quarter of the quadratic work each.
fn chunks_into(x: &BigUint, pad: usize, powers: &mut Vec<BigUint>, out: &mut Vec<u64>) {
    let start = out.len();
    let mut limbs = x.to_u64_digits();
    if limbs.len() <= QUADRATIC_LIMIT {
        while let Some(&top) = limbs.last() {
            if limbs.len() == 1 && top < D {
                out.push(top);
                break;
            }
            let mut remainder = 0;
            for limb in limbs.iter_mut().rev() {
                let (q, r) = divide_two_by_one(remainder, *limb);
                *limb = q;
                remainder = r;
            }
            out.push(remainder);
            while limbs.last() == Some(&0) {
                limbs.pop();
            }
        }
    } else {
        // about bits / log2(D) chunks; the split at the largest power of two ≤ half of them
        let chunks = (x.bits() as f64 / (D as f64).log2()) as usize;
        let j = (chunks / 2).max(1).ilog2() as usize;
        if powers.is_empty() {
            powers.push(BigUint::from(D));
        }
        while powers.len() <= j {
            let last = &powers[powers.len() - 1];
            let square = last * last;
            powers.push(square);
        }
        let (q, r) = x.div_rem(&powers[j]);
        chunks_into(&r, 1 << j, powers, out);
        if !q.is_zero() {
            chunks_into(&q, 0, powers, out);
        }
    }
    let written = out.len() - start;
    out.extend(std::iter::repeat_n(0, pad.saturating_sub(written)));
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_traits::{One, Zero};
    use proptest::prelude::*;

    #[test]
    fn edges_of_a_chunk_and_of_the_limit() {
        let ten = BigInt::from(10);
        let mut cases = vec![BigInt::zero(), BigInt::one(), -BigInt::one()];
        // the divide-and-conquer splits at D^16 … D^128 (304 … 2432 digits): runs of zero
        // chunks in the remainder, padded to the split
        for k in [
            18u32, 19, 20, 37, 38, 39, 57, 303, 304, 305, 607, 608, 609, 1216, 1233, 1234, 1300,
            2431, 2432, 2433, 4864, 5000,
        ] {
            let p = ten.pow(k);
            cases.extend([p.clone() - 1, p.clone(), p.clone() + 1, -p.clone()]);
            cases.push(&p * &p + 7);
            cases.push((&p << 1u32) * 12_345_u32 + 1);
        }
        cases.push((BigInt::one() << (64 * QUADRATIC_LIMIT as u32)) - 1);
        cases.push(BigInt::from(u64::MAX));
        for v in [i64::MIN, i64::MIN + 1, i64::MAX, -99, -100, 99, 100, 10, 9] {
            cases.push(BigInt::from(v));
        }
        for v in [u64::MAX - 1, 1 << 63, D - 1, D, D + 1] {
            cases.push(BigInt::from(v));
        }
        for x in cases {
            assert_eq!(decimal(&x), x.to_string());
            assert_eq!(long_decimal(&x), x.to_string());
        }
    }

    #[test]
    fn the_reciprocal_divides_at_the_extremes() {
        for (u1, u0) in [(0, 0), (0, u64::MAX), (D - 1, u64::MAX), (D - 1, 0), (1, 0)] {
            let u = (u128::from(u1) << 64) | u128::from(u0);
            let (q, r) = divide_two_by_one(u1, u0);
            assert_eq!(
                (u128::from(q), u128::from(r)),
                (u / u128::from(D), u % u128::from(D))
            );
        }
    }

    proptest! {
        #[test]
        fn writes_what_num_bigint_writes(
            limbs in proptest::collection::vec(any::<u32>(), 0..700),
            negative in any::<bool>(),
            u1 in 0..D,
            u0 in any::<u64>(),
        ) {
            let magnitude = num_bigint::BigUint::new(limbs);
            let sign = if negative { Sign::Minus } else { Sign::Plus };
            let x = BigInt::from_biguint(sign, magnitude);
            prop_assert_eq!(decimal(&x), x.to_string());
            assert_eq!(long_decimal(&x), x.to_string());
            let u = (u128::from(u1) << 64) | u128::from(u0);
            let (q, r) = divide_two_by_one(u1, u0);
            prop_assert_eq!((u128::from(q), u128::from(r)), (u / u128::from(D), u % u128::from(D)));
        }
    }
}
