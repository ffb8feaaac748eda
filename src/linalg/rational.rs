//! Fraction-free kernels over the rationals: integer matrices with one denominator per row or
//! column, normalised once per result entry.
//!
//! A product of rational matrices done entry by entry with `Ratio` arithmetic reduces every
//! partial sum by a gcd — n of them per entry, each as slow as the numbers are long. Here the
//! left factor's rows and the right factor's columns are scaled to integers by the lcm of their
//! denominators, the product runs on integers, and each entry becomes a reduced fraction once
//! ([`crate::algebra::fraction`], Lehmer's gcd). The same idea gives `P(A)·v` by Horner on
//! integers: with `Ã = dA`, `v = y/δ` and `Q(s) = f·dⁿ·P(s/d)` integral,
//! `P(A)·v = Q(Ã)·y / (f·dⁿ·δ)`.
//!
//! [`super::Matrix`]'s arithmetic dispatches here for `Matrix<Rational>`, so every exact
//! computation on rationals takes this path; the results are the same numbers.

use super::Matrix;
use crate::algebra::{fraction, BigInt, Rational};
use crate::poly::Poly;
use num_traits::{One, ToPrimitive, Zero};

/// Integers scaled from rationals, kept as `i64` when every entry fits (scalar products are then
/// one limb times a big number).
enum Scaled {
    Small(Vec<i64>),
    Big(Vec<BigInt>),
}

impl Scaled {
    fn new(values: Vec<BigInt>) -> Self {
        match values.iter().map(ToPrimitive::to_i64).collect() {
            Some(small) => Scaled::Small(small),
            None => Scaled::Big(values),
        }
    }
    /// `acc += self[i] · x`.
    #[inline]
    fn mul_add(&self, i: usize, x: &BigInt, acc: &mut BigInt) {
        match self {
            Scaled::Small(v) => match v[i] {
                0 => {}
                1 => *acc += x,
                -1 => *acc -= x,
                s => *acc += x * s,
            },
            Scaled::Big(v) => {
                if !v[i].is_zero() {
                    *acc += x * &v[i];
                }
            }
        }
    }
}

use crate::algebra::gcd::integer_numerators as scale;

/// `a · b` (shapes checked by the caller).
pub(crate) fn mul(a: &Matrix<Rational>, b: &Matrix<Rational>) -> Matrix<Rational> {
    let (n, k, m) = (a.rows(), a.cols(), b.cols());
    if k == 1 {
        // an outer product (a single output's L·C, L·A₁₂): each entry one product of reduced
        // fractions, reduced by cross-cancellation — gcd(n₁, d₂)·gcd(n₂, d₁), where one side is
        // usually a small entry of the plant — instead of a gcd of the full numerator and
        // denominator
        return Matrix::from_fn(n, m, |i, j| {
            crate::algebra::gcd::mul(a.get(i, 0), b.get(0, j))
        });
    }
    // rows of a and columns of b, each scaled to integers
    let rows: Vec<(Vec<BigInt>, BigInt)> = (0..n).map(|i| scale(a.row(i))).collect();
    let cols: Vec<(Vec<BigInt>, BigInt)> = (0..m).map(|j| scale(&b.col(j))).collect();
    let cols: Vec<(Scaled, BigInt)> = cols.into_iter().map(|(v, d)| (Scaled::new(v), d)).collect();
    Matrix::from_fn(n, m, |i, j| {
        let (row, dr) = &rows[i];
        let (col, dc) = &cols[j];
        let mut acc = BigInt::zero();
        for t in 0..k {
            if !row[t].is_zero() {
                col.mul_add(t, &row[t], &mut acc);
            }
        }
        fraction(acc, dr * dc)
    })
}

/// `a · b` over one denominator, not reduced: `(M, δ)` with `a·b = M/δ` (row-major), δ the
/// product of the lcms of a's and b's denominators. For a caller that goes on computing on
/// integers (the rank-one check's sums, `O_n K`), where [`mul`] would reduce every entry only
/// for it to be scaled back to one denominator (shapes checked by the caller).
pub(crate) fn mul_over_one_denominator(
    a: &Matrix<Rational>,
    b: &Matrix<Rational>,
) -> (Vec<BigInt>, BigInt) {
    let (n, k, m) = (a.rows(), a.cols(), b.cols());
    let (a_int, da) = scale(a.entries());
    let a_int = Scaled::new(a_int);
    let (b_int, db) = scale(b.entries());
    let mut product = Vec::with_capacity(n * m);
    for i in 0..n {
        for j in 0..m {
            let mut acc = BigInt::zero();
            for t in 0..k {
                if !b_int[t * m + j].is_zero() {
                    a_int.mul_add(i * k + t, &b_int[t * m + j], &mut acc);
                }
            }
            product.push(acc);
        }
    }
    (product, da * db)
}

