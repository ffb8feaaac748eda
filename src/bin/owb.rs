//! `owb`, the observer workbench's command line; everything lives in the library's `cli` module.

fn main() -> std::process::ExitCode {
    observer_workbench::cli::main()
}
