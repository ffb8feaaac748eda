//! The browser's functions, run natively: each answers as the command line does, and refuses bad
//! input with a JSON error (never a panic). The same functions run in Chromium in
//! `book/browser-test/`.

use observer_workbench::api::{self, Command};
use observer_workbench::exercise::generate::Settings;

/// What `owb ARGS` prints: the words read as the command line reads them, the request run by
/// the library function the binary calls (`tests/front_ends.rs` compares with the binary
/// itself). `None` when the command fails.
fn run_captured(args: &[&str]) -> (Option<()>, String) {
    let command = Command::from_words(args).expect("a valid command line");
    match api::run(command) {
        Ok(r) => (Some(()), r.text),
        Err(f) => (None, f.partial.text),
    }
}
use serde_json::Value;

fn json(s: &str) -> Value {
    serde_json::from_str(s).expect("the browser functions return JSON")
}

fn root(path: &str) -> String {
    format!("{}/../{path}", env!("CARGO_MANIFEST_DIR"))
}

fn read(path: &str) -> String {
    std::fs::read_to_string(root(path)).unwrap()
}

#[test]
fn check_gives_owb_checks_report_for_the_same_answers() {
    let exercise = read("worked_examples/exercises/stoustrup-pole-assignment.toml");
    // a wrong gain (the other sign convention) and an unreadable part
    let answers =
        "exercise = \"stoustrup-pole-assignment\"\n[answers]\nL = \"[6; 12]\"\nO = \"[-3 2; 2\"\n";
    let dir = std::env::temp_dir().join(format!("owb-web-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("answers.toml");
    std::fs::write(&file, answers).unwrap();
    let (_, cli) = run_captured(&[
        "check",
        &root("worked_examples/exercises/stoustrup-pole-assignment.toml"),
        file.to_str().unwrap(),
        "--json",
    ]);
    let cli = json(&cli);
    let web = json(&owb_web::check(&exercise, answers));
    // the student's name is the answer file's stem on the command line, "student" here
    assert_eq!(cli["parts"], web["report"]["parts"], "{web}");
    assert_eq!(cli["score"], web["report"]["score"]);
    assert!(web["text"].as_str().unwrap().contains("✘ L"));
    // what was read, typeset: the vector the student typed
    assert!(
        web["read"]["L"].as_str().unwrap().contains("matrix"),
        "{web}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn check_refuses_bad_files_with_where() {
    let exercise = read("worked_examples/exercises/stoustrup-pole-assignment.toml");
    let out = json(&owb_web::check(&exercise, "[answers]\nL = [1, 2\n"));
    let e = out["error"].as_str().unwrap();
    assert!(e.starts_with("answers.toml:"), "{e}");
    let out = json(&owb_web::check("id = 3", "[answers]\n"));
    assert!(
        out["error"].as_str().unwrap().contains("exercise.toml"),
        "{out}"
    );
    let out = json(&owb_web::check(
        &exercise,
        "exercise = \"another\"\n[answers]\nL = \"[1; 2]\"\n",
    ));
    assert!(
        out["error"].as_str().unwrap().contains("'another'"),
        "{out}"
    );
}

#[test]
fn a_students_variant_is_the_one_owb_exercise_new_generates() {
    let v = json(&owb_web::variant(" Ada ", "3", "a-kc", "pole-placement"));
    let (outcome, text) = run_captured(&["exercise", "new", "--student", "ada", "--order", "3"]);
    assert!(outcome.is_some());
    assert_eq!(v["toml"].as_str().unwrap(), text);
    assert_eq!(
        v["id"].as_str().unwrap(),
        Settings::for_student("ada", 3, 3, "a-kc").id()
    );
    assert_ne!(
        json(&owb_web::variant("grace", "3", "a-kc", "pole-placement"))["id"],
        v["id"],
        "two students, one exercise"
    );
    let db = json(&owb_web::variant("ada", "2", "a-kc", "dead-beat"));
    let (_, text) = run_captured(&[
        "exercise",
        "new",
        "--kind",
        "dead-beat",
        "--student",
        "ada",
        "--order",
        "2",
    ]);
    assert_eq!(db["toml"].as_str().unwrap(), text);
    // read like the book's exercises: no seed in the title, the system typeset from the
    // exercise's own matrices, the steps numbered, a hint for every part
    for v in [&v, &db] {
        let title = v["title"].as_str().unwrap();
        let seed = Settings::for_student("ada", 2, 2, "a-kc").seed.to_string();
        assert!(!title.contains("seed") && !title.contains(&seed), "{title}");
        let blocks = v["statement_blocks"].as_array().unwrap();
        assert!(
            blocks.iter().any(|b| b["math"]
                .as_str()
                .is_some_and(|m| m.starts_with("A = \\begin{bmatrix}") && m.contains("C = "))),
            "{blocks:?}"
        );
        let steps = blocks.iter().find_map(|b| b["steps"].as_array()).unwrap();
        assert!(steps.len() >= 4, "{steps:?}");
        assert!(steps
            .iter()
            .all(|s| !s.as_str().unwrap().starts_with(char::is_numeric)));
        for p in v["parts"].as_array().unwrap() {
            assert!(p["hint"].as_str().is_some_and(|h| !h.is_empty()), "{p}");
        }
    }
    for (student, order, convention, kind) in [
        ("", "3", "a-kc", "pole-placement"),
        ("x", "9", "a-kc", "pole-placement"),
        ("x", "3", "b", "pole-placement"),
        ("x", "3", "a-kc", "nonsense"),
        ("x", "1", "a-kc", "reduced-order"),
    ] {
        let out = json(&owb_web::variant(student, order, convention, kind));
        assert!(out["error"].is_string(), "{out}");
    }
}

#[test]
fn run_prints_what_owb_prints_and_typesets_the_derivation() {
    let args = [
        "gain",
        "--a",
        "[2 -3; 4 -5]",
        "--c",
        "[-3 2]",
        "--poles",
        "-4, -5",
        "--float",
    ];
    let request = r#"{"command": "gain", "a": "[2 -3; 4 -5]", "c": "[-3 2]", "poles": "-4, -5", "float": true}"#;
    let out = json(&owb_web::run(request));
    let (_, text) = run_captured(&args);
    assert_eq!(out["status"], 0);
    assert_eq!(out["output"].as_str().unwrap(), text);
    assert!(out["latex"]
        .as_str()
        .unwrap()
        .starts_with("\\begin{aligned}"));
    let bad = json(&owb_web::run(
        r#"{"command": "gain", "a": "[1 2; 3]", "c": "[1 0]", "poles": "-1, -2"}"#,
    ));
    assert_eq!(bad["status"], 2);
    assert!(bad["error"].as_str().unwrap().contains("--a"), "{bad}");
    for refused in [
        r#"{"command": "verify"}"#,
        r#"{"command": "simulate", "example": "x"}"#,
        r#"{"command": "exercise", "action": {"new": {"seed": 1, "out": "x"}}}"#,
        r#"{"command": "gain", "a": "[1]", "c": "[1]", "poles": "-1", "polls": "-2"}"#,
        r#"{"command": "gain", "a": "[1]"}"#,
        r#"{"command": "nope"}"#,
        r#"["gain", "--a", "[1]"]"#,
        "[]",
        "{",
        r#"[1]"#,
    ] {
        assert!(
            json(&owb_web::run(refused))["error"].is_string(),
            "{refused}"
        );
    }
}

#[test]
fn verify_runs_a_worked_example_from_its_text() {
    let raw = read("worked_examples/stoustrup-pole-assignment.toml");
    let out = json(&owb_web::verify("stoustrup-pole-assignment", &raw));
    assert!(out["text"].as_str().unwrap().contains("holds"), "{out}");
    assert_eq!(out["json"]["summary"]["mismatch"], 0);
    let broken = raw.replacen("[[claims]]", "[[claims]]\nnonsense = ", 1);
    assert!(json(&owb_web::verify("x", &broken))["error"].is_string());
}
