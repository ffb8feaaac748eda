//! [`Ring`]/[`Field`] implementations for the built-in scalars: `BigInt`, `BigRational`, `f64`.

use super::{Field, IntegralDomain, Ring, ToF64};
use num_bigint::BigInt;
use num_integer::Integer;
use num_rational::BigRational;
use num_traits::{One, Signed, ToPrimitive, Zero};

/// Exact rational numbers, the workbench's ground truth.
pub type Rational = BigRational;

impl Ring for BigInt {
    fn from_i64(n: i64) -> Self {
        BigInt::from(n)
    }
    fn pivot_weight(&self) -> f64 {
        if Zero::is_zero(self) {
            0.0
        } else {
            1.0 / (1.0 + self.bits() as f64)
        }
    }
    fn to_latex(&self) -> String {
        super::decimal::decimal(self)
    }
    fn to_input(&self) -> String {
        super::decimal::decimal(self)
    }
    /// Display, LaTeX and input are the same digits.
    fn renderings(&self) -> [String; 3] {
        let digits = super::decimal::decimal(self);
        [digits.clone(), digits.clone(), digits]
    }
}

impl IntegralDomain for BigInt {
    fn divide_exact(&self, divisor: &Self) -> Option<Self> {
        if Zero::is_zero(divisor) {
            return None;
        }
        let (q, r) = self.div_rem(divisor);
        Zero::is_zero(&r).then_some(q)
    }
}

impl Ring for BigRational {
    fn from_i64(n: i64) -> Self {
        BigRational::from_integer(BigInt::from(n))
    }
    fn pivot_weight(&self) -> f64 {
        if Zero::is_zero(self) {
            0.0
        } else {
            1.0 / (1.0 + (self.numer().bits() + self.denom().bits()) as f64)
        }
    }
    fn to_latex(&self) -> String {
        latex_of_parts(
            &super::decimal::decimal(self.numer()),
            &super::decimal::decimal(self.denom()),
        )
    }
    /// As `Display` writes it (`n` or `n/d`), the digits converted by division with a
    /// precomputed reciprocal of 10¹⁹.
    fn to_input(&self) -> String {
        input_of_parts(
            super::decimal::decimal(self.numer()),
            &super::decimal::decimal(self.denom()),
        )
    }
    /// The numerator's and denominator's digits drawn once: Display writes what the input
    /// syntax does (`n` or `n/d`).
    fn renderings(&self) -> [String; 3] {
        let numer = super::decimal::decimal(self.numer());
        let denom = super::decimal::decimal(self.denom());
        let latex = latex_of_parts(&numer, &denom);
        let input = input_of_parts(numer, &denom);
        [input.clone(), latex, input]
    }
}

/// LaTeX of the rational `numer/denom` from the decimal digits of its reduced parts: `numer` for
/// an integer, `-\\frac{3}{2}` otherwise (so digits produced once can serve several renderings).
pub(crate) fn latex_of_parts(numer: &str, denom: &str) -> String {
    if denom == "1" {
        return numer.to_string();
    }
    match numer.strip_prefix('-') {
        Some(digits) => concat(&["-\\frac{", digits, "}{", denom, "}"]),
        None => concat(&["\\frac{", numer, "}{", denom, "}"]),
    }
}

/// Input syntax (and `Display`) of the rational `numer/denom` from the decimal digits of its
/// reduced parts: `numer` alone for a denominator of one.
pub(crate) fn input_of_parts(numer: String, denom: &str) -> String {
    if denom == "1" {
        numer
    } else {
        concat(&[&numer, "/", denom])
    }
}

/// The parts one after another in a string of exactly their length (`format!` grows its
/// buffer as it goes: a copy of every long entry of a matrix, each 2 700 digits at order 60).
fn concat(parts: &[&str]) -> String {
    let mut out = String::with_capacity(parts.iter().map(|p| p.len()).sum());
    for part in parts {
        out.push_str(part);
    }
    out
}

impl IntegralDomain for BigRational {
    fn divide_exact(&self, divisor: &Self) -> Option<Self> {
        self.checked_div(divisor)
    }
}

impl Field for BigRational {
    type Integers = BigInt;
    fn common_denominator(values: &[Self]) -> BigInt {
        super::lcm_of_denominators(values)
    }
    fn scale_to_integer(&self, d: &BigInt) -> BigInt {
        // d is a multiple of the denominator: divide first, the smaller product follows — and
        // neither when d is the denominator, nor a division for the integer entries most
        // matrices hold, where a division by one still cost a long division's set-up
        match (One::is_one(self.denom()), One::is_one(d)) {
            (true, true) => self.numer().clone(),
            (true, false) => self.numer() * d,
            (false, _) if self.denom() == d => self.numer().clone(),
            (false, _) => self.numer() * (d / self.denom()),
        }
    }
    fn from_integer_ratio(n: BigInt, d: BigInt) -> Option<Self> {
        (!Zero::is_zero(&d)).then(|| super::fraction(n, d))
    }
    fn inverse(&self) -> Option<Self> {
        (!Zero::is_zero(self)).then(|| self.recip())
    }
}

