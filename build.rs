//! Builds the exercises shipped in `worked_examples/exercises/` into the program, so that an
//! installed `owb check ID` needs no checkout of the sources, and the source documents' authors
//! and titles (the `document` and `title` lines of `worked_examples/coverage/*.toml`), so that
//! every report — the browser's too — names a document by author and title. And, where the
//! linker is Rust's own LLD, it links `owb`'s machine code in the order of
//! `src/bin/owb.text-order` (see [`text_order`]).

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
    text_order();
}

/// The functions every command runs first, then those most commands run, laid out together at
/// the start of `owb`'s machine code (`src/bin/owb.text-order`, written by
/// `tests/bench/text_order.sh` from the functions a set of commands ran).
///
/// **Why.** The kernel maps a program's code when it is first run, 64 KiB around each page
/// touched, about 2.3 µs a time on the 2-core machine; a command's code spread over 7 MB of
/// machine code (clap, serde, the exact core) took 80 of these, 0.2 ms. Laid out together, the
/// code a command runs spans a few such windows.
///
/// **Where.** Only where the linker is known to read the list: LLD's `--symbol-ordering-file`,
/// Rust's default linker for x86-64 Linux since Rust 1.90, unless a linker is configured
/// (`RUSTC_LINKER`) or chosen in the flags. A name in the list that the program no longer has
/// is skipped (`--no-warn-symbol-ordering`), so a stale list costs speed, never a build; the
/// machine code itself, and so every result, is the same in any order.
fn text_order() {
    let list = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/bin/owb.text-order");
    println!("cargo:rerun-if-changed={}", list.display());
    println!("cargo:rerun-if-env-changed=RUSTC_LINKER");
    let var = |k: &str| std::env::var(k).unwrap_or_default();
    let rustc_minor = std::process::Command::new(var("RUSTC"))
        .arg("--version")
        .output()
        .ok()
        .and_then(|o| {
            let text = String::from_utf8_lossy(&o.stdout).into_owned();
            // "rustc 1.95.0 (…)"
            let version = text.split_whitespace().nth(1)?.to_string();
            version.split('.').nth(1)?.parse::<u32>().ok()
        })
        .unwrap_or(0);
    let lld_by_default = var("TARGET") == "x86_64-unknown-linux-gnu" && rustc_minor >= 90;
    let linker_chosen = std::env::var_os("RUSTC_LINKER").is_some()
        || var("CARGO_ENCODED_RUSTFLAGS").contains("link");
    let path_ok = !list.display().to_string().contains(','); // -Wl splits at commas
    if lld_by_default && !linker_chosen && path_ok && list.is_file() {
        println!(
            "cargo:rustc-link-arg-bin=owb=-Wl,--symbol-ordering-file={}",
            list.display()
        );
        println!("cargo:rustc-link-arg-bin=owb=-Wl,--no-warn-symbol-ordering");
    }
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
