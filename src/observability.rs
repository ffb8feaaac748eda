//! Observability: the observability and controllability matrices, the rank test, and — when a
//! pair is not observable — the evidence: a basis of the unobservable subspace and the
//! unobservable eigenvalues (the modes the output cannot see, PBH test).
//!
//! Stoustrup, Lecture 3, "Observability" and the two "series connection" examples; Di Ruscio
//! eq. (16) uses `O_n` for the canonical form.

use crate::algebra::{BigInt, Field, Quadratic, Rational, Ring};
use crate::linalg::{self, LinalgError, Matrix};
use crate::poly::{exact_roots, ExactRoots, Poly};

/// Why an observability computation failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ObservabilityError {
    /// The matrices do not fit.
    #[error(transparent)]
    Dimension(#[from] LinalgError),
    /// The pair is not observable (for designs that need it).
    #[error("the pair (A, C) is not observable: rank of the observability matrix is {rank}, the order is {order}; unobservable direction {direction}{}", modes_text(.modes))]
    Unobservable {
        /// Rank of `O_n`.
        rank: usize,
        /// Order `n`.
        order: usize,
        /// One vector `x ≠ 0` with `O_n x = 0`, printed.
        direction: String,
        /// The unobservable eigenvalues (roots of `det(λI − A|ker O_n)`), printed, when the
        /// entries are rational: the modes no gain can move.
        modes: Option<String>,
    },
    /// The pair is not detectable: an unobservable mode is not stable, so no observer makes
    /// the estimation error vanish.
    #[error("(A, C) is not detectable: the unobservable modes ({modes}) are not all stable, so no observer — Kalman or other — makes the estimation error vanish")]
    Undetectable {
        /// The unobservable eigenvalues, printed.
        modes: String,
    },
}

/// `O_n = [C; CA; …; CA^(n−1)]`.
///
/// # Errors
/// [`LinalgError`] when `A` is not square or `C` has the wrong width.
pub fn observability_matrix<R: Ring>(
    a: &Matrix<R>,
    c: &Matrix<R>,
) -> Result<Matrix<R>, LinalgError> {
    let n = a.rows();
    if !a.is_square() {
        return Err(LinalgError::NotSquare {
            operation: "observability matrix",
            rows: a.rows(),
            cols: a.cols(),
        });
    }
    if c.cols() != n {
        return Err(c.mismatch(a, "observability matrix (C against A)"));
    }
    // an integer A (the common case: a plant typed with whole numbers): rows on big integers,
    // each product term a big integer times a machine-word entry of A, a fraction reduced only
    // where C's row has a denominator
    fn rational<R: Ring>(m: &Matrix<R>) -> Option<&Matrix<Rational>> {
        (m as &dyn std::any::Any).downcast_ref::<Matrix<Rational>>()
    }
    if let (Some(ar), Some(cr)) = (rational(a), rational(c)) {
        if let Some(o) = integer_observability(ar, cr) {
            if let Some(o) = crate::algebra::from_concrete::<Matrix<R>, _>(o) {
                return Ok(o);
            }
        }
    }
    let mut block = c.clone();
    let mut rows: Vec<Vec<R>> = (0..c.rows()).map(|i| c.row(i).to_vec()).collect();
    for _ in 1..n {
        block = block.mul(a)?;
        rows.extend((0..block.rows()).map(|i| block.row(i).to_vec()));
    }
    Matrix::from_rows(rows)
}

/// `O_n` of a rational pair whose `A` has machine-word integer entries, from
/// [`integer_observability_rows`], each entry reduced once; `None` for any other pair.
fn integer_observability(a: &Matrix<Rational>, c: &Matrix<Rational>) -> Option<Matrix<Rational>> {
    let (rows, denominators) = integer_observability_rows(a, c)?;
    let p = denominators.len();
    let rows = rows
        .into_iter()
        .enumerate()
        .map(|(i, r)| {
            let d = &denominators[i % p];
            if num_traits::One::is_one(d) {
                r.into_iter().map(Rational::from_integer).collect()
            } else {
                r.into_iter()
                    .map(|x| crate::algebra::fraction(x, d.clone()))
                    .collect()
            }
        })
        .collect();
    Matrix::from_rows(rows).ok()
}

