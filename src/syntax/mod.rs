//! Reading what teachers and students type.
//!
//! * numbers: `-7/3`, `0.125` (read exactly as 1/8), `1e-3`, `2*sqrt(2) - 4`, `sqrt(2)/2`, `√2`,
//!   complex `-1+2i`;
//! * matrices, MATLAB style `[2 -3; 4 -5]` (a space before a sign and none after it starts a new
//!   entry, as in MATLAB) or nested `[[2,-3],[4,-5]]`;
//! * polynomials and transfer functions in one variable: `s^2 + 9s + 20`,
//!   `-108 (s + 7/3)/(s^2 + 15 s + 74)`;
//! * symbolic entries: `k1`, `a`, `T`, `λ`.
//!
//! Every error names the column and what was expected ([`SyntaxError`]). Printing lives with the
//! types (`Display`, `to_input`, `to_latex`); `parse(x.to_input()) == x` is a tested property.

mod eval;
mod lexer;
mod parser;
mod plain;
pub(crate) use plain::{word_fractions, WordFractions};

pub use eval::{
    evaluate_with, rational_function_with, DivisionRefused, Environment, FromExpr, ParseValue,
    SqrtRefused,
};
pub use parser::{Expr, ExprKind};

use crate::algebra::Field;
use crate::linalg::Matrix;
use crate::poly::{Poly, RationalFunction};

/// The longest input accepted, in characters.
pub const MAX_INPUT_LENGTH: usize = 1 << 20;
/// The largest exponent accepted in `x^k` and in `1e±k`.
pub const MAX_EXPONENT: u32 = 1000;
/// The largest value (in bits of numerators and denominators) that reading input may build.
pub const MAX_VALUE_BITS: u64 = 1 << 14;
/// The deepest nesting of parentheses, signs and square roots accepted (each parenthesis
/// counts twice: the sign and the term inside it).
pub const MAX_NESTING: usize = 100;
/// The longest chain of operations accepted (`1 + 1 + … + 1`, `2·2·…·2`), counting the chains
/// an expression is nested in: every reader walks the expression tree recursively, and this
/// bounds its height (a polynomial of the largest degree, 200, needs about 400).
pub const MAX_CHAIN: usize = 1000;

/// A parse or evaluation error, with the 1-based column where it was found.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SyntaxError {
    /// The input has nothing in it.
    #[error("empty input: expected {expected}")]
    Empty {
        /// What was expected.
        expected: String,
    },
    /// A token that does not fit here.
    #[error("column {column}: expected {expected}, found {found}")]
    Unexpected {
        /// 1-based column.
        column: usize,
        /// What would have fit.
        expected: String,
        /// What was there.
        found: String,
    },
    /// A construct the target type cannot hold (a symbol in a number, √2 in a rational…).
    #[error("column {column}: {what} is not allowed in {target}")]
    NotAllowed {
        /// 1-based column.
        column: usize,
        /// What was found.
        what: String,
        /// What was being read.
        target: String,
    },
    /// A symbol without a value where a value is needed (a caller may supply one: the worked
    /// examples sample free symbols).
    #[error("column {column}: the symbol '{name}' is not allowed in {target}")]
    UnknownSymbol {
        /// 1-based column.
        column: usize,
        /// The symbol.
        name: String,
        /// What was being read.
        target: String,
    },
    /// Division by zero.
    #[error("column {column}: division by zero")]
    DivisionByZero {
        /// 1-based column.
        column: usize,
    },
    /// A number or size beyond the documented limits.
    #[error("column {column}: {what} is too large (limit {limit})")]
    TooLarge {
        /// 1-based column.
        column: usize,
        /// What was too large.
        what: String,
        /// The limit.
        limit: usize,
    },
    /// Rows of different lengths.
    #[error("column {column}: row {row} has {found} entries, the first row has {expected}")]
    RaggedRows {
        /// 1-based column where the row starts.
        column: usize,
        /// 1-based row number.
        row: usize,
        /// Entries found.
        found: usize,
        /// Entries in the first row.
        expected: usize,
    },
}

impl SyntaxError {
    /// The 1-based column, when the error has one.
    pub fn column(&self) -> Option<usize> {
        match self {
            SyntaxError::Empty { .. } => None,
            SyntaxError::Unexpected { column, .. }
            | SyntaxError::NotAllowed { column, .. }
            | SyntaxError::UnknownSymbol { column, .. }
            | SyntaxError::DivisionByZero { column }
            | SyntaxError::TooLarge { column, .. }
            | SyntaxError::RaggedRows { column, .. } => Some(*column),
        }
    }

