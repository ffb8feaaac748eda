//! One request, every front end, one answer: the `owb` binary, the browser module's `run` (its
//! JSON request) and the book's `run` directive give the same report for the same request,
//! because all three call `api::run`. A front end that rebuilt a command or post-processed the
//! report would fail here.

mod common;

use observer_workbench::book::BookContext;
use observer_workbench::derivation::{Derivation, Step};
use serde_json::Value;

/// Requests as the browser sends them, and the same request as a command line.
const CASES: [(&str, &[&str]); 11] = [
    (
        r#"{"command": "observe", "a": "[1 0; 0 2]", "c": "[1 0]"}"#,
        &["observe", "--a", "[1 0; 0 2]", "--c", "[1 0]"],
    ),
    (
        r#"{"command": "canonical", "a": "[2 -3; 4 -5]", "c": "[-3 2]"}"#,
        &["canonical", "--a", "[2 -3; 4 -5]", "--c", "[-3 2]"],
    ),
    (
        r#"{"command": "gain", "a": "[2 -3; 4 -5]", "c": "[-3 2]", "butterworth": "1/2", "float": true}"#,
        &[
            "gain",
            "--a",
            "[2 -3; 4 -5]",
            "--c",
            "[-3 2]",
            "--butterworth",
            "1/2",
            "--float",
        ],
    ),
    (
        r#"{"command": "gain", "a": "[0 1; -2 -3]", "c": "[1 0]", "poles": "-4, -5", "method": "bass-gura", "convention": "a+lc"}"#,
        &[
            "gain",
            "--a",
            "[0 1; -2 -3]",
            "--c",
            "[1 0]",
            "--poles",
            "-4, -5",
            "--method",
            "bass-gura",
            "--convention",
            "a+lc",
        ],
    ),
    (
        r#"{"command": "feedback", "a": "[0 1; -2 -3]", "b": "[0; 1]", "repeated": "1/3"}"#,
        &[
            "feedback",
            "--a",
            "[0 1; -2 -3]",
            "--b",
            "[0; 1]",
            "--repeated",
            "1/3",
        ],
    ),
    (
        r#"{"command": "discrete", "a": "[1 1; 0 1]", "c": "[1 0]", "deadbeat": true, "estimator": "current"}"#,
        &[
            "discrete",
            "--a",
            "[1 1; 0 1]",
            "--c",
            "[1 0]",
            "--deadbeat",
            "--estimator",
            "current",
        ],
    ),
    (
        r#"{"command": "reduced", "a": "[0 1 0; 0 0 1; -1 -2 -3]", "c": "[1 0 0]", "poles": "-5, -6"}"#,
        &[
            "reduced",
            "--a",
            "[0 1 0; 0 0 1; -1 -2 -3]",
            "--c",
            "[1 0 0]",
            "--poles",
            "-5, -6",
        ],
    ),
    (
        r#"{"command": "dlqe", "a": "[2]", "c": "[1]", "qn": "[0]", "rn": "[1]"}"#,
        &[
            "dlqe", "--a", "[2]", "--c", "[1]", "--qn", "[0]", "--rn", "[1]",
        ],
    ),
    // float matrices in JSON: written straight into the command line's text, made values for
    // the browser
    (
        r#"{"command": "zoh", "a": "[0 1; -2 -3]", "b": "[0; 1]", "period": "1/10", "json": true}"#,
        &[
            "zoh",
            "--a",
            "[0 1; -2 -3]",
            "--b",
            "[0; 1]",
            "--period",
            "1/10",
            "--json",
        ],
    ),
    (
        r#"{"command": "dlqe", "a": "[1/2 1; 0 1/3]", "c": "[1 0]", "qn": "[1 0; 0 1]", "rn": "[1]", "json": true}"#,
        &[
            "dlqe",
            "--a",
            "[1/2 1; 0 1/3]",
            "--c",
            "[1 0]",
            "--qn",
            "[1 0; 0 1]",
            "--rn",
            "[1]",
            "--json",
        ],
    ),
    (
        r#"{"command": "exercise", "action": {"new": {"student": "ada", "order": "3", "key": true}}}"#,
        &[
            "exercise",
            "new",
            "--student",
            "ada",
            "--order",
            "3",
            "--key",
        ],
    ),
];