/// `x ± y` for one entry, reduced once.
fn add_entry(x: &Rational, y: &Rational, negate: bool) -> Rational {
    let y_num = if negate {
        -y.numer().clone()
    } else {
        y.numer().clone()
    };
    if x.denom().is_one() && y.denom().is_one() {
        return Rational::from_integer(x.numer() + y_num);
    }
    if x.denom() == y.denom() {
        return fraction(x.numer() + y_num, x.denom().clone());
    }
    // an integer plus a reduced fraction n/d is (integer·d + n)/d, reduced already:
    // gcd(integer·d + n, d) = gcd(n, d) = 1
    if x.denom().is_one() {
        return Rational::new_raw(x.numer() * y.denom() + y_num, y.denom().clone());
    }
    if y.denom().is_one() {
        return Rational::new_raw(x.numer() + y_num * x.denom(), x.denom().clone());
    }
    fraction(
        x.numer() * y.denom() + y_num * x.denom(),
        x.denom() * y.denom(),
    )
}

/// `a + b` or `a − b` (shapes checked by the caller).
pub(crate) fn add(a: &Matrix<Rational>, b: &Matrix<Rational>, negate: bool) -> Matrix<Rational> {
    Matrix::from_fn(a.rows(), a.cols(), |i, j| {
        add_entry(a.get(i, j), b.get(i, j), negate)
    })
}

/// `P(A)·V` by Horner on integers (shapes checked by the caller).
pub(crate) fn polynomial_times_vector(
    p: &Poly<Rational>,
    a: &Matrix<Rational>,
    v: &Matrix<Rational>,
) -> Matrix<Rational> {
    // V = Y/δ
    let (y, delta) = scale(v.entries());
    polynomial_times_integers(p, a, &y, &delta, v.cols())
}

/// `P(A)·V` by Horner on integers for `V = Y/δ` given over one denominator (`Y` row-major with
/// `k` columns, `δ ≠ 0` of either sign, `Y/δ` not necessarily reduced): each entry of the
/// result is reduced once, at the end.
pub(crate) fn polynomial_times_integers(
    p: &Poly<Rational>,
    a: &Matrix<Rational>,
    y: &[BigInt],
    delta: &BigInt,
    k: usize,
) -> Matrix<Rational> {
    let n = a.rows();
    let deg = p.coeffs().len().saturating_sub(1);
    // Ã = dA
    let (a_int, d) = scale(a.entries());
    let a_int = Scaled::new(a_int);
    // Q(s) = f·d^deg·P(s/d): coefficient j is f·p_j·d^(deg−j)
    let mut dpow = BigInt::one();
    let mut scaled = vec![Rational::zero(); deg + 1];
    for j in (0..=deg).rev() {
        // (Lehmer's cross-cancellation; a product of integers, the usual case, multiplies only)
        scaled[j] = crate::algebra::gcd::mul(&p.coeff(j), &Rational::from_integer(dpow.clone()));
        dpow *= &d;
    }
    let (q, f) = scale(&scaled);
    let words = match &a_int {
        Scaled::Small(words) => super::limbs::horner(words, n, &q, y, k),
        Scaled::Big(_) => None,
    };
    let acc = words.unwrap_or_else(|| horner_on_bigints(&a_int, n, &q, y, k));
    // divide by f·d^deg·δ (dpow is d^(deg+1) now)
    let denominator = f * (dpow / &d) * delta;
    let mut entries = acc.into_iter();
    Matrix::from_fn(n, k, |_, _| {
        fraction(entries.next().unwrap_or_default(), denominator.clone())
    })
}

/// `Q(Ã)·Y` on num-bigint, one allocated product per term: the path for plants whose scaled
/// entries are not small machine words (the others take the limb kernel, `linalg/limbs.rs`).
fn horner_on_bigints(
    a_int: &Scaled,
    n: usize,
    q: &[BigInt],
    y: &[BigInt],
    k: usize,
) -> Vec<BigInt> {
    let mut acc = vec![BigInt::zero(); n * k];
    for qj in q.iter().rev() {
        let mut next = vec![BigInt::zero(); n * k];
        for i in 0..n {
            for t in 0..n {
                for c in 0..k {
                    let x = &acc[t * k + c];
                    if !x.is_zero() {
                        a_int.mul_add(i * n + t, x, &mut next[i * k + c]);
                    }
                }
            }
            if !qj.is_zero() {
                for c in 0..k {
                    next[i * k + c] += qj * &y[i * k + c];
                }
            }
        }
        acc = next;
    }
    acc
}
