//! Designing with parameters, at the level a user acts: each symbolic command through the
//! binary (reviewed snapshots of the derivations a teacher reads), the formulas checked against
//! the numeric commands at sample values (`--at`), where each design breaks, and the refusals.

mod common;
use common::owb;
use observer_workbench::algebra::{Fraction, Rational};
use observer_workbench::syntax::{parse_matrix, parse_polynomial, parse_scalar};

fn json(args: &[&str]) -> serde_json::Value {
    let (code, out, err) = owb(args);
    assert_eq!(code, 0, "{args:?}: {err}");
    serde_json::from_str(&out).expect("valid JSON")
}

fn gain_entries(v: &serde_json::Value) -> Vec<String> {
    v["gain"]
        .as_array()
        .expect("gain rows")
        .iter()
        .flat_map(|r| r.as_array().expect("a row").clone())
        .map(|x| x.as_str().expect("text").to_string())
        .collect()
}

const MSD_A: &str = "[0 1; -k/m -c/m]";

/// A formula from the workbench's output evaluated at `values` (`"k=2, m=1"`), as the
/// workbench prints the number.
fn at(formula: &str, values: &str) -> String {
    let mut f = parse_scalar::<Fraction>(formula).expect("the formula reads back");
    for pair in values.split(',') {
        let (name, value) = pair.split_once('=').expect("NAME=VALUE");
        let v = parse_scalar::<Rational>(value.trim()).expect("a number");
        f = f.substitute(name.trim(), &Fraction::constant(v));
    }
    f.as_rational()
        .expect("every parameter has a value")
        .to_string()
}

#[test]
fn mass_spring_damper_gain_as_a_formula() {
    let (code, out, _) = owb(&["gain", "--a", MSD_A, "--c", "[1 0]", "--poles", "-w, -w"]);
    assert_eq!(code, 0);
    assert!(out.contains("K = [(2*m*w - c)/m; (m^2*w^2 - 2*c*m*w + c^2 - k*m)/m^2]"));
    assert!(out.contains("valid for m ≠ 0"));
    assert!(out.contains("identically in s and c, k, m, w"));
    insta::assert_snapshot!(out);
}

/// The formula, evaluated at values, is the gain the numeric command computes there — for
/// every method and both conventions.
#[test]
fn the_formula_at_values_is_the_numeric_gain() {
    let points = [
        (
            "k=2,m=1,c=3,w=4",
            [("k", 2, 1), ("m", 1, 1), ("c", 3, 1), ("w", 4, 1)],
        ),
        (
            "k=-1/2,m=3,c=0,w=7/3",
            [("k", -1, 2), ("m", 3, 1), ("c", 0, 1), ("w", 7, 3)],
        ),
    ];
    for method in ["ackermann", "bass-gura", "canonical", "lemma-3.1"] {
        for convention in ["a-kc", "a+lc"] {
            let base = [
                "gain",
                "--a",
                MSD_A,
                "--c",
                "[1 0]",
                "--poles",
                "-w, -w",
                "--method",
                method,
                "--convention",
                convention,
                "--json",
            ];
            let formula = json(&base);
            assert_eq!(formula["places_exactly"], true);
            assert_eq!(
                formula["parameters"],
                serde_json::json!(["c", "k", "m", "w"])
            );
            for (at, values) in &points {
                let mut with_at = base.to_vec();
                with_at.extend(["--at", at]);
                let numeric = gain_entries(&json(&with_at));
                let evaluated: Vec<String> = gain_entries(&formula)
                    .iter()
                    .map(|e| {
                        let mut f = parse_scalar::<Fraction>(e).expect("the formula reads back");
                        for (name, n, d) in values {
                            let v = Fraction::constant(Rational::new((*n).into(), (*d).into()));
                            f = f.substitute(name, &v);
                        }
                        f.as_rational().expect("a number").to_string()
                    })
                    .collect();
                assert_eq!(evaluated, numeric, "{method} {convention} at {at}");
            }
        }
    }
}

