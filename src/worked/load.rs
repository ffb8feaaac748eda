//! Reading worked-example files: one file, or a folder, each error located by file, line and
//! field.

use super::format::ExampleFile;

use crate::algebra::{Rational, ToF64};
use crate::syntax::parse_scalar;
use std::path::{Path, PathBuf};

/// A worked-example file that cannot be used, located by file, line and field.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{file}:{line}: {field}: {message}")]
pub struct WorkedError {
    /// The file.
    pub file: String,
    /// 1-based line (0 when unknown).
    pub line: usize,
    /// The field or claim.
    pub field: String,
    /// What is wrong.
    pub message: String,
}

/// The 1-based line of `field = …` inside the block that starts at the line `key = "value"`
/// (a claim's `id`, a scenario's `name`), or from the top when `block` is `None`; the block's
/// own line when the field is not written there.
pub(crate) fn locate(raw: &str, block: Option<(&str, &str)>, field: &str) -> usize {
    let lines: Vec<&str> = raw.lines().collect();
    let assigns = |l: &str, key: &str| {
        l.trim_start()
            .strip_prefix(key)
            .is_some_and(|r| r.trim_start().starts_with('='))
    };
    let start = match block {
        Some((key, value)) => lines
            .iter()
            .position(|l| assigns(l, key) && l.contains(&format!("\"{value}\"")))
            .unwrap_or(0),
        None => 0,
    };
    lines
        .iter()
        .enumerate()
        .skip(start)
        .find(|(_, l)| assigns(l, field))
        .map_or(start + 1, |(i, _)| i + 1)
}

/// The field a TOML error at 1-based `line` concerns, named as the other errors name fields:
/// `claims.L.what` (the table, the block's `id` or `name`, the key written on that line);
/// `toml` when the line assigns nothing (a syntax error).
pub(crate) fn toml_field(raw: &str, line: usize) -> String {
    let lines: Vec<&str> = raw.lines().collect();
    let Some(here) = line.checked_sub(1).and_then(|i| lines.get(i)) else {
        return "toml".into();
    };
    let key_of = |l: &str| -> Option<String> {
        let (k, _) = l.split_once('=')?;
        let k = k.trim();
        let bare = !k.is_empty()
            && k.chars()
                .all(|c| c.is_alphanumeric() || matches!(c, '_' | '-' | '.'));
        bare.then(|| k.to_string())
    };
    let Some(key) = key_of(here) else {
        return "toml".into();
    };
    let header = (0..line - 1).rev().find_map(|i| {
        let t = lines[i].trim();
        t.starts_with('[')
            .then(|| (i, t.trim_matches(|c| c == '[' || c == ']').to_string()))
    });
    let Some((start, table)) = header else {
        return key;
    };
    // the block's name: its `id` or `name`, wherever in the block it is written
    let end = (start + 1..lines.len())
        .find(|&i| lines[i].trim_start().starts_with('['))
        .unwrap_or(lines.len());
    let name = lines[start + 1..end].iter().find_map(|l| {
        let k = key_of(l)?;
        if k != "id" && k != "name" {
            return None;
        }
        let v = l.split_once('=')?.1.trim();
        Some(v.trim_matches('"').to_string())
    });
    match name {
        Some(n) if key != "id" && key != "name" => format!("{table}.{n}.{key}"),
        _ => format!("{table}.{key}"),
    }
}

/// Reads and checks one example file.
///
/// # Errors
/// [`WorkedError`] naming file, line and field for malformed TOML, unknown fields, bad
/// parameter values, duplicate or unknown claim kinds.
pub fn load_example(path: &Path) -> Result<(ExampleFile, String), WorkedError> {
    let file = path.display().to_string();
    let raw = std::fs::read_to_string(path).map_err(|e| WorkedError {
        file: file.clone(),
        line: 0,
        field: "file".into(),
        message: e.to_string(),
    })?;
    let ex = parse_example(&file, &raw)?;
    Ok((ex, raw))
}

