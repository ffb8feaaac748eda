//! Builds the exercises shipped in `worked_examples/exercises/` into the program, so that an
//! installed `owb check ID` needs no checkout of the sources.

use std::fmt::Write as _;
use std::path::Path;

fn main() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("worked_examples")
        .join("exercises");
    println!("cargo:rerun-if-changed={}", dir.display());
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .map(|d| {
            d.filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|x| x == "toml"))
                .collect()
        })
        .unwrap_or_default();
    files.sort();
    let mut out = String::from(
        "/// The exercises built into the program: `(id, text of the TOML file)`, sorted by id.\npub const BUILTIN_EXERCISES: &[(&str, &str)] = &[\n",
    );
    for f in &files {
        println!("cargo:rerun-if-changed={}", f.display());
        let id = f.file_stem().unwrap_or_default().to_string_lossy();
        let _ = writeln!(
            out,
            "    ({id:?}, include_str!({:?})),",
            f.display().to_string()
        );
    }
    out.push_str("];\n");
    let target = Path::new(&std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"))
        .join("builtin_exercises.rs");
    std::fs::write(target, out).expect("OUT_DIR is writable");
}
