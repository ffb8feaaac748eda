//! Issue 6: exercises checked with feedback that names the mistake, batch grading, generated
//! exercises.

mod common;
use common::owb;
use observer_workbench::algebra::Ring;
use observer_workbench::exercise::diagnose::diagnose;
use observer_workbench::exercise::generate::{pole_placement, Settings};
use observer_workbench::exercise::{
    answer_key, check_answers, load_exercise, AnswerFile, AnswerKey, PartVerdict,
};
use proptest::prelude::*;
use std::path::Path;

fn key(id: &str) -> AnswerKey {
    let path = format!("worked_examples/exercises/{id}.toml");
    let (ex, _) = load_exercise(Path::new(&path)).unwrap();
    answer_key(&path, &ex).unwrap()
}

/// `owb grade` of Stoustrup's pole-assignment exercise over `subs` into `csv`.
fn grade(subs: &Path, csv: &Path, more: &[&str]) -> (i32, String, String) {
    let mut args = vec![
        "grade",
        "stoustrup-pole-assignment",
        subs.to_str().unwrap(),
        "--csv",
        csv.to_str().unwrap(),
    ];
    args.extend_from_slice(more);
    owb(&args)
}

fn mistake(key: &AnswerKey, part: &str, answer: &str) -> Option<&'static str> {
    let p = key.part(part).unwrap();
    diagnose(key, p, answer).0.map(|d| d.mistake.name())
}

#[test]
fn every_exercise_has_a_computable_key() {
    let dir = Path::new("worked_examples/exercises");
    let mut count = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|x| x == "toml") {
            let (ex, _) = load_exercise(&path).unwrap();
            let k = answer_key(&path.display().to_string(), &ex).unwrap();
            assert_eq!(k.parts.len(), ex.parts.len());
            // the key answers itself
            let answers = AnswerFile {
                answers: k
                    .parts
                    .iter()
                    .map(|p| (p.spec.id.clone(), p.value.input()))
                    .collect(),
                ..AnswerFile::default()
            };
            assert!(
                check_answers(&k, &answers, "key").all_correct(),
                "{}",
                path.display()
            );
            count += 1;
        }
    }
    assert!(count >= 5);
}

/// Realistic wrong answers, each with the diagnosis it must get.
#[test]
fn each_mistake_kind_is_named() {
    let st = key("stoustrup-pole-assignment");
    // L = (−6, −12) in A + LC
    assert_eq!(mistake(&st, "L", "[6; 12]"), Some("sign_convention"));
    assert_eq!(
        mistake(&st, "L", "[-6; -18]"),
        Some("canonical_coordinates")
    );
    assert_eq!(mistake(&st, "L", "[-6 -12]"), Some("transposed"));
    assert_eq!(mistake(&st, "L", "[-12; -6]"), Some("reversed"));
    assert_eq!(mistake(&st, "L", "[-6; -13]"), Some("slip"));
    assert_eq!(mistake(&st, "O", "[-3 2; 2 -2]"), Some("slip"));
    assert_eq!(mistake(&st, "T", "[-3 2; -7 5]"), Some("inverse"));
    assert_eq!(
        mistake(&st, "A_o", "[-3 -2; 1 0]"),
        Some("other_canonical_form")
    );
    assert_eq!(
        mistake(&st, "open_loop", "-(s^2 + 3s + 2)"),
        Some("negated")
    );
    assert_eq!(mistake(&st, "L", "[1; 2]"), None);
    let dr = key("diruscio-example-7-1");
    // gain for T = 0.5 (the plant's time constant) instead of T = 0.125
    assert_eq!(
        mistake(&dr, "K_butterworth", "[-1.1716; 2]"),
        Some("wrong_polynomial")
    );
    // Butterworth where a double root was asked
    assert_eq!(
        mistake(&dr, "double_root", "s^2 + 8 sqrt(2) s + 64"),
        Some("wrong_polynomial")
    );
    assert_eq!(
        mistake(&dr, "K_double_root", "[18; -32]"),
        Some("sign_convention")
    );
    let oc = key("stoustrup-observer-based-control");
    assert_eq!(
        mistake(&oc, "controller", "108 (s + 7/3)/(s^2 + 15 s + 74)"),
        Some("negated")
    );
}

