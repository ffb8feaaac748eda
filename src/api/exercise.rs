//! `owb check`, `owb grade` and `owb exercise new`: students check their answers, teachers grade
//! a class and generate fresh exercises.

use super::{Outcome, Report};
use crate::exercise::generate::{pole_placement, Kind, Settings};
use crate::exercise::{
    answer_key, check_answers, load_answers, load_exercise, AnswerKey, ExerciseFile, PartVerdict,
};
use crate::files::{csv_cell, escape_untrusted, write_safely};
use anyhow::{anyhow, bail, Context, Result};
use std::path::{Path, PathBuf};

/// Arguments of `owb check`.
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "commands", derive(clap::Args))]
pub struct CheckArgs {
    /// The exercise (id in worked_examples/exercises or a file path).
    pub exercise: String,
    /// The answers file (TOML: [answers] K = "[-6; -12]").
    // (the text is the command line's help too, so its brackets stay as typed)
    #[allow(rustdoc::broken_intra_doc_links)]
    pub answers: PathBuf,
    /// Machine-readable output.
    #[cfg_attr(feature = "commands", arg(long))]
    #[serde(default)]
    pub json: bool,
}

/// Arguments of `owb grade`.
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "commands", derive(clap::Args))]
pub struct GradeArgs {
    /// The exercise (id or file path), or `variants`: each submission answers its own generated
    /// exercise (its `exercise` id, as the course book's per-student variants write it), which
    /// is regenerated, and must be the variant of the submission's `student`.
    pub exercise: String,
    /// The folder of submissions (*.toml, one per student).
    pub submissions: PathBuf,
    /// The CSV report (one row per student and part), written atomically.
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, value_name = "FILE")
    )]
    pub csv: PathBuf,
    /// A folder for one feedback file per student.
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, value_name = "DIR")
    )]
    #[serde(default)]
    pub feedback: Option<PathBuf>,
    /// With `variants`: the kind of exercise the class was set (pole-placement, dead-beat,
    /// reduced-order). Each student's variant is derived from their id and these settings,
    /// never from the submission.
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, default_value_t = super::args::defaults::exercise_kind())
    )]
    #[serde(default = "super::args::defaults::exercise_kind")]
    pub kind: String,
    /// With `variants`: the order the class was set (N or N..M; the book's default is 3).
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, default_value_t = super::args::defaults::class_order())
    )]
    #[serde(default = "super::args::defaults::class_order")]
    pub order: String,
    /// With `variants`: the convention the class was set (a-kc or a+lc).
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, default_value_t = super::args::defaults::observer_convention())
    )]
    #[serde(default = "super::args::defaults::observer_convention")]
    pub convention: String,
    /// Machine-readable summary.
    #[cfg_attr(feature = "commands", arg(long))]
    #[serde(default)]
    pub json: bool,
}

/// Arguments of `owb exercise`.
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "commands", derive(clap::Args))]
pub struct ExerciseArgs {
    /// What to do with exercises.
    #[cfg_attr(feature = "commands", command(subcommand))]
    pub action: ExerciseCommand,
}

#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "commands", derive(clap::Subcommand))]
/// What `owb exercise` does.
pub enum ExerciseCommand {
    /// Generate a fresh exercise with its answer key (the same seed gives the same exercise).
    New(NewArgs),
}

#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "commands", derive(clap::Args))]
/// Arguments of `owb exercise new`.
pub struct NewArgs {
    /// The kind of exercise: pole-placement, dead-beat, reduced-order or formula.
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, default_value_t = super::args::defaults::exercise_kind())
    )]
    #[serde(default = "super::args::defaults::exercise_kind")]
    pub kind: String,
    /// Order, or a range like 2..4.
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, default_value_t = super::args::defaults::new_exercise_orders())
    )]
    #[serde(default = "super::args::defaults::new_exercise_orders")]
    pub order: String,
    /// Seed.
    #[cfg_attr(
        feature = "commands",
        arg(
            allow_hyphen_values = true,
            long,
            required_unless_present = "student",
            conflicts_with = "student"
        )
    )]
    #[serde(default)]
    pub seed: Option<u64>,
    /// A student's id instead of a seed: the student's own variant, the same one the course
    /// book generates in the browser for this id (seed = FNV-1a of the id, lower-cased).
    #[cfg_attr(feature = "commands", arg(allow_hyphen_values = true, long))]
    #[serde(default)]
    pub student: Option<String>,
    /// a-kc (default) or a+lc.
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, default_value_t = super::args::defaults::observer_convention())
    )]
    #[serde(default = "super::args::defaults::observer_convention")]
    pub convention: String,
    /// Write the exercise here (default: print it).
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, value_name = "FILE")
    )]
    #[serde(default)]
    pub out: Option<PathBuf>,
    /// Also print the answer key.
    #[cfg_attr(feature = "commands", arg(long))]
    #[serde(default)]
    pub key: bool,
    /// Machine-readable output: the exercise's id, text and computed key.
    #[cfg_attr(feature = "commands", arg(long))]
    #[serde(default)]
    pub json: bool,
}