#[test]
fn unobservable_exactly_when_k_is_zero() {
    let v = json(&["observe", "--a", MSD_A, "--c", "[0 1]", "--json"]);
    assert_eq!(v["observable"], true);
    let numeric = |values: &str| {
        json(&[
            "observe", "--a", MSD_A, "--c", "[0 1]", "--at", values, "--json",
        ])
    };
    // det O_n as a formula is the numeric determinant at values
    let values = "k=5, m=2, c=3";
    let det = v["determinant"].as_str().expect("a determinant");
    assert_eq!(
        at(det, values),
        numeric(values)["determinant"].as_str().expect("text")
    );
    // where it vanishes, the numeric report loses the same mode
    let lost = &v["unobservable_where"][0];
    assert_eq!(lost["factor"], "k");
    assert_eq!(lost["substitution"], "k = 0");
    let there = numeric("k=0, m=2, c=3");
    assert_eq!(there["observable"], false);
    assert_eq!(lost["rank"], there["rank"]);
    let mode = lost["unobservable_polynomial"]
        .as_str()
        .expect("a polynomial");
    assert_eq!(
        mode,
        there["unobservable_polynomial"].as_str().expect("text")
    );
    assert_eq!(v["valid_unless"][0]["factor"], "m");
    let (code, out, _) = owb(&["observe", "--a", MSD_A, "--c", "[0 1]"]);
    assert_eq!(code, 0);
    assert!(out.contains("observable unless k = 0"));
    insta::assert_snapshot!(out);
}

#[test]
fn a_pair_unobservable_for_every_value_says_so() {
    let v = json(&["observe", "--a", "[a 0; 0 b]", "--c", "[1 0]", "--json"]);
    assert_eq!(v["observable"], false);
    // the lost mode as a formula is the numeric report's at values
    let numeric = json(&[
        "observe",
        "--a",
        "[a 0; 0 b]",
        "--c",
        "[1 0]",
        "--at",
        "a=1, b=3",
        "--json",
    ]);
    let formula = parse_scalar::<Fraction>(v["unobservable_polynomial"].as_str().expect("text"))
        .expect("reads back")
        .substitute("b", &Fraction::constant(Rational::from_integer(3.into())));
    assert_eq!(
        observer_workbench::algebra::Ring::to_input(&formula),
        numeric["unobservable_polynomial"].as_str().expect("text")
    );
}

#[test]
fn canonical_forms_in_symbols() {
    let (code, out, _) = owb(&["canonical", "--a", MSD_A, "--c", "[1 0]", "--b", "[0; 1/m]"]);
    assert_eq!(code, 0);
    assert!(out.contains("the same transformation"));
    insta::assert_snapshot!(out);
}

#[test]
fn state_feedback_for_the_steering_model() {
    // a double integrator with gain γ on the input: K places s² + 2ζω s + ω²
    let args = [
        "feedback",
        "--a",
        "[0 1; 0 0]",
        "--b",
        "[g; 1]",
        "--poly",
        "s^2 + 2*zeta*w*s + w^2",
    ];
    let (code, out, _) = owb(&args);
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("identically"));
    // the formula at values is what the numeric design computes there
    let mut with_json = args.to_vec();
    with_json.push("--json");
    let formula = json(&with_json);
    assert_eq!(formula["places_exactly"], true);
    for values in ["g=2, w=3, zeta=1/2", "g=-1/3, w=1/5, zeta=7"] {
        let mut numeric = with_json.clone();
        numeric.extend(["--at", values]);
        let expected = gain_entries(&json(&numeric));
        let evaluated: Vec<String> = gain_entries(&formula)
            .iter()
            .map(|e| at(e, values))
            .collect();
        assert_eq!(evaluated, expected, "at {values}");
    }
    insta::assert_snapshot!(out);
}

