//! Dense univariate polynomials `c0 + c1 x + … + cn x^n` over a ring.

use crate::algebra::{Field, Rational, Ring};
use std::fmt;
use std::ops::{Add, Mul, Neg, Sub};

/// A polynomial in one named variable (`s`, `λ`, `z`…), coefficients in ascending order, no
/// trailing zeros (the zero polynomial has no coefficients).
///
/// # Example
/// ```
/// use observer_workbench::algebra::{Rational, Ring};
/// use observer_workbench::poly::Poly;
/// let p = Poly::from_roots(&[Rational::from_i64(-4), Rational::from_i64(-5)], "s");
/// assert_eq!(p.to_string(), "s^2 + 9s + 20");
/// assert_eq!(p.eval(&Rational::from_i64(-4)), Rational::from_i64(0));
/// ```
#[derive(Clone, PartialEq, Eq)]
pub struct Poly<R> {
    coeffs: Vec<R>,
    var: String,
}

impl<R: Ring> Poly<R> {
    /// `Some` when the coefficients are rationals: the dispatch to the fraction-free paths
    /// (the polynomial counterpart of the matrices' `linalg::as_rational`).
    pub(crate) fn as_rational(&self) -> Option<&Poly<Rational>> {
        (self as &dyn std::any::Any).downcast_ref::<Poly<Rational>>()
    }
    /// Runs `f` on the coefficients when both polynomials are rational — over `Q`, or over
    /// `Q(√d)` with every coefficient rational — and brings the result back: `None` when the
    /// coefficients are not rational (the generic algorithm runs), `Some(None)` when `f` says
    /// there is no result.
    pub(crate) fn through_rationals(
        &self,
        other: &Self,
        f: impl FnOnce(&[Rational], &[Rational]) -> Option<Vec<Rational>>,
    ) -> Option<Option<Self>> {
        use crate::algebra::Quadratic;
        use std::any::Any;
        let rationals = |p: &Self| -> Option<Vec<Rational>> {
            let any = p as &dyn Any;
            if let Some(q) = any.downcast_ref::<Poly<Rational>>() {
                return Some(q.coeffs.clone());
            }
            let q = any.downcast_ref::<Poly<Quadratic>>()?;
            q.coeffs.iter().map(|c| c.as_rational().cloned()).collect()
        };
        let (a, b) = (rationals(self)?, rationals(other)?);
        let Some(result) = f(&a, &b) else {
            return Some(None);
        };
        let back: Poly<Rational> = Poly::new(result, &self.var);
        if (self as &dyn Any).is::<Poly<Rational>>() {
            return crate::algebra::from_concrete(back).map(Some);
        }
        let quadratic = back.coeffs.into_iter().map(Quadratic::rational).collect();
        crate::algebra::from_concrete(Poly::new(quadratic, &self.var)).map(Some)
    }
    /// The gcd through one multivariate gcd when both polynomials are over the rational
    /// functions of the parameters (`super::fraction_gcd`); `None` otherwise.
    fn through_fractions(&self, other: &Self) -> Option<Self> {
        use crate::algebra::Fraction;
        use std::any::Any;
        let a = (self as &dyn Any).downcast_ref::<Poly<Fraction>>()?;
        let b = (other as &dyn Any).downcast_ref::<Poly<Fraction>>()?;
        crate::algebra::from_concrete(super::fraction_gcd::gcd_fraction(a, b)?)
    }
    /// Runs `f` on the coefficients when both polynomials are over `Q(√d)` with some coefficient
    /// irrational (the fraction-free `Z[√d]` algorithms), and brings the result back; `None`
    /// when `f` declines (another type, all rational, two fields), `Some(None)` when `f` says
    /// there is no result.
    pub(crate) fn through_quadratics(
        &self,
        other: &Self,
        f: impl FnOnce(
            &[crate::algebra::Quadratic],
            &[crate::algebra::Quadratic],
        ) -> Option<Option<Vec<crate::algebra::Quadratic>>>,
    ) -> Option<Option<Self>> {
        use crate::algebra::Quadratic;
        use std::any::Any;
        let a = (self as &dyn Any).downcast_ref::<Poly<Quadratic>>()?;
        let b = (other as &dyn Any).downcast_ref::<Poly<Quadratic>>()?;
        match f(&a.coeffs, &b.coeffs)? {
            None => Some(None),
            Some(result) => crate::algebra::from_concrete(Poly::new(result, &self.var)).map(Some),
        }
    }
    /// The polynomial with coefficients `coeffs` (ascending powers) in `var`.
    pub fn new(mut coeffs: Vec<R>, var: &str) -> Self {
        while coeffs.last().is_some_and(|c| c.is_zero()) {
            coeffs.pop();
        }
        Poly {
            coeffs,
            var: var.to_string(),
        }
    }
    /// The polynomial from coefficients in descending powers (`[1, 9, 20]` is `s^2 + 9s + 20`).
    pub fn from_descending(coeffs: &[R], var: &str) -> Self {
        Poly::new(coeffs.iter().rev().cloned().collect(), var)
    }
    /// The zero polynomial.
    pub fn zero(var: &str) -> Self {
        Poly::new(Vec::new(), var)
    }
    /// The constant `c`.
    pub fn constant(c: R, var: &str) -> Self {
        Poly::new(vec![c], var)
    }
    /// The polynomial `var`.
    pub fn x(var: &str) -> Self {
        Poly::new(vec![R::zero(), R::one()], var)
    }
    /// `c · var^k`.
    pub fn monomial(c: R, k: usize, var: &str) -> Self {
        let mut v = vec![R::zero(); k];
        v.push(c);
        Poly::new(v, var)
    }
    /// The monic polynomial `∏ (var − r)` with the given roots, repeated roots repeated.
    pub fn from_roots(roots: &[R], var: &str) -> Self {
        roots.iter().fold(Poly::constant(R::one(), var), |p, r| {
            p * Poly::new(vec![-r.clone(), R::one()], var)
        })
    }
    /// The reversal `zᵈ p(1/z)` (coefficients in the opposite order, d = the degree): its roots
    /// are the inverses of p's nonzero roots.
    pub fn reversed(&self) -> Self {
        let mut coeffs = self.coeffs.clone();
        coeffs.reverse();
        Poly::new(coeffs, &self.var)
    }

