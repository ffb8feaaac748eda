//! Exact numbers `a + b√d` of a quadratic field Q(√d).
//!
//! `d` is a squarefree integer other than 0 and 1; `d = −1` gives the Gaussian rationals, written
//! `a + bi`. A number with `b = 0` is a plain rational and mixes with any field. Mixing two
//! different fields (√2 with √3) is outside this type: the parser refuses it with an error, and
//! the arithmetic operators panic on it (an internal invariant, never reachable from user input
//! that went through [`crate::syntax`]).
//!
//! Used for Butterworth coefficients (`√2` for order 2, Di Ruscio eq. (58)) and for the RC-ladder
//! eigenvalues `−2 ± √2` (Baranowski eq. (6)).

use super::{Field, IntegralDomain, Rational, Ring, ToF64};
use num_bigint::BigInt;
use num_traits::{One, Signed, Zero};
use std::fmt;
use std::ops::{Add, Mul, Neg, Sub};

/// Why a quadratic number could not be formed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum QuadraticError {
    /// Two different square roots in one expression.
    #[error(
        "cannot mix √{first} and √{second} in one number (only one quadratic field at a time)"
    )]
    MixedFields {
        /// The field already in use.
        first: i64,
        /// The field that was added.
        second: i64,
    },
    /// The radicand is too large to find its squarefree part quickly.
    #[error("cannot take the square root of {radicand}: too large to factor")]
    RadicandTooLarge {
        /// The radicand, printed.
        radicand: String,
    },
}

/// `a + b√d` with rational `a`, `b`; `d = 0` marks a plain rational (`b = 0`).
#[derive(Clone, PartialEq, Eq, Hash)]
pub struct Quadratic {
    a: Rational,
    b: Rational,
    d: i64,
}

impl Quadratic {
    /// The rational `a` as an element of every quadratic field.
    pub fn rational(a: Rational) -> Self {
        Quadratic {
            a,
            b: Rational::zero(),
            d: 0,
        }
    }

    /// `a + b√d`. `d` must be squarefree and not 0 or 1 when `b ≠ 0`; otherwise an error is
    /// returned via [`Quadratic::sqrt_of_rational`]'s normalisation rules.
    ///
    /// # Example
    /// ```
    /// use observer_workbench::algebra::{Quadratic, Rational, Ring};
    /// let x = Quadratic::new(Rational::from_i64(-4), Rational::from_i64(2), 2).unwrap();
    /// assert_eq!(x.to_string(), "2√2 − 4");
    /// assert_eq!(x.to_input(), "2*sqrt(2) - 4");
    /// // √4 is not a quadratic field:
    /// assert!(Quadratic::new(Rational::from_i64(0), Rational::from_i64(1), 4).is_none());
    /// ```
    pub fn new(a: Rational, b: Rational, d: i64) -> Option<Self> {
        if b.is_zero() {
            return Some(Quadratic::rational(a));
        }
        if d == 0 || d == 1 || squarefree_part(d.unsigned_abs())?.1 != 1 {
            return None;
        }
        Some(Quadratic { a, b, d })
    }

    /// The exact square root of a rational, `√(p/q) = (s/q)·√(p·q / s²)`, in its quadratic field.
    ///
    /// # Errors
    /// [`QuadraticError::RadicandTooLarge`] when `p·q` does not fit 64 bits.
    pub fn sqrt_of_rational(r: &Rational) -> Result<Self, QuadraticError> {
        if r.is_zero() {
            return Ok(Quadratic::rational(Rational::zero()));
        }
        let pq: BigInt = r.numer() * r.denom();
        let too_large = || QuadraticError::RadicandTooLarge {
            radicand: r.to_string(),
        };
        let pq_i: i64 = i64::try_from(&pq).map_err(|_| too_large())?;
        let (core, square_root) = squarefree_part(pq_i.unsigned_abs()).ok_or_else(too_large)?;
        let sign: i64 = if pq_i < 0 { -1 } else { 1 };
        // √(p/q) = √(pq)/q = square_root·√(sign·core)/q
        let coeff = Rational::new(BigInt::from(square_root), r.denom().clone());
        let d = sign * core as i64;
        if d == 1 {
            Ok(Quadratic::rational(coeff))
        } else {
            Ok(Quadratic {
                a: Rational::zero(),
                b: coeff,
                d,
            })
        }
    }