    /// The input with a caret under the offending column, for terminals. A long input is cut
    /// to a window around the column (a 130 KB input is not echoed whole).
    pub fn show_in(&self, input: &str) -> String {
        const WINDOW: usize = 120;
        let Some(c) = self.column() else {
            return self.to_string();
        };
        let chars: Vec<char> = input.chars().collect();
        if chars.len() <= WINDOW {
            return format!("{input}\n{}^ {self}", " ".repeat(c.saturating_sub(1)));
        }
        let at = c.saturating_sub(1).min(chars.len());
        let start = at.saturating_sub(WINDOW / 2);
        let end = (start + WINDOW).min(chars.len());
        let lead = if start > 0 { "…" } else { "" };
        let tail = if end < chars.len() { "…" } else { "" };
        let shown: String = chars[start..end].iter().collect();
        format!(
            "{lead}{shown}{tail}\n{}^ {self}",
            " ".repeat(at - start + lead.chars().count())
        )
    }
}

/// Parses one scalar (`-7/3`, `2*sqrt(2) - 4`, `k1 + a`) into the type `T`.
///
/// # Example
/// ```
/// use observer_workbench::algebra::{Quadratic, Rational, Ring};
/// use observer_workbench::syntax::parse_scalar;
/// let x: Rational = parse_scalar("0.125").unwrap();
/// assert_eq!(x.to_string(), "1/8");
/// let y: Quadratic = parse_scalar("2*sqrt(2) - 4").unwrap();
/// assert_eq!(y.to_string(), "2√2 − 4");
/// let err = parse_scalar::<Rational>("sqrt(2)").unwrap_err();
/// assert_eq!(err.to_string(), "column 1: the irrational √2 is not allowed in a rational number");
/// ```
///
/// # Errors
/// [`SyntaxError`] naming the column.
pub fn parse_scalar<T: FromExpr>(input: &str) -> Result<T, SyntaxError> {
    let e = parser::parse_expression(input)?;
    T::from_expr(&e)
}

/// Parses one expression into its tree (for evaluation later, e.g. with parameter values).
///
/// # Errors
/// [`SyntaxError`] naming the column.
pub fn parse_expression(input: &str) -> Result<Expr, SyntaxError> {
    parser::parse_expression(input)
}

/// Parses a matrix into expression trees, row by row.
///
/// # Errors
/// [`SyntaxError`] naming the column.
pub fn parse_matrix_expressions(input: &str) -> Result<Vec<Vec<Expr>>, SyntaxError> {
    parser::parse_matrix_rows(input)
}

/// Parses a matrix: `[2 -3; 4 -5]`, `[[2,-3],[4,-5]]`, or a bare scalar as a 1×1 matrix.
///
/// # Example
/// ```
/// use observer_workbench::algebra::Rational;
/// use observer_workbench::syntax::parse_matrix;
/// let a = parse_matrix::<Rational>("[2 -3; 4 -5]").unwrap();
/// assert_eq!(a.to_input(), "[2, -3; 4, -5]");
/// let err = parse_matrix::<Rational>("[1 2; 3]").unwrap_err();
/// assert_eq!(err.to_string(), "column 7: row 2 has 1 entries, the first row has 2");
/// ```
///
/// # Errors
/// [`SyntaxError`] naming the column.
pub fn parse_matrix<T: FromExpr>(input: &str) -> Result<Matrix<T>, SyntaxError> {
    let rows = parser::parse_matrix_rows(input)?;
    let values = rows
        .iter()
        .map(|r| r.iter().map(T::from_expr).collect::<Result<Vec<T>, _>>())
        .collect::<Result<Vec<_>, _>>()?;
    one_field_in_matrix(&rows, &values)?;
    Matrix::from_rows(values).map_err(|e| SyntaxError::TooLarge {
        column: 1,
        what: e.to_string(),
        limit: crate::linalg::MAX_EXACT_ORDER,
    })
}

/// Parses a matrix of exact rationals: [`parse_matrix`], with the common case of integer
/// fractions (`[8/50 -2/50; 0 1]`) scanned directly instead of built as expression trees (the
/// same matrix; anything else goes through the full parser, errors included).
///
/// # Errors
/// [`SyntaxError`] naming the column.
pub fn parse_rational_matrix(input: &str) -> Result<Matrix<crate::algebra::Rational>, SyntaxError> {
    match plain::rational_matrix(input) {
        Some(m) => Ok(m),
        None => parse_matrix(input),
    }
}

