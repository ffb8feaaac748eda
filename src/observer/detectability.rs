//! Observers for pairs that are not observable. An observer exists — some K makes A − KC stable
//! — exactly when every unobservable mode is stable (the pair is *detectable*): K cannot move
//! those modes, so they stay poles of every observer. Exact design by the Kalman observability
//! decomposition: with V_u a basis of the unobservable subspace ker O_n (A-invariant) completed to
//! T = [V_o V_u],
//!
//! ```text
//! T⁻¹ A T = [A_oo 0; A_uo A_uu],   C T = [C_o 0],
//! ```
//!
//! (A_oo, C_o) is observable, a gain K_o places its r = rank O_n poles, and K = T [K_o; 0] gives
//! det(sI − (A − KC)) = P(s) · det(sI − A_uu): the chosen poles and the fixed, unobservable
//! ones.

use super::DesiredPolynomial;
use super::{design_with, Convention, DesignError, Detail, GainMethod, ObserverDesign};
use crate::algebra::{Quadratic, Rational};
use crate::derivation::Derivation;
use crate::linalg::{self, LinalgError, Matrix};
use crate::observability::{observability_report, ObservabilityError, ObservabilityReport};
use crate::poly::{is_hurwitz, Poly};

/// Why no observer could be designed for the observable part.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DetectabilityError {
    /// The observability analysis failed (shapes).
    #[error(transparent)]
    Observability(#[from] ObservabilityError),
    /// The gain design for the observable part failed.
    #[error(transparent)]
    Design(#[from] DesignError),
    /// A matrix computation failed.
    #[error(transparent)]
    Linalg(#[from] LinalgError),
    /// Nothing is observable.
    #[error("no mode is observable (O_n = 0): every observer has the poles of A, {0}")]
    NothingObservable(String),
}

/// An observer for the observable part of a (possibly unobservable) pair.
#[derive(Debug, Clone)]
pub struct DetectableDesign {
    /// The observability report (unobservable subspace and modes).
    pub report: ObservabilityReport,
    /// Whether every unobservable mode is stable (exact Routh–Hurwitz on their polynomial).
    pub detectable: bool,
    /// T = [V_o V_u].
    pub t: Matrix<Rational>,
    /// T⁻¹ A T.
    pub a_decomposed: Matrix<Rational>,
    /// The gain for (A_oo, C_o), with its derivation.
    pub observable_part: ObserverDesign,
    /// K = T [K_o; 0], in the convention asked for.
    pub gain: Matrix<Quadratic>,
    /// det(sI − (A − KC)), recomputed: P(s) · det(sI − A_uu).
    pub observer_polynomial: Poly<Quadratic>,
    /// The steps.
    pub derivation: Derivation,
}

/// Designs an observer placing the r observable poles at `desired` (degree r = rank O_n); the
/// n − r unobservable poles stay where they are, and the design says whether they are stable.
///
/// # Errors
/// [`DetectabilityError`]: mismatched shapes, several outputs (choose one), a desired polynomial
/// of another degree than r.
pub fn detectable_design(
    a: &Matrix<Rational>,
    c: &Matrix<Rational>,
    desired: &DesiredPolynomial,
    method: GainMethod,
    convention: Convention,
) -> Result<DetectableDesign, DetectabilityError> {
    let report = observability_report(a, c)?;
    let n = a.rows();
    let r = report.rank;
    if r == 0 {
        return Err(DetectabilityError::NothingObservable(
            report.unobservable_eigenvalues.render(),
        ));
    }
    let detectable = is_hurwitz(&report.unobservable_polynomial);
    let mut d = Derivation::new("Observer for the observable part (Kalman decomposition)");
    d.push("O_n", "[C; CA; …; CA^(n−1)]", &report.matrix);
    // V_u (columns) completed with unit columns to T = [V_o V_u]
    let v_u = report
        .unobservable_subspace
        .iter()
        .try_fold(Matrix::zeros(n, 0), |acc: Matrix<Rational>, v| {
            acc.hstack(v)
        })?;
    let completed = super::reduced_order::complete_with_unit_rows(&v_u.transpose()).transpose();
    // completed = [V_u V_o]; reorder to [V_o V_u]
    let v_o = completed.block(0, n, n - r, n);
    let t = v_o.hstack(&v_u)?;
    let t_inv = linalg::inverse(&t)?;
    d.push("T", "[V_o V_u], V_u a basis of ker O_n", &t);
    let a_dec = t_inv.mul(a)?.mul(&t)?;
    let c_dec = c.mul(&t)?;
    d.push("T⁻¹ A T", "[A_oo 0; A_uo A_uu]", &a_dec);
    d.push("C T", "[C_o 0]", &c_dec);
    let a_oo = a_dec.block(0, r, 0, r);
    let c_o = c_dec.block(0, c.rows(), 0, r);
    let observable_part = design_with(
        &a_oo,
        &c_o,
        desired,
        method,
        Convention::AMinusKC,
        Detail::Full,
    )?;
    d.extend(observable_part.derivation.clone());
    let k_o = observable_part.gain.matrix.clone();
    let padded = k_o.vstack(&Matrix::zeros(n - r, 1))?;
    let k = t.map(|x| Quadratic::rational(x.clone())).mul(&padded)?;
    let shown = convention.from_a_minus_kc(&k);
    d.push("K", "T [K_o; 0]", &k);
    // det(sI − (A − KC)) recomputed from K by the rank-one update det(sI − A) +
    // C adj(sI − A) K (only O_n K and det(sI − A) enter, whatever the size of K's numbers):
    // the check `gain` makes, here on the whole plant, so it tests the decomposition too
    let lift = |x: &Rational| Quadratic::rational(x.clone());
    let open_loop = linalg::characteristic_polynomial(&a.map(lift), "s")?;
    let observer_polynomial = super::observer_polynomial(&report.matrix.map(lift), &open_loop, &k)?;
    d.push(
        "det(sI − (A − KC))",
        "P(s) · det(sI − A_uu)",
        &observer_polynomial,
    );
    Ok(DetectableDesign {
        detectable,
        report,
        t,
        a_decomposed: a_dec,
        observable_part,
        gain: shown,
        observer_polynomial,
        derivation: d,
    })
}

impl DetectableDesign {
    /// Whether the recomputed observer polynomial is the desired one times the unobservable
    /// modes' polynomial (exact).
    pub fn polynomial_checks(&self) -> bool {
        let Some(p) = self.observable_part.desired.exact.clone() else {
            return false;
        };
        let u = self
            .report
            .unobservable_polynomial
            .map(|x| Quadratic::rational(x.clone()))
            .with_var("s");
        (p.with_var("s") * u) == self.observer_polynomial
    }
}
