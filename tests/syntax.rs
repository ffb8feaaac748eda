//! Round trips: what the workbench prints in its input syntax parses back to the same value.

mod common;

use common::{polynomial, rational_matrix, small_rational};
use observer_workbench::algebra::{MultiPoly, Quadratic, Rational, Ring, Zero};
use observer_workbench::syntax::{parse_matrix, parse_polynomial, parse_scalar, SyntaxError};
use proptest::prelude::*;

fn quadratic() -> impl Strategy<Value = Quadratic> {
    (
        small_rational(),
        small_rational(),
        prop::sample::select(vec![2i64, 3, 5, -1, 6]),
    )
        .prop_map(|(a, b, d)| Quadratic::new(a, b, d).unwrap())
}

fn symbolic() -> impl Strategy<Value = MultiPoly> {
    let var = prop::sample::select(vec!["k1", "k2", "a", "T", "λ"]);
    proptest::collection::vec((small_rational(), var.clone(), var, 0u32..3), 0..5).prop_map(
        |terms| {
            terms
                .into_iter()
                .fold(MultiPoly::zero(), |acc, (c, x, y, e)| {
                    let mut t = MultiPoly::constant(c) * MultiPoly::var(x);
                    for _ in 0..e {
                        t = t * MultiPoly::var(y);
                    }
                    acc + t
                })
        },
    )
}

proptest! {
    #[test]
    fn rationals_round_trip(x in small_rational()) {
        prop_assert_eq!(parse_scalar::<Rational>(&x.to_input()).unwrap(), x.clone());
        prop_assert_eq!(parse_scalar::<Rational>(&x.to_string()).unwrap(), x);
    }

    #[test]
    fn quadratic_numbers_round_trip(x in quadratic()) {
        prop_assert_eq!(parse_scalar::<Quadratic>(&x.to_input()).unwrap(), x.clone());
        // the human form (with √ and −) parses too
        prop_assert_eq!(parse_scalar::<Quadratic>(&x.to_string()).unwrap(), x);
    }

    #[test]
    fn symbolic_polynomials_round_trip(p in symbolic()) {
        prop_assert_eq!(parse_scalar::<MultiPoly>(&p.to_input()).unwrap(), p.clone());
        prop_assert_eq!(parse_scalar::<MultiPoly>(&p.to_string()).unwrap(), p);
    }

    #[test]
    fn matrices_round_trip(m in (1usize..5, 1usize..5).prop_flat_map(|(r, c)| rational_matrix(r, c))) {
        prop_assert_eq!(parse_matrix::<Rational>(&m.to_input()).unwrap(), m);
    }

    #[test]
    fn polynomials_round_trip(p in polynomial(5)) {
        prop_assert_eq!(parse_polynomial::<Rational>(&p.to_input(), "s").unwrap(), p.clone());
        prop_assert_eq!(parse_polynomial::<Rational>(&p.to_string(), "s").unwrap(), p);
    }

    #[test]
    fn garbage_never_panics(s in "[\\[\\]0-9a-z+\\-*/^(),;. √]{0,24}") {
        let _ = parse_matrix::<Rational>(&s);
        let _ = parse_scalar::<Quadratic>(&s);
        let _ = parse_polynomial::<Rational>(&s, "s");
    }
}

#[test]
fn huge_exponents_are_refused_not_computed() {
    let e = parse_scalar::<Rational>("2^100000").unwrap_err();
    assert!(matches!(e, SyntaxError::TooLarge { .. }), "{e}");
    let e = parse_scalar::<Rational>("1e99999").unwrap_err();
    assert!(matches!(e, SyntaxError::TooLarge { .. }), "{e}");
}

#[test]
fn caret_display_points_at_the_error() {
    let input = "[1 2; 3 x]";
    let e = parse_matrix::<Rational>(input).unwrap_err();
    assert_eq!(
        e.show_in(input),
        "[1 2; 3 x]\n        ^ column 9: the symbol 'x' is not allowed in a rational number"
    );
}

/// Hostile input meets a limit, named with its column, never a stack overflow or a hang
/// (found by trying 50 000 nested parentheses, 60 000 signs, 20 000 nested roots and
/// `((2^1000)^1000)^1000`).
#[test]
fn deep_nesting_and_huge_values_are_refused() {
    let parens = format!("{}1{}", "(".repeat(50_000), ")".repeat(50_000));
    let signs = format!("{}1", "-".repeat(60_000));
    let roots = format!("{}2{}", "sqrt(".repeat(20_000), ")".repeat(20_000));
    for input in [parens, signs, roots] {
        match parse_scalar::<Quadratic>(&input) {
            Err(SyntaxError::TooLarge { what, .. }) => assert!(what.contains("nesting"), "{what}"),
            other => panic!("expected a nesting limit, got {other:?}"),
        }
    }
    match parse_scalar::<Rational>("((2^1000)^1000)^1000") {
        Err(SyntaxError::TooLarge { column, what, .. }) => {
            assert_eq!(column, 10);
            assert!(what.contains("bits"), "{what}");
        }
        other => panic!("expected a value-size limit, got {other:?}"),
    }
    // what people write still reads
    assert_eq!(
        parse_scalar::<Rational>("((((-(2^10)))))").unwrap(),
        Rational::from_i64(-1024)
    );
    assert_eq!(
        parse_scalar::<Rational>("-(-(-(-3)))").unwrap(),
        Rational::from_i64(3)
    );
}

