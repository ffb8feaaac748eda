//! Trust at the level users act (issue 26): each reproduction of the command-level sweep is a
//! regression test here, and a sweep feeds every subcommand's flags hostile values and asserts
//! a clean exit (0, 1, 2 — never a panic or a signal), a time budget, valid JSON under
//! `--json`, and no temporary file left behind.

mod common;
use common::owb;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Runs `owb` with a deadline; `(status, stdout, stderr, elapsed)`; a run past the deadline is
/// killed and reported as status -9.
fn owb_within(args: &[&str], limit: Duration) -> (i32, String, String, Duration) {
    let start = Instant::now();
    let mut child = Command::new(env!("CARGO_BIN_EXE_owb"))
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("owb starts");
    // read both pipes on threads, so a large report cannot block the child
    let mut out = child.stdout.take().expect("piped");
    let mut err = child.stderr.take().expect("piped");
    let t_out = std::thread::spawn(move || {
        let mut s = Vec::new();
        std::io::Read::read_to_end(&mut out, &mut s).ok();
        s
    });
    let t_err = std::thread::spawn(move || {
        let mut s = Vec::new();
        std::io::Read::read_to_end(&mut err, &mut s).ok();
        s
    });
    let code = loop {
        if let Some(status) = child.try_wait().expect("wait") {
            break status.code().unwrap_or(-1);
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            break -9;
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let elapsed = start.elapsed();
    let out = String::from_utf8_lossy(&t_out.join().unwrap_or_default()).into_owned();
    let err = String::from_utf8_lossy(&t_err.join().unwrap_or_default()).into_owned();
    (code, out, err, elapsed)
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("owb-trust-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// `owb check stoustrup-pole-assignment` on an answer file holding `answers` (the lines after
/// `[answers]`), with `extra` flags; `(status, stdout, stderr)` within 10 s.
fn check_stoustrup(name: &str, answers: &str, extra: &[&str]) -> (i32, String, String) {
    let dir = temp_dir(name);
    let file = dir.join("answers.toml");
    std::fs::write(
        &file,
        format!("exercise = \"stoustrup-pole-assignment\"\n[answers]\n{answers}"),
    )
    .unwrap();
    let mut args = vec!["check", "stoustrup-pole-assignment", file.to_str().unwrap()];
    args.extend_from_slice(extra);
    let (status, out, err, _) = owb_within(&args, Duration::from_secs(10));
    std::fs::remove_dir_all(&dir).ok();
    (status, out, err)
}

fn no_temporaries(dir: &Path) {
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        assert!(!name.contains("tmp-owb"), "a temporary was left: {name}");
    }
}

// ---- wrong answers with exit 0 ----------------------------------------------------------

#[test]
fn dlqe_returns_the_stabilising_solution_when_the_noise_misses_the_unstable_mode() {
    // A = 2, C = 1, Q_n = 0, R_n = 1: P = 0 also solves the equation but leaves A − LC = 2
    // unstable; the answer must solve it and make A − LC stable, both checked here exactly
    use observer_workbench::algebra::Rational;
    use observer_workbench::syntax::parse_scalar;
    let (code, out, err) = owb(&[
        "dlqe", "--a", "[2]", "--c", "[1]", "--qn", "[0]", "--rn", "[1]", "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let read = |key: &str| parse_scalar::<Rational>(v[key][0][0].as_str().unwrap()).unwrap();
    let (p, l) = (read("exact_p"), read("exact_gain"));
    let int = |k: i64| Rational::from_integer(k.into());
    let (a, q, r) = (int(2), int(0), int(1));
    // P = A P A − A P (P + R)⁻¹ P A + Q and L = A P (P + R)⁻¹, with C = 1
    let riccati = a.clone() * p.clone() * a.clone()
        - a.clone() * p.clone() * p.clone() * a.clone() / (p.clone() + r.clone())
        + q;
    assert_eq!(riccati, p, "{out}");
    assert_eq!(l, a.clone() * p.clone() / (p + r), "{out}");
    let closed = a - l;
    assert!(closed.clone() * closed < int(1), "A − LC not stable: {out}");
    assert!(v["spectral_radius"].as_f64().unwrap() < 1.0);
}

#[test]
fn dlqe_refuses_what_has_no_stabilising_solution_or_is_no_covariance() {
    for (args, why) in [
        (["[2]", "[0]", "[1]", "[1]"], "not detectable"),
        (["[1]", "[1]", "[0]", "[1]"], "unit circle"),
        (
            ["[1/2 1; 0 9/10]", "[1 0]", "[1 2; 0 1]", "[1]"],
            "not symmetric",
        ),
        (
            ["[1/2 1; 0 9/10]", "[1 0]", "[1 2; 2 1]", "[1]"],
            "negative eigenvalue",
        ),
        (["[1/2]", "[1]", "[1]", "[0]"], "R_n"),
    ] {
        let (code, out, err) = owb(&[
            "dlqe", "--a", args[0], "--c", args[1], "--qn", args[2], "--rn", args[3], "--json",
        ]);
        assert_eq!(code, 2, "{args:?}: {out}{err}");
        assert!(err.contains(why), "{args:?}: {err}");
        let v: serde_json::Value = serde_json::from_str(&out).unwrap();
        assert!(v["error"].as_str().unwrap().contains(why));
    }
}

#[test]
fn dlqe_never_reports_an_unverified_float_solution() {
    // a dense 8×8 where the equation is too ill-conditioned for f64 (SciPy's residual: 0.18)
    let a = "[-2 -4 4 3 -1 -8 8 3; -3 -5 2 -3 -2 0 4 -9; -2 -5 2 6 -9 -1 -5 3; 2 7 4 -9 -3 -1 -9 -3; 1 6 -4 7 9 -3 -4 -6; -1 -1 -4 6 -6 -4 -5 2; 7 -9 3 -9 -9 -8 0 -4; 0 -2 -7 8 7 0 -3 -2]";
    let q = "[1 0 0 0 0 0 0 0; 0 1 0 0 0 0 0 0; 0 0 1 0 0 0 0 0; 0 0 0 1 0 0 0 0; 0 0 0 0 1 0 0 0; 0 0 0 0 0 1 0 0; 0 0 0 0 0 0 1 0; 0 0 0 0 0 0 0 1]";
    let (code, out, err) = owb(&[
        "dlqe",
        "--a",
        a,
        "--c",
        "[1 0 0 0 0 0 0 0]",
        "--qn",
        q,
        "--rn",
        "[1]",
        "--json",
    ]);
    if code == 0 {
        let v: serde_json::Value = serde_json::from_str(&out).unwrap();
        assert!(v["residual"].as_f64().unwrap() <= 1e-8, "{out}");
        assert!(v["spectral_radius"].as_f64().unwrap() < 1.0, "{out}");
    } else {
        assert_eq!(code, 2, "{err}");
        assert!(err.contains("check"), "{err}");
    }
}

#[test]
fn continuous_poles_keep_their_imaginary_parts_or_are_refused() {
    let (code, _, err) = owb(&[
        "discrete",
        "--a",
        "[0 1; -2 -3]",
        "--c",
        "[1 0]",
        "--continuous-poles",
        "-1+2i, -3",
        "--period",
        "1/10",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("conjugate"), "{err}");
    let (code, out, err) = owb(&[
        "discrete",
        "--a",
        "[0 1; -2 -3]",
        "--c",
        "[1 0]",
        "--continuous-poles",
        "-1+2i, -1-2i",
        "--period",
        "1/10",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let z = v["z_poles"].as_array().unwrap();
    assert!(
        z.iter().any(|p| p["im"].as_f64().unwrap().abs() > 0.1),
        "{out}"
    );
    // an unobservable pair on the float path: refused, no empty gain
    let (code, _, err) = owb(&[
        "discrete",
        "--a",
        "[1 0; 0 2]",
        "--c",
        "[1 0]",
        "--continuous-poles",
        "-1, -2",
        "--period",
        "1",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("not observable"), "{err}");
}

#[test]
fn zoh_refuses_what_f64_cannot_hold() {
    for args in [
        ["--a", "[1]", "--b", "[1]", "--period", "1e300"],
        ["--a", "[1e1000]", "--b", "[1]", "--period", "1"],
        // finite, but its powers overflow: the squarings' count once ran into the budget
        ["--a", "[1e40 1; 1 1e40]", "--b", "[0; 1]", "--period", "1"],
        [
            "--a",
            "[1e60 -1e60; 1e60 1e60]",
            "--b",
            "[0; 1]",
            "--period",
            "1",
        ],
    ] {
        let mut all = vec!["zoh"];
        all.extend(args);
        let (code, out, err, took) = owb_within(&all, Duration::from_secs(10));
        assert_eq!(code, 2, "{args:?}: {out}{err}");
        assert!(took < Duration::from_secs(5), "{args:?} took {took:?}");
        assert!(!out.contains("NaN"), "{out}");
    }
}

#[test]
fn empty_matrices_are_refused() {
    for cmd in ["observe", "dlqe", "kalman", "perfect", "gain"] {
        let mut args = vec![cmd, "--a", "[]", "--c", "[]"];
        match cmd {
            "dlqe" => args.extend(["--qn", "[]", "--rn", "[]"]),
            "kalman" => args.extend(["--b", "[]", "--input-noise", "[]", "--output-noise", "[]"]),
            "perfect" => args.extend(["--b", "[]"]),
            "gain" => args.extend(["--poles", "-1"]),
            _ => {}
        }
        let (code, _, err) = owb(&args);
        assert_eq!(code, 2, "{cmd}: {err}");
        assert!(err.contains("empty"), "{cmd}: {err}");
    }
}

#[test]
fn an_imaginary_entry_is_no_slip() {
    let dir = temp_dir("slip");
    let f = dir.join("a.toml");
    std::fs::write(&f, "[answers]\nL = \"[i; -12]\"\n").unwrap();
    let (_, out, _) = owb(&["check", "stoustrup-pole-assignment", f.to_str().unwrap()]);
    let part = out
        .lines()
        .skip_while(|l| !l.contains(" L ("))
        .take(3)
        .collect::<Vec<_>>()
        .join("\n");
    assert!(part.contains("(0/"), "{part}");
    assert!(part.contains("not real"), "{part}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn optimal_says_when_no_start_converged() {
    // one start with a one-millisecond budget still runs that start; the report never claims
    // uniqueness without a converged minimum
    let (code, out, err) = owb(&[
        "optimal",
        "--a",
        "[0 1 0; 0 0 1; -1 -3 -3]",
        "--c",
        "[1 0 0; 0 1 0]",
        "--poles",
        "-1, -2, -3",
        "--starts",
        "1",
        "--seed",
        "7",
    ]);
    if code == 0 {
        assert!(!out.contains("0 converged"), "{out}");
    } else {
        assert_eq!(code, 2, "{err}");
        assert!(err.contains("no start converged"), "{err}");
    }
}

// ---- crashes ----------------------------------------------------------------------------

#[test]
fn long_chains_are_refused_not_a_stack_overflow() {
    let chain = vec!["1"; 7000].join("+");
    let (code, _, err) = owb(&[
        "gain",
        "--a",
        &format!("[{chain}]"),
        "--c",
        "[1]",
        "--poles",
        "-1",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("chain of operations"), "{err}");
    // a chain within the limit still reads, in a thread with the test harness's small stack
    let links = 900;
    let short = vec!["1"; links].join("+");
    let h = std::thread::spawn(move || {
        observer_workbench::syntax::parse_scalar::<observer_workbench::algebra::Rational>(&short)
    });
    assert_eq!(h.join().unwrap().unwrap().to_string(), links.to_string());
}

#[test]
fn huge_entries_on_the_float_paths_are_refused_not_a_panic() {
    for args in [
        vec![
            "gain",
            "--a",
            "[1e400 1; 0 1]",
            "--c",
            "[1 0]",
            "--poles",
            "-1, -2",
            "--float",
        ],
        vec![
            "gain",
            "--a",
            "[1e300 1; 0 1]",
            "--c",
            "[1 0]",
            "--poles",
            "-1, -2",
            "--float",
        ],
        vec![
            "discrete",
            "--a",
            "[1e300 1; 0 1]",
            "--c",
            "[1 0]",
            "--continuous-poles",
            "-1, -2",
            "--period",
            "1",
        ],
        vec![
            "kalman",
            "--a",
            "[1e300 1; 0 1]",
            "--b",
            "[0; 1]",
            "--c",
            "[1 0]",
            "--input-noise",
            "[1]",
            "--output-noise",
            "[1]",
        ],
        vec![
            "dlqe",
            "--a",
            "[1e300 1; 0 1]",
            "--c",
            "[1 0]",
            "--qn",
            "[1 0; 0 1]",
            "--rn",
            "[1]",
        ],
    ] {
        let (code, out, err, took) = owb_within(&args, Duration::from_secs(20));
        assert!(matches!(code, 0 | 2), "{args:?}: status {code}: {err}");
        assert!(took < Duration::from_secs(10), "{args:?} took {took:?}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        if code == 0 {
            // a float result that could not be trusted says so
            assert!(
                !out.contains("NaN") || out.contains("NOT") || out.contains("wrong"),
                "{args:?}: {out}"
            );
        }
    }
}

#[test]
fn a_full_or_closed_standard_output_is_an_error() {
    let full = std::fs::OpenOptions::new().write(true).open("/dev/full");
    if let Ok(full) = full {
        let status = Command::new(env!("CARGO_BIN_EXE_owb"))
            .args(["observe", "--a", "[0 1; -2 -3]", "--c", "[1 0]"])
            .stdout(full)
            .stderr(Stdio::piped())
            .output()
            .unwrap();
        assert_eq!(status.status.code(), Some(2));
        let err = String::from_utf8_lossy(&status.stderr);
        assert!(err.contains("writing standard output failed"), "{err}");
        assert!(!err.contains("panicked"), "{err}");
    }
    // a closed standard output (`>&-`), through the shell
    let closed = Command::new("sh")
        .arg("-c")
        .arg(format!(
            "'{}' observe --a '[0 1; -2 -3]' --c '[1 0]' >&-",
            env!("CARGO_BIN_EXE_owb")
        ))
        .output();
    if let Ok(o) = closed {
        assert_eq!(
            o.status.code(),
            Some(2),
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
}

/// Under a small limit on the process's data (`ulimit -d`, as an autograder's sandbox may set),
/// the commands answer as without it: the allocator's 16 MiB heap growth, refused there, falls
/// back to the C library's own (every command failed to allocate under 16 MB before that).
#[test]
fn a_small_data_limit_changes_no_answer() {
    let a = "[8 2 -1 7 1 5 7 -6 1 0; -6 3 2 8 -3 6 -4 1 2 -6; 6 -3 6 -8 -1 2 0 -3 5 4; \
             1 0 0 -6 -9 2 -8 -6 6 -5; 0 -1 -2 9 1 -4 -7 -3 9 6; 0 -9 9 5 9 -1 0 4 -9 5; \
             -9 4 9 -3 2 6 -6 7 -1 0; 9 1 6 7 -2 8 2 9 6 -4; 2 5 0 -7 4 5 -6 -1 -6 -4; \
             4 1 -1 9 8 6 -9 -9 1 9]";
    let c = "[1 0 0 0 0 0 0 0 0 0]";
    let requests: [&[&str]; 3] = [
        &["gain", "--a", a, "--c", c, "--repeated", "1", "--json"],
        &[
            "zoh",
            "--a",
            "[1/2 1; -1 -1/3]",
            "--b",
            "[1; 0]",
            "--period",
            "1/10",
        ],
        &[
            "control",
            "--a",
            a,
            "--b",
            "[1;0;0;0;0;0;0;0;0;0]",
            "--c",
            c,
            "--observer-poly",
            "(s + 1)^10",
            "--feedback-poly",
            "(s + 2)^10",
            "--json",
        ],
    ];
    for args in requests {
        let (code, free, _) = owb(args);
        assert_eq!(code, 0, "{args:?}");
        let quoted: Vec<String> = args.iter().map(|w| format!("'{w}'")).collect();
        for kb in [6000, 12000] {
            let limited = Command::new("sh")
                .arg("-c")
                .arg(format!(
                    "ulimit -d {kb} && exec '{}' {}",
                    env!("CARGO_BIN_EXE_owb"),
                    quoted.join(" ")
                ))
                .output();
            let Ok(o) = limited else { continue }; // no shell: nothing to check
            assert_eq!(
                (
                    o.status.code(),
                    String::from_utf8_lossy(&o.stdout).into_owned()
                ),
                (Some(0), free.clone()),
                "{args:?} under ulimit -d {kb}: {}",
                String::from_utf8_lossy(&o.stderr)
            );
        }
    }
}

// ---- lost files and untrusted files -----------------------------------------------------

#[test]
fn outputs_never_replace_an_exercise_a_worked_example_a_device_or_an_input() {
    let dir = temp_dir("writer");
    let subs = dir.join("subs");
    std::fs::create_dir_all(&subs).unwrap();
    std::fs::write(subs.join("ada.toml"), "[answers]\nL = \"[-6; -12]\"\n").unwrap();
    let exercise = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("worked_examples/exercises/stoustrup-pole-assignment.toml");
    let before = std::fs::read_to_string(&exercise).unwrap();
    for target in [
        exercise.to_str().unwrap(),
        "/dev/null",
        subs.join("ada.toml").to_str().unwrap(),
    ] {
        let (code, _, err) = owb(&[
            "grade",
            "stoustrup-pole-assignment",
            subs.to_str().unwrap(),
            "--csv",
            target,
        ]);
        assert_eq!(code, 2, "{target}: {err}");
    }
    assert_eq!(std::fs::read_to_string(&exercise).unwrap(), before);
    let example =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("worked_examples/diruscio-example-7-1.toml");
    let before = std::fs::read_to_string(&example).unwrap();
    let (code, _, err) = owb(&[
        "verify",
        "diruscio-example-7-1",
        "--errata",
        example.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert_eq!(std::fs::read_to_string(&example).unwrap(), before);
    #[cfg(unix)]
    {
        let link = dir.join("link.csv");
        std::os::unix::fs::symlink(dir.join("elsewhere.csv"), &link).unwrap();
        let (code, _, err) = owb(&[
            "grade",
            "stoustrup-pole-assignment",
            subs.to_str().unwrap(),
            "--csv",
            link.to_str().unwrap(),
        ]);
        assert_eq!(code, 2, "{err}");
        assert!(!dir.join("elsewhere.csv").exists());
    }
    no_temporaries(&dir);
    no_temporaries(&subs);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_class_with_hostile_submissions_is_graded_and_the_report_is_safe() {
    let dir = temp_dir("class");
    let subs = dir.join("subs");
    std::fs::create_dir_all(&subs).unwrap();
    std::fs::write(
        subs.join("a.toml"),
        "student = \"=HYPERLINK(1)\"\n[answers]\nL = \"[-6; -12]\"\n",
    )
    .unwrap();
    std::fs::write(
        subs.join("b.toml"),
        "student = \"Ada\\u202egnp.exe\"\n[answers]\nL = \"[1;\\u00072]\"\n",
    )
    .unwrap();
    let chain = vec!["1"; 7000].join("+");
    std::fs::write(
        subs.join("c.toml"),
        format!("[answers]\nL = \"[{chain}; 1]\"\n"),
    )
    .unwrap();
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink("/dev/zero", subs.join("d.toml")).unwrap();
        let _ = Command::new("mkfifo").arg(subs.join("e.toml")).status();
    }
    let csv = dir.join("report.csv");
    let (code, out, err, took) = owb_within(
        &[
            "grade",
            "stoustrup-pole-assignment",
            subs.to_str().unwrap(),
            "--csv",
            csv.to_str().unwrap(),
            "--json",
        ],
        Duration::from_secs(20),
    );
    assert_eq!(code, 0, "{err}");
    assert!(took < Duration::from_secs(10));
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(v["submissions"].as_u64().unwrap() >= 3);
    let report = std::fs::read_to_string(&csv).unwrap();
    for line in report.lines() {
        assert!(
            !line
                .chars()
                .any(|c| c.is_control() || ('\u{202a}'..='\u{202e}').contains(&c)),
            "{line:?}"
        );
        for cell in line.split(',') {
            assert!(!cell.starts_with(['=', '@', '+']), "{line}");
        }
    }
    assert!(report.contains("'=HYPERLINK"), "{report}");
    assert!(report.contains("\\u{202e}"), "{report}");
    no_temporaries(&dir);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_scenario_name_never_leaves_the_output_folder() {
    let dir = temp_dir("scenario");
    // an example with scenarios (the one named before had none, and the test returned early
    // without running anything); its first scenario renamed everywhere it is named
    let src =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("worked_examples/baranowski-rc-ladder.toml");
    let text = std::fs::read_to_string(&src).unwrap();
    assert!(
        text.contains("[[scenarios]]\nname = \"fig-3-4\""),
        "the example's first scenario"
    );
    let hostile = text.replace("\"fig-3-4\"", "\"../../escape-fig-3-4\"");
    let example = dir.join("hostile.toml");
    std::fs::write(&example, hostile).unwrap();
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    let svg = out.join("fig.svg");
    let (code, stdout, err) = owb(&[
        "simulate",
        example.to_str().unwrap(),
        "--svg",
        svg.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        stdout.contains("../../escape-fig-3-4 — Fig. 3 and 4"),
        "{stdout}"
    );
    // the figure is written inside the folder asked for, under a name with the path made safe
    let written: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(written.len(), 5, "{written:?}");
    assert!(
        written
            .iter()
            .any(|n| n.contains("escape-fig-3-4") && !n.contains('/')),
        "{written:?}"
    );
    for folder in [dir.as_path(), dir.parent().unwrap()] {
        for e in std::fs::read_dir(folder).unwrap().flatten() {
            assert!(
                !e.file_name().to_string_lossy().starts_with("escape"),
                "{:?}",
                e.path()
            );
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

// ---- messages ---------------------------------------------------------------------------

#[test]
fn argument_errors_are_json_under_json() {
    for cmd in ["gain", "observe", "grade", "dlqe", "zoh"] {
        let (code, out, _) = owb(&[cmd, "--bogus", "--json"]);
        assert_eq!(code, 2);
        let v: serde_json::Value =
            serde_json::from_str(&out).unwrap_or_else(|e| panic!("{cmd}: {e}: {out:?}"));
        assert!(v["error"].as_str().unwrap().contains("--bogus"), "{out}");
    }
    let (code, out, err) = owb(&["exercise", "new", "--seed", "3", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(v["key"].as_array().is_some_and(|k| !k.is_empty()), "{out}");
}

#[test]
fn messages_name_what_is_wrong() {
    let (_, _, err) = owb(&[
        "gain", "--a", "[1 2; 3]", "--c", "[1 0]", "--poles", "-1, -2",
    ]);
    assert!(err.contains("row 2 has 1 entries"), "{err}");
    // the nested form too (it was "too large (limit 200)")
    let (_, _, err) = owb(&["observe", "--a", "[[1,2],[3]]", "--c", "[1 0]"]);
    assert!(err.contains("row 2 has 1 entries"), "{err}");
    assert!(!err.contains("too large"), "{err}");
    let (_, _, err) = owb(&[
        "discrete",
        "--a",
        "[0 1; 0 0]",
        "--c",
        "[1 0]",
        "--poly",
        "zeta^2",
    ]);
    // zeta is a parameter now (the polynomial is refused for its degree), never rewritten
    assert!(err.contains("zeta") && !err.contains("seta"), "{err}");
    let (_, _, err) = owb(&[
        "gain",
        "--a",
        "[-1 0; 0 -2]",
        "--c",
        "[1 0; 0 1]",
        "--poles",
        "-3, -4",
        "--output",
        "1",
    ]);
    assert!(err.contains("output 1 alone does not observe"), "{err}");
    let (_, out, _) = owb(&[
        "reduced",
        "--a",
        "[0 1; -2 -3]",
        "--c",
        "[1 0]",
        "--poles",
        "-5",
        "--convention",
        "a+lc",
    ]);
    assert!(out.contains("w = z₂ + L y"), "{out}");
    let (_, _, err) = owb(&["gain", "--a", "[1\u{202e}2]", "--c", "[1]", "--poles", "-1"]);
    assert!(!err.contains('\u{202e}'), "{err}");
}

#[test]
fn built_in_exercises_need_no_checkout() {
    let dir = temp_dir("builtin");
    let f = dir.join("a.toml");
    std::fs::write(&f, "[answers]\nL = \"[-6; -12]\"\n").unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_owb"))
        .args(["check", "stoustrup-pole-assignment", f.to_str().unwrap()])
        .current_dir(&dir)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("✔ L"),
        "{text}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    std::fs::remove_dir_all(&dir).ok();
}

// ---- the sweep --------------------------------------------------------------------------

/// Hostile values for a matrix, a list or a number flag.
fn hostile() -> Vec<String> {
    let chain = vec!["1"; 7000].join("+");
    vec![
        "[1e1000]".into(),
        "[1e-1000]".into(),
        "[9^999]".into(),
        "0".into(),
        "[]".into(),
        "[[]]".into(),
        "[1 2; 3]".into(),
        format!("[{chain}]"),
        "[1\u{7}2]".into(),
        "\u{202e}[1]".into(),
        "".into(),
        "-1e300".into(),
        "nan".into(),
    ]
}

/// What a command's JSON says of its own result: an exit 0 must carry a result that passed its
/// check (the exact identity, the residual, the stability it claims).
fn passes_its_own_check(command: &str, v: &serde_json::Value) -> Result<(), String> {
    let truth = |key: &str| match v.pointer(key) {
        Some(serde_json::Value::Bool(true)) => Ok(()),
        other => Err(format!("{key} is {other:?}")),
    };
    let below = |key: &str, bound: f64| match v.pointer(key).and_then(serde_json::Value::as_f64) {
        Some(x) if x <= bound => Ok(()),
        other => Err(format!("{key} is {other:?}, not at most {bound}")),
    };
    match command {
        "gain" | "feedback" => truth("/places_exactly"),
        "observe" => truth("/pbh_confirmed"),
        "control" => truth("/separation_holds"),
        "detectable" => truth("/polynomial_checks"),
        "dlqe" => below("/residual", 1e-8).and(below("/spectral_radius", 1.0 - 1e-12)),
        "kalman" => below("/kalman/residual", 1e-6),
        "zoh" => match v.pointer("/exact") {
            Some(serde_json::Value::Bool(true)) => Ok(()),
            _ => below("/error_estimate", 1e-6),
        },
        "discrete" | "reduced" => v
            .pointer("/error_polynomial")
            .and_then(serde_json::Value::as_str)
            .filter(|p| !p.is_empty())
            .map(|_| ())
            .ok_or_else(|| "no error polynomial".to_string()),
        // their reports hold no single verdict to read here; their own tests check them
        "canonical" | "perfect" | "optimal" | "exercise new" => Ok(()),
        // a verification or simulation that exits 0 found every claim and figure holding
        "verify stoustrup-pole-assignment" | "simulate baranowski-rc-ladder" => Ok(()),
        other => Err(format!("no check known for {other}")),
    }
}

#[test]
fn every_subcommand_survives_hostile_flags() {
    // a valid base per subcommand; each flag in turn gets each hostile value
    let base: Vec<(&str, Vec<(&str, &str)>)> = vec![
        ("observe", vec![("--a", "[0 1; -2 -3]"), ("--c", "[1 0]")]),
        ("canonical", vec![("--a", "[0 1; -2 -3]"), ("--c", "[1 0]")]),
        (
            "gain",
            vec![
                ("--a", "[0 1; -2 -3]"),
                ("--c", "[1 0]"),
                ("--poles", "-4, -5"),
            ],
        ),
        (
            "feedback",
            vec![
                ("--a", "[0 1; -2 -3]"),
                ("--b", "[0; 1]"),
                ("--poles", "-4, -5"),
            ],
        ),
        (
            "discrete",
            vec![
                ("--a", "[0 1; -2 -3]"),
                ("--c", "[1 0]"),
                ("--poles", "0, 1/2"),
            ],
        ),
        (
            "zoh",
            vec![
                ("--a", "[0 1; -2 -3]"),
                ("--b", "[0; 1]"),
                ("--period", "1/10"),
            ],
        ),
        (
            "dlqe",
            vec![
                ("--a", "[1/2 1; 0 1/3]"),
                ("--c", "[1 0]"),
                ("--qn", "[1 0; 0 1]"),
                ("--rn", "[1]"),
            ],
        ),
        (
            "reduced",
            vec![("--a", "[0 1; -2 -3]"), ("--c", "[1 0]"), ("--poles", "-5")],
        ),
        (
            "detectable",
            vec![("--a", "[-1 0; 1 -1]"), ("--c", "[1 0]"), ("--poles", "-3")],
        ),
        (
            "control",
            vec![
                ("--a", "[0 1; -2 -3]"),
                ("--b", "[0; 1]"),
                ("--c", "[1 0]"),
                ("--l", "[-5; -6]"),
                ("--f", "[-1 -1]"),
            ],
        ),
        (
            "control",
            vec![
                ("--a", "[0 1; -2 -3]"),
                ("--b", "[0; 1]"),
                ("--c", "[1 0]"),
                ("--observer-poly", "s^2 + 9s + 20"),
                ("--feedback-poly", "s^2 + 3s + 2"),
            ],
        ),
        (
            "kalman",
            vec![
                ("--a", "[0 1; -2 -3]"),
                ("--b", "[0; 1]"),
                ("--c", "[1 0]"),
                ("--input-noise", "[1]"),
                ("--output-noise", "[1]"),
            ],
        ),
        (
            "perfect",
            vec![("--a", "[0 1; -2 -3]"), ("--b", "[0; 1]"), ("--c", "[1 0]")],
        ),
        (
            "optimal",
            vec![
                ("--a", "[0 1 0; 0 0 1; 1 2 3]"),
                ("--c", "[1 0 0; 0 1 0]"),
                ("--poles", "-1, -2, -3"),
                ("--starts", "2"),
                ("--time-limit", "2"),
            ],
        ),
        (
            "exercise new",
            vec![
                ("--kind", "pole-placement"),
                ("--order", "3"),
                ("--seed", "7"),
            ],
        ),
        (
            "verify stoustrup-pole-assignment",
            vec![("--dir", "worked_examples")],
        ),
        (
            "simulate baranowski-rc-ladder",
            vec![
                ("--dir", "worked_examples"),
                ("--scenario", "x0-sensitivity"),
            ],
        ),
        (
            "gain",
            vec![
                ("--a", "[0 1; -2 -3]"),
                ("--c", "[1 0]"),
                ("--poles", "-4, -5"),
                ("--time-budget", "5"),
            ],
        ),
    ];
    let budget = Duration::from_secs(20);
    let mut failures = Vec::new();
    for (cmd, flags) in &base {
        for k in 0..flags.len() {
            for value in hostile() {
                let mut args: Vec<String> = cmd.split(' ').map(String::from).collect();
                for (j, (flag, v)) in flags.iter().enumerate() {
                    args.push(flag.to_string());
                    args.push(if j == k { value.clone() } else { v.to_string() });
                }
                args.push("--json".into());
                let refs: Vec<&str> = args.iter().map(String::as_str).collect();
                let (code, out, err, took) = owb_within(&refs, budget);
                let shown = format!("{:?}", args).chars().take(200).collect::<String>();
                if !matches!(code, 0..=2) {
                    failures.push(format!(
                        "{shown}: status {code}: {}",
                        err.chars().take(300).collect::<String>()
                    ));
                    continue;
                }
                if took > Duration::from_secs(10) {
                    failures.push(format!("{shown}: took {took:?}"));
                }
                if err.contains("panicked") {
                    failures.push(format!("{shown}: panic: {err}"));
                }
                match serde_json::from_str::<serde_json::Value>(&out) {
                    Err(_) => failures.push(format!(
                        "{shown}: stdout is not JSON: {}",
                        out.chars().take(200).collect::<String>()
                    )),
                    Ok(v) if code == 0 => {
                        if let Err(why) = passes_its_own_check(cmd, &v) {
                            failures.push(format!("{shown}: exit 0 but {why}"));
                        }
                    }
                    Ok(_) => {}
                }
                if out.chars().any(|c| c == '\u{7}' || c == '\u{202e}')
                    || err.chars().any(|c| c == '\u{7}' || c == '\u{202e}')
                {
                    failures.push(format!("{shown}: an invisible character echoed"));
                }
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{} failures:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// An answer whose part name holds a pasted invisible character (`L\u{200b}`) is not "no answer
/// given": the part says its name is unreadable, with the character's position.
#[test]
fn an_invisible_character_in_a_part_name_is_named_at_the_part() {
    let (status, out, err) = check_stoustrup(
        "name",
        "\"L\u{200b}\" = \"[-6; -12]\"\nO = \"[-3 2; 2 -1]\"\n",
        &["--json"],
    );
    assert_eq!(status, 1, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let l = v["parts"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["id"] == "L")
        .unwrap();
    assert_eq!(l["verdict"], "unreadable", "{l}");
    let feedback = l["feedback"].as_str().unwrap();
    assert!(
        feedback.contains("U+200B") && feedback.contains("retype the name L"),
        "{feedback}"
    );
    assert!(
        !out.contains('\u{200b}'),
        "the invisible character is not echoed"
    );
    let o = v["parts"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["id"] == "O")
        .unwrap();
    assert_eq!(
        o["verdict"], "correct",
        "the other parts are checked as usual"
    );
}

/// `verify` and `simulate` read the worked examples of the folder given (default
/// `worked_examples` in the working folder), never the checkout the binary was built from.
#[test]
fn verify_reads_no_folder_behind_the_users_back() {
    let elsewhere = std::env::temp_dir();
    for args in [
        vec!["verify"],
        vec!["simulate", "stoustrup-pole-assignment"],
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_owb"))
            .args(&args)
            .current_dir(&elsewhere)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains("no worked-example folder") && err.contains("--dir"),
            "{err}"
        );
    }
}

/// An answer too large to read as a matrix (a 1×10 000 row where a 2×1 gain is asked) still
/// hears its shape, not only "not the answer".
#[test]
fn a_huge_answer_is_told_its_shape() {
    let row = format!("[{}]", vec!["1"; 10_000].join(" "));
    let (status, out, err) = check_stoustrup("shape", &format!("L = \"{row}\"\n"), &[]);
    assert_eq!(status, 1, "{err}");
    assert!(
        out.contains("your answer is 1×10000, the answer is 2×1"),
        "{out}"
    );
}

/// `count` entries −9…9 (each followed by `suffix`, e.g. `/40`) from a fixed linear
/// congruential sequence seeded with `seed`: reproducible dense plants for the large cases.
fn lcg_entries(seed: u64, count: usize, suffix: &str) -> Vec<String> {
    let mut x = seed;
    (0..count)
        .map(|_| {
            x = x.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            format!("{}{suffix}", ((x >> 33) % 19) as i64 - 9)
        })
        .collect()
}

/// `entries` as a matrix of `cols` columns in the workbench's syntax.
fn matrix_text(entries: &[String], cols: usize) -> String {
    let rows: Vec<String> = entries.chunks(cols).map(|r| r.join(" ")).collect();
    format!("[{}]", rows.join("; "))
}

/// Every computing command runs under a time budget: an order-80 canonical form (a minute of
/// exact work on the 2-core machine) stops at the budget with an error naming it — as JSON
/// under `--json` — instead of running for minutes; the budget is checked as a number of
/// seconds; 0 lifts it.
#[test]
fn a_computation_past_its_time_budget_stops_with_the_limit_named() {
    let n = 80;
    let entries = lcg_entries(7, n * n + n, "");
    let a = matrix_text(&entries[..n * n], n);
    let c = matrix_text(&entries[n * n..], n);
    let (code, out, err, took) = owb_within(
        &[
            "canonical",
            "--a",
            &a,
            "--c",
            &c,
            "--time-budget",
            "1",
            "--json",
        ],
        Duration::from_secs(30),
    );
    assert_eq!(code, 2, "{err}");
    assert!(took < Duration::from_secs(5), "took {took:?}");
    let v: serde_json::Value = serde_json::from_str(&out).expect("a JSON error");
    let message = v["error"].as_str().unwrap_or_default();
    assert!(
        message.contains("--time-budget") && message.contains("1 s"),
        "{message}"
    );
    for bad in ["-1", "nan", "1e300", "ten"] {
        let (code, _, err, _) = owb_within(
            &[
                "gain",
                "--a",
                "[0 1; -2 -3]",
                "--c",
                "[1 0]",
                "--poles",
                "-4, -5",
                "--time-budget",
                bad,
            ],
            Duration::from_secs(10),
        );
        assert_eq!(code, 2, "--time-budget {bad}: {err}");
        assert!(err.contains("--time-budget"), "--time-budget {bad}: {err}");
    }
    let (code, out, _, _) = owb_within(
        &[
            "gain",
            "--a",
            "[0 1; -2 -3]",
            "--c",
            "[1 0]",
            "--poles",
            "-4, -5",
            "--time-budget",
            "0",
        ],
        Duration::from_secs(10),
    );
    assert_eq!(code, 0);
    assert!(out.contains("K = [6; 0]"), "{out}");
}

/// The budget's alarm and a command finishing race at budgets of a few microseconds: each run
/// ends one way or the other, never both and never a crash — the report and status 0, or the
/// budget's error alone (standard error in text, one JSON object under `--json`) and status 2.
/// A text run past its budget prints nothing on standard output.
#[test]
fn a_budget_running_out_as_the_command_finishes_gives_one_ending() {
    let gain = [
        "gain",
        "--a",
        "[0 1 0; 0 0 1; -6 -11 -6]",
        "--c",
        "[1 0 0]",
        "--poles",
        "-2, -3, -4",
    ];
    let (mut finished, mut stopped) = (0, 0);
    for (i, budget) in ["0.000001", "0.00002", "0.0001", "0.0003", "0.001"]
        .iter()
        .cycle()
        .take(40)
        .enumerate()
    {
        let json = i % 2 == 1;
        let mut args = gain.to_vec();
        args.extend(["--time-budget", budget]);
        if json {
            args.push("--json");
        }
        let (code, out, err, _) = owb_within(&args, Duration::from_secs(10));
        match code {
            0 => {
                finished += 1;
                assert!(err.is_empty(), "budget {budget}: {err}");
                if json {
                    let v: serde_json::Value = serde_json::from_str(&out).expect("a report");
                    assert!(v.get("error").is_none(), "{out}");
                } else {
                    assert!(out.contains("K = ["), "budget {budget}: {out}");
                }
            }
            2 => {
                stopped += 1;
                let expected = format!("error: stopped after {budget} s, the time budget");
                assert!(err.starts_with(&expected), "budget {budget}: {err}");
                assert_eq!(err.lines().count(), 1, "{err}");
                if json {
                    let v: serde_json::Value = serde_json::from_str(&out).expect("one object");
                    assert_eq!(v["exit_status"], 2, "{out}");
                    assert!(v["error"].as_str().unwrap_or("").contains("time budget"));
                } else {
                    assert!(out.is_empty(), "budget {budget}: {out}");
                }
            }
            other => panic!("budget {budget}: status {other}: {out} {err}"),
        }
    }
    // a microsecond is always too short (a millisecond is usually enough: the runs that
    // finish check the report's side of the race)
    assert!(stopped > 0, "no run was stopped ({finished} finished)");
}

/// Above ten states the exact check of dlqe costs more than the float solution, so it runs only
/// when asked: on a plant whose Riccati solution is P = I exactly (A = S/2 with S the cyclic
/// shift, so A Aᵀ = I/4; C = R_n = I and Q_n = I − A Aᵀ/2 = 7/8 I, whence
/// P = A P (P + I)⁻¹ Aᵀ + Q_n = I/8 + 7/8 I), the default says why it was not tried and
/// `--exact-check` finds P = I and L = A/2.
#[test]
fn dlqe_checks_exactly_above_ten_states_only_when_asked() {
    let n = 12;
    let square = |f: &dyn Fn(usize, usize) -> &'static str| {
        format!(
            "[{}]",
            (0..n)
                .map(|i| (0..n).map(|j| f(i, j)).collect::<Vec<_>>().join(" "))
                .collect::<Vec<_>>()
                .join("; ")
        )
    };
    let a = square(&|i, j| if j == (i + 1) % n { "1/2" } else { "0" });
    let eye = square(&|i, j| if i == j { "1" } else { "0" });
    let qn = square(&|i, j| if i == j { "7/8" } else { "0" });
    let run = |extra: &[&str]| {
        let mut args = vec!["dlqe", "--a", &a, "--c", &eye, "--qn", &qn, "--rn", &eye];
        args.extend(extra);
        let (code, out, err, _) = owb_within(&args, Duration::from_secs(30));
        assert_eq!(code, 0, "{err}");
        out
    };
    let v: serde_json::Value = serde_json::from_str(&run(&["--json"])).unwrap();
    assert_eq!(v["exact_check"], "order_over_default");
    assert_eq!(
        (v["exact"].clone(), v["exact_read_back_tried"].clone()),
        (false.into(), false.into())
    );
    assert!(v.get("exact_p").is_none());
    let text = run(&[]);
    assert!(
        text.contains("12 states is above 10") && text.contains("--exact-check runs it"),
        "{text}"
    );
    let v: serde_json::Value = serde_json::from_str(&run(&["--exact-check", "--json"])).unwrap();
    assert_eq!(v["exact_check"], "holds");
    assert_eq!(
        (v["exact"].clone(), v["exact_read_back_tried"].clone()),
        (true.into(), true.into())
    );
    for i in 0..n {
        for j in 0..n {
            let p = if i == j { "1" } else { "0" };
            let l = if j == (i + 1) % n { "1/4" } else { "0" };
            assert_eq!(v["exact_p"][i][j], p, "P[{i}][{j}]");
            assert_eq!(v["exact_gain"][i][j], l, "L[{i}][{j}]");
        }
    }
}

/// dlqe does float work first: the exact read-back of P is tried only within its work budget
/// (a common denominator of at most 256 bits), and a generic order-50 filter — whose exact
/// read-back alone took 5.8 s — is solved in a fraction of a second and says the read-back was
/// not tried, even under `--exact-check`; a P with small fractions is still read back and
/// verified exactly.
#[test]
fn dlqe_tries_the_exact_read_back_only_within_its_budget() {
    let n = 50;
    let a = matrix_text(&lcg_entries(3, n * n, "/40"), n);
    let c = format!("[1{}]", " 0".repeat(n - 1));
    let qn = format!(
        "[{}]",
        (0..n)
            .map(|i| (0..n)
                .map(|j| if i == j { "1" } else { "0" })
                .collect::<Vec<_>>()
                .join(" "))
            .collect::<Vec<_>>()
            .join("; ")
    );
    let (code, out, err, took) = owb_within(
        &[
            "dlqe",
            "--a",
            &a,
            "--c",
            &c,
            "--qn",
            &qn,
            "--rn",
            "[1]",
            "--exact-check",
            "--json",
        ],
        Duration::from_secs(30),
    );
    assert_eq!(code, 0, "{err}");
    assert!(took < Duration::from_secs(3), "took {took:?}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["exact_read_back_tried"], false);
    assert_eq!(v["exact_check"], "denominator_over_budget");
    assert_eq!(v["exact"], false);
    assert!(v["residual"].as_f64().is_some_and(|r| r <= 1e-8));
    let (code, out, _, _) = owb_within(
        &[
            "dlqe", "--a", "[2]", "--c", "[1]", "--qn", "[0]", "--rn", "[1]", "--json",
        ],
        Duration::from_secs(10),
    );
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(
        (v["exact_read_back_tried"].clone(), v["exact"].clone()),
        (true.into(), true.into())
    );
}
