//! The command line: human output of each subcommand as reviewed snapshots, the `--json` shape
//! that graders rely on, and exit codes.

mod common;
use common::owb;
use observer_workbench::algebra::{Quadratic, Rational};
use observer_workbench::syntax::{parse_polynomial, parse_scalar};

#[test]
fn observe_series_connection() {
    let (code, out, _) = owb(&["observe", "--a", "[-1 0; 1 -1]", "--c", "[1 0]"]);
    assert_eq!(code, 0);
    insta::assert_snapshot!(out);
}

#[test]
fn canonical_stoustrup_example() {
    let (code, out, _) = owb(&[
        "canonical",
        "--a",
        "[2 -3; 4 -5]",
        "--b",
        "[2; 3]",
        "--c",
        "[-3 2]",
    ]);
    assert_eq!(code, 0);
    insta::assert_snapshot!(out);
}

#[test]
fn gain_stoustrup_pole_assignment() {
    let (code, out, _) = owb(&[
        "gain",
        "--a",
        "[2 -3; 4 -5]",
        "--c",
        "[-3 2]",
        "--poles",
        "-4, -5",
        "--method",
        "canonical",
        "--convention",
        "a+lc",
    ]);
    assert_eq!(code, 0);
    insta::assert_snapshot!(out);
}

#[test]
fn gain_butterworth_example_7_1() {
    let (code, out, _) = owb(&[
        "gain",
        "--a",
        "[-2 0; 0 0]",
        "--c",
        "[1 1]",
        "--butterworth",
        "0.125",
    ]);
    assert_eq!(code, 0);
    insta::assert_snapshot!(out);
}

#[test]
fn control_stoustrup_example() {
    let (code, out, _) = owb(&[
        "control",
        "--a",
        "[2 -3; 4 -5]",
        "--b",
        "[2; 3]",
        "--c",
        "[-3 2]",
        "--l",
        "[-6; -12]",
        "--f",
        "[42 -30]",
    ]);
    assert_eq!(code, 0);
    insta::assert_snapshot!(out);
}

