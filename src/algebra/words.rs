//! Machine-word arithmetic shared by the big-integer kernels: Lehmer's gcd (`gcd.rs`),
//! Barrett's reduction (`linalg/modular.rs`), the decimal conversion (`decimal.rs`) and the
//! Horner kernel on limbs (`linalg/limbs.rs`).

use num_traits::ops::overflowing::OverflowingAdd;
use num_traits::PrimInt;

/// The full 128-bit product of two words. Natively one instruction; WebAssembly has no such
/// instruction and its 128-bit multiplication is a general software routine (`__multi3`, a
/// sixth of the browser's time for a 60-state gain), so there it is four 32 × 32 → 64-bit
/// products — two to three times cheaper.
#[inline]
pub(crate) fn wide_mul(a: u64, b: u64) -> u128 {
    #[cfg(not(target_arch = "wasm32"))]
    {
        u128::from(a) * u128::from(b)
    }
    #[cfg(target_arch = "wasm32")]
    {
        wide_mul_by_halves(a, b)
    }
}

/// [`wide_mul`] from four 32 × 32 → 64-bit products (schoolbook on half-words).
#[cfg(any(target_arch = "wasm32", test))]
fn wide_mul_by_halves(a: u64, b: u64) -> u128 {
    let (a1, a0, b1, b0) = (a >> 32, a & 0xffff_ffff, b >> 32, b & 0xffff_ffff);
    let (low, m1, m2, high) = (a0 * b0, a1 * b0, a0 * b1, a1 * b1);
    let mid = (low >> 32) + (m1 & 0xffff_ffff) + (m2 & 0xffff_ffff);
    let top = high + (m1 >> 32) + (m2 >> 32) + (mid >> 32);
    (u128::from(top) << 64) | u128::from((mid << 32) | (low & 0xffff_ffff))
}

/// Two's complement negation of limbs in place (least significant first), for the gcd's 64-bit
/// limbs and the Horner kernel's 32-bit ones.
pub(crate) fn negate_limbs<L: PrimInt + OverflowingAdd>(x: &mut [L]) {
    let mut carry = true;
    for limb in x.iter_mut() {
        let one = if carry { L::one() } else { L::zero() };
        let (v, c) = (!*limb).overflowing_add(&one);
        *limb = v;
        carry = c;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    proptest::proptest! {
        /// The browser's product from half-words is the 128-bit product, at the extremes too.
        #[test]
        fn product_by_halves_is_the_wide_product(a in proptest::prelude::any::<u64>(), b in proptest::prelude::any::<u64>()) {
            for (x, y) in [(a, b), (u64::MAX, b), (a, u64::MAX), (u64::MAX, u64::MAX)] {
                proptest::prop_assert_eq!(wide_mul_by_halves(x, y), u128::from(x) * u128::from(y));
            }
        }

        /// Negation is two's complement: x + (−x) wraps to zero, on 32- and 64-bit limbs.
        #[test]
        fn negation_adds_to_zero(x in proptest::collection::vec(proptest::prelude::any::<u32>(), 1..6)) {
            let mut y = x.clone();
            negate_limbs(&mut y);
            let mut carry = 0u64;
            for (a, b) in x.iter().zip(&y) {
                let sum = u64::from(*a) + u64::from(*b) + carry;
                proptest::prop_assert_eq!(sum as u32, 0);
                carry = sum >> 32;
            }
        }
    }
}