/// Parses and checks the text of a worked-example file (`file` names it in errors).
///
/// # Errors
/// [`WorkedError`] with file, line and field.
pub fn parse_example(file: &str, raw: &str) -> Result<ExampleFile, WorkedError> {
    let file = file.to_string();
    let raw = raw.to_string();
    let ex: ExampleFile = toml::from_str(&raw).map_err(|e| {
        let line = e.span().map_or(0, |s| {
            raw[..s.start.min(raw.len())].matches('\n').count() + 1
        });
        WorkedError {
            file: file.clone(),
            line,
            field: toml_field(&raw, line),
            message: e.message().to_string(),
        }
    })?;
    for (name, value) in &ex.parameters {
        parse_scalar::<Rational>(value).map_err(|e| WorkedError {
            file: file.clone(),
            line: locate(&raw, None, name),
            field: format!("parameters.{name}"),
            message: e.show_in(value),
        })?;
    }
    let mut seen = std::collections::BTreeSet::new();
    for c in &ex.claims {
        if !seen.insert(c.id.clone()) {
            return Err(WorkedError {
                file: file.clone(),
                line: locate(&raw, Some(("id", &c.id)), "id"),
                field: "id".into(),
                message: format!("claim id '{}' appears twice", c.id),
            });
        }
        let bad = |field: &str, message: String| WorkedError {
            file: file.clone(),
            line: locate(&raw, Some(("id", &c.id)), field),
            field: format!("claims.{}.{field}", c.id),
            message,
        };
        let documented = [
            c.erratum.is_some(),
            c.approximate.is_some(),
            c.unreproducible.is_some(),
        ];
        if documented.iter().filter(|&&d| d).count() > 1 {
            return Err(bad(
                "erratum",
                "give at most one of erratum, approximate and unreproducible".into(),
            ));
        }
        if let Some(a) = &c.approximate {
            Tolerance::parse(&a.tolerance).map_err(|m| bad("tolerance", m))?;
        }
    }
    Ok(ex)
}

/// Every `*.toml` in a folder (not recursive), sorted by file name.
///
/// # Errors
/// [`WorkedError`] for an unreadable folder.
pub fn load_folder(dir: &Path) -> Result<Vec<PathBuf>, WorkedError> {
    let entries = std::fs::read_dir(dir).map_err(|e| WorkedError {
        file: dir.display().to_string(),
        line: 0,
        field: "folder".into(),
        message: e.to_string(),
    })?;
    let mut files: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    Ok(files)
}

/// A tolerance on every entry: relative (`"1.5%"`) or absolute (`"0.5"`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Tolerance {
    Relative(f64),
    Absolute(f64),
}

impl Tolerance {
    pub(super) fn parse(text: &str) -> Result<Tolerance, String> {
        let t = text.trim();
        let (number, relative) = match t.strip_suffix('%') {
            Some(n) => (n, true),
            None => (t, false),
        };
        let x = parse_scalar::<Rational>(number.trim())
            .map_err(|e| e.show_in(number))?
            .to_f64();
        if !(x.is_finite() && x > 0.0) {
            return Err(format!("'{text}': a tolerance must be positive"));
        }
        Ok(if relative {
            Tolerance::Relative(x / 100.0)
        } else {
            Tolerance::Absolute(x)
        })
    }
    pub(super) fn admits(self, (absolute, relative): (f64, f64)) -> bool {
        match self {
            Tolerance::Relative(r) => relative <= r,
            Tolerance::Absolute(a) => absolute <= a,
        }
    }
    pub(super) fn show(self) -> String {
        match self {
            Tolerance::Relative(r) => format!("{}%", r * 100.0),
            Tolerance::Absolute(a) => format!("{a}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::toml_field;

    #[test]
    fn toml_errors_name_the_field_of_their_line() {
        let raw = "id = \"x\"\n\n[[claims]]\nid = \"L\"\nwhat = \"gian\"\n\n[system]\nA = \"[1\"\n";
        assert_eq!(toml_field(raw, 1), "id");
        assert_eq!(toml_field(raw, 5), "claims.L.what");
        assert_eq!(toml_field(raw, 4), "claims.id");
        assert_eq!(toml_field(raw, 8), "system.A");
        assert_eq!(toml_field(raw, 3), "toml");
        assert_eq!(toml_field(raw, 0), "toml");
        assert_eq!(toml_field(raw, 99), "toml");
    }
}
