//! The gcd of two polynomials in `s` whose coefficients are rational functions of the plant's
//! parameters (`Poly<Fraction>`), by one multivariate gcd instead of Euclid's algorithm.
//!
//! **Algorithm.** Each polynomial is multiplied by the lcm of its coefficients' denominators
//! (read as one rational function in `s` and the parameters, its numerator), which makes it a
//! polynomial in `s` and the parameters over Q; the two are handed to the
//! multivariate gcd ([`crate::algebra::poly_gcd`], recursive primitive remainder sequences),
//! and the result, read again as a polynomial in `s`, is made monic. Euclid's algorithm over
//! the field of rational functions divides by remainders whose coefficients grow fast in the
//! parameters' degrees (each coefficient a fraction taken to lowest terms at every step): a
//! two-state controller with two parameters ran out of the symbolic work budget in the gcd
//! of its transfer function, which this takes in a few hundred products.
//!
//! **Cost.** The two polynomials read as rational functions (Horner's rule in lowest terms) and
//! one multivariate gcd, all charged to the work meter ([`crate::algebra::budget`]).
//!
//! **Identity.** By Gauss's lemma the gcd over Q(parameters)[s] is the multivariate gcd up to a
//! factor free of `s` (a unit there), which `monic` removes: `g` divides both, and the
//! cofactors are coprime over the rational functions. Values holding a square root `√d` are
//! left to Euclid (a multivariate gcd would take `√d` for a free symbol and could miss a
//! common factor).

use super::Poly;
use crate::algebra::{budget, poly_gcd, Fraction, MultiPoly, Zero};

/// The monic gcd of `a` and `b` (both nonzero) over the rational functions of the parameters,
/// `None` when a coefficient holds a square root, when the work meter has run out (Euclid then
/// runs, and stops at once: see [`crate::algebra::budget`]) or a division that must be exact is
/// not.
pub(crate) fn gcd_fraction(a: &Poly<Fraction>, b: &Poly<Fraction>) -> Option<Poly<Fraction>> {
    if a.is_zero()
        || b.is_zero()
        || a.coeffs()
            .iter()
            .chain(b.coeffs())
            .any(Fraction::has_radical)
    {
        return None;
    }
    let var = a.var();
    let g = poly_gcd(&cleared(a)?, &cleared(b)?);
    if budget::exhausted() {
        return None;
    }
    let coeffs = g
        .coefficients_in(var)
        .into_iter()
        .map(Fraction::of)
        .collect();
    Some(Poly::new(coeffs, var).monic())
}

/// `p` times the lcm of its coefficients' denominators (up to a factor free of s), as a
/// polynomial in `s` and the parameters: the numerator of `p` read as one rational function,
/// whose arithmetic keeps lowest terms and charges the work meter. `None` once the meter has
/// run out.
fn cleared(p: &Poly<Fraction>) -> Option<MultiPoly> {
    let s = Fraction::symbol(p.var());
    let whole = p
        .coeffs()
        .iter()
        .rev()
        .fold(Fraction::zero(), |acc, c| acc * s.clone() + c.clone());
    (!budget::exhausted()).then(|| whole.numerator().clone())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algebra::{Field, One};
    use crate::syntax::parse_polynomial;

    fn poly(text: &str) -> Poly<Fraction> {
        parse_polynomial::<Fraction>(text, "s").unwrap()
    }

    proptest::proptest! {
        /// Against Euclid's algorithm over the rational functions: a common factor with
        /// parameters in it, times cofactors with parameters in their coefficients.
        #[test]
        fn agrees_with_euclid(
            common in 0usize..4, u in 0usize..4, v in 0usize..4,
        ) {
            let (k, m) = (Fraction::symbol("k"), Fraction::symbol("m"));
            let (one, zero) = (Fraction::one(), Fraction::zero());
            let p = |coeffs: Vec<Fraction>| Poly::new(coeffs, "s");
            // s + k, k s + m, s² + k m, 1
            let factors = [
                p(vec![k.clone(), one.clone()]),
                p(vec![m.clone(), k.clone()]),
                p(vec![k.clone() * m.clone(), zero.clone(), one.clone()]),
                p(vec![one.clone()]),
            ];
            // s/k + 1, m s² − k, s − m/(k + 1), k s² + s + m
            let cofactors = [
                p(vec![one.clone(), k.inverse().unwrap()]),
                p(vec![-k.clone(), zero, m.clone()]),
                p(vec![-(m.clone() * (k.clone() + one.clone()).inverse().unwrap()), one.clone()]),
                p(vec![m, one, k]),
            ];
            let g = factors[common].clone();
            let a = g.clone() * cofactors[u].clone();
            let b = g * cofactors[(u + 1 + v) % 4].clone();
            let fast = gcd_fraction(&a, &b).unwrap();
            // Euclid over the field, made monic
            let (mut x, mut y) = (a.clone(), b.clone());
            while !y.is_zero() {
                let r = x.div_rem(&y).unwrap().1;
                x = y;
                y = r;
            }
            proptest::prop_assert_eq!(&fast, &x.monic());
            proptest::prop_assert!(a.divide_exact(&fast).is_some() && b.divide_exact(&fast).is_some());
        }
    }

    #[test]
    fn a_square_root_is_left_to_euclid() {
        let a = poly("s^2 - 2");
        let b = poly("s - sqrt(2)");
        assert_eq!(gcd_fraction(&a, &b), None);
        assert_eq!(a.gcd(&b), b);
    }
}
