//! Elimination: fraction-free Bareiss (determinant, rank, solve, inverse) and Gauss–Jordan
//! (reduced row echelon form, null space).
//!
//! Bareiss elimination keeps every intermediate entry a minor of the input, so over the integers
//! the numbers grow only linearly in the order (no fraction blow-up), and the division by the
//! previous pivot is always exact. Over the rationals, each row is first multiplied by the
//! common denominator of its entries ([`Field::common_denominator`]), which changes neither the
//! rank nor the solution, and the elimination runs on `BigInt`.

use super::{LinalgError, Matrix};
use crate::algebra::{Field, IntegralDomain, One, Ring, Zero};

/// A fraction-free row echelon form.
pub(crate) struct Echelon<D> {
    /// The rows after elimination.
    pub rows: Vec<Vec<D>>,
    /// `(row, column)` of each pivot, in order.
    pub pivots: Vec<(usize, usize)>,
    /// Whether an odd number of row swaps happened.
    pub odd_swaps: bool,
}

/// Bareiss elimination choosing pivots in the first `pivot_cols` columns only.
pub(crate) fn bareiss<D: IntegralDomain>(mut rows: Vec<Vec<D>>, pivot_cols: usize) -> Echelon<D> {
    let m = rows.len();
    let width = rows.first().map_or(0, Vec::len);
    let mut prev = D::one();
    let mut r = 0;
    let mut pivots = Vec::new();
    let mut odd_swaps = false;
    for c in 0..pivot_cols.min(width) {
        if r == m {
            break;
        }
        let best = (r..m)
            .map(|i| (i, rows[i][c].pivot_weight()))
            .filter(|(_, w)| *w > 0.0)
            .max_by(|a, b| a.1.total_cmp(&b.1));
        let Some((p, _)) = best else { continue };
        if p != r {
            rows.swap(p, r);
            odd_swaps = !odd_swaps;
        }
        let (top, bottom) = rows.split_at_mut(r + 1);
        let pivot_row = &top[r];
        let pivot = pivot_row[c].clone();
        for row in bottom.iter_mut() {
            let factor = row[c].clone();
            for j in c + 1..width {
                let v = pivot.clone() * row[j].clone() - factor.clone() * pivot_row[j].clone();
                row[j] = v
                    .divide_exact(&prev)
                    .expect("Bareiss: the division by the previous pivot is exact");
            }
            row[c] = D::zero();
        }
        pivots.push((r, c));
        prev = pivot;
        r += 1;
    }
    Echelon {
        rows,
        pivots,
        odd_swaps,
    }
}

/// Rows of `a` scaled to [`Field::Integers`], and the product of the scale factors.
fn integer_rows<F: Field>(a: &Matrix<F>) -> (Vec<Vec<F::Integers>>, F::Integers) {
    let mut scale = F::Integers::one();
    let rows = (0..a.rows())
        .map(|i| {
            let d = F::common_denominator(a.row(i));
            let r = a.row(i).iter().map(|x| x.scale_to_integer(&d)).collect();
            scale = scale.clone() * d;
            r
        })
        .collect();
    (rows, scale)
}

/// The determinant of a square matrix over an integral domain, by Bareiss elimination.
///
/// # Errors
/// [`LinalgError::NotSquare`].
pub fn determinant_in_domain<D: IntegralDomain>(a: &Matrix<D>) -> Result<D, LinalgError> {
    let n = a.require_square("determinant")?;
    if n == 0 {
        return Ok(D::one());
    }
    let e = bareiss(a.to_rows(), n);
    if e.pivots.len() < n {
        return Ok(D::zero());
    }
    let d = e.rows[n - 1][n - 1].clone();
    Ok(if e.odd_swaps { -d } else { d })
}