/// `O_n` of a rational pair whose `A` has machine-word integer entries, on integers: `(R, δ)`
/// with row `k·p + i` of `O_n` equal to `R[k·p + i] / δ_i` (`p` the rows of `C`, `δ_i` the lcm
/// of row i's denominators), not reduced — for a caller that goes on on integers (the loop's
/// rank-one updates), where reducing every entry of a state feedback's `F·A^k` and scaling it
/// back cost a fifth of `control` at order 60. Each product term is a big integer times an
/// `i64`, in 128-bit words while the entries fit. `None` for any other pair.
pub(crate) fn integer_observability_rows(
    a: &Matrix<Rational>,
    c: &Matrix<Rational>,
) -> Option<(Vec<Vec<BigInt>>, Vec<BigInt>)> {
    use num_traits::ToPrimitive;
    let n = a.rows();
    if !a.is_square() || c.cols() != n {
        return None;
    }
    let small: Vec<i64> = a
        .entries()
        .iter()
        .map(|x| x.is_integer().then(|| x.to_integer().to_i64()).flatten())
        .collect::<Option<_>>()?;
    // each row of C over its own denominator: (c/δ)·A^k = (c·A^k)/δ
    let (block, denominators): (Vec<Vec<BigInt>>, Vec<BigInt>) = (0..c.rows())
        .map(|i| crate::algebra::gcd::integer_numerators(c.row(i)))
        .unzip();
    // the block C·A^k in 128-bit words while its entries fit (the first blocks of a plant with
    // small entries), on big integers from the first product that would overflow
    let mut block = Block::of(block);
    let mut rows: Vec<Vec<BigInt>> = Vec::with_capacity(n * denominators.len());
    for _ in 1..n {
        let next = block.times(&small, n);
        rows.extend(block.into_big());
        block = next;
    }
    if n > 0 {
        rows.extend(block.into_big());
    }
    Some((rows, denominators))
}

/// A block of rows of `O_n` on integers: machine words while they fit, big integers after.
enum Block {
    Words(Vec<Vec<i128>>),
    Big(Vec<Vec<BigInt>>),
}

impl Block {
    /// The rows in words when every entry fits one.
    fn of(rows: Vec<Vec<BigInt>>) -> Block {
        let words: Option<Vec<Vec<i128>>> = rows
            .iter()
            .map(|r| r.iter().map(num_traits::ToPrimitive::to_i128).collect())
            .collect();
        words.map_or(Block::Big(rows), Block::Words)
    }
    /// `row · A` for each row: in words unless a product or sum would overflow.
    fn times(&self, a: &[i64], n: usize) -> Block {
        match self {
            Block::Words(w) => words_times_a(w, a, n)
                .map_or_else(|| Block::Big(times_a(&big_of(w), a, n)), Block::Words),
            Block::Big(b) => Block::Big(times_a(b, a, n)),
        }
    }
    fn into_big(self) -> Vec<Vec<BigInt>> {
        match self {
            Block::Words(w) => big_of(&w),
            Block::Big(b) => b,
        }
    }
}

/// The rows in big integers (through `i64` where a word holds the entry: num-bigint keeps a
/// one-limb number inline, where its conversion from `i128` allocates).
fn big_of(block: &[Vec<i128>]) -> Vec<Vec<BigInt>> {
    block
        .iter()
        .map(|r| {
            r.iter()
                .map(|&x| i64::try_from(x).map_or_else(|_| BigInt::from(x), BigInt::from))
                .collect()
        })
        .collect()
}

/// `row · A` for each row in 128-bit words; `None` when a product or sum would overflow.
fn words_times_a(block: &[Vec<i128>], a: &[i64], n: usize) -> Option<Vec<Vec<i128>>> {
    block
        .iter()
        .map(|r| {
            (0..n)
                .map(|j| {
                    let mut acc: i128 = 0;
                    for (i, &x) in r.iter().enumerate() {
                        let w = a[i * n + j];
                        if w != 0 && x != 0 {
                            // two words multiply without overflow (one widening product); a
                            // wider entry takes the checked 128-bit product (a library call)
                            let product = match i64::try_from(x) {
                                Ok(x) => i128::from(x) * i128::from(w),
                                Err(_) => x.checked_mul(i128::from(w))?,
                            };
                            acc = acc.checked_add(product)?;
                        }
                    }
                    Some(acc)
                })
                .collect()
        })
        .collect()
}