/// An exercise found: a file, or one built into the program.
enum Found {
    File(PathBuf),
    BuiltIn(&'static str, &'static str),
}

/// An exercise by file path, by id in `./worked_examples/exercises`, or by id among the
/// exercises built into the program (an installed `owb` needs no checkout).
fn find(exercise: &str) -> Result<Found> {
    let p = Path::new(exercise);
    if p.is_file() {
        return Ok(Found::File(p.to_path_buf()));
    }
    let local = Path::new("worked_examples")
        .join("exercises")
        .join(format!("{exercise}.toml"));
    if !exercise.contains(['/', '\\']) && local.is_file() {
        return Ok(Found::File(local));
    }
    if let Some((id, text)) = crate::exercise::builtin(exercise) {
        return Ok(Found::BuiltIn(id, text));
    }
    bail!(
        "no exercise '{}' (give a file path or an id: {})",
        escape_untrusted(exercise),
        crate::exercise::BUILTIN_EXERCISES
            .iter()
            .map(|(id, _)| *id)
            .collect::<Vec<_>>()
            .join(", ")
    )
}

fn key_of(exercise: &str) -> Result<(ExerciseFile, AnswerKey, Option<PathBuf>)> {
    match find(exercise)? {
        Found::File(path) => {
            let (ex, _) = load_exercise(&path)?;
            let key = answer_key(&path.display().to_string(), &ex)?;
            Ok((ex, key, Some(path)))
        }
        Found::BuiltIn(id, text) => {
            let name = format!("{id} (built in)");
            let ex = crate::exercise::parse_exercise(Path::new(&name), text)?;
            let key = answer_key(&name, &ex)?;
            Ok((ex, key, None))
        }
    }
}

fn student_name(path: &Path, given: Option<&str>) -> String {
    given.map(str::to_string).unwrap_or_else(|| {
        path.file_stem()
            .map_or_else(|| "student".into(), |s| s.to_string_lossy().into_owned())
    })
}

impl ExerciseArgs {
    /// Whether the request writes a file (`exercise new --out`).
    pub fn writes_file(&self) -> bool {
        match &self.action {
            ExerciseCommand::New(n) => n.out.is_some(),
        }
    }
}

