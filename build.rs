//! Builds the exercises shipped in `worked_examples/exercises/` into the program, so that an
//! installed `owb check ID` needs no checkout of the sources, and the source documents' authors
//! and titles (the `document` and `title` lines of `worked_examples/coverage/*.toml`), so that
//! every report — the browser's too — names a document by author and title.

use std::fmt::Write as _;
use std::path::Path;

fn main() {
    let mut out = String::from(
        "/// The exercises built into the program: `(id, text of the TOML file)`, sorted by id.\npub const BUILTIN_EXERCISES: &[(&str, &str)] = &[\n",
    );
    for f in toml_files("exercises") {
        let id = f.file_stem().unwrap_or_default().to_string_lossy();
        let _ = writeln!(
            out,
            "    ({id:?}, include_str!({:?})),",
            f.display().to_string()
        );
    }
    out.push_str("];\n");
    write_generated("builtin_exercises.rs", &out);
    document_titles();
}

/// The `*.toml` files of `worked_examples/<folder>`, sorted, each watched for changes.
fn toml_files(folder: &str) -> Vec<std::path::PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("worked_examples")
        .join(folder);
    println!("cargo:rerun-if-changed={}", dir.display());
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .map(|d| {
            d.filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|x| x == "toml"))
                .collect()
        })
        .unwrap_or_default();
    files.sort();
    for f in &files {
        println!("cargo:rerun-if-changed={}", f.display());
    }
    files
}

fn write_generated(name: &str, text: &str) {
    let target = Path::new(&std::env::var("OUT_DIR").expect("cargo sets OUT_DIR")).join(name);
    std::fs::write(target, text).expect("OUT_DIR is writable");
}

/// `BUILTIN_DOCUMENT_TITLES: &[(file, author and title)]` from the coverage lists' top lines.
fn document_titles() {
    let mut out = String::from(
        "/// The source documents by file name: `(file, author and title)`, from the coverage lists.\npub const BUILTIN_DOCUMENT_TITLES: &[(&str, &str)] = &[\n",
    );
    for f in toml_files("coverage") {
        let text = std::fs::read_to_string(&f).unwrap_or_default();
        // the top-level `key = "value"` lines before the first table
        let top = |key: &str| {
            text.lines()
                .take_while(|l| !l.starts_with('['))
                .find_map(|l| {
                    let (k, v) = l.split_once('=')?;
                    (k.trim() == key).then(|| v.trim().trim_matches('"').to_string())
                })
        };
        if let (Some(document), Some(title)) = (top("document"), top("title")) {
            let _ = writeln!(out, "    ({document:?}, {title:?}),");
        }
    }
    out.push_str("];\n");
    write_generated("builtin_document_titles.rs", &out);
}
