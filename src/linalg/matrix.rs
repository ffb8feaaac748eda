//! The dense matrix container.

use super::{LinalgError, MAX_EXACT_ORDER};
use crate::algebra::{Rational, Ring};
use std::fmt;

/// A dense row-major matrix over a ring.
///
/// Arithmetic is dimension-checked and returns [`LinalgError`] rather than panicking.
///
/// # Example
/// ```
/// use observer_workbench::algebra::{Rational, Ring};
/// use observer_workbench::linalg::Matrix;
/// let a = Matrix::from_rows(vec![
///     vec![Rational::from_i64(2), Rational::from_i64(-3)],
///     vec![Rational::from_i64(4), Rational::from_i64(-5)],
/// ]).unwrap();
/// assert_eq!(a.to_input(), "[2, -3; 4, -5]");
/// let b = Matrix::<Rational>::identity(3);
/// assert!(a.mul(&b).is_err()); // 2×2 times 3×3
/// ```
#[derive(Clone, PartialEq, Eq)]
pub struct Matrix<T> {
    rows: usize,
    cols: usize,
    data: Vec<T>,
}

impl<T: Ring> Matrix<T> {
    /// The `rows × cols` zero matrix.
    pub fn zeros(rows: usize, cols: usize) -> Self {
        Matrix {
            rows,
            cols,
            data: vec![T::zero(); rows * cols],
        }
    }
    /// The identity of order `n`.
    pub fn identity(n: usize) -> Self {
        Matrix::from_fn(n, n, |i, j| if i == j { T::one() } else { T::zero() })
    }
    /// The matrix with entry `(i, j) = f(i, j)`.
    pub fn from_fn(rows: usize, cols: usize, mut f: impl FnMut(usize, usize) -> T) -> Self {
        let mut data = Vec::with_capacity(rows * cols);
        for i in 0..rows {
            for j in 0..cols {
                data.push(f(i, j));
            }
        }
        Matrix { rows, cols, data }
    }
    /// The matrix with the given rows.
    ///
    /// # Errors
    /// [`LinalgError::RaggedRows`] when the rows differ in length, [`LinalgError::TooLarge`]
    /// beyond [`MAX_EXACT_ORDER`].
    pub fn from_rows(rows: Vec<Vec<T>>) -> Result<Self, LinalgError> {
        let n = rows.len();
        let m = rows.first().map_or(0, Vec::len);
        within_limit(n, m)?;
        let mut data = Vec::with_capacity(n * m);
        for (i, r) in rows.into_iter().enumerate() {
            if r.len() != m {
                return Err(LinalgError::RaggedRows {
                    row: i + 1,
                    found: r.len(),
                    expected: m,
                });
            }
            data.extend(r);
        }
        Ok(Matrix {
            rows: n,
            cols: m,
            data,
        })
    }
    /// The `rows × cols` matrix whose entries, row after row, are `data`.
    ///
    /// # Errors
    /// [`LinalgError::TooLarge`] beyond [`MAX_EXACT_ORDER`], [`LinalgError::RaggedRows`] when
    /// `data` does not hold `rows × cols` entries: the first row it leaves short, or the row
    /// after the last holding what is left over.
    pub fn from_row_major(rows: usize, cols: usize, data: Vec<T>) -> Result<Self, LinalgError> {
        within_limit(rows, cols)?;
        let (full, width) = (rows * cols, cols.max(1));
        if data.len() != full {
            let (row, found) = if data.len() < full {
                (data.len() / width + 1, data.len() % width)
            } else {
                (rows + 1, data.len() - full)
            };
            return Err(LinalgError::RaggedRows {
                row,
                found,
                expected: cols,
            });
        }
        Ok(Matrix { rows, cols, data })
    }
    /// A column vector.
    pub fn column(v: Vec<T>) -> Self {
        Matrix {
            rows: v.len(),
            cols: 1,
            data: v,
        }
    }
    /// A row vector.
    pub fn row_vector(v: Vec<T>) -> Self {
        Matrix {
            rows: 1,
            cols: v.len(),
            data: v,
        }
    }
    /// The `k`-th unit column vector of length `n`.
    pub fn unit(n: usize, k: usize) -> Self {
        Matrix::from_fn(n, 1, |i, _| if i == k { T::one() } else { T::zero() })
    }
    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.rows
    }
    /// Number of columns.
    pub fn cols(&self) -> usize {
        self.cols
    }
    /// `(rows, cols)`.
    pub fn shape(&self) -> (usize, usize) {
        (self.rows, self.cols)
    }
    /// Whether the matrix is square.
    pub fn is_square(&self) -> bool {
        self.rows == self.cols
    }
    /// Entry `(i, j)`, zero-based. Panics out of range, like slice indexing.
    pub fn get(&self, i: usize, j: usize) -> &T {
        &self.data[i * self.cols + j]
    }
    /// Sets entry `(i, j)`.
    pub fn set(&mut self, i: usize, j: usize, v: T) {
        self.data[i * self.cols + j] = v;
    }
    /// Row `i` as a slice.
    pub fn row(&self, i: usize) -> &[T] {
        &self.data[i * self.cols..(i + 1) * self.cols]
    }
    /// Column `j`, copied.
    pub fn col(&self, j: usize) -> Vec<T> {
        (0..self.rows).map(|i| self.get(i, j).clone()).collect()
    }
    /// All entries, row by row.
    pub fn entries(&self) -> &[T] {
        &self.data
    }
    /// The rows as vectors.
    pub fn to_rows(&self) -> Vec<Vec<T>> {
        (0..self.rows).map(|i| self.row(i).to_vec()).collect()
    }
    /// The transpose.
    pub fn transpose(&self) -> Self {
        Matrix::from_fn(self.cols, self.rows, |i, j| self.get(j, i).clone())
    }
    /// Every entry mapped.
    pub fn map<S: Ring>(&self, f: impl Fn(&T) -> S) -> Matrix<S> {
        Matrix {
            rows: self.rows,
            cols: self.cols,
            data: self.data.iter().map(f).collect(),
        }
    }
    /// `c · self`.
    pub fn scale(&self, c: &T) -> Self {
        self.map(|x| x.clone() * c.clone())
    }
    /// Whether every entry is zero.
    pub fn is_zero(&self) -> bool {
        self.data.iter().all(T::is_zero)
    }

    fn check_same(&self, other: &Self, operation: &'static str) -> Result<(), LinalgError> {
        if self.shape() == other.shape() {
            Ok(())
        } else {
            Err(self.mismatch(other, operation))
        }
    }
    pub(crate) fn mismatch(&self, other: &Self, operation: &'static str) -> LinalgError {
        LinalgError::DimensionMismatch {
            operation,
            left_rows: self.rows,
            left_cols: self.cols,
            right_rows: other.rows,
            right_cols: other.cols,
        }
    }
    pub(crate) fn require_square(&self, operation: &'static str) -> Result<usize, LinalgError> {
        if self.is_square() {
            Ok(self.rows)
        } else {
            Err(LinalgError::NotSquare {
                operation,
                rows: self.rows,
                cols: self.cols,
            })
        }
    }

    /// `self + other`.
    pub fn add(&self, other: &Self) -> Result<Self, LinalgError> {
        self.check_same(other, "sum")?;
        if let (Some(x), Some(y)) = (super::as_rational(self), super::as_rational(other)) {
            if let Some(r) = crate::algebra::from_concrete(super::rational::add(x, y, false)) {
                return Ok(r);
            }
        }
        if let Some(r) = self.rational_in_quadratic(other, |x, y| super::rational::add(x, y, false))
        {
            return Ok(r);
        }
        Ok(Matrix::from_fn(self.rows, self.cols, |i, j| {
            self.get(i, j).clone() + other.get(i, j).clone()
        }))
    }
    /// `self − other`.
    pub fn sub(&self, other: &Self) -> Result<Self, LinalgError> {
        self.check_same(other, "difference")?;
        if let (Some(x), Some(y)) = (super::as_rational(self), super::as_rational(other)) {
            if let Some(r) = crate::algebra::from_concrete(super::rational::add(x, y, true)) {
                return Ok(r);
            }
        }
        if let Some(r) = self.rational_in_quadratic(other, |x, y| super::rational::add(x, y, true))
        {
            return Ok(r);
        }
        Ok(Matrix::from_fn(self.rows, self.cols, |i, j| {
            self.get(i, j).clone() - other.get(i, j).clone()
        }))
    }
    /// `op` on the rational path when both are Q(√d) matrices whose entries are all rational
    /// (a rational design carried over Q(√d) because a desired polynomial may bring √d): the
    /// fraction-free kernels, without a gcd per Q(√d) operation; `None` otherwise.
    fn rational_in_quadratic(
        &self,
        other: &Self,
        op: impl Fn(&Matrix<Rational>, &Matrix<Rational>) -> Matrix<Rational>,
    ) -> Option<Self> {
        let (x, y) = (super::as_quadratic(self)?, super::as_quadratic(other)?);
        let (qx, qy) = (super::rational_entries(x)?, super::rational_entries(y)?);
        let result = op(&qx, &qy).map(|r| crate::algebra::Quadratic::rational(r.clone()));
        crate::algebra::from_concrete(result)
    }
    /// `−self`.
    pub fn neg(&self) -> Self {
        self.map(|x| -x.clone())
    }
    /// The product `self · other`.
    pub fn mul(&self, other: &Self) -> Result<Self, LinalgError> {
        if self.cols != other.rows {
            return Err(self.mismatch(other, "product"));
        }
        if let (Some(x), Some(y)) = (super::as_rational(self), super::as_rational(other)) {
            if let Some(r) = crate::algebra::from_concrete(super::rational::mul(x, y)) {
                return Ok(r);
            }
        }
        // Q(√d) matrices whose entries are all rational (a rational design checked over Q(√d)
        // because a desired polynomial may bring √d): the same fraction-free product, without
        // a gcd per Q(√d) operation
        if let Some(r) = self.rational_in_quadratic(other, super::rational::mul) {
            return Ok(r);
        }
        let mut out = Matrix::<T>::zeros(self.rows, other.cols);
        for i in 0..self.rows {
            for k in 0..self.cols {
                let a = self.get(i, k);
                if a.is_zero() {
                    continue;
                }
                for j in 0..other.cols {
                    let idx = i * out.cols + j;
                    out.data[idx] = out.data[idx].clone() + a.clone() * other.get(k, j).clone();
                }
            }
        }
        Ok(out)
    }
    /// Rows stacked: `[self; other]`.
    pub fn vstack(&self, other: &Self) -> Result<Self, LinalgError> {
        if self.cols != other.cols && self.rows > 0 && other.rows > 0 {
            return Err(self.mismatch(other, "vertical stack"));
        }
        let mut data = self.data.clone();
        data.extend(other.data.iter().cloned());
        Ok(Matrix {
            rows: self.rows + other.rows,
            cols: self.cols.max(other.cols),
            data,
        })
    }
    /// Columns side by side: `[self, other]`.
    pub fn hstack(&self, other: &Self) -> Result<Self, LinalgError> {
        if self.rows != other.rows {
            return Err(self.mismatch(other, "horizontal stack"));
        }
        Ok(Matrix::from_fn(
            self.rows,
            self.cols + other.cols,
            |i, j| {
                if j < self.cols {
                    self.get(i, j).clone()
                } else {
                    other.get(i, j - self.cols).clone()
                }
            },
        ))
    }
    /// The block of rows `r0..r1`, columns `c0..c1`.
    pub fn block(&self, r0: usize, r1: usize, c0: usize, c1: usize) -> Self {
        Matrix::from_fn(r1 - r0, c1 - c0, |i, j| self.get(r0 + i, c0 + j).clone())
    }
    /// The trace.
    pub fn trace(&self) -> T {
        (0..self.rows.min(self.cols)).fold(T::zero(), |acc, i| acc + self.get(i, i).clone())
    }
    /// `self^k` for a square matrix.
    pub fn pow(&self, k: u32) -> Result<Self, LinalgError> {
        let n = self.require_square("power")?;
        let mut out = Matrix::<T>::identity(n);
        for _ in 0..k {
            out = out.mul(self)?;
        }
        Ok(out)
    }

    /// Aligned rows for a terminal, one row per line: `[ 2  -3 ]`.
    pub fn render(&self) -> String {
        let cells: Vec<String> = self.data.iter().map(|x| x.to_string()).collect();
        layout_text(self.rows, self.cols, &cells)
    }
    /// Input syntax: `[2, -3; 4, -5]`.
    pub fn to_input(&self) -> String {
        let cells: Vec<String> = self.data.iter().map(|x| x.to_input()).collect();
        layout_input(self.rows, self.cols, &cells)
    }
    /// LaTeX `bmatrix`.
    pub fn to_latex(&self) -> String {
        let cells: Vec<String> = self.data.iter().map(|x| x.to_latex()).collect();
        layout_latex(self.rows, self.cols, &cells)
    }
    /// `(render, to_latex, to_input)` at once. For rationals each entry's digits are produced
    /// once and shared by the three forms (a large exact result has millions of digits, and
    /// decimal conversion is then most of the cost of showing it).
    pub fn renderings(&self) -> (String, String, String) {
        let (text, latex, input, _) = self.renderings_with_cells();
        (text, latex, input)
    }
    /// [`Matrix::renderings`] and, when they were produced on the way (rational entries), the
    /// entries in input syntax, row-major.
    pub fn renderings_with_cells(&self) -> (String, String, String, Option<Vec<String>>) {
        if let Some(q) = super::as_rational(self) {
            let mut text = Vec::with_capacity(self.data.len());
            let mut latex = Vec::with_capacity(self.data.len());
            // each distinct long denominator converted once: a matrix computed over one
            // denominator (a gain, A − KC) holds a handful of them, as long as its numerators
            // and interleaved (half the digits of a reduced observer's F at order 60); a
            // denominator within a word is converted where it stands, as quickly as it is found
            let mut seen: Vec<(&num_bigint::BigInt, String)> = Vec::new();
            for x in q.entries() {
                let numer = crate::algebra::decimal::decimal(x.numer());
                let word;
                let denom = if x.denom().bits() < 64 {
                    word = crate::algebra::decimal::decimal(x.denom());
                    word.as_str()
                } else {
                    let at = match seen.iter().position(|(d, _)| *d == x.denom()) {
                        Some(at) => at,
                        None => {
                            if seen.len() == DENOMINATORS_KEPT {
                                seen.remove(0);
                            }
                            seen.push((x.denom(), crate::algebra::decimal::decimal(x.denom())));
                            seen.len() - 1
                        }
                    };
                    seen[at].1.as_str()
                };
                latex.push(crate::algebra::latex_of_parts(&numer, denom));
                text.push(crate::algebra::input_of_parts(numer, denom));
            }
            return (
                layout_text(self.rows, self.cols, &text),
                layout_latex(self.rows, self.cols, &latex),
                layout_input(self.rows, self.cols, &text),
                Some(text),
            );
        }
        // a Q(√d) matrix with rational entries (the reduced-order observer's F, G, …) renders
        // as its rational matrix: each entry converted to decimal once, not once per format
        if let Some(r) = super::as_quadratic(self).and_then(super::rational_entries) {
            return r.renderings_with_cells();
        }
        (self.render(), self.to_latex(), self.to_input(), None)
    }
}

