//! Exact (and float) linear algebra written once over the ring traits.
//!
//! * [`Matrix`]: a small dense container with dimension-checked arithmetic.
//! * [`elimination`]: fraction-free Bareiss elimination (determinant, rank, solve, inverse) and
//!   Gauss–Jordan (reduced row echelon form, null space). Over the rationals every elimination
//!   first clears denominators row by row and runs on integers.
//! * [`charpoly`]: the characteristic polynomial by Berkowitz's division-free algorithm (so it
//!   runs over the symbolic ring too), matrix polynomials `P(A)` and `P(A)·v` by Horner.
//! * [`definiteness`]: exact positive semidefiniteness of symmetric matrices.
//! * [`kronecker`](mod@kronecker): Kronecker products and `vec`, for Lyapunov equations.
//! * [`lyapunov`]: `F X + X Fᵀ + W = 0`, exact (vectorised) and in `f64` (Bartels–Stewart).
//! * [`float`]: the `f64` side through nalgebra: eigenvalues, singular values, condition numbers.
//! * [`expm`](mod@expm): the matrix exponential in `f64` (scaling and squaring, Padé).
//! * [`gemm`]: the `f64` matrix product, nalgebra's bits without its first `cpuid`.
//! * [`cpu`]: the processor's vector instructions, read from the C library where it has them.

pub mod charpoly;
pub mod cpu;
pub mod definiteness;
pub mod elimination;
pub mod expm;
pub mod float;
pub mod gemm;
pub mod kronecker;
mod limbs;
pub mod lyapunov;
mod matrix;
pub mod modular;
mod rational;

pub(crate) use charpoly::{adjugate_product_on_integers, rank_one_update};
pub use charpoly::{
    berkowitz, characteristic_polynomial, matrix_polynomial, polynomial_times_solution,
    polynomial_times_vector,
};
pub use elimination::{determinant, inverse, null_space, rank, rref, solve, Rref};
pub use kronecker::{kronecker, vectorize};
pub use matrix::Matrix;
pub(crate) use rational::mul_over_one_denominator;

/// From this order on, exact rational problems go through [`modular`] (multimodular, certified)
/// instead of fraction-free elimination or Berkowitz, which are faster below it.
pub const MODULAR_FROM_ORDER: usize = 8;

/// `Some(&Matrix<Rational>)` when `F` is the rationals: the dispatch to the multimodular path.
pub(crate) fn as_rational<F: crate::algebra::Ring>(
    a: &Matrix<F>,
) -> Option<&Matrix<crate::algebra::Rational>> {
    (a as &dyn std::any::Any).downcast_ref::<Matrix<crate::algebra::Rational>>()
}

/// `Some(&Matrix<Quadratic>)` when `F` is Q(√d): the dispatch of its all-rational matrices to
/// the rational path.
pub(crate) fn as_quadratic<F: crate::algebra::Ring>(
    a: &Matrix<F>,
) -> Option<&Matrix<crate::algebra::Quadratic>> {
    (a as &dyn std::any::Any).downcast_ref::<Matrix<crate::algebra::Quadratic>>()
}

/// The rational matrix a Q(√d) matrix is, when every entry is rational: the way onto the
/// rational (fraction-free, multimodular) path, which takes no gcd per Q(√d) operation.
pub fn rational_entries(
    m: &Matrix<crate::algebra::Quadratic>,
) -> Option<Matrix<crate::algebra::Rational>> {
    m.entries()
        .iter()
        .all(|x| x.as_rational().is_some())
        .then(|| m.map(|x| x.as_rational().cloned().unwrap_or_default()))
}

/// The largest matrix order the exact algorithms accept; larger inputs are refused with
/// [`LinalgError::TooLarge`] instead of running for hours.
pub const MAX_EXACT_ORDER: usize = 200;

/// What went wrong in a matrix computation, with the evidence.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum LinalgError {
    /// Operand shapes do not fit the operation.
    #[error("{operation}: dimension mismatch, left is {left_rows}×{left_cols}, right is {right_rows}×{right_cols}")]
    DimensionMismatch {
        /// The operation attempted (`"product"`, `"solve"`…).
        operation: &'static str,
        /// Rows of the left operand.
        left_rows: usize,
        /// Columns of the left operand.
        left_cols: usize,
        /// Rows of the right operand.
        right_rows: usize,
        /// Columns of the right operand.
        right_cols: usize,
    },
    /// A square matrix was needed.
    #[error("{operation}: the matrix must be square, it is {rows}×{cols}")]
    NotSquare {
        /// The operation attempted.
        operation: &'static str,
        /// Rows found.
        rows: usize,
        /// Columns found.
        cols: usize,
    },
    /// The matrix is singular.
    #[error("the {order}×{order} matrix is singular (rank {rank})")]
    Singular {
        /// The order of the matrix.
        order: usize,
        /// Its rank.
        rank: usize,
    },
    /// The rows given have different lengths.
    #[error("row {row} has {found} entries, the first row has {expected}")]
    RaggedRows {
        /// The offending row (1-based).
        row: usize,
        /// Entries in that row.
        found: usize,
        /// Entries in the first row.
        expected: usize,
    },
    /// A matrix beyond [`MAX_EXACT_ORDER`].
    #[error("a {rows}×{cols} matrix is larger than the exact algorithms accept ({limit}×{limit})")]
    TooLarge {
        /// Rows found.
        rows: usize,
        /// Columns found.
        cols: usize,
        /// The limit.
        limit: usize,
    },
}