    /// The imaginary unit `i = √−1`.
    pub fn imaginary_unit() -> Self {
        Quadratic {
            a: Rational::zero(),
            b: Rational::one(),
            d: -1,
        }
    }

    /// The rational part `a`.
    pub fn rational_part(&self) -> &Rational {
        &self.a
    }
    /// The coefficient `b` of `√d`.
    pub fn radical_part(&self) -> &Rational {
        &self.b
    }
    /// The radicand `d` (0 for a plain rational).
    pub fn radicand(&self) -> i64 {
        self.d
    }
    /// `Some(a)` when the number is rational.
    pub fn as_rational(&self) -> Option<&Rational> {
        self.b.is_zero().then_some(&self.a)
    }
    /// `a − b√d`, the Galois conjugate (complex conjugate for `d < 0`).
    pub fn conjugate(&self) -> Self {
        Quadratic {
            a: self.a.clone(),
            b: -self.b.clone(),
            d: self.d,
        }
    }
    /// `a² − d b²`, rational.
    pub fn norm(&self) -> Rational {
        self.a.clone() * self.a.clone()
            - Rational::from_i64(self.d) * self.b.clone() * self.b.clone()
    }
    /// Whether the number is real (`d > 0` or rational).
    pub fn is_real(&self) -> bool {
        self.d >= 0 || self.b.is_zero()
    }
    /// Whether the two numbers can be combined (same field, or one of them rational).
    pub fn compatible(&self, other: &Self) -> Result<(), QuadraticError> {
        if self.d != 0 && other.d != 0 && self.d != other.d {
            Err(QuadraticError::MixedFields {
                first: self.d,
                second: other.d,
            })
        } else {
            Ok(())
        }
    }
    /// Real and imaginary parts as `f64` (imaginary part 0 for real fields).
    pub fn to_complex_f64(&self) -> (f64, f64) {
        let a = self.a.to_f64();
        let b = self.b.to_f64();
        if self.d < 0 {
            (a, b * (-self.d as f64).sqrt())
        } else {
            (a + b * (self.d as f64).sqrt(), 0.0)
        }
    }

    fn field(&self, other: &Self) -> i64 {
        if let Err(e) = self.compatible(other) {
            panic!("{e}");
        }
        if self.d != 0 {
            self.d
        } else {
            other.d
        }
    }

    fn normalised(a: Rational, b: Rational, d: i64) -> Self {
        if b.is_zero() {
            Quadratic::rational(a)
        } else {
            Quadratic { a, b, d }
        }
    }
}

/// Splits `n = core · s²` with `core` squarefree; `None` when `n` is too large for trial division.
fn squarefree_part(n: u64) -> Option<(u64, u64)> {
    let factors = super::factor_small(n, 1 << 52)?;
    Some(factors.iter().fold((1u64, 1u64), |(core, root), &(p, e)| {
        (
            if e % 2 == 1 { core * p } else { core },
            root * p.pow(e / 2),
        )
    }))
}

// The arithmetic reduces its rational parts by Lehmer's gcd (`super::gcd::{add, mul}`), not
// num-rational's operators, whose binary gcd costs a pass per bit: a sum of polynomials with
// 12 000-bit coefficients in an answer file spent 70 % of its time there.
use super::gcd::{add as add_q, mul as mul_q};

impl Add for Quadratic {
    type Output = Quadratic;
    fn add(self, rhs: Self) -> Self {
        let d = self.field(&rhs);
        Quadratic::normalised(add_q(&self.a, &rhs.a), add_q(&self.b, &rhs.b), d)
    }
}

impl Sub for Quadratic {
    type Output = Quadratic;
    fn sub(self, rhs: Self) -> Self {
        let d = self.field(&rhs);
        Quadratic::normalised(add_q(&self.a, &-rhs.a), add_q(&self.b, &-rhs.b), d)
    }
}