/// The book's `run` directive for these words, its report (the fenced block's body after the
/// `$ owb …` line).
fn book_report(words: &[&str]) -> String {
    let ctx = BookContext {
        root: env!("CARGO_MANIFEST_DIR").into(),
        run_commands: true,
    };
    let quoted: Vec<String> = words
        .iter()
        .map(|w| {
            if w.contains(' ') {
                format!("\"{w}\"")
            } else {
                (*w).to_string()
            }
        })
        .collect();
    let block = ctx
        .directive(&format!("run {}", quoted.join(" ")))
        .unwrap_or_else(|e| panic!("the book's directive failed: {e}"));
    let body = block
        .strip_prefix("```text\n")
        .and_then(|b| b.strip_suffix("```\n"))
        .unwrap_or_else(|| panic!("not a text block: {block}"));
    let (command_line, report) = body
        .split_once('\n')
        .expect("a command line, then the report");
    assert!(command_line.starts_with("$ owb "), "{command_line}");
    report.to_string()
}

#[test]
fn one_request_gives_one_report_in_the_command_line_the_browser_and_the_book() {
    for (json, words) in CASES {
        let (status, cli, stderr) = common::owb(words);
        assert_eq!(status, 0, "owb {words:?}: {stderr}");
        let web: Value = serde_json::from_str(&owb_web::run(json)).unwrap();
        assert_eq!(web["status"], 0, "{web}");
        assert_eq!(
            web["output"].as_str().unwrap(),
            cli,
            "the browser differs from owb for {json}"
        );
        assert_eq!(
            book_report(words),
            cli,
            "the book differs from owb for {json}"
        );
    }
}

#[test]
fn the_browsers_typeset_derivation_is_the_command_lines_json_steps() {
    for (json, words) in CASES {
        if words[0] == "exercise" {
            continue;
        }
        let mut with_json = words.to_vec();
        if !with_json.contains(&"--json") {
            with_json.push("--json");
        }
        let (status, text, _) = common::owb(&with_json);
        assert_eq!(status, 0);
        let v: Value = serde_json::from_str(&text).unwrap();
        let web: Value = serde_json::from_str(&owb_web::run(json)).unwrap();
        match v.get("steps") {
            Some(steps) => {
                let steps: Vec<Step> = serde_json::from_value(steps.clone()).unwrap();
                let latex = Derivation {
                    title: String::new(),
                    steps,
                }
                .to_latex();
                assert_eq!(web["latex"].as_str(), Some(latex.as_str()), "{json}");
            }
            None => assert!(web.get("latex").is_none(), "{json}: {web}"),
        }
    }
}

#[test]
fn a_refusal_is_the_same_message_everywhere() {
    let json = r#"{"command": "gain", "a": "[1 2; 3]", "c": "[1 0]", "poles": "-1, -2"}"#;
    let words = [
        "gain", "--a", "[1 2; 3]", "--c", "[1 0]", "--poles", "-1, -2",
    ];
    let (status, _, stderr) = common::owb(&words);
    assert_eq!(status, 2);
    let web: Value = serde_json::from_str(&owb_web::run(json)).unwrap();
    assert_eq!(web["status"], 2);
    let first = stderr.lines().next().unwrap();
    assert_eq!(
        first,
        format!("error: {}", web["error"].as_str().unwrap()),
        "{web}"
    );
    let ctx = BookContext {
        root: env!("CARGO_MANIFEST_DIR").into(),
        run_commands: true,
    };
    let book = ctx
        .directive("run gain --a \"[1 2; 3]\" --c \"[1 0]\" --poles \"-1, -2\"")
        .unwrap_err();
    let book = format!("{book:#}");
    assert!(
        book.contains(web["error"].as_str().unwrap()),
        "{book} / {web}"
    );
}

