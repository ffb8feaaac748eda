//! A printed matrix formula evaluated as printed: `Q T A T^-1` over the claim's named matrices
//! (`[claims.matrices]`) and the system's, exactly. It checks a document's statement in its
//! literal matrix form — dimensions included, so a selector matrix printed with the wrong number
//! of rows is found — rather than through an equivalent condition the workbench derived.

use super::inputs::{input_error, ComputeError, Inputs};
use crate::algebra::Rational;
use crate::derivation::Derivation;
use crate::linalg::{self, Matrix};
use crate::syntax::parse_expression;
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

/// A value met while evaluating: a number or a matrix.
enum Term {
    Scalar(Rational),
    Matrix(Matrix<Rational>),
}

fn shape(m: &Matrix<Rational>) -> String {
    format!("{}×{}", m.rows(), m.cols())
}

/// Evaluates `e`; `lookup` gives a named matrix; each named matrix is recorded in `d`.
fn eval(
    e: &Expr,
    lookup: &dyn Fn(&str) -> Result<Matrix<Rational>, ComputeError>,
) -> Result<Term, FormulaError> {
    let bad = FormulaError::Refused;
    Ok(match &e.kind {
        ExprKind::Number(r) => Term::Scalar(r.clone()),
        ExprKind::Symbol(name) => Term::Matrix(lookup(name)?),
        ExprKind::Neg(x) => match eval(x, lookup)? {
            Term::Scalar(r) => Term::Scalar(-r),
            Term::Matrix(m) => Term::Matrix(m.neg()),
        },
        ExprKind::Add(x, y) | ExprKind::Sub(x, y) => {
            let minus = matches!(e.kind, ExprKind::Sub(..));
            match (eval(x, lookup)?, eval(y, lookup)?) {
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
        ExprKind::Mul(x, y) => match (eval(x, lookup)?, eval(y, lookup)?) {
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
        ExprKind::Div(x, y) => match (eval(x, lookup)?, eval(y, lookup)?) {
            (t, Term::Scalar(b)) if !num_traits::Zero::is_zero(&b) => match t {
                Term::Scalar(a) => Term::Scalar(a / b),
                Term::Matrix(m) => Term::Matrix(m.scale(&b.recip())),
            },
            _ => {
                return Err(bad(format!(
                    "a division by a matrix or by zero (column {}); write X^-1",
                    e.column
                )))
            }
        },
        ExprKind::Pow(x, k) => match eval(x, lookup)? {
            Term::Scalar(a) => {
                Term::Scalar(num_traits::pow(a, k.unsigned_abs() as usize)).inverted_if(*k < 0)?
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
        ExprKind::Sqrt(_) | ExprKind::ImaginaryUnit => {
            return Err(bad(format!(
                "square roots are not evaluated in a matrix formula (column {})",
                e.column
            )))
        }
    })
}

impl Term {
    fn inverted_if(self, invert: bool) -> Result<Term, FormulaError> {
        match self {
            Term::Scalar(a) if invert => {
                if num_traits::Zero::is_zero(&a) {
                    Err(FormulaError::Refused("zero to a negative power".into()))
                } else {
                    Ok(Term::Scalar(a.recip()))
                }
            }
            t => Ok(t),
        }
    }
}

/// The claim's `expression` evaluated over its matrices, with each named matrix and the result
/// in the derivation.
///
/// # Errors
/// An input error naming the expression and what does not fit (undefined products, singular
/// inverses, unknown names).
pub fn evaluate(
    inputs: &Inputs,
    title: &str,
) -> Result<(Matrix<Rational>, Derivation), ComputeError> {
    let text = inputs.claim.expression.as_deref().ok_or_else(|| {
        input_error(
            "expression",
            "a matrix_expression claim gives its expression",
        )
    })?;
    let e = parse_expression(text).map_err(|e| input_error("expression", e.show_in(text)))?;
    let mut d = Derivation::new(title);
    let mut names: Vec<String> = Vec::new();
    collect_symbols(&e, &mut names);
    for n in &names {
        let m = inputs.numeric(n)?;
        d.push(n, "as printed", &m);
    }
    let lookup = |name: &str| inputs.numeric(name);
    match eval(&e, &lookup).map_err(|m| input_error("expression", format!("{text}: {m}")))? {
        Term::Matrix(m) => {
            d.push("result", text, &m);
            Ok((m, d))
        }
        Term::Scalar(_) => Err(input_error(
            "expression",
            format!("{text} is a number, not a matrix"),
        )),
    }
}

fn collect_symbols(e: &Expr, out: &mut Vec<String>) {
    match &e.kind {
        ExprKind::Symbol(s) if !out.contains(s) => out.push(s.clone()),
        ExprKind::Neg(x) | ExprKind::Sqrt(x) | ExprKind::Pow(x, _) => collect_symbols(x, out),
        ExprKind::Add(x, y) | ExprKind::Sub(x, y) | ExprKind::Mul(x, y) | ExprKind::Div(x, y) => {
            collect_symbols(x, out);
            collect_symbols(y, out);
        }
        _ => {}
    }
}
