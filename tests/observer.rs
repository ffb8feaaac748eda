//! Properties of the design engine on random observable systems built valid by construction:
//! a companion-form pair (always observable) moved by a random unimodular-ish change of basis.

mod common;

use common::invertible_matrix;
use observer_workbench::algebra::{Rational, Ring};
use observer_workbench::canonical_form::{observer_form_di_ruscio, observer_form_stoustrup};
use observer_workbench::control::{observer_based_control, observer_gain, state_feedback};
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
        // the control layer's own design (`control --observer-poly`) is the same gain
        let desired_l = Poly::from_roots(&p.iter().map(|&x| Rational::from_i64(x)).collect::<Vec<_>>(), "s");
        prop_assert_eq!(&observer_gain(&a, &c, &desired_l).unwrap(), &l);
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

/// Every family set by a time constant is the unit polynomial with its poles scaled by 1/T
/// (coefficient of sᵏ times T^(k−n)), is Hurwitz, and is placed exactly by the gain; ITAE is
/// tabulated for orders 1 to 6 and refuses 7 by name.
#[test]
fn time_constant_families_scale_by_one_over_t_and_are_placed_exactly() {
    use observer_workbench::algebra::Field;
    use observer_workbench::observer::Family;
    use observer_workbench::poly::is_hurwitz;
    let one = Rational::from_i64(1);
    let t = Rational::new(3.into(), 7.into());
    for family in Family::ALL.iter().copied() {
        for n in 1..=6usize {
            let unit = family.polynomial(&one, n).unwrap();
            let scaled = family.polynomial(&t, n).unwrap();
            let (Some(u), Some(p)) = (unit.exact.as_ref(), scaled.exact.as_ref()) else {
                // Butterworth 4 and 6 are known in f64 only
                assert_eq!(family, Family::Butterworth, "{family} {n}");
                continue;
            };
            let t_q = observer_workbench::algebra::Quadratic::rational(t.clone());
            for k in 0..=n {
                let mut expected = u.coeff(k);
                for _ in k..n {
                    expected = expected.checked_div(&t_q).unwrap();
                }
                assert_eq!(p.coeff(k), expected, "{family} order {n}, s^{k}");
            }
            if let Some(r) = scaled.rational() {
                assert!(is_hurwitz(&r), "{family} {n}: {r}");
            }
        }
    }
    let e = Family::Itae.polynomial(&one, 7).unwrap_err();
    assert!(e.to_string().contains("orders 1 to 6"), "{e}");
}

#[test]
fn owb_gain_itae_1_places_s2_plus_1_4s_plus_1() {
    let (status, out, err) = common::owb(&[
        "gain",
        "--a",
        "[0 1; -2 -3]",
        "--c",
        "[1 0]",
        "--itae",
        "1",
        "--json",
    ]);
    assert_eq!(status, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let placed = v["observer_polynomial"].as_str().unwrap();
    let p = observer_workbench::syntax::parse_polynomial::<Rational>(placed, "s").unwrap();
    let wanted =
        observer_workbench::syntax::parse_polynomial::<Rational>("s^2 + 1.4s + 1", "s").unwrap();
    assert_eq!(p, wanted);
    assert_eq!(v["places_exactly"], true);
    assert!(v["desired"].as_str().unwrap().contains("ITAE"), "{v}");
    let (status, _, err) = common::owb(&[
        "gain",
        "--a",
        "[0 1; -2 -3]",
        "--c",
        "[1 0]",
        "--itae",
        "-1",
    ]);
    assert_eq!(status, 2);
    assert!(err.contains("in --itae"), "{err}");
}

/// A design that places a pole in the right half-plane is not accepted in silence: the text
/// warns and `--json` says `observer_stable: false` (a stable design says `true`).
#[test]
fn an_unstable_observer_is_said_to_be_unstable() {
    let (status, out, _) = common::owb(&[
        "gain",
        "--a",
        "[0 1; -2 -3]",
        "--c",
        "[1 0]",
        "--poles",
        "5, -4",
    ]);
    assert_eq!(status, 0);
    assert!(out.contains("warning: the observer is not stable"), "{out}");
    for (poles, stable) in [("5, -4", false), ("-1+2i, -1-2i", true), ("0, -1", false)] {
        let (_, out, _) = common::owb(&[
            "gain",
            "--a",
            "[0 1; -2 -3]",
            "--c",
            "[1 0]",
            "--poles",
            poles,
            "--json",
        ]);
        let v: serde_json::Value = serde_json::from_str(&out).unwrap();
        assert_eq!(v["observer_stable"], stable, "{poles}");
    }
}
