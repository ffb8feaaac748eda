//! Stability of a polynomial decided exactly: the Routh–Hurwitz test in rational arithmetic.
//! A continuous-time characteristic polynomial is *Hurwitz* when every root has a negative real
//! part; Routh's array answers that from the coefficients, with no root computed, so the answer
//! is exact also where floating-point roots scatter (repeated roots, roots near the axis).

use crate::algebra::{BigInt, Rational};
use crate::poly::Poly;
use num_traits::{Signed, Zero};

/// Whether every root of `p` has a strictly negative real part (Routh–Hurwitz, exact).
/// Constants are Hurwitz (no roots); the zero polynomial is not.
///
/// ```
/// use observer_workbench::algebra::{Rational, Ring};
/// use observer_workbench::poly::{is_hurwitz, Poly};
/// let p = |c: &[i64]| Poly::from_descending(&c.iter().map(|&x| Rational::from_i64(x)).collect::<Vec<_>>(), "s");
/// assert!(is_hurwitz(&p(&[1, 12, 48, 64])));   // (s + 4)^3
/// assert!(!is_hurwitz(&p(&[1, 0, 1])));        // s^2 + 1: roots on the axis
/// assert!(!is_hurwitz(&p(&[1, 1, -2])));       // (s + 2)(s − 1)
/// ```
pub fn is_hurwitz(p: &Poly<Rational>) -> bool {
    let Some(n) = p.degree() else {
        return false;
    };
    // descending coefficients on integers (times the lcm of the denominators), the leading
    // one made positive: scaling the polynomial by a nonzero constant keeps its roots
    let descending: Vec<Rational> = p.coeffs().iter().rev().cloned().collect();
    let (mut c, _) = crate::algebra::gcd::integer_numerators(&descending);
    if c[0].is_negative() {
        c.iter_mut().for_each(|x| *x = -x.clone());
    }
    // Routh's array fraction-free: row_(k+1)[j] = cur[0]·prev[j+1] − prev[0]·cur[j+1] is the
    // textbook row (prev[j+1] − prev[0]·cur[j+1]/cur[0]) times the pivot cur[0] > 0, and a row
    // scaled by a positive number leaves the rows after it unchanged (they depend on its
    // ratios) and its own first entry's sign; each row is divided by its content, so the
    // numbers stay the size of the textbook row's numerators
    let mut previous: Vec<BigInt> = c.iter().step_by(2).cloned().collect();
    let mut current: Vec<BigInt> = c.iter().skip(1).step_by(2).cloned().collect();
    for _ in 0..n {
        let Some(pivot) = current.first().cloned() else {
            return false;
        };
        if !pivot.is_positive() {
            return false;
        }
        let at = |v: &[BigInt], j: usize| v.get(j).cloned().unwrap_or_default();
        let mut next: Vec<BigInt> = (0..previous.len().saturating_sub(1).max(1))
            .map(|j| &pivot * at(&previous, j + 1) - &previous[0] * at(&current, j + 1))
            .collect();
        let content = next
            .iter()
            .fold(BigInt::zero(), |g, x| crate::algebra::gcd(&g, x));
        if !content.is_zero() && content != BigInt::from(1) {
            next.iter_mut().for_each(|x| *x = &*x / &content);
        }
        previous = std::mem::replace(&mut current, next);
        // the last row of a degree-n array is a single entry; trailing zeros are harmless
        while current.len() > 1 && current.last().is_some_and(Zero::is_zero) {
            current.pop();
        }
    }
    true
}