    /// The variable's name.
    pub fn var(&self) -> &str {
        &self.var
    }
    /// The same polynomial in another variable.
    pub fn with_var(mut self, var: &str) -> Self {
        self.var = var.to_string();
        self
    }
    /// Coefficients, ascending powers.
    pub fn coeffs(&self) -> &[R] {
        &self.coeffs
    }
    /// Coefficients, descending powers, leading one first.
    pub fn coeffs_descending(&self) -> Vec<R> {
        self.coeffs.iter().rev().cloned().collect()
    }
    /// The coefficient of `var^k` (zero beyond the degree).
    pub fn coeff(&self, k: usize) -> R {
        self.coeffs.get(k).cloned().unwrap_or_else(R::zero)
    }
    /// The degree; `None` for the zero polynomial.
    pub fn degree(&self) -> Option<usize> {
        self.coeffs.len().checked_sub(1)
    }
    /// Whether this is the zero polynomial.
    pub fn is_zero(&self) -> bool {
        self.coeffs.is_empty()
    }
    /// The leading coefficient (zero for the zero polynomial).
    pub fn leading(&self) -> R {
        self.coeffs.last().cloned().unwrap_or_else(R::zero)
    }
    /// Whether the leading coefficient is one.
    pub fn is_monic(&self) -> bool {
        self.leading().is_one()
    }
    /// The value at `x`, by Horner's rule.
    pub fn eval(&self, x: &R) -> R {
        self.coeffs
            .iter()
            .rev()
            .fold(R::zero(), |acc, c| acc * x.clone() + c.clone())
    }
    /// The derivative.
    pub fn derivative(&self) -> Self {
        let c = self
            .coeffs
            .iter()
            .enumerate()
            .skip(1)
            .map(|(k, c)| c.clone() * R::from_i64(k as i64))
            .collect();
        Poly::new(c, &self.var)
    }
    /// `c · self`.
    pub fn scale(&self, c: &R) -> Self {
        if c.is_one() {
            // multiplying a big rational by 1 still runs num-rational's gcds (quadratic in the
            // bits for num-bigint): found by fuzzing, an answer with a 12 000-bit coefficient
            return self.clone();
        }
        Poly::new(
            self.coeffs.iter().map(|x| x.clone() * c.clone()).collect(),
            &self.var,
        )
    }
    /// `self^k`.
    pub fn pow(&self, k: u32) -> Self {
        (0..k).fold(Poly::constant(R::one(), &self.var), |acc, _| {
            acc * self.clone()
        })
    }
    /// The polynomial with every coefficient mapped (e.g. exact to `f64`).
    pub fn map<S: Ring>(&self, f: impl Fn(&R) -> S) -> Poly<S> {
        Poly::new(self.coeffs.iter().map(f).collect(), &self.var)
    }
    /// `self(q(x))`.
    pub fn compose(&self, q: &Poly<R>) -> Self {
        self.coeffs
            .iter()
            .rev()
            .fold(Poly::zero(&self.var), |acc, c| {
                acc * q.clone() + Poly::constant(c.clone(), &self.var)
            })
    }

