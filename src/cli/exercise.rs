//! `owb check`, `owb grade` and `owb exercise new`: students check their answers, teachers grade
//! a class and generate fresh exercises.

use super::args::{examples_folder, print_json, write_atomically};
use super::Outcome;
use crate::exercise::generate::{pole_placement, Settings};
use crate::exercise::{
    answer_key, check_answers, load_answers, load_exercise, AnswerKey, ExerciseFile, PartVerdict,
};
use anyhow::{anyhow, bail, Context, Result};
use std::path::{Path, PathBuf};

/// Arguments of `owb check`.
#[derive(clap::Args)]
pub struct CheckArgs {
    /// The exercise (id in worked_examples/exercises or a file path).
    exercise: String,
    /// The answers file (TOML: [answers] K = "[-6; -12]").
    answers: PathBuf,
    /// Machine-readable output.
    #[arg(long)]
    json: bool,
}

/// Arguments of `owb grade`.
#[derive(clap::Args)]
pub struct GradeArgs {
    /// The exercise (id or file path).
    exercise: String,
    /// The folder of submissions (*.toml, one per student).
    submissions: PathBuf,
    /// The CSV report (one row per student and part), written atomically.
    #[arg(allow_hyphen_values = true, long, value_name = "FILE")]
    csv: PathBuf,
    /// A folder for one feedback file per student.
    #[arg(allow_hyphen_values = true, long, value_name = "DIR")]
    feedback: Option<PathBuf>,
}

/// Arguments of `owb exercise`.
#[derive(clap::Args)]
pub struct ExerciseArgs {
    #[command(subcommand)]
    command: ExerciseCommand,
}

#[derive(clap::Subcommand)]
enum ExerciseCommand {
    /// Generate a fresh exercise with its answer key (the same seed gives the same exercise).
    New(NewArgs),
}

#[derive(clap::Args)]
struct NewArgs {
    /// The kind of exercise (pole-placement).
    #[arg(allow_hyphen_values = true, long, default_value = "pole-placement")]
    kind: String,
    /// Order, or a range like 2..4.
    #[arg(allow_hyphen_values = true, long, default_value = "2..3")]
    order: String,
    /// Seed.
    #[arg(allow_hyphen_values = true, long)]
    seed: u64,
    /// a-kc (default) or a+lc.
    #[arg(allow_hyphen_values = true, long, default_value = "a-kc")]
    convention: String,
    /// Write the exercise here (default: print it).
    #[arg(allow_hyphen_values = true, long, value_name = "FILE")]
    out: Option<PathBuf>,
    /// Also print the answer key.
    #[arg(long)]
    key: bool,
}

fn find(exercise: &str) -> Result<PathBuf> {
    let p = Path::new(exercise);
    if p.is_file() {
        return Ok(p.to_path_buf());
    }
    let dir = examples_folder(Path::new("worked_examples")).join("exercises");
    let candidate = dir.join(format!("{exercise}.toml"));
    if candidate.is_file() {
        return Ok(candidate);
    }
    bail!(
        "no exercise '{exercise}' (give a file path or an id in {})",
        dir.display()
    )
}

fn key_of(exercise: &str) -> Result<(ExerciseFile, AnswerKey)> {
    let path = find(exercise)?;
    let (ex, _) = load_exercise(&path)?;
    let key = answer_key(&path.display().to_string(), &ex)?;
    Ok((ex, key))
}

fn student_name(path: &Path, given: Option<&str>) -> String {
    given.map(str::to_string).unwrap_or_else(|| {
        path.file_stem()
            .map_or_else(|| "student".into(), |s| s.to_string_lossy().into_owned())
    })
}

pub fn check(args: CheckArgs) -> Result<Outcome> {
    let (ex, key) = key_of(&args.exercise)?;
    let (answers, _) = load_answers(&args.answers)?;
    if let Some(id) = &answers.exercise {
        if id != &ex.id {
            bail!(
                "{}: these answers are for exercise '{id}', not '{}'",
                args.answers.display(),
                ex.id
            );
        }
    }
    let report = check_answers(
        &key,
        &answers,
        &student_name(&args.answers, answers.student.as_deref()),
    );
    if args.json {
        print_json(&serde_json::to_value(&report)?);
    } else {
        out!("{}", report.text());
    }
    Ok(if report.all_correct() {
        Outcome::Ok
    } else {
        Outcome::Failed
    })
}

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

