//! Observer and controller canonical forms of single-output (single-input) systems.
//!
//! * Di Ruscio's `ss2ocf` (eq. (16)–(22)): `T_o = (Mᵀ O_n)⁻¹`, with `M` the upper-triangular
//!   Toeplitz matrix whose first row is `[1, a_1, …, a_(n−1)]` (eq. (18)) from
//!   `det(λI − A) = λⁿ + a_1 λⁿ⁻¹ + … + a_n`. The form has `−a_i` in the first column of `A_o`.
//! * Stoustrup's procedure (Lecture 3, "observable canonical form"): `t_n = O⁻¹ e_n`,
//!   `t_(k−1) = A t_k`, `T = [t_1 … t_n]`. Stoustrup writes the first column of `A_o` as
//!   `(a_1, …, a_n)` with `det(λI − A_o) = λⁿ − a_1 λⁿ⁻¹ − … − a_n`: the same matrix, with his
//!   `a_i` the negatives of Di Ruscio's. Both procedures give the same `T` (a tested property).
//! * Controller form through `T_c = C_n M` (Di Ruscio §3.2).

use crate::algebra::Field;
use crate::linalg::{self, LinalgError, Matrix};
use crate::observability::{controllability_matrix, require_observable, ObservabilityError};
use crate::poly::Poly;

/// Which textbook procedure produced the transformation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CanonicalProcedure {
    /// Di Ruscio's `T_o = (Mᵀ O_n)⁻¹`.
    DiRuscio,
    /// Stoustrup's `t_n = O⁻¹ e_n`, `t_(k−1) = A t_k`.
    Stoustrup,
}

/// A canonical form with its working: `x = T x_o`, `A_o = T⁻¹AT`, `B_o = T⁻¹B`, `C_o = CT`.
#[derive(Clone, PartialEq, Debug)]
pub struct CanonicalForm<F: Field> {
    /// The procedure used.
    pub procedure: CanonicalProcedure,
    /// `det(λI − A)`.
    pub open_loop: Poly<F>,
    /// `O_n` (observer form) or `C_n` (controller form).
    pub test_matrix: Matrix<F>,
    /// The Toeplitz matrix `M` of eq. (18).
    pub toeplitz: Matrix<F>,
    /// `T`.
    pub t: Matrix<F>,
    /// `T⁻¹`.
    pub t_inv: Matrix<F>,
    /// `A_o = T⁻¹AT`.
    pub a: Matrix<F>,
    /// `B_o = T⁻¹B` (zero columns if no B was given).
    pub b: Matrix<F>,
    /// `C_o = CT`.
    pub c: Matrix<F>,
}

