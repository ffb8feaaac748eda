//! The state-space model `ẋ = Ax + Bu, y = Cx + Du`, dimension-checked at construction.

use crate::algebra::Ring;
use crate::linalg::Matrix;

/// Why a state-space model could not be formed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SystemError {
    /// `A` is not square.
    #[error("A must be square, it is {rows}×{cols}")]
    NonSquareA {
        /// Rows of A.
        rows: usize,
        /// Columns of A.
        cols: usize,
    },
    /// A matrix does not fit the order or the other matrices.
    #[error("{matrix} is {rows}×{cols}, expected {expected}")]
    Shape {
        /// Which matrix (`"B"`, `"C"`, `"D"`).
        matrix: &'static str,
        /// Rows found.
        rows: usize,
        /// Columns found.
        cols: usize,
        /// What was expected, e.g. `"2 rows (the order of A)"`.
        expected: String,
    },
}

/// A linear time-invariant model; `B` and `D` may have zero columns (no input).
#[derive(Clone, PartialEq, Debug)]
pub struct StateSpace<T: Ring> {
    a: Matrix<T>,
    b: Matrix<T>,
    c: Matrix<T>,
    d: Matrix<T>,
}

impl<T: Ring> StateSpace<T> {
    /// `(A, B, C, D)`; `B = None` means no input, `D = None` means `D = 0`.
    ///
    /// # Errors
    /// [`SystemError`] naming the matrix whose shape does not fit.
    ///
    /// # Example
    /// ```
    /// use observer_workbench::algebra::Rational;
    /// use observer_workbench::syntax::parse_matrix;
    /// use observer_workbench::system::StateSpace;
    /// let a = parse_matrix::<Rational>("[2 -3; 4 -5]").unwrap();
    /// let c = parse_matrix::<Rational>("[-3 2 1]").unwrap();
    /// let err = StateSpace::new(a, None, c, None).unwrap_err();
    /// assert_eq!(err.to_string(), "C is 1×3, expected 2 columns (the order of A)");
    /// ```
    pub fn new(
        a: Matrix<T>,
        b: Option<Matrix<T>>,
        c: Matrix<T>,
        d: Option<Matrix<T>>,
    ) -> Result<Self, SystemError> {
        let n = a.rows();
        let b = b.unwrap_or_else(|| Matrix::zeros(n, 0));
        let d = d.unwrap_or_else(|| Matrix::zeros(c.rows(), b.cols()));
        Self::check_shapes(&a, Some(&b), &c, Some(&d))?;
        Ok(StateSpace { a, b, c, d })
    }
    /// Whether `(A, B, C, D)` fit together, without building the model (`B = None`: no input,
    /// `D = None`: zero).
    ///
    /// # Errors
    /// [`SystemError`] naming the matrix whose shape does not fit.
    pub fn check_shapes(
        a: &Matrix<T>,
        b: Option<&Matrix<T>>,
        c: &Matrix<T>,
        d: Option<&Matrix<T>>,
    ) -> Result<(), SystemError> {
        if !a.is_square() {
            return Err(SystemError::NonSquareA {
                rows: a.rows(),
                cols: a.cols(),
            });
        }
        let n = a.rows();
        let inputs = b.map_or(0, Matrix::cols);
        if let Some(b) = b.filter(|b| b.rows() != n) {
            return Err(SystemError::Shape {
                matrix: "B",
                rows: b.rows(),
                cols: b.cols(),
                expected: format!("{n} rows (the order of A)"),
            });
        }
        if c.cols() != n {
            return Err(SystemError::Shape {
                matrix: "C",
                rows: c.rows(),
                cols: c.cols(),
                expected: format!("{n} columns (the order of A)"),
            });
        }
        if let Some(d) = d.filter(|d| d.shape() != (c.rows(), inputs)) {
            return Err(SystemError::Shape {
                matrix: "D",
                rows: d.rows(),
                cols: d.cols(),
                expected: format!("{}×{inputs} (outputs × inputs)", c.rows()),
            });
        }
        Ok(())
    }
    /// The system matrix.
    pub fn a(&self) -> &Matrix<T> {
        &self.a
    }
    /// The input matrix.
    pub fn b(&self) -> &Matrix<T> {
        &self.b
    }
    /// The output matrix.
    pub fn c(&self) -> &Matrix<T> {
        &self.c
    }
    /// The feedthrough matrix.
    pub fn d(&self) -> &Matrix<T> {
        &self.d
    }
    /// The order `n`.
    pub fn order(&self) -> usize {
        self.a.rows()
    }
    /// The number of inputs.
    pub fn inputs(&self) -> usize {
        self.b.cols()
    }
    /// The number of outputs.
    pub fn outputs(&self) -> usize {
        self.c.rows()
    }
    /// Every matrix mapped into another number type.
    pub fn map<S: Ring>(&self, f: impl Fn(&T) -> S + Copy) -> StateSpace<S> {
        StateSpace {
            a: self.a.map(f),
            b: self.b.map(f),
            c: self.c.map(f),
            d: self.d.map(f),
        }
    }
}
