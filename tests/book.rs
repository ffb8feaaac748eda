//! Issue 8: the course book is expanded from the code. Every chapter's directives expand (as the
//! `mdbook-owb` preprocessor does), the result carries computed values and no directive text, and
//! every worked example and exercise appears in the book.

use observer_workbench::book::{chapters, BookContext};
use std::path::{Path, PathBuf};

fn ctx() -> BookContext {
    BookContext {
        root: PathBuf::from(env!("CARGO_MANIFEST_DIR")),
        run_commands: true,
    }
}

fn expanded() -> Vec<(String, String)> {
    let ctx = ctx();
    chapters(Path::new("book/src"))
        .into_iter()
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            let text = std::fs::read_to_string(&p).unwrap();
            let out = ctx.expand(&name, &text).unwrap_or_else(|e| panic!("{e}"));
            (name, out)
        })
        .collect()
}

#[test]
fn every_chapter_expands_with_computed_content() {
    let book = expanded();
    assert!(book.len() >= 10, "{} chapters", book.len());
    for (name, text) in &book {
        assert!(!text.contains("{{#owb"), "{name}: unexpanded directive");
    }
    let all: String = book.iter().map(|(_, t)| t.as_str()).collect();
    // computed, not typed: Stoustrup's gain, Di Ruscio's corrected gain, J1, the Kalman bandwidth
    for needle in [
        "[-6; -12]",
        "8*sqrt(2) - 34",
        "29.046",
        "286.6",
        "<svg",
        "\\begin{aligned}",
    ] {
        assert!(all.contains(needle), "the book lacks {needle}");
    }
}

#[test]
fn every_worked_example_and_exercise_is_in_the_book() {
    let sources: String = chapters(Path::new("book/src"))
        .iter()
        .map(|p| std::fs::read_to_string(p).unwrap())
        .collect();
    for dir in ["worked_examples", "worked_examples/exercises"] {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|x| x == "toml") {
                let id = path.file_stem().unwrap().to_string_lossy().into_owned();
                let directive = if dir.ends_with("exercises") {
                    format!("{{{{#owb exercise {id}}}}}")
                } else {
                    format!("{{{{#owb verify-table {id}}}}}")
                };
                assert!(
                    sources.contains(&directive),
                    "{id} is not in the book ({directive})"
                );
            }
        }
    }
}

/// Runs the preprocessor on a `[context, book]` input.
fn preprocess(exe: &Path, input: &serde_json::Value) -> std::process::Output {
    use std::io::Write;
    let mut child = std::process::Command::new(exe)
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    child
        .stdin
        .take()
        .unwrap()
        .write_all(input.to_string().as_bytes())
        .unwrap();
    child.wait_with_output().unwrap()
}

#[test]
fn the_preprocessor_speaks_the_mdbook_protocol() {
    let exe = PathBuf::from(env!("CARGO_BIN_EXE_mdbook-owb"));
    let status = std::process::Command::new(&exe)
        .args(["supports", "html"])
        .status()
        .unwrap();
    assert!(status.success());
    let book_root = Path::new(env!("CARGO_MANIFEST_DIR")).join("book");
    let input = serde_json::json!([
        {"root": book_root, "config": {}, "renderer": "html", "mdbook_version": "0.4.52"},
        {"sections": [{"Chapter": {"name": "t", "content": "x {{#owb run gain --a \"[2 -3; 4 -5]\" --c \"[-3 2]\" --poles \"-4, -5\" --convention a+lc}} y",
            "number": [1], "sub_items": [], "path": "t.md", "source_path": "t.md", "parent_names": []}}],
         "__non_exhaustive": null}
    ]);
    let out = preprocess(&exe, &input);
    assert!(out.status.success());
    let book: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let content = book["sections"][0]["Chapter"]["content"].as_str().unwrap();
    assert!(content.contains("L = [-6; -12]"), "{content}");
    // a failing directive fails the build with the chapter named
    let bad = serde_json::json!([
        {"root": book_root},
        {"sections": [{"Chapter": {"name": "t", "content": "{{#owb figure nowhere x}}", "sub_items": [], "source_path": "bad.md"}}]}
    ]);
    let out = preprocess(&exe, &bad);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("bad.md"));
}
