//! Where the command line's report goes: standard output when `owb` runs, a buffer when the
//! library runs a command for someone else (the book preprocessor's `run` directive, the CLI
//! fuzz target, tests). `outln!` and `out!` are `println!` and `print!` that honour the buffer.

use std::cell::RefCell;
use std::fmt::Arguments;
use std::io::Write;

thread_local! {
    static CAPTURE: RefCell<Option<Vec<u8>>> = const { RefCell::new(None) };
}

/// Writes formatted text to the capture buffer if one is active, else to standard output.
/// A closed standard output panics as `print!` does (the binary's hook turns that into a
/// quiet exit with status 141).
pub fn write(args: Arguments<'_>) {
    let captured = CAPTURE.with(|c| match c.borrow_mut().as_mut() {
        Some(buf) => {
            let _ = buf.write_fmt(args);
            true
        }
        None => false,
    });
    if !captured {
        print!("{args}");
    }
}

/// Runs `f` with its report captured, and returns the report beside `f`'s result.
pub fn capture<R>(f: impl FnOnce() -> R) -> (R, String) {
    let previous = CAPTURE.with(|c| c.replace(Some(Vec::new())));
    let result = f();
    let buf = CAPTURE.with(|c| c.replace(previous)).unwrap_or_default();
    (result, String::from_utf8_lossy(&buf).into_owned())
}

/// `println!` into the command's report.
macro_rules! outln {
    () => { $crate::cli::output::write(format_args!("\n")) };
    ($($t:tt)*) => {{
        $crate::cli::output::write(format_args!($($t)*));
        $crate::cli::output::write(format_args!("\n"));
    }};
}

/// `print!` into the command's report.
macro_rules! out {
    ($($t:tt)*) => { $crate::cli::output::write(format_args!($($t)*)) };
}
