//! A printed equation reference checked by reading the equations: "A, B and C₁ are given by
//! (3), (4) and (7)". The claim records the document's numbered equations as printed
//! (`[claims.equations]`, label → matrix, or words for an equation that is not a matrix) and
//! what the sentence refers to (`refers`); for each referent the workbench finds the equations
//! that hold it and compares those labels with the print.
//!
//! A referent is a matrix the claim or its system names (`A`, `B`, `C1`), matched by equality
//! with the equation's matrix, or `gain`: an equation holding an observer gain, i.e. a column
//! `K` with `det(sI − (A − K c)) = P(s)` for the claim's desired polynomial and some row `c` of
//! the system's `C` (`gain:i`: the i-th row only) — the same test a reader applies ("the gains
//! are (10a) and (13)").
//! Labels are the text before the first space of a key, so one equation printing two matrices
//! is recorded as `"(7) C1"` and `"(7) C2"`.
//!
//! A referent `=formula` is a matrix formula (`=A - T_o K_o C`) over the claim's matrices, its
//! `where` definitions and what the workbench derives (see `matrix_expression`); an equation
//! printing a formula over the same names holds it when the two evaluate to the same matrix.
//!
//! Two referents are polynomials: `observer_polynomial`, `det(λI − (A − K C))` with the claim's
//! symbolic `gain` K, and `desired_polynomial`, the claim's desired polynomial (a family with a
//! symbolic `T` allowed). An equation printing a polynomial holds one when the two agree as
//! rational functions of the symbols once both are made monic in the variable (`s` and `λ` are
//! the same variable here), so `T³s³ + 2T²s² + 2Ts + 1` holds the Butterworth polynomial
//! `s³ + (2/T)s² + (2/T²)s + 1/T³`.

use super::inputs::{input_error, to_numeric, ComputeError, Computed, Inputs};
use super::value::Value;
use crate::algebra::{Fraction, Rational, Zero};
use crate::derivation::{Derivation, Words};
use crate::linalg::charpoly::characteristic_polynomial;
use crate::linalg::Matrix;

/// The matrix an equation prints, or `None` for an equation that is not a matrix (an error
/// equation, a system of equations written in words).
fn equation_matrix(text: &str, inputs: &Inputs) -> Option<Matrix<Rational>> {
    to_numeric(&inputs.read_matrix("equations", text).ok()?).ok()
}

/// Whether `k` is an observer gain placing the claim's desired polynomial for one row of `C`.
fn places(k: &Matrix<Rational>, row: Option<usize>, inputs: &Inputs) -> Result<bool, ComputeError> {
    let (a, c) = (inputs.numeric("A")?, inputs.numeric("C")?);
    if k.shape() != (a.rows(), 1) {
        return Ok(false);
    }
    let desired = inputs
        .desired()?
        .rational()
        .ok_or_else(|| {
            input_error(
                "poles",
                "an equation reference to gains needs a rational desired polynomial",
            )
        })?
        .with_var("s");
    for i in (0..c.rows()).filter(|i| row.is_none_or(|r| r == *i)) {
        let row = Matrix::from_rows(vec![c.row(i).to_vec()])?;
        let closed = a.sub(&k.mul(&row)?)?;
        if characteristic_polynomial(&closed, "s")?.with_var("s") == desired {
            return Ok(true);
        }
    }
    Ok(false)
}

/// `p` in `λ` (an `s` renamed), divided by its leading coefficient in `λ`; `None` when it is not
/// a polynomial in `λ` (or is zero).
fn monic(p: &Fraction) -> Option<Fraction> {
    let p = p.substitute("s", &Fraction::symbol("λ"));
    let coefficients = p.coefficients_in("λ")?;
    let lead = coefficients.iter().rev().find(|c| !c.is_zero())?.clone();
    p.checked_div(&lead)
}

/// The polynomial referents, monic in `λ`.
fn polynomial_referent(r: &str, inputs: &Inputs) -> Result<Option<Fraction>, ComputeError> {
    let p = match r {
        "observer_polynomial" => {
            let a = inputs.symbolic("A")?;
            let c = inputs.symbolic("C")?;
            let k = inputs.symbolic("gain")?;
            let closed = a.sub(&k.mul(&c)?)?;
            Fraction::of(super::compute::symbolic_charpoly(&closed, "λ")?)
        }
        "desired_polynomial" => {
            let n = inputs.order()?;
            let coefficients = super::proof::symbolic_desired(inputs, n)
                .map_err(|e| input_error("refers", e.to_string()))?;
            let x = Fraction::symbol("λ");
            coefficients
                .iter()
                .rev()
                .fold(Fraction::zero(), |acc, c| acc * x.clone() + c.clone())
        }
        _ => return Ok(None),
    };
    Ok(monic(&p))
}

