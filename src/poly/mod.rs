//! Polynomials in one variable and rational functions (transfer functions).
//!
//! [`Poly`] works over any [`Ring`](crate::algebra::Ring) (arithmetic, evaluation, derivative)
//! and over any [`Field`](crate::algebra::Field) (Euclidean division, monic gcd, square-free
//! factorisation, construction from roots). Over the rationals, [`Factored`] finds the exact
//! linear factors, so that the workbench can say `(s + 4)^3` rather than `s^3 + 12s^2 + 48s + 64`.
//! [`RationalFunction`] keeps a transfer function in lowest terms with a monic denominator.

mod factor;
mod fraction_gcd;
mod integer_gcd;
pub(crate) use integer_gcd::divide_exact_integers;
mod kronecker;
mod quadratic_gcd;
mod rational_function;
mod stability;
mod univariate;

pub use factor::{exact_roots, rational_roots, ExactRoots, Factored, RootSearch};
pub use rational_function::RationalFunction;
pub use stability::{has_unit_circle_root, is_hurwitz, is_schur};
pub use univariate::Poly;
