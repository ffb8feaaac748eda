//! Issue 7: the simulator against analytic solutions, the observer's designed decay, seeded
//! noise reproducibility, and the documents' figures as reviewed summaries.

mod common;
use common::owb;
use nalgebra::DMatrix;
use observer_workbench::simulation::csv::to_csv;
use observer_workbench::simulation::integrate::{dopri5, AdaptiveStats};
use observer_workbench::simulation::noise::NoiseSpec;
use observer_workbench::simulation::{simulate, Integrator, Loop, Setup, Signal};

/// The simulator's RK4 on ẋ = [[0, 1], [−1, 0]] x from (1, 0), exactly (cos t, −sin t), run to
/// t = 2 with step h (zero observer gain, zero input).
fn rk4_error(h: f64) -> f64 {
    let l = Loop {
        a: DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -1.0, 0.0]),
        b: DMatrix::from_row_slice(2, 1, &[0.0, 1.0]),
        c: DMatrix::from_row_slice(1, 2, &[1.0, 0.0]),
        d: DMatrix::zeros(1, 1),
        gain: DMatrix::zeros(2, 1),
        feedback: None,
    };
    let s = Setup {
        horizon: 2.0,
        step: h,
        integrator: Integrator::Rk4,
        input: vec![Signal::Zero],
        output_noise: None,
        process_noise: None,
        x0: vec![1.0, 0.0],
        xhat0: vec![0.0, 0.0],
    };
    let trace = simulate(&l, &s).unwrap();
    let x = &trace.x[trace.t.len() - 1];
    ((x[0] - 2f64.cos()).powi(2) + (x[1] + 2f64.sin()).powi(2)).sqrt()
}

#[test]
fn rk4_error_falls_as_h_to_the_fourth() {
    let errors: Vec<f64> = [0.2, 0.1, 0.05, 0.025]
        .iter()
        .map(|&h| rk4_error(h))
        .collect();
    for w in errors.windows(2) {
        let order = (w[0] / w[1]).log2();
        assert!(
            (order - 4.0).abs() < 0.15,
            "observed order {order:.3} from {errors:?}"
        );
    }
}

#[test]
fn dormand_prince_meets_its_tolerance_on_a_fast_stable_system() {
    // ẋ = −600 (x − cos t): the 600 rad/s time scale of Furlan's observer
    let mut f = |t: f64, x: &[f64]| vec![-600.0 * (x[0] - t.cos())];
    let mut h = 1e-3;
    let mut stats = AdaptiveStats::default();
    let x = dopri5(&mut f, 0.0, &[1.0], 1.0, 1e-10, 1e-12, &mut h, &mut stats).unwrap();
    // exact: x = (600² cos t + 600 sin t)/(600² + 1) + c e^{−600 t}, c ≈ 1/(600²+1)
    let a = 600.0f64;
    let exact =
        (a * a * 1f64.cos() + a * 1f64.sin()) / (a * a + 1.0) + (1.0 / (a * a + 1.0)) * (-a).exp();
    assert!((x[0] - exact).abs() < 1e-8, "{} vs {exact}", x[0]);
}

fn stoustrup_loop() -> Loop {
    // A − LC with L = (6, 12) (Stoustrup's (−6, −12) in A + LC): poles −4, −5
    Loop {
        a: DMatrix::from_row_slice(2, 2, &[2.0, -3.0, 4.0, -5.0]),
        b: DMatrix::from_row_slice(2, 1, &[2.0, 3.0]),
        c: DMatrix::from_row_slice(1, 2, &[-3.0, 2.0]),
        d: DMatrix::zeros(1, 1),
        gain: DMatrix::from_row_slice(2, 1, &[6.0, 12.0]),
        feedback: None,
    }
}

fn setup(noise: Option<NoiseSpec>) -> Setup {
    Setup {
        horizon: 6.0,
        step: 0.001,
        integrator: Integrator::Rk4,
        input: vec![Signal::Sine {
            amplitude: 1.0,
            frequency: 2.0,
            phase: 0.0,
        }],
        output_noise: noise,
        process_noise: None,
        x0: vec![1.0, -1.0],
        xhat0: vec![0.0, 0.0],
    }
}

#[test]
fn observer_error_decays_at_the_designed_rate() {
    let trace = simulate(&stoustrup_loop(), &setup(None)).unwrap();
    let norm = |k: usize| {
        (0..2)
            .map(|i| (trace.xhat[k][i] - trace.x[k][i]).powi(2))
            .sum::<f64>()
            .sqrt()
    };
    // poles −4, −5: over one second late in the run the error shrinks by e^{−4}
    let ratio = norm(5000) / norm(4000);
    assert!(
        (ratio.ln() + 4.0).abs() < 0.02,
        "decay rate {}",
        -ratio.ln()
    );
}

