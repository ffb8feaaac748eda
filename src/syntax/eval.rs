//! Evaluating parsed expressions into the workbench's number types, polynomials and rational
//! functions.

use super::parser::{Expr, ExprKind};
use super::{SyntaxError, MAX_VALUE_BITS};
use crate::algebra::{Field, MultiPoly, One, Quadratic, Rational, Ring, Zero};
use crate::poly::{Poly, RationalFunction};

/// Why a division could not be carried out.
pub enum DivisionRefused {
    /// The divisor is zero.
    ByZero,
    /// The target type cannot divide by this (e.g. a symbolic divisor).
    NotAllowed(String),
}

/// Why a square root is not a value of the target type.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SqrtRefused {
    /// An irrational root, for a type that holds rationals only.
    #[error("the irrational {0}")]
    Irrational(Box<crate::algebra::Quadratic>),
    /// The root of a negative number, for a real type.
    #[error("the square root of the negative number {0}")]
    Negative(Rational),
    /// A radicand beyond the quadratic fields the workbench carries.
    #[error(transparent)]
    Radicand(#[from] crate::algebra::QuadraticError),
}

/// A type an expression can be evaluated into.
pub trait FromExpr: Ring {
    /// What the type is called in error messages ("a rational number").
    const TARGET: &'static str;
    /// The exact number `r`.
    fn from_rational(r: Rational) -> Self;
    /// A named symbol, if the type has symbols.
    fn symbol(_name: &str) -> Option<Self> {
        None
    }
    /// The imaginary unit, if the type has it.
    fn imaginary_unit() -> Option<Self> {
        None
    }
    /// The square root of a rational, or why it is not in the type.
    fn sqrt_of(r: &Rational) -> Result<Self, SqrtRefused>;
    /// `self / divisor`.
    fn divide(&self, divisor: &Self) -> Result<Self, DivisionRefused>;
    /// The quadratic field the value lives in (0: rational), to refuse mixing √2 and √3.
    fn field_tag(&self) -> i64 {
        0
    }
    /// The size of the value in bits (numerators and denominators), to bound what input can
    /// build: `((2^1000)^1000)^1000` is 22 characters.
    fn size_bits(&self) -> u64 {
        0
    }
    /// How many terms the value has (symbolic polynomials; 1 for numbers): a product has up to
    /// the product of the counts, a power `(t terms)^k` up to C(k + t − 1, t − 1).
    fn term_count(&self) -> u64 {
        1
    }
    /// `self^k` (`k ≥ 0`), by squaring unless the type knows better: exact numbers raise the
    /// numerator and the denominator apart, which stay coprime, instead of reducing a fraction
    /// at every squaring (found by fuzzing: a gcd with 1 costs num-bigint's binary gcd
    /// `bits²/64` word operations, and `11110131761244566941^231` spent 5 ms in them).
    fn power_of(self, k: u64) -> Self {
        power(Self::one(), self, k)
    }
    /// What an addition, subtraction, product or quotient of `a` and `b` costs in reduction:
    /// about `(bits of a + bits of b)² / 64` word operations for the exact numbers (their gcds),
    /// 0 for types bounded otherwise (symbolic values count their term products; floats cost
    /// nothing).
    fn reduction_work(_a: &Self, _b: &Self) -> u64 {
        0
    }
    /// Evaluates a whole expression.
    ///
    /// # Errors
    /// [`SyntaxError`] naming the column of the construct that does not fit.
    fn from_expr(e: &Expr) -> Result<Self, SyntaxError> {
        let mut ctx = Context::default();
        scalar(e, &mut ctx)
    }
}

/// Parsing into a type from text, for the types [`FromExpr`] covers (and matrices of them).
pub trait ParseValue: Sized {
    /// Parses `input`.
    ///
    /// # Errors
    /// [`SyntaxError`].
    fn parse_value(input: &str) -> Result<Self, SyntaxError>;
}

impl<T: FromExpr> ParseValue for T {
    fn parse_value(input: &str) -> Result<Self, SyntaxError> {
        super::parse_scalar(input)
    }
}

/// Values substituted for symbols while evaluating (parameters such as `T = 1/8`).
pub type Environment = std::collections::BTreeMap<String, Rational>;

#[derive(Default)]
struct Context<'a> {
    field: Option<(i64, usize)>,
    env: Option<&'a Environment>,
    /// The work of the operations on rational functions (with a denominator that is not a
    /// number) done so far, measured as in [`bound_rf_work`].
    rf_work: u64,
    /// The reduction work of the operations on exact numbers done so far
    /// ([`FromExpr::reduction_work`]), bounded by [`MAX_REDUCTION_WORK`].
    reduction_work: u64,
}

impl Context<'_> {
    /// Charges an operation on `a` and `b` to the expression's reduction work, refusing it
    /// once the total passes [`MAX_REDUCTION_WORK`].
    fn charge<T: FromExpr>(&mut self, a: &T, b: &T, column: usize) -> Result<(), SyntaxError> {
        self.reduction_work = self.reduction_work.saturating_add(T::reduction_work(a, b));
        if self.reduction_work > MAX_REDUCTION_WORK {
            return Err(SyntaxError::TooLarge {
                column,
                what: format!(
                    "arithmetic on large numbers of about {} word operations up to here",
                    self.reduction_work
                ),
                limit: MAX_REDUCTION_WORK as usize,
            });
        }
        Ok(())
    }

    fn note_field(&mut self, tag: i64, column: usize) -> Result<(), SyntaxError> {
        if tag == 0 {
            return Ok(());
        }
        match self.field {
            Some((t, _)) if t != tag => Err(SyntaxError::NotAllowed {
                column,
                what: format!("{} after {}", radical(tag), radical(t)),
                target: "one number (only one quadratic field at a time)".into(),
            }),
            _ => {
                self.field = Some((tag, column));
                Ok(())
            }
        }
    }
}