    /// Human-readable text, `s^2 + 9s + 20`.
    pub fn render(&self) -> String {
        self.render_with(Render::Human)
    }
    /// LaTeX, `s^{2} + 9 s + 20`.
    pub fn to_latex(&self) -> String {
        self.render_with(Render::Latex)
    }
    /// Input syntax, `s^2 + 9*s + 20`.
    pub fn to_input(&self) -> String {
        self.render_with(Render::Input)
    }

    fn render_with(&self, how: Render) -> String {
        let texts: Vec<Option<String>> = self
            .coeffs
            .iter()
            .map(|c| {
                (!c.is_zero()).then(|| match how {
                    Render::Human => c.to_string(),
                    Render::Input => c.to_input(),
                    Render::Latex => c.to_latex(),
                })
            })
            .collect();
        self.assemble(|k| texts[k].as_deref(), how)
    }

    /// `[Display, LaTeX, input]`, each coefficient's three texts drawn together
    /// ([`Ring::renderings`]: a rational's digits converted once, not three times).
    pub fn renderings(&self) -> [String; 3] {
        let texts: Vec<Option<[String; 3]>> = self
            .coeffs
            .iter()
            .map(|c| (!c.is_zero()).then(|| c.renderings()))
            .collect();
        [(0, Render::Human), (1, Render::Latex), (2, Render::Input)]
            .map(|(at, how)| self.assemble(|k| texts[k].as_ref().map(|t| t[at].as_str()), how))
    }

    /// The polynomial in the style `how` from its nonzero coefficients' texts (`None` for a
    /// zero coefficient), highest power first.
    fn assemble<'a>(&self, text: impl Fn(usize) -> Option<&'a str>, how: Render) -> String {
        if self.coeffs.is_empty() {
            return "0".into();
        }
        let var = match how {
            Render::Latex => crate::algebra::latex_symbol(&self.var),
            _ => self.var.clone(),
        };
        let mut out = String::with_capacity(8 * self.coeffs.len());
        for k in (0..self.coeffs.len()).rev() {
            let Some(text) = text(k) else {
                continue;
            };
            let (neg, body) = split_sign(text);
            let first = out.is_empty();
            if first {
                if neg {
                    out.push('-');
                }
            } else {
                out.push_str(match (neg, how) {
                    (false, _) => " + ",
                    (true, Render::Human) => " − ",
                    (true, _) => " - ",
                });
            }
            push_term(&mut out, body, &var, k, how);
        }
        out
    }
}

