//! Characteristic polynomials by Berkowitz's algorithm, and matrix polynomials by Horner.
//!
//! Berkowitz's algorithm never divides, so the same code gives `det(λI − A)` over the integers,
//! over Q(√d) and over the multivariate polynomials (a symbolic gain inside `A − KC`). Its cost
//! is O(n⁴) ring operations. Over the rationals the matrix is first scaled to integers by a common
//! denominator `d`: `p_{dA}(μ) = dⁿ p_A(μ/d)`, so the coefficients come back by exact division.

use super::{LinalgError, Matrix};
use crate::algebra::{Field, One, Ring};
use crate::poly::Poly;

/// `det(var·I − A)`, monic of degree n, by Berkowitz's division-free algorithm.
///
/// # Example
/// ```
/// use observer_workbench::algebra::{MultiPoly, Ring};
/// use observer_workbench::linalg::{berkowitz, Matrix};
/// // A − KC for A = [0 1; 0 0], C = [1 0], K = [k1; k2]
/// let k = |n| MultiPoly::var(n);
/// let f = Matrix::from_rows(vec![
///     vec![-k("k1"), MultiPoly::from_i64(1)],
///     vec![-k("k2"), MultiPoly::from_i64(0)],
/// ]).unwrap();
/// assert_eq!(berkowitz(&f, "s").unwrap().to_string(), "s^2 + k1 s + k2");
/// ```
///
/// # Errors
/// [`LinalgError::NotSquare`].
pub fn berkowitz<R: Ring>(a: &Matrix<R>, var: &str) -> Result<Poly<R>, LinalgError> {
    let n = a.require_square("characteristic polynomial")?;
    // v holds the coefficients of the characteristic polynomial of the leading r×r block,
    // highest power first.
    let mut v: Vec<R> = vec![R::one()];
    for r in 0..n {
        // Toeplitz column t = [1, −a_rr, −R C, −R M C, …, −R M^(r−1) C]
        let mut t: Vec<R> = Vec::with_capacity(r + 2);
        t.push(R::one());
        t.push(-a.get(r, r).clone());
        let mut mc: Vec<R> = (0..r).map(|i| a.get(i, r).clone()).collect();
        for _ in 0..r {
            let rc = (0..r).fold(R::zero(), |acc, j| {
                acc + a.get(r, j).clone() * mc[j].clone()
            });
            t.push(-rc);
            mc = (0..r)
                .map(|i| {
                    (0..r).fold(R::zero(), |acc, j| {
                        acc + a.get(i, j).clone() * mc[j].clone()
                    })
                })
                .collect();
        }
        let next: Vec<R> = (0..r + 2)
            .map(|i| {
                (0..=i.min(r)).fold(R::zero(), |acc, j| {
                    if v.get(j).is_some() {
                        acc + t[i - j].clone() * v[j].clone()
                    } else {
                        acc
                    }
                })
            })
            .collect();
        v = next;
    }
    Ok(Poly::from_descending(&v, var))
}

