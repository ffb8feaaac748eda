//! The course book's directives: `{{#owb …}}` in the book's markdown, expanded from the code at
//! build time by the `mdbook-owb` preprocessor, so book and workbench cannot disagree.
//!
//! | directive | expands to |
//! |---|---|
//! | `{{#owb verify-table EXAMPLE}}` | the example's claims: printed, recomputed, verdict |
//! | `{{#owb derivation EXAMPLE CLAIM}}` | the claim's derivation in LaTeX (display math) |
//! | `{{#owb figure EXAMPLE SCENARIO}}` | the simulated figure (inline SVG), its numbers and checked statements |
//! | `{{#owb exercise ID}}` | an exercise's statement and parts, answer fields checked in the browser, and how to check answers with `owb check` |
//! | `{{#owb variant}}` | a form giving each student their own generated exercise, checked in the browser |
//! | `{{#owb playground}}` | the workbench in the page: gain, observability, canonical form, worked examples verified |
//! | `{{#owb errata}}` | the errata found in the documents |
//! | `{{#owb value EXAMPLE CLAIM}}` | a claim's recomputed value, inline (the build fails if the claim is a mismatch) |
//! | `{{#owb coverage}}` | every document's checkable statements, each with what checks it or why nothing does |
//! | `{{#owb run ARGS…}}` | the output of `owb ARGS…` (quotes group words) |
//!
//! An unknown directive or a failing computation is an error naming the chapter and the
//! directive, and fails the book build.

pub mod widgets;

use crate::exercise::{answer_key, load_exercise};
use crate::simulation::plot::svg;
use crate::worked::{load_example, load_folder, run_scenarios, verify_example, ExampleReport};
use anyhow::{anyhow, bail, Result};
use std::fmt::Write;
use std::path::{Path, PathBuf};

/// A directive that could not be expanded.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{chapter}: {{{{#owb {directive}}}}}: {message}")]
pub struct BookError {
    /// The chapter (source path).
    pub chapter: String,
    /// The directive text.
    pub directive: String,
    /// What went wrong.
    pub message: String,
}

/// Where the workbench's data are.
#[derive(Clone, Debug)]
pub struct BookContext {
    /// The crate root (holds `worked_examples/`).
    pub root: PathBuf,
    /// Whether `run` directives may run `owb` commands (off when expanding untrusted text:
    /// a command can read and write files).
    pub run_commands: bool,
}

/// Splits directive arguments on whitespace; double quotes group words.
fn split_args(text: &str) -> Result<Vec<String>> {
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut quoted = false;
    let mut any = false;
    for ch in text.chars() {
        match ch {
            '"' => {
                quoted = !quoted;
                any = true;
            }
            c if c.is_whitespace() && !quoted => {
                if any {
                    out.push(std::mem::take(&mut cur));
                    any = false;
                }
            }
            c => {
                cur.push(c);
                any = true;
            }
        }
    }
    if quoted {
        bail!("unclosed double quote");
    }
    if any {
        out.push(cur);
    }
    Ok(out)
}

/// A matrix in input syntax written as the documents write it, entries separated by spaces
/// (`[1 0; -1 0]`), when no entry holds a space (`[1 + sqrt(2), 3]` keeps its commas).
fn matlab_spacing(text: &str) -> String {
    let t = text.trim();
    let Some(inner) = t.strip_prefix('[').and_then(|r| r.strip_suffix(']')) else {
        return text.to_string();
    };
    let entries_plain = inner
        .split([';', ','])
        .all(|e| !e.trim().is_empty() && !e.trim().contains(' '));
    if entries_plain && !inner.contains('[') {
        format!("[{}]", inner.replace(", ", " "))
    } else {
        text.to_string()
    }
}

fn cell(s: &str) -> String {
    s.replace('|', "\\|")
        .replace('\n', " ")
        .replace('*', "\\*")
        .replace('_', "\\_")
}

impl BookContext {
    fn example(&self, id: &str) -> Result<(PathBuf, crate::worked::ExampleFile, String)> {
        let dir = self.root.join("worked_examples");
        let files = load_folder(&dir)?;
        let path = files
            .into_iter()
            .find(|f| f.file_stem().is_some_and(|s| s == id))
            .ok_or_else(|| anyhow!("no worked example '{id}' in {}", dir.display()))?;
        let (ex, raw) = load_example(&path)?;
        Ok((path, ex, raw))
    }