/// `coefficient · var^k` appended to `out` in the chosen style: a coefficient of one
/// disappears, a compound one (a sum, or a fraction outside LaTeX) is parenthesised; no
/// intermediate strings (a polynomial is rendered three times in every derivation).
fn push_term(out: &mut String, coef: &str, var: &str, k: usize, how: Render) {
    if k == 0 {
        out.push_str(coef);
        return;
    }
    if coef != "1" {
        let compound = coef.contains(' ') || (how != Render::Latex && coef.contains('/'));
        if compound {
            out.push('(');
            out.push_str(coef);
            out.push(')');
        } else {
            out.push_str(coef);
        }
        match how {
            Render::Human if !compound && coef.chars().any(|c| c.is_alphabetic() || c == '√') => {
                out.push(' ');
            }
            Render::Human => {}
            Render::Input => out.push('*'),
            Render::Latex => out.push(' '),
        }
    }
    out.push_str(var);
    if k > 1 {
        use std::fmt::Write;
        let _ = match how {
            Render::Latex => write!(out, "^{{{k}}}"),
            Render::Human | Render::Input => write!(out, "^{k}"),
        };
    }
}

#[derive(Clone, Copy, PartialEq)]
pub(crate) enum Render {
    Human,
    Input,
    Latex,
}

/// Splits a printed single-term coefficient into (negative?, magnitude). A compound coefficient
/// (`√2 − 2`) is returned whole, to be parenthesised.
pub(crate) fn split_sign(text: &str) -> (bool, &str) {
    let compound = |t: &str| t.contains(" + ") || t.contains(" − ") || t.contains(" - ");
    match text.strip_prefix('-') {
        Some(rest) if !compound(rest) => (true, rest),
        _ => (false, text),
    }
}

impl<F: Field + 'static> Poly<F> {
    /// Euclidean division: `(q, r)` with `self = q·divisor + r`, `deg r < deg divisor`; `None`
    /// for a zero divisor.
    pub fn div_rem(&self, divisor: &Self) -> Option<(Self, Self)> {
        let dd = divisor.degree()?;
        let lead_inv = divisor.leading().inverse()?;
        let mut rem = self.coeffs.clone();
        let n = self.coeffs.len();
        if n <= dd {
            return Some((Poly::zero(&self.var), self.clone()));
        }
        let mut q = vec![F::zero(); n - dd];
        for k in (0..n - dd).rev() {
            let c = rem[k + dd].clone() * lead_inv.clone();
            if !c.is_zero() {
                for (j, dc) in divisor.coeffs.iter().enumerate() {
                    rem[k + j] = rem[k + j].clone() - c.clone() * dc.clone();
                }
            }
            q[k] = c;
        }
        rem.truncate(dd);
        Some((Poly::new(q, &self.var), Poly::new(rem, &self.var)))
    }
    /// The monic multiple of `self` (zero stays zero).
    pub fn monic(&self) -> Self {
        match self.leading().inverse() {
            Some(inv) => self.scale(&inv),
            None => self.clone(),
        }
    }
    /// The monic greatest common divisor (zero only when both are zero).
    pub fn gcd(&self, other: &Self) -> Self {
        if let Some(Some(g)) =
            self.through_rationals(other, |a, b| Some(super::integer_gcd::gcd_rational(a, b)))
        {
            return g;
        }
        if let Some(Some(g)) = self.through_quadratics(other, |a, b| {
            super::quadratic_gcd::gcd_quadratic(a, b).map(Some)
        }) {
            return g;
        }
        if let Some(g) = self.through_fractions(other) {
            return g;
        }
        let (mut a, mut b) = (self.clone(), other.clone());
        while !b.is_zero() {
            let r = match a.div_rem(&b) {
                Some((_, r)) => r,
                None => break,
            };
            a = b;
            b = r;
        }
        a.monic()
    }
    /// `self / divisor` when the division leaves no remainder.
    pub fn divide_exact(&self, divisor: &Self) -> Option<Self> {
        if let Some(q) = self.through_rationals(divisor, super::integer_gcd::divide_exact_rational)
        {
            return q;
        }
        if let Some(q) =
            self.through_quadratics(divisor, super::quadratic_gcd::divide_exact_quadratic)
        {
            return q;
        }
        let (q, r) = self.div_rem(divisor)?;
        r.is_zero().then_some(q)
    }
    /// Square-free decomposition (Yun): monic square-free, pairwise coprime `(f_i, i)` with
    /// `self = lc · ∏ f_i^i`.
    ///
    /// ```
    /// use observer_workbench::algebra::{Rational, Ring};
    /// use observer_workbench::poly::Poly;
    /// let four = Rational::from_i64(-4);
    /// let p = Poly::from_roots(&[four.clone(), four.clone(), four, Rational::from_i64(1)], "s");
    /// let parts: Vec<String> = p.square_free().iter().map(|(f, m)| format!("{f}^{m}")).collect();
    /// assert_eq!(parts, ["s − 1^1", "s + 4^3"]);
    /// ```
    pub fn square_free(&self) -> Vec<(Self, u32)> {
        let mut out = Vec::new();
        if self.degree().unwrap_or(0) == 0 {
            return out;
        }
        let f = self.monic();
        let fp = f.derivative();
        let c = f.gcd(&fp);
        let mut w = f.divide_exact(&c).unwrap_or_else(|| f.clone());
        let mut y = fp.divide_exact(&c).unwrap_or_else(|| fp.clone());
        let mut z = y - w.derivative();
        let mut i = 1;
        while w.degree().unwrap_or(0) > 0 {
            let g = w.gcd(&z);
            if g.degree().unwrap_or(0) > 0 {
                out.push((g.clone(), i));
            }
            w = w.divide_exact(&g).unwrap_or_else(|| w.clone());
            y = z.divide_exact(&g).unwrap_or_else(|| z.clone());
            z = y - w.derivative();
            i += 1;
        }
        out
    }
}

