//! Exact-core benchmarks: characteristic polynomial, solve, inverse and the full exact observer
//! gain `K = P(A)·O⁻¹·eₙ` on the RC ladder (tridiagonal −2, 1) and on dense random integer
//! matrices with entries in [−9, 9], for n = 5 … 80.
//!
//! Run with `cargo bench`; `OWB_BENCH_MAX_N` lowers the largest order (default 80).

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use observer_workbench::algebra::{Rational, Ring};
use observer_workbench::linalg::{characteristic_polynomial, inverse, solve, Matrix};
use observer_workbench::poly::Poly;
use std::time::Duration;

/// A reproducible dense integer matrix with entries in [−9, 9] (xorshift, fixed seed).
fn dense_random(n: usize, seed: u64) -> Matrix<Rational> {
    let mut state = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    Matrix::from_fn(n, n, |_, _| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        Rational::from_i64((state % 19) as i64 - 9)
    })
}

fn rc_ladder(n: usize) -> Matrix<Rational> {
    Matrix::from_fn(n, n, |i, j| match i.abs_diff(j) {
        0 => Rational::from_i64(-2),
        1 => Rational::from_i64(1),
        _ => Rational::from_i64(0),
    })
}

fn first_state_output(n: usize) -> Matrix<Rational> {
    Matrix::from_fn(1, n, |_, j| Rational::from_i64(i64::from(j == 0)))
}

/// `K = P(A) O⁻¹ eₙ` with all observer poles at −4 (single output).
fn exact_gain(a: &Matrix<Rational>, c: &Matrix<Rational>) -> Matrix<Rational> {
    let n = a.rows();
    let desired = Poly::from_roots(&vec![Rational::from_i64(-4); n], "s");
    observer_workbench::observer::ackermann_gain(a, c, &desired).expect("observable")
}

fn orders() -> Vec<usize> {
    let max: usize = std::env::var("OWB_BENCH_MAX_N")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(80);
    [5, 10, 20, 40, 60, 80]
        .into_iter()
        .filter(|&n| n <= max)
        .collect()
}

fn bench(c: &mut Criterion) {
    for (family, make) in [
        ("rc_ladder", rc_ladder as fn(usize) -> Matrix<Rational>),
        ("dense_random", |n| dense_random(n, 7)),
    ] {
        let mut g = c.benchmark_group(family);
        g.sample_size(10).warm_up_time(Duration::from_millis(200));
        for n in orders() {
            let a = make(n);
            let cm = first_state_output(n);
            let b = Matrix::unit(n, n - 1);
            g.bench_with_input(BenchmarkId::new("charpoly", n), &a, |bch, a| {
                bch.iter(|| characteristic_polynomial(a, "s").unwrap())
            });
            g.bench_with_input(BenchmarkId::new("solve", n), &a, |bch, a| {
                bch.iter(|| solve(a, &b))
            });
            g.bench_with_input(BenchmarkId::new("inverse", n), &a, |bch, a| {
                bch.iter(|| inverse(a))
            });
            g.bench_with_input(BenchmarkId::new("gain", n), &a, |bch, a| {
                bch.iter(|| exact_gain(a, &cm))
            });
        }
        g.finish();
    }
}

/// The user path: what `owb gain --json` calls — the exact design with its full derivation
/// (O_n, det(sI − A), q_n, K, A − KC, the exact check) rendered to JSON — on dense random
/// integer matrices, and `owb gain --float` on the RC ladder with poles −1 … −n.
fn bench_user_path(c: &mut Criterion) {
    use observer_workbench::algebra::{Quadratic, Rational};
    use observer_workbench::observer::float_check::float_check;
    use observer_workbench::observer::{
        design_with, Convention, DesiredPolynomial, Detail, GainMethod,
    };
    let max: usize = std::env::var("OWB_BENCH_MAX_N")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(80);
    let exact =
        |a: &Matrix<Rational>, cm: &Matrix<Rational>, desired: &DesiredPolynomial, method| {
            design_with(a, cm, desired, method, Convention::AMinusKC, Detail::Full).unwrap()
        };
    let mut g = c.benchmark_group("user_path");
    g.sample_size(10).warm_up_time(Duration::from_millis(200));
    for n in [10, 20, 30, 60].into_iter().filter(|&n| n <= max) {
        let a = dense_random(n, 7);
        let cm = first_state_output(n);
        let desired = DesiredPolynomial::repeated(&Rational::from_i64(1), n).unwrap();
        for method in [GainMethod::Ackermann, GainMethod::BassGura] {
            let id = BenchmarkId::new(format!("gain {method} + derivation json"), n);
            g.bench_with_input(id, &a, |bch, a| {
                bch.iter(|| {
                    let d = exact(a, &cm, &desired, method);
                    serde_json::to_string(&d.derivation.steps).unwrap().len()
                })
            });
        }
    }
    for n in [20, 60].into_iter().filter(|&n| n <= max) {
        let a = rc_ladder(n);
        let cm = first_state_output(n);
        let poles: Vec<Quadratic> = (1..=n as i64)
            .map(|k| Quadratic::rational(Rational::from_i64(-k)))
            .collect();
        let desired = DesiredPolynomial::from_poles(&poles).unwrap();
        let id = BenchmarkId::new("rc ladder gain --float", n);
        g.bench_with_input(id, &a, |bch, a| {
            bch.iter(|| {
                let k = exact(a, &cm, &desired, GainMethod::Ackermann).gain.matrix;
                let p = desired.rational();
                float_check(a, &cm, &desired.float, p.as_ref(), Some(&k), 1e-6)
            })
        });
    }
    g.finish();
}

