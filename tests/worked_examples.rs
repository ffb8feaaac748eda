//! The worked examples: every file's derivation is a reviewed snapshot, every claim is
//! recomputed, and a corrupted print is caught.

use observer_workbench::worked::{
    load_example, load_folder, render_derivations, render_table, verify_example, ExampleReport,
    Summary, Verdict,
};
use std::path::{Path, PathBuf};

fn folder() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("worked_examples")
}

#[test]
fn every_example_derivation_is_a_reviewed_snapshot() {
    insta::glob!("../worked_examples", "*.toml", |path| {
        let (ex, raw) = load_example(path).unwrap();
        let report = verify_example(path, &ex, &raw).unwrap();
        let text = format!("{}\n{}", render_table(&report), render_derivations(&report));
        insta::assert_snapshot!(text);
    });
}

#[test]
fn every_claim_is_recomputed_and_none_is_a_mismatch() {
    let files = load_folder(&folder()).unwrap();
    assert!(
        files.len() >= 10,
        "expected the documents' examples, found {}",
        files.len()
    );
    let mut reports = Vec::new();
    for f in &files {
        let (ex, raw) = load_example(f).unwrap();
        assert!(
            !ex.claims.is_empty() || !ex.printed_only.is_empty(),
            "{} records nothing",
            f.display()
        );
        let r = verify_example(f, &ex, &raw).unwrap();
        for c in &r.claims {
            assert_ne!(
                c.recomputed, "—",
                "{}/{}: no recomputation: {}",
                r.id, c.id, c.explanation
            );
            assert_ne!(
                c.verdict,
                Verdict::Mismatch,
                "{}/{}: {}",
                r.id,
                c.id,
                c.explanation
            );
        }
        reports.push(r);
    }
    let s = Summary::of(&reports);
    assert!(
        s.erratum >= 5,
        "the documents' known errata were not all found: {s:?}"
    );
}

#[test]
fn the_committed_errata_report_is_current() {
    let files = load_folder(&folder()).unwrap();
    let reports: Vec<_> = files
        .iter()
        .map(|f| {
            let (ex, raw) = load_example(f).unwrap();
            verify_example(f, &ex, &raw).unwrap()
        })
        .collect();
    let generated = observer_workbench::worked::errata_markdown_titled(
        &reports,
        &observer_workbench::worked::coverage::titles(&folder()),
    );
    let committed =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("book/src/errata.md"))
            .expect(
            "book/src/errata.md exists (regenerate with `owb verify --errata book/src/errata.md`)",
        );
    assert_eq!(
        committed, generated,
        "book/src/errata.md is stale: run `cargo run -- verify --errata book/src/errata.md`"
    );
}

