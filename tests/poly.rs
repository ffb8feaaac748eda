//! Properties of polynomials, factoring and rational functions.

mod common;

use common::{nonconstant_polynomial, polynomial, small_integer};
use observer_workbench::algebra::{Rational, Ring};
use observer_workbench::poly::{rational_roots, Factored, Poly, RationalFunction};
use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    #[test]
    fn gcd_divides_both_and_keeps_common_factors(p in polynomial(4), q in polynomial(4), r in nonconstant_polynomial(3)) {
        let (a, b) = (p.clone() * r.clone(), q.clone() * r.clone());
        let g = a.gcd(&b);
        prop_assume!(!g.is_zero());
        prop_assert!(g.is_monic());
        prop_assert!(a.divide_exact(&g).is_some());
        prop_assert!(b.divide_exact(&g).is_some());
        if !p.is_zero() && !q.is_zero() {
            prop_assert!(g.divide_exact(&r.monic()).is_some(), "gcd {} misses the common factor {}", g, r);
        }
    }

    #[test]
    fn euclidean_division_reconstructs(a in polynomial(6), b in nonconstant_polynomial(3)) {
        let (q, r) = a.div_rem(&b).unwrap();
        prop_assert!(r.degree().unwrap_or(0) < b.degree().unwrap());
        prop_assert_eq!(q * b + r, a);
    }

    #[test]
    fn factoring_finds_every_rational_root_with_its_multiplicity(
        roots in proptest::collection::vec(small_integer(), 1..6),
        lead in 1i64..=3,
        extra in prop::bool::ANY,
    ) {
        let mut p = Poly::from_roots(&roots, "s").scale(&Rational::from_i64(lead));
        if extra {
            // times s^2 + 2, which has no rational root
            p = p * Poly::from_descending(&[1, 0, 2].map(Rational::from_i64), "s");
        }
        let f = Factored::of(&p);
        prop_assert!(f.exhaustive);
        prop_assert_eq!(f.expand(), p.clone());
        let mut expected: Vec<(Rational, u32)> = Vec::new();
        for r in &roots {
            match expected.iter_mut().find(|(x, _)| x == r) {
                Some(e) => e.1 += 1,
                None => expected.push((r.clone(), 1)),
            }
        }
        let mut found = f.rational_roots();
        found.sort();
        expected.sort();
        prop_assert_eq!(found, expected);
        let distinct = rational_roots(&p).roots.len();
        prop_assert_eq!(distinct, f.rational_roots().len());
    }

    #[test]
    fn square_free_parts_multiply_back(roots in proptest::collection::vec(small_integer(), 1..7)) {
        let p = Poly::from_roots(&roots, "s");
        let parts = p.square_free();
        let back = parts.iter().fold(Poly::constant(Rational::from_i64(1), "s"), |acc, (f, m)| acc * f.pow(*m));
        prop_assert_eq!(back, p);
    }

    #[test]
    fn rational_function_field_identities(
        a in polynomial(3), b in nonconstant_polynomial(3),
        c in nonconstant_polynomial(2), d in nonconstant_polynomial(3),
    ) {
        let x = RationalFunction::new(a, b).unwrap();
        let y = RationalFunction::new(c, d).unwrap();
        prop_assert_eq!((x.clone() + y.clone()) - y.clone(), x.clone());
        prop_assert_eq!((x.clone() * y.clone()).checked_div(&y).unwrap(), x.clone());
        prop_assert!(x.denominator().is_monic());
        prop_assert_eq!(x.numerator().gcd(x.denominator()).degree(), Some(0));
        prop_assert_eq!(x.clone() * (y.clone() + y.clone()), x.clone() * y.clone() + x * y);
    }
}
