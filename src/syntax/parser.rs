//! Recursive-descent parser: expressions and matrices into [`Expr`] trees with columns.

use super::lexer::{tokenize, Tok, Token};
use super::{SyntaxError, MAX_CHAIN, MAX_EXPONENT, MAX_NESTING};
use crate::algebra::Rational;
use num_bigint::BigInt;

/// A parsed expression with the column it starts at.
#[derive(Debug, Clone, PartialEq)]
pub struct Expr {
    /// What the expression is.
    pub kind: ExprKind,
    /// 1-based column of its first character.
    pub column: usize,
}

/// The kinds of expression the syntax knows.
#[derive(Debug, Clone, PartialEq)]
pub enum ExprKind {
    /// An exact number (decimals are read exactly).
    Number(Rational),
    /// A named symbol (`k1`, `s`, `λ`).
    Symbol(String),
    /// The imaginary unit `i` (engineers' `j` too).
    ImaginaryUnit,
    /// `sqrt(x)` or `√x`.
    Sqrt(Box<Expr>),
    /// `−x`.
    Neg(Box<Expr>),
    /// `x + y`.
    Add(Box<Expr>, Box<Expr>),
    /// `x − y`.
    Sub(Box<Expr>, Box<Expr>),
    /// `x · y` (also written by juxtaposition, `9s`).
    Mul(Box<Expr>, Box<Expr>),
    /// `x / y`.
    Div(Box<Expr>, Box<Expr>),
    /// `x ^ k` with an integer `k`.
    Pow(Box<Expr>, i64),
    /// `X^T`, the transpose: meaningful in a printed matrix formula only (a number or a
    /// polynomial refuses it).
    Transpose(Box<Expr>),
}

/// A product holding `i` and the root of a nonnegative number, `2*sqrt(3)*i`, read as the root
/// of the negated number, `2*sqrt(-3)`: `i·√r = √(−r)` for `r ≥ 0`, and one quadratic field
/// (`Q(√−3)`) holds it, where `√3` and `i` alone lie in two. Other products are left as they
/// are (`√(−3)·i = −√3` is not `√3`, so a root of a negative number is not folded).
fn imaginary_radical(e: Expr) -> Expr {
    fn factors(e: Expr, out: &mut Vec<Expr>) {
        match e.kind {
            ExprKind::Mul(x, y) => {
                factors(*x, out);
                factors(*y, out);
            }
            kind => out.push(Expr {
                kind,
                column: e.column,
            }),
        }
    }
    fn nonnegative_literal(e: &Expr) -> bool {
        match &e.kind {
            ExprKind::Number(r) => !num_traits::Signed::is_negative(r),
            ExprKind::Div(x, y) => nonnegative_literal(x) && nonnegative_literal(y),
            _ => false,
        }
    }
    let column = e.column;
    match e.kind {
        ExprKind::Div(x, y) => Expr {
            kind: ExprKind::Div(Box::new(imaginary_radical(*x)), y),
            column,
        },
        ExprKind::Mul(x, y) => {
            let mut fs = Vec::new();
            factors(*x, &mut fs);
            factors(*y, &mut fs);
            let units: Vec<usize> = (0..fs.len())
                .filter(|&k| fs[k].kind == ExprKind::ImaginaryUnit)
                .collect();
            let root = fs
                .iter()
                .position(|f| matches!(&f.kind, ExprKind::Sqrt(arg) if nonnegative_literal(arg)));
            if let (&[unit], Some(root)) = (units.as_slice(), root) {
                if let ExprKind::Sqrt(arg) = &mut fs[root].kind {
                    let inner = std::mem::replace(
                        arg.as_mut(),
                        Expr {
                            kind: ExprKind::Number(<Rational as num_traits::Zero>::zero()),
                            column,
                        },
                    );
                    let c = inner.column;
                    **arg = Expr {
                        kind: ExprKind::Neg(Box::new(inner)),
                        column: c,
                    };
                }
                fs.remove(unit);
            }
            let mut it = fs.into_iter();
            let first = it.next().expect("a product has factors");
            it.fold(first, |acc, f| Expr {
                kind: ExprKind::Mul(Box::new(acc), Box::new(f)),
                column,
            })
        }
        kind => Expr { kind, column },
    }
}

struct Parser {
    toks: Vec<Token>,
    pos: usize,
    /// Inside matrix brackets (and not inside parentheses): whitespace separates entries.
    in_matrix: bool,
    /// Current recursion depth (see [`MAX_NESTING`]).
    depth: usize,
    /// Operators of the `+ − · /` chains being read, the enclosing ones included: a bound on
    /// the height of the tree being built (see [`MAX_CHAIN`]).
    chain: usize,
}