/// How many distinct denominators [`Matrix::renderings_with_cells`] keeps in decimal (the
/// most recent; a reduced observer's F at order 60 has seven).
const DENOMINATORS_KEPT: usize = 16;

/// Row-major cells aligned in columns, one row per line: `[ ` and the row's cells, each padded on
/// the left to its column's width and separated by two spaces, then ` ]`. Written into one
/// buffer (a cell is copied once, not formatted into a row and joined again).
fn layout_text(rows: usize, cols: usize, cells: &[String]) -> String {
    if rows == 0 || cols == 0 {
        return format!("[] ({rows}×{cols})");
    }
    let counts: Vec<usize> = cells.iter().map(|c| c.chars().count()).collect();
    let widths: Vec<usize> = (0..cols)
        .map(|j| (0..rows).map(|i| counts[i * cols + j]).max().unwrap_or(0))
        .collect();
    let bytes: usize = cells.iter().map(String::len).sum();
    let mut out =
        String::with_capacity(bytes + rows * (widths.iter().sum::<usize>() + 2 * cols + 4));
    for i in 0..rows {
        if i > 0 {
            out.push('\n');
        }
        out.push_str("[ ");
        for j in 0..cols {
            if j > 0 {
                out.push_str("  ");
            }
            let k = i * cols + j;
            out.extend(std::iter::repeat_n(' ', widths[j] - counts[k]));
            out.push_str(&cells[k]);
        }
        out.push_str(" ]");
    }
    out
}