    fn report(&self, id: &str) -> Result<ExampleReport> {
        let (path, ex, raw) = self.example(id)?;
        Ok(verify_example(&path, &ex, &raw)?)
    }

    fn verify_table(&self, id: &str) -> Result<String> {
        let r = self.report(id)?;
        // the document by its author and title (its file name only where no title is recorded)
        let titles = crate::worked::coverage::titles(&self.root.join("worked_examples"));
        let source = titles
            .get(&r.document)
            .map_or_else(|| format!("`{}`", r.document), Clone::clone);
        let mut out = format!(
            "*Worked example `{}` — {} (source: {source}), recomputed by `owb verify {}`:*\n\n| claim | where | printed | recomputed | verdict |\n|---|---|---|---|---|\n",
            r.id, r.title, r.id
        );
        for c in &r.claims {
            let _ = writeln!(
                out,
                "| {} | {} | `{}` | `{}` | <span class=\"owb-verdict-{}\">{}</span> |",
                cell(&c.id),
                cell(&c.source),
                c.printed.replace('|', "\\|").replace('\n', " "),
                // the value only; how it was obtained is in the verdict's explanation
                matlab_spacing(c.recomputed.split(" — ").next().unwrap_or(""))
                    .replace('|', "\\|")
                    .replace('\n', " "),
                match c.verdict {
                    crate::worked::Verdict::HoldsApproximately => "approx",
                    v => v.key(),
                },
                c.verdict.word()
            );
        }
        let notes: Vec<String> = r
            .claims
            .iter()
            .filter(|c| c.verdict != crate::worked::Verdict::Holds)
            .map(|c| {
                // the first sentence; the whole explanation and its check are in the errata chapter
                let first = c
                    .explanation
                    .split_once(". ")
                    .map_or(c.explanation.as_str(), |(a, _)| a);
                format!(
                    "- **{}** ({}): {}. [The whole explanation and its check.](errata.md)",
                    c.id,
                    c.verdict.word(),
                    cell(first.trim_end_matches('.'))
                )
            })
            .collect();
        if !notes.is_empty() {
            out.push('\n');
            out.push_str(&notes.join("\n"));
            out.push('\n');
        }
        Ok(out)
    }

    /// One claim of an example, verified.
    fn claim(&self, id: &str, claim: &str) -> Result<crate::worked::ClaimReport> {
        self.report(id)?
            .claims
            .into_iter()
            .find(|c| c.id == claim)
            .ok_or_else(|| anyhow!("example '{id}' has no claim '{claim}'"))
    }

    fn derivation(&self, id: &str, claim: &str) -> Result<String> {
        let c = self.claim(id, claim)?;
        let mut out = format!(
            "*Derivation of `{}` ({}), computed by the workbench — verdict: **{}**.*\n\n$$\n{}\n$$\n",
            c.id,
            c.source,
            c.verdict.word(),
            c.derivation.to_latex()
        );
        out.push('\n');
        Ok(out)
    }

    fn figure(&self, id: &str, scenario: &str) -> Result<String> {
        let (path, ex, raw) = self.example(id)?;
        let (runs, checks) = run_scenarios(&path, &ex, &raw)?;
        let run = runs
            .iter()
            .find(|r| r.name == scenario)
            .ok_or_else(|| anyhow!("example '{id}' has no scenario '{scenario}'"))?;
        let title = format!("{} — {}", ex.id, run.figure);
        let picture = svg(&run.trace, &run.plot, &title, &run.time_unit)?;
        let picture = picture
            .lines()
            .filter(|l| !l.trim().is_empty())
            .collect::<Vec<_>>()
            .join("\n");
        let mut out = format!(
            "<figure class=\"owb-figure\">\n{picture}\n<figcaption>{} (<code>owb simulate {id} --scenario {scenario}</code>)</figcaption>\n</figure>\n\n",
            run.figure
        );
        let _ = writeln!(
            out,
            "*Observer:* {}. *Assumptions:* {}\n",
            run.observer, run.assumptions
        );
        out.push_str("| error | ∫e² dt | overshoot | settling (s) | steady RMS | max \\|e\\|/max \\|x\\| |\n|---|---|---|---|---|---|\n");
        for s in &run.summary {
            // an overshoot is relative to the initial error: none without one
            let overshoot = if s.initial_error == 0.0 {
                "— (e(0) = 0)".to_string()
            } else {
                format!("{:.4}", s.overshoot)
            };
            let _ = writeln!(
                out,
                "| e{} | {:.4e} | {overshoot} | {:.3} | {:.3e} | {:.3e} |",
                s.state, s.ise, s.settling_time, s.steady_rms, s.max_relative_error
            );
        }
        let mine: Vec<_> = checks.iter().filter(|c| c.scenario == scenario).collect();
        if !mine.is_empty() {
            out.push_str("\nWhat the document says about this figure, checked by the numbers:\n\n");
            for c in mine {
                let _ = writeln!(
                    out,
                    "- {} — {}: {} → **{}**",
                    c.source,
                    c.metric,
                    c.comparison,
                    c.verdict()
                );
            }
        }
        Ok(out)
    }