/// `owb check`: a student's answers checked, the mistake named.
///
/// # Errors
///
/// What the request gets wrong (named by its flag) or what the computation refuses.
pub fn check(args: CheckArgs, rep: &mut Report) -> Result<Outcome> {
    let (ex, key, _) = key_of(&args.exercise)?;
    let (answers, _) = load_answers(&args.answers)?;
    if let Some(id) = &answers.exercise {
        if id != &ex.id {
            bail!(
                "{}: these answers are for exercise '{}', not '{}'",
                escape_untrusted(&args.answers.display().to_string()),
                escape_untrusted(id),
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
        rep.json(serde_json::to_value(&report)?);
    } else {
        out!(rep, "{}", report.text());
    }
    Ok(if report.all_correct() {
        Outcome::Ok
    } else {
        Outcome::Failed
    })
}

/// The longest text a report cell holds: feedback quoting a huge answer is cut, said so.
const MAX_CELL_CHARS: usize = 2000;

/// A report cell: cut at [`MAX_CELL_CHARS`] (said so), safe for spreadsheets
/// ([`csv_cell`]: no formulas, no invisible characters).
fn csv_field(s: &str) -> String {
    match s.char_indices().nth(MAX_CELL_CHARS) {
        Some((end, _)) => csv_cell(&format!(
            "{}… ({} more characters)",
            &s[..end],
            s[end..].chars().count()
        )),
        None => csv_cell(s),
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

/// What a class answers: one exercise, or each student their own generated variant of the
/// teacher's settings.
enum Target {
    One { id: String, key: Box<AnswerKey> },
    Variants(Settings),
}

/// The key of the variant a student was set: derived from the student's id and the teacher's
/// settings, never from the submission (a submission naming another variant — an easier
/// order, another kind — is refused, with both named).
fn variant_key(
    class: &Settings,
    answers: &crate::exercise::AnswerFile,
) -> Result<(String, AnswerKey)> {
    let student = answers
        .student
        .as_deref()
        .filter(|s| !s.trim().is_empty())
        .ok_or_else(|| anyhow!("a variant's answers name their student (student = \"…\")"))?;
    let settings = Settings {
        kind: class.kind,
        ..Settings::for_student(student, class.min_order, class.max_order, &class.convention)
    };
    let id = settings.id();
    if let Some(theirs) = answers.exercise.as_deref() {
        if theirs != id {
            bail!(
                "answers for exercise '{}', but the variant set for student '{}' is '{id}'",
                escape_untrusted(theirs),
                escape_untrusted(student)
            );
        }
    }
    let text = pole_placement(&settings)?;
    let ex: ExerciseFile = toml::from_str(&text)?;
    let key = answer_key(&id, &ex)?;
    Ok((id, key))
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
        Target::Variants(_) => String::new(),
    };
    let invalid = |student: &str, exercise: &str, why: &str| {
        format!(
            "{},{},,invalid,,0,{},{},{}\n",
            csv_field(student),
            csv_field(&file.display().to_string()),
            total,
            csv_field(why),
            csv_field(exercise)
        )
    };
    let class_id = match target {
        Target::One { id, .. } => id.clone(),
        Target::Variants(_) => String::new(),
    };
    let answers = match load_answers(file) {
        Err(e) => {
            tally.invalid += 1;
            return Graded {
                lines: vec![invalid(
                    &student_name(file, None),
                    &class_id,
                    &e.to_string(),
                )],
                feedback: None,
            };
        }
        Ok((answers, _)) => answers,
    };
    let student = student_name(file, answers.student.as_deref());
    let refused = |tally: &mut Tally, exercise: &str, why: &str| {
        tally.invalid += 1;
        Graded {
            lines: vec![invalid(&student, exercise, why)],
            feedback: None,
        }
    };
    let variant;
    let (exercise, key) = match target {
        Target::One { id: exercise, key } => {
            if let Some(id) = answers.exercise.as_ref().filter(|id| *id != exercise) {
                return refused(
                    tally,
                    exercise,
                    &format!("answers for exercise '{id}', not '{exercise}'"),
                );
            }
            (exercise.clone(), &**key)
        }
        Target::Variants(class) => match variant_key(class, &answers) {
            Ok((id, k)) => {
                variant = k;
                (id, &variant)
            }
            Err(why) => return refused(tally, "", &format!("{why:#}")),
        },
    };
    // a bug met by one submission is that submission's row, not the end of the class's grading
    let report = match std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        check_answers(key, &answers, &student)
    })) {
        Ok(r) => r,
        Err(_) => {
            return refused(
                tally,
                &exercise,
                "internal error while checking these answers (a bug in the workbench; please report it)",
            )
        }
    };
    tally.perfect += usize::from(report.all_correct());
    let lines = report
        .parts
        .iter()
        .map(|p| {
            format!(
                "{},{},{},{},{},{},{},{},{}\n",
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
                csv_field(&p.feedback),
                csv_field(&exercise)
            )
        })
        .collect();
    Graded {
        lines,
        feedback: Some(report.text()),
    }
}

/// The order flag: N or N..M.
fn order_range(flag: &str, order: &str) -> Result<(usize, usize)> {
    let (lo, hi) = match order.split_once("..") {
        Some((l, h)) => (l.trim().parse::<usize>(), h.trim().parse::<usize>()),
        None => (order.trim().parse::<usize>(), order.trim().parse::<usize>()),
    };
    let shown = escape_untrusted(order);
    Ok((
        lo.map_err(|e| anyhow!("in {flag}: '{shown}': {e} (give N or N..M)"))?,
        hi.map_err(|e| anyhow!("in {flag}: '{shown}': {e} (give N or N..M)"))?,
    ))
}

fn kind_flag(kind: &str) -> Result<Kind> {
    Kind::parse(kind).ok_or_else(|| {
        anyhow!(
            "in --kind: unknown kind '{}' ({})",
            escape_untrusted(kind),
            Kind::ALL.map(Kind::name).join(", ")
        )
    })
}