pub fn grade(args: GradeArgs) -> Result<Outcome> {
    let (ex, key) = key_of(&args.exercise)?;
    let mut files: Vec<PathBuf> = std::fs::read_dir(&args.submissions)
        .with_context(|| format!("reading {}", args.submissions.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    if files.is_empty() {
        bail!("no submissions (*.toml) in {}", args.submissions.display());
    }
    // Never write a report over a student's submission (or over the exercise itself).
    let same = |a: &std::path::Path, b: &std::path::Path| match (a.canonicalize(), b.canonicalize())
    {
        (Ok(x), Ok(y)) => x == y,
        _ => false,
    };
    for out in std::iter::once(&args.csv) {
        if let Some(f) = files.iter().find(|f| same(f, out)) {
            bail!(
                "in --csv: {} is a submission being graded; write the report elsewhere",
                f.display()
            );
        }
        if same(std::path::Path::new(&args.exercise), out) {
            bail!("in --csv: {} is the exercise file", out.display());
        }
    }
    if let Some(dir) = &args.feedback {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let mut csv = String::from("student,file,part,verdict,mistake,score,points,feedback\n");
    let (mut students, mut invalid, mut perfect) = (0, 0, 0);
    for file in &files {
        students += 1;
        let name = student_name(file, None);
        match load_answers(file) {
            Err(e) => {
                invalid += 1;
                csv.push_str(&format!(
                    "{},{},,invalid,,0,{},{}\n",
                    csv_field(&name),
                    csv_field(&file.display().to_string()),
                    key.parts.iter().map(|p| p.spec.points).sum::<f64>(),
                    csv_field(&e.to_string())
                ));
            }
            Ok((answers, _)) => {
                let student = student_name(file, answers.student.as_deref());
                let wrong_exercise = answers.exercise.as_ref().filter(|id| **id != ex.id);
                if let Some(id) = wrong_exercise {
                    invalid += 1;
                    csv.push_str(&format!(
                        "{},{},,invalid,,0,{},{}\n",
                        csv_field(&student),
                        csv_field(&file.display().to_string()),
                        key.parts.iter().map(|p| p.spec.points).sum::<f64>(),
                        csv_field(&format!("answers for exercise '{id}', not '{}'", ex.id))
                    ));
                    continue;
                }
                let report = check_answers(&key, &answers, &student);
                perfect += usize::from(report.all_correct());
                for p in &report.parts {
                    csv.push_str(&format!(
                        "{},{},{},{},{},{},{},{}\n",
                        csv_field(&student),
                        csv_field(&file.display().to_string()),
                        csv_field(&p.id),
                        match p.verdict {
                            PartVerdict::Correct => "correct",
                            PartVerdict::Wrong => "wrong",
                            PartVerdict::Missing => "missing",
                            PartVerdict::Unreadable => "unreadable",
                        },
                        p.mistake.as_deref().unwrap_or(""),
                        p.score,
                        p.points,
                        csv_field(&p.feedback)
                    ));
                }
                if let Some(dir) = &args.feedback {
                    let name = file
                        .file_stem()
                        .map_or_else(|| "student".into(), |s| s.to_string_lossy().into_owned());
                    write_atomically(&dir.join(format!("{name}.txt")), &report.text())?;
                }
            }
        }
    }
    write_atomically(&args.csv, &csv)?;
    outln!(
        "{students} submissions graded for {}: {perfect} fully correct, {invalid} invalid (reported in {}); report written to {}",
        ex.id,
        args.csv.display(),
        args.csv.display()
    );
    Ok(Outcome::Ok)
}

pub fn exercise(args: ExerciseArgs) -> Result<Outcome> {
    match args.command {
        ExerciseCommand::New(a) => {
            if a.kind != "pole-placement" {
                bail!("in --kind: unknown kind '{}' (pole-placement)", a.kind);
            }
            let (lo, hi) = match a.order.split_once("..") {
                Some((l, h)) => (l.trim().parse::<usize>(), h.trim().parse::<usize>()),
                None => (
                    a.order.trim().parse::<usize>(),
                    a.order.trim().parse::<usize>(),
                ),
            };
            let (lo, hi) = (
                lo.map_err(|e| anyhow!("in --order: '{}': {e} (give N or N..M)", a.order))?,
                hi.map_err(|e| anyhow!("in --order: '{}': {e} (give N or N..M)", a.order))?,
            );
            let text = pole_placement(&Settings {
                min_order: lo,
                max_order: hi,
                seed: a.seed,
                convention: a.convention.clone(),
            })?;
            // the key is computed, never typed: fail here if it cannot be
            let ex: ExerciseFile =
                toml::from_str(&text).context("the generated exercise does not parse (a bug)")?;
            let key = answer_key("generated", &ex)?;
            match &a.out {
                Some(p) => write_atomically(p, &text)?,
                None => out!("{text}"),
            }
            if a.key {
                outln!("# answer key (computed)");
                for p in &key.parts {
                    outln!("# {} = \"{}\"", p.spec.id, p.value.input());
                }
            }
            Ok(Outcome::Ok)
        }
    }
}