pub(crate) fn parse_expression(input: &str) -> Result<Expr, SyntaxError> {
    let mut p = Parser::new(input)?;
    p.skip_newlines();
    if p.peek().tok == Tok::End {
        return Err(SyntaxError::Empty {
            expected: "an expression".into(),
        });
    }
    let e = p.expr()?;
    p.skip_newlines();
    p.expect_end("an operator or the end of the input")?;
    Ok(e)
}

pub(crate) fn parse_matrix_rows(input: &str) -> Result<Vec<Vec<Expr>>, SyntaxError> {
    let mut p = Parser::new(input)?;
    p.skip_newlines();
    if p.peek().tok == Tok::End {
        return Err(SyntaxError::Empty {
            expected: "a matrix such as [1 2; 3 4]".into(),
        });
    }
    let rows = if p.peek().tok == Tok::LBrack {
        p.bracketed_matrix()?
    } else {
        p.in_matrix = true;
        p.rows_until(&Tok::End)?
    };
    p.skip_newlines();
    p.expect_end("the end of the input after the matrix")?;
    Ok(rows)
}

/// Refuses rows of different lengths, naming the first that differs (`starts`: the column
/// each row starts at).
fn same_length(rows: &[Vec<Expr>], starts: &[usize]) -> Result<(), SyntaxError> {
    let Some(first) = rows.first() else {
        return Ok(());
    };
    match rows
        .iter()
        .enumerate()
        .skip(1)
        .find(|(_, r)| r.len() != first.len())
    {
        Some((k, r)) => Err(SyntaxError::RaggedRows {
            column: starts.get(k).copied().unwrap_or(1),
            row: k + 1,
            found: r.len(),
            expected: first.len(),
        }),
        None => Ok(()),
    }
}

impl Parser {
    fn new(input: &str) -> Result<Self, SyntaxError> {
        Ok(Parser {
            toks: tokenize(input)?,
            pos: 0,
            in_matrix: false,
            depth: 0,
            chain: 0,
        })
    }
    fn peek(&self) -> &Token {
        &self.toks[self.pos.min(self.toks.len() - 1)]
    }
    fn peek_at(&self, k: usize) -> &Token {
        &self.toks[(self.pos + k).min(self.toks.len() - 1)]
    }
    fn next(&mut self) -> Token {
        let t = self.peek().clone();
        if self.pos < self.toks.len() - 1 {
            self.pos += 1;
        }
        t
    }
    fn unexpected(&self, expected: &str) -> SyntaxError {
        let t = self.peek();
        SyntaxError::Unexpected {
            column: t.column,
            expected: expected.into(),
            found: t.tok.describe(),
        }
    }
    fn expect(&mut self, tok: Tok, expected: &str) -> Result<Token, SyntaxError> {
        if self.peek().tok == tok {
            Ok(self.next())
        } else {
            Err(self.unexpected(expected))
        }
    }
    fn expect_end(&mut self, expected: &str) -> Result<(), SyntaxError> {
        self.expect(Tok::End, expected).map(|_| ())
    }
    fn skip_newlines(&mut self) {
        while self.peek().tok == Tok::Newline {
            self.next();
        }
    }

    /// `[ rows ]` or `[[row], [row]]`.
    fn bracketed_matrix(&mut self) -> Result<Vec<Vec<Expr>>, SyntaxError> {
        self.expect(Tok::LBrack, "'['")?;
        let saved = self.in_matrix;
        self.in_matrix = true;
        self.skip_newlines();
        let rows = if self.peek().tok == Tok::LBrack {
            let mut rows = Vec::new();
            let mut starts = Vec::new();
            loop {
                self.skip_newlines();
                starts.push(self.peek().column);
                self.expect(Tok::LBrack, "'[' starting a row")?;
                rows.push(self.row()?);
                self.expect(Tok::RBrack, "',' or ']' closing the row")?;
                self.skip_newlines();
                match self.peek().tok {
                    Tok::Comma | Tok::Semi => {
                        self.next();
                    }
                    Tok::RBrack => break,
                    _ => return Err(self.unexpected("',' or ']'")),
                }
            }
            same_length(&rows, &starts)?;
            rows
        } else {
            self.rows_until(&Tok::RBrack)?
        };
        self.expect(Tok::RBrack, "']' closing the matrix")?;
        self.in_matrix = saved;
        Ok(rows)
    }

