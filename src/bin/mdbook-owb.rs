//! `mdbook-owb`: the mdBook preprocessor of the course book. It follows mdBook's preprocessor
//! protocol — `mdbook-owb supports RENDERER` answers whether a renderer is supported, and a plain
//! run reads `[context, book]` as JSON on stdin and writes the book back with every
//! `{{#owb …}}` directive expanded by the workbench (see the library's `book` module). A failing
//! directive prints its chapter and reason and exits 1, which fails `mdbook build`.

use observer_workbench::book::preprocess;
use std::io::Read;
use std::process::ExitCode;

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
    match preprocess(&input, None) {
        Ok(book) => {
            println!("{book}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("mdbook-owb: {e:#}");
            ExitCode::from(1)
        }
    }
}
