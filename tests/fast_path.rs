//! The fast user path against the generic one: the same numbers, whatever kernel computed them.
//!
//! Rational matrices take fraction-free kernels (one reduction per entry, Lehmer's gcd, integer
//! Horner, multimodular rank, determinant and solve, the achieved polynomial by a rank-one
//! update). The same matrices lifted into Q(√2) — or with symbolic entries — go through the
//! generic `Ratio` and `MultiPoly` arithmetic, so every comparison below is fast path against
//! generic path.

mod common;

use common::{rational_matrix, small_integer};
use observer_workbench::algebra::{gcd, BigInt, MultiPoly, Quadratic, Rational, Ring};
use observer_workbench::linalg::{
    berkowitz, determinant, polynomial_times_vector, rank, Matrix, MODULAR_FROM_ORDER,
};
use observer_workbench::observer::{
    design, design_with, Convention, DesiredPolynomial, Detail, GainMethod,
};
use observer_workbench::poly::Poly;
use proptest::prelude::*;
use std::collections::BTreeMap;

fn sqrt2() -> Quadratic {
    Quadratic::new(Rational::from_i64(0), Rational::from_i64(1), 2).unwrap()
}

fn lift(m: &Matrix<Rational>) -> Matrix<Quadratic> {
    m.map(|x| Quadratic::rational(x.clone()))
}

fn big(limbs: &[u64], negative: bool) -> BigInt {
    let mut v = BigInt::from(0);
    for &l in limbs {
        v = (v << 64) + l;
    }
    if negative {
        -v
    } else {
        v
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn lehmer_gcd_equals_binary_gcd(
        x in proptest::collection::vec(any::<u64>(), 0..40),
        y in proptest::collection::vec(any::<u64>(), 0..40),
        common in proptest::collection::vec(any::<u64>(), 0..6),
        (sx, sy) in (any::<bool>(), any::<bool>()),
    ) {
        use num_integer::Integer;
        let g = big(&common, false) + 1;
        let (a, b) = (big(&x, sx) * &g, big(&y, sy) * &g);
        prop_assert_eq!(gcd(&a, &b), a.gcd(&b));
    }

    /// Products, sums and P(A)·v on rationals equal the generic arithmetic in Q(√2), also when
    /// √2 enters: (A + √2 B)(C) computed generically splits into the rational products.
    #[test]
    fn fraction_free_arithmetic_equals_generic(
        (a, b, v) in (1usize..=6).prop_flat_map(|n| (rational_matrix(n, n), rational_matrix(n, n), rational_matrix(n, 2))),
        coeffs in proptest::collection::vec(small_integer(), 1..8),
    ) {
        let r2 = sqrt2();
        let mixed = lift(&a).add(&lift(&b).scale(&r2)).unwrap();
        let generic = mixed.mul(&lift(&v)).unwrap();
        let fast = lift(&a.mul(&v).unwrap()).add(&lift(&b.mul(&v).unwrap()).scale(&r2)).unwrap();
        prop_assert_eq!(generic, fast);
        prop_assert_eq!(lift(&a.sub(&b).unwrap()), lift(&a).sub(&lift(&b)).unwrap());
        let p = Poly::new(coeffs, "s");
        let pq = p.map(|x| Quadratic::rational(x.clone()));
        prop_assert_eq!(
            lift(&polynomial_times_vector(&p, &a, &v).unwrap()),
            polynomial_times_vector(&pq, &lift(&a), &lift(&v)).unwrap()
        );
    }

    /// P(A)·v with a symbolic vector v = (k1, k2, …): the fast rational path at any point equals
    /// the symbolic result evaluated there.
    #[test]
    fn polynomial_times_vector_equals_symbolic(
        a in (1usize..=5).prop_flat_map(|n| rational_matrix(n, n)),
        coeffs in proptest::collection::vec(small_integer(), 1..6),
        point in proptest::collection::vec(small_integer(), 5),
    ) {
        let n = a.rows();
        let names: Vec<String> = (1..=n).map(|i| format!("k{i}")).collect();
        let vs = Matrix::from_fn(n, 1, |i, _| MultiPoly::var(&names[i]));
        let am = a.map(|x| MultiPoly::constant(x.clone()));
        let p = Poly::new(coeffs, "s");
        let symbolic = polynomial_times_vector(&p.map(|x| MultiPoly::constant(x.clone())), &am, &vs).unwrap();
        let values: BTreeMap<String, Rational> = names.iter().cloned().zip(point.iter().cloned()).collect();
        let v = Matrix::from_fn(n, 1, |i, _| point[i].clone());
        let fast = polynomial_times_vector(&p, &a, &v).unwrap();
        for i in 0..n {
            prop_assert_eq!(symbolic.get(i, 0).evaluate(&values), Some(fast.get(i, 0).clone()));
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(16))]

    /// Every method's exact design on rationals equals the design in Q(√2) (generic kernels), and
    /// the achieved polynomial from the rank-one update equals Berkowitz's det(sI − (A − KC)).
    #[test]
    fn designs_equal_generic_designs(
        a in (2usize..=MODULAR_FROM_ORDER + 2).prop_flat_map(|n| rational_matrix(n, n)),
        t in 1i64..=4,
    ) {
        let n = a.rows();
        let c = Matrix::row_vector(a.row(0).to_vec());
        let desired = DesiredPolynomial::repeated(&Rational::new(1.into(), t.into()), n).unwrap();
        for method in GainMethod::ALL {
            let Ok(d) = design(&a, &c, &desired, method, Convention::AMinusKC) else {
                // an unobservable pair: the generic path must say so too
                prop_assert!(observer_workbench::observer::canonical_gain(&lift(&a), &lift(&c), &desired.exact.clone().unwrap()).is_err());
                continue;
            };
            let k = &d.gain.matrix;
            let observer = lift(&a).sub(&k.mul(&lift(&c)).unwrap()).unwrap();
            prop_assert_eq!(&berkowitz(&observer, "s").unwrap(), &d.achieved);
            prop_assert!(d.places_exactly());
            let summary = design_with(&a, &c, &desired, method, Convention::AMinusKC, Detail::Summary).unwrap();
            prop_assert_eq!(&summary.gain, &d.gain);
            let generic = match method {
                GainMethod::Ackermann => observer_workbench::observer::ackermann_gain(&lift(&a), &lift(&c), &desired.exact.clone().unwrap()).unwrap(),
                _ => observer_workbench::observer::canonical_gain(&lift(&a), &lift(&c), &desired.exact.clone().unwrap()).unwrap().gain,
            };
            prop_assert_eq!(k, &generic);
        }
    }

    /// Rank and determinant of large rational matrices (multimodular certificate) equal the
    /// fraction-free elimination in Q(√2).
    #[test]
    fn rank_and_determinant_equal_generic(
        (a, dependent) in (MODULAR_FROM_ORDER..MODULAR_FROM_ORDER + 3).prop_flat_map(|n| (rational_matrix(n, n), any::<bool>())),
    ) {
        let mut a = a;
        if dependent {
            // make the last row the sum of the first two: rank drops
            let n = a.rows();
            a = Matrix::from_fn(n, n, |i, j| if i == n - 1 { a.get(0, j).clone() + a.get(1, j).clone() } else { a.get(i, j).clone() });
        }
        prop_assert_eq!(rank(&a), rank(&lift(&a)));
        prop_assert_eq!(Quadratic::rational(determinant(&a).unwrap()), determinant(&lift(&a)).unwrap());
    }
}