/// A 130 KB input was echoed whole in its error: the caret display is a window.
#[test]
fn long_inputs_are_not_echoed_whole() {
    let input = format!("[{} x]", "1 ".repeat(60_000));
    let err = parse_matrix::<Rational>(&input).unwrap_err();
    let shown = err.show_in(&input);
    assert!(
        shown.chars().count() < 400,
        "{} chars",
        shown.chars().count()
    );
    let lines: Vec<&str> = shown.lines().collect();
    // the caret is under the x
    let caret = lines[1].chars().position(|c| c == '^').unwrap();
    assert_eq!(lines[0].chars().nth(caret), Some('x'));
}

/// Symbolic division is exact long division: a divisor with a variable the dividend lacks is
/// refused at once, and one whose long division would cost too much is refused by a work bound
/// (found by fuzzing: `(s^222 + 74)/(2s + u22 + 20)` took seconds).
#[test]
fn symbolic_divisions_are_exact_or_refused_quickly() {
    let q = parse_scalar::<MultiPoly>("(s^2 - u^2)/(s - u)").unwrap();
    assert_eq!(q, parse_scalar::<MultiPoly>("s + u").unwrap());
    for text in [
        "(s^222 + 74)/(2s + u22 + 20)",
        "(u*s^222 + 74)/(2s + u + 20)",
    ] {
        let e = parse_scalar::<MultiPoly>(text).unwrap_err().to_string();
        assert!(e.contains("a division by"), "{text}: {e}");
    }
    let e = parse_scalar::<MultiPoly>("(u*s^222 + 74)/(2s + u + 20)")
        .unwrap_err()
        .to_string();
    assert!(e.contains("term operations"), "{e}");
}

/// Powers over Q(√d) with irrational coefficients are bounded by the work of their last
/// squaring (found by fuzzing: `(s + i − 2)^184` took 2 s); the powers a course uses pass.
#[test]
fn irrational_powers_are_bounded_by_their_work() {
    use observer_workbench::syntax::parse_polynomial;
    for ok in ["(s^2 + sqrt(2) s + 1)^3", "(s + 1 + i)^5", "(s + 1)^100"] {
        assert!(parse_polynomial::<Quadratic>(ok, "s").is_ok(), "{ok}");
    }
    let e = parse_polynomial::<Quadratic>("(s + i - 2)^184", "s").unwrap_err();
    assert!(e.to_string().contains("irrational coefficients"), "{e}");
}

/// A power's coefficients together are bounded, not only the largest (found by fuzzing:
/// `(26^19 s + 25^21)^110`, 111 coefficients of 11 000 bits, took a second).
#[test]
fn powers_are_bounded_by_all_their_coefficients() {
    use observer_workbench::syntax::parse_polynomial;
    let e = parse_polynomial::<Rational>("(26^19 s + 25^21)^110", "s").unwrap_err();
    assert!(e.to_string().contains("a power of degree 110"), "{e}");
    assert!(parse_polynomial::<Rational>("(26^19 s + 25^21)^3", "s").is_ok());
}

/// One matrix, one quadratic field: `[sqrt(2); i]` is refused where the second field starts
/// (found by fuzzing: such an answer matrix crashed the checker's characteristic polynomial).
#[test]
fn a_matrix_holds_one_quadratic_field() {
    let e = parse_matrix::<Quadratic>("[sqrt(2) - 3; 4i]").unwrap_err();
    assert_eq!(
        e.to_string(),
        "column 16: i after √2 is not allowed in one matrix (only one quadratic field at a time)"
    );
    assert!(parse_matrix::<Quadratic>("[sqrt(2); 1 - sqrt(8)]").is_ok());
    let e =
        observer_workbench::syntax::parse_list::<Quadratic>("1 + i, 1 - i, sqrt(3)").unwrap_err();
    assert!(
        e.to_string()
            .contains("√3 after i is not allowed in one list"),
        "{e}"
    );
}

/// Complex numbers as engineers write them: `j` is `i`, and `i` times the root of a nonnegative
/// number is the root of its negative (one quadratic field), wherever the factors stand.
#[test]
fn j_and_i_times_a_root_read_as_courses_write_them() {
    use observer_workbench::algebra::Quadratic;
    let q = |s: &str| observer_workbench::syntax::parse_scalar::<Quadratic>(s);
    assert_eq!(q("-1 + 2j").unwrap(), q("-1 + 2i").unwrap());
    for (written, meant) in [
        ("-2 + 2*sqrt(3)*i", "-2 + 2*sqrt(-3)"),
        ("-2 + 2sqrt(3)j", "-2 + 2*sqrt(-3)"),
        ("i*sqrt(3/4)", "sqrt(-3/4)"),
        ("3*i*sqrt(2)/2", "3*sqrt(-2)/2"),
        ("(1 + sqrt(5)*i)*2", "2 + 2*sqrt(-5)"),
    ] {
        assert_eq!(q(written).unwrap(), q(meant).unwrap(), "{written}");
    }
    // √(−3)·i is −√3, not √3: a root of a negative number is never folded
    assert_ne!(q("sqrt(-3)*i").ok(), q("sqrt(3)").ok());
    // a product with two i keeps its meaning: i·i·√3 = −√3 would mix Q(i) and Q(√3) midway
    assert_ne!(q("i*i*sqrt(3)").ok(), q("sqrt(-3)").ok());
}
