//! Recomputed values and their comparison with what a document printed.

use crate::algebra::{MultiPoly, Quadratic, Rational, Ring};
use crate::derivation::Show;
use crate::linalg::Matrix;
use crate::poly::{Factored, Poly, RationalFunction};
use crate::syntax::{
    evaluate_with, parse_expression, parse_matrix_expressions, rational_function_with, Environment,
};
use num_traits::Zero;

/// A recomputed value.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// An exact matrix.
    Matrix(Matrix<Quadratic>),
    /// A matrix with symbolic entries.
    SymbolicMatrix(Matrix<MultiPoly>),
    /// An exact polynomial in one variable.
    Polynomial(Poly<Quadratic>),
    /// A polynomial in `var` with symbolic coefficients (`var` is one of its symbols).
    SymbolicPolynomial(MultiPoly, String),
    /// An exact number.
    Scalar(Quadratic),
    /// A symbolic expression.
    Symbolic(MultiPoly),
    /// A formula in free parameters: a matrix of rational functions of them (a polynomial in
    /// `s` is a 1×1 matrix whose entry mentions `s`), compared as an identity.
    Formula(Matrix<crate::algebra::Fraction>),
    /// Yes or no.
    Bool(bool),
    /// A multiset of exact roots.
    Roots(Vec<Quadratic>),
    /// A transfer function.
    Transfer(RationalFunction<Rational>),
    /// Polynomial equations `p_i = 0`, in order.
    Equations(Vec<MultiPoly>),
    /// A set of conditions `p_i = 0` (order does not matter).
    Conditions(Vec<MultiPoly>),
    /// The two sides of a printed equality, each evaluated as printed (left, right).
    Sides(Box<Value>, Box<Value>),
    /// Words, one per item, compared as printed: equation labels, one per referent (`(4)`,
    /// `(10a) or (13)`, `none`), or a verdict (`stable`, `unstable`).
    Labels(Vec<String>),
    /// A linear system `M g = r`.
    LinearSystem(Matrix<Rational>, Matrix<Rational>),
    /// Float results of an optimisation: every equally good candidate (`rows × cols`, row-major),
    /// and how they were found.
    Approximate {
        /// Rows of each candidate.
        rows: usize,
        /// Columns of each candidate.
        cols: usize,
        /// The candidates.
        candidates: Vec<Vec<f64>>,
        /// How they were found.
        note: String,
    },
}

/// Six decimals in the everyday range, six significant digits (scientific) outside it.
fn float_text(x: f64) -> String {
    if x == 0.0 || (1e-3..1e7).contains(&x.abs()) {
        format!("{x:.6}")
    } else {
        format!("{x:.5e}")
    }
}

fn float_matrix(rows: usize, cols: usize, v: &[f64]) -> String {
    let r: Vec<String> = (0..rows)
        .map(|i| {
            (0..cols)
                .map(|j| float_text(v[i * cols + j]))
                .collect::<Vec<_>>()
                .join(", ")
        })
        .collect();
    if rows * cols == 1 {
        r.join("")
    } else {
        format!("[{}]", r.join("; "))
    }
}