/// The determinant of a square matrix over a field, fraction-free.
///
/// # Example
/// ```
/// use observer_workbench::algebra::{Rational, Ring};
/// use observer_workbench::linalg::{determinant, Matrix};
/// let a = Matrix::from_rows(vec![
///     vec![Rational::new(1.into(), 2.into()), Rational::from_i64(1)],
///     vec![Rational::from_i64(3), Rational::from_i64(4)],
/// ]).unwrap();
/// assert_eq!(determinant(&a).unwrap(), Rational::from_i64(-1));
/// let wide = Matrix::<Rational>::zeros(2, 3);
/// assert!(determinant(&wide).is_err());
/// ```
///
/// # Errors
/// [`LinalgError::NotSquare`].
pub fn determinant<F: Field>(a: &Matrix<F>) -> Result<F, LinalgError> {
    let n = a.require_square("determinant")?;
    if n >= super::MODULAR_FROM_ORDER {
        if let Some(d) = super::as_rational(a)
            .map(super::modular::determinant_rational)
            .and_then(crate::algebra::from_concrete)
        {
            return Ok(d);
        }
    }
    let (rows, scale) = integer_rows(a);
    let m = Matrix::from_rows(rows)?;
    let d = determinant_in_domain(&m)?;
    Ok(F::from_integer_ratio(d, scale).unwrap_or_else(F::zero))
}

/// The rank over a field (exact for exact types; for `f64` use [`super::float::rank`], which takes
/// a tolerance).
///
/// Large rational matrices are first tried modulo a prime: a full rank there proves full rank
/// over Q ([`super::modular::has_full_rank`]); otherwise fraction-free elimination decides.
pub fn rank<F: Field>(a: &Matrix<F>) -> usize {
    if a.rows().max(a.cols()) >= super::MODULAR_FROM_ORDER {
        if let Some(q) = super::as_rational(a) {
            if super::modular::has_full_rank(q) {
                return a.rows().min(a.cols());
            }
        }
    }
    let (rows, _) = integer_rows(a);
    bareiss(rows, a.cols()).pivots.len()
}

/// Solves `A X = B` for square nonsingular `A`, by fraction-free elimination and fraction-free
/// back substitution (`det(A)·X` stays in the integers).
///
/// # Errors
/// [`LinalgError::NotSquare`], [`LinalgError::DimensionMismatch`], [`LinalgError::Singular`].
pub fn solve<F: Field>(a: &Matrix<F>, b: &Matrix<F>) -> Result<Matrix<F>, LinalgError> {
    let n = a.require_square("solve")?;
    if b.rows() != n {
        return Err(a.mismatch(b, "solve"));
    }
    let k = b.cols();
    if n >= super::MODULAR_FROM_ORDER {
        if let (Some(qa), Some(qb)) = (super::as_rational(a), super::as_rational(b)) {
            if let Some(x) =
                super::modular::solve_rational(qa, qb).and_then(crate::algebra::from_concrete)
            {
                return Ok(x);
            }
        }
    }
    let (rows, _) = integer_rows(&a.hstack(b)?);
    let e = bareiss(rows, n);
    if e.pivots.len() < n {
        return Err(LinalgError::Singular {
            order: n,
            rank: e.pivots.len(),
        });
    }
    let u = &e.rows;
    let d = u[n - 1][n - 1].clone();
    let mut y: Vec<Vec<F::Integers>> = vec![vec![F::Integers::zero(); k]; n];
    for c in 0..k {
        for i in (0..n).rev() {
            let mut acc = d.clone() * u[i][n + c].clone();
            for j in i + 1..n {
                acc = acc - u[i][j].clone() * y[j][c].clone();
            }
            y[i][c] = acc
                .divide_exact(&u[i][i])
                .expect("fraction-free back substitution divides exactly");
        }
    }
    let x = y
        .into_iter()
        .map(|r| {
            r.into_iter()
                .map(|v| F::from_integer_ratio(v, d.clone()).unwrap_or_else(F::zero))
                .collect()
        })
        .collect();
    Matrix::from_rows(x)
}

/// The inverse of a square nonsingular matrix.
///
/// # Errors
/// As [`solve`].
pub fn inverse<F: Field>(a: &Matrix<F>) -> Result<Matrix<F>, LinalgError> {
    let n = a.require_square("inverse")?;
    solve(a, &Matrix::identity(n))
}

/// A reduced row echelon form with its pivot columns.
#[derive(Clone, PartialEq)]
pub struct Rref<F> {
    /// The reduced matrix (pivots one, zeros above and below).
    pub matrix: Matrix<F>,
    /// The pivot column of each nonzero row.
    pub pivot_columns: Vec<usize>,
}

impl<F: Ring> std::fmt::Debug for Rref<F> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "Rref({:?}, pivots {:?})",
            self.matrix, self.pivot_columns
        )
    }
}