#[test]
fn observer_based_control_in_symbols() {
    // the double integrator; its observer gain given, or designed from its polynomial
    let plant = [
        "control",
        "--a",
        "[0 1; 0 0]",
        "--b",
        "[0; 1]",
        "--c",
        "[1 0]",
    ];
    let feedback = ["--feedback-poly", "s^2 + 2*zeta*w*s + w^2"];
    let (code, out, _) = owb(&[&plant[..], &["--l", "[-2*w; -w^2]"], &feedback].concat());
    assert_eq!(code, 0);
    assert!(out.contains("Separation principle: det(sI − A_cl) = det"));
    // the same L designed in symbols from its polynomial gives the same report
    let designed = owb(&[
        &plant[..],
        &["--observer-poly", "s^2 + 2*w*s + w^2"],
        &feedback,
    ]
    .concat());
    assert_eq!(designed, (0, out.clone(), String::new()));
    insta::assert_snapshot!(out);
}

#[test]
fn butterworth_with_a_symbolic_time_constant() {
    let base = [
        "gain",
        "--a",
        "[0 1; 0 0]",
        "--c",
        "[1 0]",
        "--butterworth",
        "T",
        "--json",
    ];
    let v = json(&base);
    assert_eq!(v["valid_unless"][0]["factor"], "T");
    assert_eq!(v["places_exactly"], true);
    // against the numeric Butterworth family (its own code path) at T = 1/2 and T = 3: the
    // formula's entries hold √2, so compare the exact texts the workbench prints
    for t in ["1/2", "3"] {
        let numeric = gain_entries(&json(&[
            "gain",
            "--a",
            "[0 1; 0 0]",
            "--c",
            "[1 0]",
            "--butterworth",
            t,
            "--json",
        ]));
        let evaluated: Vec<String> = gain_entries(&v)
            .iter()
            .map(|e| {
                let f = parse_scalar::<Fraction>(e).expect("reads back").substitute(
                    "T",
                    &Fraction::constant(parse_scalar::<Rational>(t).unwrap()),
                );
                let q = f.as_quadratic().expect("a number of Q(√2)");
                observer_workbench::algebra::Ring::to_input(&q)
            })
            .collect();
        assert_eq!(evaluated, numeric, "T = {t}");
    }
}

