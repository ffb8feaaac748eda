//! `mdbook-owb`: the mdBook preprocessor of the course book. It follows mdBook's preprocessor
//! protocol — `mdbook-owb supports RENDERER` answers whether a renderer is supported, and a plain
//! run reads `[context, book]` as JSON on stdin and writes the book back with every
//! `{{#owb …}}` directive expanded by the workbench (see the library's `book` module). A failing
//! directive prints its chapter and reason and exits 1, which fails `mdbook build`.

use observer_workbench::book::BookContext;
use serde_json::Value;
use std::io::Read;
use std::path::PathBuf;
use std::process::ExitCode;

fn walk(v: &mut Value, ctx: &BookContext) -> Result<(), String> {
    match v {
        Value::Object(map) => {
            if let Some(Value::Object(ch)) = map.get_mut("Chapter") {
                let name = ch
                    .get("source_path")
                    .and_then(Value::as_str)
                    .or_else(|| ch.get("name").and_then(Value::as_str))
                    .unwrap_or("chapter")
                    .to_string();
                if let Some(Value::String(content)) = ch.get_mut("content") {
                    *content = ctx.expand(&name, content).map_err(|e| e.to_string())?;
                }
                if let Some(sub) = ch.get_mut("sub_items") {
                    walk(sub, ctx)?;
                }
                return Ok(());
            }
            for value in map.values_mut() {
                walk(value, ctx)?;
            }
        }
        Value::Array(items) => {
            for item in items {
                walk(item, ctx)?;
            }
        }
        _ => {}
    }
    Ok(())
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().collect();
    if args.get(1).map(String::as_str) == Some("supports") {
        // HTML (and anything reading markdown) is supported
        return ExitCode::SUCCESS;
    }
    let mut input = String::new();
    if let Err(e) = std::io::stdin().read_to_string(&mut input) {
        eprintln!("mdbook-owb: reading stdin: {e}");
        return ExitCode::from(1);
    }
    let parsed: Value = match serde_json::from_str(&input) {
        Ok(v) => v,
        Err(e) => {
            eprintln!("mdbook-owb: the input is not mdBook's [context, book] JSON: {e}");
            return ExitCode::from(1);
        }
    };
    let Some(Value::Object(context)) = parsed.get(0).cloned() else {
        eprintln!("mdbook-owb: expected [context, book]");
        return ExitCode::from(1);
    };
    let Some(mut book) = parsed.get(1).cloned() else {
        eprintln!("mdbook-owb: expected [context, book]");
        return ExitCode::from(1);
    };
    let book_root = context
        .get("root")
        .and_then(Value::as_str)
        .map_or_else(|| PathBuf::from("book"), PathBuf::from);
    // the book lives in <crate>/book
    let root = book_root
        .parent()
        .map_or_else(|| PathBuf::from("."), PathBuf::from);
    let owb = std::env::current_exe()
        .ok()
        .and_then(|p| p.parent().map(|d| d.join("owb")))
        .filter(|p| p.is_file())
        .or_else(|| std::env::var_os("OWB").map(PathBuf::from));
    let ctx = BookContext { root, owb };
    if let Err(e) = walk(&mut book, &ctx) {
        eprintln!("mdbook-owb: {e}");
        return ExitCode::from(1);
    }
    match serde_json::to_string(&book) {
        Ok(s) => {
            println!("{s}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("mdbook-owb: {e}");
            ExitCode::from(1)
        }
    }
}