/// `det(var·I − A)` over a field, computed on integers after clearing denominators.
///
/// # Errors
/// [`LinalgError::NotSquare`].
pub fn characteristic_polynomial<F: Field>(
    a: &Matrix<F>,
    var: &str,
) -> Result<Poly<F>, LinalgError> {
    let n = a.require_square("characteristic polynomial")?;
    // a block triangular matrix: the product of its diagonal blocks' polynomials (an observer-
    // based loop [A + BF, BF; 0, A + LC] is one, and whole, its gains' large entries in every
    // row and column would call for thousands of primes)
    if let Some(k) = block_triangular_split(a) {
        let top = characteristic_polynomial(&a.block(0, k, 0, k), var)?;
        let bottom = characteristic_polynomial(&a.block(k, n, k, n), var)?;
        return Ok(top * bottom);
    }
    if let Some(r) = super::as_rational(a) {
        if let Some(p) =
            one_fractional_line(r, var)?.and_then(crate::algebra::from_concrete::<Poly<F>, _>)
        {
            return Ok(p);
        }
    }
    // Q(√d) entries that are all rational: the rational path (multimodular from
    // MODULAR_FROM_ORDER on), not the generic one with a gcd per operation
    let quadratic = (a as &dyn std::any::Any).downcast_ref::<Matrix<crate::algebra::Quadratic>>();
    if let Some(r) = quadratic.and_then(super::rational_entries) {
        let p = characteristic_polynomial(&r, var)?;
        let lifted = p.map(|c| crate::algebra::Quadratic::rational(c.clone()));
        if let Some(p) = crate::algebra::from_concrete::<Poly<F>, _>(lifted) {
            return Ok(p);
        }
    }
    let d = F::common_denominator(a.entries());
    let scaled = a.map(|x| x.scale_to_integer(&d));
    let p = integer_charpoly(&scaled, var)?;
    // [λ^k] p_A = [μ^k] p_{dA} / d^(n−k)
    let mut dpow = F::Integers::one();
    let mut coeffs = vec![F::zero(); n + 1];
    for k in (0..=n).rev() {
        coeffs[k] = F::from_integer_ratio(p.coeff(k), dpow.clone()).unwrap_or_else(F::zero);
        dpow = dpow * d.clone();
    }
    Ok(Poly::new(coeffs, var))
}

/// A rational matrix of the multimodular orders whose fractions all lie in one row (or one
/// column): `A = A₀ + e_r a_r` with `A₀` integral (row r zero) is a rank-one update, so
/// `det(sI − A) = det(sI − A₀) − a_r adj(sI − A₀) e_r` ([`rank_one_update`] on the Krylov rows
/// of `δ a_r`, δ its denominator) — where scaling the whole matrix by δ would put δ's digits in
/// every entry and multiply the primes needed by n (A + BF with a gain F, B = e₁; A + LC by
/// its transpose). `None` for any other matrix.
fn one_fractional_line(
    r: &Matrix<crate::algebra::Rational>,
    var: &str,
) -> Result<Option<Poly<crate::algebra::Rational>>, LinalgError> {
    use crate::algebra::{Rational, Zero};
    let n = r.rows();
    if n < super::MODULAR_FROM_ORDER {
        return Ok(None);
    }
    let fractional = |x: &Rational| !x.is_integer();
    let rows: Vec<usize> = (0..n)
        .filter(|&i| r.row(i).iter().any(fractional))
        .collect();
    let columns: Vec<usize> = (0..n)
        .filter(|&j| (0..n).any(|i| fractional(r.get(i, j))))
        .collect();
    let (line, m) = match (rows.as_slice(), columns.as_slice()) {
        (&[i], _) => (i, r.clone()),
        (_, &[j]) => (j, r.transpose()),
        _ => return Ok(None),
    };
    let row = m.block(line, line + 1, 0, n);
    let a0 = Matrix::from_fn(n, n, |i, j| {
        if i == line {
            Rational::zero()
        } else {
            m.get(i, j).clone()
        }
    });
    let delta = Rational::from_integer(Rational::common_denominator(row.entries()));
    let krylov = crate::observability::observability_matrix(&a0, &row.map(|x| x * &delta))?;
    let open = characteristic_polynomial(&a0, var)?;
    // det(sI − A₀ + K C) with C = δ a_r and K = −e_r / δ
    let k = Matrix::from_fn(n, 1, |i, _| {
        if i == line {
            -Rational::one() / delta.clone()
        } else {
            Rational::zero()
        }
    });
    Ok(Some(rank_one_update(&krylov, &open, &k)?))
}

/// The smallest k (0 < k < n) at which the square matrix `a` is block triangular —
/// `[X Y; 0 Z]` or `[X 0; Y Z]` with X of order k — so that `det(λI − a)` is
/// `det(λI − X) det(λI − Z)`. O(n²) zero tests: row i's first and last nonzero columns, their
/// suffix minima and prefix maxima.
fn block_triangular_split<R: Ring>(a: &Matrix<R>) -> Option<usize> {
    let zero: Vec<bool> = a.entries().iter().map(|x| x.is_zero()).collect();
    split_of_zero_pattern(&zero, a.rows())
}