/// A wrong gain that is the right gain of a neighbouring problem is named as that problem,
/// before any transformation of the key: the RC ladder's gain for the last node, [14; 14; 6],
/// is also the first node's gain reversed (the ladder is symmetric), and the checker says the
/// first (issue 27).
#[test]
fn a_gain_for_another_output_is_named_as_that_output() {
    let rc = key("baranowski-single-output");
    let p = rc.part("G1").unwrap();
    let (d, notes) = diagnose(&rc, p, "[14; 14; 6]");
    let d = d.expect("a diagnosis");
    assert_eq!(d.mistake.name(), "another_output");
    assert!(
        d.message.contains("x₃") && d.message.contains("[0 0 1]"),
        "{}",
        d.message
    );
    // and what the answer does is still said: the poles it places
    assert!(
        notes.iter().any(|n| n.contains("observer polynomial")),
        "{notes:?}"
    );
    // the other output's gain with the other convention is no neighbouring problem of this kind
    assert_ne!(mistake(&rc, "G1", "[-14; -14; -6]"), Some("another_output"));
    // the same answer through the command line, as the page shows it
    let dir = std::env::temp_dir().join(format!("owb-another-output-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let answers = dir.join("a.toml");
    std::fs::write(&answers, "[answers]\nG1 = \"[14; 14; 6]\"\n").unwrap();
    let (code, out, _) = owb(&[
        "check",
        "baranowski-single-output",
        answers.to_str().unwrap(),
    ]);
    assert_eq!(code, 1);
    assert!(
        out.contains("another output — this is the gain for output x₃"),
        "{out}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Every mistake the checker names is explained in the exercises' README.
#[test]
fn every_named_mistake_is_in_the_readme_table() {
    let readme = std::fs::read_to_string("worked_examples/exercises/README.md").unwrap();
    for m in observer_workbench::exercise::Mistake::ALL {
        assert!(
            readme.contains(&format!("| `{}` |", m.name())),
            "{} is not in worked_examples/exercises/README.md",
            m.name()
        );
    }
}

#[test]
fn equivalent_forms_and_rounding_count_as_correct() {
    let st = key("stoustrup-pole-assignment");
    let dr = key("diruscio-example-7-1");
    let oc = key("stoustrup-observer-based-control");
    let ok = |k: &AnswerKey, part: &str, answer: &str| {
        let answers = AnswerFile {
            answers: [(part.to_string(), answer.to_string())].into(),
            ..AnswerFile::default()
        };
        let r = check_answers(k, &answers, "s");
        r.parts.iter().find(|p| p.id == part).unwrap().verdict == PartVerdict::Correct
    };
    assert!(ok(&st, "desired", "(s + 4)(s + 5)"));
    assert!(ok(&st, "desired", "s^2 + 9 s + 20"));
    assert!(ok(&oc, "controller", "(-216 s - 504)/(2 s^2 + 30 s + 148)"));
    assert!(ok(&oc, "controller", "-108 (s + 7/3)/(s^2 + 15 s + 74)"));
    // 8√2 − 34 = −22.6863 (rounded to 4 decimals), truncation −22.6862 is wrong
    assert!(ok(&dr, "K_butterworth", "[-22.6863; 32]"));
    assert!(!ok(&dr, "K_butterworth", "[-22.6862; 32]"));
    assert!(ok(&dr, "K_butterworth", "[8*sqrt(2) - 34; 32]"));
}

#[test]
fn feedback_for_three_typical_wrong_answers() {
    let st = key("stoustrup-pole-assignment");
    let dr = key("diruscio-example-7-1");
    let answers = |pairs: &[(&str, &str)]| AnswerFile {
        answers: pairs
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect(),
        ..AnswerFile::default()
    };
    let a = check_answers(
        &st,
        &answers(&[
            ("L", "[6; 12]"),
            ("L_o", "[-6; -18]"),
            ("T", "[-3 2; -7 5]"),
        ]),
        "student-a",
    );
    let b = check_answers(
        &dr,
        &answers(&[
            ("K_butterworth", "[-1.1716; 2]"),
            ("double_root", "s^2 + 11.3137 s + 64"),
        ]),
        "student-b",
    );
    insta::assert_snapshot!(format!("{}\n{}", a.text(), b.text()));
}

#[test]
fn check_and_grade_from_the_command_line() {
    let dir = std::env::temp_dir().join(format!("owb-grade-{}", std::process::id()));
    let subs = dir.join("subs");
    std::fs::create_dir_all(&subs).unwrap();
    std::fs::write(
        subs.join("ada.toml"),
        "[answers]\nL = \"[-6; -12]\"\nO = \"[-3 2; 2 -1]\"\n",
    )
    .unwrap();
    std::fs::write(subs.join("bob.toml"), "[answers]\nL = \"[6; 12]\"\n").unwrap();
    std::fs::write(subs.join("eve.toml"), "[answers\nL = ").unwrap();
    std::fs::write(subs.join("zed.toml"), "[answers]\nL = \"[6; 12\"\n").unwrap();
    let (code, out, err) = owb(&[
        "check",
        "stoustrup-pole-assignment",
        subs.join("bob.toml").to_str().unwrap(),
    ]);
    assert_eq!(code, 1, "{out}{err}");
    assert!(out.contains("sign convention"));
    let (code, _, err) = owb(&[
        "check",
        "stoustrup-pole-assignment",
        subs.join("eve.toml").to_str().unwrap(),
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("eve.toml:"), "{err}");
    let csv = dir.join("report.csv");
    let fb = dir.join("feedback");
    let (code, out, err) = grade(&subs, &csv, &["--feedback", fb.to_str().unwrap()]);
    assert_eq!(code, 0, "{out}{err}");
    let report = std::fs::read_to_string(&csv).unwrap();
    // eve's file is reported, not skipped; zed's unreadable answer is named
    assert!(
        report
            .lines()
            .any(|l| l.starts_with("eve,") && l.contains(",invalid,")),
        "{report}"
    );
    assert!(
        report
            .lines()
            .any(|l| l.starts_with("zed,") && l.contains(",unreadable,")),
        "{report}"
    );
    assert!(
        report
            .lines()
            .any(|l| l.starts_with("bob,") && l.contains(",L,wrong,sign_convention,")),
        "{report}"
    );
    assert_eq!(report.lines().filter(|l| l.starts_with("ada,")).count(), 8);
    assert!(fb.join("bob.txt").is_file());
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn generated_exercises_are_reproducible_and_small() {
    let settings = |seed| Settings {
        kind: Default::default(),
        min_order: 2,
        max_order: 4,
        seed,
        convention: "a-kc".into(),
    };
    assert_eq!(
        pole_placement(&settings(5)).unwrap(),
        pole_placement(&settings(5)).unwrap()
    );
    assert_ne!(
        pole_placement(&settings(5)).unwrap(),
        pole_placement(&settings(6)).unwrap()
    );
    for seed in 0..20 {
        let text = pole_placement(&settings(seed)).unwrap();
        let ex: observer_workbench::exercise::ExerciseFile = toml::from_str(&text).unwrap();
        let k = answer_key("generated", &ex).unwrap();
        // T and the system stay in small integers
        for id in ["T", "O"] {
            let v = k.part(id).unwrap().value.input();
            assert!(!v.contains('/'), "seed {seed}: {id} = {v}");
        }
        let t = k.part("T").unwrap().value.input();
        let biggest = t
            .split(|c: char| !c.is_ascii_digit())
            .filter_map(|s| s.parse::<i64>().ok())
            .max()
            .unwrap_or(0);
        assert!(biggest <= 9, "seed {seed}: T = {t}");
    }
    let (code, out, _) = owb(&["exercise", "new", "--seed", "3", "--order", "2..3", "--key"]);
    assert_eq!(code, 0);
    assert!(out.contains("# K = "));
}

/// `owb exercise new --kind formula`: one entry of A is a parameter and the poles multiples of
/// w; the key is a formula, the pair observable for generic a, a right formula is right and
/// the key with the other sign is named.
#[test]
fn generated_formula_exercises_check_formulas() {
    use observer_workbench::exercise::generate::Kind;
    for seed in 0..12 {
        for convention in ["a-kc", "a+lc"] {
            let s = Settings {
                kind: Kind::Formula,
                min_order: 2,
                max_order: 3,
                seed,
                convention: convention.into(),
            };
            let text = pole_placement(&s).unwrap();
            assert_eq!(text, pole_placement(&s).unwrap(), "reproducible");
            let ex: observer_workbench::exercise::ExerciseFile = toml::from_str(&text).unwrap();
            let k = answer_key("generated", &ex).unwrap();
            let det = k.part("det_O").unwrap().value.input();
            assert!(
                det.contains('a') && det != "0",
                "seed {seed}: det O_n = {det}"
            );
            let letter = if convention == "a-kc" { "K" } else { "L" };
            let gain = k.part(letter).unwrap().value.input();
            assert!(gain.contains('w'), "seed {seed}: {gain}");
            let right = AnswerFile {
                answers: [(letter.to_string(), gain.clone())].into(),
                ..AnswerFile::default()
            };
            let r = check_answers(&k, &right, "t");
            let part = r.parts.iter().find(|p| p.id == letter).unwrap();
            assert_eq!(
                part.verdict,
                PartVerdict::Correct,
                "seed {seed}: {}",
                part.feedback
            );
            // the key with every entry negated (entries are formulas without brackets)
            let entries = gain.trim_start_matches('[').trim_end_matches(']');
            let negated: Vec<String> = entries.split("; ").map(|e| format!("-({e})")).collect();
            let wrong = AnswerFile {
                answers: [(letter.to_string(), format!("[{}]", negated.join("; ")))].into(),
                ..AnswerFile::default()
            };
            let r = check_answers(&k, &wrong, "t");
            let part = r.parts.iter().find(|p| p.id == letter).unwrap();
            assert_eq!(part.verdict, PartVerdict::Wrong, "seed {seed}");
            assert_eq!(
                part.mistake.as_deref(),
                Some("sign_convention"),
                "seed {seed}: {}",
                part.feedback
            );
        }
    }
    let (code, out, _) = owb(&[
        "exercise", "new", "--kind", "formula", "--seed", "5", "--order", "2", "--key",
    ]);
    assert_eq!(code, 0);
    assert!(out.contains("# K = ") && out.contains("w"), "{out}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn random_answer_text_never_panics(text in "\\PC{0,40}", part in 0usize..8) {
        let st = key("stoustrup-pole-assignment");
        let id = st.parts[part].spec.id.clone();
        let answers = AnswerFile { answers: [(id, text)].into(), ..AnswerFile::default() };
        let r = check_answers(&st, &answers, "fuzz");
        prop_assert_eq!(r.parts.len(), 8);
    }

    #[test]
    fn matrix_like_answers_never_panic(entries in proptest::collection::vec(-50i64..50, 0..7), rows in 1usize..4) {
        let st = key("stoustrup-pole-assignment");
        let per = entries.len().div_ceil(rows).max(1);
        let text = format!("[{}]", entries.chunks(per).map(|c| c.iter().map(ToString::to_string).collect::<Vec<_>>().join(" ")).collect::<Vec<_>>().join("; "));
        for id in ["L", "T", "O", "A_o"] {
            let answers = AnswerFile { answers: [(id.to_string(), text.clone())].into(), ..AnswerFile::default() };
            let _ = check_answers(&st, &answers, "fuzz");
        }
    }
}

/// `owb grade EX DIR --csv DIR/some-submission.toml` graded that file and then replaced the
/// student's submission with the report (exit 0): now refused, the submission intact.
#[test]
fn grade_never_writes_over_a_submission() {
    let dir = std::env::temp_dir().join(format!("owb-grade-guard-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let sub = dir.join("ada.toml");
    let text = "[answers]\nL = \"[-6; -12]\"\n";
    std::fs::write(&sub, text).unwrap();
    let (code, _, err) = grade(&dir, &sub, &[]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("is an input of this run"), "{err}");
    assert_eq!(std::fs::read_to_string(&sub).unwrap(), text);
    std::fs::remove_dir_all(&dir).ok();
}

/// `--json` on an error prints a JSON error object, so a script never reads an empty stdout.
#[test]
fn json_errors_are_json() {
    let (code, out, _) = owb(&[
        "gain", "--a", "[1 2]", "--c", "[1]", "--poles", "-1", "--json",
    ]);
    assert_eq!(code, 2);
    let v: serde_json::Value = serde_json::from_str(&out).expect("JSON on stdout");
    assert!(
        v["error"].as_str().unwrap().contains("must be square"),
        "{v}"
    );
}

/// Output handling (issue 17): a folder given as `--out` is refused and leaves no temporary
/// behind; `--svg f --csv f` is refused before anything is written; a class with an oversized
/// submission is graded, the oversized file an `invalid` row, and no report cell echoes more
/// than the cell limit.
#[test]
fn outputs_are_refused_or_written_whole() {
    let dir = std::env::temp_dir().join(format!("owb-outputs-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (code, _, err) = owb(&[
        "exercise",
        "new",
        "--seed",
        "3",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("is a folder"), "{err}");
    let leftovers: Vec<_> = std::fs::read_dir(dir.parent().unwrap())
        .unwrap()
        .filter_map(Result::ok)
        .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp-owb"))
        .filter(|e| e.file_name().to_string_lossy().contains("owb-outputs"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");

    let same = dir.join("figure.out");
    let (code, _, err) = owb(&[
        "simulate",
        "diruscio-example-7-1",
        "--svg",
        same.to_str().unwrap(),
        "--csv",
        same.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--svg and --csv both name"), "{err}");
    assert!(!same.exists());

    let subs = dir.join("subs");
    std::fs::create_dir_all(&subs).unwrap();
    std::fs::write(subs.join("ada.toml"), "[answers]\nL = \"[-6; -12]\"\n").unwrap();
    let huge = format!("[answers]\nL = \"[{}]\"\n", "1 ".repeat(600_000));
    std::fs::write(subs.join("huge.toml"), huge).unwrap();
    let long = format!("[answers]\nL = \"[{}]\"\n", "((".repeat(3000));
    std::fs::write(subs.join("long.toml"), long).unwrap();
    let csv = dir.join("report.csv");
    let (code, out, err) = grade(&subs, &csv, &[]);
    assert_eq!(code, 0, "{out}{err}");
    let report = std::fs::read_to_string(&csv).unwrap();
    assert!(
        report
            .lines()
            .any(|l| l.starts_with("huge,") && l.contains(",invalid,") && l.contains("1 MiB")),
        "{report}"
    );
    assert!(report.lines().any(|l| l.starts_with("long,")), "{report}");
    assert!(
        report.lines().all(|l| l.chars().count() < 2400),
        "a cell echoes too much"
    );
    assert!(!dir.join("report.csv.tmp-owb").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Mistakes recognised by computing (issue 17): the answer to another part, the right rows or
/// columns in another order, F with the opposite feedback sign; and attributions fit the
/// exercise (no Lemma 3.1 where the exercise never used it).
#[test]
fn mistakes_found_by_computing() {
    let st = key("stoustrup-pole-assignment");
    // O = [C; CA] with its rows swapped
    let o = st.part("O").unwrap().value.input();
    let rows: Vec<&str> = o
        .trim_matches(['[', ']'])
        .split(';')
        .map(str::trim)
        .collect();
    let swapped = format!("[{}; {}]", rows[1], rows[0]);
    assert_eq!(mistake(&st, "O", &swapped), Some("permuted"));
    // the open-loop polynomial given where the desired one is asked
    let open_loop = st.part("open_loop").unwrap().value.input();
    assert_eq!(mistake(&st, "desired", &open_loop), Some("another_part"));
    let p = st.part("desired").unwrap();
    let (d, _) = diagnose(&st, p, &open_loop);
    assert!(d.unwrap().message.contains("part open_loop"));
    // F of u = Fx given as K of u = −Kx
    let oc = key("stoustrup-observer-based-control");
    let f = oc.part("F").unwrap();
    let negated = match &f.value {
        observer_workbench::worked::Value::Matrix(m) => m.neg().to_input(),
        _ => unreachable!("F is a matrix"),
    };
    let (d, _) = diagnose(&oc, f, &negated);
    let d = d.unwrap();
    assert_eq!(d.mistake.name(), "feedback_sign");
    assert!(d.message.contains("u = −Kx"), "{}", d.message);
    // a reversed gain in an exercise without Lemma 3.1 does not cite it
    let l = st.part("L").unwrap();
    if let observer_workbench::worked::Value::Matrix(m) = &l.value {
        let rev = format!("[{}; {}]", m.get(1, 0).to_input(), m.get(0, 0).to_input());
        let (d, _) = diagnose(&st, l, &rev);
        let d = d.unwrap();
        assert_eq!(d.mistake.name(), "reversed");
        let cites = st
            .parts
            .iter()
            .any(|q| q.claim.method.as_deref() == Some("lemma-3.1"));
        assert_eq!(d.message.contains("Lemma 3.1"), cites, "{}", d.message);
    }
}

/// A polynomial answer may use the prompt's λ (the key computes in s) — and still be wrong
/// when it is wrong.
#[test]
fn polynomial_answers_may_use_lambda() {
    let st = key("stoustrup-pole-assignment");
    let answers = |text: &str| AnswerFile {
        answers: [("desired".to_string(), text.to_string())].into(),
        ..AnswerFile::default()
    };
    let part = |text: &str| {
        let r = check_answers(&st, &answers(text), "l");
        let p = r.parts.iter().find(|p| p.id == "desired").unwrap().clone();
        p.verdict
    };
    use observer_workbench::exercise::PartVerdict;
    assert_eq!(part("(λ + 4)(λ + 5)"), PartVerdict::Correct);
    assert_eq!(part("λ^2 + 9λ + 20"), PartVerdict::Correct);
    assert_eq!(part("λ^2 + 9λ + 21"), PartVerdict::Wrong);
}

/// Each student's own exercise: `--student` names the variant the course book generates for the
/// id, and `owb grade variants` checks every submission against the variant its `exercise` id
/// names — refusing one that belongs to another student, or names no generated exercise.
#[test]
fn student_variants_are_generated_and_graded_per_student() {
    let dir = std::env::temp_dir().join(format!("owb-variants-{}", std::process::id()));
    let subs = dir.join("subs");
    std::fs::create_dir_all(&subs).unwrap();
    let (code, key, err) = owb(&[
        "exercise",
        "new",
        "--student",
        "Ada",
        "--order",
        "2",
        "--key",
    ]);
    assert_eq!(code, 0, "{err}");
    let ada = Settings::for_student("ada", 2, 2, "a-kc");
    assert!(key.contains(&format!("id = \"{}\"", ada.id())), "{key}");
    let (_, by_seed, _) = owb(&[
        "exercise",
        "new",
        "--seed",
        &ada.seed.to_string(),
        "--order",
        "2",
        "--key",
    ]);
    assert_eq!(key, by_seed, "--student is the seed of the id");
    let (code, _, err) = owb(&["exercise", "new", "--student", "x", "--seed", "1"]);
    assert_eq!(code, 2, "both a seed and a student: {err}");
    // the right answers, from the computed key
    let answers: Vec<String> = key
        .lines()
        .filter_map(|l| l.strip_prefix("# "))
        .filter(|l| l.contains(" = \""))
        .map(str::to_string)
        .collect();
    assert!(answers.len() >= 5, "{key}");
    let file = |student: &str, exercise: &str| {
        format!(
            "exercise = \"{exercise}\"\nstudent = \"{student}\"\n[answers]\n{}\n",
            answers.join("\n")
        )
    };
    std::fs::write(subs.join("ada.toml"), file("ada", &ada.id())).unwrap();
    std::fs::write(subs.join("eve.toml"), file("eve", &ada.id())).unwrap();
    std::fs::write(
        subs.join("bob.toml"),
        file("bob", "stoustrup-pole-assignment"),
    )
    .unwrap();
    let csv = dir.join("report.csv");
    let (code, out, err) = owb(&[
        "grade",
        "variants",
        subs.to_str().unwrap(),
        "--csv",
        csv.to_str().unwrap(),
        "--order",
        "2",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("3 submissions graded for their own variants (pole-placement, order 2, a-kc): 1 fully correct, 2 invalid"),
        "{out}"
    );
    let report = std::fs::read_to_string(&csv).unwrap();
    let rows: Vec<&str> = report.lines().collect();
    assert!(
        rows.iter()
            .filter(|r| r.starts_with("ada,"))
            .all(|r| r.contains(",correct,")),
        "{report}"
    );
    let theirs = Settings::for_student("eve", 2, 2, "a-kc").id();
    assert!(
        report.contains(&format!(
            "but the variant set for student 'eve' is '{theirs}'"
        )),
        "{report}"
    );
    assert!(
        report.contains("answers for exercise 'stoustrup-pole-assignment', but the variant set for student 'bob'"),
        "{report}"
    );
    // a student who chose an easier variant (order 1) is graded against the one set, never theirs
    let easy = Settings {
        min_order: 1,
        max_order: 1,
        ..Settings::for_student("eve", 1, 1, "a-kc")
    };
    std::fs::write(subs.join("eve.toml"), file("eve", &easy.id())).unwrap();
    let (code, _, err) = owb(&[
        "grade",
        "variants",
        subs.to_str().unwrap(),
        "--csv",
        csv.to_str().unwrap(),
        "--order",
        "2",
    ]);
    assert_eq!(code, 0, "{err}");
    let report = std::fs::read_to_string(&csv).unwrap();
    assert!(
        report
            .lines()
            .filter(|r| r.starts_with("eve,"))
            .all(|r| r.contains(",invalid,")),
        "{report}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
