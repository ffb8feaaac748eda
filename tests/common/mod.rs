//! Generators shared by the property tests: small-integer inputs that are valid by
//! construction (no rejection sampling).
#![allow(dead_code)]

use observer_workbench::algebra::{Rational, Ring};
use observer_workbench::linalg::Matrix;
use observer_workbench::poly::Poly;
use proptest::prelude::*;

/// A small rational: numerator in [−9, 9], denominator in [1, 4].
pub fn small_rational() -> impl Strategy<Value = Rational> {
    (-9i64..=9, 1i64..=4).prop_map(|(n, d)| Rational::new(n.into(), d.into()))
}

/// An integer in [−9, 9] as a rational.
pub fn small_integer() -> impl Strategy<Value = Rational> {
    (-9i64..=9).prop_map(Rational::from_i64)
}

/// An `n × m` matrix of small rationals.
pub fn rational_matrix(n: usize, m: usize) -> impl Strategy<Value = Matrix<Rational>> {
    proptest::collection::vec(small_rational(), n * m)
        .prop_map(move |v| Matrix::from_fn(n, m, |i, j| v[i * m + j].clone()))
}

/// A square matrix of order 1..=max_n.
pub fn square_matrix(max_n: usize) -> impl Strategy<Value = Matrix<Rational>> {
    (1..=max_n).prop_flat_map(|n| rational_matrix(n, n))
}

/// An invertible matrix `L·U`: unit lower triangular times upper triangular with a nonzero
/// diagonal, both with small entries.
pub fn invertible_matrix(max_n: usize) -> impl Strategy<Value = Matrix<Rational>> {
    (1..=max_n).prop_flat_map(|n| {
        (
            rational_matrix(n, n),
            rational_matrix(n, n),
            proptest::collection::vec((1i64..=5, prop::bool::ANY), n),
        )
            .prop_map(move |(l, u, diag)| {
                let lower = Matrix::from_fn(n, n, |i, j| match i.cmp(&j) {
                    std::cmp::Ordering::Greater => l.get(i, j).clone(),
                    std::cmp::Ordering::Equal => Rational::from_i64(1),
                    std::cmp::Ordering::Less => Rational::from_i64(0),
                });
                let upper = Matrix::from_fn(n, n, |i, j| match i.cmp(&j) {
                    std::cmp::Ordering::Less => u.get(i, j).clone(),
                    std::cmp::Ordering::Equal => {
                        let (m, neg) = diag[i];
                        Rational::from_i64(if neg { -m } else { m })
                    }
                    std::cmp::Ordering::Greater => Rational::from_i64(0),
                });
                lower.mul(&upper).expect("square factors of one order")
            })
    })
}

/// A polynomial of degree ≤ max_deg with small rational coefficients.
pub fn polynomial(max_deg: usize) -> impl Strategy<Value = Poly<Rational>> {
    proptest::collection::vec(small_rational(), 1..=max_deg + 1).prop_map(|c| Poly::new(c, "s"))
}

/// A nonzero polynomial of degree 1..=max_deg.
pub fn nonconstant_polynomial(max_deg: usize) -> impl Strategy<Value = Poly<Rational>> {
    (
        proptest::collection::vec(small_rational(), 1..=max_deg),
        1i64..=4,
    )
        .prop_map(|(mut c, lead)| {
            c.push(Rational::from_i64(lead));
            Poly::new(c, "s")
        })
}

/// Runs the `owb` binary: (exit code, stdout, stderr).
pub fn owb(args: &[&str]) -> (i32, String, String) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_owb"))
        .args(args)
        .output()
        .expect("owb runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}