#[test]
fn refusals_name_the_flag_and_the_way_out() {
    let (code, _, err) = owb(&[
        "gain",
        "--a",
        "[0 1; -s 0]",
        "--c",
        "[1 0]",
        "--poles",
        "-1,-2",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("'s' is reserved"), "{err}");
    let (code, _, err) = owb(&[
        "kalman",
        "--a",
        "[0 1; -k 0]",
        "--c",
        "[1 0]",
        "--b",
        "[0; 1]",
        "--input-noise",
        "[1]",
        "--output-noise",
        "[1]",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("--at k=…"), "{err}");
    let (code, _, err) = owb(&[
        "gain", "--a", MSD_A, "--c", "[1 0]", "--poles", "-w,-w", "--at", "k=1",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("without a value"), "{err}");
    let (code, _, err) = owb(&[
        "gain", "--a", MSD_A, "--c", "[1 0]", "--poles", "-w,-w", "--float",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("--at"), "{err}");
    let nine: Vec<String> = (0..13).map(|i| format!("p{i}")).collect();
    let a = format!("[{} 0; 0 0]", nine.join("+"));
    let (code, _, err) = owb(&["observe", "--a", &a, "--c", "[1 1]"]);
    assert_eq!(code, 2);
    assert!(err.contains("at most 12"), "{err}");
}

/// A dense symbolic plant whose gcds would run for minutes is refused by the work budget.
#[test]
fn the_work_budget_stops_a_runaway_design() {
    let names = ["a", "b", "c", "d", "e1", "f", "g", "h"];
    let rows: Vec<String> = (0..6)
        .map(|i| {
            (0..6)
                .map(|j| format!("{}+{}", names[(i + j) % 8], names[(i * j + 3) % 8]))
                .collect::<Vec<_>>()
                .join(" ")
        })
        .collect();
    let a = format!("[{}]", rows.join("; "));
    let (code, _, err) = owb(&[
        "gain",
        "--a",
        &a,
        "--c",
        "[1 0 0 0 0 1]",
        "--poles",
        "-1,-2,-3,-4,-5,-6",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("units of work"), "{err}");
    assert!(parse_matrix::<Rational>("[1 2]").is_ok());
}

fn check(exercise: &str, answers: &str) -> serde_json::Value {
    // a folder per call: the tests run in parallel in one process
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!(
        "owb-formula-{}-{call}-{exercise}",
        std::process::id()
    ));
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    let file = dir.join(format!("answers-{}.toml", answers.len()));
    std::fs::write(&file, answers).expect("the answers are written");
    let path = format!("worked_examples/exercises/{exercise}.toml");
    let (code, out, err) = owb(&["check", &path, file.to_str().expect("utf-8"), "--json"]);
    std::fs::remove_dir_all(&dir).ok();
    assert!(code == 0 || code == 1, "{err}");
    serde_json::from_str(&out).expect("valid JSON")
}

fn part<'a>(report: &'a serde_json::Value, id: &str) -> &'a serde_json::Value {
    report["parts"]
        .as_array()
        .expect("parts")
        .iter()
        .find(|p| p["id"] == id)
        .expect("the part")
}

#[test]
fn formulas_are_checked_as_identities() {
    // the gain written in another but equal form is right; the desired polynomial expanded
    // or factored is right
    let r = check(
        "formula-mass-spring-damper",
        "[answers]\ndesired = \"s^2 + 2 w s + w^2\"\nK = \"[2*w - c/m; w^2 - k/m - (2*w - c/m)*c/m]\"\ndet_velocity = \"k/m\"\n",
    );
    for id in ["desired", "K", "det_velocity"] {
        assert_eq!(part(&r, id)["verdict"], "correct", "{id}: {r}");
    }
    let r = check(
        "formula-mass-spring-damper",
        "[answers]\ndesired = \"(s - w)^2\"\nK = \"[-(2*w - c/m); -(w^2 - k/m - (2*w - c/m)*c/m)]\"\ndet_velocity = \"-k/m\"\n",
    );
    assert_eq!(part(&r, "desired")["verdict"], "wrong");
    assert_eq!(part(&r, "K")["mistake"], "sign_convention");
    assert_eq!(part(&r, "det_velocity")["mistake"], "negated");
}

#[test]
fn symbolic_mistakes_are_named() {
    // K_o = c − a, the gain left in canonical coordinates
    let r = check(
        "formula-mass-spring-damper",
        "[answers]\nK = \"[2*w - c/m; w^2 - k/m]\"\n",
    );
    assert_eq!(part(&r, "K")["mistake"], "canonical_coordinates");
    // one entry wrong
    let r = check(
        "formula-diruscio-time-constant",
        "[answers]\nK_double_root = \"[2/T + a + 1/(a T^2); 1/(a T^2)]\"\nK_butterworth = \"[-1/(a T^2); sqrt(2)/T + a + 1/(a T^2)]\"\n",
    );
    assert_eq!(part(&r, "K_double_root")["mistake"], "slip");
    assert_eq!(part(&r, "K_butterworth")["mistake"], "reversed");
    let r = check(
        "formula-double-integrator",
        "[answers]\nL = \"[-2*zeta*w; -w^2]\"\nF = \"[w^2, 2*zeta*w]\"\n",
    );
    assert_eq!(part(&r, "L")["verdict"], "correct");
    assert_eq!(part(&r, "F")["mistake"], "feedback_sign");
}

#[test]
fn right_only_at_some_values_is_said_with_the_values() {
    // the double-root gain with T fixed at 1/8 inside the formula: right at T = 1/8 only
    let r = check(
        "formula-diruscio-time-constant",
        "[answers]\nK_double_root = \"[16 + a + 1/(a T^2); -1/(a T^2)]\"\n",
    );
    let p = part(&r, "K_double_root");
    assert_eq!(p["mistake"], "only_at_some_values", "{p}");
    let feedback = p["feedback"].as_str().expect("feedback");
    assert!(feedback.contains("T = 1/8"), "{feedback}");
    assert_eq!(p["score"], 0.5);
}

/// Found by the `cli` fuzz target (session 9): a parameter beside a 100-digit decimal made the
/// controller's transfer-function gcds run for minutes (num-bigint's binary gcd on growing
/// coefficients, which the meter then counted by terms only); work was then weighted by the
/// size of the numbers and the request refused at once. Since session 20 those gcds are one
/// multivariate gcd each (`poly::fraction_gcd`) instead of Euclid's algorithm over the rational
/// functions, and the request is answered, still at once.
#[test]
fn big_coefficients_beside_a_parameter_finish_quickly() {
    let started = std::time::Instant::now();
    let (code, out, err) = owb(&[
        "control", "--a", "[0 1; 2 1]", "--b", "[0; 1]", "--c",
        "[5.555455555 05222222222222000000000000000000000000000000000000000000000000000000000000000000000000000000000000014--repe395206007012]",
        "--l", "[2; 1]", "--f", "[0 --3]", "--convention", "a-kc",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("Separation principle: det(sI − A_cl) = det(sI − (A + BF))·det(sI − (A + LC)), identically in s and repe395206007012"),
        "{out}"
    );
    assert!(
        started.elapsed().as_secs() < 10,
        "took {:?}",
        started.elapsed()
    );
}

/// Every command that computes with numbers takes `--at` for the letters in any of its
/// matrices, and names it when a letter has no value.
#[test]
fn numeric_commands_take_values_for_letters() {
    let cases: [(&[&str], &[&str]); 3] = [
        (
            &[
                "zoh",
                "--a",
                "[0 1; 0 -k]",
                "--b",
                "[0; 1]",
                "--period",
                "T",
                "--json",
            ],
            &[
                "zoh",
                "--a",
                "[0 1; 0 -2]",
                "--b",
                "[0; 1]",
                "--period",
                "1/2",
                "--json",
            ],
        ),
        (
            &[
                "dlqe",
                "--a",
                "[1 k; 0 1]",
                "--c",
                "[1 0]",
                "--qn",
                "[q 0; 0 q]",
                "--rn",
                "[1]",
                "--json",
            ],
            &[
                "dlqe",
                "--a",
                "[1 2; 0 1]",
                "--c",
                "[1 0]",
                "--qn",
                "[1/2 0; 0 1/2]",
                "--rn",
                "[1]",
                "--json",
            ],
        ),
        (
            &[
                "kalman",
                "--a",
                "[0 1; -k 0]",
                "--b",
                "[0; k]",
                "--c",
                "[1 0]",
                "--input-noise",
                "[q]",
                "--output-noise",
                "[1]",
                "--json",
            ],
            &[
                "kalman",
                "--a",
                "[0 1; -2 0]",
                "--b",
                "[0; 2]",
                "--c",
                "[1 0]",
                "--input-noise",
                "[1/2]",
                "--output-noise",
                "[1]",
                "--json",
            ],
        ),
    ];
    for (letters, numbers) in cases {
        let (code, _, err) = owb(letters);
        assert_eq!(code, 2, "{letters:?}");
        assert!(err.contains("--at"), "{err}");
        let mut valued = letters.to_vec();
        valued.extend(["--at", "k=2, T=1/2, q=1/2"]);
        assert_eq!(json(&valued), json(numbers), "{letters:?}");
    }
}

/// Discrete time with parameters (a double integrator sampled with period T): the dead-beat
/// gain and the pole-placing gains as formulas, their error polynomial an identity, dead-beat
/// proved by the powers of the error matrix, the current estimator A⁻¹K — and every formula,
/// evaluated at values, the gain the numeric command computes there with `--at`.
#[test]
fn discrete_time_designs_with_parameters() {
    let desired: [&[&str]; 3] = [
        &["--deadbeat"],
        &["--poles", "p, p/2"],
        &["--poly", "z^2 - a*z + a^2/4"],
    ];
    let points = ["T=1/2,p=1/3,a=1/5", "T=3,p=-1/4,a=2/3"];
    for estimator in ["prediction", "current"] {
        for d in desired {
            let mut base = vec!["discrete", "--a", "[1 T; 0 1]", "--c", "[1 0]"];
            base.extend_from_slice(d);
            base.extend(["--estimator", estimator, "--json"]);
            let formula = json(&base);
            assert_eq!(formula["places_exactly"], true, "{base:?}");
            assert!(formula["parameters"]
                .as_array()
                .is_some_and(|p| p.contains(&"T".into())));
            for point in points {
                let mut with_at = base.clone();
                with_at.extend(["--at", point]);
                let numeric = json(&with_at);
                let evaluate = |v: &serde_json::Value, key: &str| -> Vec<String> {
                    v[key]
                        .as_array()
                        .map(|rows| {
                            rows.iter()
                                .flat_map(|r| r.as_array().cloned().unwrap_or_default())
                                .map(|x| at(x.as_str().expect("text"), point))
                                .collect()
                        })
                        .unwrap_or_default()
                };
                for key in ["gain", "current_gain", "error_matrix"] {
                    let numbers: Vec<String> = numeric[key]
                        .as_array()
                        .map(|rows| {
                            rows.iter()
                                .flat_map(|r| r.as_array().cloned().unwrap_or_default())
                                .map(|x| at(x.as_str().expect("text"), point))
                                .collect()
                        })
                        .unwrap_or_default();
                    assert_eq!(
                        evaluate(&formula, key),
                        numbers,
                        "{key} of {base:?} at {point}"
                    );
                }
                assert_eq!(
                    formula["deadbeat_steps"], numeric["deadbeat_steps"],
                    "{base:?}"
                );
            }
        }
    }
    let (code, out, _) = owb(&[
        "discrete",
        "--a",
        "[1 T; 0 1]",
        "--c",
        "[1 0]",
        "--deadbeat",
    ]);
    assert_eq!(code, 0);
    assert!(out.contains("K = [2; 1/T]"), "{out}");
    assert!(out.contains("(error matrix)^2 = 0 identically"), "{out}");
    assert!(out.contains("valid for T ≠ 0"), "{out}");
    insta::assert_snapshot!(out);
    // the transcendental map needs numbers
    let (code, _, err) = owb(&[
        "discrete",
        "--a",
        "[1 T; 0 1]",
        "--c",
        "[1 0]",
        "--continuous-poles",
        "-1, -2",
        "--period",
        "1",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("--at"), "{err}");
}

/// A reduced-order observer with parameters (the mass–spring–damper measured at its position,
/// and a third-order companion plant measured at x₁): the gain, F, G, H and D_y as formulas,
/// the error polynomial an identity — and each formula at values equal to the numeric
/// command's matrices there (`--at`), in both conventions.
#[test]
fn reduced_order_designs_with_parameters() {
    let cases: [(&[&str], &str); 2] = [
        (
            &[
                "--a", MSD_A, "--c", "[1 0]", "--b", "[0; 1/m]", "--poles", "-w",
            ],
            "k=2,m=1/2,c=3,w=4",
        ),
        (
            &[
                "--a",
                "[0 1 0; 0 0 1; -a0 -a1 -a2]",
                "--c",
                "[1 0 0]",
                "--poles",
                "-p, -2*p",
            ],
            "a0=1,a1=-2,a2=3/4,p=5",
        ),
    ];
    for (plant, point) in cases {
        for convention in ["a-kc", "a+lc"] {
            let mut base = vec!["reduced"];
            base.extend_from_slice(plant);
            base.extend(["--convention", convention, "--json"]);
            let formula = json(&base);
            assert_eq!(formula["places_exactly"], true, "{base:?}");
            let mut with_at = base.clone();
            with_at.extend(["--at", point]);
            let numeric = json(&with_at);
            for key in ["gain", "f", "g", "h", "direct", "from_w"] {
                let entries = |v: &serde_json::Value, evaluate: bool| -> Vec<String> {
                    v[key]
                        .as_array()
                        .map(|rows| {
                            rows.iter()
                                .flat_map(|r| r.as_array().cloned().unwrap_or_default())
                                .map(|x| {
                                    let t = x.as_str().expect("text");
                                    if evaluate {
                                        at(t, point)
                                    } else {
                                        t.to_string()
                                    }
                                })
                                .collect()
                        })
                        .unwrap_or_default()
                };
                assert_eq!(
                    entries(&formula, true),
                    entries(&numeric, false),
                    "{key} of {base:?} at {point}"
                );
            }
            assert_eq!(
                at(formula["noise_gain"].as_str().expect("text"), point),
                numeric["noise_gain"].as_str().expect("text"),
                "{base:?}"
            );
        }
    }
    let (code, out, _) = owb(&[
        "reduced", "--a", MSD_A, "--c", "[1 0]", "--b", "[0; 1/m]", "--poles", "-w",
    ]);
    assert_eq!(code, 0);
    assert!(out.contains("L (A₂₂ − L A₁₂) = [(m*w - c)/m]"), "{out}");
    assert!(out.contains("valid for m ≠ 0"), "{out}");
    insta::assert_snapshot!(out);
    // C fixes the coordinates: with a parameter in C the way out is named
    let (code, _, err) = owb(&["reduced", "--a", MSD_A, "--c", "[1 q]", "--poles", "-w"]);
    assert_eq!(code, 2);
    assert!(err.contains("--c") && err.contains("--at"), "{err}");
}

/// Every operation of the rational functions is charged to the work meter before it multiplies
/// (a cli fuzz finding: a gain with seven parameters, i and √2 ran 1.3 s after the meter had run
/// out, in divisions that were never charged); the budget now stops it at once.
#[test]
fn the_work_budget_stops_divisions_too() {
    let start = std::time::Instant::now();
    let (code, _, err) = owb(&[
        "gain",
        "--a",
        "[0 1 0; 0 0 1; h-1 -2 -pylo3eeeeee---a-geeeeeeeeeeeeeeeeeeeee-c-eeonventio--periodmethode]",
        "--c",
        "[--i--indexndex5 0 -ncoe-vntion0]",
        "--butterworth",
        "1-2",
    ]);
    let took = start.elapsed();
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("units of work"), "{err}");
    assert!(took < std::time::Duration::from_secs(1), "took {took:?}");
}

/// `owb detectable` with parameters: the decomposition for generic values, the observable
/// part's gain as a formula that is the numeric command's gain at values, and detectability as
/// a condition on the parameters that the numeric command confirms on either side.
#[test]
fn detectability_as_a_condition_on_the_parameters() {
    let plant = [
        "detectable",
        "--a",
        "[0 1 0; -k/m -c/m 0; 0 0 -d]",
        "--c",
        "[1 0 0]",
        "--poles",
        "-w, -w",
    ];
    let mut with_json = plant.to_vec();
    with_json.push("--json");
    let formula = json(&with_json);
    assert_eq!(formula["rank"], 2);
    assert_eq!(formula["polynomial_checks"], true);
    assert_eq!(formula["detectable"], serde_json::Value::Null);
    assert_eq!(formula["detectable_when"], serde_json::json!(["d > 0"]));
    for (point, detectable) in [
        ("k=2,m=1/2,c=3,w=4,d=5", true),
        ("k=1,m=2,c=1,w=1,d=-1", false),
    ] {
        let mut numeric_args = with_json.clone();
        numeric_args.extend(["--at", point]);
        let numeric = json(&numeric_args);
        assert_eq!(numeric["detectable"], detectable, "{point}");
        let evaluated: Vec<String> = gain_entries(&formula)
            .iter()
            .map(|x| at(x, point))
            .collect();
        assert_eq!(evaluated, gain_entries(&numeric), "{point}");
    }
    // a fixed mode that is a number decides for every value, either way
    for (a, decided) in [("[-a 0; 1 -2]", true), ("[-a 0; 1 3]", false)] {
        let v = json(&[
            "detectable",
            "--a",
            a,
            "--c",
            "[1 0]",
            "--poles",
            "-w",
            "--json",
        ]);
        assert_eq!(v["detectable"], decided, "{a}");
        assert_eq!(v["detectable_when"], serde_json::json!([]), "{a}");
    }
    let (code, out, _) = owb(&plant);
    assert_eq!(code, 0);
    assert!(out.contains("detectable exactly when d > 0"), "{out}");
    assert!(out.contains("valid for m ≠ 0"), "{out}");
    insta::assert_snapshot!(out);
}

/// Deciding whether a desired polynomial mentions parameters reads it, and that reading is under
/// the symbolic budget too (a syntax fuzz input given to `--poly` ran into the 10 s time
/// budget: Euclid's remainder sequence over degree-25 fractions in Q(i), read before any budget
/// opened; that gcd is now fraction-free in Z[i], 0.37 s → 1.3 ms, and the reading metered).
#[test]
fn a_desired_polynomial_too_costly_to_read_is_refused_quickly() {
    let text =
        std::fs::read_to_string(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(
            "fuzz/regressions/syntax/syntax-timeout-fa800bd4bf330eca5ba1ae382fe8054e31b295af",
        ))
        .expect("the fuzz input");
    let start = std::time::Instant::now();
    let (code, _, err) = owb(&["gain", "--a", "[1]", "--c", "[1]", "--poly", text.trim()]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--poly") && err.contains("symbolic computation"),
        "{err}"
    );
    assert!(
        start.elapsed() < std::time::Duration::from_secs(5),
        "{:?}",
        start.elapsed()
    );
}

/// A mass–spring–damper's controller with both gains designed in symbols (k, c): the transfer
/// functions' gcds over the rational functions of k and c stay within the symbolic work budget
/// (Euclid's algorithm there ran out of it).
#[test]
fn a_controller_designed_in_two_parameters() {
    let plant = ["--a", "[0 1; -k -c]", "--c", "[1 0]"];
    let (observer, feedback) = ("s^2 + 9s + 20", "(s + 2)^2");
    let both = [
        "--b",
        "[0; 1]",
        "--observer-poly",
        observer,
        "--feedback-poly",
        feedback,
    ];
    let (code, out, err) = owb(&[&["control"][..], &plant, &both].concat());
    assert_eq!(code, 0, "{err}");
    // L as `owb gain` designs it for A + LC
    let poly = ["--poly", observer, "--convention", "a+lc", "--json"];
    let (code, gain, err) = owb(&[&["gain"][..], &plant, &poly].concat());
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&gain).expect("JSON");
    let entries: Vec<&str> = v["gain"]
        .as_array()
        .expect("the gain")
        .iter()
        .filter_map(|row| row[0].as_str())
        .collect();
    let l = format!("[{}]", entries.join("; "));
    assert!(out.contains(&format!("L = {l} (A + LC)")), "{l}: {out}");
    // the closed loop's denominator is the product of the two polynomials
    let p = |text: &str| parse_polynomial::<Rational>(text, "s").expect("a polynomial");
    let product = p(observer) * p(feedback);
    assert!(out.contains(&format!("({product})")), "{product}: {out}");
    assert!(out.contains("identically in s and c, k"), "{out}");
}