/// The coefficient-wise sum (or difference) of two rational coefficient lists, each reduced by
/// Lehmer's gcd ([`crate::algebra::gcd::add`]): num-rational's `+` reduces by num-bigint's
/// binary gcd, a pass per bit — the loop updates of an order-60 `control` spent an eighth of
/// their time there. The same numbers.
fn add_rationals(a: &[Rational], b: &[Rational], negate: bool) -> Vec<Rational> {
    let zero = <Rational as num_traits::Zero>::zero();
    (0..a.len().max(b.len()))
        .map(|k| {
            let x = a.get(k).unwrap_or(&zero);
            let y = b.get(k).unwrap_or(&zero);
            if negate {
                crate::algebra::gcd::add(x, &-y)
            } else {
                crate::algebra::gcd::add(x, y)
            }
        })
        .collect()
}

impl<R: Ring> Add for Poly<R> {
    type Output = Poly<R>;
    fn add(self, rhs: Self) -> Self {
        if let Some(Some(p)) = self.through_rationals(&rhs, |a, b| Some(add_rationals(a, b, false)))
        {
            return p;
        }
        let n = self.coeffs.len().max(rhs.coeffs.len());
        let c = (0..n).map(|k| self.coeff(k) + rhs.coeff(k)).collect();
        Poly::new(c, &self.var)
    }
}

impl<R: Ring> Sub for Poly<R> {
    type Output = Poly<R>;
    fn sub(self, rhs: Self) -> Self {
        if let Some(Some(p)) = self.through_rationals(&rhs, |a, b| Some(add_rationals(a, b, true)))
        {
            return p;
        }
        let n = self.coeffs.len().max(rhs.coeffs.len());
        let c = (0..n).map(|k| self.coeff(k) - rhs.coeff(k)).collect();
        Poly::new(c, &self.var)
    }
}