impl Value {
    /// The value in the workbench's input syntax.
    pub fn input(&self) -> String {
        match self {
            Value::Matrix(m) => m.to_input(),
            Value::SymbolicMatrix(m) => m.to_input(),
            Value::Formula(m) => formula_input(m),
            Value::Polynomial(p) => p.to_input(),
            Value::SymbolicPolynomial(p, var) => symbolic_poly_text(p, var, Style::Input),
            Value::Scalar(x) => x.to_input(),
            Value::Symbolic(x) => x.to_input(),
            Value::Bool(b) => b.to_string(),
            Value::Labels(l) => l.join(", "),
            Value::Sides(l, _) => l.input(),
            Value::Roots(r) => r.iter().map(Ring::to_input).collect::<Vec<_>>().join(", "),
            Value::Transfer(t) => t.to_input(),
            Value::Equations(e) | Value::Conditions(e) => e
                .iter()
                .map(|p| format!("{} = 0", p.to_input()))
                .collect::<Vec<_>>()
                .join("; "),
            Value::LinearSystem(m, r) => format!("{} g = {}", m.to_input(), r.to_input()),
            Value::Approximate {
                rows,
                cols,
                candidates,
                note,
            } => {
                let c: Vec<String> = candidates
                    .iter()
                    .map(|v| float_matrix(*rows, *cols, v))
                    .collect();
                if note.is_empty() {
                    c.join(" or ")
                } else {
                    format!("{} ({note})", c.join(" or "))
                }
            }
        }
    }
    /// Terminal text.
    pub fn text(&self) -> String {
        match self {
            Value::Matrix(m) => m.render(),
            Value::SymbolicMatrix(m) => m.render(),
            Value::Formula(m) if m.shape() == (1, 1) => m.get(0, 0).to_string(),
            Value::Formula(m) => m.render(),
            Value::Polynomial(p) => factored_text(p).unwrap_or_else(|| p.to_string()),
            Value::SymbolicPolynomial(p, var) => symbolic_poly_text(p, var, Style::Human),
            Value::Scalar(x) => x.to_string(),
            Value::Symbolic(x) => x.to_string(),
            Value::Bool(b) => {
                if *b {
                    "yes".into()
                } else {
                    "no".into()
                }
            }
            Value::Labels(l) => l.join(", "),
            Value::Sides(l, _) => l.text(),
            Value::Roots(r) => r
                .iter()
                .map(|x| x.to_string())
                .collect::<Vec<_>>()
                .join(", "),
            Value::Transfer(t) => {
                let den = Factored::of(t.denominator());
                format!("{t}   (denominator {den})")
            }
            Value::Equations(e) | Value::Conditions(e) => e
                .iter()
                .map(|p| format!("{p} = 0"))
                .collect::<Vec<_>>()
                .join("\n"),
            Value::LinearSystem(m, r) => format!("{}\n  g =\n{}", m.render(), r.render()),
            Value::Approximate { .. } => self.input(),
        }
    }
    /// LaTeX.
    pub fn latex(&self) -> String {
        match self {
            Value::Matrix(m) => m.to_latex(),
            Value::SymbolicMatrix(m) => m.to_latex(),
            Value::Formula(m) if m.shape() == (1, 1) => m.get(0, 0).to_latex(),
            Value::Formula(m) => m.to_latex(),
            Value::Polynomial(p) => p.to_latex(),
            Value::SymbolicPolynomial(p, var) => symbolic_poly_text(p, var, Style::Latex),
            Value::Scalar(x) => x.to_latex(),
            Value::Symbolic(x) => x.to_latex(),
            Value::Bool(b) => format!("\\text{{{}}}", if *b { "yes" } else { "no" }),
            Value::Labels(l) => format!("\\text{{{}}}", l.join(", ")),
            Value::Sides(l, _) => l.latex(),
            Value::Roots(r) => r
                .iter()
                .map(Ring::to_latex)
                .collect::<Vec<_>>()
                .join(",\\ "),
            Value::Transfer(t) => t.to_latex(),
            Value::Equations(e) | Value::Conditions(e) => e
                .iter()
                .map(|p| format!("{} = 0", p.to_latex()))
                .collect::<Vec<_>>()
                .join(",\\quad "),
            Value::LinearSystem(m, r) => format!("{} g = {}", m.to_latex(), r.to_latex()),
            Value::Approximate { .. } => format!("\\text{{{}}}", self.input()),
        }
    }
}

impl Show for Value {
    fn text(&self) -> String {
        Value::text(self)
    }
    fn latex(&self) -> String {
        Value::latex(self)
    }
    fn input(&self) -> String {
        Value::input(self)
    }
}

