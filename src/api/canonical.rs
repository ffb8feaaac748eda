//! `owb canonical`: observer canonical form by both textbook procedures.

use super::args::json_matrix;
use super::parametric::Parametric;
use super::{Outcome, Report};
use crate::algebra::{Field, Fraction};
use crate::canonical_form::{observer_forms, CanonicalForm};
use crate::derivation::Derivation;
use crate::linalg::Matrix;
use anyhow::Result;

/// Arguments of `owb canonical`.
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "commands", derive(clap::Args))]
pub struct Args {
    /// The plant's A and C (`a`, `c`).
    #[serde(flatten)]
    #[cfg_attr(feature = "commands", command(flatten))]
    pub system: super::args::SystemPair,
    /// The input matrix B (optional).
    #[cfg_attr(feature = "commands", arg(allow_hyphen_values = true, long = "b"))]
    #[serde(default)]
    pub b: Option<String>,
    /// Machine-readable output.
    #[cfg_attr(feature = "commands", arg(long))]
    #[serde(default)]
    pub json: bool,
}

fn derivation<F: Field>(title: &str, t_formula: &str, f: &CanonicalForm<F>) -> Derivation {
    let mut d = Derivation::new(title);
    d.push("O_n", "[C; CA; …]", &f.test_matrix);
    d.push("det(sI − A)", "open-loop polynomial", &f.open_loop);
    d.push(
        "M",
        "upper-triangular Toeplitz of [1 a_1 … a_(n−1)]",
        &f.toeplitz,
    );
    d.push("T", t_formula, &f.t);
    d.push("T⁻¹", "", &f.t_inv);
    d.push("A_o", "T⁻¹ A T", &f.a);
    if f.b.cols() > 0 {
        d.push("B_o", "T⁻¹ B", &f.b);
    }
    d.push("C_o", "C T", &f.c);
    d
}

/// `owb canonical`: the observer canonical form of a request.
///
/// # Errors
///
/// What the request gets wrong (named by its flag) or what the computation refuses.
pub fn run(args: Args, rep: &mut Report) -> Result<Outcome> {
    let (a, c) = match args.system.plant()? {
        super::args::Plant::Symbolic(a, c) => return symbolic(&args, &a, &c, rep),
        super::args::Plant::Numeric(a, c) => (a, c),
    };
    let b = args.system.input(args.b.as_deref())?;
    super::args::check_plant(&a, b.as_ref(), &c, None)?;
    let (di, st) = observer_forms(&a, b.as_ref(), &c)?;
    render(rep, args.json, &di, &st);
    Ok(Outcome::Ok)
}

/// The canonical forms in the parameters, with where they break (the plant's denominators and
/// det O_n, which T_o inverts).
fn symbolic(
    args: &Args,
    a: &Matrix<Fraction>,
    c: &Matrix<Fraction>,
    rep: &mut Report,
) -> Result<Outcome> {
    let b = args
        .b
        .as_deref()
        .map(|t| super::args::matrix::<Fraction>("--b", t))
        .transpose()?;
    if let Some(b) = &b {
        super::args::expect_shape("--b", b, a.rows(), b.cols(), "states × inputs")?;
    }
    let mut work = Parametric::new(a)?
        .with(c.entries(), "C")?
        .with(b.as_ref().map_or(&[][..], |b| b.entries()), "B")?;
    let (di, st) = work.run(|| Ok::<_, anyhow::Error>(observer_forms(a, b.as_ref(), c)?))??;
    work.observability(a, c)?;
    let json = args.json.then(|| forms_json(&di, &st));
    work.answer(rep, json, |rep| render(rep, false, &di, &st));
    Ok(Outcome::Ok)
}

fn forms_json<F: Field>(di: &CanonicalForm<F>, st: &CanonicalForm<F>) -> serde_json::Value {
    let one = |f: &CanonicalForm<F>| {
        super::args::object(vec![
            ("T", json_matrix(&f.t)),
            ("T_inv", json_matrix(&f.t_inv)),
            ("A_o", json_matrix(&f.a)),
            ("B_o", json_matrix(&f.b)),
            ("C_o", json_matrix(&f.c)),
            ("open_loop", f.open_loop.to_input().into()),
        ])
    };
    super::args::object(vec![
        ("di_ruscio", one(di)),
        ("stoustrup", one(st)),
        ("same_transformation", (di.t == st.t).into()),
    ])
}

fn render<F: Field>(rep: &mut Report, json: bool, di: &CanonicalForm<F>, st: &CanonicalForm<F>) {
    let same = di.t == st.t;
    if json {
        rep.json(forms_json(di, st));
    } else {
        out!(
            rep,
            "{}",
            derivation("Di Ruscio ss2ocf: T_o = (Mᵀ O_n)⁻¹", "(Mᵀ O_n)⁻¹", di).render()
        );
        out!(
            rep,
            "{}",
            derivation(
                "Stoustrup: t_n = O⁻¹ e_n, t_(k−1) = A t_k",
                "[t_1 … t_n]",
                st
            )
            .render()
        );
        outln!(rep,
            "Both procedures give {} transformation; A_o has −a_i (Di Ruscio's a_i) = Stoustrup's a_i in its first column.",
            if same { "the same" } else { "different" }
        );
    }
}