/// Whether every root of `p` lies strictly inside the unit circle (a stable discrete-time
/// characteristic polynomial), decided exactly: the Möbius map z = (1 + w)/(1 − w) takes the
/// open unit disc onto the open left half-plane, so `p` is Schur stable iff
/// `q(w) = (1 − w)ⁿ p((1 + w)/(1 − w))` has degree n and is Hurwitz. (A root at z = −1 is what
/// makes q lose degree; it is on the circle, so not stable.)
///
/// ```
/// use observer_workbench::algebra::{Rational, Ring};
/// use observer_workbench::poly::{is_schur, Poly};
/// let p = |c: &[(i64, i64)]| Poly::from_descending(&c.iter().map(|&(n, d)| Rational::new(n.into(), d.into())).collect::<Vec<_>>(), "z");
/// assert!(is_schur(&p(&[(1, 1), (0, 1), (0, 1)])));          // z^2: dead-beat
/// assert!(is_schur(&p(&[(1, 1), (-1, 1), (1, 4)])));         // (z − 1/2)^2
/// assert!(!is_schur(&p(&[(1, 1), (-1, 1)])));                // z − 1: on the circle
/// assert!(!is_schur(&p(&[(1, 1), (1, 1)])));                 // z + 1: on the circle
/// assert!(!is_schur(&p(&[(1, 1), (0, 1), (-9, 4)])));        // z^2 − 9/4: roots ±3/2
/// ```
pub fn is_schur(p: &Poly<Rational>) -> bool {
    let Some(n) = p.degree() else {
        return false;
    };
    // two exact shortcuts before the transform: |a_n| > Σ_(i<n) |a_i| puts every root inside
    // (Rouché's theorem on |z| = 1: dead-beat's zⁿ is decided at once), and |a_0| ≥ |a_n|
    // puts one outside or on the circle (the product of the roots' moduli is |a_0/a_n|)
    let lead = p.coeff(n).abs();
    if (0..n).fold(Rational::zero(), |acc, i| acc + p.coeff(i).abs()) < lead {
        return true;
    }
    if p.coeff(0).abs() >= lead {
        return false;
    }
    // on integers: p times the lcm of its denominators has the same roots
    let (a, _) = crate::algebra::gcd::integer_numerators(p.coeffs());
    // q(s) = Σ_k a_k (1 + s)^k (1 − s)^(n−k) by Horner's rule in (1 + s): q ← q·(1 + s) +
    // a_k (1 − s)^(n−k), with (1 − s)^j's coefficients (−1)^i C(j, i) — O(n²) integer
    // operations, no fraction reduced
    let minus_power = |j: usize| -> Vec<BigInt> {
        let mut row = Vec::with_capacity(j + 1);
        let mut binomial = BigInt::from(1);
        for i in 0..=j {
            row.push(if i % 2 == 0 {
                binomial.clone()
            } else {
                -binomial.clone()
            });
            binomial = binomial * BigInt::from(j - i) / BigInt::from(i + 1);
        }
        row
    };
    let mut q: Vec<BigInt> = vec![a[n].clone()];
    for k in (0..n).rev() {
        // q·(1 + s): coefficient i becomes q_i + q_(i−1)
        let mut next = vec![BigInt::zero(); q.len() + 1];
        for (i, x) in q.iter().enumerate() {
            next[i] += x;
            next[i + 1] += x;
        }
        if !a[k].is_zero() {
            for (i, m) in minus_power(n - k).into_iter().enumerate() {
                next[i] += &a[k] * m;
            }
        }
        q = next;
    }
    let q = Poly::new(q.into_iter().map(Rational::from_integer).collect(), p.var());
    q.degree() == Some(n) && is_hurwitz(&q)
}