/// [`block_triangular_split`] on the row-major zero pattern of an n × n matrix (one function
/// for every ring: the browser's module holds it once).
fn split_of_zero_pattern(zero: &[bool], n: usize) -> Option<usize> {
    let nonzero = |i: usize| (0..n).filter(move |&j| !zero[i * n + j]);
    // lower left zero: every row from k on starts at column k or later
    let mut first_from_k = vec![n; n + 1];
    for i in (0..n).rev() {
        first_from_k[i] = first_from_k[i + 1].min(nonzero(i).next().unwrap_or(n));
    }
    // upper right zero: every row before k ends before column k
    let mut last_before_k = 0;
    for k in 1..n {
        last_before_k = last_before_k.max(nonzero(k - 1).next_back().map_or(0, |j| j + 1));
        if first_from_k[k] >= k || last_before_k <= k {
            return Some(k);
        }
    }
    None
}

/// The characteristic polynomial of a matrix over a field's integers: multimodular for `BigInt`
/// from [`super::MODULAR_FROM_ORDER`] on, Berkowitz otherwise.
fn integer_charpoly<D: Ring>(a: &Matrix<D>, var: &str) -> Result<Poly<D>, LinalgError> {
    if a.rows() >= super::MODULAR_FROM_ORDER {
        let big = (a as &dyn std::any::Any).downcast_ref::<Matrix<num_bigint::BigInt>>();
        if let Some(p) = big
            .map(|m| Poly::new(super::modular::charpoly_integer(m), var))
            .and_then(crate::algebra::from_concrete::<Poly<D>, _>)
        {
            return Ok(p);
        }
    }
    berkowitz(a, var)
}

/// `det(sI − (A − KC))` for a single-output pair with observability matrix `o` and open-loop
/// polynomial `det(sI − A)` (the check of every gain design), by the rank-one update
/// `det(sI − A + KC) = det(sI − A) + C adj(sI − A) K` with
/// `adj(sI − A) = Σ_j A^j Σ_(i>j) a_i s^(i−j−1)`: only the numbers `C A^j K = (O_n K)_j`
/// enter, so the check costs one matrix–vector product, whatever the size of `K`.
///
/// # Errors
/// [`LinalgError::DimensionMismatch`] when `k` does not fit `o`.
pub(crate) fn rank_one_update<F: Field>(
    o: &Matrix<F>,
    open_loop: &Poly<F>,
    k: &Matrix<F>,
) -> Result<Poly<F>, LinalgError> {
    let rational = (
        super::as_rational(o),
        super::as_rational(k),
        open_loop.as_rational(),
    );
    if let (Some(o), Some(k), Some(open_loop)) = rational {
        if o.cols() != k.rows() {
            return Err(o.mismatch(k, "product"));
        }
        let (mm, delta) = super::mul_over_one_denominator(o, k);
        let p = rank_one_update_integers(&mm, &delta, open_loop, true);
        if let Some(p) = crate::algebra::from_concrete(p) {
            return Ok(p);
        }
    }
    let m = o.mul(k)?;
    let a = open_loop.coeffs();
    let n = a.len().saturating_sub(1);
    let mut coeffs = a.to_vec();
    for j in 0..n.min(m.rows()) {
        let mj = m.get(j, 0);
        if mj.is_zero() {
            continue;
        }
        for i in j + 1..=n {
            let e = i - j - 1;
            coeffs[e] = coeffs[e].clone() + mj.clone() * a[i].clone();
        }
    }
    Ok(Poly::new(coeffs, open_loop.var()))
}

