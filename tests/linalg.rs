//! Properties of the exact linear algebra on small-integer matrices valid by construction.

mod common;

use common::{invertible_matrix, rational_matrix, square_matrix};
use observer_workbench::algebra::{MultiPoly, One, Rational, Zero};
use observer_workbench::linalg::{
    berkowitz, characteristic_polynomial, determinant, elimination::determinant_in_domain, float,
    inverse, matrix_polynomial, null_space, polynomial_times_vector, rank, solve, Matrix,
};
use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn cayley_hamilton_holds_exactly(a in square_matrix(6)) {
        let p = characteristic_polynomial(&a, "s").unwrap();
        prop_assert_eq!(p.degree(), Some(a.rows()));
        prop_assert!(matrix_polynomial(&p, &a).unwrap().is_zero());
    }

    #[test]
    fn determinant_is_multiplicative((a, b) in (1usize..=5).prop_flat_map(|n| (rational_matrix(n, n), rational_matrix(n, n)))) {
        let ab = a.mul(&b).unwrap();
        prop_assert_eq!(determinant(&ab).unwrap(), determinant(&a).unwrap() * determinant(&b).unwrap());
    }

    #[test]
    fn inverse_is_an_inverse(a in invertible_matrix(6)) {
        let inv = inverse(&a).unwrap();
        prop_assert_eq!(a.mul(&inv).unwrap(), Matrix::identity(a.rows()));
        prop_assert_eq!(inv.mul(&a).unwrap(), Matrix::identity(a.rows()));
    }

    #[test]
    fn solve_agrees_with_the_inverse((a, b) in invertible_matrix(5).prop_flat_map(|a| { let n = a.rows(); (Just(a), rational_matrix(n, 2)) })) {
        let x = solve(&a, &b).unwrap();
        prop_assert_eq!(a.mul(&x).unwrap(), b.clone());
        prop_assert_eq!(x, inverse(&a).unwrap().mul(&b).unwrap());
    }

    #[test]
    fn rank_plus_nullity_is_the_width(a in (1usize..=4, 1usize..=5, 1usize..=5)
        .prop_flat_map(|(k, n, m)| (rational_matrix(n, k), rational_matrix(k, m)))
        .prop_map(|(l, r)| l.mul(&r).unwrap()))
    {
        // n × k times k × m products have rank ≤ k: deficient ranks are common.
        let basis = null_space(&a);
        prop_assert_eq!(rank(&a) + basis.len(), a.cols());
        for v in &basis {
            prop_assert!(a.mul(v).unwrap().is_zero());
        }
    }

    #[test]
    fn berkowitz_equals_the_symbolic_determinant(a in square_matrix(4)) {
        let n = a.rows();
        let lambda = MultiPoly::var("λ");
        let m = Matrix::from_fn(n, n, |i, j| {
            let entry = MultiPoly::constant(a.get(i, j).clone());
            if i == j { lambda.clone() - entry } else { -entry }
        });
        let det = determinant_in_domain(&m).unwrap();
        let p = characteristic_polynomial(&a, "λ").unwrap();
        let expanded = p.coeffs().iter().enumerate().fold(MultiPoly::zero(), |acc, (k, c)| {
            acc + MultiPoly::constant(c.clone()) * (0..k).fold(MultiPoly::one(), |x, _| x * lambda.clone())
        });
        prop_assert_eq!(det, expanded.clone());
        // and Berkowitz run directly over the symbolic ring agrees as well
        let symbolic = berkowitz(&a.map(|x| MultiPoly::constant(x.clone())), "λ").unwrap();
        prop_assert_eq!(symbolic.coeffs().len(), n + 1);
        for (k, c) in symbolic.coeffs().iter().enumerate() {
            prop_assert_eq!(c.as_constant().unwrap(), p.coeff(k));
        }
    }

    #[test]
    fn horner_on_vectors_matches_the_matrix_polynomial((a, v) in square_matrix(5).prop_flat_map(|a| { let n = a.rows(); (Just(a), rational_matrix(n, 1)) }), p in common::polynomial(5)) {
        let full = matrix_polynomial(&p, &a).unwrap().mul(&v).unwrap();
        prop_assert_eq!(polynomial_times_vector(&p, &a, &v).unwrap(), full);
    }

    #[test]
    fn float_path_agrees_on_well_conditioned_input(a in invertible_matrix(5)) {
        let exact = inverse(&a).unwrap();
        let f = float::to_nalgebra(&a);
        let cond = float::condition_number(&f);
        prop_assume!(cond < 1e6);
        let finv = f.clone().try_inverse().unwrap();
        let e = float::to_nalgebra(&exact);
        let err = (finv - &e).norm() / e.norm();
        prop_assert!(err < cond * 1e-13, "relative error {err} with cond {cond}");
        let det_f = f.determinant();
        let det_e = observer_workbench::algebra::rational_to_f64(&determinant(&a).unwrap());
        prop_assert!((det_f - det_e).abs() <= 1e-9 * det_e.abs().max(1.0));
    }
}

#[test]
fn singular_inverse_is_an_error_not_a_panic() {
    let a = Matrix::<Rational>::zeros(3, 3);
    assert!(inverse(&a).is_err());
    let wide = Matrix::<Rational>::zeros(2, 3);
    assert!(characteristic_polynomial(&wide, "s").is_err());
}

/// The multimodular paths (rationals, order ≥ 8) against the generic algorithms run in Q(√2)
/// (which never take the modular path): the characteristic polynomial, solve, and the gain.
mod multimodular {
    use super::common::rational_matrix;
    use observer_workbench::algebra::{Quadratic, Rational, Ring};
    use observer_workbench::linalg::{
        characteristic_polynomial, solve, Matrix, MODULAR_FROM_ORDER,
    };
    use observer_workbench::observer::ackermann_gain;
    use observer_workbench::poly::Poly;
    use proptest::prelude::*;

    fn lift(m: &Matrix<Rational>) -> Matrix<Quadratic> {
        m.map(|x| Quadratic::rational(x.clone()))
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(12))]

        #[test]
        fn modular_agrees_with_generic(
            (a, b) in (MODULAR_FROM_ORDER..MODULAR_FROM_ORDER + 4)
                .prop_flat_map(|n| (rational_matrix(n, n), rational_matrix(n, 2))),
            roots in proptest::collection::vec(-5i64..=5, MODULAR_FROM_ORDER + 4),
        ) {
            let n = a.rows();
            let p = characteristic_polynomial(&a, "s").unwrap();
            prop_assert_eq!(p.map(|x| Quadratic::rational(x.clone())), characteristic_polynomial(&lift(&a), "s").unwrap());
            match (solve(&a, &b), solve(&lift(&a), &lift(&b))) {
                (Ok(x), Ok(y)) => prop_assert_eq!(lift(&x), y),
                (Err(e), Err(f)) => prop_assert_eq!(e, f),
                (x, y) => prop_assert!(false, "one path failed: {:?} vs {:?}", x.err(), y.err()),
            }
            let c = Matrix::row_vector(a.row(0).to_vec());
            let desired = Poly::from_roots(&roots[..n].iter().map(|&r| Rational::from_i64(r)).collect::<Vec<_>>(), "s");
            match (ackermann_gain(&a, &c, &desired), ackermann_gain(&lift(&a), &lift(&c), &desired.map(|x| Quadratic::rational(x.clone())))) {
                (Ok(k), Ok(kq)) => prop_assert_eq!(lift(&k), kq),
                (Err(_), Err(_)) => {}
                (x, y) => prop_assert!(false, "one path failed: {:?} vs {:?}", x.err(), y.err()),
            }
        }
    }
}