#[test]
fn seeded_noise_gives_bit_identical_csv() {
    let noise = Some(NoiseSpec::Gaussian {
        sigma: 0.05,
        seed: 42,
    });
    let a = to_csv(&simulate(&stoustrup_loop(), &setup(noise.clone())).unwrap());
    let b = to_csv(&simulate(&stoustrup_loop(), &setup(noise)).unwrap());
    assert_eq!(a, b);
    let c = to_csv(
        &simulate(
            &stoustrup_loop(),
            &setup(Some(NoiseSpec::Gaussian {
                sigma: 0.05,
                seed: 43,
            })),
        )
        .unwrap(),
    );
    assert_ne!(a, c);
    assert!(a.starts_with("t,x1,x2,xhat1,xhat2,e1,e2,y1,u1\n"));
}

#[test]
fn bad_settings_are_refused() {
    let mut s = setup(None);
    s.step = 0.0;
    assert!(simulate(&stoustrup_loop(), &s).is_err());
    let mut s = setup(None);
    s.x0 = vec![1.0];
    let e = simulate(&stoustrup_loop(), &s).unwrap_err().to_string();
    assert!(e.contains("initial states"), "{e}");
    let mut s = setup(None);
    s.horizon = 1e9;
    assert!(simulate(&stoustrup_loop(), &s)
        .unwrap_err()
        .to_string()
        .contains("limit"));
}

/// The figures' summaries, rounded to 3 significant digits, as reviewed snapshots; every
/// figure statement must hold.
#[test]
fn document_figures_are_reproduced() {
    for example in [
        "diruscio-example-7-1",
        "baranowski-rc-ladder",
        "slawinski-perfect-observer",
        "stoustrup-observer-based-control",
    ] {
        let (code, out, err) = owb(&["simulate", example, "--json"]);
        assert_eq!(code, 0, "{example}: {out}{err}");
        let mut v: serde_json::Value = serde_json::from_str(&out).unwrap();
        round(&mut v);
        insta::assert_json_snapshot!(format!("figures-{example}"), v);
    }
}

fn round(v: &mut serde_json::Value) {
    match v {
        serde_json::Value::Number(n) => {
            if let Some(x) = n.as_f64() {
                if x != 0.0 && x.fract() != 0.0 {
                    let s = format!("{x:.3e}");
                    *v = serde_json::Value::String(s);
                }
            }
        }
        serde_json::Value::Array(a) => a.iter_mut().for_each(round),
        serde_json::Value::Object(o) => o.values_mut().for_each(round),
        _ => {}
    }
}

#[test]
fn simulate_writes_svg_and_csv() {
    let dir = std::env::temp_dir().join(format!("owb-sim-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let svg = dir.join("fig.svg");
    let csv = dir.join("fig.csv");
    let (code, _, err) = owb(&[
        "simulate",
        "diruscio-example-7-1",
        "--scenario",
        "fig-1-butterworth",
        "--svg",
        svg.to_str().unwrap(),
        "--csv",
        csv.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.starts_with("<svg") && text.contains("t (s)") && text.contains("x̂2 (observer)"));
    let csv = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(csv.lines().count(), 502, "header + 501 samples");
    let (code, _, err) = owb(&["simulate", "diruscio-example-7-1", "--scenario", "nope"]);
    assert_eq!(code, 2);
    assert!(err.contains("fig-1-butterworth"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn discrete_time_deadbeat_observer_is_exact_after_n_steps() {
    // x[k+1] = [1 1; 0 1] x[k], y = x1; K = (2, 1) makes A − KC nilpotent (both poles at 0)
    let l = Loop {
        a: DMatrix::from_row_slice(2, 2, &[1.0, 1.0, 0.0, 1.0]),
        b: DMatrix::from_row_slice(2, 1, &[0.0, 1.0]),
        c: DMatrix::from_row_slice(1, 2, &[1.0, 0.0]),
        d: DMatrix::zeros(1, 1),
        gain: DMatrix::from_row_slice(2, 1, &[2.0, 1.0]),
        feedback: None,
    };
    let s = Setup {
        horizon: 5.0,
        step: 1.0,
        integrator: Integrator::Discrete,
        input: vec![Signal::Step {
            amplitude: 1.0,
            at: 0.0,
        }],
        output_noise: None,
        process_noise: None,
        x0: vec![3.0, -1.0],
        xhat0: vec![0.0, 0.0],
    };
    let trace = simulate(&l, &s).unwrap();
    assert_ne!(trace.x[1], trace.xhat[1]);
    for k in 2..trace.t.len() {
        assert_eq!(trace.x[k], trace.xhat[k], "step {k}");
    }
}

#[test]
fn csv_input_signals_interpolate_and_report_bad_lines() {
    let s = Signal::from_csv("t,u\n0,0\n1,2\n3,2\n").unwrap();
    assert_eq!(s.value(0.5), 1.0);
    assert_eq!(s.value(10.0), 2.0);
    let e = Signal::from_csv("t,u\n0,0\n1,x\n").unwrap_err();
    assert!(e.contains("line 3"), "{e}");
}