    fn exercise(&self, id: &str) -> Result<String> {
        let path = self
            .root
            .join("worked_examples/exercises")
            .join(format!("{id}.toml"));
        let (ex, raw) = load_exercise(&path)?;
        // the key must be computable, or the exercise is not in the book
        let key = answer_key(&path.display().to_string(), &ex)?;
        let mut out = format!(
            "### Exercise: {}\n\n*Source: {}.*\n\n{}\n\nParts to answer:\n\n",
            ex.title,
            ex.source,
            ex.statement.trim()
        );
        for p in &key.parts {
            let _ = writeln!(
                out,
                "- `{}` — {} ({} point{})",
                p.spec.id,
                p.spec.prompt,
                p.spec.points,
                if p.spec.points == 1.0 { "" } else { "s" }
            );
        }
        let _ = write!(
            out,
            "\nWrite your answers in a TOML file (`[answers]` then `{} = \"…\"`, in the workbench's input syntax) and check them with `owb check {id} answers.toml`: the checker names the mistake when it recognises it.\n",
            key.parts.first().map_or("K", |p| p.spec.id.as_str())
        );
        let _ = write!(out, "\n{}\n", widgets::exercise_form(id, &raw, &key));
        Ok(out)
    }

    /// Every document's coverage list: per statement, what checks it or why nothing does.
    fn coverage(&self) -> Result<String> {
        use crate::worked::coverage;
        let dir = self.root.join("worked_examples");
        let mut examples = Vec::new();
        for f in load_folder(&dir)? {
            examples.push(load_example(&f)?.0);
        }
        let mut out = String::new();
        for (path, list) in coverage::load(&dir)? {
            let totals = coverage::check(&path, &list, &examples)?;
            let _ = write!(
                out,
                "\n## {}\n\n*{}* (`{}`)\n\n| where | statement | checked by |\n|---|---|---|\n",
                cell(&list.title),
                cell(&totals.counts()),
                list.document
            );
            for st in &list.statements {
                let by = if !st.recorded.is_empty() {
                    st.recorded
                        .iter()
                        .map(|r| format!("`{r}`"))
                        .collect::<Vec<_>>()
                        .join(", ")
                } else if let Some(ex) = &st.input {
                    format!("input data of `{ex}`")
                } else {
                    st.not_checked
                        .map_or_else(String::new, |w| format!("not checked: {}", w.word()))
                };
                let by = if st.related.is_empty() {
                    by
                } else {
                    format!(
                        "{by}; related (bears on it, not counted): {}",
                        st.related
                            .iter()
                            .map(|r| format!("`{r}`"))
                            .collect::<Vec<_>>()
                            .join(", ")
                    )
                };
                let by = match &st.note {
                    Some(n) => format!("{by} — {}", cell(n)),
                    None => by,
                };
                let _ = writeln!(
                    out,
                    "| {} | {} | {} |",
                    cell(&st.location),
                    cell(&st.statement),
                    by
                );
            }
        }
        Ok(out)
    }

    fn playground(&self) -> Result<String> {
        let dir = self.root.join("worked_examples");
        let mut examples = Vec::new();
        for f in load_folder(&dir)? {
            let (_, raw) = load_example(&f)?;
            let id = f
                .file_stem()
                .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
            examples.push((id, raw));
        }
        Ok(format!("\n{}\n", widgets::playground(&examples)))
    }