/// `control --observer-poly` designs L as `owb gain` does for A + LC: the report is the one
/// `--l` gives with that gain, in text and JSON, whatever `--convention` says.
#[test]
fn control_designs_the_observer_gain_from_its_polynomial() {
    let plant = ["--a", "[2 -3; 4 -5]", "--c", "[-3 2]"];
    let (code, out, err) = owb(&[
        &["gain"][..],
        &plant,
        &["--poly", "s^2 + 12s + 36", "--convention", "a+lc", "--json"],
    ]
    .concat());
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let entries: Vec<&str> = v["gain"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r[0].as_str().unwrap())
        .collect();
    let l = format!("[{}]", entries.join("; "));
    let control = [
        &["control"][..],
        &plant,
        &["--b", "[2; 3]", "--f", "[42 -30]"],
    ]
    .concat();
    for json in [&[][..], &["--json"]] {
        let given = owb(&[&control[..], &["--l", &l], json].concat());
        assert_eq!(given.0, 0, "{}", given.2);
        for convention in ["a+lc", "a-kc"] {
            let designed = owb(&[
                &control[..],
                &["--observer-poly", "(s + 6)^2", "--convention", convention],
                json,
            ]
            .concat());
            assert_eq!(
                designed, given,
                "--observer-poly, --convention {convention}, {json:?}"
            );
        }
    }
    // refused: neither gain, both, a polynomial of the wrong degree, an unobservable pair
    let unobservable = [
        "control",
        "--a",
        "[1 0; 0 2]",
        "--c",
        "[1 0]",
        "--b",
        "[1; 1]",
        "--f",
        "[0 0]",
    ];
    let refusals: [(Vec<&str>, &str); 4] = [
        (control.clone(), "give --l or --observer-poly"),
        (
            [&control[..], &["--l", &l, "--observer-poly", "s^2 + 1"]].concat(),
            "cannot be used with",
        ),
        (
            [&control[..], &["--observer-poly", "s^3 + 1"]].concat(),
            "monic of degree 2",
        ),
        (
            [&unobservable[..], &["--observer-poly", "s^2 + 1"]].concat(),
            "unobservable eigenvalues 2",
        ),
    ];
    for (args, needle) in refusals {
        let (code, _, err) = owb(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
    // a JSON request is not parsed by the command line: both gains are refused by the command
    let both = r#"{"command": "control", "a": "[2 -3; 4 -5]", "b": "[2; 3]", "c": "[-3 2]",
        "l": "[-6; -12]", "observer-poly": "s^2 + 1", "f": "[42 -30]"}"#;
    let request = observer_workbench::api::Command::from_json(both).expect("a well-formed request");
    let failure = observer_workbench::api::run(request).expect_err("refused");
    assert!(failure.to_string().contains("not both"), "{failure}");
    // and so are both feedbacks, a given F and its polynomial (numbers and symbols alike)
    for a in ["[2 -3; 4 -5]", "[2 -3; k -5]"] {
        let both = serde_json::json!({"command": "control", "a": a, "b": "[2; 3]",
            "c": "[-3 2]", "observer-poly": "s^2 + 3s + 2", "f": "[42 -30]",
            "feedback-poly": "s^2 + 2s + 1"});
        let request = observer_workbench::api::Command::from_value(&both).expect("well-formed");
        let failure = observer_workbench::api::run(request).expect_err("refused");
        assert!(
            failure
                .to_string()
                .contains("give --f or --feedback-poly, not both"),
            "{a}: {failure}"
        );
    }
}

/// The stable `--json` interface of `owb gain`.
#[test]
fn gain_json_shape_is_stable() {
    let (code, out, _) = owb(&[
        "gain",
        "--a",
        "[2 -3; 4 -5]",
        "--c",
        "[-3 2]",
        "--poly",
        "s^2 + 9s + 20",
        "--convention",
        "a+lc",
        "--json",
    ]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["gain"], serde_json::json!([["-6"], ["-12"]]));
    assert_eq!(v["convention"], "a+lc");
    assert_eq!(v["method"], "ackermann");
    assert_eq!(v["observer_polynomial"], "s^2 + 9*s + 20");

    let (_, out, _) = owb(&[
        "gain",
        "--a",
        "[-2 0; 0 0]",
        "--c",
        "[1 1]",
        "--butterworth",
        "1/2",
        "--json",
        "--float",
    ]);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    // Di Ruscio eq. (77) with T = 0.5 (the value the document printed): exact in Q(√2), and
    // equal to the printed [−1.1716; 2] to its 4 decimals.
    let gain: Vec<Quadratic> = v["gain"]
        .as_array()
        .unwrap()
        .iter()
        .map(|row| parse_scalar::<Quadratic>(row[0].as_str().unwrap()).unwrap())
        .collect();
    assert_ne!(
        gain[0].radicand(),
        0,
        "k1 stays exact with √2: {:?}",
        v["gain"]
    );
    for (k, printed) in gain.iter().zip([-1.1716, 2.0]) {
        assert!(
            (k.to_complex_f64().0 - printed).abs() <= 0.5e-4,
            "{k} vs printed {printed}"
        );
    }
    assert_eq!(v["places_exactly"], true);
    assert_eq!(v["float"]["verdict"], "reliable");
}

#[test]
fn repeated_and_bessel_families() {
    let (code, out, _) = owb(&[
        "gain",
        "--a",
        "[0 1; 0 0]",
        "--c",
        "[1 0]",
        "--repeated",
        "1/4",
        "--json",
    ]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    // --repeated T puts both poles at −1/T: the observer polynomial is (s + 4)^2, placed exactly
    let placed =
        parse_polynomial::<Rational>(v["observer_polynomial"].as_str().unwrap(), "s").unwrap();
    assert_eq!(
        placed,
        parse_polynomial::<Rational>("(s + 4)^2", "s").unwrap()
    );
    assert_eq!(v["places_exactly"], true);
    let (_, out, _) = owb(&[
        "gain",
        "--a",
        "[0 1; 0 0]",
        "--c",
        "[1 0]",
        "--bessel",
        "1",
        "--json",
    ]);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["observer_polynomial"], "s^2 + 3*s + 3");
}

#[test]
fn bad_input_exits_2_with_the_reason() {
    let (code, _, err) = owb(&[
        "gain",
        "--a",
        "[2 -3; 4 -5]",
        "--c",
        "[-3 2 1]",
        "--poles",
        "-4, -5",
    ]);
    assert_eq!(code, 2);
    assert!(
        err.contains("C is 1×3") || err.contains("dimension"),
        "{err}"
    );
    let (code, _, err) = owb(&[
        "gain",
        "--a",
        "[-1 0; 1 -1]",
        "--c",
        "[1 0]",
        "--poles",
        "-4, -5",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("not observable"), "{err}");
    let (code, _, err) = owb(&[
        "gain",
        "--a",
        "[2 -3; 4 &]",
        "--c",
        "[-3 2]",
        "--poles",
        "-4, -5",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("in --a") && err.contains("column 10"), "{err}");
    let (code, _, err) = owb(&[
        "gain",
        "--a",
        "[2 -3; 4 -5]",
        "--c",
        "[-3 2]",
        "--poles",
        "-1+2i, -3",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("conjugate"), "{err}");
}

#[test]
fn multi_output_exact_and_robust() {
    let ladder = "[-2 1 0; 1 -2 1; 0 1 -2]";
    // Baranowski's G1 from the first output alone, G = [G1 0]
    let (code, out, _) = owb(&[
        "gain",
        "--a",
        ladder,
        "--c",
        "[1 0 0; 0 0 1]",
        "--poles",
        "-4, -4, -4",
        "--output",
        "1",
        "--json",
    ]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(
        v["gain"],
        serde_json::json!([["6", "0"], ["14", "0"], ["14", "0"]])
    );
    let (code, out, err) = owb(&[
        "gain",
        "--a",
        ladder,
        "--c",
        "[1 0 0; 0 0 1]",
        "--poles",
        "-4, -5, -6",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["method"], "knv-robust");
    assert!(v["robust"]["residual"].as_f64().unwrap() < 1e-9);
    // complex-conjugate poles
    let (code, out, err) = owb(&[
        "gain",
        "--a",
        ladder,
        "--c",
        "[1 0 0; 0 0 1]",
        "--poles",
        "-4+2i, -4-2i, -6",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(v["robust"]["residual"].as_f64().unwrap() < 1e-9);
    // a triple pole cannot be placed robustly with two outputs: said, not approximated
    let (code, _, err) = owb(&[
        "gain",
        "--a",
        ladder,
        "--c",
        "[1 0 0; 0 0 1]",
        "--poles",
        "-4, -4, -4",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("repeated 3 times"), "{err}");
}

const LADDER_A: &str = "[-2 1 0; 1 -2 1; 0 1 -2]";
const LADDER_C: &str = "[1 0 0; 0 0 1]";

#[test]
fn optimal_j2_and_the_printed_gain() {
    let (code, out, _) = owb(&[
        "optimal",
        "--a",
        LADDER_A,
        "--c",
        LADDER_C,
        "--poles",
        "-4, -4, -4",
        "--index",
        "j2",
        "--weight",
        "[0 0 0; 0 1 0; 0 0 0]",
        "--starts",
        "16",
        "--check-gain",
        "[2.8976 0.5863; 2.7712 2.7531; 0.8762 3.1024]",
    ]);
    assert_eq!(code, 0);
    insta::assert_snapshot!(out);
}

#[test]
fn optimal_json_reports_the_minima() {
    let (code, out, _) = owb(&[
        "optimal",
        "--a",
        LADDER_A,
        "--c",
        LADDER_C,
        "--poles",
        "-4, -4, -4",
        "--starts",
        "20",
        "--json",
    ]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let minima = v["report"]["minima"].as_array().unwrap();
    let best = minima[0]["cost"].as_f64().unwrap();
    assert!(
        (best - 29.0466).abs() < 5e-5,
        "printed J1 = 29.0466, found {best}"
    );
    assert_eq!(v["convention"], "a-kc");
}

#[test]
fn kalman_versus_chosen_poles_for_furlan() {
    let (code, out, _) = owb(&[
        "kalman",
        "--a",
        "[0 1; -15000 -45/14]",
        "--b",
        "[0; 1/0.056]",
        "--c",
        "[1 0; -15000 -45/14]",
        "--d",
        "[0; 1/0.056]",
        "--input-noise",
        "[4.47e-8]",
        "--output-noise",
        "[5.08e-16 0; 0 4.47e-6]",
        "--poles",
        "-548, -670",
        "--derivative-output",
        "2",
        "--derivative-state",
        "2",
        "--grid",
        "201",
    ]);
    assert_eq!(code, 0, "{out}");
    insta::assert_snapshot!(out);
    let (_, json, _) = owb(&[
        "kalman",
        "--a",
        "[0 1; -15000 -45/14]",
        "--b",
        "[0; 1/0.056]",
        "--c",
        "[1 0; -15000 -45/14]",
        "--d",
        "[0; 1/0.056]",
        "--input-noise",
        "[4.47e-8]",
        "--output-noise",
        "[5.08e-16 0; 0 4.47e-6]",
        "--json",
    ]);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert!(v["kalman"]["residual"].as_f64().unwrap() < 1e-12);
    assert_eq!(v["comparison"][0]["method"], "kalman");
}

#[test]
fn perfect_observer_and_a_plant_it_does_not_fit() {
    let (code, out, _) = owb(&[
        "perfect",
        "--a",
        "[0 1 0; 0 0 1; -6 -11 -6]",
        "--b",
        "[3; 2; 1]",
        "--c",
        "[1 0 0]",
        "--changed-a",
        "[0 1 0; 0 0 1; -2 -3 1]",
        "--changed-b",
        "[3; 2; 3]",
    ]);
    assert_eq!(code, 0);
    insta::assert_snapshot!(out);
    // changing row 1 of A breaks the observer: the check fails with exit 1
    let (code, out, _) = owb(&[
        "perfect",
        "--a",
        "[0 1 0; 0 0 1; -6 -11 -6]",
        "--b",
        "[3; 2; 1]",
        "--c",
        "[1 0 0]",
        "--changed-a",
        "[0 2 0; 0 0 1; -6 -11 -6]",
    ]);
    assert_eq!(code, 1);
    assert!(out.contains("does NOT fit"));
    // unobservable or dependent outputs: exit 2 with the reason
    let (code, _, err) = owb(&[
        "perfect",
        "--a",
        "[-1 0; 1 -1]",
        "--b",
        "[1; 0]",
        "--c",
        "[1 0]",
    ]);
    assert_eq!(code, 2);
    assert!(
        err.contains("not observable") || err.contains("unobservable"),
        "{err}"
    );
    let (code, _, err) = owb(&[
        "kalman",
        "--a",
        "[0 1; -1 -1]",
        "--b",
        "[0; 1]",
        "--c",
        "[1 0]",
        "--input-noise",
        "[1]",
        "--output-noise",
        "[0]",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("singular"), "{err}");
    let (code, _, err) = owb(&[
        "optimal", "--a", LADDER_A, "--c", LADDER_C, "--poles", "-4, -4",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("2 poles given"), "{err}");
}

/// `optimal` on a dense integer plant of order 5 (entries −9…9, two outputs): its constraints'
/// terms reach 10⁵ and more, where f64 cannot bring them below the absolute 10⁻¹³ Newton's
/// method first asks for, and no start converged. Now Newton stops at f64's resolution for
/// these coefficients, checks the placement exactly and says how close it is; the gain it
/// reports places the poles.
#[test]
fn optimal_converges_on_a_plant_with_large_coefficients_and_says_to_what() {
    let a = "[8 -9 3 -3 4; -9 7 -2 5 6; 8 -2 2 -2 -2; 5 0 -9 4 8; -6 -4 0 -6 1]";
    let c = "[1 0 0 0 0; 0 1 0 0 0]";
    let (code, out, err) = owb(&["optimal", "--a", a, "--c", c, "--repeated", "1"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("places each coefficient of the polynomial within"),
        "{out}"
    );
    let (code, json, err) = owb(&["optimal", "--a", a, "--c", c, "--repeated", "1", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let best = &v["report"]["minima"][0];
    let residual = best["constraint_residual"].as_f64().unwrap();
    assert!(residual > 1e-13, "{residual}");
    let placed = best["placement_error"].as_f64().unwrap();
    assert!(placed <= 1e-6, "{placed}");
    let k = floats(&best["gain"]);
    // det(sI − (A − GC)) in f64 against (s + 1)⁵, G filled column by column
    let entries: Vec<f64> = a
        .trim_matches(['[', ']'])
        .split(';')
        .flat_map(|row| row.split_whitespace().map(|x| x.parse::<f64>().unwrap()))
        .collect();
    let m = observer_workbench::linalg::Matrix::from_fn(5, 5, |i, j| {
        // (GC)_ij = G_ij for the two measured states, column j of G being k[5j..5j + 5]
        entries[5 * i + j] - if j < 2 { k[5 * j + i] } else { 0.0 }
    });
    let p = observer_workbench::linalg::berkowitz(&m, "s").unwrap();
    // the desired polynomial of `--repeated 1`, made by the workbench, not typed
    let desired = observer_workbench::poly::Poly::from_roots(&[-1.0f64; 5], "s");
    for power in 0..=5 {
        let (got, want) = (p.coeff(power), desired.coeff(power));
        assert!((got - want).abs() < 1e-6, "s^{power}: {got} ≠ {want}");
    }
}

/// A JSON array of numbers (an `optimal` gain, column by column) as f64s.
fn floats(array: &serde_json::Value) -> Vec<f64> {
    array
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

/// A matrix typed as integers, `[1 -2; 3 4]`, with every entry divided by `by`, as text.
fn divided(integers: &str, by: u32) -> String {
    let rows: Vec<String> = integers
        .trim_matches(['[', ']'])
        .split(';')
        .map(|row| {
            row.split_whitespace()
                .map(|x| format!("{x}/{by}"))
                .collect::<Vec<_>>()
                .join(" ")
        })
        .collect();
    format!("[{}]", rows.join("; "))
}

/// At order 10 the same kind of plant has terms so large that no f64 gain places the
/// polynomial to 10⁻⁶: `optimal` reports no gain, and says why and what to do, instead of
/// suggesting more starts; the plant scaled down by 10 converges.
#[test]
fn optimal_says_when_the_plant_is_too_large_for_an_f64_gain() {
    let a = "[-5 9 -7 -1 -6 6 5 6 3 -3; -6 6 -9 3 4 -9 5 -1 -2 9; -6 1 -9 -9 -9 8 -9 3 -3 4; -9 7 -2 5 6 8 -2 2 -2 -2; 5 0 -9 4 8 -6 -4 0 -6 1; 7 4 7 -3 0 0 9 6 7 3; 9 -8 6 -2 3 4 -4 2 8 2; -7 5 7 -6 -4 7 3 2 6 -9; 6 -8 0 9 9 3 -4 -4 7 -2; -9 -3 8 8 -2 3 7 2 9 2]";
    let c = "[1 0 0 0 0 0 0 0 0 0; 0 1 0 0 0 0 0 0 0 0]";
    let (code, _, err) = owb(&["optimal", "--a", a, "--c", c, "--repeated", "1"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("too large for an f64 gain"), "{err}");
    let scaled = divided(a, 10);
    let (code, out, err) = owb(&["optimal", "--a", &scaled, "--c", c, "--repeated", "1"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("best J1"), "{out}");
}

/// Order 15 with entries near 1 (a dense integer plant divided by 15, two outputs): Newton's
/// undamped steps on the KKT system leave the constraint set from every random start, and no
/// start converged. The same starts, first moved by a descent on the constraint set, converge,
/// and the report says that is how; the best gain places (s + 1)¹⁵.
#[test]
fn optimal_descends_on_the_constraint_set_when_newton_alone_does_not_converge() {
    let integers = "[4 -5 7 9 1 5 8 -3 -8 6 9 -2 4 7 0; -4 -7 -6 0 6 7 2 -8 2 -8 7 0 6 -9 5; -3 4 4 -5 -4 7 4 -9 7 -6 -2 3 4 -7 -5; 9 -4 -4 9 -8 -8 3 1 5 -3 -8 -5 -5 -4 1; -3 -8 -3 8 -5 5 -9 -9 -5 -7 1 -5 0 0 2; -8 8 -6 -8 -9 8 -1 0 4 8 -4 0 -6 -3 -6; -3 7 1 3 -6 -5 1 8 -3 -5 5 7 -1 -6 -1; 5 8 -6 -3 -8 -3 9 2 -9 6 3 5 -3 -4 -9; 0 9 9 -2 8 -3 5 -2 0 8 -4 -3 -4 2 3; -4 0 -2 -9 -4 5 4 3 -3 7 3 8 -4 1 -3; -7 2 5 3 7 2 2 4 -7 1 -8 1 2 7 -7; -3 4 9 -4 8 -9 5 -6 -9 5 -2 -4 -2 -7 2; -8 -7 3 6 3 9 -3 4 -8 -8 -2 -2 -5 8 2; 7 -9 8 8 9 8 0 -4 -6 3 4 6 -3 9 2; -4 7 5 2 8 8 -4 -2 0 -8 4 -4 -9 5 4]";
    let a = divided(integers, 15);
    let c = format!(
        "[{}; {}]",
        (0..15)
            .map(|j| if j == 0 { "1" } else { "0" })
            .collect::<Vec<_>>()
            .join(" "),
        (0..15)
            .map(|j| if j == 1 { "1" } else { "0" })
            .collect::<Vec<_>>()
            .join(" ")
    );
    let args = [
        "optimal",
        "--a",
        &a,
        "--c",
        &c,
        "--repeated",
        "1",
        "--starts",
        "2",
    ];
    let (code, out, err) = owb(&args);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("none converged from where it began"), "{out}");
    // with no time left to take the starts again, the error says the time limit stopped it
    let (code, _, err) = owb(&[&args[..], &["--time-limit", "0.001"]].concat());
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("raise --time-limit"), "{err}");
    let (code, json, err) = owb(&[&args[..], &["--json"]].concat());
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let report = &v["report"];
    assert_eq!(report["descended"], 2, "{report}");
    assert!(report["converged"].as_u64().unwrap() >= 1, "{report}");
    let best = &report["minima"][0];
    assert!(best["placement_error"].as_f64().unwrap() <= 1e-6, "{best}");
    let k = floats(&best["gain"]);
    // det(sI − (A − GC)) computed exactly from the gain as printed (every f64 is a rational):
    // f64 itself cannot check it, the constant term being a sum of terms near 60¹⁵
    use observer_workbench::algebra::Rational;
    use observer_workbench::linalg::Matrix;
    let exact = |x: f64| <Rational as num_traits::FromPrimitive>::from_f64(x).unwrap();
    let plant = observer_workbench::syntax::parse_matrix::<Rational>(&a).unwrap();
    // A − GC, G filled column by column, C measuring the first two states
    let m = Matrix::from_fn(15, 15, |i, j| {
        let g = if j < 2 {
            exact(k[15 * j + i])
        } else {
            Rational::from_integer(0.into())
        };
        plant.get(i, j).clone() - g
    });
    let p = observer_workbench::linalg::characteristic_polynomial(&m, "s").unwrap();
    let desired = observer_workbench::poly::Poly::from_roots(&[-1.0f64; 15], "s");
    for power in 0..=15 {
        let got = observer_workbench::algebra::rational_to_f64(&p.coeff(power));
        let want = desired.coeff(power);
        assert!(
            (got - want).abs() <= 1e-6 * want.abs().max(1.0),
            "s^{power}: {got} ≠ {want}"
        );
    }
}

/// `owb verify | head -1`: the reader goes away, the program ends quietly (it panicked with
/// "failed printing to stdout: Broken pipe").
#[test]
fn a_closed_output_ends_quietly() {
    use std::io::Read;
    use std::process::{Command, Stdio};
    let mut child = Command::new(env!("CARGO_BIN_EXE_owb"))
        .arg("verify")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("owb runs");
    let mut first = [0u8; 16];
    child
        .stdout
        .take()
        .expect("stdout")
        .read_exact(&mut first)
        .expect("some output");
    // stdout is dropped here: the pipe is closed while owb still writes
    let out = child.wait_with_output().expect("owb ends");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(
        matches!(out.status.code(), Some(141) | Some(0)),
        "{:?}",
        out.status
    );
}

/// Nonsense that was accepted with exit 0 (found by a scripted campaign over the subcommands)
/// is refused with exit 2 and the flag named.
#[test]
fn nonsense_requests_are_refused_with_the_flag_named() {
    let ladder = "[-2 1 0; 1 -2 1; 0 1 -2]";
    let two = "[1 0 0; 0 0 1]";
    let with = |base: &[&'static str], extra: &[&'static str]| -> Vec<&'static str> {
        base.iter().chain(extra).copied().collect()
    };
    let scalar_gain = ["gain", "--a", "[1]", "--c", "[1]", "--poles", "-1"];
    let optimal = [
        "optimal",
        "--a",
        ladder,
        "--c",
        two,
        "--poles",
        "-4, -4, -4",
    ];
    let kalman = ["kalman", "--a", "[-1]", "--b", "[1]", "--c", "[1]"];
    let diagonal = "[1 0 0; 0 2 0; 0 0 3]";
    let first_state_twice = "[1 0 0; 1 0 0]";
    #[rustfmt::skip]
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (with(&scalar_gain, &["--tolerance", "NaN"]), "--tolerance"),
        (with(&scalar_gain, &["--tolerance", "-1"]), "--tolerance"),
        (vec!["optimal", "--a", "[-2 1; 1 -2]", "--c", "[1 0]", "--poles", "-4, -4"], "nothing to optimise"),
        (with(&optimal, &["--starts", "0"]), "--starts"),
        (with(&optimal, &["--starts", "100000000"]), "--starts"),
        (with(&optimal, &["--index", "j2", "--weight", "[-1 0 0; 0 1 0; 0 0 1]"]), "--weight"),
        (vec!["optimal", "--a", diagonal, "--c", first_state_twice, "--poles", "-4, -4, -4"], "not observable"),
        (vec!["optimal", "--a", "[0]", "--c", "[1; 2]", "--poles", "0", "--index", "j2"], "not Hurwitz"),
        (vec!["optimal", "--a", "[1]", "--c", "[0; 1]", "--poles", "-1", "--index", "j2"], "output 1 cannot place the poles alone"),
        (vec!["gain", "--a", diagonal, "--c", first_state_twice, "--poles", "-1, -2, -3"], "unobservable eigenvalues 3, 2"),
        (with(&kalman, &["--input-noise", "[-1]", "--output-noise", "[1]"]), "--input-noise"),
        (with(&kalman, &["--input-noise", "[1]", "--output-noise", "[1]", "--derivative-output", "1"]), "give --poles"),
        (vec!["control", "--a", "[1 0; 0 2]", "--c", "[1 1]", "--b", "[1; 0]", "--l", "[-5; -6]", "--feedback-poly", "s^2 + 3s + 2"], "(A, B) is not controllable"),
    ];
    for (args, needle) in cases {
        let (code, out, err) = owb(&args);
        assert_eq!(code, 2, "{args:?}: {out}{err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
}

/// A 1×1 plant with two outputs: J2 = D/6 on every gain placing s + 3, so the minimiser is not
/// unique (every direction is flat, though the Hessian vanishes there).
#[test]
fn a_constant_j2_is_flat_everywhere() {
    let (code, out, err) = owb(&[
        "optimal", "--a", "[-1]", "--c", "[1; 1]", "--poles", "-3", "--index", "j2", "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).expect("json");
    assert_eq!(v["report"]["flat_directions"], 1, "{out}");
    let j2 = v["report"]["best"]["cost"].as_f64().expect("cost");
    assert!((j2 - 1.0 / 6.0).abs() < 1e-9, "{j2}");
}

/// Issue 17's diagnoses: each refusal names the flag and what was expected, in the user's
/// words, and an undetectable pair or out-of-range noise is said as such (exit 2 each).
#[test]
fn refusals_name_the_flag_and_the_reason() {
    // a double integrator with observer and feedback gains; one matrix changed per case
    let control = |b: &'static str, l: &'static str, f: &'static str| {
        let plant = ["control", "--a", "[0 1; 0 0]", "--c", "[1 0]"];
        [&plant[..], &["--b", b, "--l", l, "--f", f]].concat()
    };
    let kalman = |a: &'static str, c: &'static str, cu: &'static str, cy: &'static str| {
        let noise = ["--input-noise", cu, "--output-noise", cy];
        [&["kalman", "--a", a, "--b", "[0; 1]", "--c", c][..], &noise].concat()
    };
    let stable = "[0 1; -2 -3]";
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec![
                "gain",
                "--a",
                "[2 -3; 4 -5]",
                "--c",
                "[-3 2 1]",
                "--poles",
                "-1, -2",
            ],
            "in --c: C is 1×3, expected 2 columns (the order of A)",
        ),
        (
            control("[0; 1; 2]", "[2; 1]", "[-1 -2]"),
            "in --b: B is 3×1, expected 2 rows",
        ),
        (
            control("[0; 1]", "[2 1]", "[-1 -2]"),
            "in --l: the matrix is 1×2, expected 2×1 (states × outputs)",
        ),
        (
            control("[0; 1]", "[2; 1]", "[-1 -2 3]"),
            "in --f: the matrix is 1×3, expected 1×2 (inputs × states)",
        ),
        (
            vec![
                "canonical",
                "--a",
                "[0 1; 0 0]",
                "--b",
                "[0; 1; 1]",
                "--c",
                "[1 0]",
            ],
            "in --b: B is 3×1",
        ),
        (
            vec![
                "perfect",
                "--a",
                stable,
                "--b",
                "[0; 1]",
                "--c",
                "[1 0]",
                "--changed-a",
                "[1 2 3]",
            ],
            "in --changed-a: the matrix is 1×3, expected 2×2",
        ),
        (
            kalman("[1 0; 0 -1]", "[0 1]", "[1]", "[1]"),
            "(A, C) is not detectable: the unobservable modes (1)",
        ),
        (
            kalman(stable, "[1 0]", "[1]", "[1e-320]"),
            "in --output-noise: an intensity of about 1e-320 is outside the range of f64",
        ),
        (
            kalman(stable, "[1 0]", "[1 0; 0 1]", "[1]"),
            "in --input-noise: the matrix is 2×2, expected 1×1 (inputs × inputs)",
        ),
    ];
    for (args, expected) in &cases {
        let (code, out, err) = owb(args);
        assert_eq!(code, 2, "{args:?}: {out}{err}");
        assert!(err.contains(expected), "{args:?}: {err}");
    }
    // a detectable pair (the unobservable mode at −1 is stable) is designed, not refused
    let (code, out, err) = owb(&kalman("[-1 0; 0 -1]", "[0 1]", "[1]", "[1]"));
    assert_eq!(code, 0, "{out}{err}");
}

/// `owb feedback`: Stoustrup's F (u = F x) and its K (u = −K x); an uncontrollable pair names its
/// mode; several inputs are refused with the flag.
#[test]
fn feedback_in_both_conventions_and_its_refusals() {
    let base = [
        "feedback",
        "--a",
        "[2 -3; 4 -5]",
        "--b",
        "[2; 3]",
        "--poles",
        "-4, -5",
    ];
    let (code, out, err) = owb(&[&base[..], &["--convention", "u=fx", "--json"]].concat());
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["gain"], serde_json::json!([["42", "-30"]]));
    assert_eq!(v["convention"], "u=fx");
    assert_eq!(v["places_exactly"], true);
    let (_, out, _) = owb(&[&base[..], &["--method", "bass-gura"]].concat());
    assert!(out.contains("K = [-42, 30]"), "{out}");
    let (code, _, err) = owb(&[
        "feedback",
        "--a",
        "[1 0; 0 2]",
        "--b",
        "[1; 0]",
        "--poles",
        "-1, -2",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("uncontrollable eigenvalues 2"), "{err}");
    let (code, _, err) = owb(&[
        "feedback",
        "--a",
        "[0 1; 0 0]",
        "--b",
        "[0 1; 1 0]",
        "--poles",
        "-1, -2",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("in --b"), "{err}");
}
