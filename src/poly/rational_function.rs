//! Rational functions `n(s)/d(s)` in lowest terms with a monic denominator: transfer functions.

use super::univariate::split_sign;
use super::Poly;
use crate::algebra::Field;
use std::fmt;
use std::ops::{Add, Mul, Neg, Sub};

/// `numerator / denominator`, kept in lowest terms with a monic denominator, so that equal
/// functions have equal representations (and `==` means mathematical equality).
///
/// # Example
/// ```
/// use observer_workbench::algebra::{Rational, Ring};
/// use observer_workbench::poly::{Poly, RationalFunction};
/// let r = |v: &[i64]| Poly::from_descending(&v.iter().map(|&x| Rational::from_i64(x)).collect::<Vec<_>>(), "s");
/// // (2s + 8) / (2s^2 + 18s + 40) = 1/(s + 5)
/// let g = RationalFunction::new(r(&[2, 8]), r(&[2, 18, 40])).unwrap();
/// assert_eq!(g.to_string(), "1/(s + 5)");
/// assert!(RationalFunction::new(r(&[1]), r(&[])).is_none());
/// ```
#[derive(Clone, PartialEq, Eq)]
pub struct RationalFunction<F> {
    num: Poly<F>,
    den: Poly<F>,
}

impl<F: Field> RationalFunction<F> {
    /// `num / den` reduced; `None` when `den` is zero.
    pub fn new(num: Poly<F>, den: Poly<F>) -> Option<Self> {
        if den.is_zero() {
            return None;
        }
        let var = den.var().to_string();
        if num.is_zero() {
            return Some(RationalFunction {
                num: Poly::zero(&var),
                den: Poly::constant(F::one(), &var),
            });
        }
        if den.degree() == Some(0) {
            // a polynomial over a number: no gcd to take, one scaling (none by 1)
            let lead = den.leading().inverse()?;
            return Some(RationalFunction {
                num: num.scale(&lead).with_var(&var),
                den: Poly::constant(F::one(), &var),
            });
        }
        let g = num.gcd(&den);
        let num = num.divide_exact(&g)?;
        let den = den.divide_exact(&g)?;
        let lead = den.leading().inverse()?;
        Some(RationalFunction {
            num: num.scale(&lead).with_var(&var),
            den: den.scale(&lead),
        })
    }
    /// The polynomial `p` as `p / 1`.
    pub fn from_poly(p: Poly<F>) -> Self {
        let var = p.var().to_string();
        RationalFunction {
            num: p,
            den: Poly::constant(F::one(), &var),
        }
    }
    /// The numerator (in lowest terms).
    pub fn numerator(&self) -> &Poly<F> {
        &self.num
    }
    /// The monic denominator (in lowest terms).
    pub fn denominator(&self) -> &Poly<F> {
        &self.den
    }
    /// Whether the function is zero.
    pub fn is_zero(&self) -> bool {
        self.num.is_zero()
    }
    /// `1 / self`; `None` for zero.
    pub fn inverse(&self) -> Option<Self> {
        RationalFunction::new(self.den.clone(), self.num.clone())
    }
    /// `self / other`; `None` when `other` is zero.
    pub fn checked_div(&self, other: &Self) -> Option<Self> {
        Some(self.clone() * other.inverse()?)
    }
    /// The value at `x`; `None` at a pole.
    pub fn eval(&self, x: &F) -> Option<F> {
        self.num.eval(x).checked_div(&self.den.eval(x))
    }
    /// LaTeX, `\frac{num}{den}`.
    pub fn to_latex(&self) -> String {
        self.shown(Poly::to_latex, latex)
    }
    /// Input syntax, `(num)/(den)`.
    pub fn to_input(&self) -> String {
        self.shown(Poly::to_input, input)
    }
    fn render(&self) -> String {
        self.shown(Poly::render, human)
    }
    /// The function in one format: over a constant denominator the numerator's text alone,
    /// otherwise the two texts joined by `join`.
    fn shown(
        &self,
        text: impl Fn(&Poly<F>) -> String,
        join: fn(String, String) -> String,
    ) -> String {
        let num = text(&self.num);
        if self.den.degree() == Some(0) {
            return num;
        }
        join(num, text(&self.den))
    }
    /// `[Display, LaTeX, input]`, the numerator's and denominator's digits drawn once
    /// ([`Poly::renderings`]), joined as [`RationalFunction::to_latex`] and the others join them.
    pub fn renderings(&self) -> [String; 3] {
        let [num_text, num_latex, num_input] = self.num.renderings();
        if self.den.degree() == Some(0) {
            return [num_text, num_latex, num_input];
        }
        let [den_text, den_latex, den_input] = self.den.renderings();
        [
            human(num_text, den_text),
            latex(num_latex, den_latex),
            input(num_input, den_input),
        ]
    }
}