/// Every command as a front end runs it — a JSON request through `api::run`, its report
/// rendered — on a dense random integer plant of order n (the first state measured, the last
/// driven): the work of `owb <command>` without the process start (about 1 ms, see the README).
fn bench_commands(c: &mut Criterion) {
    use observer_workbench::api::{run, Command};
    let max: usize = std::env::var("OWB_BENCH_MAX_N")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(80);
    let mut g = c.benchmark_group("commands");
    g.sample_size(10).warm_up_time(Duration::from_millis(200));
    for n in [5, 10, 20].into_iter().filter(|&n| n <= max) {
        let a = dense_random(n, 11).to_input();
        let cm = first_state_output(n).to_input();
        let b = Matrix::from_fn(n, 1, |i, _| Rational::from_i64(i64::from(i + 1 == n))).to_input();
        let poles = (1..=n)
            .map(|k| format!("-{k}"))
            .collect::<Vec<_>>()
            .join(", ");
        let reduced_poles = (1..n)
            .map(|k| format!("-{k}"))
            .collect::<Vec<_>>()
            .join(", ");
        let discrete_poles = (1..=n)
            .map(|k| format!("1/{}", k + 1))
            .collect::<Vec<_>>()
            .join(", ");
        // the observer gain of the random plant (all poles at −4) for control; a plant scaled
        // by 1/(2n) (spectral radius below 1 for most seeds) for the float commands
        let l = exact_gain(&dense_random(n, 11), &first_state_output(n)).to_input();
        let feedback_poly = format!("(s + 2)^{n}");
        let scaled = dense_random(n, 11)
            .map(|x| x.clone() / Rational::from_i64(2 * n as i64))
            .to_input();
        let identity = Matrix::<Rational>::identity(n).to_input();
        let requests = [
            ("observe", serde_json::json!({"a": a, "c": cm})),
            ("canonical", serde_json::json!({"a": a, "c": cm})),
            (
                "gain",
                serde_json::json!({"a": a, "c": cm, "poles": poles, "summary": true}),
            ),
            (
                "gain",
                serde_json::json!({"a": a, "c": cm, "poles": poles, "float": true}),
            ),
            (
                "feedback",
                serde_json::json!({"a": a, "b": b, "poles": poles}),
            ),
            (
                "discrete",
                serde_json::json!({"a": a, "c": cm, "poles": discrete_poles}),
            ),
            (
                "reduced",
                serde_json::json!({"a": a, "c": cm, "poles": reduced_poles}),
            ),
            (
                "kalman",
                serde_json::json!({"a": a, "b": b, "c": cm, "input-noise": "1", "output-noise": "1/10"}),
            ),
            (
                "discrete",
                serde_json::json!({"a": a, "c": cm, "deadbeat": true}),
            ),
            (
                "detectable",
                serde_json::json!({"a": a, "c": cm, "poles": poles}),
            ),
            (
                "control",
                serde_json::json!({"a": a, "b": b, "c": cm, "l": l, "convention": "a-kc",
                                   "feedback-poly": feedback_poly}),
            ),
            ("perfect", serde_json::json!({"a": a, "b": b, "c": cm})),
            (
                "zoh",
                serde_json::json!({"a": scaled, "b": b, "period": "1/10"}),
            ),
            (
                "dlqe",
                serde_json::json!({"a": scaled, "c": cm, "qn": identity, "rn": "[1]"}),
            ),
        ];
        for (k, (name, fields)) in requests.into_iter().enumerate() {
            let mut request = fields;
            request["command"] = serde_json::json!(name);
            let command = Command::from_value(&request).expect("a valid request");
            // a request the command refuses (a random plant can be uncontrollable) is left out
            if run(command.clone()).is_err() {
                continue;
            }
            let id = BenchmarkId::new(format!("{name} #{k}"), n);
            g.bench_with_input(id, &command, |bch, command| {
                bch.iter(|| run(command.clone()).map(|r| r.text.len()).unwrap_or(0))
            });
        }
    }
    g.finish();
}

