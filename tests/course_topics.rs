//! The course's topics beyond the documents, property-tested against their definitions:
//! dead-beat observers are nilpotent, the current estimator has the prediction estimator's
//! polynomial, a reduced-order observer's error polynomial is the one asked for and its estimate
//! reproduces the state, a detectable design's polynomial factors into chosen and fixed poles,
//! the exact unit-circle test agrees with the roots, the exact zero-order hold with the float one.
mod common;

use common::{owb, rational_matrix, small_integer};
use observer_workbench::algebra::{rational_to_f64, Quadratic, Rational, Ring};
use observer_workbench::linalg::{self, Matrix};
use observer_workbench::observability::observability_report;
use observer_workbench::observer::detectability::detectable_design;
use observer_workbench::observer::discrete::{
    deadbeat_polynomial, discrete_observer, nilpotent_index, zero_order_hold, Estimator, Sampled,
};
use observer_workbench::observer::reduced_order::reduced_order_observer;
use observer_workbench::observer::{Convention, DesiredPolynomial, Detail, GainMethod};
use observer_workbench::poly::{is_schur, Poly};
use proptest::prelude::*;

fn observable(a: &Matrix<Rational>, c: &Matrix<Rational>) -> bool {
    observability_report(a, c).is_ok_and(|r| r.observable())
}

fn integers(v: &[i64]) -> Vec<Quadratic> {
    v.iter().map(|&x| Quadratic::from_i64(x)).collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Every pole at 0: the error matrix is nilpotent of index n (one Jordan block).
    #[test]
    fn deadbeat_error_matrix_is_nilpotent(a in rational_matrix(3, 3), c in rational_matrix(1, 3)) {
        prop_assume!(observable(&a, &c));
        let d = discrete_observer(&a, &c, &deadbeat_polynomial(3), GainMethod::Ackermann,
            Convention::AMinusKC, Estimator::Prediction, Detail::Summary).unwrap();
        prop_assert_eq!(d.nilpotent_index, Some(3));
        prop_assert_eq!(d.stable, Some(true));
    }

    /// The current estimator (L_c = A⁻¹K) has the prediction estimator's error polynomial.
    #[test]
    fn current_and_prediction_estimators_share_the_polynomial(
        a in rational_matrix(2, 2), c in rational_matrix(1, 2), p in (-3i64..=3, -3i64..=3),
    ) {
        prop_assume!(observable(&a, &c) && linalg::inverse(&a).is_ok());
        let desired = DesiredPolynomial::from_poles(&integers(&[p.0, p.1])).unwrap();
        let run = |e| discrete_observer(&a, &c, &desired, GainMethod::Ackermann,
            Convention::AMinusKC, e, Detail::Summary).unwrap();
        let (pred, cur) = (run(Estimator::Prediction), run(Estimator::Current));
        prop_assert_eq!(&pred.error_polynomial, &cur.error_polynomial);
        prop_assert_eq!(pred.error_polynomial.coeffs().to_vec(), desired.exact.clone().unwrap().coeffs().to_vec());
    }

    /// The exact unit-circle test agrees with the roots of products of known factors.
    #[test]
    fn schur_test_agrees_with_the_roots(roots in proptest::collection::vec((-7i64..=7, 1i64..=4), 1..4)) {
        let r: Vec<Rational> = roots.iter().map(|&(n, d)| Rational::new(n.into(), d.into())).collect();
        let p = Poly::from_roots(&r, "z");
        let inside = r.iter().all(|x| rational_to_f64(x).abs() < 1.0);
        prop_assert_eq!(is_schur(&p), inside, "{}", p);
    }

    /// The reduced-order observer's error polynomial is the one asked for, and its estimate
    /// is exact when the error is zero: x̂ = D_y C x + M (z₂ − L y) = x for every x.
    #[test]
    fn reduced_order_observer_reconstructs_the_state(
        a in rational_matrix(3, 3), c in rational_matrix(1, 3), x in rational_matrix(3, 1),
        p in (-4i64..=-1, -4i64..=-1),
    ) {
        prop_assume!(observable(&a, &c));
        let desired = DesiredPolynomial::from_poles(&integers(&[p.0, p.1])).unwrap();
        let r = reduced_order_observer(&a, None, &c, &desired, GainMethod::Ackermann).unwrap();
        prop_assert_eq!(r.error_polynomial.coeffs().to_vec(), desired.exact.clone().unwrap().coeffs().to_vec());
        // the F step shows the design's observer matrix: it must be F's own rendering
        let step = r.derivation.step("F").unwrap();
        prop_assert_eq!((step.text.clone(), step.latex.clone(), step.input.clone()), r.f.renderings());
        let lift = |m: &Matrix<Rational>| m.map(|v| Quadratic::rational(v.clone()));
        let y = lift(&c).mul(&lift(&x)).unwrap();
        let z2 = lift(&r.q).mul(&lift(&x)).unwrap().block(1, 3, 0, 1);
        let w = z2.sub(&r.l.mul(&y).unwrap()).unwrap();
        let estimate = r.direct.mul(&y).unwrap().add(&r.from_w.mul(&w).unwrap()).unwrap();
        prop_assert_eq!(estimate, lift(&x));
    }

    /// A nilpotent A (strictly upper triangular) is sampled exactly, and the float exponential
    /// agrees with it.
    #[test]
    fn zero_order_hold_is_exact_for_nilpotent_matrices(
        u in (small_integer(), small_integer(), small_integer()), b in rational_matrix(3, 1),
        t in 1i64..=5,
    ) {
        let z = Rational::from_i64(0);
        let a = Matrix::from_rows(vec![
            vec![z.clone(), u.0, u.1],
            vec![z.clone(), z.clone(), u.2],
            vec![z.clone(), z.clone(), z],
        ]).unwrap();
        let t = Rational::new(t.into(), 10.into());
        prop_assert!(nilpotent_index(&a.map(|x| Quadratic::rational(x.clone()))).unwrap().is_some());
        match zero_order_hold(&a, &b, &t).unwrap() {
            Sampled::Exact { phi, .. } => {
                // Φ = I + AT + (AT)²/2 agrees with nalgebra's exponential
                let f = nalgebra::DMatrix::from_fn(3, 3, |i, j| rational_to_f64(a.get(i, j)) * rational_to_f64(&t)).exp();
                for i in 0..3 { for j in 0..3 {
                    prop_assert!((f[(i, j)] - rational_to_f64(phi.get(i, j))).abs() < 1e-9);
                }}
            }
            Sampled::Float { .. } => prop_assert!(false, "a nilpotent A must be sampled exactly"),
        }
    }
}

