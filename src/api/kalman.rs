//! `owb kalman`: the steady-state Kalman filter of a plant with noisy input and outputs, and
//! the noise let through by observers with chosen poles (Furlan et al.'s comparison).

use super::{Outcome, Report};
use crate::algebra::{Rational, Zero};
use crate::linalg::definiteness::{definiteness, Definiteness};
use crate::linalg::float::{eigenvalues, to_nalgebra};
use crate::linalg::Matrix;
use crate::observer::kalman::{
    error_covariance, kalman_filter, kalman_filter_ignoring_correlation, natural_frequency,
    NoiseIntensities, Plant,
};
use crate::observer::partial::gain_for_observer_matrix;
use crate::observer::robust::robust_observer_gain;
use crate::observer::weighted::weighted_design;
use crate::poly::Poly;
use crate::syntax::parse_list;
use crate::system::StateSpace;
use anyhow::{anyhow, bail, Result};
use nalgebra::{Complex, DMatrix};
use serde_json::json;

/// Arguments of `owb kalman`.
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "commands", derive(clap::Args))]
pub struct Args {
    /// The plant's A and C (`a`, `c`).
    #[serde(flatten)]
    #[cfg_attr(feature = "commands", command(flatten))]
    pub system: super::args::SystemPair,
    /// The plant's B and D (`b`, `d`).
    #[serde(flatten)]
    #[cfg_attr(feature = "commands", command(flatten))]
    pub inputs: super::args::InputMatrices,
    /// White-noise intensity C_U of the measured input (m×m), e.g. "[4.47e-8]".
    #[cfg_attr(feature = "commands", arg(allow_hyphen_values = true, long))]
    pub input_noise: String,
    /// White-noise intensity C_Y of the outputs (p×p), e.g. "[5.08e-16 0; 0 4.47e-6]".
    #[cfg_attr(feature = "commands", arg(allow_hyphen_values = true, long))]
    pub output_noise: String,
    /// Chosen observer poles (rational) to compare with the Kalman filter, e.g. "-548, -670".
    #[cfg_attr(feature = "commands", arg(allow_hyphen_values = true, long))]
    #[serde(default)]
    pub poles: Option<String>,
    /// With --poles: the output that measures a state's derivative (1-based), for the
    /// weighted-derivative observer (l = w·e_state in its column).
    #[cfg_attr(feature = "commands", arg(allow_hyphen_values = true, long))]
    #[serde(default)]
    pub derivative_output: Option<usize>,
    /// … and that state (1-based).
    #[cfg_attr(feature = "commands", arg(allow_hyphen_values = true, long))]
    #[serde(default)]
    pub derivative_state: Option<usize>,
    /// Grid points of the weight search in [0, 1].
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, default_value_t = super::args::defaults::kalman_grid())
    )]
    #[serde(default = "super::args::defaults::kalman_grid")]
    pub grid: usize,
    /// Machine-readable output.
    #[cfg_attr(feature = "commands", arg(long))]
    #[serde(default)]
    pub json: bool,
}

struct Row {
    method: String,
    gain: DMatrix<f64>,
    note: String,
}

fn rows(m: &DMatrix<f64>) -> Vec<Vec<f64>> {
    super::args::float_rows(m)
}

fn show(m: &DMatrix<f64>) -> String {
    super::args::float_matrix_text(m, |x| format!("{x:.6e}"))
}

fn pole_text(z: &Complex<f64>) -> String {
    if z.im.abs() > 1e-9 * z.re.abs().max(1.0) {
        format!(
            "{:.3} {} {:.3}i",
            z.re,
            if z.im < 0.0 { "−" } else { "+" },
            z.im.abs()
        )
    } else {
        format!("{:.3}", z.re)
    }
}

/// A noise intensity must be a symmetric positive semidefinite matrix (a negative intensity
/// gave negative covariances).
fn require_covariance(flag: &str, m: &Matrix<Rational>) -> Result<()> {
    match definiteness(m)? {
        Definiteness::PositiveSemidefinite => Ok(()),
        Definiteness::NotSymmetric => bail!(
            "in {flag}: a noise intensity must be a symmetric matrix, this one is {}×{}{}",
            m.rows(),
            m.cols(),
            if m.is_square() { " and not symmetric" } else { "" }
        ),
        Definiteness::Indefinite(p) => bail!(
            "in {flag}: a noise intensity must be positive semidefinite; det(λI − M) = {p} has a negative root"
        ),
    }
}

/// The exact plant and noise intensities, as read.
struct Exact<'a> {
    plant: &'a StateSpace<Rational>,
    cu: &'a Matrix<Rational>,
    cy: &'a Matrix<Rational>,
}

