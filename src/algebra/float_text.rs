//! An `f64` in scientific notation, as `format!("{x:e}")` writes it, without core's formatting
//! machinery.
//!
//! **Algorithm.** Żmij (the crate serde_json already prints floats with) finds the shortest
//! decimal digits that read back as `x`, the nearest such string when several are as short. Its
//! text depends on the exponent (`1.5e-7`, `0.001`, `123.0`, `1e20`). In fixed notation
//! (magnitudes 10⁻⁵ to 10¹⁶) the decimal exponent k is guessed from the binary one and checked
//! against the text, and the digits are copied around the point in slices (`push_fixed`); any
//! other text, or a guess the text refutes, is read back digit by digit as a digit string and
//! a decimal exponent, leading and trailing zeros dropped (`push_parsed`). Either way it is
//! written as `d[.ddd]e[-]x`. Infinities and NaN are left to core (`inf`, `-inf`, `NaN`), and
//! so are the few numbers that may lie exactly halfway between two shortest candidates
//! (`may_tie`), where the two round the last digit differently.
//!
//! **Identity.** Core's `{:e}` without a precision writes the same shortest, nearest digits
//! (Grisu with Dragon4's fallback), so the two texts are equal but at exact ties, which go to
//! core; property tests compare them on random bit patterns, on every binary exponent of the
//! fixed notation's range with random fractions, on short decimals, every power of two and of
//! ten with its neighbours, and the edge values.
//!
//! **Cost.** Measured on the 2-core machine, 10 100 numbers like a zero-order hold's entries:
//! 46 ns a number, of which Żmij's digits take 21; reading its text back byte by byte, a branch
//! on each, took 64, and core's `{:e}` through `format!` about
//! 2 300 instructions. `zoh` at n = 100 (10 100 numbers written): 25.6 million instructions for
//! the whole process, 23.3 million with the fixed notation's slices.

use std::fmt::Write;

/// The powers 10^k for k in −6..=16 as `f64` (the negative ones rounded: a guess they mislead
/// is caught by the check of the text).
const POW10: [f64; 23] = [
    1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 1e-1, 1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10,
    1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
];

/// `x` as `format!("{x:e}")` writes it, appended to `out`.
pub fn push_exp(out: &mut String, x: f64) {
    if !x.is_finite() || may_tie(x) {
        let _ = write!(out, "{x:e}");
        return;
    }
    let mut buffer = zmij::Buffer::new();
    let text = buffer.format_finite(x);
    if !push_fixed(out, x, text) {
        push_parsed(out, text.as_bytes());
    }
}

/// Żmij's fixed notation (`123.45`, `0.00123`: magnitudes from 10⁻⁵ to below 10¹⁶) rewritten
/// without reading it digit by digit: the decimal exponent k is guessed from the binary one
/// (⌊e₂·log₁₀2⌋ by 1233/4096, then one more when the magnitude reaches 10^(k+1)) and checked
/// against the text — the point right after k + 1 digits, or `0.` and −k − 1 zeros before a
/// nonzero digit. `false`, and nothing written, when the text is not that (a rounding that
/// carried into the next power of ten, or the exponential notation).
fn push_fixed(out: &mut String, x: f64, text: &str) -> bool {
    let negative = x.is_sign_negative();
    let unsigned = if negative { &text[1..] } else { text };
    let bytes = unsigned.as_bytes();
    let m = x.abs();
    if !(1e-5..1e16).contains(&m) {
        return false;
    }
    let binary = ((m.to_bits() >> 52) as i32) - 1023;
    let mut k = (binary * 1233) >> 12;
    k += i32::from(m >= POW10[(k + 7) as usize]);
    if k >= 0 {
        // `d…d.f…f` with k + 1 digits before the point: d.d…df…f, trailing zeros dropped
        let int = (k + 1) as usize;
        if bytes.len() <= int + 1 || bytes[int] != b'.' || bytes[0] == b'0' {
            return false;
        }
        if negative {
            out.push('-');
        }
        let start = out.len();
        out.push_str(&unsigned[..1]);
        out.push('.');
        out.push_str(&unsigned[1..int]);
        out.push_str(&unsigned[int + 1..]);
        let kept = out.as_bytes()[start..]
            .iter()
            .rposition(|&c| c != b'0')
            .map_or(0, |last| last + 1);
        // a point with no digit after it goes too
        out.truncate(start + if kept == 2 { 1 } else { kept });
    } else {
        // `0.` and −k − 1 zeros, then the digits (the last one nonzero)
        let zeros = (-k - 1) as usize;
        if bytes.len() <= zeros + 2
            || !bytes.starts_with(b"0.")
            || bytes[2 + zeros] == b'0'
            || bytes[2..2 + zeros].iter().any(|&c| c != b'0')
        {
            return false;
        }
        if negative {
            out.push('-');
        }
        let digits = &unsigned[2 + zeros..];
        out.push_str(&digits[..1]);
        if digits.len() > 1 {
            out.push('.');
            out.push_str(&digits[1..]);
        }
    }
    push_exponent(out, k);
    true
}

/// `e`, a minus sign when negative, and the exponent's digits.
fn push_exponent(out: &mut String, e: i32) {
    let mut written = [b'e', b'-', b'0', b'0', b'0'];
    let u = e.unsigned_abs();
    let mut at = if e < 0 { 2 } else { 1 };
    if u >= 100 {
        written[at] = b'0' + (u / 100 % 10) as u8;
        at += 1;
    }
    if u >= 10 {
        written[at] = b'0' + (u / 10 % 10) as u8;
        at += 1;
    }
    written[at] = b'0' + (u % 10) as u8;
    at += 1;
    // ASCII a byte at a time: no validation of five bytes, no copy call
    for &b in &written[..at] {
        out.push(char::from(b));
    }
}

/// Żmij's text, any notation, read back as a digit string and a decimal exponent, leading and
/// trailing zeros dropped, and written as `d[.ddd]e[-]x`.
fn push_parsed(out: &mut String, text: &[u8]) {
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
    // sign, d₁, '.', d₂…, then the exponent
    let mut written = [0u8; 64];
    let mut at = 0;
    if negative {
        written[0] = b'-';
        at = 1;
    }
    if count == 0 {
        written[at] = b'0';
        at += 1;
    } else {
        written[at] = digits[0];
        at += 1;
        if count > 1 {
            written[at] = b'.';
            written[at + 1..at + count].copy_from_slice(&digits[1..count]);
            at += count;
        }
    }
    out.push_str(std::str::from_utf8(&written[..at]).unwrap_or_default());
    push_exponent(out, if count == 0 { 0 } else { point - 1 });
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
        fn fixed_notation_range_matches_core(
            fraction in 0u64..(1 << 52),
            binary in -19i32..=55,
            negative in any::<bool>(),
        ) {
            // every magnitude Żmij writes in fixed notation (10⁻⁵ to 10¹⁶) and a little beyond
            let bits = (u64::from(negative) << 63) | (((binary + 1023) as u64) << 52) | fraction;
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