/// `row · A` for each row, on big integers, `A` (n × n, row-major) in machine words.
fn times_a(block: &[Vec<BigInt>], a: &[i64], n: usize) -> Vec<Vec<BigInt>> {
    block
        .iter()
        .map(|r| {
            (0..n)
                .map(|j| {
                    let mut acc = BigInt::from(0);
                    for (i, x) in r.iter().enumerate() {
                        let w = a[i * n + j];
                        if w != 0 && !num_traits::Zero::is_zero(x) {
                            acc += x * w;
                        }
                    }
                    acc
                })
                .collect()
        })
        .collect()
}

/// `C_n = [B, AB, …, A^(n−1)B]`.
///
/// # Errors
/// [`LinalgError`] when `A` is not square or `B` has the wrong height.
pub fn controllability_matrix<R: Ring>(
    a: &Matrix<R>,
    b: &Matrix<R>,
) -> Result<Matrix<R>, LinalgError> {
    Ok(observability_matrix(&a.transpose(), &b.transpose())?.transpose())
}

/// The result of the observability test, with its working.
#[derive(Clone, PartialEq, Debug)]
pub struct ObservabilityReport {
    /// `O_n`.
    pub matrix: Matrix<Rational>,
    /// `det O_n` for a single output (square `O_n`).
    pub determinant: Option<Rational>,
    /// `rank O_n`.
    pub rank: usize,
    /// The order `n`.
    pub order: usize,
    /// A basis of the unobservable subspace `ker O_n` (empty when observable).
    pub unobservable_subspace: Vec<Matrix<Rational>>,
    /// `det(λI − A|ker O_n)`: the characteristic polynomial of the unobservable part.
    pub unobservable_polynomial: Poly<Rational>,
    /// Its roots, exact where rational or in a quadratic field.
    pub unobservable_eigenvalues: ExactRoots,
    /// For each exact unobservable eigenvalue λ: `rank [λI − A; C] < n` (PBH), checked.
    pub pbh_confirmed: bool,
}

impl ObservabilityReport {
    /// Whether `(A, C)` is observable.
    pub fn observable(&self) -> bool {
        self.rank == self.order
    }
}

/// The observability test over the rationals, with evidence when it fails.
///
/// # Example
/// ```
/// use observer_workbench::algebra::Rational;
/// use observer_workbench::observability::observability_report;
/// use observer_workbench::syntax::parse_matrix;
/// // Stoustrup's series connection with y = x1: the second tank is invisible.
/// let a = parse_matrix::<Rational>("[-1 0; 1 -1]").unwrap();
/// let c = parse_matrix::<Rational>("[1 0]").unwrap();
/// let r = observability_report(&a, &c).unwrap();
/// assert!(!r.observable());
/// assert_eq!(r.matrix.to_input(), "[1, 0; -1, 0]");
/// assert_eq!(r.unobservable_subspace[0].to_input(), "[0; 1]");
/// assert_eq!(r.unobservable_polynomial.to_string(), "s + 1");
/// ```
///
/// # Errors
/// [`LinalgError`] for mismatched dimensions.
pub fn observability_report(
    a: &Matrix<Rational>,
    c: &Matrix<Rational>,
) -> Result<ObservabilityReport, LinalgError> {
    report(a, c, true)
}

/// [`observability_report`] without `det O_n` (`determinant` is `None`), for the designs that
/// show `O_n` and its rank only: the determinant of an order-40 `O_n` costs as much as the
/// design's own solve.
///
/// # Errors
/// [`LinalgError`] for mismatched dimensions.
pub fn observability_rank_report(
    a: &Matrix<Rational>,
    c: &Matrix<Rational>,
) -> Result<ObservabilityReport, LinalgError> {
    report(a, c, false)
}