/// What a sentence refers to, read from one entry of `refers`.
enum Referent<'r> {
    /// `=formula`: the matrix it evaluates to (`None` when it does not evaluate).
    Formula(&'r str, Option<Value>),
    /// `observer_polynomial`, `desired_polynomial`: monic in λ.
    Polynomial(&'r str, Fraction),
    /// `gain` or `gain:i`: a column placing the desired polynomial for one row of C (or row i).
    Gain(&'r str, Option<usize>),
    /// A matrix of the claim or its system.
    Matrix(&'r str, Matrix<Rational>),
}

impl<'r> Referent<'r> {
    fn read(r: &'r str, inputs: &Inputs) -> Result<Self, ComputeError> {
        if let Some(formula) = r.strip_prefix('=') {
            let mut scratch = Derivation::new("");
            let wanted = super::matrix_expression::evaluate_texts(
                inputs,
                &[("refers", r, formula)],
                &mut scratch,
            )?
            .pop();
            return Ok(Referent::Formula(formula, wanted));
        }
        if let Some(p) = polynomial_referent(r, inputs)? {
            return Ok(Referent::Polynomial(r, p));
        }
        Ok(match r.strip_prefix("gain") {
            Some("") => Referent::Gain(r, None),
            Some(i) => Referent::Gain(
                r,
                Some(
                    i.strip_prefix(':')
                        .and_then(|i| i.parse::<usize>().ok())
                        .filter(|i| *i >= 1)
                        .ok_or_else(|| {
                            input_error("refers", format!("'{r}' is not gain or gain:i"))
                        })?
                        - 1,
                ),
            ),
            None => Referent::Matrix(r, inputs.numeric(r)?),
        })
    }

    /// Whether the equation printed as `text` holds it.
    fn held_by(&self, text: &str, inputs: &Inputs) -> Result<bool, ComputeError> {
        Ok(match self {
            Referent::Formula(_, wanted) => {
                let mut scratch = Derivation::new("");
                let value = super::matrix_expression::evaluate_texts(
                    inputs,
                    &[("equations", text, text)],
                    &mut scratch,
                )
                .ok()
                .and_then(|mut v| v.pop());
                value.is_some() && value == *wanted
            }
            Referent::Polynomial(_, p) => super::value::read_formula(text, inputs.env)
                .ok()
                .filter(|m| m.shape() == (1, 1))
                .and_then(|m| monic(m.get(0, 0)))
                .is_some_and(|q| q == *p),
            Referent::Gain(_, row) => match equation_matrix(text, inputs) {
                Some(m) => places(&m, *row, inputs)?,
                None => false,
            },
            Referent::Matrix(_, w) => equation_matrix(text, inputs).is_some_and(|m| m == *w),
        })
    }

    /// Its name in the derivation, and how the equations were read.
    fn describe(&self) -> (&'r str, &'static str) {
        match self {
            Referent::Formula(f, _) => (
                f,
                "the equations whose formula, evaluated as printed, is the same matrix",
            ),
            Referent::Polynomial(r, _) => (
                r,
                "the equations printing it (as rational functions, made monic in λ; s read as λ)",
            ),
            Referent::Gain(r, _) => (
                r,
                "the equations holding a gain that places the desired polynomial for one output",
            ),
            Referent::Matrix(r, _) => (r, "the equations whose matrix equals it"),
        }
    }
}

/// For each referent, the labels of the equations that hold it (`or` between several, `none`).
///
/// # Errors
/// [`ComputeError`] for a claim without `refers` or `[claims.equations]`, or a referent the
/// claim and its system do not give.
pub fn evaluate(inputs: &Inputs, title: &str) -> Result<Computed, ComputeError> {
    let claim = inputs.claim;
    if claim.refers.is_empty() || claim.equations.is_empty() {
        return Err(input_error(
            "refers",
            "an equation_reference claim gives `refers` and `[claims.equations]`",
        ));
    }
    let mut d = Derivation::new(title);
    for (key, text) in &claim.equations {
        d.push(
            &format!("equation {key}"),
            "as printed",
            &Words(text.clone()),
        );
    }
    let mut found = Vec::new();
    for r in &claim.refers {
        let referent = Referent::read(r, inputs)?;
        let mut labels: Vec<&str> = Vec::new();
        for (key, text) in &claim.equations {
            // one equation printing two matrices is recorded as "(7) C1" and "(7) C2"
            let label = key.split_whitespace().next().unwrap_or(key);
            if referent.held_by(text, inputs)? && !labels.contains(&label) {
                labels.push(label);
            }
        }
        let text = if labels.is_empty() {
            "none".to_string()
        } else {
            labels.join(" or ")
        };
        let (name, how) = referent.describe();
        d.push(&format!("{name} is given by"), how, &Words(text.clone()));
        found.push(text);
    }
    Ok(Computed {
        value: Value::Labels(found),
        derivation: d,
    })
}