/// The commands that do not scale with an order: `optimal` (two outputs of a 3-state plant,
/// 8 seeded starts), `verify` (one worked example), `check` (an answer file), `exercise new`,
/// `simulate` (a worked example's scenarios, no figure written), `grade` (a class of 30
/// submissions, the report written to a temporary folder) — each as the command line reads it,
/// run by `api::run`.
fn bench_fixed_commands(c: &mut Criterion) {
    use observer_workbench::api::{run, Command};
    let root = env!("CARGO_MANIFEST_DIR");
    let dir = std::env::temp_dir().join(format!("owb-bench-{}", std::process::id()));
    let submissions = dir.join("submissions");
    std::fs::create_dir_all(&submissions).expect("a temporary folder");
    let answers = dir.join("answers.toml");
    std::fs::write(&answers, "[answers]\nL = \"[6; 12]\"\n").expect("written");
    for k in 0..30 {
        let answer = if k % 3 == 0 { "[-6; -12]" } else { "[6; 12]" };
        std::fs::write(
            submissions.join(format!("s{k}.toml")),
            format!("student = \"s{k}\"\n[answers]\nL = \"{answer}\"\n"),
        )
        .expect("written");
    }
    let (examples, answers_s, subs, csv) = (
        format!("{root}/worked_examples"),
        answers.display().to_string(),
        submissions.display().to_string(),
        dir.join("report.csv").display().to_string(),
    );
    let lines: [(&str, Vec<&str>); 6] = [
        (
            "optimal j1, n = 3, 8 starts",
            vec![
                "optimal",
                "--a",
                "[0 1 0; 0 0 1; 1 2 3]",
                "--c",
                "[1 0 0; 0 1 0]",
                "--poles",
                "-1+2i, -1-2i, -3",
                "--starts",
                "8",
            ],
        ),
        (
            "verify stoustrup-pole-assignment",
            vec!["verify", "stoustrup-pole-assignment", "--dir", &examples],
        ),
        (
            "check stoustrup-pole-assignment",
            vec!["check", "stoustrup-pole-assignment", &answers_s],
        ),
        (
            "exercise new, order 3",
            vec![
                "exercise",
                "new",
                "--kind",
                "pole-placement",
                "--order",
                "3",
                "--seed",
                "7",
                "--key",
            ],
        ),
        (
            "simulate baranowski-rc-ladder (every scenario, its claims checked)",
            vec!["simulate", "baranowski-rc-ladder", "--dir", &examples],
        ),
        (
            "grade, 30 submissions",
            vec!["grade", "stoustrup-pole-assignment", &subs, "--csv", &csv],
        ),
    ];
    let mut g = c.benchmark_group("commands-fixed");
    g.sample_size(10).warm_up_time(Duration::from_millis(200));
    for (name, words) in lines {
        let command = Command::from_words(&words).expect("a valid command line");
        if let Err(e) = run(command.clone()) {
            panic!("{name}: {}", e.error);
        }
        g.bench_function(name, |bch| {
            bch.iter(|| run(command.clone()).map(|r| r.text.len()).unwrap_or(0))
        });
    }
    g.finish();
    let _ = std::fs::remove_dir_all(dir);
}

/// A 10 s run at h = 0.01 (RK4) of Baranowski's 3-state ladder with a two-output observer and
/// uniform output noise: the cost of one figure.
fn bench_simulation(c: &mut Criterion) {
    use nalgebra::DMatrix;
    use observer_workbench::simulation::noise::NoiseSpec;
    use observer_workbench::simulation::{simulate, Integrator, Loop, Setup, Signal};
    let l = Loop {
        a: DMatrix::from_row_slice(3, 3, &[-2.0, 1.0, 0.0, 1.0, -2.0, 1.0, 0.0, 1.0, -2.0]),
        b: DMatrix::from_row_slice(3, 2, &[1.0, 0.0, 0.0, 0.0, 0.0, 1.0]),
        c: DMatrix::from_row_slice(2, 3, &[1.0, 0.0, 0.0, 0.0, 0.0, 1.0]),
        d: DMatrix::zeros(2, 2),
        gain: DMatrix::from_row_slice(3, 2, &[3.086, 0.6775, 1.7139, 2.5086, -1.1585, 2.914]),
        feedback: None,
    };
    let s = Setup {
        horizon: 10.0,
        step: 0.01,
        integrator: Integrator::Rk4,
        input: vec![
            Signal::Sine {
                amplitude: 1.0,
                frequency: 1.0,
                phase: 0.0,
            },
            Signal::Zero,
        ],
        output_noise: Some(NoiseSpec::Uniform {
            amplitude: 0.1,
            seed: 1,
        }),
        process_noise: None,
        x0: vec![5.0, 5.0, 5.0],
        xhat0: vec![0.0; 3],
    };
    c.bench_function(
        "simulate 3-state plant + observer, 10 s at h = 0.01 (RK4)",
        |b| b.iter(|| simulate(&l, &s).unwrap()),
    );
}

criterion_group!(
    benches,
    bench,
    bench_user_path,
    bench_commands,
    bench_fixed_commands,
    bench_simulation
);
criterion_main!(benches);