/// A copy of the shipped example `name` with one print replaced (`from` → `to`), written to a
/// temporary folder `tag` and verified: its path and report.
fn verify_corrupted(name: &str, from: &str, to: &str, tag: &str) -> (PathBuf, ExampleReport) {
    let text = std::fs::read_to_string(folder().join(name)).unwrap();
    let corrupted = text.replacen(from, to, 1);
    assert_ne!(text, corrupted, "{from} is not in {name}");
    let dir = std::env::temp_dir().join(format!("owb-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, &corrupted).unwrap();
    let (ex, raw) = load_example(&path).unwrap();
    let report = verify_example(&path, &ex, &raw).unwrap();
    (path, report)
}

/// The mismatches of a report.
fn mismatches(r: &ExampleReport) -> Vec<&observer_workbench::worked::ClaimReport> {
    r.claims
        .iter()
        .filter(|c| c.verdict == Verdict::Mismatch)
        .collect()
}

/// A copy of an example with one printed value changed must be reported as a mismatch, and
/// `owb verify` must exit 1.
#[test]
fn a_corrupted_print_is_a_mismatch_and_exit_code_1() {
    let (path, r) = verify_corrupted(
        "stoustrup-pole-assignment.toml",
        "printed = \"[-6; -12]\"",
        "printed = \"[-6; -13]\"",
        "corrupt",
    );
    let bad = mismatches(&r);
    assert_eq!(bad.len(), 1);
    assert_eq!(bad[0].id, "L");

    let out = std::process::Command::new(env!("CARGO_BIN_EXE_owb"))
        .args(["verify", "--json", path.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["summary"]["mismatch"], 1);
    assert_eq!(json["examples"][0]["document"], "001_7629475c4a00cd3e.txt");
    std::fs::remove_dir_all(path.parent().unwrap()).ok();
}

/// Malformed files are bad input (exit 2) with file, line and field named.
#[test]
fn malformed_example_files_name_file_line_and_field() {
    let dir = std::env::temp_dir().join(format!("owb-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("bad.toml");
    std::fs::write(
        &path,
        "id = \"bad\"\ntitle = \"t\"\ndocument = \"d\"\n\n[system]\nA = \"[1 2; 3]\"\nC = \"[1 0]\"\n\n[[claims]]\nid = \"O\"\nsource = \"s\"\nwhat = \"observability_matrix\"\nprinted = \"[1 0; 1 2]\"\n",
    )
    .unwrap();
    let (ex, raw) = load_example(&path).unwrap();
    let err = verify_example(&path, &ex, &raw).unwrap_err();
    assert_eq!(err.line, 6);
    assert!(err.field.starts_with("system.A"), "{err}");
    assert!(err.message.contains("row 2 has 1 entries"), "{err}");

    std::fs::write(
        &path,
        "id = \"bad\"\ntitle = \"t\"\ndocument = \"d\"\ncolour = 3\n",
    )
    .unwrap();
    let err = load_example(&path).unwrap_err();
    assert_eq!(err.line, 4, "{err}");

    let out = std::process::Command::new(env!("CARGO_BIN_EXE_owb"))
        .args(["verify", path.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("bad.toml:4"), "{stderr}");
    std::fs::remove_dir_all(&dir).ok();
}

/// The graded verdicts: a value within its documented tolerance holds approximately, outside it
/// is a mismatch; an undefined print is unreproducible unless one of its readings reproduces it
/// (then the file should record that reading); a claim documents at most one of the three.
#[test]
fn approximate_and_unreproducible_verdicts_are_checked() {
    use observer_workbench::worked::{parse_example, Verdict};
    let head = "id = \"g\"\ntitle = \"t\"\ndocument = \"d\"\n[system]\nA = \"[0 1; -6 -5]\"\n";
    let claim = |printed: &str, extra: &str| {
        format!(
            "{head}[[claims]]\nid = \"w\"\nsource = \"s\"\nwhat = \"natural_frequency\"\npoles = \"-2, -3\"\nprinted = \"{printed}\"\n{extra}"
        )
    };
    let verdict = |text: String| {
        let ex = parse_example("g.toml", &text).unwrap();
        let r = verify_example(Path::new("g.toml"), &ex, &text).unwrap();
        (r.claims[0].verdict, r.claims[0].explanation.clone())
    };
    // ω_n = √6 = 2.449…
    let approx = "[claims.approximate]\ntolerance = \"3%\"\nkind = \"design_target\"\nreason = \"aimed at 2.5\"\n";
    let (v, why) = verdict(claim("2.5", approx));
    assert_eq!(v, Verdict::HoldsApproximately, "{why}");
    // the deviation shown is |√6 − 2.5| and its share of the print
    let off = 2.5 - 6f64.sqrt();
    let shown = format!("off by {off:.4} ({:.2}% of the print)", off / 2.5 * 100.0);
    assert!(why.contains(&shown), "{why}\n{shown}");
    let (v, why) = verdict(claim("2.6", approx));
    assert_eq!(v, Verdict::Mismatch, "{why}");
    let (v, _) = verdict(claim("2.449", approx));
    assert_eq!(
        v,
        Verdict::Mismatch,
        "an approximation documented on a print that holds"
    );
    // 6 is the product of the poles' moduli, not ω_n: a reading that reproduces it
    let undefined = |what: &str| {
        format!("[claims.unreproducible]\nundefined = \"the frequency\"\n[[claims.unreproducible.readings]]\nreading = \"r\"\nwhat = \"{what}\"\n")
    };
    let (v, why) = verdict(claim("7", &undefined("natural_frequency")));
    assert_eq!(v, Verdict::Unreproducible, "{why}");
    assert!(
        why.contains("Readings: as recorded (natural_frequency)"),
        "{why}"
    );
    let (v, why) = verdict(claim("2.449", &undefined("natural_frequency")));
    assert_eq!(v, Verdict::Mismatch, "{why}");
    assert!(
        why.contains("an undefined print is documented, but the print holds"),
        "{why}"
    );
    // two documentations at once, and a malformed tolerance, are refused where they are written
    let both = format!("{approx}[claims.erratum]\nexplanation = \"e\"\ncorrected = \"2.449\"\n");
    let e = parse_example("g.toml", &claim("2.5", &both)).unwrap_err();
    assert!(e.message.contains("at most one"), "{e}");
    let bad = approx.replace("3%", "-3%");
    let e = parse_example("g.toml", &claim("2.5", &bad)).unwrap_err();
    assert_eq!(e.field, "claims.w.tolerance", "{e}");
}

/// The sampled identities are proved over the rational functions of their symbols; a print that
/// differs as a rational function is a mismatch said in those terms.
#[test]
fn symbolic_identities_are_proved_and_a_wrong_one_refuted() {
    let src = folder().join("diruscio-butterworth.toml");
    let (ex, raw) = load_example(&src).unwrap();
    let r = verify_example(&src, &ex, &raw).unwrap();
    let proved: Vec<&str> = r
        .claims
        .iter()
        .filter(|c| c.explanation.contains("proved as an identity"))
        .map(|c| c.id.as_str())
        .collect();
    for id in [
        "repeated-order-4",
        "butterworth-order-2",
        "butterworth-gain-order-3",
    ] {
        assert!(proved.contains(&id), "{id} not proved: {proved:?}");
    }
    let (path, r) = verify_corrupted(
        "diruscio-butterworth.toml",
        "printed = \"[a1 + sqrt(2)/T; a2 + 1/T^2]\"",
        "printed = \"[a1 + sqrt(2)/T; a2 + 2/T^2]\"",
        "refuted",
    );
    let bad = mismatches(&r);
    assert_eq!(bad.len(), 1);
    assert_eq!(bad[0].id, "butterworth-gain-order-2");
    assert!(
        bad[0]
            .explanation
            .contains("as rational functions of T, a1, a2 the print differs"),
        "{}",
        bad[0].explanation
    );
    std::fs::remove_dir_all(path.parent().unwrap()).ok();
}

/// Every source document has a coverage list, every list fits the examples (its claims and
/// figures exist and belong to the document, and every claim and figure is listed), and a list
/// that names a missing claim, or leaves a claim out, is refused.
#[test]
fn coverage_lists_fit_the_examples_both_ways() {
    use observer_workbench::worked::coverage;
    let dir = folder();
    let lists = coverage::load(&dir).unwrap();
    let examples: Vec<_> = load_folder(&dir)
        .unwrap()
        .iter()
        .map(|p| load_example(p).unwrap().0)
        .collect();
    // the source documents (../shared/seeds/*.txt); the course's own examples cite
    // python-control, which has no list
    let mut documents: Vec<&str> = examples
        .iter()
        .map(|e| e.document.as_str())
        .filter(|d| d.ends_with(".txt"))
        .collect();
    documents.sort_unstable();
    documents.dedup();
    for d in &documents {
        assert!(
            lists.iter().any(|(_, l)| l.document == *d),
            "no coverage list for {d}"
        );
    }
    for (path, list) in &lists {
        let t = coverage::check(path, list, &examples).unwrap();
        assert_eq!(
            t.statements,
            t.recorded + t.inputs + t.not_checked.values().sum::<usize>()
        );
        assert!(t.recorded > 0, "{}", t.line());
    }
    // a dangling reference, and an example claim no statement lists
    let (path, list) = &lists[0];
    let mut broken = list.clone();
    broken.statements[0].recorded = vec![format!("{}/no-such-claim", examples[0].id)];
    broken.statements[0].not_checked = None;
    broken.statements[0].input = None;
    assert!(coverage::check(path, &broken, &examples).is_err());
    let mut short = list.clone();
    short.statements.retain(|s| s.recorded.is_empty());
    let e = coverage::check(path, &short, &examples).unwrap_err();
    assert!(
        e.message.contains("no statement of the list records it"),
        "{e}"
    );
    // one statement, one check: a claim credited to a second statement without listing it in
    // its own `checks`, and a figure without checks of its own recorded as a check
    let (path, list) = lists
        .iter()
        .find(|(_, l)| l.title.starts_with("Baranowski"))
        .unwrap();
    let mut twice = list.clone();
    let g1 = "baranowski-rc-ladder/G1".to_string();
    let theorem = twice
        .statements
        .iter_mut()
        .find(|s| s.location == "Theorem 1")
        .unwrap();
    theorem.related.retain(|r| *r != g1);
    theorem.recorded.push(g1);
    let e = coverage::check(path, &twice, &examples).unwrap_err();
    assert!(e.message.contains("`checks` lists each of them"), "{e}");
    let mut figure = list.clone();
    let bound = figure
        .statements
        .iter_mut()
        .find(|s| s.location == "eq. (24)")
        .unwrap();
    bound.recorded = std::mem::take(&mut bound.related);
    bound.not_checked = None;
    let e = coverage::check(path, &figure, &examples).unwrap_err();
    assert!(e.message.contains("has no checks of its own"), "{e}");
    // the strict share: recorded of checkable
    let t = coverage::check(path, list, &examples).unwrap();
    assert!(t.recorded <= t.checkable && t.checkable <= t.statements);
}

/// Printed formulas are evaluated as printed and can fail: a wrong sign in a symbolic matrix, a
/// printed equality whose sides differ, a wrong equation reference, a wrong stability verdict;
/// a corrected value documented as an erratum is confirmed; a transpose is refused outside a
/// matrix formula.
#[test]
fn formulas_as_printed_can_fail() {
    use observer_workbench::worked::{parse_example, Verdict};
    let head = "id = \"g\"\ntitle = \"t\"\ndocument = \"d\"\n[system]\nA = \"[a1 1; a2 0]\"\nC = \"[1 0]\"\n";
    let verdict = |claim: &str| {
        let text = format!("{head}[[claims]]\nid = \"w\"\nsource = \"s\"\n{claim}");
        let ex = parse_example("g.toml", &text).unwrap();
        let r = verify_example(Path::new("g.toml"), &ex, &text).unwrap();
        (r.claims[0].verdict, r.claims[0].explanation.clone())
    };
    // A − KC with symbols: the print with the right signs holds, a flipped sign does not
    let expression = |printed: &str| {
        format!("what = \"matrix_expression\"\nexpression = \"A - K C\"\nprinted = \"{printed}\"\n[claims.matrices]\nK = \"[k1; k2]\"\n")
    };
    assert_eq!(
        verdict(&expression("[a1 - k1, 1; a2 - k2, 0]")).0,
        Verdict::Holds
    );
    let (v, why) = verdict(&expression("[a1 + k1, 1; a2 - k2, 0]"));
    assert_eq!(v, Verdict::Mismatch, "{why}");
    // a printed equality: both sides evaluated; a transpose in a matrix formula is read
    let identity = |left: &str, right: &str| {
        format!("what = \"matrix_identity\"\nexpression = \"{left}\"\nprinted = \"{right}\"\n[claims.matrices]\nK = \"[k1; k2]\"\n")
    };
    assert_eq!(
        verdict(&identity("(A - K C)^T", "A^T - C^T K^T")).0,
        Verdict::Holds
    );
    let (v, why) = verdict(&identity("(A - K C)^T", "A - C^T K^T"));
    assert_eq!(v, Verdict::Mismatch, "{why}");
    let (v, why) = verdict(&identity("T_o^-1 A T_o", "[-a_1 1; -a_2 0]"));
    assert_eq!(v, Verdict::Holds, "{why}");
    let (v, why) = verdict(&identity("T_o^-1 A T_o", "[a_1 1; a_2 0]"));
    assert_eq!(v, Verdict::Mismatch, "{why}");
    // an equation reference: the matrix of (2) is A only at a1 = 0, a2 = 1
    let reference = |printed: &str, extra: &str| {
        format!("what = \"equation_reference\"\nA = \"[0 1; 1 0]\"\nrefers = [\"A\", \"C\"]\nprinted = \"{printed}\"\n[claims.equations]\n\"(1)\" = \"ẋ = Ax\"\n\"(2)\" = \"[0 1; 1 0]\"\n\"(3)\" = \"[1 0]\"\n{extra}")
    };
    assert_eq!(verdict(&reference("(2), (3)", "")).0, Verdict::Holds);
    let (v, why) = verdict(&reference("(1), (3)", ""));
    assert_eq!(v, Verdict::Mismatch, "{why}");
    let erratum = "[claims.erratum]\nexplanation = \"shifted\"\nseverity = \"notation\"\ncorrected = \"(2), (3)\"\n";
    let (v, why) = verdict(&reference("(1), (3)", erratum));
    assert_eq!(v, Verdict::Erratum, "{why}");
    // a wrong correction is not confirmed
    let wrong = "[claims.erratum]\nexplanation = \"shifted\"\nseverity = \"notation\"\ncorrected = \"(1), (2)\"\n";
    assert_eq!(verdict(&reference("(1), (3)", wrong)).0, Verdict::Mismatch);
    // stability decided exactly
    let stable = |a: &str, printed: &str| {
        format!("what = \"stable\"\nA = \"{a}\"\nprinted = \"{printed}\"\n")
    };
    assert_eq!(verdict(&stable("[0 1; -2 -3]", "stable")).0, Verdict::Holds);
    assert_eq!(
        verdict(&stable("[0 1; -2 3]", "stable")).0,
        Verdict::Mismatch
    );
    assert_eq!(
        verdict(&stable("[0 1; -1 0]", "stable")).0,
        Verdict::Mismatch
    );
    // the transpose is for matrix formulas: a number refuses it, naming the column
    let e = observer_workbench::syntax::parse_expression("s^T + 1").unwrap();
    let err = observer_workbench::syntax::evaluate_with::<observer_workbench::algebra::Rational>(
        &e,
        &Default::default(),
    )
    .unwrap_err();
    assert!(err.to_string().contains("transpose"), "{err}");
}