/// `owb grade`: a folder of submissions graded into a CSV report.
///
/// # Errors
///
/// What the request gets wrong (named by its flag) or what the computation refuses.
pub fn grade(args: GradeArgs, rep: &mut Report) -> Result<Outcome> {
    let mut exercise_file = None;
    let target = if args.exercise == "variants" {
        let (lo, hi) = order_range("--order", &args.order)?;
        let class = Settings {
            kind: kind_flag(&args.kind)?,
            ..Settings::for_student("", lo, hi, &args.convention)
        };
        // the settings must generate: refuse a bad order or convention once, not per student
        pole_placement(&class).map_err(|e| anyhow!("in --order/--convention: {e}"))?;
        Target::Variants(class)
    } else {
        let (ex, key, path) = key_of(&args.exercise)?;
        exercise_file = path;
        Target::One {
            id: ex.id,
            key: Box::new(key),
        }
    };
    let mut files: Vec<PathBuf> = std::fs::read_dir(&args.submissions)
        .with_context(|| {
            format!(
                "reading {}",
                escape_untrusted(&args.submissions.display().to_string())
            )
        })?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    if files.is_empty() {
        bail!(
            "no submissions (*.toml) in {}",
            escape_untrusted(&args.submissions.display().to_string())
        );
    }
    // every input of the run is protected from the report and the feedback files
    let mut inputs: Vec<&Path> = files.iter().map(PathBuf::as_path).collect();
    if let Some(p) = &exercise_file {
        inputs.push(p);
    }
    if let Some(dir) = &args.feedback {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    // One submission at a time, each row streamed to the report: memory stays that of one
    // submission, whatever the class size. A progress bar on a terminal only (not in CI logs).
    let progress = super::progress::Progress::new("grading", files.len());
    let mut tally = Tally::default();
    let mut feedback_error = None;
    let written = write_safely(&args.csv, &inputs, |out| {
        out.write_all(b"student,file,part,verdict,mistake,score,points,feedback,exercise\n")?;
        for file in &files {
            let rows = grade_one(&target, file, &mut tally);
            for row in &rows.lines {
                out.write_all(row.as_bytes())?;
            }
            if let (Some(dir), Some(text)) = (&args.feedback, rows.feedback) {
                let name = file
                    .file_stem()
                    .map_or_else(|| "student".into(), |s| s.to_string_lossy().into_owned());
                let path = dir.join(format!("{name}.txt"));
                if let Err(e) = write_safely(&path, &inputs, |w| w.write_all(text.as_bytes())) {
                    feedback_error = Some(e);
                    return Err(std::io::Error::other(
                        "a feedback file could not be written",
                    ));
                }
            }
            progress.inc();
        }
        Ok(())
    });
    if let Err(e) = written {
        return Err(match feedback_error.take() {
            Some(f) => anyhow!("in --feedback: {f}"),
            None => anyhow!("in --csv: {e}"),
        });
    }
    progress.finish();
    let Tally {
        students,
        invalid,
        perfect,
    } = tally;
    let what = match &target {
        Target::One { id, .. } => id.clone(),
        Target::Variants(s) => format!(
            "their own variants ({}, order {}, {})",
            s.kind.name(),
            s.order(),
            s.convention
        ),
    };
    if args.json {
        rep.json(serde_json::json!({
            "exercise": what,
            "submissions": students,
            "fully_correct": perfect,
            "invalid": invalid,
            "report": args.csv.display().to_string(),
        }));
    } else {
        outln!(rep,
            "{students} submissions graded for {what}: {perfect} fully correct, {invalid} invalid (reported in {}); report written to {}",
            args.csv.display(),
            args.csv.display()
        );
    }
    Ok(Outcome::Ok)
}

/// `owb exercise new`: a fresh exercise with its computed key.
///
/// # Errors
///
/// What the request gets wrong (named by its flag) or what the computation refuses.
pub fn exercise(args: ExerciseArgs, rep: &mut Report) -> Result<Outcome> {
    match args.action {
        ExerciseCommand::New(a) => {
            let kind = kind_flag(&a.kind)?;
            let (lo, hi) = order_range("--order", &a.order)?;
            let settings = match (&a.student, a.seed) {
                (Some(_), Some(_)) => {
                    bail!("--seed and --student both given: a student's variant has its own seed")
                }
                (None, None) => bail!("give --seed N or --student ID"),
                (Some(student), None) => Settings {
                    kind,
                    ..Settings::for_student(student, lo, hi, &a.convention)
                },
                (None, Some(seed)) => Settings {
                    kind,
                    min_order: lo,
                    max_order: hi,
                    seed,
                    convention: a.convention.clone(),
                },
            };
            let text = pole_placement(&settings)?;
            // the key is computed, never typed: fail here if it cannot be
            let ex: ExerciseFile =
                toml::from_str(&text).context("the generated exercise does not parse (a bug)")?;
            let key = answer_key("generated", &ex)?;
            if let Some(p) = &a.out {
                write_safely(p, &[], |w| w.write_all(text.as_bytes()))
                    .map_err(|e| anyhow!("in --out: {e}"))?;
            }
            if a.json {
                rep.json(serde_json::json!({
                    "id": ex.id,
                    "exercise": text,
                    "out": a.out.as_ref().map(|p| p.display().to_string()),
                    "key": key.parts.iter().map(|p| serde_json::json!({
                        "part": p.spec.id,
                        "answer": p.value.input(),
                    })).collect::<Vec<_>>(),
                }));
                return Ok(Outcome::Ok);
            }
            if a.out.is_none() {
                out!(rep, "{text}");
            }
            if a.key {
                outln!(rep, "# answer key (computed)");
                for p in &key.parts {
                    outln!(rep, "# {} = \"{}\"", p.spec.id, p.value.input());
                }
            }
            Ok(Outcome::Ok)
        }
    }
}