/// Why a canonical form could not be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CanonicalFormError {
    /// Only single-output (observer form) or single-input (controller form) systems have it here.
    #[error("the {form} canonical form needs a single {what}; the system has {found}")]
    NotSingle {
        /// `"observer"` or `"controller"`.
        form: &'static str,
        /// `"output"` or `"input"`.
        what: &'static str,
        /// How many there are.
        found: usize,
    },
    /// The pair is not observable.
    #[error(transparent)]
    Observability(#[from] ObservabilityError),
    /// The pair is not controllable.
    #[error("the pair (A, B) is not controllable: rank of the controllability matrix is {rank}, the order is {order}")]
    Uncontrollable {
        /// Rank of `C_n`.
        rank: usize,
        /// Order.
        order: usize,
    },
    /// A matrix computation failed.
    #[error(transparent)]
    Linalg(#[from] LinalgError),
}

/// Di Ruscio's `M`: upper triangular Toeplitz, first row `[1, a_1, …, a_(n−1)]` (eq. (18)).
pub fn toeplitz_m<F: Field>(open_loop: &Poly<F>) -> Matrix<F> {
    let n = open_loop.degree().unwrap_or(0);
    // a_k is the coefficient of λ^(n−k)
    Matrix::from_fn(n, n, |i, j| {
        if j >= i {
            open_loop.coeff(n - (j - i))
        } else {
            F::zero()
        }
    })
}

/// The pieces every procedure computes before the transformation is applied.
struct Working<F: Field> {
    open_loop: Poly<F>,
    test_matrix: Matrix<F>,
    toeplitz: Matrix<F>,
    t: Matrix<F>,
    /// `T⁻¹` when the procedure already has it (Di Ruscio's `T_o⁻¹ = Mᵀ O_n`).
    t_inv: Option<Matrix<F>>,
}

fn finish<F: Field>(
    procedure: CanonicalProcedure,
    a: &Matrix<F>,
    b: Option<&Matrix<F>>,
    c: &Matrix<F>,
    w: Working<F>,
) -> Result<CanonicalForm<F>, LinalgError> {
    let Working {
        open_loop,
        test_matrix,
        toeplitz,
        t,
        t_inv,
    } = w;
    let t_inv = match t_inv {
        Some(t_inv) => t_inv,
        None => linalg::inverse(&t)?,
    };
    let n = a.rows();
    let b = b.cloned().unwrap_or_else(|| Matrix::zeros(n, 0));
    Ok(CanonicalForm {
        procedure,
        a: t_inv.mul(a)?.mul(&t)?,
        b: t_inv.mul(&b)?,
        c: c.mul(&t)?,
        open_loop,
        test_matrix,
        toeplitz,
        t,
        t_inv,
    })
}

fn single_output<F: Field>(c: &Matrix<F>) -> Result<(), CanonicalFormError> {
    if c.rows() == 1 {
        Ok(())
    } else {
        Err(CanonicalFormError::NotSingle {
            form: "observer",
            what: "output",
            found: c.rows(),
        })
    }
}

/// Di Ruscio's `ss2ocf`: `T_o = (Mᵀ O_n)⁻¹`.
///
/// # Example
/// ```
/// use observer_workbench::algebra::Rational;
/// use observer_workbench::canonical_form::observer_form_di_ruscio;
/// use observer_workbench::syntax::parse_matrix;
/// let a = parse_matrix::<Rational>("[2 -3; 4 -5]").unwrap();
/// let c = parse_matrix::<Rational>("[-3 2]").unwrap();
/// let f = observer_form_di_ruscio(&a, None, &c).unwrap();
/// assert_eq!(f.t.to_input(), "[-5, 2; -7, 3]");
/// assert_eq!(f.a.to_input(), "[-3, 1; -2, 0]");
/// ```
///
/// # Errors
/// [`CanonicalFormError`] for several outputs or an unobservable pair.
pub fn observer_form_di_ruscio<F: Field>(
    a: &Matrix<F>,
    b: Option<&Matrix<F>>,
    c: &Matrix<F>,
) -> Result<CanonicalForm<F>, CanonicalFormError> {
    single_output(c)?;
    let o = require_observable(a, c)?;
    let open_loop = linalg::characteristic_polynomial(a, "s")?;
    let m = toeplitz_m(&open_loop);
    let t_inv = m.transpose().mul(&o)?;
    let t = linalg::inverse(&t_inv)?;
    Ok(finish(
        CanonicalProcedure::DiRuscio,
        a,
        b,
        c,
        Working {
            open_loop,
            test_matrix: o,
            toeplitz: m,
            t,
            t_inv: Some(t_inv),
        },
    )?)
}

/// Stoustrup's procedure: `t_n = O⁻¹ e_n`, `t_(k−1) = A t_k`.
///
/// # Errors
/// [`CanonicalFormError`] for several outputs or an unobservable pair.
pub fn observer_form_stoustrup<F: Field>(
    a: &Matrix<F>,
    b: Option<&Matrix<F>>,
    c: &Matrix<F>,
) -> Result<CanonicalForm<F>, CanonicalFormError> {
    single_output(c)?;
    let o = require_observable(a, c)?;
    let open_loop = linalg::characteristic_polynomial(a, "s")?;
    let t = stoustrup_t(a, &o)?;
    let m = toeplitz_m(&open_loop);
    let t_inv = stoustrup_inverse(&t, m.transpose().mul(&o)?)?;
    Ok(finish(
        CanonicalProcedure::Stoustrup,
        a,
        b,
        c,
        Working {
            open_loop,
            test_matrix: o,
            toeplitz: m,
            t,
            t_inv: Some(t_inv),
        },
    )?)
}

/// Stoustrup's `T`: `t_n = O_n⁻¹ e_n`, `t_(k−1) = A t_k`.
fn stoustrup_t<F: Field>(a: &Matrix<F>, o: &Matrix<F>) -> Result<Matrix<F>, LinalgError> {
    let n = a.rows();
    let mut cols = vec![linalg::solve(o, &Matrix::unit(n, n - 1))?];
    for _ in 1..n {
        let next = a.mul(cols.last().expect("nonempty"))?;
        cols.push(next);
    }
    cols.reverse();
    Ok(Matrix::from_fn(n, n, |i, j| cols[j].get(i, 0).clone()))
}

/// The inverse of Stoustrup's T. It should be Di Ruscio's `candidate = Mᵀ O_n`; a product
/// proves it, far cheaper than inverting T, whose entries run to thousands of digits for large
/// n.
fn stoustrup_inverse<F: Field>(
    t: &Matrix<F>,
    candidate: Matrix<F>,
) -> Result<Matrix<F>, LinalgError> {
    if t.mul(&candidate)? == Matrix::identity(t.rows()) {
        Ok(candidate)
    } else {
        linalg::inverse(t)
    }
}

/// Both procedures on one plant, the forms [`observer_form_di_ruscio`] and
/// [`observer_form_stoustrup`] return, sharing what they have in common: Stoustrup's takes O_n,
/// det(sI − A) and M from Di Ruscio's form. Each procedure still builds its own T; when Stoustrup's equals Di Ruscio's
/// (always, in exact arithmetic — they are the same matrix by two routes), its T⁻¹ is Di
/// Ruscio's `Mᵀ O_n` and the transformed (A, B, C) are Di Ruscio's, which are not formed twice;
/// otherwise the second form is finished on its own, as [`observer_form_stoustrup`] does.
///
/// # Errors
/// [`CanonicalFormError`] for several outputs or an unobservable pair.
pub fn observer_forms<F: Field>(
    a: &Matrix<F>,
    b: Option<&Matrix<F>>,
    c: &Matrix<F>,
) -> Result<(CanonicalForm<F>, CanonicalForm<F>), CanonicalFormError> {
    let di = observer_form_di_ruscio(a, b, c)?;
    let t_stoustrup = stoustrup_t(a, &di.test_matrix)?;
    let st = if t_stoustrup == di.t {
        CanonicalForm {
            procedure: CanonicalProcedure::Stoustrup,
            ..di.clone()
        }
    } else {
        let t_inv = stoustrup_inverse(&t_stoustrup, di.t_inv.clone())?;
        finish(
            CanonicalProcedure::Stoustrup,
            a,
            b,
            c,
            Working {
                open_loop: di.open_loop.clone(),
                test_matrix: di.test_matrix.clone(),
                toeplitz: di.toeplitz.clone(),
                t: t_stoustrup,
                t_inv: Some(t_inv),
            },
        )?
    };
    Ok((di, st))
}

/// The controller canonical form through `T_c = C_n M` (Di Ruscio §3.2).
///
/// # Errors
/// [`CanonicalFormError`] for several inputs or an uncontrollable pair.
pub fn controller_form<F: Field>(
    a: &Matrix<F>,
    b: &Matrix<F>,
    c: Option<&Matrix<F>>,
) -> Result<CanonicalForm<F>, CanonicalFormError> {
    if b.cols() != 1 {
        return Err(CanonicalFormError::NotSingle {
            form: "controller",
            what: "input",
            found: b.cols(),
        });
    }
    let n = a.rows();
    let cn = controllability_matrix(a, b)?;
    let rank = linalg::rank(&cn);
    if rank < n {
        return Err(CanonicalFormError::Uncontrollable { rank, order: n });
    }
    let open_loop = linalg::characteristic_polynomial(a, "s")?;
    let m = toeplitz_m(&open_loop);
    let t = cn.mul(&m)?;
    let c = c.cloned().unwrap_or_else(|| Matrix::zeros(0, n));
    Ok(finish(
        CanonicalProcedure::DiRuscio,
        a,
        Some(b),
        &c,
        Working {
            open_loop,
            test_matrix: cn,
            toeplitz: m,
            t,
            t_inv: None,
        },
    )?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algebra::{Quadratic, Rational};

    proptest::proptest! {
        /// Both forms at once are the forms each procedure gives on its own, errors included
        /// (unobservable pairs, several outputs).
        #[test]
        fn both_forms_at_once_are_each_procedures_forms(
            entries in proptest::collection::vec(-3i64..=3, 9),
            c in proptest::collection::vec(-2i64..=2, 6),
            b in proptest::collection::vec(-2i64..=2, 3),
            outputs in 1usize..=2,
            with_b in proptest::prelude::any::<bool>(),
        ) {
            let q = |x: i64| Quadratic::rational(Rational::from_integer(x.into()));
            let a = Matrix::from_fn(3, 3, |i, j| q(entries[3 * i + j]));
            let c = Matrix::from_fn(outputs, 3, |i, j| q(c[3 * i + j]));
            let b = Matrix::from_fn(3, 1, |i, _| q(b[i]));
            let b = with_b.then_some(&b);
            let separately = observer_form_di_ruscio(&a, b, &c)
                .and_then(|di| Ok((di, observer_form_stoustrup(&a, b, &c)?)));
            proptest::prop_assert_eq!(observer_forms(&a, b, &c), separately);
        }
    }
}