fn factored_text(p: &Poly<Quadratic>) -> Option<String> {
    let c: Option<Vec<Rational>> = p
        .coeffs()
        .iter()
        .map(|c| c.as_rational().cloned())
        .collect();
    let q = Poly::new(c?, p.var());
    let f = Factored::of(&q);
    let plain = q.to_string();
    let fact = f.to_string();
    Some(
        if fact == plain || f.factors.len() <= 1 && f.factors.iter().all(|(_, m)| *m == 1) {
            plain
        } else {
            format!("{plain} = {fact}")
        },
    )
}

#[derive(Clone, Copy, PartialEq)]
enum Style {
    Human,
    Input,
    Latex,
}

/// A symbolic polynomial printed by powers of `var`: `λ^2 + (k1 + k2 − a)λ − a k2`.
fn symbolic_poly_text(p: &MultiPoly, var: &str, style: Style) -> String {
    let coeffs = p.coefficients_in(var);
    let mut out = String::new();
    for (k, c) in coeffs.iter().enumerate().rev() {
        if c.is_zero() {
            continue;
        }
        let body = match style {
            Style::Human => c.to_string(),
            Style::Input => c.to_input(),
            Style::Latex => c.to_latex(),
        };
        let compound = c.terms().count() > 1;
        let (neg, body) = match body.strip_prefix('-') {
            Some(rest) if !compound => (true, rest.to_string()),
            _ => (false, body),
        };
        if !out.is_empty() {
            out.push_str(match (neg, style) {
                (false, _) => " + ",
                (true, Style::Human) => " − ",
                (true, _) => " - ",
            });
        } else if neg {
            out.push('-');
        }
        let v = if style == Style::Latex {
            crate::algebra::latex_symbol(var)
        } else {
            var.to_string()
        };
        let power = match k {
            0 => String::new(),
            1 => v,
            _ if style == Style::Latex => format!("{v}^{{{k}}}"),
            _ => format!("{v}^{k}"),
        };
        let coef = match (compound, style) {
            (true, Style::Latex) => format!("\\left({body}\\right)"),
            (true, _) => format!("({body})"),
            (false, _) => body,
        };
        let join = if style == Style::Input { "*" } else { " " };
        out.push_str(&match (coef.as_str(), power.is_empty()) {
            (_, true) => coef,
            ("1", false) => power,
            (_, false) => format!("{coef}{join}{power}"),
        });
    }
    if out.is_empty() {
        "0".into()
    } else {
        out
    }
}

/// How a printed value compared.
#[derive(Debug, Clone, PartialEq)]
pub enum Agreement {
    /// Equal exactly.
    Exact,
    /// Equal to the precision printed (`digits` decimals, rounding).
    Rounded {
        /// Decimals printed.
        digits: i32,
    },
    /// Not equal; the reason.
    Differs(String),
}

impl Agreement {
    /// Whether the print holds.
    pub fn holds(&self) -> bool {
        !matches!(self, Agreement::Differs(_))
    }
}

/// The decimal places of the most precise number in `text`, counting a scientific exponent
/// (`5.63e-4` has 6); negative for coarse prints such as `1.2e3`.
fn printed_decimals(text: &str) -> Option<i32> {
    let chars: Vec<char> = text.chars().collect();
    let mut best = None;
    for i in 0..chars.len() {
        if chars[i] == '.' && i > 0 && chars[i - 1].is_ascii_digit() {
            let d = chars[i + 1..]
                .iter()
                .take_while(|c| c.is_ascii_digit())
                .count();
            let mut places = d as i32;
            let mut j = i + 1 + d;
            if j < chars.len() && (chars[j] == 'e' || chars[j] == 'E') {
                j += 1;
                let negative = j < chars.len() && chars[j] == '-';
                if j < chars.len() && (chars[j] == '-' || chars[j] == '+') {
                    j += 1;
                }
                let digits: String = chars[j..]
                    .iter()
                    .take_while(|c| c.is_ascii_digit())
                    .collect();
                if let Ok(e) = digits.parse::<i32>() {
                    places += if negative { e } else { -e };
                }
            }
            best = Some(best.map_or(places, |b: i32| b.max(places)));
        }
    }
    best
}