    /// Rows separated by `;` or line breaks, up to (not including) `end`.
    fn rows_until(&mut self, end: &Tok) -> Result<Vec<Vec<Expr>>, SyntaxError> {
        let mut rows: Vec<Vec<Expr>> = Vec::new();
        let mut starts: Vec<usize> = Vec::new();
        loop {
            self.skip_newlines();
            if &self.peek().tok == end {
                break;
            }
            starts.push(self.peek().column);
            let row = self.row()?;
            if !row.is_empty() {
                rows.push(row);
            }
            match &self.peek().tok {
                Tok::Semi | Tok::Newline => {
                    self.next();
                }
                t if t == end => break,
                _ => {
                    let what = if end == &Tok::End {
                        "',', ';' or the end of the input"
                    } else {
                        "',', ';' or ']'"
                    };
                    return Err(self.unexpected(what));
                }
            }
        }
        same_length(&rows, &starts)?;
        Ok(rows)
    }

    /// Entries separated by commas or (MATLAB style) whitespace.
    fn row(&mut self) -> Result<Vec<Expr>, SyntaxError> {
        let mut out = Vec::new();
        loop {
            match self.peek().tok {
                Tok::RBrack | Tok::Semi | Tok::Newline | Tok::End => break,
                _ => {}
            }
            out.push(self.expr()?);
            match self.peek().tok {
                Tok::Comma => {
                    self.next();
                }
                Tok::RBrack | Tok::Semi | Tok::Newline | Tok::End => break,
                _ if self.peek().space_before => {}
                _ => return Err(self.unexpected("',' or the next entry")),
            }
        }
        Ok(out)
    }

    /// A sign with space before and none after starts a new matrix entry.
    fn starts_new_entry(&self) -> bool {
        self.in_matrix && self.peek().space_before && !self.peek_at(1).space_before
    }

    /// One more operator in a chain (`1 + 1 + …`): the tree grows one level deeper, so chains
    /// are bounded as nesting is, and every walker of the tree stays within its stack.
    fn one_more_link(&mut self) -> Result<(), SyntaxError> {
        if self.chain >= MAX_CHAIN {
            return Err(SyntaxError::TooLarge {
                column: self.peek().column,
                what: "the chain of operations (+ − · / and nested chains)".into(),
                limit: MAX_CHAIN,
            });
        }
        self.chain += 1;
        Ok(())
    }

    fn expr(&mut self) -> Result<Expr, SyntaxError> {
        let saved = self.chain;
        let r = self.expr_chain();
        self.chain = saved;
        r
    }

    fn expr_chain(&mut self) -> Result<Expr, SyntaxError> {
        let mut lhs = self.term()?;
        loop {
            let op = self.peek().tok.clone();
            if !matches!(op, Tok::Plus | Tok::Minus) || self.starts_new_entry() {
                break;
            }
            self.one_more_link()?;
            let column = self.next().column;
            let rhs = self.term()?;
            let kind = if op == Tok::Plus {
                ExprKind::Add(Box::new(lhs), Box::new(rhs))
            } else {
                ExprKind::Sub(Box::new(lhs), Box::new(rhs))
            };
            lhs = Expr { kind, column };
        }
        Ok(lhs)
    }

    fn term(&mut self) -> Result<Expr, SyntaxError> {
        let saved = self.chain;
        let r = self.term_chain();
        self.chain = saved;
        r
    }

    fn term_chain(&mut self) -> Result<Expr, SyntaxError> {
        let mut lhs = self.unary()?;
        loop {
            let t = self.peek().clone();
            match t.tok {
                Tok::Star | Tok::Slash => {
                    self.one_more_link()?;
                    self.next();
                    let rhs = self.unary()?;
                    let kind = if t.tok == Tok::Star {
                        ExprKind::Mul(Box::new(lhs), Box::new(rhs))
                    } else {
                        ExprKind::Div(Box::new(lhs), Box::new(rhs))
                    };
                    lhs = Expr {
                        kind,
                        column: t.column,
                    };
                }
                // Juxtaposition: 9s, 2(s + 1), √2 s, k1 k2 (not across spaces inside matrices,
                // and never number after number).
                Tok::Ident(_) | Tok::LParen | Tok::Sqrt if !(self.in_matrix && t.space_before) => {
                    self.one_more_link()?;
                    let rhs = self.power()?;
                    lhs = Expr {
                        kind: ExprKind::Mul(Box::new(lhs), Box::new(rhs)),
                        column: t.column,
                    };
                }
                _ => break,
            }
        }
        Ok(imaginary_radical(lhs))
    }

