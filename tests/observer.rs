//! Properties of the design engine on random observable systems built valid by construction:
//! a companion-form pair (always observable) moved by a random unimodular-ish change of basis.

mod common;

use common::invertible_matrix;
use observer_workbench::algebra::{Rational, Ring};
use observer_workbench::canonical_form::{observer_form_di_ruscio, observer_form_stoustrup};
use observer_workbench::control::{observer_based_control, state_feedback};
use observer_workbench::linalg::{characteristic_polynomial, inverse, Matrix};
use observer_workbench::observability::observability_matrix;
use observer_workbench::observer::{design, Convention, DesiredPolynomial, GainMethod};
use observer_workbench::poly::Poly;
use proptest::prelude::*;

/// `(A, C)` observable: `A = S A_o S⁻¹`, `C = C_o S⁻¹` with `(A_o, C_o)` in observer form.
fn observable_pair(max_n: usize) -> impl Strategy<Value = (Matrix<Rational>, Matrix<Rational>)> {
    invertible_matrix(max_n).prop_flat_map(|s| {
        let n = s.rows();
        (Just(s), proptest::collection::vec(-9i64..=9, n)).prop_map(move |(s, coeffs)| {
            let a_o = Matrix::from_fn(n, n, |i, j| {
                if j == 0 {
                    Rational::from_i64(-coeffs[i])
                } else if j == i + 1 {
                    Rational::from_i64(1)
                } else {
                    Rational::from_i64(0)
                }
            });
            let c_o = Matrix::unit(n, 0).transpose();
            let s_inv = inverse(&s).unwrap();
            (
                s.mul(&a_o).unwrap().mul(&s_inv).unwrap(),
                c_o.mul(&s_inv).unwrap(),
            )
        })
    })
}

fn poles(n: usize) -> impl Strategy<Value = Vec<i64>> {
    proptest::collection::vec(-6i64..=-1, n)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn all_methods_agree_and_place_the_polynomial_exactly(
        ((a, c), p) in observable_pair(5).prop_flat_map(|(a, c)| { let n = a.rows(); (Just((a, c)), poles(n)) })
    ) {
        let poles: Vec<_> = p.iter().map(|&x| observer_workbench::algebra::Quadratic::from_i64(x)).collect();
        let desired = DesiredPolynomial::from_poles(&poles).unwrap();
        let gains: Vec<_> = GainMethod::ALL
            .iter()
            .map(|&m| design(&a, &c, &desired, m, Convention::AMinusKC).unwrap())
            .collect();
        for d in &gains {
            prop_assert!(d.places_exactly(), "{} misses: {}", d.method, d.achieved);
            prop_assert_eq!(&d.gain, &gains[0].gain);
        }
        // the A + LC convention is the negative
        let l = design(&a, &c, &desired, GainMethod::Ackermann, Convention::APlusLC).unwrap();
        prop_assert_eq!(l.gain.matrix, gains[0].gain.matrix.neg());
    }

    #[test]
    fn both_canonical_procedures_give_the_canonical_form((a, c) in observable_pair(5)) {
        let n = a.rows();
        let di = observer_form_di_ruscio(&a, None, &c).unwrap();
        let st = observer_form_stoustrup(&a, None, &c).unwrap();
        prop_assert_eq!(&di.t, &st.t);
        let p = characteristic_polynomial(&a, "s").unwrap();
        for i in 0..n {
            for j in 0..n {
                let expected = if j == 0 { -p.coeff(n - 1 - i) } else if j == i + 1 { Rational::from_i64(1) } else { Rational::from_i64(0) };
                prop_assert_eq!(di.a.get(i, j), &expected);
            }
        }
        prop_assert_eq!(&di.c, &Matrix::unit(n, 0).transpose());
        // Mᵀ = (O_n^o)⁻¹ (Di Ruscio eq. (23))
        let o_o = observability_matrix(&di.a, &di.c).unwrap();
        prop_assert_eq!(di.toeplitz.transpose().mul(&o_o).unwrap(), Matrix::identity(n));
    }

    #[test]
    fn separation_principle_holds(
        ((a, c), p, q, b) in observable_pair(4).prop_flat_map(|(a, c)| {
            let n = a.rows();
            (Just((a, c)), poles(n), poles(n), proptest::collection::vec(-3i64..=3, n))
        })
    ) {
        let n = a.rows();
        let b = Matrix::column(b.iter().map(|&x| Rational::from_i64(x)).collect());
        let desired_f = Poly::from_roots(&q.iter().map(|&x| Rational::from_i64(x)).collect::<Vec<_>>(), "s");
        let Ok(f) = state_feedback(&a, &b, &desired_f) else { return Ok(()); }; // (A, b) may be uncontrollable
        let poles: Vec<_> = p.iter().map(|&x| observer_workbench::algebra::Quadratic::from_i64(x)).collect();
        let desired = DesiredPolynomial::from_poles(&poles).unwrap();
        let l = design(&a, &c, &desired, GainMethod::Ackermann, Convention::APlusLC).unwrap();
        let l = l.gain.matrix.map(|x| x.as_rational().unwrap().clone());
        let plant = observer_workbench::system::StateSpace::new(a, Some(b), c, None).unwrap();
        let r = observer_based_control(&plant, &f, &l).unwrap();
        prop_assert!(r.separation_holds);
        prop_assert_eq!(r.feedback_polynomial, desired_f);
        prop_assert_eq!(r.closed_loop_polynomial.degree(), Some(2 * n));
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]
    /// The state feedback designed on its own (by duality, every method) is the one the control
    /// layer computes, places the desired polynomial exactly, and the two conventions differ by
    /// a sign: for a controllable pair (Aᵀ, Cᵀ of an observable pair).
    #[test]
    fn feedback_by_duality_places_and_agrees(
        ((a, c), p) in observable_pair(4).prop_flat_map(|(a, c)| {
            let n = a.rows();
            (Just((a, c)), poles(n))
        })
    ) {
        use observer_workbench::feedback::{design_feedback, FeedbackConvention};
        use observer_workbench::observer::Detail;
        let (a, b) = (a.transpose(), c.transpose());
        let q: Vec<_> = p.iter().map(|&x| Rational::from_i64(x)).collect();
        let poly = Poly::from_roots(&q, "s");
        let desired = DesiredPolynomial::from_poles(
            &p.iter().map(|&x| observer_workbench::algebra::Quadratic::from_i64(x)).collect::<Vec<_>>(),
        ).unwrap();
        let f = state_feedback(&a, &b, &poly).unwrap();
        for method in [GainMethod::Ackermann, GainMethod::BassGura, GainMethod::Canonical] {
            let d = design_feedback(&a, &b, &desired, method, FeedbackConvention::UEqualsFx, Detail::Summary).unwrap();
            prop_assert!(d.places_exactly());
            prop_assert_eq!(d.gain.map(|x| x.as_rational().unwrap().clone()), f.clone());
            let k = design_feedback(&a, &b, &desired, method, FeedbackConvention::UEqualsMinusKx, Detail::Summary).unwrap();
            prop_assert_eq!(k.gain.neg(), d.gain);
        }
    }
}