fn close(x: &Quadratic, p: &Quadratic, digits: Option<i32>) -> bool {
    match digits {
        None => x == p,
        Some(d) => {
            let (xr, xi) = x.to_complex_f64();
            let (pr, pi) = p.to_complex_f64();
            let tol = 0.5 * 10f64.powi(-d) * (1.0 + 1e-9);
            (xr - pr).abs() <= tol && (xi - pi).abs() <= tol
        }
    }
}

fn agreement(ok: bool, digits: Option<i32>, why: impl FnOnce() -> String) -> Agreement {
    match (ok, digits) {
        (true, None) => Agreement::Exact,
        (true, Some(d)) => Agreement::Rounded { digits: d },
        (false, _) => Agreement::Differs(why()),
    }
}

/// Why a printed value could not be read as the kind of value it is compared with.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PrintError {
    /// The print does not parse: the error shown under the text.
    #[error("{}", error.show_in(text))]
    Syntax {
        /// What the reader refused, with its column.
        error: crate::syntax::SyntaxError,
        /// The text it refused.
        text: String,
    },
    /// The print has the wrong shape for a matrix.
    #[error(transparent)]
    Shape(#[from] crate::linalg::LinalgError),
    /// The print is not of the form the value needs (an equation, `M g = r`, yes/no …).
    #[error("{0}")]
    Form(String),
}

impl PrintError {
    fn syntax(error: crate::syntax::SyntaxError, text: &str) -> Self {
        PrintError::Syntax {
            error,
            text: text.to_string(),
        }
    }
}

/// Compares a recomputed value with printed text, symbols in the print taken from `env`.
///
/// # Errors
/// [`PrintError`] when the printed text cannot be read as that kind of value.
pub fn compare(value: &Value, printed: &str, env: &Environment) -> Result<Agreement, PrintError> {
    let digits = printed_decimals(printed);
    match value {
        Value::Matrix(m) => compare_matrix(m, printed, env, digits),
        Value::SymbolicMatrix(m) => compare_symbolic_matrix(m, printed, env),
        Value::Formula(m) => compare_formula(m, printed, env),
        Value::Polynomial(q) => compare_polynomial(q, printed, env, digits),
        Value::SymbolicPolynomial(q, _) | Value::Symbolic(q) => compare_symbolic(q, printed, env),
        Value::Scalar(x) => compare_scalar(x, printed, env, digits),
        Value::Bool(b) => compare_bool(b, printed),
        Value::Labels(l) => Ok(compare_labels(l, printed)),
        Value::Sides(l, r) => Ok(compare_sides(l, r)),
        Value::Roots(r) => compare_roots(r, printed, env, digits),
        Value::Transfer(t) => compare_transfer(t, printed, env),
        Value::Equations(eqs) => compare_equations(eqs, printed, env),
        Value::Conditions(conds) => compare_conditions(conds, printed, env),
        Value::Approximate {
            rows,
            cols,
            candidates,
            ..
        } => compare_approximate((rows, cols), candidates, printed, env, digits),
        Value::LinearSystem(m, r) => compare_linear_system(m, r, printed),
    }
}

/// A formula in input syntax: a 1×1 as its entry.
fn formula_input(m: &Matrix<crate::algebra::Fraction>) -> String {
    if m.shape() == (1, 1) {
        m.get(0, 0).to_input()
    } else {
        m.to_input()
    }
}

