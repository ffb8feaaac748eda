//! The float path checked against the exact one on the RC ladder with all observer poles at −4
//! (n = 3 … 20): where repeated roots make eigenvalues scatter like ε^(1/n), the check must tell
//! scatter from a wrong gain, and it must never pass a wrong float gain silently.

use observer_workbench::algebra::{Rational, Ring};
use observer_workbench::linalg::Matrix;
use observer_workbench::observer::float_check::{float_check, FloatVerdict};
use observer_workbench::observer::{design, Convention, DesiredPolynomial, GainMethod};

fn rc_ladder(n: usize) -> Matrix<Rational> {
    Matrix::from_fn(n, n, |i, j| match i.abs_diff(j) {
        0 => Rational::from_i64(-2),
        1 => Rational::from_i64(1),
        _ => Rational::from_i64(0),
    })
}

fn sig(x: f64) -> String {
    format!("{x:.0e}")
}

#[test]
fn rc_ladder_float_table() {
    let mut table = String::from(
        "n   cond(O_n)  gain error  bound   max |λ − (−4)|  predicted  poly check  verdict\n",
    );
    for n in 3..=20 {
        let a = rc_ladder(n);
        let c = Matrix::from_fn(1, n, |_, j| Rational::from_i64(i64::from(j == 0)));
        let desired = DesiredPolynomial::repeated(&Rational::new(1.into(), 4.into()), n).unwrap();
        let exact = design(
            &a,
            &c,
            &desired,
            GainMethod::Ackermann,
            Convention::AMinusKC,
        )
        .unwrap();
        assert!(exact.places_exactly(), "exact design misses at n = {n}");
        let f = float_check(
            &a,
            &c,
            &desired.float,
            desired.rational().as_ref(),
            Some(&exact.gain.matrix),
            1e-6,
        );
        // Never silently wrong: a float gain beyond tolerance must be flagged.
        if f.gain_relative_error > 1e-6 {
            assert_eq!(f.verdict, FloatVerdict::GainUnreliable, "n = {n}");
        }
        // A verdict that clears the gain must rest on evidence: the exact polynomial check of
        // the float gain, or a scatter within the repeated-root prediction.
        if matches!(
            f.verdict,
            FloatVerdict::RepeatedRootScatter | FloatVerdict::PolesIllConditioned
        ) {
            let poly_ok = f.polynomial_relative_error.is_some_and(|e| e <= 1e-6);
            assert!(
                poly_ok || f.max_pole_distance <= 10.0 * f.predicted_scatter_with_gain_error,
                "n = {n}: {f:?}"
            );
        }
        assert_ne!(f.verdict, FloatVerdict::PolesUnexplained, "n = {n}: {f:?}");
        table.push_str(&format!(
            "{n:<3} {:<10} {:<11} {:<7} {:<15} {:<10} {:<11} {:?}\n",
            sig(f.condition_number),
            sig(f.gain_relative_error),
            sig(f.gain_error_bound),
            sig(f.max_pole_distance),
            sig(f.predicted_scatter_with_gain_error),
            f.polynomial_relative_error.map_or("—".into(), sig),
            f.verdict
        ));
    }
    insta::assert_snapshot!(table);
}
