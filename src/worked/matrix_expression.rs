//! A printed matrix formula evaluated as printed: `Q T A T^-1` over the claim's named matrices
//! (`[claims.matrices]`) and the system's, exactly. It checks a document's statement in its
//! literal matrix form — dimensions included, so a selector matrix printed with the wrong number
//! of rows is found — rather than through an equivalent condition the workbench derived.
//!
//! Matrices with free symbols (`A = [a1 1; a2 0]`, `K = [k1; k2]`) are evaluated over the
//! rational functions of those symbols, so a general formula (`A − K C` at order n) is checked
//! as an identity, not at sample points; numbers stay on the rational path.

use super::inputs::{input_error, lift, to_numeric, ComputeError, Computed, Inputs};
use super::value::Value;
use crate::algebra::{Field, Fraction, MultiPoly, Rational};
use crate::derivation::Derivation;
use crate::linalg::{self, Matrix};
use crate::syntax::{evaluate_with, parse_expression, parse_matrix_expressions};
use crate::syntax::{Expr, ExprKind};

/// Why a printed matrix formula cannot be evaluated as printed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
enum FormulaError {
    /// A named matrix that the claim does not give.
    #[error(transparent)]
    Input(#[from] ComputeError),
    /// A matrix operation refused (a singular inverse, an overflowing power).
    #[error(transparent)]
    Linalg(#[from] linalg::LinalgError),
    /// An operation the formula's shapes or values do not allow, with its column.
    #[error("{0}")]
    Refused(String),
}

/// A value met while evaluating: a number or a matrix (over the rationals, or the rational
/// functions of the symbols).
enum Term<F> {
    Scalar(F),
    Matrix(Matrix<F>),
}

fn shape<F: Field>(m: &Matrix<F>) -> String {
    format!("{}×{}", m.rows(), m.cols())
}

/// Evaluates `e`; `lookup` gives a named matrix or scalar (a parameter), `number` a printed
/// number in the field.
fn eval<F: Field>(
    e: &Expr,
    lookup: &dyn Fn(&str) -> Result<Term<F>, ComputeError>,
    number: &dyn Fn(&Rational) -> F,
) -> Result<Term<F>, FormulaError> {
    let bad = FormulaError::Refused;
    let eval = |x: &Expr| eval(x, lookup, number);
    Ok(match &e.kind {
        ExprKind::Number(r) => Term::Scalar(number(r)),
        ExprKind::Symbol(name) => lookup(name)?,
        ExprKind::Neg(x) => match eval(x)? {
            Term::Scalar(r) => Term::Scalar(-r),
            Term::Matrix(m) => Term::Matrix(m.neg()),
        },
        ExprKind::Add(x, y) | ExprKind::Sub(x, y) => {
            let minus = matches!(e.kind, ExprKind::Sub(..));
            match (eval(x)?, eval(y)?) {
                (Term::Scalar(a), Term::Scalar(b)) => {
                    Term::Scalar(if minus { a - b } else { a + b })
                }
                (Term::Matrix(a), Term::Matrix(b)) => {
                    let r = if minus { a.sub(&b) } else { a.add(&b) };
                    Term::Matrix(r.map_err(|_| {
                        bad(format!(
                            "a sum of a {} and a {} matrix (column {})",
                            shape(&a),
                            shape(&b),
                            e.column
                        ))
                    })?)
                }
                _ => {
                    return Err(bad(format!(
                        "a number added to a matrix (column {})",
                        e.column
                    )))
                }
            }
        }
        ExprKind::Mul(x, y) => match (eval(x)?, eval(y)?) {
            (Term::Scalar(a), Term::Scalar(b)) => Term::Scalar(a * b),
            (Term::Scalar(a), Term::Matrix(m)) | (Term::Matrix(m), Term::Scalar(a)) => {
                Term::Matrix(m.scale(&a))
            }
            (Term::Matrix(a), Term::Matrix(b)) => Term::Matrix(a.mul(&b).map_err(|_| {
                bad(format!(
                    "the product of a {} and a {} matrix is undefined (column {})",
                    shape(&a),
                    shape(&b),
                    e.column
                ))
            })?),
        },
        ExprKind::Div(x, y) => match (eval(x)?, eval(y)?) {
            (t, Term::Scalar(b)) if !num_traits::Zero::is_zero(&b) => {
                let inverse = b
                    .inverse()
                    .ok_or_else(|| bad(format!("a division by zero (column {})", e.column)))?;
                match t {
                    Term::Scalar(a) => Term::Scalar(a * inverse),
                    Term::Matrix(m) => Term::Matrix(m.scale(&inverse)),
                }
            }
            _ => {
                return Err(bad(format!(
                    "a division by a matrix or by zero (column {}); write X^-1",
                    e.column
                )))
            }
        },
        ExprKind::Pow(x, k) => match eval(x)? {
            Term::Scalar(a) => {
                let k_abs = u32::try_from(k.unsigned_abs())
                    .ok()
                    .filter(|k| *k <= 64)
                    .ok_or_else(|| bad(format!("the power {k} is too large (at most 64)")))?;
                let mut p = F::one();
                for _ in 0..k_abs {
                    p = p * a.clone();
                }
                Term::Scalar(p).inverted_if(*k < 0)?
            }
            Term::Matrix(m) => {
                if !m.is_square() {
                    return Err(bad(format!(
                        "the power of a {} matrix (column {})",
                        shape(&m),
                        e.column
                    )));
                }
                let base = if *k < 0 {
                    linalg::inverse(&m)
                        .map_err(|err| bad(format!("{err} (column {})", e.column)))?
                } else {
                    m
                };
                let k = u32::try_from(k.unsigned_abs())
                    .ok()
                    .filter(|k| *k <= 64)
                    .ok_or_else(|| bad(format!("the power {k} is too large (at most 64)")))?;
                Term::Matrix(base.pow(k)?)
            }
        },
        ExprKind::Transpose(x) => match eval(x)? {
            Term::Scalar(a) => Term::Scalar(a),
            Term::Matrix(m) => Term::Matrix(m.transpose()),
        },
        ExprKind::Sqrt(_) | ExprKind::ImaginaryUnit => {
            return Err(bad(format!(
                "square roots are not evaluated in a matrix formula (column {})",
                e.column
            )))
        }
    })
}

impl<F: Field> Term<F> {
    fn inverted_if(self, invert: bool) -> Result<Term<F>, FormulaError> {
        match self {
            Term::Scalar(a) if invert => a
                .inverse()
                .map(Term::Scalar)
                .ok_or_else(|| FormulaError::Refused("zero to a negative power".into())),
            t => Ok(t),
        }
    }
}

/// How a name of a formula is read: a matrix of the claim or its system; else one the workbench
/// derives from the claim's `A` and `C` (see [`derived`]); else a parameter (a scalar, `k1`,
/// `a`), its value substituted when the example gives one.
enum Name {
    Matrix(Matrix<MultiPoly>),
    Scalar(MultiPoly),
    Derived(Term<Fraction>),
}

/// The names a printed formula may use for what the workbench computes from the claim's `A`
/// and `C` (single output), over the rational functions of their symbols:
/// `O_n` (the observability matrix), `M` (Di Ruscio's Toeplitz matrix of `det(λI − A)`, eq.
/// (18)), `T_o` (Di Ruscio's transformation to observer form, `ss2ocf`) with `A_o = T_o⁻¹ A T_o`
/// and `C_o = C T_o`, `T_s` (Stoustrup's,
/// `t_n = O⁻¹ e_n`, `t_(i−1) = A t_i`) and the scalars `a_1 … a_n` of
/// `det(λI − A) = λⁿ + a_1 λⁿ⁻¹ + … + a_n`. Each is computed by the same function the commands
/// call, so a printed formula over them is compared with the workbench's own result. `None`
/// for any other name.
fn derived(inputs: &Inputs, n: &str) -> Result<Option<Term<Fraction>>, ComputeError> {
    let coefficient = n
        .strip_prefix("a_")
        .and_then(|k| k.parse::<usize>().ok())
        .filter(|k| *k >= 1);
    if !matches!(n, "O_n" | "M" | "T_o" | "A_o" | "C_o" | "T_s") && coefficient.is_none() {
        return Ok(None);
    }
    let fractions = |name: &str| -> Result<Matrix<Fraction>, ComputeError> {
        let m = inputs.symbolic(name)?;
        let rows = (0..m.rows())
            .map(|i| m.row(i).iter().cloned().map(Fraction::of).collect())
            .collect();
        Matrix::from_rows(rows).map_err(|e| input_error(name, e.to_string()))
    };
    let (a, c) = (fractions("A")?, fractions("C")?);
    let refused = |e: String| input_error("expression", format!("{n}: {e}"));
    Ok(Some(match (n, coefficient) {
        (_, Some(k)) => {
            let chi = crate::linalg::charpoly::berkowitz(&a, "s")?;
            let deg = a.rows();
            if k > deg {
                return Err(refused(format!("A has order {deg}, so a_1 … a_{deg}")));
            }
            Term::Scalar(chi.coeff(deg - k))
        }
        ("O_n", None) => Term::Matrix(crate::observability::observability_matrix(&a, &c)?),
        ("M" | "T_o" | "A_o" | "C_o", None) => {
            let f = crate::canonical_form::observer_form_di_ruscio(&a, None, &c)
                .map_err(|e| refused(e.to_string()))?;
            Term::Matrix(match n {
                "M" => f.toeplitz,
                "T_o" => f.t,
                "A_o" => f.a,
                _ => f.c,
            })
        }
        _ => Term::Matrix(
            crate::canonical_form::observer_form_stoustrup(&a, None, &c)
                .map_err(|e| refused(e.to_string()))?
                .t,
        ),
    }))
}

fn name(inputs: &Inputs, n: &str) -> Result<Name, ComputeError> {
    if let Some(t) = derived(inputs, n)? {
        return Ok(Name::Derived(t));
    }
    // a matrix the document defines by a formula (`where.K = "T_o K_o"`): evaluated over the
    // same names, which may not be defined by formulas in turn
    if let Some(text) = inputs.claim.definitions.get(n) {
        let e = parse_expression(text)
            .map_err(|e| input_error(&format!("where.{n}"), e.show_in(text)))?;
        let mut inner = Vec::new();
        collect_symbols(&e, &mut inner);
        if let Some(m) = inner
            .iter()
            .find(|m| inputs.claim.definitions.contains_key(*m))
        {
            return Err(input_error(
                &format!("where.{n}"),
                format!("{text} names {m}, itself defined by a formula"),
            ));
        }
        let mut scratch = Derivation::new("");
        let field = format!("where.{n}");
        return match evaluate_texts(inputs, &[(&field, n, text)], &mut scratch)?.pop() {
            Some(Value::Formula(m)) => Ok(Name::Derived(Term::Matrix(m))),
            Some(Value::Matrix(m)) => Ok(Name::Derived(Term::Matrix(m.map(Fraction::quadratic)))),
            _ => Err(input_error(
                &field,
                format!("{text} is not a matrix formula"),
            )),
        };
    }
    match inputs.symbolic(n) {
        Ok(m) => Ok(Name::Matrix(m)),
        Err(missing @ ComputeError::Input { .. }) => {
            let e = parse_expression(n).map_err(|_| missing.clone())?;
            evaluate_with::<MultiPoly>(&e, inputs.env)
                .map(Name::Scalar)
                .map_err(|_| missing)
        }
        Err(other) => Err(other),
    }
}

/// Evaluates the printed formulas `texts` over the same names: exactly over the rationals when
/// every name is a number, else over the rational functions of the symbols (each result a
/// [`Value::Formula`]). Each named matrix goes into `d` once.
pub(super) fn evaluate_texts(
    inputs: &Inputs,
    texts: &[(&str, &str, &str)],
    d: &mut Derivation,
) -> Result<Vec<Value>, ComputeError> {
    let mut parsed = Vec::new();
    let mut names: Vec<String> = Vec::new();
    for (field, label, text) in texts {
        let form = if text.trim_start().starts_with('[') {
            // a written-out matrix, possibly transposed as a whole (`[C1 C2]^T`)
            let (body, transposed) = match text.trim_end().strip_suffix("^T") {
                Some(b) if b.trim_end().ends_with(']') => (b, true),
                _ => (*text, false),
            };
            let rows =
                parse_matrix_expressions(body).map_err(|e| input_error(field, e.show_in(text)))?;
            rows.iter()
                .flatten()
                .for_each(|e| collect_symbols(e, &mut names));
            Form::Literal(rows, transposed)
        } else {
            let e = parse_expression(text).map_err(|e| input_error(field, e.show_in(text)))?;
            collect_symbols(&e, &mut names);
            Form::Formula(e)
        };
        parsed.push((*field, *label, *text, form));
    }
    // in the order the formulas name them (the derivation lists them so)
    let mut read: Vec<(String, Name)> = Vec::new();
    for n in &names {
        read.push((n.clone(), name(inputs, n)?));
    }
    let get = |n: &str| read.iter().find(|(m, _)| m == n).map(|(_, v)| v);
    // what the workbench derives is over the rational functions, numbers or not
    let symbolic = read.iter().map(|(_, v)| v).any(|v| match v {
        Name::Matrix(m) => m.entries().iter().any(|x| x.as_constant().is_none()),
        Name::Scalar(x) => x.as_constant().is_none(),
        Name::Derived(_) => true,
    });
    for (n, v) in &read {
        match v {
            Name::Matrix(m) => d.push(n, "as printed", m),
            Name::Derived(Term::Matrix(m)) => d.push(n, "computed by the workbench", m),
            Name::Derived(Term::Scalar(x)) => {
                d.push(
                    n,
                    "computed by the workbench",
                    &Matrix::from_rows(vec![vec![x.clone()]])?,
                );
            }
            Name::Scalar(_) => {}
        }
    }
    let mut out = Vec::new();
    for (field, label, text, form) in &parsed {
        let refused = |m: FormulaError| input_error(field, format!("{text}: {m}"));
        let value = if symbolic {
            let lookup = |n: &str| -> Result<Term<Fraction>, ComputeError> {
                match get(n) {
                    Some(Name::Matrix(m)) => {
                        let rows = (0..m.rows())
                            .map(|i| m.row(i).iter().cloned().map(Fraction::of).collect())
                            .collect();
                        Ok(Term::Matrix(
                            Matrix::from_rows(rows).map_err(|e| input_error(n, e.to_string()))?,
                        ))
                    }
                    Some(Name::Scalar(x)) => Ok(Term::Scalar(Fraction::of(x.clone()))),
                    Some(Name::Derived(Term::Matrix(m))) => Ok(Term::Matrix(m.clone())),
                    Some(Name::Derived(Term::Scalar(x))) => Ok(Term::Scalar(x.clone())),
                    None => Err(input_error(n, "missing")),
                }
            };
            let number = |r: &Rational| Fraction::constant(r.clone());
            let m = form.matrix(&lookup, &number).map_err(refused)?;
            d.push(label, text, &m);
            Value::Formula(m)
        } else {
            let lookup = |n: &str| -> Result<Term<Rational>, ComputeError> {
                match get(n) {
                    Some(Name::Matrix(m)) => Ok(Term::Matrix(to_numeric(m)?)),
                    Some(Name::Scalar(x)) => x
                        .as_constant()
                        .map(Term::Scalar)
                        .ok_or_else(|| ComputeError::NeedsValues(x.variables())),
                    // derived names make the evaluation symbolic (above)
                    Some(Name::Derived(_)) | None => Err(input_error(n, "missing")),
                }
            };
            let number = |r: &Rational| r.clone();
            let m = form.matrix(&lookup, &number).map_err(refused)?;
            d.push(label, text, &m);
            Value::Matrix(lift(&m))
        };
        out.push(value);
    }
    Ok(out)
}

/// A printed side: a matrix formula (`(A + L C) e`) or a matrix written out entry by entry
/// (`[-a_1 1; -a_2 0]`, each entry a formula over the same names, a matrix entry a block),
/// possibly transposed as a whole (`[C1 C2]^T`).
enum Form {
    Formula(Expr),
    Literal(Vec<Vec<Expr>>, bool),
}

impl Form {
    fn matrix<F: Field>(
        &self,
        lookup: &dyn Fn(&str) -> Result<Term<F>, ComputeError>,
        number: &dyn Fn(&Rational) -> F,
    ) -> Result<Matrix<F>, FormulaError> {
        match self {
            Form::Formula(e) => match eval(e, lookup, number)? {
                Term::Matrix(m) => Ok(m),
                Term::Scalar(_) => Err(FormulaError::Refused("a number, not a matrix".into())),
            },
            // entries that are matrices are blocks (`[C; C A]`): each row of blocks side by
            // side, the rows stacked, a number a 1×1 block; shapes that do not fit are refused
            Form::Literal(rows, transposed) => {
                let mut out: Option<Matrix<F>> = None;
                for r in rows {
                    let mut row: Option<Matrix<F>> = None;
                    for e in r {
                        let block = match eval(e, lookup, number)? {
                            Term::Scalar(x) => Matrix::from_rows(vec![vec![x]])?,
                            Term::Matrix(m) => m,
                        };
                        row = Some(match row {
                            None => block,
                            Some(left) => left.hstack(&block).map_err(|_| {
                                FormulaError::Refused(format!(
                                    "blocks of different heights side by side (column {})",
                                    e.column
                                ))
                            })?,
                        });
                    }
                    let Some(row) = row else {
                        return Err(FormulaError::Refused("an empty row".into()));
                    };
                    out = Some(match out {
                        None => row,
                        Some(top) => top.vstack(&row).map_err(|_| {
                            FormulaError::Refused("rows of blocks of different widths".into())
                        })?,
                    });
                }
                let m = out.ok_or_else(|| FormulaError::Refused("an empty matrix".into()))?;
                Ok(if *transposed { m.transpose() } else { m })
            }
        }
    }
}

/// The claim's `expression` evaluated over its matrices, with each named matrix and the result
/// in the derivation: an exact matrix, or a matrix of formulas when a name has symbols.
///
/// # Errors
/// An input error naming the expression and what does not fit (undefined products, singular
/// inverses, unknown names).
pub fn evaluate(inputs: &Inputs, title: &str) -> Result<Computed, ComputeError> {
    let text = inputs.claim.expression.as_deref().ok_or_else(|| {
        input_error(
            "expression",
            "a matrix_expression claim gives its expression",
        )
    })?;
    let mut d = Derivation::new(title);
    let value = evaluate_texts(inputs, &[("expression", "result", text)], &mut d)?
        .pop()
        .ok_or_else(|| input_error("expression", "nothing evaluated"))?;
    Ok(Computed {
        value,
        derivation: d,
    })
}

/// A printed equality of two matrix formulas (`A(x̂ − x) + L(Cx̂ − Cx) = (A + LC)e`): the left
/// side is the claim's `expression`, the right side its `printed`, both evaluated as printed over
/// the same names, compared exactly (an identity in the symbols when there are any).
///
/// # Errors
/// As [`evaluate`], for either side.
pub fn evaluate_identity(inputs: &Inputs, title: &str) -> Result<Computed, ComputeError> {
    let left = inputs.claim.expression.as_deref().ok_or_else(|| {
        input_error(
            "expression",
            "a matrix_identity claim gives its left side as expression",
        )
    })?;
    let right = inputs.claim.printed.as_str();
    let mut d = Derivation::new(title);
    let mut sides = evaluate_texts(
        inputs,
        &[
            ("expression", "left side", left),
            ("printed", "right side", right),
        ],
        &mut d,
    )?;
    let (Some(r), Some(l)) = (sides.pop(), sides.pop()) else {
        return Err(input_error("expression", "nothing evaluated"));
    };
    Ok(Computed {
        value: Value::Sides(Box::new(l), Box::new(r)),
        derivation: d,
    })
}

fn collect_symbols(e: &Expr, out: &mut Vec<String>) {
    match &e.kind {
        ExprKind::Symbol(s) if !out.contains(s) => out.push(s.clone()),
        ExprKind::Neg(x) | ExprKind::Sqrt(x) | ExprKind::Pow(x, _) | ExprKind::Transpose(x) => {
            collect_symbols(x, out)
        }
        ExprKind::Add(x, y) | ExprKind::Sub(x, y) | ExprKind::Mul(x, y) | ExprKind::Div(x, y) => {
            collect_symbols(x, out);
            collect_symbols(y, out);
        }
        _ => {}
    }
}
