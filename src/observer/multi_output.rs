//! Gains for several outputs, where pole placement leaves `n(p − 1)` entries free: the
//! workbench's two policies. Either the gain is designed exactly from one chosen output (its
//! column by the single-output formulas, the other columns zero), or the free entries are chosen
//! for well-conditioned eigenvectors by the robust float placement (Kautsky–Nichols–Van Dooren)
//! at the roots of the desired polynomial. The optimal choices (minimum norm, minimal dynamical
//! error) are in [`super::optimal`] and [`super::dynamical_error`].

use super::float_check::companion_roots;
use super::gain::{design_with, DesignError, Detail, ObserverDesign};
use super::robust::{robust_observer_gain, RobustError, RobustPlacement};
use super::{Convention, DesiredPolynomial, GainMethod};
use crate::algebra::Rational;
use crate::algebra::{Quadratic, Zero};
use crate::linalg::float::to_nalgebra;
use crate::linalg::Matrix;
use crate::observability::{require_observable, ObservabilityError};

/// Why a multi-output gain could not be designed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MultiOutputError {
    /// The chosen output does not exist.
    #[error("output {output} does not exist (C has {outputs} rows; outputs are numbered from 1)")]
    NoSuchOutput {
        /// The output asked for (1-based).
        output: usize,
        /// Rows of C.
        outputs: usize,
    },
    /// The single-output design failed.
    #[error(transparent)]
    Design(#[from] DesignError),
    /// The pair is not observable.
    #[error(transparent)]
    Observability(#[from] ObservabilityError),
    /// The robust placement failed.
    #[error(transparent)]
    Robust(#[from] RobustError),
    /// The chosen output alone does not observe the state (the pair with all outputs may).
    #[error("output {output} alone does not observe the state: (A, c_{output}) with c_{output} = {row} — {reason}; choose another output, or omit --output for the robust method with every output")]
    OutputNotObserving {
        /// The output (1-based).
        output: usize,
        /// Its row of C, printed.
        row: String,
        /// Why, as the observability test says.
        reason: String,
    },
}

/// The gain designed exactly from output `output` (1-based) alone: its column placed by the
/// single-output method, the other columns zero; the design of that column with it.
///
/// ```
/// use observer_workbench::algebra::{Quadratic, Rational};
/// use observer_workbench::observer::multi_output::gain_from_output;
/// use observer_workbench::observer::{Convention, DesiredPolynomial, Detail, GainMethod};
/// use observer_workbench::syntax::{parse_list, parse_matrix};
/// let m = |s: &str| parse_matrix::<Rational>(s).unwrap();
/// let p = DesiredPolynomial::from_poles(&parse_list::<Quadratic>("-4, -4, -4").unwrap()).unwrap();
/// let (gain, _) = gain_from_output(&m("[-2 1 0; 1 -2 1; 0 1 -2]"), &m("[1 0 0; 0 0 1]"), 1, &p,
///     GainMethod::Ackermann, Convention::AMinusKC, Detail::Summary).unwrap();
/// assert_eq!(gain.to_input(), "[6, 0; 14, 0; 14, 0]"); // Baranowski's G1, eq. (10a)
/// ```
///
/// # Errors
/// [`MultiOutputError`] for an output that does not exist or a failed design.
pub fn gain_from_output(
    a: &Matrix<Rational>,
    c: &Matrix<Rational>,
    output: usize,
    desired: &DesiredPolynomial,
    method: GainMethod,
    convention: Convention,
    detail: Detail,
) -> Result<(Matrix<Quadratic>, ObserverDesign), MultiOutputError> {
    let (n, p) = (a.rows(), c.rows());
    if output == 0 || output > p {
        return Err(MultiOutputError::NoSuchOutput { output, outputs: p });
    }
    let row = c.block(output - 1, output, 0, n);
    let d = design_with(a, &row, desired, method, convention, detail).map_err(|e| match e {
        DesignError::Observability(o) => MultiOutputError::OutputNotObserving {
            output,
            row: row.to_input(),
            reason: o
                .to_string()
                .replace("the pair (A, C)", &format!("the pair (A, c_{output})")),
        },
        e => e.into(),
    })?;
    let gain = Matrix::from_fn(n, p, |i, j| {
        if j == output - 1 {
            d.gain.matrix.get(i, 0).clone()
        } else {
            Quadratic::zero()
        }
    });
    Ok((gain, d))
}

/// The desired polynomial's roots in `f64`: exact where they are rational or quadratic, else
/// the companion matrix's eigenvalues.
pub fn desired_poles_f64(desired: &DesiredPolynomial) -> Vec<(f64, f64)> {
    let companion = || {
        companion_roots(&desired.float)
            .iter()
            .map(|z| (z.re, z.im))
            .collect()
    };
    match desired.rational() {
        Some(p) => {
            let roots = crate::poly::exact_roots(&p);
            if roots.complete() {
                roots
                    .roots
                    .iter()
                    .flat_map(|(x, m)| std::iter::repeat_n(x.to_complex_f64(), *m as usize))
                    .collect()
            } else {
                companion()
            }
        }
        None => companion(),
    }
}

/// The robust float placement at the desired roots; the gain, row by row, in `convention`
/// (`K` of `A − KC` or `L = −K` of `A + LC`).
///
/// # Errors
/// [`MultiOutputError`] for an unobservable pair (with its modes) or a failed placement.
pub fn robust_gain(
    a: &Matrix<Rational>,
    c: &Matrix<Rational>,
    desired: &DesiredPolynomial,
    convention: Convention,
) -> Result<(Vec<Vec<f64>>, RobustPlacement), MultiOutputError> {
    // an unobservable pair is reported as such (with its modes), whatever the rank of C
    require_observable(a, c)?;
    let r = robust_observer_gain(
        &to_nalgebra(a),
        &to_nalgebra(c),
        &desired_poles_f64(desired),
    )?;
    let gain = r
        .gain
        .iter()
        .map(|row| row.iter().map(|x| convention.sign() * x).collect())
        .collect();
    Ok((gain, r))
}
