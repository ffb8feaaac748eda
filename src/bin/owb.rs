//! `owb`, the observer workbench's command line; everything lives in the library's `cli` module.

/// The C library's allocator, large blocks mapped on their own for huge pages (`cli::LargePages`).
#[cfg(target_os = "linux")]
#[global_allocator]
static ALLOCATOR: observer_workbench::cli::LargePages = observer_workbench::cli::LargePages;

fn main() -> std::process::ExitCode {
    observer_workbench::cli::main()
}