impl Mul for Quadratic {
    type Output = Quadratic;
    fn mul(self, rhs: Self) -> Self {
        let d = self.field(&rhs);
        if self.b.is_zero() && rhs.b.is_zero() {
            return Quadratic::normalised(mul_q(&self.a, &rhs.a), Rational::zero(), d);
        }
        let dd = Rational::from_i64(d);
        let a = add_q(
            &mul_q(&self.a, &rhs.a),
            &mul_q(&dd, &mul_q(&self.b, &rhs.b)),
        );
        let b = add_q(&mul_q(&self.a, &rhs.b), &mul_q(&self.b, &rhs.a));
        Quadratic::normalised(a, b, d)
    }
}

impl Neg for Quadratic {
    type Output = Quadratic;
    fn neg(self) -> Self {
        Quadratic {
            a: -self.a,
            b: -self.b,
            d: self.d,
        }
    }
}

fn signed_term(out: &mut String, coeff: &Rational, body: &str, first: bool, unicode: bool) {
    let neg = coeff.is_negative();
    if first {
        if neg {
            out.push('-');
        }
    } else {
        out.push_str(match (neg, unicode) {
            (true, true) => " − ",
            (true, false) => " - ",
            (false, _) => " + ",
        });
    }
    let m = coeff.abs();
    if body.is_empty() {
        out.push_str(&m.to_input());
    } else {
        let (n, den) = (m.numer(), m.denom());
        if !n.is_one() {
            out.push_str(&super::decimal::decimal(n));
            if !unicode {
                out.push('*');
            }
        }
        out.push_str(body);
        if !den.is_one() {
            out.push('/');
            out.push_str(&super::decimal::decimal(den));
        }
    }
}

impl Quadratic {
    fn render(&self, unicode: bool) -> String {
        if self.b.is_zero() {
            // as Display writes a rational (`n` or `n/d`), the digits by the crate's conversion
            return self.a.to_input();
        }
        let body = match (self.d, unicode) {
            (-1, _) => "i".to_string(),
            (d, true) if d < 0 => format!("√({d})"),
            (d, true) => format!("√{d}"),
            (d, false) => format!("sqrt({d})"),
        };
        let mut out = String::new();
        if self.d < 0 {
            // complex numbers read a + bi
            if self.a.is_zero() {
                signed_term(&mut out, &self.b, &body, true, unicode);
            } else {
                signed_term(&mut out, &self.a, "", true, unicode);
                signed_term(&mut out, &self.b, &body, false, unicode);
            }
        } else {
            signed_term(&mut out, &self.b, &body, true, unicode);
            if !self.a.is_zero() {
                signed_term(&mut out, &self.a, "", false, unicode);
            }
        }
        out
    }
}

impl fmt::Display for Quadratic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.render(true))
    }
}

impl fmt::Debug for Quadratic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.render(false))
    }
}

impl Zero for Quadratic {
    fn zero() -> Self {
        Quadratic::rational(Rational::zero())
    }
    fn is_zero(&self) -> bool {
        self.a.is_zero() && self.b.is_zero()
    }
}

impl One for Quadratic {
    fn one() -> Self {
        Quadratic::rational(Rational::one())
    }
}

impl Ring for Quadratic {
    fn from_i64(n: i64) -> Self {
        Quadratic::rational(Rational::from_i64(n))
    }
    fn pivot_weight(&self) -> f64 {
        if self.is_zero() {
            0.0
        } else if self.b.is_zero() {
            1.0
        } else {
            0.5
        }
    }
    fn to_latex(&self) -> String {
        if self.b.is_zero() {
            return self.a.to_latex();
        }
        let root = if self.d == -1 {
            "i".to_string()
        } else {
            format!("\\sqrt{{{}}}", self.d)
        };
        let bn = self.b.numer().abs();
        let bd = self.b.denom();
        let mut radical = if bn.is_one() {
            root
        } else {
            format!("{bn}{root}")
        };
        if !bd.is_one() {
            radical = format!("\\frac{{{radical}}}{{{bd}}}");
        }
        let bsign_neg = self.b.is_negative();
        if self.d < 0 && !self.a.is_zero() {
            let op = if bsign_neg { "-" } else { "+" };
            return format!("{} {op} {radical}", self.a.to_latex());
        }
        let mut out = if bsign_neg {
            format!("-{radical}")
        } else {
            radical
        };
        if !self.a.is_zero() {
            let op = if self.a.is_negative() { "-" } else { "+" };
            out.push_str(&format!(" {op} {}", self.a.abs().to_latex()));
        }
        out
    }
    fn to_input(&self) -> String {
        self.render(false)
    }
}