impl<R: Ring> Mul for Poly<R> {
    type Output = Poly<R>;
    fn mul(self, rhs: Self) -> Self {
        if self.is_zero() || rhs.is_zero() {
            return Poly::zero(&self.var);
        }
        // integer coefficients: one product of big integers (Kronecker substitution)
        {
            use std::any::Any;
            let (x, y) = (&self as &dyn Any, &rhs as &dyn Any);
            if let (Some(x), Some(y)) = (
                x.downcast_ref::<Poly<num_bigint::BigInt>>(),
                y.downcast_ref::<Poly<num_bigint::BigInt>>(),
            ) {
                let c = super::kronecker::mul_integers(&x.coeffs, &y.coeffs);
                if let Some(p) = crate::algebra::from_concrete(Poly::new(c, &self.var)) {
                    return p;
                }
            }
        }
        // rational coefficients: fraction-free, one reduction per result coefficient
        if let Some(Some(p)) =
            self.through_rationals(&rhs, |a, b| Some(super::integer_gcd::mul_rational(a, b)))
        {
            return p;
        }
        let mut c = vec![R::zero(); self.coeffs.len() + rhs.coeffs.len() - 1];
        for (i, a) in self.coeffs.iter().enumerate() {
            if a.is_zero() {
                continue;
            }
            for (j, b) in rhs.coeffs.iter().enumerate() {
                c[i + j] = c[i + j].clone() + a.clone() * b.clone();
            }
        }
        Poly::new(c, &self.var)
    }
}

impl<R: Ring> Neg for Poly<R> {
    type Output = Poly<R>;
    fn neg(self) -> Self {
        let c = self.coeffs.into_iter().map(|x| -x).collect();
        Poly::new(c, &self.var)
    }
}

impl<R: Ring> fmt::Display for Poly<R> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.render())
    }
}

impl<R: Ring> fmt::Debug for Poly<R> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.to_input())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algebra::{Quadratic, Rational};

    fn p(c: &[i64]) -> Poly<Rational> {
        Poly::from_descending(
            &c.iter().map(|&x| Rational::from_i64(x)).collect::<Vec<_>>(),
            "s",
        )
    }

    #[test]
    fn printing_follows_the_textbook() {
        assert_eq!(p(&[1, 9, 20]).to_string(), "s^2 + 9s + 20");
        assert_eq!(p(&[1, -2, 0, -1]).to_string(), "s^3 − 2s^2 − 1");
        assert_eq!(p(&[-1, 0]).to_input(), "-s");
        assert_eq!(p(&[1, 9, 20]).to_latex(), "s^{2} + 9 s + 20");
        let third = Poly::new(
            vec![Rational::new(1.into(), 3.into()), Rational::from_i64(-7)],
            "s",
        );
        assert_eq!(third.to_string(), "-7s + 1/3");
        let half = Poly::new(
            vec![Rational::from_i64(0), Rational::new((-7).into(), 3.into())],
            "s",
        );
        assert_eq!(half.to_string(), "-(7/3)s");
        assert_eq!(half.to_input(), "-(7/3)*s");
    }

    #[test]
    fn butterworth_order_two_prints_with_sqrt2() {
        let sqrt2 = Quadratic::sqrt_of_rational(&Rational::from_i64(2)).unwrap();
        let b = Poly::new(
            vec![Quadratic::from_i64(1), sqrt2, Quadratic::from_i64(1)],
            "s",
        );
        assert_eq!(b.to_string(), "s^2 + √2 s + 1");
        let shifted = Poly::new(
            vec![Quadratic::from_i64(1), Quadratic::from_i64(-2) + b.coeff(1)],
            "s",
        );
        assert_eq!(shifted.to_string(), "(√2 − 2)s + 1");
    }

    #[test]
    fn division_and_gcd() {
        let a = p(&[1, 9, 20]);
        let b = p(&[1, 3, -4]);
        assert_eq!(a.gcd(&b), p(&[1, 4]));
        let (q, r) = a.div_rem(&p(&[1, 4])).unwrap();
        assert_eq!((q, r), (p(&[1, 5]), p(&[])));
        assert!(a.div_rem(&p(&[])).is_none());
    }
}