/// `\frac{num}{den}` from the two polynomials' LaTeX.
fn latex(num: String, den: String) -> String {
    format!("\\frac{{{num}}}{{{den}}}")
}

/// `(num)/(den)` from the two polynomials' input syntax.
fn input(num: String, den: String) -> String {
    format!("({num})/({den})")
}

/// `num/den` as text from the two polynomials' texts, each parenthesised when it is a sum.
fn human(num: String, den: String) -> String {
    let wrap = |t: String| {
        if t.contains(' ') {
            format!("({t})")
        } else {
            t
        }
    };
    // A constant numerator keeps its sign in front: -108/(s + 5).
    let (neg, body) = split_sign(&num);
    let body = body.to_string();
    format!("{}{}/{}", if neg { "-" } else { "" }, wrap(body), wrap(den))
}

impl<F: Field> Add for RationalFunction<F> {
    type Output = Self;
    fn add(self, rhs: Self) -> Self {
        let n = self.num * rhs.den.clone() + rhs.num * self.den.clone();
        let d = self.den * rhs.den;
        RationalFunction::new(n, d).expect("product of nonzero denominators is nonzero")
    }
}

impl<F: Field> Sub for RationalFunction<F> {
    type Output = Self;
    fn sub(self, rhs: Self) -> Self {
        self + (-rhs)
    }
}

impl<F: Field> Mul for RationalFunction<F> {
    type Output = Self;
    fn mul(self, rhs: Self) -> Self {
        let n = self.num * rhs.num;
        let d = self.den * rhs.den;
        RationalFunction::new(n, d).expect("product of nonzero denominators is nonzero")
    }
}

impl<F: Field> Neg for RationalFunction<F> {
    type Output = Self;
    fn neg(self) -> Self {
        RationalFunction {
            num: -self.num,
            den: self.den,
        }
    }
}

impl<F: Field> fmt::Display for RationalFunction<F> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.render())
    }
}

impl<F: Field> fmt::Debug for RationalFunction<F> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.to_input())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algebra::{Rational, Ring};

    fn r(v: &[i64]) -> Poly<Rational> {
        Poly::from_descending(
            &v.iter().map(|&x| Rational::from_i64(x)).collect::<Vec<_>>(),
            "s",
        )
    }

    #[test]
    fn sums_cancel_to_lowest_terms() {
        // 1/(s+1) − 1/(s+2) = 1/((s+1)(s+2))
        let a = RationalFunction::new(r(&[1]), r(&[1, 1])).unwrap();
        let b = RationalFunction::new(r(&[1]), r(&[1, 2])).unwrap();
        let d = a.clone() - b;
        assert_eq!(d.to_string(), "1/(s^2 + 3s + 2)");
        assert_eq!((a.clone() - a.clone()).to_string(), "0");
        assert_eq!(a.checked_div(&a).unwrap().to_string(), "1");
    }

    #[test]
    fn numerator_sign_and_monic_denominator() {
        let g = RationalFunction::new(r(&[-216, -504]), r(&[2, 30, 148])).unwrap();
        assert_eq!(g.to_string(), "(-108s − 252)/(s^2 + 15s + 74)");
        assert_eq!(g.to_input(), "(-108*s - 252)/(s^2 + 15*s + 74)");
    }
}
