//! Where the command line's report goes: standard output, with a failed write remembered (not
//! panicked on) and turned into the program's status by [`finish`]. `outln!` and `out!` are
//! `println!` and `print!` that do so.

use std::fmt::Arguments;
use std::io::Write;
#[cfg(target_os = "linux")]
use std::path::Path;

/// The first error writing standard output met (a full disk, a closed descriptor, a reader
/// gone): later writes are skipped and [`finish`] reports it.
static FAILED: std::sync::Mutex<Option<std::io::ErrorKind>> = std::sync::Mutex::new(None);

fn failed() -> Option<std::io::ErrorKind> {
    *FAILED
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Writes formatted text to standard output. A write that fails (a full disk, a closed descriptor, the reader gone) is remembered, not
/// panicked on: [`finish`] turns it into the program's status.
pub fn write(args: Arguments<'_>) {
    if failed().is_none() {
        if let Err(e) = std::io::stdout().lock().write_fmt(args) {
            let mut f = FAILED
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner);
            f.get_or_insert(e.kind());
        }
    }
}

/// Flushes standard output and says how writing it went: `Ok` when everything written
/// arrived, else the kind of the first failure (a broken pipe, a full disk, a closed output).
pub fn finish() -> Result<(), std::io::ErrorKind> {
    if let Err(e) = std::io::stdout().lock().flush() {
        let mut f = FAILED
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        f.get_or_insert(e.kind());
    }
    failed().map_or(Ok(()), Err)
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

/// Refuses to run with a closed standard output (`owb … >&-`): the standard library treats
/// writes to a closed descriptor as successful, so the report would vanish with status 0,
/// and the first file the command opened would take the descriptor's place.
pub fn standard_output_open() -> std::io::Result<()> {
    let closed = "standard output is closed: the report would be lost; redirect it to a file (or to /dev/null)";
    #[cfg(unix)]
    {
        use std::os::fd::AsFd;
        if std::io::stdout().as_fd().try_clone_to_owned().is_err() {
            return Err(std::io::Error::other(closed));
        }
    }
    // The standard library opens /dev/null read-write in place of a standard descriptor that
    // was closed at start; a shell's `> /dev/null` opens it write-only. On Linux the two differ.
    #[cfg(target_os = "linux")]
    {
        let null = std::fs::read_link("/proc/self/fd/1").is_ok_and(|p| p == Path::new("/dev/null"));
        // its flags read only for /dev/null (an open, a read and a close less for every other
        // output)
        let read_write = || {
            std::fs::read_to_string("/proc/self/fdinfo/1").is_ok_and(|info| {
                info.lines()
                    .find_map(|l| l.strip_prefix("flags:"))
                    .and_then(|f| u32::from_str_radix(f.trim(), 8).ok())
                    .is_some_and(|flags| flags & 0o3 == 0o2)
            })
        };
        if null && read_write() {
            return Err(std::io::Error::other(closed));
        }
    }
    // (elsewhere — the browser — there is no standard output to test)
    let _ = closed;
    Ok(())
}
