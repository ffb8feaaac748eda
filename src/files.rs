//! Files the workbench reads from others and files it writes, handled in one place.
//!
//! * [`read_untrusted`]: a student's or a teacher's file is read only when it is a regular file
//!   (no symbolic link, FIFO, device or socket), and its size is bounded while it is read, not
//!   trusted from its metadata (`/proc` files and devices report 0 bytes).
//! * [`write_safely`]: every file the workbench writes (`--csv`, `--feedback`, `--svg`,
//!   `--out`, `--errata`) goes through a fresh temporary beside it, renamed over the target
//!   only when complete, and never over an input of the run, a worked example or exercise, a
//!   symbolic link, a device or a FIFO; the temporary is removed on every failure path, and
//!   errors name the file the user asked for.
//! * [`escape_untrusted`] and [`first_invisible`]: text from a student's file is echoed with
//!   its control and bidirectional characters made visible (`\u{202e}`), and answers that hold
//!   them are refused with the position named.

use std::io::{Read, Write};
use std::path::{Path, PathBuf};

/// Why a file could not be read or written.
#[derive(Debug, thiserror::Error)]
pub enum FileError {
    /// The file is not a regular file.
    #[error("{file}: {what}; only regular files are read")]
    NotRegular {
        /// The file as given.
        file: String,
        /// What it is instead.
        what: &'static str,
    },
    /// The file is larger than the limit.
    #[error("{file}: larger than {limit} bytes (the most accepted)")]
    TooLarge {
        /// The file as given.
        file: String,
        /// The limit in bytes.
        limit: u64,
    },
    /// The file is not UTF-8 text.
    #[error("{file}: not UTF-8 text")]
    NotText {
        /// The file as given.
        file: String,
    },
    /// A write that would replace something it must not.
    #[error("{file}: {why}; write elsewhere")]
    Refused {
        /// The file as given.
        file: String,
        /// What it would have replaced.
        why: String,
    },
    /// The operating system refused.
    #[error("{file}: {source}")]
    Io {
        /// The file as given.
        file: String,
        /// The error.
        source: std::io::Error,
    },
}

fn io(file: &Path) -> impl Fn(std::io::Error) -> FileError + '_ {
    move |source| FileError::Io {
        file: escape_untrusted(&file.display().to_string()),
        source,
    }
}

fn shown(path: &Path) -> String {
    escape_untrusted(&path.display().to_string())
}

/// What a file that is not a regular file is, from its metadata (not following links).
fn kind_of(meta: &std::fs::Metadata) -> Option<&'static str> {
    let t = meta.file_type();
    if t.is_symlink() {
        return Some("a symbolic link");
    }
    if t.is_dir() {
        return Some("a folder");
    }
    if t.is_file() {
        return None;
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return Some("a FIFO (named pipe)");
        }
        if t.is_char_device() || t.is_block_device() {
            return Some("a device");
        }
        if t.is_socket() {
            return Some("a socket");
        }
    }
    Some("not a regular file")
}

/// Reads a file someone else wrote: a regular file (symbolic links, FIFOs, devices and sockets
/// refused before anything is opened, so a FIFO cannot block), at most `limit` bytes counted
/// while reading, UTF-8.
///
/// # Errors
/// [`FileError`] naming the file (its name escaped) and the reason.
pub fn read_untrusted(path: &Path, limit: u64) -> Result<String, FileError> {
    let meta = std::fs::symlink_metadata(path).map_err(io(path))?;
    if let Some(what) = kind_of(&meta) {
        return Err(FileError::NotRegular {
            file: shown(path),
            what,
        });
    }
    let file = std::fs::File::open(path).map_err(io(path))?;
    // the file opened must still be a regular file (it may have been swapped meanwhile)
    let opened = file.metadata().map_err(io(path))?;
    if let Some(what) = kind_of(&opened) {
        return Err(FileError::NotRegular {
            file: shown(path),
            what,
        });
    }
    let mut bytes = Vec::new();
    file.take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(io(path))?;
    if bytes.len() as u64 > limit {
        return Err(FileError::TooLarge {
            file: shown(path),
            limit,
        });
    }
    String::from_utf8(bytes).map_err(|_| FileError::NotText { file: shown(path) })
}

/// Whether a character would change what a terminal, a spreadsheet or a page shows without
/// being seen: C0 and C1 controls (but tab and line breaks), DEL, the bidirectional
/// overrides, embeddings and isolates, and the zero-width characters.
pub fn is_invisible(c: char) -> bool {
    (c.is_control() && !matches!(c, '\t' | '\n' | '\r'))
        || matches!(c,
            '\u{200b}'..='\u{200f}'
            | '\u{202a}'..='\u{202e}'
            | '\u{2060}'..='\u{2064}'
            | '\u{2066}'..='\u{2069}'
            | '\u{feff}'
            | '\u{061c}')
}

/// The text with every invisible character (see [`is_invisible`]) written as `\u{…}`, so that
/// echoing a student's text cannot move the cursor, ring the bell or reverse what follows.
pub fn escape_untrusted(text: &str) -> String {
    if !text.chars().any(is_invisible) {
        return text.to_string();
    }
    text.chars()
        .map(|c| {
            if is_invisible(c) {
                format!("\\u{{{:x}}}", c as u32)
            } else {
                c.to_string()
            }
        })
        .collect()
}