/// A formula as written (a student's answer, a print) read as rational functions of the free
/// parameters, values of `env` substituted: a matrix in brackets, or one formula — a
/// polynomial in s is one expression, where `2 w s` is a product, not three entries of a row.
///
/// # Errors
/// [`PrintError`] showing where the text cannot be read.
pub fn read_formula(
    printed: &str,
    env: &Environment,
) -> Result<Matrix<crate::algebra::Fraction>, PrintError> {
    let syntax = |e: crate::syntax::SyntaxError| PrintError::syntax(e, printed);
    if printed.trim_start().starts_with('[') {
        return crate::syntax::parse_matrix_with(printed, env).map_err(syntax);
    }
    let e = crate::syntax::parse_expression(printed).map_err(syntax)?;
    let x = evaluate_with::<crate::algebra::Fraction>(&e, env).map_err(syntax)?;
    Matrix::from_rows(vec![vec![x]]).map_err(|e| PrintError::Form(e.to_string()))
}

/// A printed formula read as rational functions of the free parameters (values of `env`
/// substituted), the same shape and every entry equal as a rational function.
fn compare_formula(
    m: &Matrix<crate::algebra::Fraction>,
    printed: &str,
    env: &Environment,
) -> Result<Agreement, PrintError> {
    let read = read_formula(printed, env)?;
    if read.shape() != m.shape() {
        return Ok(Agreement::Differs(format!(
            "printed {}×{}, computed {}×{}",
            read.rows(),
            read.cols(),
            m.rows(),
            m.cols()
        )));
    }
    Ok(if read == *m {
        Agreement::Exact
    } else {
        Agreement::Differs(format!(
            "as formulas in the parameters, the print differs from {}",
            formula_input(m)
        ))
    })
}

/// The printed text read as rows of values, symbols taken from `env` (errors shown in the text).
fn printed_rows<T: crate::syntax::FromExpr>(
    printed: &str,
    env: &Environment,
) -> Result<Vec<Vec<T>>, PrintError> {
    let syntax = |e: crate::syntax::SyntaxError| PrintError::syntax(e, printed);
    let rows = parse_matrix_expressions(printed).map_err(syntax)?;
    rows.iter()
        .map(|r| r.iter().map(|e| evaluate_with::<T>(e, env)).collect())
        .collect::<Result<_, _>>()
        .map_err(syntax)
}

fn compare_matrix(
    m: &Matrix<Quadratic>,
    printed: &str,
    env: &Environment,
    digits: Option<i32>,
) -> Result<Agreement, PrintError> {
    let p: Vec<Vec<Quadratic>> = printed_rows(printed, env)?;
    let shape_ok = p.len() == m.rows() && p.iter().all(|r| r.len() == m.cols());
    if !shape_ok {
        return Ok(Agreement::Differs(format!(
            "printed {}×{}, recomputed {}×{}",
            p.len(),
            p.first().map_or(0, Vec::len),
            m.rows(),
            m.cols()
        )));
    }
    let mut bad = Vec::new();
    for i in 0..m.rows() {
        for j in 0..m.cols() {
            if !close(m.get(i, j), &p[i][j], digits) {
                bad.push(format!(
                    "({}, {}): printed {}, recomputed {}",
                    i + 1,
                    j + 1,
                    p[i][j],
                    m.get(i, j)
                ));
            }
        }
    }
    Ok(agreement(bad.is_empty(), digits, || bad.join("; ")))
}

fn compare_symbolic_matrix(
    m: &Matrix<MultiPoly>,
    printed: &str,
    env: &Environment,
) -> Result<Agreement, PrintError> {
    let p: Vec<Vec<MultiPoly>> = printed_rows(printed, env)?;
    let pm = Matrix::from_rows(p)?;
    let ok = pm == *m;
    Ok(agreement(ok, None, || {
        format!("printed {}, recomputed {}", pm.to_input(), m.to_input())
    }))
}

/// The variables a characteristic polynomial is written in, in the documents and the course.
const POLYNOMIAL_VARIABLES: [&str; 2] = ["s", "λ"];

fn compare_polynomial(
    q: &Poly<Quadratic>,
    printed: &str,
    env: &Environment,
    digits: Option<i32>,
) -> Result<Agreement, PrintError> {
    let p = printed_polynomial(printed, q.var(), env)?;
    let n = p.degree().unwrap_or(0).max(q.degree().unwrap_or(0));
    let ok = (0..=n).all(|k| close(&q.coeff(k), &p.coeff(k), digits));
    Ok(agreement(ok, digits, || {
        format!("printed {p}, recomputed {q}")
    }))
}