    /// A claim's recomputed value, inline, for prose that quotes a number: the build fails when
    /// the claim is a mismatch, so the sentence cannot outlive its number.
    fn value(&self, id: &str, claim: &str) -> Result<String> {
        let c = self.claim(id, claim)?;
        if c.verdict == crate::worked::Verdict::Mismatch {
            bail!("claim '{claim}' of '{id}' is a mismatch: the prose quoting it is wrong");
        }
        Ok(format!("`{}`", matlab_spacing(&c.recomputed)))
    }

    fn errata(&self) -> Result<String> {
        let dir = self.root.join("worked_examples");
        let files = load_folder(&dir)?;
        let mut reports = Vec::new();
        for f in &files {
            let (ex, raw) = load_example(f)?;
            reports.push(verify_example(f, &ex, &raw)?);
        }
        let md =
            crate::worked::errata_markdown_titled(&reports, &crate::worked::coverage::titles(&dir));
        // the chapter has its own title
        Ok(md
            .lines()
            .skip_while(|l| l.starts_with("# "))
            .collect::<Vec<_>>()
            .join("\n"))
    }

    fn run(&self, args: &[String]) -> Result<String> {
        // the directive's words are read as the command line reads them, and the request run
        // by the same library function as the `owb` binary's
        let command = crate::api::Command::from_words(args)
            .map_err(|e| anyhow!("owb {}: {e}", args.join(" ")))?;
        let report = match crate::api::run(command) {
            Ok(r) if r.outcome == crate::api::Outcome::Ok => r.text,
            Ok(_) => bail!("owb {} reported a failure", args.join(" ")),
            Err(f) => return Err(f.error.context(format!("owb {}", args.join(" ")))),
        };
        Ok(format!(
            "```text\n$ owb {}\n{}```\n",
            args.iter()
                .map(|a| if a.contains(' ') || a.is_empty() {
                    format!("\"{a}\"")
                } else {
                    a.clone()
                })
                .collect::<Vec<_>>()
                .join(" "),
            report
        ))
    }

    /// Expands one directive (the text between `{{#owb ` and `}}`).
    ///
    /// # Errors
    /// A message for an unknown directive, wrong arguments or a failing computation.
    pub fn directive(&self, text: &str) -> Result<String> {
        let args = split_args(text)?;
        let (name, rest) = args
            .split_first()
            .ok_or_else(|| anyhow!("empty directive"))?;
        let want = |n: usize| -> Result<()> {
            if rest.len() == n {
                Ok(())
            } else {
                Err(anyhow!(
                    "'{name}' takes {n} argument(s), {} given",
                    rest.len()
                ))
            }
        };
        match name.as_str() {
            "verify-table" => want(1).and_then(|()| self.verify_table(&rest[0])),
            "derivation" => want(2).and_then(|()| self.derivation(&rest[0], &rest[1])),
            "figure" => want(2).and_then(|()| self.figure(&rest[0], &rest[1])),
            "exercise" => want(1).and_then(|()| self.exercise(&rest[0])),
            "errata" => want(0).and_then(|()| self.errata()),
            "variant" => want(0).map(|()| format!("\n{}\n", widgets::variant_form())),
            "playground" => want(0).and_then(|()| self.playground()),
            "coverage" => want(0).and_then(|()| self.coverage()),
            "value" => want(2).and_then(|()| self.value(&rest[0], &rest[1])),
            "run" if !self.run_commands => Err(anyhow!("run directives are off here")),
            "run" => self.run(rest),
            other => Err(anyhow!(
                "unknown directive '{other}' (verify-table, derivation, figure, exercise, variant, playground, coverage, value, errata, run)"
            )),
        }
    }

    /// Expands every `{{#owb …}}` in a chapter.
    ///
    /// # Errors
    /// [`BookError`] for the first directive that fails.
    pub fn expand(&self, chapter: &str, content: &str) -> Result<String, BookError> {
        let mut out = String::with_capacity(content.len());
        let mut rest = content;
        while let Some(start) = rest.find("{{#owb") {
            out.push_str(&rest[..start]);
            let after = &rest[start + "{{#owb".len()..];
            let end = after.find("}}").ok_or_else(|| BookError {
                chapter: chapter.into(),
                directive: after.lines().next().unwrap_or("").into(),
                message: "no closing }}".into(),
            })?;
            let body = after[..end].trim();
            // the outermost point of a book build: the error and its causes become the message
            let expanded = self.directive(body).map_err(|e| BookError {
                chapter: chapter.into(),
                directive: body.into(),
                message: format!("{e:#}"),
            })?;
            out.push_str(&expanded);
            rest = &after[end + 2..];
        }
        out.push_str(rest);
        Ok(out)
    }
}