impl ToF64 for BigRational {
    fn to_f64(&self) -> f64 {
        rational_to_f64(self)
    }
}

/// The `f64` nearest to `n/d` when both parts are exact in `f64` (at most 2⁵³): one correctly
/// rounded division, as num-rational's own fast track does, without its copies of the two parts
/// (a `zoh` of order 100 reads 10 000), whether or not the fraction is in lowest terms. `None`
/// beyond, where the quotient of the two rounded parts would round twice.
pub(crate) fn words_to_f64(n: i64, d: i64) -> Option<f64> {
    const EXACT: u64 = 1 << f64::MANTISSA_DIGITS;
    (n.unsigned_abs() <= EXACT && d.unsigned_abs() <= EXACT).then(|| n as f64 / d as f64)
}

/// The `f64` nearest to a rational, also for numerators and denominators far beyond `f64`'s
/// range (where `numer / denom` would give `inf / inf`).
pub fn rational_to_f64(r: &BigRational) -> f64 {
    if let Some(x) = r
        .numer()
        .to_i64()
        .zip(r.denom().to_i64())
        .and_then(|(n, d)| words_to_f64(n, d))
    {
        return x;
    }
    if let Some(v) = ToPrimitive::to_f64(r).filter(|v| v.is_finite()) {
        return v;
    }
    // Scale both parts down to about 60 significant bits, keep the binary exponent apart.
    let nb = r.numer().bits() as i64;
    let db = r.denom().bits() as i64;
    let shift_n = (nb - 60).max(0);
    let shift_d = (db - 60).max(0);
    let n = ToPrimitive::to_f64(&(r.numer() >> shift_n as usize)).unwrap_or(0.0);
    let d = ToPrimitive::to_f64(&(r.denom() >> shift_d as usize)).unwrap_or(1.0);
    let exp = (shift_n - shift_d).clamp(-4000, 4000) as i32;
    (n / d) * 2f64.powi(exp.clamp(-1074, 1023))
}

impl Ring for f64 {
    const EXACT: bool = false;
    fn from_i64(n: i64) -> Self {
        n as f64
    }
    fn pivot_weight(&self) -> f64 {
        self.abs()
    }
    fn to_latex(&self) -> String {
        self.to_string()
    }
    fn to_input(&self) -> String {
        super::float_text::exp(*self)
    }
}

impl IntegralDomain for f64 {
    fn divide_exact(&self, divisor: &Self) -> Option<Self> {
        (*divisor != 0.0).then(|| self / divisor)
    }
}

impl Field for f64 {
    type Integers = f64;
    fn common_denominator(_: &[Self]) -> f64 {
        1.0
    }
    fn scale_to_integer(&self, d: &f64) -> f64 {
        self * d
    }
    fn from_integer_ratio(n: f64, d: f64) -> Option<Self> {
        (d != 0.0).then(|| n / d)
    }
    fn inverse(&self) -> Option<Self> {
        (*self != 0.0).then(|| 1.0 / self)
    }
}

impl ToF64 for f64 {
    fn to_f64(&self) -> f64 {
        *self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn huge_rationals_convert_to_f64_without_overflow() {
        let big = BigInt::from(10).pow(400);
        let r = BigRational::new(big.clone() * 3, big);
        assert!((rational_to_f64(&r) - 3.0).abs() < 1e-12);
    }

    proptest::proptest! {
        /// The fast track gives num-rational's correctly rounded conversion, bit for bit, at
        /// and around its limit of 2⁵³.
        #[test]
        fn small_rationals_convert_as_num_rational_does(
            n in -(1i64 << 54)..(1i64 << 54),
            d in 1i64..(1i64 << 54),
            near in proptest::bool::ANY,
        ) {
            let (n, d) = if near { ((1i64 << 53) - n % 3, (1i64 << 53) + d % 3) } else { (n, d) };
            let r = BigRational::new(n.into(), d.into());
            let theirs = ToPrimitive::to_f64(&r).expect("in range");
            proptest::prop_assert_eq!(rational_to_f64(&r).to_bits(), theirs.to_bits());
        }
    }

    #[test]
    fn bigint_exact_division_refuses_remainders() {
        let a = BigInt::from(12);
        assert_eq!(a.divide_exact(&BigInt::from(4)), Some(BigInt::from(3)));
        assert_eq!(a.divide_exact(&BigInt::from(5)), None);
        assert_eq!(a.divide_exact(&BigInt::from(0)), None);
    }
}