    /// One level deeper into the recursion (signs, parentheses, roots), refused past
    /// [`MAX_NESTING`] so that hostile input meets an error, not a stack overflow.
    fn nested<T>(
        &mut self,
        f: impl FnOnce(&mut Self) -> Result<T, SyntaxError>,
    ) -> Result<T, SyntaxError> {
        if self.depth >= MAX_NESTING {
            return Err(SyntaxError::TooLarge {
                column: self.peek().column,
                what: "the nesting of parentheses, signs and square roots".into(),
                limit: MAX_NESTING,
            });
        }
        self.depth += 1;
        let r = f(self);
        self.depth -= 1;
        r
    }

    fn unary(&mut self) -> Result<Expr, SyntaxError> {
        self.nested(Self::unary_inner)
    }

    fn unary_inner(&mut self) -> Result<Expr, SyntaxError> {
        match self.peek().tok {
            Tok::Minus => {
                let column = self.next().column;
                let inner = self.unary()?;
                Ok(Expr {
                    kind: ExprKind::Neg(Box::new(inner)),
                    column,
                })
            }
            Tok::Plus => {
                self.next();
                self.unary()
            }
            _ => self.power(),
        }
    }

    fn power(&mut self) -> Result<Expr, SyntaxError> {
        let base = self.primary()?;
        if self.peek().tok != Tok::Caret {
            return Ok(base);
        }
        let caret = self.next();
        if self.peek().tok == Tok::Ident("T".into()) {
            self.next();
            return Ok(Expr {
                kind: ExprKind::Transpose(Box::new(base)),
                column: caret.column,
            });
        }
        let paren = self.peek().tok == Tok::LParen;
        if paren {
            self.next();
        }
        let negative = match self.peek().tok {
            Tok::Minus => {
                self.next();
                true
            }
            Tok::Plus => {
                self.next();
                false
            }
            _ => false,
        };
        let t = self.next();
        let k: i64 = match &t.tok {
            Tok::Number(n) if n.chars().all(|c| c.is_ascii_digit()) => match n.parse::<u32>() {
                Ok(k) if k <= MAX_EXPONENT => k as i64,
                _ => {
                    return Err(SyntaxError::TooLarge {
                        column: t.column,
                        what: format!("the exponent {n}"),
                        limit: MAX_EXPONENT as usize,
                    })
                }
            },
            other => {
                return Err(SyntaxError::Unexpected {
                    column: t.column,
                    expected: "a whole-number exponent".into(),
                    found: other.describe(),
                })
            }
        };
        if paren {
            self.expect(Tok::RParen, "')' closing the exponent")?;
        }
        Ok(Expr {
            kind: ExprKind::Pow(Box::new(base), if negative { -k } else { k }),
            column: caret.column,
        })
    }

    fn primary(&mut self) -> Result<Expr, SyntaxError> {
        self.nested(Self::primary_inner)
    }

    fn primary_inner(&mut self) -> Result<Expr, SyntaxError> {
        let t = self.peek().clone();
        match &t.tok {
            Tok::Number(text) => {
                self.next();
                Ok(Expr {
                    kind: ExprKind::Number(parse_decimal(text, t.column)?),
                    column: t.column,
                })
            }
            Tok::Sqrt => {
                self.next();
                let arg = self.primary()?;
                Ok(Expr {
                    kind: ExprKind::Sqrt(Box::new(arg)),
                    column: t.column,
                })
            }
            Tok::Ident(name) => {
                self.next();
                if name == "sqrt" {
                    self.expect(Tok::LParen, "'(' after sqrt")?;
                    let arg = self.parenthesised()?;
                    return Ok(Expr {
                        kind: ExprKind::Sqrt(Box::new(arg)),
                        column: t.column,
                    });
                }
                if self.peek().tok == Tok::LParen && !self.peek().space_before && is_function(name)
                {
                    return Err(SyntaxError::NotAllowed {
                        column: t.column,
                        what: format!("the function {name}()"),
                        target: "exact input (only sqrt is known)".into(),
                    });
                }
                let kind = if name == "i" || name == "j" {
                    ExprKind::ImaginaryUnit
                } else {
                    ExprKind::Symbol(name.clone())
                };
                Ok(Expr {
                    kind,
                    column: t.column,
                })
            }
            Tok::LParen => {
                self.next();
                self.parenthesised()
            }
            _ => Err(self.unexpected("a number, a name, '√' or '('")),
        }
    }

    /// The expression after '(' up to and including ')'; whitespace does not separate entries
    /// inside parentheses.
    fn parenthesised(&mut self) -> Result<Expr, SyntaxError> {
        let saved = self.in_matrix;
        self.in_matrix = false;
        self.skip_newlines();
        let e = self.expr()?;
        self.skip_newlines();
        self.in_matrix = saved;
        self.expect(Tok::RParen, "')'")?;
        Ok(e)
    }
}