/// The entries of one matrix or list lie in one quadratic field: `[sqrt(2); i]` would make every
/// later product mix `Q(√2)` with `Q(i)` (found by fuzzing: an answer matrix crashed the
/// checker's characteristic polynomial). `entries` are `(column, value)`.
pub(crate) fn one_field<'a, T: FromExpr + 'a>(
    entries: impl IntoIterator<Item = (usize, &'a T)>,
    target: &str,
) -> Result<(), SyntaxError> {
    let mut first: Option<i64> = None;
    for (column, v) in entries {
        let tag = v.field_tag();
        if tag == 0 {
            continue;
        }
        match first {
            Some(t) if t != tag => {
                return Err(SyntaxError::NotAllowed {
                    column,
                    what: format!("{} after {}", radical(tag), radical(t)),
                    target: format!("{target} (only one quadratic field at a time)"),
                })
            }
            _ => first = Some(tag),
        }
    }
    Ok(())
}

fn radical(tag: i64) -> String {
    if tag == -1 {
        "i".into()
    } else {
        format!("√{tag}")
    }
}

fn unknown_symbol(column: usize, name: &str, target: &str) -> SyntaxError {
    SyntaxError::UnknownSymbol {
        column,
        name: name.into(),
        target: target.into(),
    }
}

fn not_allowed(column: usize, what: impl Into<String>, target: &str) -> SyntaxError {
    SyntaxError::NotAllowed {
        column,
        what: what.into(),
        target: target.into(),
    }
}

/// `base^k` by squaring (`one` is the unit: rational functions carry their variable).
fn power<T: Clone + std::ops::Mul<Output = T>>(one: T, base: T, k: u64) -> T {
    let (mut acc, mut square, mut e) = (one, base, k);
    while e > 0 {
        if e & 1 == 1 {
            acc = acc * square.clone();
        }
        e >>= 1;
        if e > 0 {
            square = square.clone() * square;
        }
    }
    acc
}

fn scalar<T: FromExpr>(e: &Expr, ctx: &mut Context) -> Result<T, SyntaxError> {
    let c = e.column;
    let v = match &e.kind {
        ExprKind::Number(r) => T::from_rational(r.clone()),
        ExprKind::Symbol(name) => match ctx.env.and_then(|e| e.get(name)) {
            Some(v) => T::from_rational(v.clone()),
            None => T::symbol(name).ok_or_else(|| unknown_symbol(c, name, T::TARGET))?,
        },
        ExprKind::ImaginaryUnit => {
            T::imaginary_unit().ok_or_else(|| not_allowed(c, "the imaginary unit i", T::TARGET))?
        }
        ExprKind::Sqrt(arg) => {
            let r = rational_argument(arg)?;
            T::sqrt_of(&r).map_err(|what| not_allowed(c, what.to_string(), T::TARGET))?
        }
        ExprKind::Transpose(_) => return Err(not_allowed(c, "a transpose ^T", T::TARGET)),
        ExprKind::Neg(x) => -scalar::<T>(x, ctx)?,
        ExprKind::Add(x, y) => {
            let (a, b) = (scalar::<T>(x, ctx)?, scalar::<T>(y, ctx)?);
            ctx.charge(&a, &b, c)?;
            a + b
        }
        ExprKind::Sub(x, y) => {
            let (a, b) = (scalar::<T>(x, ctx)?, scalar::<T>(y, ctx)?);
            ctx.charge(&a, &b, c)?;
            a - b
        }
        ExprKind::Mul(x, y) => {
            let (a, b) = (scalar::<T>(x, ctx)?, scalar::<T>(y, ctx)?);
            ctx.charge(&a, &b, c)?;
            let terms = a.term_count().saturating_mul(b.term_count());
            if terms > MAX_TERMS {
                return Err(too_many_terms(c, terms));
            }
            // a product of sums costs one coefficient product per pair of terms, each the
            // dearer the longer the coefficients
            let work = terms.saturating_mul(size_factor(
                words(a.size_bits(), 1),
                words(b.size_bits(), 1),
            ));
            if work > MAX_PRODUCT_WORK {
                return Err(too_much_work(c, work));
            }
            a * b
        }
        ExprKind::Div(x, y) => {
            let (a, b) = (scalar::<T>(x, ctx)?, scalar::<T>(y, ctx)?);
            ctx.charge(&a, &b, c)?;
            divide(&a, &b, c, T::TARGET)?
        }
        ExprKind::Pow(x, k) => {
            let b = scalar::<T>(x, ctx)?;
            let estimate = b.size_bits().saturating_mul(k.unsigned_abs());
            if estimate > MAX_VALUE_BITS {
                return Err(too_large(c, estimate));
            }
            let terms = power_terms(b.term_count(), k.unsigned_abs());
            if terms > MAX_TERMS {
                return Err(too_many_terms(c, terms));
            }
            let work = power_work(b.term_count(), k.unsigned_abs(), b.size_bits());
            if work > MAX_PRODUCT_WORK {
                return Err(too_much_work(c, work));
            }
            let p = b.power_of(k.unsigned_abs());
            if *k < 0 {
                ctx.charge(&T::one(), &p, c)?;
                divide(&T::one(), &p, c, T::TARGET)?
            } else {
                p
            }
        }
    };
    ctx.note_field(v.field_tag(), c)?;
    if v.size_bits() > MAX_VALUE_BITS {
        return Err(too_large(c, v.size_bits()));
    }
    Ok(v)
}

/// The most reduction work ([`FromExpr::reduction_work`]) one expression's arithmetic on exact
/// numbers may cost: four operations on two numbers of [`MAX_VALUE_BITS`] each (a reduction's
/// binary gcd with num-bigint, some milliseconds each), or thousands on numbers of a few
/// hundred bits. Every value is bounded in size, but a chain of operations was not (found by
/// fuzzing: `0/a^231/b^231/…` kept its value 0 through divisions by 15 000-bit numbers).
const MAX_REDUCTION_WORK: u64 = 4 * (2 * MAX_VALUE_BITS) * (2 * MAX_VALUE_BITS) / 64;

/// The most terms a symbolic value read from input may have.
const MAX_TERMS: u64 = 20_000;

/// C(k + t − 1, t − 1), saturating: the terms of a `t`-term sum raised to `k`.
fn power_terms(t: u64, k: u64) -> u64 {
    if t <= 1 {
        return 1;
    }
    let mut c: u64 = 1;
    for i in 1..t {
        c = c.saturating_mul(k + i) / i;
        if c > MAX_TERMS {
            return u64::MAX;
        }
    }
    c
}

/// The most term-by-term coefficient products one operation on input may cost (a product of
/// sums, or all the products of a power by squaring): about a second of symbolic arithmetic.
/// `(s2 + s6 + w + g)^44` has 16 215 terms, under [`MAX_TERMS`], but computing it costs
/// 4 million products. (200 000 until session 11: a fuzz input's power of a sum of ten
/// symbols took 0.4 s in a release build within it; now about a tenth of a second.)
const MAX_PRODUCT_WORK: u64 = 50_000;

/// The 64-bit words of a coefficient of a value of `bits` bits raised to `e` (at most
/// `bits · e` bits), at least 1.
fn words(bits: u64, e: u64) -> u64 {
    bits.saturating_mul(e).div_ceil(64).max(1)
}

/// What one coefficient product costs beside the bookkeeping of a term (about 5 µs for small
/// coefficients in a sum of symbols): a product of `wa`- and `wb`-word numbers, in units of that
/// bookkeeping (4 096 word products).
fn size_factor(wa: u64, wb: u64) -> u64 {
    1 + wa.saturating_mul(wb) / 4096
}

/// The term-by-term products [`power`] performs raising a `t`-term sum of `bits` bits to `k`
/// (square and multiply; term counts bounded by [`power_terms`]), each weighted by the size
/// of the coefficients it multiplies ([`size_factor`]: found by fuzzing,
/// `(s--dir+21.72e-86)^53` did 170 000 products of coefficients of up to 16 000 bits, 1.3 s),
/// saturating.
fn power_work(t: u64, k: u64, bits: u64) -> u64 {
    let (mut acc, mut square, mut e) = (0_u64, 1_u64, k);
    let mut work: u64 = 0;
    let products = |x: u64, y: u64| {
        power_terms(t, x)
            .saturating_mul(power_terms(t, y))
            .saturating_mul(size_factor(words(bits, x), words(bits, y)))
    };
    while e > 0 {
        if e & 1 == 1 {
            if acc > 0 {
                work = work.saturating_add(products(acc, square));
            }
            acc += square;
        }
        e >>= 1;
        if e > 0 {
            work = work.saturating_add(products(square, square));
            square = square.saturating_mul(2);
        }
    }
    work
}

fn too_much_work(column: usize, products: u64) -> SyntaxError {
    SyntaxError::TooLarge {
        column,
        what: format!("symbolic arithmetic of about {products} coefficient products here"),
        limit: MAX_PRODUCT_WORK as usize,
    }
}

fn too_many_terms(column: usize, terms: u64) -> SyntaxError {
    SyntaxError::TooLarge {
        column,
        what: format!("a symbolic expression of up to {terms} terms built here"),
        limit: MAX_TERMS as usize,
    }
}

fn too_large(column: usize, bits: u64) -> SyntaxError {
    SyntaxError::TooLarge {
        column,
        what: format!("a value of about {bits} bits built here"),
        limit: MAX_VALUE_BITS as usize,
    }
}

fn divide<T: FromExpr>(a: &T, b: &T, column: usize, target: &str) -> Result<T, SyntaxError> {
    a.divide(b).map_err(|e| match e {
        DivisionRefused::ByZero => SyntaxError::DivisionByZero { column },
        DivisionRefused::NotAllowed(what) => not_allowed(column, what, target),
    })
}

/// The argument of a square root must be an exact rational.
fn rational_argument(arg: &Expr) -> Result<Rational, SyntaxError> {
    Rational::from_expr(arg).map_err(|e| match e {
        SyntaxError::NotAllowed { column, what, .. } => not_allowed(
            column,
            what,
            "a square root's argument (it must be a rational number)",
        ),
        // a square root's argument is read without the symbols' values: no value can help
        SyntaxError::UnknownSymbol { column, name, .. } => not_allowed(
            column,
            format!("the symbol '{name}'"),
            "a square root's argument (it must be a rational number)",
        ),
        other => other,
    })
}

/// Evaluates into a rational function of `var` over `F`.
pub(crate) fn rational_function<F: Field + FromExpr>(
    e: &Expr,
    var: &str,
) -> Result<RationalFunction<F>, SyntaxError> {
    rational_function_with(e, var, None)
}

/// Evaluates into a rational function of `var` over `F`, other symbols taken from `env`.
///
/// # Errors
/// [`SyntaxError`] naming the column of a symbol without a value or a division by zero.
pub fn rational_function_with<F: Field + FromExpr>(
    e: &Expr,
    var: &str,
    env: Option<&Environment>,
) -> Result<RationalFunction<F>, SyntaxError> {
    let mut ctx = Context {
        env,
        ..Context::default()
    };
    rf(e, var, &mut ctx)
}

/// Evaluates a scalar with symbols taken from `env` (symbols not in `env` stay symbols when the
/// type has them).
///
/// # Errors
/// [`SyntaxError`] naming the column.
pub fn evaluate_with<T: FromExpr>(e: &Expr, env: &Environment) -> Result<T, SyntaxError> {
    let mut ctx = Context {
        env: Some(env),
        ..Context::default()
    };
    scalar(e, &mut ctx)
}

/// Evaluates into a polynomial in `var` over `F`.
pub(crate) fn polynomial<F: Field + FromExpr>(e: &Expr, var: &str) -> Result<Poly<F>, SyntaxError> {
    let r = rational_function::<F>(e, var)?;
    if r.denominator().degree() == Some(0) {
        Ok(r.numerator().clone())
    } else {
        Err(not_allowed(
            e.column,
            format!("a division by the polynomial {}", r.denominator()),
            &format!("a polynomial in {var}"),
        ))
    }
}

/// Whether the expression contains the variable.
fn mentions(e: &Expr, var: &str) -> bool {
    match &e.kind {
        ExprKind::Symbol(name) => name == var,
        ExprKind::Number(_) | ExprKind::ImaginaryUnit => false,
        ExprKind::Sqrt(x) | ExprKind::Neg(x) | ExprKind::Pow(x, _) | ExprKind::Transpose(x) => {
            mentions(x, var)
        }
        ExprKind::Add(x, y) | ExprKind::Sub(x, y) | ExprKind::Mul(x, y) | ExprKind::Div(x, y) => {
            mentions(x, var) || mentions(y, var)
        }
    }
}

fn deg<F: Field>(p: &Poly<F>) -> usize {
    p.degree().unwrap_or(0)
}

/// The larger degree of numerator and denominator.
fn degree<F: Field>(r: &RationalFunction<F>) -> usize {
    r.numerator()
        .degree()
        .unwrap_or(0)
        .max(r.denominator().degree().unwrap_or(0))
}

/// Polynomials and rational functions read from input stay within degree
/// [`MAX_EXACT_ORDER`](crate::linalg::MAX_EXACT_ORDER), the largest system the exact algorithms
/// accept: `s^999 s^999 …` would otherwise grow with the length of the input, and sums over
/// high-degree denominators cost polynomial gcds of that degree (found by fuzzing).
fn bound_degree(column: usize, degree: usize) -> Result<(), SyntaxError> {
    let limit = crate::linalg::MAX_EXACT_ORDER;
    if degree > limit {
        return Err(SyntaxError::TooLarge {
            column,
            what: format!("a polynomial of degree {degree} built here"),
            limit,
        });
    }
    Ok(())
}

/// The most work one operation on transfer functions read from input may cost, measured as
/// the degree of the result times the bits of all the operands' coefficients: reducing the
/// result to lowest terms is a polynomial gcd, whose cost grows with both (over `Q(√d)` the
/// Euclidean remainders swell). Transfer functions a person types stay far below it (degree
/// 10 with 60-bit coefficients: about 12 000).
const MAX_RF_WORK: u64 = 50_000;

/// Every coefficient of numerator and denominator.
fn coefficients<F: Field>(r: &RationalFunction<F>) -> impl Iterator<Item = &F> {
    r.numerator()
        .coeffs()
        .iter()
        .chain(r.denominator().coeffs())
}

/// Whether a coefficient lies outside Q (in Q(√d), d ≠ 1).
fn irrational<F: Field + FromExpr>(r: &RationalFunction<F>) -> bool {
    coefficients(r).any(|c| c.field_tag() != 0)
}

/// The most bits a power of a polynomial read from input may hold, all coefficients together
/// (degree 100 with 2 000-bit coefficients).
const MAX_POWER_BITS: u64 = 200_000;

/// A power of a transfer function multiplies the size of its coefficients by the exponent: the
/// largest coefficient of the base times the exponent stays within
/// [`MAX_VALUE_BITS`], the bound on any number built while reading (found by fuzzing:
/// `(33848^-845 - s + 263 - 12)^111` built coefficients of 1.4 million bits).
fn bound_rf_power<F: Field + FromExpr>(
    column: usize,
    base: &RationalFunction<F>,
    exponent: u64,
) -> Result<(), SyntaxError> {
    let largest = coefficients(base)
        .map(FromExpr::size_bits)
        .max()
        .unwrap_or(0);
    let estimate = largest.saturating_mul(exponent);
    if estimate > MAX_VALUE_BITS {
        return Err(too_large(column, estimate));
    }
    // all the coefficients together: the last squaring multiplies every pair of them (found by
    // fuzzing: `(26^19 s + 25^21)^110`, 111 coefficients of 11 000 bits, took a second)
    let degree = (degree(base) as u64).saturating_mul(exponent);
    let total = degree.saturating_add(1).saturating_mul(estimate);
    if total > MAX_POWER_BITS {
        return Err(SyntaxError::TooLarge {
            column,
            what: format!(
                "a power of degree {degree} with coefficients of about {estimate} bits built here"
            ),
            limit: MAX_POWER_BITS as usize,
        });
    }
    // Over Q(√d) with irrational coefficients every coefficient operation reduces fractions:
    // the last squaring, with the work measure of a product (degree × coefficient bits), stays
    // within the irrational budget (found by fuzzing: `(s + i − 2)^184` took 2 s)
    if irrational(base) {
        let work = degree
            .saturating_mul(degree / 2 + 1)
            .saturating_mul(estimate);
        if work > MAX_RF_WORK / 10 {
            return Err(SyntaxError::TooLarge {
                column,
                what: format!(
                    "a power of degree {degree} with irrational coefficients of about {estimate} bits built here"
                ),
                limit: (MAX_RF_WORK / 10) as usize,
            });
        }
    }
    Ok(())
}

/// The most work all the operations on rational functions of one expression may cost
/// together (each within [`MAX_RF_WORK`]): a chain of sums over high-degree denominators, each
/// within the bound, otherwise adds up (found by fuzzing: `s + 22E-220 s^-24 − 219 s^-23 + …`,
/// thirty sums each reduced by a polynomial gcd of degree 24 with 700-bit coefficients, took 0.2
/// s in a release build and a second with debug assertions). Operations on polynomials (both
/// denominators numbers) need no gcd and are not counted.
const MAX_RF_TOTAL_WORK: u64 = 2 * MAX_RF_WORK;

/// A power of a fraction with a nonconstant denominator reduces its products by polynomial
/// gcds: it counts towards the expression's [`MAX_RF_TOTAL_WORK`] as the degree of the result
/// times the bits of all its coefficients (found by fuzzing: the cube of a degree-24 fraction
/// with 700-bit coefficients, inside a quotient, took 8 s with debug assertions).
fn bound_rf_power_work<F: Field + FromExpr>(
    column: usize,
    base: &RationalFunction<F>,
    exponent: u64,
    ctx: &mut Context,
) -> Result<(), SyntaxError> {
    if base.denominator().degree().is_none_or(|d| d == 0) {
        return Ok(());
    }
    let largest = coefficients(base)
        .map(FromExpr::size_bits)
        .max()
        .unwrap_or(0);
    let degree = (degree(base) as u64).saturating_mul(exponent);
    let bits = degree
        .saturating_add(1)
        .saturating_mul(largest.saturating_mul(exponent));
    ctx.rf_work = ctx.rf_work.saturating_add(degree.saturating_mul(bits));
    if ctx.rf_work > MAX_RF_TOTAL_WORK {
        return Err(SyntaxError::TooLarge {
            column,
            what: format!(
                "transfer-function arithmetic of about {} units of work (degree × coefficient bits, summed over the operations) up to here",
                ctx.rf_work
            ),
            limit: MAX_RF_TOTAL_WORK as usize,
        });
    }
    Ok(())
}

fn bound_rf_work<F: Field + FromExpr>(
    column: usize,
    a: &RationalFunction<F>,
    b: &RationalFunction<F>,
    ctx: &mut Context,
) -> Result<(), SyntaxError> {
    let bits = |r: &RationalFunction<F>| -> u64 { coefficients(r).map(FromExpr::size_bits).sum() };
    // over Q(√d) with irrational coefficients the gcd is Euclid's, its remainders swelling:
    // a tenth of the budget (a Butterworth filter with √2 uses well under a thousand)
    let limit = if irrational(a) || irrational(b) {
        MAX_RF_WORK / 10
    } else {
        MAX_RF_WORK
    };
    let degree = (degree(a) + degree(b)) as u64;
    let work = degree.saturating_mul(bits(a) + bits(b));
    if work > limit {
        return Err(SyntaxError::TooLarge {
            column,
            what: format!(
                "a transfer function of degree {degree} with {} bits of coefficients built here",
                bits(a) + bits(b)
            ),
            limit: limit as usize,
        });
    }
    let fraction = |r: &RationalFunction<F>| r.denominator().degree().is_some_and(|d| d > 0);
    if fraction(a) || fraction(b) {
        ctx.rf_work = ctx.rf_work.saturating_add(work);
        let total_limit = if limit < MAX_RF_WORK {
            MAX_RF_TOTAL_WORK / 10
        } else {
            MAX_RF_TOTAL_WORK
        };
        if ctx.rf_work > total_limit {
            return Err(SyntaxError::TooLarge {
                column,
                what: format!(
                    "transfer-function arithmetic of about {} units of work (degree × coefficient bits, summed over the operations) up to here",
                    ctx.rf_work
                ),
                limit: total_limit as usize,
            });
        }
    }
    Ok(())
}

fn rf<F: Field + FromExpr>(
    e: &Expr,
    var: &str,
    ctx: &mut Context,
) -> Result<RationalFunction<F>, SyntaxError> {
    let c = e.column;
    let constant = |v: F| RationalFunction::from_poly(Poly::constant(v, var));
    // a part without the variable is a number: evaluated with the number limits
    if !mentions(e, var) && !matches!(e.kind, ExprKind::Symbol(_)) {
        return Ok(constant(scalar::<F>(e, ctx)?));
    }
    Ok(match &e.kind {
        ExprKind::Symbol(name) if name == var => RationalFunction::from_poly(Poly::x(var)),
        ExprKind::Symbol(name) if ctx.env.is_some_and(|e| e.contains_key(name)) => {
            constant(scalar::<F>(e, ctx)?)
        }
        ExprKind::Symbol(name) => {
            return Err(unknown_symbol(c, name, &format!("a function of {var}")))
        }
        ExprKind::Number(_)
        | ExprKind::ImaginaryUnit
        | ExprKind::Sqrt(_)
        | ExprKind::Transpose(_) => constant(scalar::<F>(e, ctx)?),
        ExprKind::Neg(x) => -rf(x, var, ctx)?,
        ExprKind::Add(x, y) | ExprKind::Sub(x, y) => {
            let (a, b) = (rf::<F>(x, var, ctx)?, rf::<F>(y, var, ctx)?);
            // a sum over the product of the denominators
            let (na, da) = (deg(a.numerator()), deg(a.denominator()));
            let (nb, db) = (deg(b.numerator()), deg(b.denominator()));
            bound_degree(c, (na + db).max(nb + da).max(da + db))?;
            bound_rf_work(c, &a, &b, ctx)?;
            if matches!(e.kind, ExprKind::Add(..)) {
                a + b
            } else {
                a - b
            }
        }
        ExprKind::Mul(x, y) => {
            let (a, b) = (rf::<F>(x, var, ctx)?, rf::<F>(y, var, ctx)?);
            bound_degree(c, degree(&a) + degree(&b))?;
            bound_rf_work(c, &a, &b, ctx)?;
            a * b
        }
        ExprKind::Div(x, y) => {
            let (a, b) = (rf::<F>(x, var, ctx)?, rf::<F>(y, var, ctx)?);
            bound_degree(c, degree(&a) + degree(&b))?;
            bound_rf_work(c, &a, &b, ctx)?;
            a.checked_div(&b)
                .ok_or(SyntaxError::DivisionByZero { column: c })?
        }
        ExprKind::Pow(x, k) => {
            let b = rf::<F>(x, var, ctx)?;
            bound_degree(c, degree(&b).saturating_mul(k.unsigned_abs() as usize))?;
            bound_rf_power(c, &b, k.unsigned_abs())?;
            bound_rf_power_work(c, &b, k.unsigned_abs(), ctx)?;
            let p = power(constant(F::one()), b, k.unsigned_abs());
            if *k < 0 {
                p.inverse()
                    .ok_or(SyntaxError::DivisionByZero { column: c })?
            } else {
                p
            }
        }
    })
}

impl FromExpr for Rational {
    fn size_bits(&self) -> u64 {
        self.numer().bits() + self.denom().bits()
    }
    const TARGET: &'static str = "a rational number";
    fn from_rational(r: Rational) -> Self {
        r
    }
    fn sqrt_of(r: &Rational) -> Result<Self, SqrtRefused> {
        let q = Quadratic::sqrt_of_rational(r)?;
        match q.as_rational() {
            Some(x) => Ok(x.clone()),
            None => Err(SqrtRefused::Irrational(Box::new(q))),
        }
    }
    fn divide(&self, divisor: &Self) -> Result<Self, DivisionRefused> {
        if divisor.is_zero() {
            return Err(DivisionRefused::ByZero);
        }
        // `8/50` as typed: two machine-word integers reduced by one word gcd
        if let (true, true, Some(n), Some(d)) = (
            self.is_integer(),
            divisor.is_integer(),
            num_traits::ToPrimitive::to_i64(self.numer()),
            num_traits::ToPrimitive::to_i64(divisor.numer()),
        ) {
            return Ok(crate::algebra::small_ratio(i128::from(n), i128::from(d)));
        }
        Ok(crate::algebra::gcd::mul(self, &divisor.recip()))
    }
    fn power_of(self, k: u64) -> Self {
        rational_power(self, k)
    }
    fn reduction_work(a: &Self, b: &Self) -> u64 {
        let bits = a.size_bits().saturating_add(b.size_bits());
        bits.saturating_mul(bits) / 64
    }
}

/// `r^k` with the numerator and the denominator raised apart (coprime powers of coprime
/// numbers: nothing to reduce).
fn rational_power(r: Rational, k: u64) -> Rational {
    match u32::try_from(k) {
        Ok(k) => {
            let (n, d) = r.into_raw();
            Rational::new_raw(n.pow(k), d.pow(k))
        }
        Err(_) => power(<Rational as One>::one(), r, k),
    }
}

impl FromExpr for Quadratic {
    fn size_bits(&self) -> u64 {
        let bits = |r: &Rational| r.numer().bits() + r.denom().bits();
        bits(self.rational_part()) + bits(self.radical_part())
    }
    const TARGET: &'static str = "an exact number";
    fn from_rational(r: Rational) -> Self {
        Quadratic::rational(r)
    }
    fn imaginary_unit() -> Option<Self> {
        Some(Quadratic::imaginary_unit())
    }
    fn sqrt_of(r: &Rational) -> Result<Self, SqrtRefused> {
        Ok(Quadratic::sqrt_of_rational(r)?)
    }
    fn divide(&self, divisor: &Self) -> Result<Self, DivisionRefused> {
        self.checked_div(divisor).ok_or(DivisionRefused::ByZero)
    }
    fn field_tag(&self) -> i64 {
        self.radicand()
    }
    fn power_of(self, k: u64) -> Self {
        match self.as_rational() {
            Some(r) => Quadratic::rational(rational_power(r.clone(), k)),
            None => power(<Quadratic as One>::one(), self, k),
        }
    }
    fn reduction_work(a: &Self, b: &Self) -> u64 {
        // a product in Q(√d) is four rational products and two sums
        let bits = a.size_bits().saturating_add(b.size_bits());
        bits.saturating_mul(bits) / 16
    }
}

impl FromExpr for MultiPoly {
    fn term_count(&self) -> u64 {
        self.terms().count() as u64
    }
    fn size_bits(&self) -> u64 {
        self.terms()
            .map(|(m, c)| c.numer().bits() + c.denom().bits() + u64::from(m.degree()))
            .sum()
    }
    const TARGET: &'static str = "a polynomial with rational coefficients";
    fn power_of(self, k: u64) -> Self {
        match self.as_constant() {
            Some(c) => MultiPoly::constant(rational_power(c, k)),
            None => power(<MultiPoly as One>::one(), self, k),
        }
    }
    fn reduction_work(a: &Self, b: &Self) -> u64 {
        // numbers only: products of sums count their term products instead
        match (a.as_constant(), b.as_constant()) {
            (Some(x), Some(y)) => Rational::reduction_work(&x, &y),
            _ => 0,
        }
    }
    fn from_rational(r: Rational) -> Self {
        MultiPoly::constant(r)
    }
    fn symbol(name: &str) -> Option<Self> {
        Some(MultiPoly::var(name))
    }
    fn sqrt_of(r: &Rational) -> Result<Self, SqrtRefused> {
        Rational::sqrt_of(r).map(MultiPoly::constant)
    }
    fn divide(&self, divisor: &Self) -> Result<Self, DivisionRefused> {
        match divisor.as_constant() {
            Some(c) if c.is_zero() => Err(DivisionRefused::ByZero),
            Some(c) => Ok(self.clone() * MultiPoly::constant(c.recip())),
            None => match self.divide_exact_within(divisor, MAX_PRODUCT_WORK) {
                Ok(Some(q)) => Ok(q),
                Ok(None) => Err(DivisionRefused::NotAllowed(format!(
                    "a division by {}",
                    shortened(&divisor.to_string())
                ))),
                // found by fuzzing: (s^222 + 74)/(2s + u22 + 20) by long division
                Err(e) => Err(DivisionRefused::NotAllowed(format!(
                    "a division by {} costing over {} term operations",
                    shortened(&divisor.to_string()),
                    e.budget
                ))),
            },
        }
    }
}

impl FromExpr for f64 {
    const TARGET: &'static str = "a float";
    fn from_rational(r: Rational) -> Self {
        crate::algebra::rational_to_f64(&r)
    }
    fn sqrt_of(r: &Rational) -> Result<Self, SqrtRefused> {
        let x = crate::algebra::rational_to_f64(r);
        if x < 0.0 {
            Err(SqrtRefused::Negative(r.clone()))
        } else {
            Ok(x.sqrt())
        }
    }
    fn divide(&self, divisor: &Self) -> Result<Self, DivisionRefused> {
        if *divisor == 0.0 {
            Err(DivisionRefused::ByZero)
        } else {
            Ok(self / divisor)
        }
    }
}

impl FromExpr for crate::algebra::Fraction {
    const TARGET: &'static str = "a rational function of the symbols";
    fn power_of(self, k: u64) -> Self {
        match fraction_constant(&self) {
            Some(c) => crate::algebra::Fraction::constant(rational_power(c, k)),
            None => power(<Self as One>::one(), self, k),
        }
    }
    fn reduction_work(a: &Self, b: &Self) -> u64 {
        // numbers only: rational functions are bounded by the symbolic meter
        match (fraction_constant(a), fraction_constant(b)) {
            (Some(x), Some(y)) => Rational::reduction_work(&x, &y),
            _ => 0,
        }
    }
    fn from_rational(r: Rational) -> Self {
        crate::algebra::Fraction::of(MultiPoly::constant(r))
    }
    fn symbol(name: &str) -> Option<Self> {
        Some(crate::algebra::Fraction::symbol(name))
    }
    fn imaginary_unit() -> Option<Self> {
        Some(crate::algebra::Fraction::quadratic(
            &Quadratic::imaginary_unit(),
        ))
    }
    fn sqrt_of(r: &Rational) -> Result<Self, SqrtRefused> {
        Ok(crate::algebra::Fraction::quadratic(
            &Quadratic::sqrt_of_rational(r)?,
        ))
    }
    fn divide(&self, divisor: &Self) -> Result<Self, DivisionRefused> {
        self.checked_div(divisor).ok_or(DivisionRefused::ByZero)
    }
    fn size_bits(&self) -> u64 {
        self.num.size_bits() + self.den.size_bits()
    }
    fn term_count(&self) -> u64 {
        self.num.term_count().max(self.den.term_count())
    }
}

/// A value as an error message shows it: at most 80 characters (a divisor of thousands of
/// terms is named by its beginning; rendering all of it cost a tenth of a fuzz input's time).
fn shortened(text: &str) -> String {
    match text.char_indices().nth(80) {
        Some((at, _)) => format!("{} …", &text[..at]),
        None => text.to_string(),
    }
}

/// The number a rational function is, if it is one.
fn fraction_constant(f: &crate::algebra::Fraction) -> Option<Rational> {
    let (n, d) = (f.numerator().as_constant()?, f.denominator().as_constant()?);
    n.checked_div(&d)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::syntax::{
        parse_list, parse_matrix, parse_polynomial, parse_rational_function, parse_scalar,
    };

    #[test]
    fn numbers_in_every_spelling() {
        let r = |s: &str| parse_scalar::<Rational>(s).unwrap().to_string();
        assert_eq!(r("-7/3"), "-7/3");
        assert_eq!(r("0.125"), "1/8");
        assert_eq!(r("1e-3"), "1/1000");
        assert_eq!(r("2^-2"), "1/4");
        assert_eq!(r("sqrt(9/4)"), "3/2");
        let q = |s: &str| parse_scalar::<Quadratic>(s).unwrap().to_string();
        assert_eq!(q("sqrt(2)/2"), "√2/2");
        assert_eq!(q("√2 − 2"), "√2 − 2");
        assert_eq!(q("-1+2i"), "-1 + 2i");
        assert_eq!(q("1/(1 + sqrt(2))"), "√2 − 1");
    }

    #[test]
    fn mixing_square_roots_is_refused() {
        let e = parse_scalar::<Quadratic>("sqrt(2) + sqrt(3)").unwrap_err();
        assert_eq!(
            e.to_string(),
            "column 11: √3 after √2 is not allowed in one number (only one quadratic field at a time)"
        );
        let e = parse_polynomial::<Quadratic>("sqrt(2) s + sqrt(3)", "s").unwrap_err();
        assert!(matches!(e, SyntaxError::NotAllowed { .. }));
    }

    #[test]
    fn division_by_zero_names_the_column() {
        let e = parse_scalar::<Rational>("1/(2 - 2)").unwrap_err();
        assert_eq!(e, SyntaxError::DivisionByZero { column: 2 });
    }

    #[test]
    fn powers_of_numbers_are_exact_and_cheap() {
        let r = |s: &str| parse_scalar::<Rational>(s).unwrap().to_string();
        assert_eq!(r("(-3/4)^7"), "-2187/16384");
        assert_eq!(r("(6/4)^-3"), "8/27");
        assert_eq!(r("0^0"), "1");
        let q = |s: &str| parse_scalar::<Quadratic>(s).unwrap().to_string();
        assert_eq!(q("(2/3)^3 + sqrt(2)"), q("8/27 + sqrt(2)"));
        let p = |s: &str| parse_scalar::<MultiPoly>(s).unwrap().to_string();
        assert_eq!(p("(1/2)^10 * k"), p("k/1024"));
    }

    #[test]
    fn arithmetic_on_large_numbers_is_bounded_as_a_whole() {
        // each quotient keeps the value 0 and within the size bound; together they are refused
        let big = "11110131761244566941^231";
        let chain = format!("0{}", format!("/{big}").repeat(40));
        let e = parse_scalar::<Rational>(&chain).unwrap_err().to_string();
        assert!(e.contains("arithmetic on large numbers"), "{e}");
        assert!(parse_scalar::<Rational>(&format!("0/{big}/{big}")).is_ok());
        // a person's numbers are far below it: a thousand operations on 30-digit decimals
        let decimal = format!("1.{}", "3".repeat(30));
        let sum = vec![decimal; 1000].join(" + ");
        assert!(parse_scalar::<Rational>(&sum).is_ok());
    }

    #[test]
    fn symbolic_matrices_and_lists() {
        let m = parse_matrix::<MultiPoly>("[-k1 1; -k2 0]").unwrap();
        assert_eq!(m.to_input(), "[-k1, 1; -k2, 0]");
        let poles = parse_list::<Quadratic>("-1+2i, -1-2i, -3").unwrap();
        assert_eq!(poles.len(), 3);
        let e = parse_matrix::<Rational>("[1 k]").unwrap_err();
        assert_eq!(
            e.to_string(),
            "column 4: the symbol 'k' is not allowed in a rational number"
        );
    }

    #[test]
    fn transfer_functions_reduce() {
        let g =
            parse_rational_function::<Rational>("-108 (s + 7/3)/(s^2 + 15 s + 74)", "s").unwrap();
        assert_eq!(g.to_string(), "(-108s − 252)/(s^2 + 15s + 74)");
        let p = parse_polynomial::<Rational>("s^2 + 9s + 20", "s").unwrap();
        assert_eq!(p.to_input(), "s^2 + 9*s + 20");
    }
}