/// Gauss–Jordan elimination to the reduced row echelon form.
pub fn rref<F: Field>(a: &Matrix<F>) -> Rref<F> {
    let (int_rows, _) = integer_rows(a);
    // Fraction-free echelon first, then normalise pivots and clear above them in the field.
    let e = bareiss(int_rows, a.cols());
    let mut rows: Vec<Vec<F>> = e
        .rows
        .into_iter()
        .map(|r| {
            r.into_iter()
                .map(|v| F::from_integer_ratio(v, F::Integers::one()).unwrap_or_else(F::zero))
                .collect()
        })
        .collect();
    let mut pivot_columns = Vec::new();
    for &(r, c) in &e.pivots {
        let inv = rows[r][c].inverse().unwrap_or_else(F::zero);
        for v in rows[r].iter_mut() {
            *v = v.clone() * inv.clone();
        }
        for i in 0..rows.len() {
            if i != r && !rows[i][c].is_zero() {
                let f = rows[i][c].clone();
                for j in 0..a.cols() {
                    let v = rows[i][j].clone() - f.clone() * rows[r][j].clone();
                    rows[i][j] = v;
                }
            }
        }
        pivot_columns.push(c);
    }
    let matrix = Matrix::from_fn(a.rows(), a.cols(), |i, j| rows[i][j].clone());
    Rref {
        matrix,
        pivot_columns,
    }
}

/// A basis of the null space `{x : A x = 0}`, one column vector per free variable.
///
/// ```
/// use observer_workbench::algebra::{Rational, Ring};
/// use observer_workbench::linalg::{null_space, Matrix};
/// let r = |v: i64| Rational::from_i64(v);
/// let a = Matrix::from_rows(vec![vec![r(1), r(2)], vec![r(2), r(4)]]).unwrap();
/// let basis = null_space(&a);
/// assert_eq!(basis.len(), 1);
/// assert_eq!(basis[0].to_input(), "[-2; 1]");
/// ```
pub fn null_space<F: Field>(a: &Matrix<F>) -> Vec<Matrix<F>> {
    let r = rref(a);
    let free: Vec<usize> = (0..a.cols())
        .filter(|c| !r.pivot_columns.contains(c))
        .collect();
    free.iter()
        .map(|&f| {
            let mut v = vec![F::zero(); a.cols()];
            v[f] = F::one();
            for (row, &pc) in r.pivot_columns.iter().enumerate() {
                v[pc] = -r.matrix.get(row, f).clone();
            }
            Matrix::column(v)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algebra::{MultiPoly, Rational};

    fn q(rows: &[&[i64]]) -> Matrix<Rational> {
        Matrix::from_rows(
            rows.iter()
                .map(|r| r.iter().map(|&x| Rational::from_i64(x)).collect())
                .collect(),
        )
        .unwrap()
    }

    #[test]
    fn singular_systems_are_reported_with_their_rank() {
        #[rustfmt::skip]
        let a = q(&[&[1, 2, 3],
                    &[2, 4, 6],
                    &[1, 0, 1]]);
        let err = solve(&a, &Matrix::identity(3)).unwrap_err();
        assert_eq!(err, LinalgError::Singular { order: 3, rank: 2 });
        assert_eq!(rank(&a), 2);
        assert_eq!(determinant(&a).unwrap(), Rational::from_i64(0));
    }

    #[test]
    fn inverse_of_the_stoustrup_observability_matrix() {
        // O = [C; CA] for A = [2 -3; 4 -5], C = [1 0] is [1 0; 2 -3].
        #[rustfmt::skip]
        let o = q(&[&[1, 0],
                    &[2, -3]]);
        let inv = inverse(&o).unwrap();
        assert_eq!(inv.to_input(), "[1, 0; 2/3, -1/3]");
        assert_eq!(o.mul(&inv).unwrap(), Matrix::identity(2));
    }

    #[test]
    fn symbolic_determinant_by_bareiss() {
        let v = MultiPoly::var;
        #[rustfmt::skip]
        let a = Matrix::from_rows(vec![
            vec![v("a"), v("b")],
            vec![v("c"), v("d")],
        ]).unwrap();
        let d = determinant_in_domain(&a).unwrap();
        assert_eq!(d, v("a") * v("d") - v("b") * v("c"));
    }
}