/// `C adj(sI − A) K` — [`rank_one_update`]'s polynomial less `det(sI − A)` — for `O_n` given on
/// integers, row `j` being `o[j] / delta_o` (a single row of C over its denominator,
/// [`crate::observability::integer_observability_rows`]): with `K = K̃/d_K`,
/// `O_n K = (R K̃)/(δ_o d_K)` — no entry of `O_n` reduced, nor scaled back to integers for the
/// product, and no `det(sI − A)` added only to be taken away again. `None` when `k` is not a
/// column of `o`'s width.
pub(crate) fn adjugate_product_on_integers(
    o: &[Vec<crate::algebra::BigInt>],
    delta_o: &crate::algebra::BigInt,
    open_loop: &Poly<crate::algebra::Rational>,
    k: &Matrix<crate::algebra::Rational>,
) -> Option<Poly<crate::algebra::Rational>> {
    use crate::algebra::Zero;
    if k.cols() != 1 || o.iter().any(|row| row.len() != k.rows()) {
        return None;
    }
    let (k_int, d_k) = crate::algebra::gcd::integer_numerators(k.entries());
    let mm: Vec<crate::algebra::BigInt> = o
        .iter()
        .map(|row| {
            let mut acc = crate::algebra::BigInt::zero();
            for (x, y) in row.iter().zip(&k_int) {
                if !x.is_zero() && !y.is_zero() {
                    acc += x * y;
                }
            }
            acc
        })
        .collect();
    Some(rank_one_update_integers(
        &mm,
        &(delta_o * d_k),
        open_loop,
        false,
    ))
}

/// [`rank_one_update`]'s sums over the rationals on integers: with `m = O_n K = M/δ` and the
/// open-loop coefficients `a = α/d`, coefficient `e` is `(δ α_e + Σ_j M_j α_(j+e+1)) / (d δ)`,
/// reduced once — n reductions instead of one per term. Without `with_open_loop` the term
/// `δ α_e` is left out: the polynomial `C adj(sI − A) K` alone.
fn rank_one_update_integers(
    mm: &[crate::algebra::BigInt],
    delta: &crate::algebra::BigInt,
    open_loop: &Poly<crate::algebra::Rational>,
    with_open_loop: bool,
) -> Poly<crate::algebra::Rational> {
    let (alpha, d) = crate::algebra::gcd::integer_numerators(open_loop.coeffs());
    let n = alpha.len().saturating_sub(1);
    let terms = n.min(mm.len());
    let denominator = &d * delta;
    let coeffs = (0..alpha.len())
        .map(|e| {
            let mut numerator = if with_open_loop {
                &alpha[e] * delta
            } else {
                <crate::algebra::BigInt as crate::algebra::Zero>::zero()
            };
            for (j, mj) in mm.iter().enumerate().take(terms) {
                if let Some(a) = alpha.get(j + e + 1) {
                    if !crate::algebra::Zero::is_zero(mj) && !crate::algebra::Zero::is_zero(a) {
                        numerator += mj * a;
                    }
                }
            }
            crate::algebra::fraction(numerator, denominator.clone())
        })
        .collect();
    Poly::new(coeffs, open_loop.var())
}

/// `P(A) = p_n Aⁿ + … + p_1 A + p_0 I` by Horner's rule.
///
/// # Errors
/// [`LinalgError::NotSquare`].
pub fn matrix_polynomial<R: Ring>(p: &Poly<R>, a: &Matrix<R>) -> Result<Matrix<R>, LinalgError> {
    let n = a.require_square("matrix polynomial")?;
    let mut acc = Matrix::zeros(n, n);
    for c in p.coeffs().iter().rev() {
        acc = acc.mul(a)?.add(&Matrix::identity(n).scale(c))?;
    }
    Ok(acc)
}

/// `P(A)·v` by Horner's rule on vectors: n matrix–vector products, never forming `P(A)`.
///
/// # Errors
/// [`LinalgError::NotSquare`], [`LinalgError::DimensionMismatch`].
pub fn polynomial_times_vector<R: Ring>(
    p: &Poly<R>,
    a: &Matrix<R>,
    v: &Matrix<R>,
) -> Result<Matrix<R>, LinalgError> {
    let n = a.require_square("matrix polynomial")?;
    if v.rows() != n {
        return Err(a.mismatch(v, "matrix polynomial times vector"));
    }
    let as_poly = p.as_rational();
    if let (Some(qp), Some(qa), Some(qv)) = (as_poly, super::as_rational(a), super::as_rational(v))
    {
        if let Some(r) =
            crate::algebra::from_concrete(super::rational::polynomial_times_vector(qp, qa, qv))
        {
            return Ok(r);
        }
    }
    let mut acc = Matrix::zeros(n, v.cols());
    for c in p.coeffs().iter().rev() {
        acc = a.mul(&acc)?.add(&v.scale(c))?;
    }
    Ok(acc)
}

