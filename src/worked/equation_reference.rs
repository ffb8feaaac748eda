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

use super::inputs::{input_error, to_numeric, ComputeError, Inputs};
use super::value::Value;
use crate::algebra::{Fraction, MultiPoly, Rational, Zero};
use crate::derivation::{Derivation, Words};
use crate::linalg::charpoly::characteristic_polynomial;
use crate::linalg::Matrix;
use crate::syntax::{evaluate_with, parse_matrix_expressions};

/// The matrix an equation prints, or `None` for an equation that is not a matrix (an error
/// equation, a system of equations written in words).
fn equation_matrix(text: &str, inputs: &Inputs) -> Option<Matrix<Rational>> {
    let rows = parse_matrix_expressions(text).ok()?;
    let values = rows
        .iter()
        .map(|r| {
            r.iter()
                .map(|e| evaluate_with::<MultiPoly>(e, inputs.env))
                .collect::<Result<Vec<_>, _>>()
        })
        .collect::<Result<Vec<_>, _>>()
        .ok()?;
    to_numeric(&Matrix::from_rows(values).ok()?).ok()
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

/// For each referent, the labels of the equations that hold it (`or` between several, `none`).
///
/// # Errors
/// [`ComputeError`] for a claim without `refers` or `[claims.equations]`, or a referent the
/// claim and its system do not give.
pub fn evaluate(inputs: &Inputs, title: &str) -> Result<(Value, Derivation), ComputeError> {
    let claim = inputs.claim;
    if claim.refers.is_empty() || claim.equations.is_empty() {
        return Err(input_error(
            "refers",
            "an equation_reference claim gives `refers` and `[claims.equations]`",
        ));
    }
    let mut d = Derivation::new(title);
    let equations: Vec<(&str, Option<Matrix<Rational>>)> = claim
        .equations
        .iter()
        .map(|(key, text)| {
            let label = key.split_whitespace().next().unwrap_or(key);
            (label, equation_matrix(text, inputs))
        })
        .collect();
    for (key, text) in &claim.equations {
        d.push(
            &format!("equation {key}"),
            "as printed",
            &Words(text.clone()),
        );
    }
    let mut found = Vec::new();
    for r in &claim.refers {
        let mut labels: Vec<&str> = Vec::new();
        // `=formula`: a matrix formula over the claim's names (and what the workbench derives),
        // held by the equations whose own formula evaluates to the same matrix
        if let Some(formula) = r.strip_prefix('=') {
            let mut scratch = Derivation::new("");
            let wanted = super::matrix_expression::evaluate_texts(
                inputs,
                &[("refers", r, formula)],
                &mut scratch,
            )?
            .pop();
            for (key, text) in &claim.equations {
                let label = key.split_whitespace().next().unwrap_or(key);
                let value = super::matrix_expression::evaluate_texts(
                    inputs,
                    &[("equations", key, text)],
                    &mut scratch,
                )
                .ok()
                .and_then(|mut v| v.pop());
                if value.is_some() && value == wanted && !labels.contains(&label) {
                    labels.push(label);
                }
            }
            let text = if labels.is_empty() {
                "none".to_string()
            } else {
                labels.join(" or ")
            };
            d.push(
                &format!("{formula} is given by"),
                "the equations whose formula, evaluated as printed, is the same matrix",
                &Words(text.clone()),
            );
            found.push(text);
            continue;
        }
        if let Some(p) = polynomial_referent(r, inputs)? {
            for (key, text) in &claim.equations {
                let label = key.split_whitespace().next().unwrap_or(key);
                let holds = super::value::read_formula(text, inputs.env)
                    .ok()
                    .filter(|m| m.shape() == (1, 1))
                    .and_then(|m| monic(m.get(0, 0)))
                    .is_some_and(|q| q == p);
                if holds && !labels.contains(&label) {
                    labels.push(label);
                }
            }
            let text = if labels.is_empty() {
                "none".to_string()
            } else {
                labels.join(" or ")
            };
            d.push(
                &format!("{r} is given by"),
                "the equations printing it (as rational functions, made monic in λ; s read as λ)",
                &Words(text.clone()),
            );
            found.push(text);
            continue;
        }
        // `gain` (any output) or `gain:i` (the i-th row of C, 1-based), else a named matrix
        let gain_row = match r.strip_prefix("gain") {
            Some("") => Some(None),
            Some(i) => Some(Some(
                i.strip_prefix(':')
                    .and_then(|i| i.parse::<usize>().ok())
                    .filter(|i| *i >= 1)
                    .ok_or_else(|| input_error("refers", format!("'{r}' is not gain or gain:i")))?
                    - 1,
            )),
            None => None,
        };
        let wanted = match gain_row {
            Some(_) => None,
            None => Some(inputs.numeric(r)?),
        };
        for (label, m) in &equations {
            let Some(m) = m else { continue };
            let holds = match &wanted {
                Some(w) => w == m,
                None => places(m, gain_row.flatten(), inputs)?,
            };
            if holds && !labels.contains(label) {
                labels.push(label);
            }
        }
        let text = if labels.is_empty() {
            "none".to_string()
        } else {
            labels.join(" or ")
        };
        let how = if gain_row.is_some() {
            "the equations holding a gain that places the desired polynomial for one output"
        } else {
            "the equations whose matrix equals it"
        };
        d.push(&format!("{r} is given by"), how, &Words(text.clone()));
        found.push(text);
    }
    Ok((Value::Labels(found), d))
}