/// Row-major cells joined with `col_sep` and `row_sep` between `open` and `close`, written
/// into one string of exactly its length (each cell copied once).
fn join_cells(
    rows: usize,
    cols: usize,
    cells: &[String],
    [open, col_sep, row_sep, close]: [&str; 4],
) -> String {
    let bytes: usize = cells.iter().map(String::len).sum::<usize>()
        + open.len()
        + close.len()
        + rows * cols.saturating_sub(1) * col_sep.len()
        + rows.saturating_sub(1) * row_sep.len();
    let mut out = String::with_capacity(bytes);
    out.push_str(open);
    for i in 0..rows {
        if i > 0 {
            out.push_str(row_sep);
        }
        for (j, cell) in cells[i * cols..(i + 1) * cols].iter().enumerate() {
            if j > 0 {
                out.push_str(col_sep);
            }
            out.push_str(cell);
        }
    }
    out.push_str(close);
    out
}

fn layout_input(rows: usize, cols: usize, cells: &[String]) -> String {
    join_cells(rows, cols, cells, ["[", ", ", "; ", "]"])
}

fn layout_latex(rows: usize, cols: usize, cells: &[String]) -> String {
    join_cells(
        rows,
        cols,
        cells,
        ["\\begin{bmatrix} ", " & ", " \\\\ ", " \\end{bmatrix}"],
    )
}

