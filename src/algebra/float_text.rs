//! An `f64` in scientific notation, as `format!("{x:e}")` writes it, without core's formatting
//! machinery.
//!
//! **Algorithm.** Żmij (the crate serde_json already prints floats with) finds the shortest
//! decimal digits that read back as `x`, the nearest such string when several are as short;
//! its text (`1.5e-7`, `0.001`, `123.0`, `1e20`: the notation depends on the exponent) is read
//! back as a digit string and a decimal exponent, leading and trailing zeros dropped, and written
//! as `d[.ddd]e[-]x`. Infinities and NaN are left to core (`inf`, `-inf`, `NaN`), and so are
//! the few numbers that may lie exactly halfway between two shortest candidates (`may_tie`),
//! where the two round the last digit differently.
//!
//! **Identity.** Core's `{:e}` without a precision writes the same shortest, nearest digits
//! (Grisu with Dragon4's fallback), so the two texts are equal but at exact ties, which go to
//! core; a property test compares them on random bit patterns, short decimals, every power of
//! two and of ten with its neighbours, and the edge values.
//!
//! **Cost.** About 950 instructions a number, Żmij's digits included, where core's `{:e}`
//! through `format!` took about 2 300 (its padding logic and a growing `String`): with the
//! conversion of the rationals it reads, `zoh` at n = 100 (10 100 numbers written) went from
//! 69.4 to 53.9 million instructions for the whole process.

use std::fmt::Write;

/// `x` as `format!("{x:e}")` writes it, appended to `out`.
pub fn push_exp(out: &mut String, x: f64) {
    if !x.is_finite() || may_tie(x) {
        let _ = write!(out, "{x:e}");
        return;
    }
    let mut buffer = zmij::Buffer::new();
    let text = buffer.format_finite(x).as_bytes();
    let (negative, text) = match text.split_first() {
        Some((b'-', rest)) => (true, rest),
        _ => (false, text),
    };
    // the value is 0.d₁d₂… × 10^point, d the digits before any `e` (the point skipped)
    let mut point: i32 = 0;
    let mut seen_point = false;
    let mut digits = [0u8; 40];
    let mut count = 0;
    let mut rest = text;
    while let Some((&c, tail)) = rest.split_first() {
        match c {
            b'.' => seen_point = true,
            b'0'..=b'9' => {
                if !seen_point {
                    point += 1;
                }
                if count == 0 && c == b'0' {
                    point -= 1; // a leading zero
                } else if count < digits.len() {
                    digits[count] = c;
                    count += 1;
                }
            }
            _ => break, // `e` or `E`
        }
        rest = tail;
    }
    if let Some(exponent) = rest.get(1..) {
        point += std::str::from_utf8(exponent)
            .ok()
            .and_then(|e| e.parse::<i32>().ok())
            .unwrap_or(0);
    }
    while count > 0 && digits[count - 1] == b'0' {
        count -= 1;
    }
    // sign, d₁, '.', d₂…, 'e', sign, exponent: at most 1 + 17 + 1 + 1 + 1 + 3 bytes
    let mut written = [0u8; 64];
    let mut at = 0;
    let mut put = |b: u8| {
        written[at] = b;
        at += 1;
    };
    if negative {
        put(b'-');
    }
    if count == 0 {
        for &b in b"0e0" {
            put(b);
        }
    } else {
        put(digits[0]);
        if count > 1 {
            put(b'.');
            for &d in &digits[1..count] {
                put(d);
            }
        }
        put(b'e');
        let e = point - 1;
        if e < 0 {
            put(b'-');
        }
        let e = e.unsigned_abs();
        if e >= 100 {
            put(b'0' + (e / 100) as u8);
        }
        if e >= 10 {
            put(b'0' + (e / 10 % 10) as u8);
        }
        put(b'0' + (e % 10) as u8);
    }
    out.push_str(std::str::from_utf8(&written[..at]).unwrap_or_default());
}

/// Whether `x`'s exact decimal expansion has at most 18 significant digits after a binary
/// point: only then can it lie exactly halfway between two shortest candidates, where Żmij
/// rounds the last digit to even and core rounds it up (2⁻²⁵ = 2.98023223876953125e-8: Żmij
/// writes …312, core …313). With `x = m·2^e`, `m` odd and `e < 0`, the expansion is the
/// `m·5^(−e)` digits, which number at least 19 once `−e > 26` (5²⁷ > 10¹⁸).
fn may_tie(x: f64) -> bool {
    let bits = x.abs().to_bits();
    let (biased, fraction) = ((bits >> 52) as i32, bits & ((1 << 52) - 1));
    let (m, e) = if biased == 0 {
        (fraction, -1074)
    } else {
        (fraction | (1 << 52), biased - 1075)
    };
    if m == 0 {
        return false;
    }
    let zeros = m.trailing_zeros();
    let (m, e) = (m >> zeros, e + zeros as i32);
    (-26..0).contains(&e) && u128::from(m) * 5u128.pow(e.unsigned_abs()) < 10u128.pow(18)
}

/// `x` as `format!("{x:e}")` writes it (see [`push_exp`]).
pub fn exp(x: f64) -> String {
    let mut out = String::with_capacity(24);
    push_exp(&mut out, x);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn edge_values_match_core() {
        let mut values = vec![
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.1,
            0.5,
            10.0,
            123.0,
            1e15,
            1e16,
            1e17,
            1e-5,
            1e-7,
            1.5e-7,
            0.3,
            2.0 / 3.0,
            f64::MAX,
            f64::MIN,
            f64::MIN_POSITIVE,
            f64::EPSILON,
            5e-324,
            -5e-324,
            9007199254740993.0,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
        ];
        // every power of ten and of two in range, and their neighbours
        for k in -330..=310 {
            let p = 10f64.powi(k);
            values.extend([p, p.next_up(), p.next_down()]);
        }
        for k in -1074..=1023 {
            let p = 2f64.powi(k);
            values.extend([p, p.next_up(), p.next_down(), -p]);
        }
        for x in values {
            assert_eq!(exp(x), format!("{x:e}"), "{x:?}");
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(20_000))]
        #[test]
        fn random_bit_patterns_match_core(bits in any::<u64>()) {
            let x = f64::from_bits(bits);
            prop_assert_eq!(exp(x), format!("{x:e}"));
        }

        #[test]
        fn dyadic_fractions_match_core(m in -(1i64 << 53)..(1i64 << 53), k in 0i32..80) {
            // the numbers that can tie: m / 2^k
            let x = m as f64 / 2f64.powi(k);
            prop_assert_eq!(exp(x), format!("{x:e}"));
        }

        #[test]
        fn short_decimals_match_core(m in -999_999i64..999_999, e in -30i32..30) {
            let x = m as f64 * 10f64.powi(e);
            prop_assert_eq!(exp(x), format!("{x:e}"));
        }
    }
}