/// An unobservable pair: the chosen poles and the fixed ones multiply to the observer
/// polynomial, and detectability follows the fixed pole's sign.
#[test]
fn detectable_designs_place_what_they_can() {
    let m = |s: &str| observer_workbench::syntax::parse_matrix::<Rational>(s).unwrap();
    let desired = DesiredPolynomial::from_poles(&integers(&[-3])).unwrap();
    for (a, stable) in [("[-1 0; 1 -1]", true), ("[-1 0; 1 2]", false)] {
        let d = detectable_design(
            &m(a),
            &m("[0 1]"),
            &desired,
            GainMethod::Ackermann,
            Convention::AMinusKC,
        );
        // measured at x₂, this pair is observable: the design needs 2 poles
        assert!(d.is_err(), "{a}");
        let d = detectable_design(
            &m(a),
            &m("[1 0]"),
            &desired,
            GainMethod::Ackermann,
            Convention::AMinusKC,
        )
        .unwrap();
        assert_eq!(d.detectable, stable, "{a}");
        assert!(d.polynomial_checks(), "{a}");
        assert_eq!(d.report.rank, 1);
    }
}

/// The new subcommands refuse bad input with exit status 2 and the flag named.
#[test]
fn course_subcommands_refuse_bad_input() {
    let cases: [(&[&str], &str); 7] = [
        (
            &[
                "discrete",
                "--a",
                "[0 1; 0 0]",
                "--c",
                "[1 0]",
                "--poles",
                "1/2, 1/2",
                "--estimator",
                "current",
            ],
            "A invertible",
        ),
        (
            &[
                "discrete",
                "--a",
                "[1 2; 3 4]",
                "--c",
                "[1 0]",
                "--poles",
                "1/2",
            ],
            "--poles",
        ),
        (
            &[
                "discrete",
                "--a",
                "[1 2; 3 4]",
                "--c",
                "[1 0]",
                "--period",
                "1",
            ],
            "--period",
        ),
        (
            &[
                "zoh",
                "--a",
                "[1 2; 3 4]",
                "--b",
                "[1; 2]",
                "--period",
                "-1",
            ],
            "positive",
        ),
        (
            &[
                "zoh",
                "--a",
                "[1 2; 3 4]",
                "--b",
                "[1; 2; 3]",
                "--period",
                "1",
            ],
            "rows",
        ),
        (
            &[
                "reduced",
                "--a",
                "[1 2; 3 4]",
                "--c",
                "[1 0; 0 1]",
                "--poles",
                "-1",
            ],
            "--poles",
        ),
        (
            &[
                "detectable",
                "--a",
                "[1 0; 0 1]",
                "--c",
                "[0 0]",
                "--poles",
                "-1",
            ],
            "no mode is observable",
        ),
    ];
    for (args, needle) in cases {
        let (code, _, err) = owb(args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
    let (code, out, _) = owb(&[
        "discrete",
        "--a",
        "[2 -3; 4 -5]",
        "--c",
        "[-3 2]",
        "--deadbeat",
        "--json",
    ]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["deadbeat_steps"], 2);
    assert_eq!(v["error_polynomial"], "z^2");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    /// The discrete Kalman filter of a random system (G = Q_n = R_n = I, which make every
    /// mode stabilisable): the P it reports satisfies the Riccati equation within the
    /// tolerance it promises — the residual recomputed here in exact arithmetic from the f64
    /// entries it returned, not read from its own report — and A − LC is stable.
    #[test]
    fn discrete_kalman_solves_its_riccati_equation(a in rational_matrix(2, 2), c in rational_matrix(1, 2)) {
        use observer_workbench::observer::discrete_kalman::{discrete_kalman, RESIDUAL_TOLERANCE};
        prop_assume!(observable(&a, &c));
        let i2 = Matrix::<Rational>::identity(2);
        let one = Matrix::<Rational>::identity(1);
        let k = discrete_kalman(&a, &i2, &c, &i2, &one).unwrap();
        let p = Matrix::from_rows(
            (0..2)
                .map(|i| (0..2).map(|j| Rational::from_float(k.p[(i, j)]).unwrap()).collect())
                .collect(),
        )
        .unwrap();
        let s_inv = linalg::inverse(&c.mul(&p).unwrap().mul(&c.transpose()).unwrap().add(&one).unwrap()).unwrap();
        let l = a.mul(&p).unwrap().mul(&c.transpose()).unwrap().mul(&s_inv).unwrap();
        let ric = a.mul(&p).unwrap().mul(&a.transpose()).unwrap()
            .sub(&l.mul(&c).unwrap().mul(&p).unwrap().mul(&a.transpose()).unwrap()).unwrap()
            .add(&i2).unwrap();
        let largest = |m: &Matrix<Rational>| {
            (0..2).flat_map(|i| (0..2).map(move |j| (i, j)))
                .map(|(i, j)| rational_to_f64(m.get(i, j)).abs())
                .fold(0.0, f64::max)
        };
        let exact_residual = largest(&ric.sub(&p).unwrap()) / largest(&p);
        prop_assert!(exact_residual <= RESIDUAL_TOLERANCE, "exact residual {exact_residual:e}");
        prop_assert!(k.residual <= RESIDUAL_TOLERANCE, "residual {}", k.residual);
        for (re, im) in &k.eigenvalues {
            prop_assert!((re * re + im * im).sqrt() < 1.0 + 1e-9);
        }
        if let Some(p) = &k.exact_p {
            // an exact solution is symmetric and agrees with the float one
            prop_assert_eq!(p, &p.transpose());
            prop_assert!((rational_to_f64(p.get(0, 0)) - k.p[(0, 0)]).abs() < 1e-6);
        }
    }
}
