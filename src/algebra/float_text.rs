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
    // the text is `int[.frac][e[-]exp]`: the value is 0.d₁d₂… × 10^point, d₁ ≠ 0
    let e_at = text
        .iter()
        .position(|&c| c == b'e' || c == b'E')
        .unwrap_or(text.len());
    let (mantissa, exponent) = text.split_at(e_at);
    let mut point = exponent.get(1..).map_or(0, small_exponent);
    let (int, frac) = match mantissa.iter().position(|&c| c == b'.') {
        Some(dot) => (&mantissa[..dot], &mantissa[dot + 1..]),
        None => (mantissa, &mantissa[mantissa.len()..]),
    };
    // the significant digits, copied whole (at most 17 of them, and zeros around)
    let mut digits = [0u8; 48];
    let count = match int.iter().position(|&c| c != b'0') {
        Some(lead) => {
            let (head, tail) = (&int[lead..], frac);
            point += head.len() as i32;
            let count = (head.len() + tail.len()).min(digits.len());
            let split = head.len().min(count);
            digits[..split].copy_from_slice(&head[..split]);
            digits[split..count].copy_from_slice(&tail[..count - split]);
            count
        }
        None => {
            let lead = frac.iter().position(|&c| c != b'0').unwrap_or(frac.len());
            point -= lead as i32;
            let significant = &frac[lead..];
            let count = significant.len().min(digits.len());
            digits[..count].copy_from_slice(&significant[..count]);
            count
        }
    };
    let count = digits[..count]
        .iter()
        .rposition(|&d| d != b'0')
        .map_or(0, |last| last + 1);
    // sign, d₁, '.', d₂…, 'e', sign, exponent
    let mut written = [0u8; 64];
    let mut at = 0;
    if negative {
        written[0] = b'-';
        at = 1;
    }
    if count == 0 {
        written[at..at + 3].copy_from_slice(b"0e0");
        at += 3;
    } else {
        written[at] = digits[0];
        at += 1;
        if count > 1 {
            written[at] = b'.';
            written[at + 1..at + count].copy_from_slice(&digits[1..count]);
            at += count;
        }
        written[at] = b'e';
        at += 1;
        let e = point - 1;
        if e < 0 {
            written[at] = b'-';
            at += 1;
        }
        let e = e.unsigned_abs();
        if e >= 100 {
            written[at] = b'0' + (e / 100) as u8;
            at += 1;
        }
        if e >= 10 {
            written[at] = b'0' + (e / 10 % 10) as u8;
            at += 1;
        }
        written[at] = b'0' + (e % 10) as u8;
        at += 1;
    }
    out.push_str(std::str::from_utf8(&written[..at]).unwrap_or_default());
}

/// A decimal exponent `[-]d…` as Żmij writes it (at most three digits; 0 for anything else).
fn small_exponent(text: &[u8]) -> i32 {
    let (sign, digits) = match text.split_first() {
        Some((b'-', rest)) => (-1, rest),
        Some((b'+', rest)) => (1, rest),
        _ => (1, text),
    };
    if digits.is_empty() || digits.len() > 4 || !digits.iter().all(u8::is_ascii_digit) {
        return 0;
    }
    sign * digits
        .iter()
        .fold(0i32, |e, &d| e * 10 + i32::from(d - b'0'))
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