fn compare_symbolic(
    q: &MultiPoly,
    printed: &str,
    env: &Environment,
) -> Result<Agreement, PrintError> {
    let syntax = |e: crate::syntax::SyntaxError| PrintError::syntax(e, printed);
    let e = parse_expression(printed).map_err(syntax)?;
    let p = evaluate_with::<MultiPoly>(&e, env).map_err(syntax)?;
    let ok = &p == q;
    Ok(agreement(ok, None, || {
        format!(
            "printed {p}, recomputed {q}; difference {}",
            p.clone() - q.clone()
        )
    }))
}

fn compare_scalar(
    x: &Quadratic,
    printed: &str,
    env: &Environment,
    digits: Option<i32>,
) -> Result<Agreement, PrintError> {
    let syntax = |e: crate::syntax::SyntaxError| PrintError::syntax(e, printed);
    let e = parse_expression(printed).map_err(syntax)?;
    let p = evaluate_with::<Quadratic>(&e, env).map_err(syntax)?;
    Ok(agreement(close(x, &p, digits), digits, || {
        format!("printed {p}, recomputed {x}")
    }))
}

/// The two sides of a printed equality: equal, or the right side's value named.
fn compare_sides(l: &Value, r: &Value) -> Agreement {
    if l == r {
        Agreement::Exact
    } else {
        Agreement::Differs(format!(
            "the printed right side is {}, the left side {}",
            r.input(),
            l.input()
        ))
    }
}

/// A printed polynomial in `var`, or in the other variable the course writes (`s` for `λ` and
/// back: a student answering with the prompt's λ is not wrong), read in `var`.
///
/// # Errors
/// [`PrintError`] for text that does not read, or a rational function that is not a polynomial.
pub(super) fn printed_polynomial(
    printed: &str,
    var: &str,
    env: &Environment,
) -> Result<Poly<Quadratic>, PrintError> {
    let syntax = |e: crate::syntax::SyntaxError| PrintError::syntax(e, printed);
    let e = parse_expression(printed).map_err(syntax)?;
    let rf = match rational_function_with::<Quadratic>(&e, var, Some(env)) {
        Err(crate::syntax::SyntaxError::UnknownSymbol { name, .. })
            if POLYNOMIAL_VARIABLES.contains(&name.as_str()) && name != var =>
        {
            rational_function_with::<Quadratic>(&e, &name, Some(env)).map_err(syntax)?
        }
        r => r.map_err(syntax)?,
    };
    // a rational function's denominator is monic: a polynomial's is 1
    if rf.denominator().degree() != Some(0) {
        return Err(PrintError::Form(format!(
            "the printed value {printed} is not a polynomial in {var}"
        )));
    }
    Ok(rf.numerator().clone().with_var(var))
}

/// Equation labels as printed (`(3), (4), (7)`), one per referent, compared in order.
fn compare_labels(l: &[String], printed: &str) -> Agreement {
    let p: Vec<&str> = printed.split(',').map(str::trim).collect();
    let bad: Vec<String> = l
        .iter()
        .enumerate()
        .filter(|(i, x)| p.get(*i) != Some(&x.as_str()))
        .map(|(i, x)| {
            format!(
                "item {}: printed {}, recomputed {x}",
                i + 1,
                p.get(i).copied().unwrap_or("nothing")
            )
        })
        .collect();
    let counts = if p.len() == l.len() {
        String::new()
    } else {
        format!(" ({} printed, {} recomputed)", p.len(), l.len())
    };
    agreement(bad.is_empty() && counts.is_empty(), None, || {
        format!("{}{counts}", bad.join("; "))
    })
}

