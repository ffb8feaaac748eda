//! `owb check`, `owb grade` and `owb exercise new`: students check their answers, teachers grade
//! a class and generate fresh exercises.

use super::args::{examples_folder, print_json, write_atomically, write_atomically_with};
use super::Outcome;
use crate::exercise::generate::{pole_placement, Kind, Settings};
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
    /// The exercise (id or file path), or `variants`: each submission answers its own generated
    /// exercise (its `exercise` id, as the course book's per-student variants write it), which
    /// is regenerated, and must be the variant of the submission's `student`.
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
    /// The kind of exercise: pole-placement, dead-beat or reduced-order.
    #[arg(allow_hyphen_values = true, long, default_value = "pole-placement")]
    kind: String,
    /// Order, or a range like 2..4.
    #[arg(allow_hyphen_values = true, long, default_value = "2..3")]
    order: String,
    /// Seed.
    #[arg(
        allow_hyphen_values = true,
        long,
        required_unless_present = "student",
        conflicts_with = "student"
    )]
    seed: Option<u64>,
    /// A student's id instead of a seed: the student's own variant, the same one the course
    /// book generates in the browser for this id (seed = FNV-1a of the id, lower-cased).
    #[arg(allow_hyphen_values = true, long)]
    student: Option<String>,
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

/// The longest text a report cell holds: feedback quoting a huge answer is cut, said so.
const MAX_CELL_CHARS: usize = 2000;