fn is_function(name: &str) -> bool {
    matches!(
        name,
        "exp" | "log" | "ln" | "sin" | "cos" | "tan" | "abs" | "pow" | "cbrt"
    )
}

/// `123.456e-7` read exactly as a rational.
fn parse_decimal(text: &str, column: usize) -> Result<Rational, SyntaxError> {
    // the common case, a short integer, read as a machine word (19 digits stay below 2⁶⁴)
    if text.len() <= 19 && text.bytes().all(|b| b.is_ascii_digit()) {
        if let Ok(n) = text.parse::<u64>() {
            return Ok(Rational::from_integer(BigInt::from(n)));
        }
    }
    let (mantissa, exponent) = match text.find(['e', 'E']) {
        Some(k) => (&text[..k], &text[k + 1..]),
        None => (text, "0"),
    };
    let exp: i64 = exponent.parse().map_err(|_| SyntaxError::Unexpected {
        column,
        expected: "a decimal exponent".into(),
        found: exponent.into(),
    })?;
    if exp.unsigned_abs() > MAX_EXPONENT as u64 {
        return Err(SyntaxError::TooLarge {
            column,
            what: format!("the decimal exponent in {text}"),
            limit: MAX_EXPONENT as usize,
        });
    }
    let (int_part, frac_part) = mantissa.split_once('.').unwrap_or((mantissa, ""));
    let digits = format!("{int_part}{frac_part}");
    let digits = if digits.is_empty() { "0" } else { &digits };
    let n: BigInt = digits.parse().map_err(|_| SyntaxError::Unexpected {
        column,
        expected: "a number".into(),
        found: text.into(),
    })?;
    let scale = exp - frac_part.len() as i64;
    let ten = BigInt::from(10);
    let r = if scale >= 0 {
        Rational::from(n * num_traits::pow(ten, scale as usize))
    } else {
        Rational::new(n, num_traits::pow(ten, (-scale) as usize))
    };
    Ok(r)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rows(input: &str) -> Vec<usize> {
        parse_matrix_rows(input)
            .unwrap()
            .iter()
            .map(Vec::len)
            .collect()
    }

    #[test]
    fn a_transpose_is_read_and_a_symbol_t_is_not_an_exponent() {
        let e = parse_expression("(A - K C)^T").unwrap();
        assert!(matches!(e.kind, ExprKind::Transpose(_)));
        let e = parse_expression("M^T O_n").unwrap();
        match e.kind {
            ExprKind::Mul(x, _) => assert!(matches!(x.kind, ExprKind::Transpose(_))),
            other => panic!("{other:?}"),
        }
        // only the letter T alone: T2 or a number stay what they were
        assert!(parse_expression("s^T2").is_err());
        assert!(matches!(
            parse_expression("s^2").unwrap().kind,
            ExprKind::Pow(_, 2)
        ));
    }

    #[test]
    fn matlab_whitespace_rules() {
        assert_eq!(rows("[2 -3; 4 -5]"), [2, 2]);
        assert_eq!(rows("[2 - 3 4 -5]"), [3]);
        assert_eq!(rows("[2 -3\n 4 -5]"), [2, 2]);
        assert_eq!(rows("[[2,-3],[4,-5]]"), [2, 2]);
        assert_eq!(rows("[(1 - 2) 3]"), [2]);
        assert_eq!(rows("[-6; -12]"), [1, 1]);
        assert_eq!(rows("-4, -5"), [2]);
        assert_eq!(rows("[2*k1 a]"), [2]);
    }

    #[test]
    fn decimals_are_exact() {
        assert_eq!(parse_decimal("0.125", 1).unwrap().to_string(), "1/8");
        assert_eq!(parse_decimal("1e-3", 1).unwrap().to_string(), "1/1000");
        assert_eq!(parse_decimal("1.1716", 1).unwrap().to_string(), "2929/2500");
        assert_eq!(parse_decimal("2.5E2", 1).unwrap().to_string(), "250");
    }

    #[test]
    fn errors_name_the_column() {
        let e = parse_expression("2 * (s + ").unwrap_err();
        assert_eq!(
            e.to_string(),
            "column 10: expected a number, a name, '√' or '(', found the end of the input"
        );
        let e = parse_expression("exp(2)").unwrap_err();
        assert!(e.to_string().contains("exp()"), "{e}");
        let e = parse_expression("2 $ 3").unwrap_err();
        assert_eq!(e.column(), Some(3));
    }
}