fn report(
    a: &Matrix<Rational>,
    c: &Matrix<Rational>,
    with_determinant: bool,
) -> Result<ObservabilityReport, LinalgError> {
    let o = observability_matrix(a, c)?;
    let n = a.rows();
    let determinant = if with_determinant && o.is_square() {
        Some(linalg::determinant(&o)?)
    } else {
        None
    };
    // a nonzero det O_n is full rank already: the rank test only when it is zero or not shown
    let rank = match &determinant {
        Some(d) if !num_traits::Zero::is_zero(d) => n,
        _ => linalg::rank(&o),
    };
    let (basis, unobservable_polynomial) = unobservable_part(a, &o, rank)?;
    let unobservable_eigenvalues = exact_roots(&unobservable_polynomial);
    let pbh_confirmed = unobservable_eigenvalues
        .roots
        .iter()
        .all(|(lambda, _)| pbh_rank(a, c, lambda) < n);
    Ok(ObservabilityReport {
        matrix: o,
        determinant,
        rank,
        order: n,
        unobservable_subspace: basis,
        unobservable_polynomial,
        unobservable_eigenvalues,
        pbh_confirmed,
    })
}

/// The unobservable part of `(A, C)` from `O_n` and its rank: a basis of `ker O_n` and the
/// polynomial of the unobservable modes, `det(sI − A|ker O_n)` (1 when the rank is full). Over
/// any field: the rational report and the symbolic one (in the plant's parameters) share it.
///
/// # Errors
/// [`LinalgError`] for mismatched dimensions.
pub fn unobservable_part<F: Field>(
    a: &Matrix<F>,
    o: &Matrix<F>,
    rank: usize,
) -> Result<(Vec<Matrix<F>>, Poly<F>), LinalgError> {
    // ker O_n is {0} when the rank is full (proved cheaply for large matrices)
    let basis = if rank == a.rows() {
        Vec::new()
    } else {
        linalg::null_space(o)
    };
    let restricted = restriction(a, &basis)?;
    let polynomial = linalg::characteristic_polynomial(&restricted, "s")?;
    Ok((basis, polynomial))
}

/// `A` restricted to an `A`-invariant subspace spanned by the columns `basis`: the matrix `R`
/// with `A·N = N·R`.
fn restriction<F: Field>(a: &Matrix<F>, basis: &[Matrix<F>]) -> Result<Matrix<F>, LinalgError> {
    let k = basis.len();
    if k == 0 {
        return Ok(Matrix::zeros(0, 0));
    }
    let n = a.rows();
    let nmat = Matrix::from_fn(n, k, |i, j| basis[j].get(i, 0).clone());
    let an = a.mul(&nmat)?;
    // N has full column rank: solve on k independent rows.
    let rows = linalg::rref(&nmat.transpose()).pivot_columns;
    let sub_n = Matrix::from_fn(k, k, |i, j| nmat.get(rows[i], j).clone());
    let sub_an = Matrix::from_fn(k, k, |i, j| an.get(rows[i], j).clone());
    linalg::solve(&sub_n, &sub_an)
}

/// `rank [λI − A; C]` in the field of λ.
pub fn pbh_rank(a: &Matrix<Rational>, c: &Matrix<Rational>, lambda: &Quadratic) -> usize {
    let n = a.rows();
    let aq = a.map(|x| Quadratic::rational(x.clone()));
    let shifted = Matrix::<Quadratic>::identity(n)
        .scale(lambda)
        .sub(&aq)
        .expect("square");
    let stacked = shifted
        .vstack(&c.map(|x| Quadratic::rational(x.clone())))
        .expect("same width");
    linalg::rank(&stacked)
}

fn modes_text(modes: &Option<String>) -> String {
    match modes {
        Some(m) => format!(
            "; unobservable eigenvalues {m}: no observer gain can move these modes (an observer exists only if they are stable)"
        ),
        None => String::new(),
    }
}

/// The unobservable eigenvalues of a rational pair with the given basis of `ker O_n`.
fn unobservable_modes(a: &Matrix<Rational>, basis: &[Matrix<Rational>]) -> Option<String> {
    let restricted = restriction(a, basis).ok()?;
    let p = linalg::characteristic_polynomial(&restricted, "s").ok()?;
    Some(exact_roots(&p).render())
}