/// `--tf`: the observer canonical form realises G exactly — C (sI − A)⁻¹ B + D is G in lowest
/// terms, for proper random transfer functions — and every command that takes a plant takes it.
#[test]
fn a_transfer_function_is_realised_exactly_in_observer_canonical_form() {
    use observer_workbench::algebra::Rational;
    use observer_workbench::control::siso_transfer_function;
    use observer_workbench::syntax::parse_rational_function;
    use observer_workbench::system::observer_form_of;
    let mut seed = 7u64;
    let mut next = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((seed >> 33) % 19) as i64 - 9
    };
    for n in 1..=6usize {
        for m in 0..=n {
            let den: Vec<String> = (0..n).map(|k| format!("{}*s^{k}", next())).collect();
            let num: Vec<String> = (0..=m).map(|k| format!("{}*s^{k}", next())).collect();
            let text = format!("({})/(s^{n} + {})", num.join(" + "), den.join(" + "));
            let g = parse_rational_function::<Rational>(&text, "s").unwrap();
            match observer_form_of(&g) {
                Ok((a, b, c, d)) => {
                    let back = siso_transfer_function(&a, &b, &c, &d.get(0, 0).clone()).unwrap();
                    assert_eq!(back, g, "{text}");
                    assert_eq!(a.rows(), g.denominator().degree().unwrap());
                }
                // a zero numerator or everything cancelled: a constant
                Err(e) => assert_eq!(g.denominator().degree(), Some(0), "{text}: {e}"),
            }
        }
    }
    let tf = "(s + 1)/(s^2 + 3s + 5)";
    for words in [
        vec!["observe", "--tf", tf],
        vec!["canonical", "--tf", tf],
        vec!["gain", "--tf", tf, "--poles", "-4, -5"],
        vec!["discrete", "--tf", tf, "--deadbeat"],
        vec!["reduced", "--tf", tf, "--poles", "-6"],
        vec![
            "control",
            "--tf",
            tf,
            "--l",
            "[6; 15]",
            "--feedback-poly",
            "s^2 + 4s + 4",
        ],
        vec![
            "kalman",
            "--tf",
            tf,
            "--input-noise",
            "1",
            "--output-noise",
            "1",
        ],
        vec!["perfect", "--tf", tf],
    ] {
        let (status, out, err) = common::owb(&words);
        assert_eq!(status, 0, "{words:?}: {err}");
        assert!(
            out.starts_with("Plant from --tf: G(s) = (s + 1)/(s^2 + 3s + 5)"),
            "{out}"
        );
        let mut json = words.clone();
        json.push("--json");
        let (_, out, _) = common::owb(&json);
        let v: Value = serde_json::from_str(&out).unwrap();
        assert_eq!(v["realisation"]["a"][1][0], "-5", "{v}");
    }
    for (tf, refusal) in [
        ("s^3/(s + 1)", "improper"),
        ("(s + 1)/(s + 1)", "constant"),
        ("1/(s + ", "in --tf"),
    ] {
        let (status, _, err) = common::owb(&["observe", "--tf", tf]);
        assert_eq!(status, 2);
        assert!(err.contains(refusal), "{tf}: {err}");
    }
}

/// The playground's "any command" requests (as its script reads the `key = value` lines) each
/// run, and the page offers every command the browser module runs.
#[test]
fn the_playgrounds_example_requests_all_run() {
    use observer_workbench::api::{run, Command};
    use observer_workbench::book::widgets::ANY_COMMAND_EXAMPLES;
    let numbers = [
        "output",
        "starts",
        "seed",
        "grid",
        "time-limit",
        "tolerance",
    ];
    for (command, fields) in ANY_COMMAND_EXAMPLES {
        let mut request = serde_json::json!({ "command": command });
        for line in fields.lines() {
            let (key, value) = line.split_once('=').unwrap();
            let (key, value) = (key.trim(), value.trim());
            request[key] = if value == "true" {
                Value::Bool(true)
            } else if numbers.contains(&key) {
                // as JSON.stringify writes Number(value): 4, not 4.0
                match value.parse::<u64>() {
                    Ok(k) => serde_json::json!(k),
                    Err(_) => serde_json::json!(value.parse::<f64>().unwrap()),
                }
            } else {
                Value::String(value.into())
            };
        }
        let c = Command::from_value(&request).unwrap_or_else(|e| panic!("{command}: {e}"));
        let report = run(c).unwrap_or_else(|f| panic!("{command}: {:#}", f.error));
        assert!(!report.text.is_empty(), "{command}");
    }
    let offered: Vec<&str> = ANY_COMMAND_EXAMPLES.iter().map(|(c, _)| *c).collect();
    for name in Command::IN_MEMORY {
        assert!(
            name == "exercise" || offered.contains(&name),
            "{name} not in the playground"
        );
    }
}