/// The first invisible character of a text (see [`is_invisible`]), as "U+202E at character 4",
/// or `None` when there is none.
pub fn first_invisible(text: &str) -> Option<String> {
    text.chars()
        .enumerate()
        .find(|(_, c)| is_invisible(*c))
        .map(|(k, c)| format!("U+{:04X} at character {}", c as u32, k + 1))
}

/// A CSV cell: quoted when needed, and a cell a spreadsheet would read as a formula (starting
/// with `=`, `+`, `-`, `@`, a tab or a carriage return) prefixed with `'`; invisible
/// characters escaped.
pub fn csv_cell(text: &str) -> String {
    let mut s = escape_untrusted(text);
    if s.starts_with(['=', '+', '-', '@', '\t', '\r']) {
        s.insert(0, '\'');
    }
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s
    }
}

/// `path` with its folder resolved (the file itself need not exist).
fn resolved(path: &Path) -> Option<PathBuf> {
    if let Ok(p) = path.canonicalize() {
        return Some(p);
    }
    let name = path.file_name()?;
    let parent = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    Some(parent.canonicalize().ok()?.join(name))
}

/// The folders of worked examples and exercises no output may be written into: the one in the
/// current folder and the one shipped beside the crate.
fn protected_folders() -> Vec<PathBuf> {
    let mut out = Vec::new();
    for base in [
        PathBuf::from("worked_examples"),
        Path::new(env!("CARGO_MANIFEST_DIR")).join("worked_examples"),
    ] {
        if let Ok(p) = base.canonicalize() {
            if !out.contains(&p) {
                out.push(p);
            }
        }
    }
    out
}

/// Refuses a target that exists and is not a regular file, that is an input of this run, or
/// that lies in a folder of worked examples.
fn check_target(path: &Path, inputs: &[&Path]) -> Result<PathBuf, FileError> {
    let refuse = |why: String| FileError::Refused {
        file: shown(path),
        why,
    };
    if path.as_os_str().is_empty() {
        return Err(refuse("an empty file name".into()));
    }
    if let Ok(meta) = std::fs::symlink_metadata(path) {
        if let Some(what) = kind_of(&meta) {
            return Err(refuse(format!("it is {what}, not a regular file")));
        }
    }
    let target = resolved(path)
        .ok_or_else(|| refuse("its folder does not exist or cannot be resolved".into()))?;
    for input in inputs {
        if resolved(input).is_some_and(|i| i == target) {
            return Err(refuse(format!(
                "it is an input of this run ({})",
                shown(input)
            )));
        }
    }
    if let Some(dir) = protected_folders()
        .into_iter()
        .find(|d| target.starts_with(d))
    {
        return Err(refuse(format!(
            "it is inside the worked examples and exercises ({})",
            dir.display()
        )));
    }
    Ok(target)
}

/// Writes a file through a fresh temporary beside it, renamed over `path` only when complete,
/// after refusing targets it must not replace (see the module doc): `inputs` are the files
/// this run reads. A failure leaves the old file intact and no temporary behind.
///
/// # Errors
/// [`FileError`] naming `path` as the user gave it.
pub fn write_safely(
    path: &Path,
    inputs: &[&Path],
    fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<(), FileError> {
    let target = check_target(path, inputs)?;
    let name = target.file_name().unwrap_or_default().to_string_lossy();
    let folder = target.parent().unwrap_or(Path::new("."));
    // a fresh name, created exclusively: never an existing file or a planted link
    let mut tmp = None;
    for attempt in 0..100u32 {
        let candidate = folder.join(format!(".{name}.{}-{attempt}.tmp-owb", std::process::id()));
        match std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&candidate)
        {
            Ok(f) => {
                tmp = Some((candidate, f));
                break;
            }
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
            Err(e) => return Err(io(path)(e)),
        }
    }
    let Some((tmp, file)) = tmp else {
        return Err(FileError::Refused {
            file: shown(path),
            why: "no fresh temporary file could be created beside it".into(),
        });
    };
    let written = (|| {
        let mut out = std::io::BufWriter::new(file);
        fill(&mut out)?;
        out.flush()?;
        out.into_inner().map_err(|e| e.into_error())?.sync_all()?;
        // the target may have changed kind while we wrote
        if let Ok(meta) = std::fs::symlink_metadata(&target) {
            if kind_of(&meta).is_some() {
                return Err(std::io::Error::other(
                    "the target stopped being a regular file while it was written",
                ));
            }
        }
        std::fs::rename(&tmp, &target)
    })();
    if let Err(e) = written {
        let _ = std::fs::remove_file(&tmp);
        return Err(io(path)(e));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_cells_cannot_be_formulas() {
        assert_eq!(csv_cell("=1+1"), "'=1+1");
        assert_eq!(csv_cell("@SUM(A1)"), "'@SUM(A1)");
        assert_eq!(csv_cell("-2"), "'-2");
        assert_eq!(csv_cell("a,b"), "\"a,b\"");
        assert_eq!(csv_cell("Ada\u{202e}gnp.exe"), "Ada\\u{202e}gnp.exe");
    }

    #[test]
    fn invisible_characters_are_found_and_escaped() {
        assert_eq!(
            first_invisible("[1; \u{7}2]").as_deref(),
            Some("U+0007 at character 5")
        );
        assert_eq!(first_invisible("[1; 2]\n"), None);
        assert_eq!(escape_untrusted("a\u{1b}[2Jb"), "a\\u{1b}[2Jb");
    }
}