fn compare_bool(b: &bool, printed: &str) -> Result<Agreement, PrintError> {
    let t = printed.trim().to_lowercase();
    let p = match t.as_str() {
        "true" | "yes" | "observable" | "holds" => true,
        "false" | "no" | "unobservable" | "not observable" => false,
        _ => {
            return Err(PrintError::Form(format!(
                "expected yes/no (true, false, observable, unobservable), found '{printed}'"
            )))
        }
    };
    Ok(agreement(p == *b, None, || {
        format!("printed {p}, recomputed {b}")
    }))
}

fn compare_roots(
    r: &[Quadratic],
    printed: &str,
    env: &Environment,
    digits: Option<i32>,
) -> Result<Agreement, PrintError> {
    let mut p: Vec<Quadratic> = printed_rows(printed, env)?.into_iter().flatten().collect();
    let mut unmatched = Vec::new();
    for x in r {
        match p.iter().position(|y| close(x, y, digits)) {
            Some(k) => {
                p.remove(k);
            }
            None => unmatched.push(x.to_string()),
        }
    }
    let ok = unmatched.is_empty() && p.is_empty();
    Ok(agreement(ok, digits, || {
        format!(
            "recomputed roots not printed: [{}]; printed roots not recomputed: [{}]",
            unmatched.join(", "),
            p.iter()
                .map(|x| x.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        )
    }))
}

fn compare_transfer(
    t: &RationalFunction<Rational>,
    printed: &str,
    env: &Environment,
) -> Result<Agreement, PrintError> {
    let syntax = |e: crate::syntax::SyntaxError| PrintError::syntax(e, printed);
    let e = parse_expression(printed).map_err(syntax)?;
    let p = rational_function_with::<Rational>(&e, "s", Some(env)).map_err(syntax)?;
    Ok(agreement(&p == t, None, || {
        format!("printed {p}, recomputed {t}")
    }))
}

fn compare_equations(
    eqs: &[MultiPoly],
    printed: &str,
    env: &Environment,
) -> Result<Agreement, PrintError> {
    let parts: Vec<&str> = printed
        .split(';')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .collect();
    if parts.len() != eqs.len() {
        return Ok(Agreement::Differs(format!(
            "printed {} equations, recomputed {}",
            parts.len(),
            eqs.len()
        )));
    }
    let mut bad = Vec::new();
    for (k, (text, q)) in parts.iter().zip(eqs).enumerate() {
        let p = equation(text, env)?;
        if !proportional(&p, q) {
            bad.push(format!(
                "equation {}: printed {} = 0, recomputed {} = 0",
                k + 1,
                p,
                q
            ));
        }
    }
    Ok(agreement(bad.is_empty(), None, || bad.join("; ")))
}

fn compare_conditions(
    conds: &[MultiPoly],
    printed: &str,
    env: &Environment,
) -> Result<Agreement, PrintError> {
    let printed_conds: Vec<MultiPoly> = printed
        .split(';')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(|t| equation(t, env))
        .collect::<Result<_, _>>()?;
    let mut remaining: Vec<&MultiPoly> = conds.iter().collect();
    let mut not_recomputed = Vec::new();
    for p in &printed_conds {
        match remaining.iter().position(|q| proportional(p, q)) {
            Some(k) => {
                remaining.remove(k);
            }
            None => not_recomputed.push(format!("{p} = 0")),
        }
    }
    let ok = not_recomputed.is_empty() && remaining.is_empty();
    Ok(agreement(ok, None, || {
        let mut why = Vec::new();
        if !not_recomputed.is_empty() {
            why.push(format!(
                "printed but not required: {}",
                not_recomputed.join(", ")
            ));
        }
        if !remaining.is_empty() {
            why.push(format!(
                "required but not printed: {}",
                remaining
                    .iter()
                    .map(|q| format!("{q} = 0"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
        why.join("; ")
    }))
}

fn compare_approximate(
    (rows, cols): (&usize, &usize),
    candidates: &[Vec<f64>],
    printed: &str,
    env: &Environment,
    digits: Option<i32>,
) -> Result<Agreement, PrintError> {
    let syntax = |e: crate::syntax::SyntaxError| PrintError::syntax(e, printed);
    let prows = parse_matrix_expressions(printed).map_err(syntax)?;
    let p: Vec<f64> = prows
        .iter()
        .flatten()
        .map(|e| evaluate_with::<Quadratic>(e, env).map(|x| x.to_complex_f64().0))
        .collect::<Result<_, _>>()
        .map_err(syntax)?;
    if prows.len() != *rows || p.len() != rows * cols {
        return Ok(Agreement::Differs(format!(
            "printed {} entries, recomputed {rows}×{cols}",
            p.len()
        )));
    }
    let d = digits.unwrap_or(0);
    let tol = 0.5 * 10f64.powi(-d) * (1.0 + 1e-9);
    let matches = |c: &Vec<f64>| c.iter().zip(&p).all(|(x, y)| (x - y).abs() <= tol);
    let ok = candidates.iter().any(matches);
    let worst = candidates
        .iter()
        .map(|c| {
            c.iter()
                .zip(&p)
                .map(|(x, y)| (x - y).abs())
                .fold(0.0, f64::max)
        })
        .fold(f64::INFINITY, f64::min);
    Ok(agreement(ok, Some(d), || {
        format!("largest difference {worst:.3e} from the nearest recomputed candidate")
    }))
}

fn compare_linear_system(
    m: &Matrix<Rational>,
    r: &Matrix<Rational>,
    printed: &str,
) -> Result<Agreement, PrintError> {
    let syntax = |e: crate::syntax::SyntaxError| PrintError::syntax(e, printed);
    let (lhs, rhs) = printed
        .split_once('=')
        .ok_or_else(|| PrintError::Form(format!("expected 'M g = r', found '{printed}'")))?;
    let close_bracket = lhs
        .rfind(']')
        .ok_or_else(|| PrintError::Form(format!("expected a matrix before the gain in '{lhs}'")))?;
    let pm = crate::syntax::parse_matrix::<Rational>(&lhs[..=close_bracket]).map_err(syntax)?;
    let pr = crate::syntax::parse_matrix::<Rational>(rhs.trim()).map_err(syntax)?;
    // a system of equations does not depend on the order of its rows
    let rows = |m: &Matrix<Rational>, r: &Matrix<Rational>| {
        let mut v: Vec<Vec<Rational>> = (0..m.rows())
            .map(|i| {
                let mut row = m.row(i).to_vec();
                row.push(r.get(i, 0).clone());
                row
            })
            .collect();
        v.sort();
        v
    };
    let ok = pm.shape() == m.shape() && pr.shape() == r.shape() && rows(&pm, &pr) == rows(m, r);
    Ok(agreement(ok, None, || {
        format!(
            "printed {} g = {}, recomputed {} g = {}",
            pm.to_input(),
            pr.to_input(),
            m.to_input(),
            r.to_input()
        )
    }))
}

/// `lhs = rhs` as the polynomial `lhs − rhs`.
fn equation(text: &str, env: &Environment) -> Result<MultiPoly, PrintError> {
    let (l, r) = text.split_once('=').ok_or_else(|| {
        PrintError::Form(format!("expected an equation 'lhs = rhs', found '{text}'"))
    })?;
    let side = |s: &str| -> Result<MultiPoly, PrintError> {
        let e = parse_expression(s).map_err(|e| PrintError::syntax(e, s))?;
        evaluate_with::<MultiPoly>(&e, env).map_err(|e| PrintError::syntax(e, s))
    };
    Ok(side(l)? - side(r)?)
}

/// Whether `p = c·q` for a nonzero rational `c`.
fn proportional(p: &MultiPoly, q: &MultiPoly) -> bool {
    let Some((m, c)) = q.terms().next() else {
        return p.is_zero();
    };
    let pc = p.coefficient(m);
    if pc.is_zero() {
        return false;
    }
    let ratio = pc / c.clone();
    *p == q.clone() * MultiPoly::constant(ratio)
}