/// Parses a matrix whose entries may use named values from `env` (`[a 0; 0 -k/m]`).
///
/// # Example
/// ```
/// use observer_workbench::algebra::Rational;
/// use observer_workbench::syntax::{parse_matrix_with, Environment};
/// let env: Environment = [("a".to_string(), Rational::from_integer((-2).into()))].into();
/// assert_eq!(parse_matrix_with::<Rational>("[a 0; 1 a^2]", &env).unwrap().to_input(), "[-2, 0; 1, 4]");
/// ```
///
/// # Errors
/// [`SyntaxError`] naming the column (an unknown name, ragged rows…).
pub fn parse_matrix_with<T: FromExpr>(
    input: &str,
    env: &Environment,
) -> Result<Matrix<T>, SyntaxError> {
    let rows = parser::parse_matrix_rows(input)?;
    let values = rows
        .iter()
        .map(|r| {
            r.iter()
                .map(|e| evaluate_with::<T>(e, env))
                .collect::<Result<Vec<T>, _>>()
        })
        .collect::<Result<Vec<_>, _>>()?;
    one_field_in_matrix(&rows, &values)?;
    Matrix::from_rows(values).map_err(|e| SyntaxError::TooLarge {
        column: 1,
        what: e.to_string(),
        limit: crate::linalg::MAX_EXACT_ORDER,
    })
}

/// Parses a comma-separated list of scalars (`-1+2i, -1-2i, -3`); brackets are optional.
///
/// # Errors
/// [`SyntaxError`] naming the column.
pub fn parse_list<T: FromExpr>(input: &str) -> Result<Vec<T>, SyntaxError> {
    let rows = parser::parse_matrix_rows(input)?;
    let values: Vec<T> = rows
        .iter()
        .flatten()
        .map(T::from_expr)
        .collect::<Result<_, _>>()?;
    let columns = rows.iter().flatten().map(|e| e.column);
    eval::one_field(columns.zip(&values), "one list")?;
    Ok(values)
}

/// [`parse_list`] with symbols taken from `env` (those not in it stay symbols when the type has
/// them).
///
/// # Errors
/// [`SyntaxError`] naming the column.
pub fn parse_list_with<T: FromExpr>(input: &str, env: &Environment) -> Result<Vec<T>, SyntaxError> {
    let rows = parser::parse_matrix_rows(input)?;
    let values: Vec<T> = rows
        .iter()
        .flatten()
        .map(|e| evaluate_with::<T>(e, env))
        .collect::<Result<_, _>>()?;
    let columns = rows.iter().flatten().map(|e| e.column);
    eval::one_field(columns.zip(&values), "one list")?;
    Ok(values)
}

/// The entries of a matrix in one quadratic field (see [`eval::one_field`]).
fn one_field_in_matrix<T: FromExpr>(
    rows: &[Vec<parser::Expr>],
    values: &[Vec<T>],
) -> Result<(), SyntaxError> {
    let columns = rows.iter().flatten().map(|e| e.column);
    eval::one_field(columns.zip(values.iter().flatten()), "one matrix")
}

/// Parses a polynomial in `var` (`s^2 + 9s + 20`, `(s + 4)^3`).
///
/// # Example
/// ```
/// use observer_workbench::algebra::Rational;
/// use observer_workbench::syntax::parse_polynomial;
/// let p = parse_polynomial::<Rational>("(s + 4)^3", "s").unwrap();
/// assert_eq!(p.to_string(), "s^3 + 12s^2 + 48s + 64");
/// assert!(parse_polynomial::<Rational>("s^2 + x", "s").is_err());
/// ```
///
/// # Errors
/// [`SyntaxError`] naming the column.
pub fn parse_polynomial<F: Field + FromExpr>(
    input: &str,
    var: &str,
) -> Result<Poly<F>, SyntaxError> {
    let e = parser::parse_expression(input)?;
    eval::polynomial(&e, var)
}

/// Parses a rational function in `var` (`-108 (s + 7/3)/(s^2 + 15 s + 74)`).
///
/// # Errors
/// [`SyntaxError`] naming the column.
pub fn parse_rational_function<F: Field + FromExpr>(
    input: &str,
    var: &str,
) -> Result<RationalFunction<F>, SyntaxError> {
    let e = parser::parse_expression(input)?;
    eval::rational_function(&e, var)
}