/// Requires detectability (continuous time): every unobservable mode stable, decided exactly
/// by Routh–Hurwitz on the unobservable polynomial `det(λI − A|ker O_n)`.
///
/// # Errors
/// [`ObservabilityError::Undetectable`] naming the unobservable modes; a dimension error.
pub fn require_detectable(
    a: &Matrix<Rational>,
    c: &Matrix<Rational>,
) -> Result<(), ObservabilityError> {
    // an observable pair is detectable: proved modulo a prime without forming O_n, whose pn
    // rows can exceed what the exact algorithms accept when there are many outputs
    if a.is_square() && c.cols() == a.rows() && linalg::modular::observable_mod_prime(a, c) {
        return Ok(());
    }
    let report = observability_rank_report(a, c)?;
    if report.observable() || crate::poly::is_hurwitz(&report.unobservable_polynomial) {
        return Ok(());
    }
    Err(ObservabilityError::Undetectable {
        modes: report.unobservable_eigenvalues.render(),
    })
}

/// Requires observability: `Ok(O_n)` or the evidence why not.
///
/// # Errors
/// [`ObservabilityError::Unobservable`] with a direction in `ker O_n`.
pub fn require_observable<F: Field>(
    a: &Matrix<F>,
    c: &Matrix<F>,
) -> Result<Matrix<F>, ObservabilityError> {
    let o = observability_matrix(a, c)?;
    let rank = linalg::rank(&o);
    if rank < a.rows() {
        let basis = linalg::null_space(&o);
        let direction = basis.first().map(|v| v.to_input()).unwrap_or_default();
        let modes = linalg::as_rational(a).and_then(|qa| {
            let qb: Option<Vec<Matrix<Rational>>> = basis
                .iter()
                .map(|v| linalg::as_rational(v).cloned())
                .collect();
            unobservable_modes(qa, &qb?)
        });
        return Err(ObservabilityError::Unobservable {
            rank,
            order: a.rows(),
            direction,
            modes,
        });
    }
    Ok(o)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// `[C; CA; …; CA^(n−1)]` by products of rational matrices, block by block.
    fn by_products(a: &Matrix<Rational>, c: &Matrix<Rational>) -> Matrix<Rational> {
        let mut block = c.clone();
        let mut rows: Vec<Vec<Rational>> = (0..c.rows()).map(|i| c.row(i).to_vec()).collect();
        for _ in 1..a.rows() {
            block = block.mul(a).unwrap();
            rows.extend((0..block.rows()).map(|i| block.row(i).to_vec()));
        }
        Matrix::from_rows(rows).unwrap()
    }

    proptest! {
        /// The integer path — 128-bit words, then big integers once a product would overflow
        /// (entries up to 2⁴⁰ overflow within a few powers), each row of C over its own
        /// denominator — gives O_n as the rational products do, and `C adj(sI − A) K` from its
        /// integer rows the rank-one update of the reduced O_n less det(sI − A).
        #[test]
        fn integer_rows_are_the_rational_products(
            n in 1usize..6,
            entries in proptest::collection::vec((-(1i64 << 40)..(1i64 << 40), 0u32..41), 36),
            c_entries in proptest::collection::vec((-50i64..50, 1i64..30), 12),
            outputs in 1usize..3,
            k_entries in proptest::collection::vec((-1000i64..1000, 1i64..99), 6),
        ) {
            let a = Matrix::from_fn(n, n, |i, j| {
                let (v, shift) = entries[i * 6 + j];
                Rational::from_integer(BigInt::from(v >> shift))
            });
            let c = Matrix::from_fn(outputs, n, |i, j| {
                let (num, den) = c_entries[i * 6 + j];
                Rational::new(num.into(), den.into())
            });
            let expected = by_products(&a, &c);
            prop_assert_eq!(integer_observability(&a, &c), Some(expected.clone()));
            if outputs == 1 {
                let (rows, denominators) = integer_observability_rows(&a, &c).unwrap();
                let open = linalg::characteristic_polynomial(&a, "s").unwrap();
                let k = Matrix::from_fn(n, 1, |i, _| {
                    let (num, den) = k_entries[i];
                    Rational::new(num.into(), den.into())
                });
                prop_assert_eq!(
                    linalg::adjugate_product_on_integers(&rows, &denominators[0], &open, &k),
                    Some(linalg::rank_one_update(&expected, &open, &k).unwrap() - open.clone())
                );
            }
        }
    }
}