impl<T: Ring> fmt::Display for Matrix<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.render())
    }
}

impl<T: Ring> fmt::Debug for Matrix<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.to_input())
    }
}

/// [`LinalgError::TooLarge`] for a size beyond [`MAX_EXACT_ORDER`].
fn within_limit(rows: usize, cols: usize) -> Result<(), LinalgError> {
    if rows > MAX_EXACT_ORDER || cols > MAX_EXACT_ORDER {
        return Err(LinalgError::TooLarge {
            rows,
            cols,
            limit: MAX_EXACT_ORDER,
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Entries row after row make the matrix `from_rows` makes; too few or too many are the
    /// ragged row they leave, and a size beyond the limit is refused first.
    #[test]
    fn from_row_major_is_from_rows() {
        let rows: Vec<Vec<f64>> = vec![vec![1.0, 2.0, 3.0], vec![4.0, 5.0, 6.0]];
        let flat: Vec<f64> = rows.concat();
        assert_eq!(
            Matrix::from_row_major(2, 3, flat.clone()),
            Matrix::from_rows(rows)
        );
        // too few: the error from_rows gives for the same entries cut into rows of three
        for short in [4, 3] {
            let cut: Vec<Vec<f64>> = vec![flat[..3].to_vec(), flat[3..short].to_vec()];
            assert_eq!(
                Matrix::from_row_major(2, 3, flat[..short].to_vec()).unwrap_err(),
                Matrix::from_rows(cut).unwrap_err()
            );
        }
        // too many: the row after the last, holding the three left over
        assert!(matches!(
            Matrix::from_row_major(1, 3, flat.clone()),
            Err(LinalgError::RaggedRows {
                row: 2,
                found: 3,
                expected: 3
            })
        ));
        assert!(matches!(
            Matrix::from_row_major(MAX_EXACT_ORDER + 1, 1, vec![0.0; MAX_EXACT_ORDER + 1]),
            Err(LinalgError::TooLarge { .. })
        ));
    }
}