/// The chapters of a book's `src/` folder (markdown files), for tests and checks.
pub fn chapters(src: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(src)
        .map(|d| {
            d.filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|x| x == "md"))
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

/// Expands the `{{#owb …}}` directives of every chapter in a book, walking mdBook's book JSON.
fn walk(v: &mut serde_json::Value, ctx: &BookContext) -> Result<()> {
    match v {
        serde_json::Value::Object(map) => {
            if let Some(serde_json::Value::Object(ch)) = map.get_mut("Chapter") {
                let name = ch
                    .get("source_path")
                    .and_then(serde_json::Value::as_str)
                    .or_else(|| ch.get("name").and_then(serde_json::Value::as_str))
                    .unwrap_or("chapter")
                    .to_string();
                if let Some(serde_json::Value::String(content)) = ch.get_mut("content") {
                    *content = ctx.expand(&name, content)?;
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
        serde_json::Value::Array(items) => {
            for item in items {
                walk(item, ctx)?;
            }
        }
        _ => {}
    }
    Ok(())
}

/// The preprocessor's whole job: mdBook's `[context, book]` JSON in, the book JSON with every
/// directive expanded out. The crate root is `root` if given, else the parent of the context's
/// book root.
///
/// # Errors
///
/// Input that is not `[context, book]` JSON, or the first directive that fails (its chapter and
/// reason).
pub fn preprocess(input: &str, root: Option<&Path>) -> Result<String> {
    preprocess_with(input, root, true)
}

/// [`preprocess`], with `run` directives allowed or not.
///
/// # Errors
///
/// As [`preprocess`]; a `run` directive when `run_commands` is false.
pub fn preprocess_with(input: &str, root: Option<&Path>, run_commands: bool) -> Result<String> {
    use serde_json::Value;
    let parsed: Value = serde_json::from_str(input)
        .map_err(|e| anyhow!("the input is not mdBook's [context, book] JSON: {e}"))?;
    let Some(Value::Object(context)) = parsed.get(0) else {
        bail!("expected [context, book]: no context object");
    };
    let Some(book) = parsed.get(1) else {
        bail!("expected [context, book]: no book");
    };
    let root = match root {
        Some(r) => r.to_path_buf(),
        None => {
            let book_root = context
                .get("root")
                .and_then(Value::as_str)
                .map_or_else(|| PathBuf::from("book"), PathBuf::from);
            // the book lives in <crate>/book
            book_root
                .parent()
                .map_or_else(|| PathBuf::from("."), PathBuf::from)
        }
    };
    let mut book = book.clone();
    walk(&mut book, &BookContext { root, run_commands })?;
    Ok(serde_json::to_string(&book)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arguments_split_on_spaces_and_quotes() {
        assert_eq!(
            split_args(r#"run gain --a "[2 -3; 4 -5]" --c "[-3 2]""#).unwrap(),
            vec!["run", "gain", "--a", "[2 -3; 4 -5]", "--c", "[-3 2]"]
        );
        assert!(split_args("run \"open").is_err());
    }

    #[test]
    fn unknown_directives_fail_with_the_chapter() {
        let ctx = BookContext {
            root: PathBuf::from(env!("CARGO_MANIFEST_DIR")),
            run_commands: false,
        };
        let e = ctx
            .expand("intro.md", "text {{#owb nonsense 1}} more")
            .unwrap_err();
        assert_eq!(e.chapter, "intro.md");
        assert!(e.message.contains("unknown directive"));
        assert!(ctx
            .expand("a.md", "{{#owb verify-table no-such-example}}")
            .is_err());
        // a quoted value: inline, and refused for a claim that does not exist
        let v = ctx
            .expand("a.md", "G1 is {{#owb value baranowski-rc-ladder G1}} here")
            .unwrap();
        assert_eq!(v, "G1 is `[6; 14; 14]` here");
        assert!(ctx
            .expand("a.md", "{{#owb value baranowski-rc-ladder no-such-claim}}")
            .is_err());
        assert_eq!(ctx.expand("a.md", "plain").unwrap(), "plain");
    }
}