fn csv_field(s: &str) -> String {
    let cut;
    let s = match s.char_indices().nth(MAX_CELL_CHARS) {
        Some((end, _)) => {
            cut = format!(
                "{}… ({} more characters)",
                &s[..end],
                s[end..].chars().count()
            );
            cut.as_str()
        }
        None => s,
    };
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// Counts over the class.
#[derive(Default)]
struct Tally {
    students: usize,
    invalid: usize,
    perfect: usize,
}

/// One submission's report rows and feedback text.
struct Graded {
    lines: Vec<String>,
    feedback: Option<String>,
}

/// Grades one submission: a file that cannot be read, or answers another exercise, is an
/// `invalid` row (never skipped); otherwise one row per part.
/// What a class answers: one exercise, or each student their own generated variant.
enum Target {
    One { id: String, key: Box<AnswerKey> },
    Variants,
}

/// The key of the variant a submission answers: its `exercise` id regenerated, refused unless it
/// is the variant of the submission's `student`.
fn variant_key(answers: &crate::exercise::AnswerFile) -> std::result::Result<AnswerKey, String> {
    use crate::exercise::generate::student_seed;
    let id = answers
        .exercise
        .as_deref()
        .ok_or("a variant's answers name their exercise (exercise = \"generated-…\")")?;
    let student = answers
        .student
        .as_deref()
        .ok_or("a variant's answers name their student (student = \"…\")")?;
    let settings =
        Settings::from_id(id).ok_or_else(|| format!("'{id}' is not a generated exercise's id"))?;
    if settings.seed != student_seed(student) {
        let theirs = Settings {
            kind: settings.kind,
            ..Settings::for_student(
                student,
                settings.min_order,
                settings.max_order,
                &settings.convention,
            )
        };
        return Err(format!(
            "exercise '{id}' is not the variant of student '{student}' (theirs is '{}')",
            theirs.id()
        ));
    }
    let text = pole_placement(&settings).map_err(|e| e.to_string())?;
    let ex: ExerciseFile = toml::from_str(&text).map_err(|e| e.to_string())?;
    answer_key(id, &ex).map_err(|e| e.to_string())
}

fn grade_one(target: &Target, file: &Path, tally: &mut Tally) -> Graded {
    tally.students += 1;
    // the points possible (unknown for a variant that cannot be regenerated)
    let total = match target {
        Target::One { key, .. } => key
            .parts
            .iter()
            .map(|p| p.spec.points)
            .sum::<f64>()
            .to_string(),
        Target::Variants => String::new(),
    };
    let invalid = |student: &str, why: &str| {
        format!(
            "{},{},,invalid,,0,{},{}\n",
            csv_field(student),
            csv_field(&file.display().to_string()),
            total,
            csv_field(why)
        )
    };
    let answers = match load_answers(file) {
        Err(e) => {
            tally.invalid += 1;
            return Graded {
                lines: vec![invalid(&student_name(file, None), &e.to_string())],
                feedback: None,
            };
        }
        Ok((answers, _)) => answers,
    };
    let student = student_name(file, answers.student.as_deref());
    let refused = |tally: &mut Tally, why: &str| {
        tally.invalid += 1;
        Graded {
            lines: vec![invalid(&student, why)],
            feedback: None,
        }
    };
    let variant;
    let key = match target {
        Target::One { id: exercise, key } => {
            if let Some(id) = answers.exercise.as_ref().filter(|id| *id != exercise) {
                return refused(
                    tally,
                    &format!("answers for exercise '{id}', not '{exercise}'"),
                );
            }
            key
        }
        Target::Variants => match variant_key(&answers) {
            Ok(k) => {
                variant = k;
                &variant
            }
            Err(why) => return refused(tally, &why),
        },
    };
    let report = check_answers(key, &answers, &student);
    tally.perfect += usize::from(report.all_correct());
    let lines = report
        .parts
        .iter()
        .map(|p| {
            format!(
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
            )
        })
        .collect();
    Graded {
        lines,
        feedback: Some(report.text()),
    }
}

pub fn grade(args: GradeArgs) -> Result<Outcome> {
    let target = if args.exercise == "variants" {
        Target::Variants
    } else {
        let (ex, key) = key_of(&args.exercise)?;
        Target::One {
            id: ex.id,
            key: Box::new(key),
        }
    };
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
    // One submission at a time, each row streamed to the report: memory stays that of one
    // submission, whatever the class size. A progress bar on a terminal only (not in CI logs).
    let progress = super::progress::Progress::new("grading", files.len());
    let mut tally = Tally::default();
    let mut feedback_error = None;
    write_atomically_with(&args.csv, |out| {
        out.write_all(b"student,file,part,verdict,mistake,score,points,feedback\n")?;
        for file in &files {
            let rows = grade_one(&target, file, &mut tally);
            for row in &rows.lines {
                out.write_all(row.as_bytes())?;
            }
            if let (Some(dir), Some(text)) = (&args.feedback, rows.feedback) {
                let name = file
                    .file_stem()
                    .map_or_else(|| "student".into(), |s| s.to_string_lossy().into_owned());
                if let Err(e) = write_atomically(&dir.join(format!("{name}.txt")), &text) {
                    feedback_error = Some(e);
                    return Err(std::io::Error::other(
                        "a feedback file could not be written",
                    ));
                }
            }
            progress.inc();
        }
        Ok(())
    })
    .map_err(|e| feedback_error.take().unwrap_or(e))?;
    progress.finish();
    let Tally {
        students,
        invalid,
        perfect,
    } = tally;
    outln!(
        "{students} submissions graded for {}: {perfect} fully correct, {invalid} invalid (reported in {}); report written to {}",
        match &target {
            Target::One { id, .. } => id.as_str(),
            Target::Variants => "their own variants",
        },
        args.csv.display(),
        args.csv.display()
    );
    Ok(Outcome::Ok)
}

pub fn exercise(args: ExerciseArgs) -> Result<Outcome> {
    match args.command {
        ExerciseCommand::New(a) => {
            let kind = Kind::parse(&a.kind).ok_or_else(|| {
                anyhow!(
                    "in --kind: unknown kind '{}' ({})",
                    a.kind,
                    Kind::ALL.map(Kind::name).join(", ")
                )
            })?;
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
            let settings = match (&a.student, a.seed) {
                (Some(student), _) => Settings {
                    kind,
                    ..Settings::for_student(student, lo, hi, &a.convention)
                },
                (None, seed) => Settings {
                    kind,
                    min_order: lo,
                    max_order: hi,
                    seed: seed.unwrap_or_default(),
                    convention: a.convention.clone(),
                },
            };
            let text = pole_placement(&settings)?;
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