/// `P(A)·X` with `X = M⁻¹ B` (Ackermann's `P(A) O_n⁻¹ e_n`), and `X` itself when `keep` asks
/// for it. Over the rationals from [`super::MODULAR_FROM_ORDER`] on, `X` goes into Horner's
/// rule as the multimodular solve gives it — integers over the one denominator `det M` — and
/// only the result's entries are reduced: the n gcds of numbers as long as `det M` that
/// reducing `X` costs are spent only when `X` is kept (at order 40 they were a tenth of a
/// gain's design). Elsewhere [`super::solve`], then [`polynomial_times_vector`]. The numbers
/// are the same either way.
///
/// # Errors
/// As [`super::solve`] and [`polynomial_times_vector`].
pub fn polynomial_times_solution<F: Field>(
    p: &Poly<F>,
    a: &Matrix<F>,
    m: &Matrix<F>,
    b: &Matrix<F>,
    keep: bool,
) -> Result<(Matrix<F>, Option<Matrix<F>>), LinalgError> {
    let n = m.require_square("solve")?;
    let fast = n >= super::MODULAR_FROM_ORDER && a.rows() == n && a.cols() == n;
    let as_poly = p.as_rational();
    if let (true, Some(qp), Some(qa), Some(qm), Some(qb)) = (
        fast,
        as_poly,
        super::as_rational(a),
        super::as_rational(m),
        super::as_rational(b),
    ) {
        if let Some((y, det)) = super::modular::solve_rational_scaled(qm, qb) {
            let k = b.cols();
            let r = super::rational::polynomial_times_integers(qp, qa, &y, &det, k);
            let x = keep.then(|| {
                Matrix::from_fn(n, k, |i, j| {
                    crate::algebra::fraction(y[i * k + j].clone(), det.clone())
                })
            });
            // the same types (F is the rationals): the conversions cannot fail
            let x = match x {
                None => Some(None),
                Some(x) => crate::algebra::from_concrete(x).map(Some),
            };
            if let (Some(r), Some(x)) = (crate::algebra::from_concrete(r), x) {
                return Ok((r, x));
            }
        }
    }
    let x = super::solve(m, b)?;
    let r = polynomial_times_vector(p, a, &x)?;
    Ok((r, keep.then_some(x)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algebra::Rational;

    #[test]
    fn stoustrup_open_loop_polynomial() {
        // A = [2 -3; 4 -5]: det(sI − A) = s^2 + 3s + 2
        let r = |x| Rational::from_i64(x);
        let a = Matrix::from_rows(vec![vec![r(2), r(-3)], vec![r(4), r(-5)]]).unwrap();
        let p = characteristic_polynomial(&a, "s").unwrap();
        assert_eq!(p.to_string(), "s^2 + 3s + 2");
        assert!(matrix_polynomial(&p, &a).unwrap().is_zero());
    }

    proptest::proptest! {
        /// A block triangular matrix's polynomial, taken as the product of its diagonal
        /// blocks', is Berkowitz's on the whole matrix — either triangle zero, at any split,
        /// below and from the multimodular order (and a split is found where there is one).
        #[test]
        fn block_triangular_matrices_split_exactly(
            n in 2usize..12,
            split in 1usize..11,
            upper in proptest::prelude::any::<bool>(),
            entries in proptest::collection::vec(-4i64..=4, 144),
        ) {
            let k = split.min(n - 1);
            let a = Matrix::from_fn(n, n, |i, j| {
                let zero = if upper { i >= k && j < k } else { i < k && j >= k };
                if zero { Rational::from_i64(0) } else { Rational::from_i64(entries[12 * i + j]) }
            });
            proptest::prop_assert!(block_triangular_split(&a).is_some_and(|s| s <= k));
            let direct = berkowitz(&a, "s").unwrap();
            proptest::prop_assert_eq!(characteristic_polynomial(&a, "s").unwrap(), direct);
        }

        /// A matrix whose fractions lie in one row or one column (a gain's, with a large
        /// denominator): its polynomial by the rank-one update of its integral rest is
        /// Berkowitz's on the whole matrix.
        #[test]
        fn one_fractional_line_is_a_rank_one_update(
            n in 8usize..11,
            line in 0usize..10,
            column in proptest::prelude::any::<bool>(),
            entries in proptest::collection::vec(-4i64..=4, 100),
            numerators in proptest::collection::vec(-1_000_000i64..=1_000_000, 10),
            denominator in 1i64..=999_983,
        ) {
            let line = line.min(n - 1);
            let big = crate::algebra::BigInt::from(denominator).pow(5);
            let a = Matrix::from_fn(n, n, |i, j| {
                let (on_line, k) = if column { (j == line, i) } else { (i == line, j) };
                if on_line {
                    Rational::new(numerators[k].into(), big.clone())
                } else {
                    Rational::from_i64(entries[10 * i + j])
                }
            });
            proptest::prop_assert!(one_fractional_line(&a, "s").unwrap().is_some() || denominator == 1);
            proptest::prop_assert_eq!(characteristic_polynomial(&a, "s").unwrap(), berkowitz(&a, "s").unwrap());
        }
    }

    #[test]
    fn rational_entries_scale_back_exactly() {
        let h = |n: i64, d: i64| Rational::new(n.into(), d.into());
        let a = Matrix::from_rows(vec![vec![h(1, 2), h(1, 3)], vec![h(0, 1), h(-1, 4)]]).unwrap();
        let p = characteristic_polynomial(&a, "s").unwrap();
        assert_eq!(p.to_string(), "s^2 − (1/4)s − 1/8");
    }

    /// The unreduced path (integers over `det M`, of either sign) gives the numbers of a solve
    /// then Horner, and keeps `X` in lowest terms when asked; below the multimodular order
    /// the generic path runs.
    #[test]
    fn polynomial_times_solution_agrees_with_solve_then_horner() {
        let mut seed = 12_345u64;
        let mut next = |modulus: u64| {
            seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            ((seed >> 33) % modulus) as i64
        };
        for n in [3, 8, 9, 13] {
            for trial in 0..3 {
                let mut entry = || Rational::new((next(19) - 9).into(), (next(5) + 1).into());
                let a = Matrix::from_fn(n, n, |_, _| entry());
                let m = Matrix::from_fn(n, n, |_, _| entry());
                let b = Matrix::from_fn(n, 1 + trial % 2, |_, _| entry());
                let p = Poly::new((0..=n).map(|_| entry()).collect(), "s");
                let x = crate::linalg::solve(&m, &b).unwrap();
                let expected = polynomial_times_vector(&p, &a, &x).unwrap();
                let (r, kept) = polynomial_times_solution(&p, &a, &m, &b, true).unwrap();
                assert_eq!(r, expected, "n = {n}");
                assert_eq!(kept.as_ref(), Some(&x), "n = {n}");
                let (r, kept) = polynomial_times_solution(&p, &a, &m, &b, false).unwrap();
                assert_eq!(r, expected, "n = {n}");
                assert!(kept.is_none());
                // a row swapped flips det M's sign: the same numbers
                let mut rows: Vec<Vec<Rational>> = (0..n).map(|i| m.row(i).to_vec()).collect();
                rows.swap(0, 1);
                let mut brows: Vec<Vec<Rational>> = (0..n).map(|i| b.row(i).to_vec()).collect();
                brows.swap(0, 1);
                let (m2, b2) = (
                    Matrix::from_rows(rows).unwrap(),
                    Matrix::from_rows(brows).unwrap(),
                );
                assert_eq!(
                    polynomial_times_solution(&p, &a, &m2, &b2, false)
                        .unwrap()
                        .0,
                    expected
                );
            }
        }
    }
}
