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

/// A transfer function that has no state-space realisation of positive order.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum RealisationError {
    /// More zeros than poles: no proper realisation.
    #[error("G(s) is improper (numerator degree {numerator} > denominator degree {denominator}): no state-space model realises it")]
    Improper {
        /// Degree of the numerator.
        numerator: usize,
        /// Degree of the denominator.
        denominator: usize,
    },
    /// A constant: order 0, nothing to observe.
    #[error("G(s) = {0} is a constant (no poles after cancelling common factors): there is no state to observe")]
    Static(String),
}

/// The observer canonical form of a SISO transfer function, exact: for
/// `G(s) = D + (β_{n−1} s^{n−1} + … + β₀)/(sⁿ + a_{n−1} s^{n−1} + … + a₀)` (in lowest terms, the
/// denominator monic),
///
/// ```text
///     ⎡ −a_{n−1}  1  0 … 0 ⎤       ⎡ β_{n−1} ⎤
/// A = ⎢ −a_{n−2}  0  1 … 0 ⎥   B = ⎢    ⋮    ⎥   C = [1 0 … 0],   D = [D]
///     ⎢    ⋮            ⋱  ⎥       ⎣   β₀    ⎦
///     ⎣   −a₀     0  0 … 0 ⎦
/// ```
///
/// so `C (sI − A)⁻¹ B + D = G(s)`: the denominator's coefficients down the first column, the
/// numerator's in B, and C reads the first state. The pair (A, C) is observable by construction
/// and, the fraction being in lowest terms, (A, B) controllable: a minimal realisation.
///
/// ```
/// use observer_workbench::algebra::Rational;
/// use observer_workbench::syntax::parse_rational_function;
/// use observer_workbench::system::observer_form_of;
/// let g = parse_rational_function::<Rational>("(s + 1)/(s^2 + 3s + 5)", "s").unwrap();
/// let (a, b, c, d) = observer_form_of(&g).unwrap();
/// assert_eq!(a.to_input(), "[-3, 1; -5, 0]");
/// assert_eq!((b.to_input(), c.to_input(), d.to_input()), ("[1; 1]".into(), "[1, 0]".into(), "[0]".into()));
/// ```
///
/// # Errors
/// [`RealisationError`] for an improper or constant `G`.
#[allow(clippy::type_complexity)]
pub fn observer_form_of<F: crate::algebra::Field>(
    g: &crate::poly::RationalFunction<F>,
) -> Result<(Matrix<F>, Matrix<F>, Matrix<F>, Matrix<F>), RealisationError> {
    let (num, den) = (g.numerator(), g.denominator());
    let n = den.degree().unwrap_or(0);
    let m = num.degree().unwrap_or(0);
    if m > n {
        return Err(RealisationError::Improper {
            numerator: m,
            denominator: n,
        });
    }
    if n == 0 {
        return Err(RealisationError::Static(g.to_string()));
    }
    // the feedthrough, and the strictly proper remainder β = num − D·den
    let d = if m == n { num.coeff(n) } else { F::zero() };
    let beta: Vec<F> = (0..n)
        .map(|k| num.coeff(k) - d.clone() * den.coeff(k))
        .collect();
    let mut a = Matrix::zeros(n, n);
    let mut b = Matrix::zeros(n, 1);
    for i in 0..n {
        // row i: −a_{n−1−i} in the first column, 1 just right of the diagonal
        a.set(i, 0, -den.coeff(n - 1 - i));
        if i + 1 < n {
            a.set(i, i + 1, F::one());
        }
        b.set(i, 0, beta[n - 1 - i].clone());
    }
    let mut c = Matrix::zeros(1, n);
    c.set(0, 0, F::one());
    let mut dm = Matrix::zeros(1, 1);
    dm.set(0, 0, d);
    Ok((a, b, c, dm))
}