/// Whether the real polynomial `u` has a root on the unit circle: `Some(true)` or
/// `Some(false)` decided exactly, `None` when it cannot be (a self-reciprocal irreducible
/// factor of degree ≥ 3). A root on the circle is a common root of `u` and its reversal
/// `u*(z) = z^d u(1/z)` (its inverse 1/λ = λ̄ is a root); the common factor's exact roots are
/// tested by |λ|² = 1, and an irreducible factor that is not self-reciprocal has none.
pub fn has_unit_circle_root(u: &Poly<Rational>) -> Option<bool> {
    if u.degree().is_none() {
        return Some(false);
    }
    let g = u.gcd(&u.reversed());
    if g.degree().unwrap_or(0) == 0 {
        return Some(false);
    }
    let roots = crate::poly::exact_roots(&g);
    let one = Rational::from_integer(1.into());
    if roots.roots.iter().any(|(l, _)| {
        if l.is_real() {
            l.clone() * l.clone() == crate::algebra::Quadratic::rational(one.clone())
        } else {
            l.norm() == one
        }
    }) {
        return Some(true);
    }
    // an irreducible factor with a root on the circle holds its inverse too: self-reciprocal
    if roots
        .unresolved
        .iter()
        .any(|(f, _)| f.reversed().monic() == f.monic())
    {
        return None;
    }
    Some(false)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algebra::Ring;

    /// Routh's array in rational arithmetic, as the textbook writes it: the oracle of the
    /// fraction-free array.
    fn routh_on_rationals(p: &Poly<Rational>) -> bool {
        let Some(n) = p.degree() else {
            return false;
        };
        // descending coefficients, leading one made positive
        let mut c: Vec<Rational> = p.coeffs().iter().rev().cloned().collect();
        if c[0] < Rational::zero() {
            c.iter_mut().for_each(|x| *x = -x.clone());
        }
        let mut previous: Vec<Rational> = c.iter().step_by(2).cloned().collect();
        let mut current: Vec<Rational> = c.iter().skip(1).step_by(2).cloned().collect();
        for _ in 0..n {
            let Some(pivot) = current.first().cloned() else {
                return false;
            };
            if pivot <= Rational::zero() {
                return false;
            }
            let at = |v: &[Rational], j: usize| v.get(j).cloned().unwrap_or_else(Rational::zero);
            let next: Vec<Rational> = (0..previous.len().saturating_sub(1).max(1))
                .map(|j| {
                    at(&previous, j + 1) - previous[0].clone() * at(&current, j + 1) / pivot.clone()
                })
                .collect();
            previous = std::mem::replace(&mut current, next);
            // the last row of a degree-n array is a single entry; trailing zeros are harmless
            while current.len() > 1 && current.last().is_some_and(|x| *x == Rational::zero()) {
                current.pop();
            }
        }
        true
    }

    proptest::proptest! {
        /// Schur stability against the factors: a real root r is inside when |r| < 1, and
        /// z² + b z + c has both roots inside exactly when |c| < 1 and |b| < 1 + c (Jury);
        /// a product is stable when every factor is.
        #[test]
        fn schur_agrees_with_the_factors(
            real in proptest::collection::vec((-5i64..6, 1i64..5), 0..4),
            pairs in proptest::collection::vec(((-7i64..8, 1i64..5), (-5i64..6, 1i64..5)), 0..3),
        ) {
            let q = |(n, d): (i64, i64)| Rational::new(n.into(), d.into());
            let one = Rational::from_i64(1);
            let mut p = Poly::new(vec![one.clone()], "z");
            let mut stable = true;
            for &r in &real {
                p = p * Poly::new(vec![-q(r), one.clone()], "z");
                stable &= q(r).abs() < one;
            }
            for &(b, c) in &pairs {
                let (b, c) = (q(b), q(c));
                p = p * Poly::new(vec![c.clone(), b.clone(), one.clone()], "z");
                stable &= c.abs() < one && b.abs() < &one + &c;
            }
            if p.degree().unwrap_or(0) > 0 {
                proptest::prop_assert_eq!(is_schur(&p), stable, "{}", p);
            }
        }

        /// The fraction-free array decides as the textbook one, on random rational
        /// coefficients (zeros and signs mixed) and on products of known factors.
        #[test]
        fn fraction_free_routh_agrees_with_the_textbook_array(
            coeffs in proptest::collection::vec((-5i64..6, 1i64..4), 1..10),
            roots in proptest::collection::vec((-6i64..3, 1i64..4), 1..9),
        ) {
            let p = Poly::new(coeffs.iter().map(|&(n, d)| Rational::new(n.into(), d.into())).collect(), "s");
            proptest::prop_assert_eq!(is_hurwitz(&p), routh_on_rationals(&p), "{}", p);
            let r: Vec<Rational> = roots.iter().map(|&(n, d)| Rational::new(n.into(), d.into())).collect();
            let q = Poly::from_roots(&r, "s");
            proptest::prop_assert_eq!(is_hurwitz(&q), routh_on_rationals(&q), "{}", q);
        }
    }

    proptest::proptest! {
        /// Against the roots themselves: a product of real roots and quadratic factors
        /// s² + b s + c is Hurwitz exactly when every real root is negative and every
        /// quadratic factor has b > 0, c > 0.
        #[test]
        fn agrees_with_the_roots(
            real in proptest::collection::vec(-6i64..6, 0..4),
            pairs in proptest::collection::vec((-4i64..5, -4i64..9), 0..3),
            lead in proptest::sample::select(vec![-3i64, -1, 1, 2]),
        ) {
            let q = Rational::from_i64;
            let mut p = Poly::constant(q(lead), "s");
            for &r in &real {
                p = p * Poly::new(vec![q(-r), q(1)], "s");
            }
            for &(b, c) in &pairs {
                p = p * Poly::new(vec![q(c), q(b), q(1)], "s");
            }
            let expected = real.iter().all(|&r| r < 0) && pairs.iter().all(|&(b, c)| b > 0 && c > 0);
            proptest::prop_assert_eq!(is_hurwitz(&p), expected, "{}", p);
        }
    }
}
