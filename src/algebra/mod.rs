//! Number types and the small traits every algorithm of the workbench is written against.
//!
//! An algorithm is written once, over [`Ring`] (division-free: Berkowitz), [`IntegralDomain`]
//! (exact division: Bareiss) or [`Field`] (Gauss–Jordan, polynomial gcd), and runs on
//!
//! * [`BigInt`] and [`Rational`] (`BigRational`), the exact ground truth;
//! * [`Quadratic`], numbers `a + b√d` of a quadratic field Q(√d), so that √2 in Butterworth
//!   polynomials and `−2 ± √2` in the RC-ladder eigenvalues stay exact (`d = −1` gives the
//!   Gaussian rationals, so complex-conjugate poles `−1 ± 2i` are exact too);
//! * [`MultiPoly`], multivariate polynomials over named symbols (`k1`, `a`, `T`, `λ`…), so a
//!   characteristic polynomial with a symbolic gain is computed, not typed;
//! * `f64`, the float path that is always checked against the exact one.
//!
//! Exactness is a property of the type ([`Ring::EXACT`]); tolerances never appear in exact code.

pub mod budget;
pub(crate) mod decimal;
pub mod float_text;
mod fraction;
pub(crate) mod gcd;
mod multigcd;
mod multivariate;
mod quadratic;
mod scalars;
pub(crate) mod words;

pub use fraction::Fraction;
pub use gcd::{fraction, gcd, lcm_of_denominators, small_ratio};
pub use multigcd::{normalised, normalising_factor, poly_gcd};
pub(crate) use multivariate::latex_symbol;
pub use multivariate::{DivisionTooCostly, FloatPoly, Monomial, MultiPoly};
pub use num_bigint::BigInt;
pub use quadratic::{Quadratic, QuadraticError};
pub(crate) use scalars::{input_of_parts, latex_of_parts, words_to_f64};
pub use scalars::{rational_to_f64, Rational};

pub use num_traits::{One, Zero};
use std::fmt::{Debug, Display};
use std::ops::{Add, Mul, Neg, Sub};

/// A commutative ring with one (`zero`, `one`, `is_zero` come from num-traits).
///
/// The operators take their operands by value; algorithms clone where they must.
pub trait Ring:
    'static
    + Clone
    + PartialEq
    + Debug
    + Display
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Neg<Output = Self>
    + Zero
    + One
{
    /// `true` when arithmetic is exact (everything but `f64`).
    const EXACT: bool = true;
    /// The image of an integer.
    fn from_i64(n: i64) -> Self;
    /// How attractive `self` is as an elimination pivot: larger is better, 0 means unusable.
    ///
    /// Exact types prefer small entries (to keep numbers short); `f64` prefers large ones
    /// (partial pivoting).
    fn pivot_weight(&self) -> f64 {
        if self.is_zero() {
            0.0
        } else {
            1.0
        }
    }
    /// `self` rendered in LaTeX.
    fn to_latex(&self) -> String;
    /// `self` in the workbench's input syntax (`-7/3`, `2*sqrt(2) - 4`), so that parsing it
    /// gives `self` back.
    fn to_input(&self) -> String;
    /// `[Display, LaTeX, input]` at once: a type whose three share their work (a rational's
    /// decimal digits) draws it once — a polynomial's coefficients are shown in all three in
    /// every step.
    fn renderings(&self) -> [String; 3] {
        [self.to_string(), self.to_latex(), self.to_input()]
    }
}

/// A ring without zero divisors, in which a division known to be exact can be carried out.
pub trait IntegralDomain: Ring {
    /// `self / divisor` when `divisor` divides `self` exactly, `None` otherwise (and for a zero
    /// divisor).
    fn divide_exact(&self, divisor: &Self) -> Option<Self>;
}

/// A field: every nonzero element has an inverse.
pub trait Field: IntegralDomain {
    /// The ring the field's elements are fractions of, where elimination runs fraction-free:
    /// `BigInt` for the rationals, the field itself for `Q(√d)` and `f64`.
    type Integers: IntegralDomain;
    /// A common denominator `d` of `values`, so that every `d·v` lies in [`Field::Integers`].
    fn common_denominator(values: &[Self]) -> Self::Integers;
    /// `d·self` as an element of [`Field::Integers`], where `d` is a common denominator.
    fn scale_to_integer(&self, d: &Self::Integers) -> Self::Integers;
    /// The element `n / d` of the field.
    fn from_integer_ratio(n: Self::Integers, d: Self::Integers) -> Option<Self>;
    /// The multiplicative inverse, `None` for zero.
    fn inverse(&self) -> Option<Self>;
    /// `self / divisor`, `None` for a zero divisor.
    fn checked_div(&self, divisor: &Self) -> Option<Self> {
        divisor.inverse().map(|inv| self.clone() * inv)
    }
    /// The rational `n / d` in this field (`d ≠ 0`).
    fn from_ratio(n: i64, d: i64) -> Self {
        Self::from_i64(n)
            .checked_div(&Self::from_i64(d))
            .unwrap_or_else(Self::zero)
    }
}

/// The prime factorisation of `n ≥ 1` by trial division, as `(prime, exponent)` pairs; `None`
/// when `n` exceeds `limit` (trial division would take too long).
pub fn factor_small(n: u64, limit: u64) -> Option<Vec<(u64, u32)>> {
    if n > limit {
        return None;
    }
    let mut out = Vec::new();
    let mut rest = n;
    let mut p = 2u64;
    while p * p <= rest {
        let mut e = 0;
        while rest.is_multiple_of(p) {
            rest /= p;
            e += 1;
        }
        if e > 0 {
            out.push((p, e));
        }
        p += 1;
    }
    if rest > 1 {
        out.push((rest, 1));
    }
    Some(out)
}

/// Fields whose elements can be rounded to `f64`, so an exact result can be compared with the
/// float path.
pub trait ToF64 {
    /// The nearest `f64` (as near as the conversion can tell).
    fn to_f64(&self) -> f64;
}

/// Moves a value computed for a concrete type back into the generic type `T` (which is it): how a
/// generic algorithm hands a computation to a specialised path (the rational fraction-free path
/// of a generic matrix product) and takes the result back.
pub fn from_concrete<T: 'static, S: 'static>(value: S) -> Option<T> {
    (Box::new(value) as Box<dyn std::any::Any>)
        .downcast::<T>()
        .ok()
        .map(|b| *b)
}