/// The observers with the chosen poles compared with the Kalman filter: robust (KNV), diagonal
/// observer matrices when C is square, and the weighted-derivative observer.
fn pole_rows(
    args: &Args,
    ptext: &str,
    exact: &Exact<'_>,
    plant: &Plant,
    table: &mut Vec<Row>,
) -> Result<()> {
    let Exact {
        plant: exact_plant,
        cu,
        cy,
    } = *exact;
    let (a, c) = (exact_plant.a(), exact_plant.c());
    let poles =
        parse_list::<Rational>(ptext).map_err(|e| anyhow!("in --poles: {}", e.show_in(ptext)))?;
    if poles.len() != a.rows() {
        bail!("in --poles: {} poles for order {}", poles.len(), a.rows());
    }
    let float_poles: Vec<(f64, f64)> = poles
        .iter()
        .map(|p| (crate::algebra::rational_to_f64(p), 0.0))
        .collect();
    match robust_observer_gain(&plant.a, &plant.c, &float_poles) {
        Ok(r) => table.push(Row {
            method: "robust".into(),
            gain: DMatrix::from_fn(r.gain.len(), c.rows(), |i, j| r.gain[i][j]),
            note: format!("KNV, eigenvector condition {:.3}", r.eigenvector_condition),
        }),
        Err(e) => eprintln!("robust placement not available: {e}"),
    }
    if c.rows() == a.rows() {
        let n = a.rows();
        for (label, order) in [
            ("diagonal", poles.clone()),
            (
                "diagonal-reversed",
                poles.iter().rev().cloned().collect::<Vec<_>>(),
            ),
        ] {
            let m = Matrix::from_fn(n, n, |i, j| {
                if i == j {
                    order[i].clone()
                } else {
                    Rational::zero()
                }
            });
            if let Ok(l) = gain_for_observer_matrix(a, c, &m) {
                table.push(Row {
                    method: label.into(),
                    gain: to_nalgebra(&l),
                    note: format!(
                        "A − LC = diag({}), exact",
                        order
                            .iter()
                            .map(ToString::to_string)
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                });
            }
        }
    }
    if let (Some(o), Some(s)) = (args.derivative_output, args.derivative_state) {
        if o == 0 || s == 0 {
            bail!("in --derivative-output/--derivative-state: indices are 1-based");
        }
        let desired = Poly::from_roots(&poles, "s");
        let w = weighted_design(exact_plant, &desired, (cu, cy), (o - 1, s - 1), args.grid)?;
        table.push(Row {
            method: "weighted".into(),
            gain: DMatrix::from_fn(w.gain.len(), c.rows(), |i, j| w.gain[i][j]),
            note: format!(
                "w = {} ≈ {:.6} (grid of {} + golden section); trace Σ at w = 0: {:.4e}, at w = 1: {:.4e}",
                w.weight, w.weight_f64, w.grid_points, w.variance_at_ends.0, w.variance_at_ends.1
            ),
        });
    }
    Ok(())
}

/// One line per compared observer: poles, natural frequency and error covariance, in `text`;
/// the same as JSON rows.
fn tabulate(
    table: &[Row],
    plant: &Plant,
    noise: &NoiseIntensities,
    text: &mut String,
) -> Result<Vec<serde_json::Value>> {
    let mut json_rows = Vec::new();
    text.push_str("method               poles                          ω_n (rad/s)   diag Σ                        trace Σ       √trace Σ\n");
    for row in table {
        let f = &plant.a - &row.gain * &plant.c;
        let ev = eigenvalues(&f);
        let wn = natural_frequency(&ev);
        let (sigma, residual) = error_covariance(plant, noise, &row.gain)?;
        let diag: Vec<String> = (0..sigma.nrows())
            .map(|i| format!("{:.4e}", sigma[(i, i)]))
            .collect();
        text.push_str(&format!(
            "{:<20} {:<30} {:>11.3}   {:<29} {:<13.4e} {:.4e}\n    L = {}  ({}; Lyapunov residual {:.1e})\n",
            row.method,
            ev.iter().map(pole_text).collect::<Vec<_>>().join(", "),
            wn,
            diag.join(", "),
            sigma.trace(),
            sigma.trace().sqrt(),
            show(&row.gain),
            row.note,
            residual
        ));
        json_rows.push(json!({
            "method": row.method,
            "gain": rows(&row.gain),
            "poles": ev.iter().map(|z| (z.re, z.im)).collect::<Vec<_>>(),
            "natural_frequency": wn,
            "covariance": rows(&sigma),
            "trace": sigma.trace(),
            "rms": sigma.trace().sqrt(),
            "note": row.note,
        }));
    }
    text.push_str("ω_n = (Π|λ_i|)^(1/n); Σ: steady-state estimation-error covariance with C_U, C_Y read as white-noise intensities.\n");
    Ok(json_rows)
}

/// `owb kalman`: the Kalman filter against chosen poles.
///
/// # Errors
///
/// What the request gets wrong (named by its flag) or what the computation refuses.
pub fn run(args: Args, rep: &mut Report) -> Result<Outcome> {
    let (a, c) = args.system.parse()?;
    let (b, d) = args.inputs.parse(&args.system)?;
    super::args::check_plant(&a, Some(&b), &c, d.as_ref())?;
    let d = d.unwrap_or_else(|| Matrix::zeros(c.rows(), b.cols()));
    let values = args.system.values()?;
    let cu = super::args::matrix_at("--input-noise", &args.input_noise, &values)?;
    let cy = super::args::matrix_at("--output-noise", &args.output_noise, &values)?;
    for (flag, m) in [("--a", &a), ("--b", &b), ("--c", &c), ("--d", &d)] {
        // (the noise intensities have their own range check below, which says more)
        super::args::float_range(flag, m)?;
    }
    let (m, p) = (b.cols(), c.rows());
    super::args::expect_shape("--input-noise", &cu, m, m, "inputs × inputs")?;
    super::args::expect_shape("--output-noise", &cy, p, p, "outputs × outputs")?;
    for (flag, m) in [("--input-noise", &cu), ("--output-noise", &cy)] {
        require_covariance(flag, m)?;
        // exact values that f64 cannot hold would be read as zero noise (or denormal noise)
        if let Some(x) = m.entries().iter().find(|x| {
            let f = crate::algebra::ToF64::to_f64(*x);
            !x.is_zero() && (f.abs() < f64::MIN_POSITIVE || !f.is_finite())
        }) {
            let decimal_exponent =
                (x.numer().bits() as f64 - x.denom().bits() as f64) * std::f64::consts::LOG10_2;
            bail!(
                "in {flag}: an intensity of about 1e{decimal_exponent:.0} is outside the range of f64 ({:e} to {:e}), where the Riccati equation is solved: scale the noise (other units)",
                f64::MIN_POSITIVE,
                f64::MAX
            );
        }
    }
    // An observer of any kind needs every unobservable mode stable (detectability).
    crate::observability::require_detectable(&a, &c)?;
    if args.grid == 0 || args.grid > 100_000 {
        bail!("in --grid: {} points; give between 1 and 100000", args.grid);
    }
    if args.poles.is_none() && (args.derivative_output.is_some() || args.derivative_state.is_some())
    {
        bail!("--derivative-output and --derivative-state compare observers with chosen poles: give --poles too");
    }
    let exact_plant = StateSpace::new(a.clone(), Some(b.clone()), c.clone(), Some(d.clone()))?;
    let plant = Plant::from_exact(&exact_plant);
    let noise = NoiseIntensities::from_exact(&cu, &cy);
    let k = kalman_filter(&plant, &noise)?;
    let kalman_gain = DMatrix::from_fn(k.gain.len(), c.rows(), |i, j| k.gain[i][j]);
    let mut table = vec![Row {
        method: "kalman".into(),
        gain: kalman_gain.clone(),
        note: format!("Riccati residual {:.1e}", k.residual),
    }];
    let (_, _, s_corr) = plant.intensities(&noise);
    if s_corr.iter().any(|x| *x != 0.0) {
        let u = kalman_filter_ignoring_correlation(&plant, &noise)?;
        table.push(Row {
            method: "kalman-uncorrelated".into(),
            gain: DMatrix::from_fn(u.gain.len(), c.rows(), |i, j| u.gain[i][j]),
            note: format!(
                "designed with S = B C_U Dᵀ ignored (Riccati residual {:.1e}); Σ is for the true, correlated noise",
                u.residual
            ),
        });
    }
    if let Some(ptext) = &args.poles {
        let exact = Exact {
            plant: &exact_plant,
            cu: &cu,
            cy: &cy,
        };
        pole_rows(&args, ptext, &exact, &plant, &mut table)?;
    }
    let mut text = String::new();
    let (q, r, s) = plant.intensities(&noise);
    text.push_str(&format!(
        "Noise model: the observer sees u + n_u (C_U) and y + n_y (C_Y): Q = B C_U Bᵀ = {}, R = D C_U Dᵀ + C_Y = {}, S = B C_U Dᵀ = {}\n",
        show(&q), show(&r), show(&s)
    ));
    text.push_str(&format!(
        "Kalman filter (A − LC): P = {}, {} sign-function iterations, {} Newton–Kleinman steps, relative residual {:.2e}\n",
        show(&DMatrix::from_fn(k.covariance.len(), k.covariance.len(), |i, j| k.covariance[i][j])),
        k.sign_iterations, k.newton_steps, k.residual
    ));
    let json_rows = tabulate(&table, &plant, &noise, &mut text)?;
    if args.poles.is_some() {
        let (n, p) = (a.rows(), c.rows());
        text.push_str(&format!(
            "Placing {n} poles with a {n}×{p} gain leaves {} free parameters{}; the rows above are different choices of them.\n",
            n * p - n,
            if p == n { " (C is square: every observer matrix M with those poles is reached by L = (A − M)C⁻¹)" } else { "" }
        ));
    }
    if args.json {
        rep.json(json!({
            "convention": "a-lc",
            "kalman": k,
            "comparison": json_rows,
        }));
    } else {
        out!(rep, "{text}");
    }
    Ok(Outcome::Ok)
}