impl IntegralDomain for Quadratic {
    fn divide_exact(&self, divisor: &Self) -> Option<Self> {
        self.checked_div(divisor)
    }
}

impl Field for Quadratic {
    type Integers = Quadratic;
    fn common_denominator(_: &[Self]) -> Quadratic {
        Quadratic::one()
    }
    fn scale_to_integer(&self, d: &Quadratic) -> Quadratic {
        self.clone() * d.clone()
    }
    fn from_integer_ratio(n: Quadratic, d: Quadratic) -> Option<Self> {
        n.checked_div(&d)
    }
    fn inverse(&self) -> Option<Self> {
        if self.b.is_zero() {
            // a rational: its reciprocal, without squaring it into the norm (found by
            // fuzzing: the norm of a 15 000-bit integer cost two quadratic-time gcds with 1)
            return (!self.a.is_zero()).then(|| Quadratic::rational(self.a.recip()));
        }
        let n = self.norm();
        if n.is_zero() {
            return None;
        }
        let c = self.conjugate();
        Some(Quadratic::normalised(c.a / n.clone(), c.b / n, self.d))
    }
}

impl ToF64 for Quadratic {
    fn to_f64(&self) -> f64 {
        self.to_complex_f64().0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn q(a: i64, b: i64, d: i64) -> Quadratic {
        Quadratic::new(Rational::from_i64(a), Rational::from_i64(b), d).unwrap()
    }

    #[test]
    fn sqrt_of_rationals_reduces_the_radicand() {
        let half = Rational::new(BigInt::from(1), BigInt::from(2));
        let s = Quadratic::sqrt_of_rational(&half).unwrap();
        assert_eq!(s.to_string(), "√2/2");
        assert_eq!(s.clone() * s, Quadratic::rational(half));
        let eight = Quadratic::sqrt_of_rational(&Rational::from_i64(8)).unwrap();
        assert_eq!(eight.to_input(), "2*sqrt(2)");
        let four = Quadratic::sqrt_of_rational(&Rational::from_i64(4)).unwrap();
        assert_eq!(four, Quadratic::from_i64(2));
        let minus_four = Quadratic::sqrt_of_rational(&Rational::from_i64(-4)).unwrap();
        assert_eq!(minus_four.to_string(), "2i");
    }

    #[test]
    fn rc_ladder_eigenvalues_multiply_to_a_rational() {
        // (−2 + √2)(−2 − √2) = 2
        let x = q(-2, 1, 2);
        assert_eq!(x.to_string(), "√2 − 2");
        assert_eq!(x.clone() * x.conjugate(), Quadratic::from_i64(2));
        assert_eq!(x.to_latex(), "\\sqrt{2} - 2");
    }

    #[test]
    fn complex_numbers_print_as_a_plus_bi() {
        let z = q(-1, 2, -1);
        assert_eq!(z.to_string(), "-1 + 2i");
        assert_eq!(z.conjugate().to_input(), "-1 - 2*i");
        assert_eq!(z.clone() * z.conjugate(), Quadratic::from_i64(5));
        assert_eq!(z.inverse().unwrap() * z, Quadratic::one());
    }

    #[test]
    fn mixing_fields_is_reported() {
        assert!(q(0, 1, 2).compatible(&q(0, 1, 3)).is_err());
        assert!(q(0, 1, 2).compatible(&Quadratic::from_i64(3)).is_ok());
    }
}
