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
use crate::algebra::{Fraction, Quadratic, Rational};
use crate::derivation::Derivation;
use crate::linalg::{self, LinalgError, Matrix};
use crate::observability::{observability_rank_report, ObservabilityError, ObservabilityReport};
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

/// The Kalman observability decomposition, over any field.
struct Decomposition<F> {
    /// T = [V_o V_u].
    t: Matrix<F>,
    /// Whether T = I (an observable pair): no change of basis to apply.
    identity: bool,
    /// T⁻¹ A T = [A_oo 0; A_uo A_uu].
    a_decomposed: Matrix<F>,
    /// The observable part's A_oo (r × r).
    a_oo: Matrix<F>,
    /// The observable part's C_o.
    c_o: Matrix<F>,
}

/// V_u, a basis of ker O_n (its `n − r` columns), completed with unit columns to
/// T = [V_o V_u]; T⁻¹ A T and C T, and the observable part's blocks; the steps pushed to `d`
/// (`o` is O_n).
fn decompose<F: crate::algebra::Field>(
    a: &Matrix<F>,
    c: &Matrix<F>,
    o: &Matrix<F>,
    basis: &[Matrix<F>],
    r: usize,
    d: &mut Derivation,
) -> Result<Decomposition<F>, LinalgError> {
    let n = a.rows();
    d.push("O_n", "[C; CA; …; CA^(n−1)]", o);
    let v_u = basis
        .iter()
        .try_fold(Matrix::zeros(n, 0), |acc: Matrix<F>, v| acc.hstack(v))?;
    // completed = [V_u V_o]; reorder to [V_o V_u]
    let completed = super::reduced_order::complete_with_unit_rows(&v_u.transpose()).transpose();
    let v_o = completed.block(0, n, n - r, n);
    let t = v_o.hstack(&v_u)?;
    d.push("T", "[V_o V_u], V_u a basis of ker O_n", &t);
    // an observable pair needs no change of basis: T = I (two products of order n saved)
    let identity = t == Matrix::identity(n);
    let (a_decomposed, c_dec) = if identity {
        (a.clone(), c.clone())
    } else {
        let t_inv = linalg::inverse(&t)?;
        (t_inv.mul(a)?.mul(&t)?, c.mul(&t)?)
    };
    d.push("T⁻¹ A T", "[A_oo 0; A_uo A_uu]", &a_decomposed);
    d.push("C T", "[C_o 0]", &c_dec);
    Ok(Decomposition {
        a_oo: a_decomposed.block(0, r, 0, r),
        c_o: c_dec.block(0, c.rows(), 0, r),
        t,
        identity,
        a_decomposed,
    })
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
    let report = observability_rank_report(a, c)?;
    detectable_design_from(report, a, c, desired, method, convention)
}

/// [`detectable_design`] from the pair's observability report, when the caller has it
/// already (the command reads the desired polynomial's degree, rank O_n, from it).
///
/// # Errors
/// As [`detectable_design`].
pub fn detectable_design_from(
    report: ObservabilityReport,
    a: &Matrix<Rational>,
    c: &Matrix<Rational>,
    desired: &DesiredPolynomial,
    method: GainMethod,
    convention: Convention,
) -> Result<DetectableDesign, DetectabilityError> {
    let n = a.rows();
    let r = report.rank;
    if r == 0 {
        return Err(DetectabilityError::NothingObservable(
            report.unobservable_eigenvalues.render(),
        ));
    }
    let detectable = is_hurwitz(&report.unobservable_polynomial);
    let mut d = Derivation::new("Observer for the observable part (Kalman decomposition)");
    let Decomposition {
        t,
        identity,
        a_decomposed: a_dec,
        a_oo,
        c_o,
    } = decompose(
        a,
        c,
        &report.matrix,
        &report.unobservable_subspace,
        r,
        &mut d,
    )?;
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
    let k = if identity {
        padded
    } else {
        t.map(|x| Quadratic::rational(x.clone())).mul(&padded)?
    };
    let shown = convention.from_a_minus_kc(&k);
    d.push("K", "T [K_o; 0]", &k);
    // det(sI − (A − KC)) recomputed from K by the rank-one update det(sI − A) +
    // C adj(sI − A) K (only O_n K and det(sI − A) enter, whatever the size of K's numbers):
    // the check `gain` makes, here on the whole plant, so it tests the decomposition too
    // — except when the pair is observable and T = I: the observable part is then the plant,
    // and the design's own rank-one check computed this very polynomial from the same K
    let observer_polynomial = if identity && r == n {
        observable_part.achieved.clone()
    } else {
        let lift = |x: &Rational| Quadratic::rational(x.clone());
        let open_loop = linalg::characteristic_polynomial(&a.map(lift), "s")?;
        crate::linalg::rank_one_update(&report.matrix.map(lift), &open_loop, &k)?
    };
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

/// [`detectable_design`] with parameters: the same Kalman decomposition over the rational
/// functions of the plant's parameters (for their generic values: the rank of `O_n` over that
/// field), the gain of the observable part in symbols, the observer polynomial checked as an
/// identity, and detectability as conditions on the parameters — the Hurwitz determinants of
/// the unobservable polynomial (`Δ₁ > 0, …, Δ_(m−1) > 0` and the constant coefficient `> 0`).
#[derive(Debug, Clone)]
pub struct SymbolicDetectable {
    /// rank O_n for generic values of the parameters.
    pub rank: usize,
    /// O_n.
    pub o: Matrix<Fraction>,
    /// T = [V_o V_u].
    pub t: Matrix<Fraction>,
    /// T⁻¹ A T.
    pub a_decomposed: Matrix<Fraction>,
    /// The design for (A_oo, C_o).
    pub observable_part: super::gain::SymbolicDesign,
    /// (A_oo, C_o), for where their observability breaks.
    pub observable_pair: (Matrix<Fraction>, Matrix<Fraction>),
    /// K = T [K_o; 0], in the convention asked for.
    pub gain: Matrix<Fraction>,
    /// det(sI − A_uu), monic (1 when every mode is observable).
    pub unobservable_polynomial: Poly<Fraction>,
    /// det(sI − (A − KC)), recomputed from K.
    pub observer_polynomial: Poly<Fraction>,
    /// Whether the observer polynomial is the desired one times the unobservable one, as an
    /// identity in s and the parameters.
    pub identity: bool,
    /// What must be positive for every unobservable mode to be stable (constants included:
    /// a nonpositive one means not detectable for any value).
    pub conditions: Vec<Fraction>,
    /// The steps.
    pub derivation: Derivation,
}

/// Designs the observer of [`detectable_design`] with parameters in A, C or the desired
/// polynomial (degree r = rank O_n for generic values).
///
/// # Errors
/// [`DetectabilityError`]: shapes, nothing observable, a desired polynomial of another degree.
pub fn detectable_symbolic(
    a: &Matrix<Fraction>,
    c: &Matrix<Fraction>,
    desired: &Poly<Fraction>,
    method: GainMethod,
    convention: Convention,
) -> Result<SymbolicDetectable, DetectabilityError> {
    let n = a.rows();
    let o = crate::observability::observability_matrix(a, c)?;
    let r = linalg::rank(&o);
    let (basis, unobservable_polynomial) = crate::observability::unobservable_part(a, &o, r)?;
    if r == 0 {
        return Err(DetectabilityError::NothingObservable(
            unobservable_polynomial.to_string(),
        ));
    }
    let mut d = Derivation::new("Observer for the observable part (Kalman decomposition)");
    let Decomposition {
        t,
        a_decomposed: a_dec,
        a_oo,
        c_o,
        ..
    } = decompose(a, c, &o, &basis, r, &mut d)?;
    let observable_part = super::gain::design_symbolic(
        &a_oo,
        &c_o,
        desired,
        method,
        Convention::AMinusKC,
        Detail::Full,
    )?;
    d.extend(observable_part.derivation.clone());
    let padded = observable_part
        .gain
        .matrix
        .vstack(&Matrix::zeros(n - r, 1))?;
    let k = t.mul(&padded)?;
    d.push("K", "T [K_o; 0]", &k);
    let closed = a.sub(&k.mul(c)?)?;
    let observer_polynomial = linalg::characteristic_polynomial(&closed, "s")?;
    d.push(
        "det(sI − (A − KC))",
        "P(s) · det(sI − A_uu)",
        &observer_polynomial,
    );
    let identity = desired.clone().with_var("s") * unobservable_polynomial.clone().with_var("s")
        == observer_polynomial;
    let conditions = hurwitz_conditions(&unobservable_polynomial)?;
    Ok(SymbolicDetectable {
        rank: r,
        o,
        t,
        a_decomposed: a_dec,
        observable_pair: (a_oo, c_o),
        observable_part,
        gain: convention.from_a_minus_kc(&k),
        unobservable_polynomial,
        observer_polynomial,
        identity,
        conditions,
        derivation: d,
    })
}

impl SymbolicDetectable {
    /// Detectable for every value (`Some(true)`: every condition a positive number), for none
    /// (`Some(false)`: one a nonpositive number), or exactly when the conditions that are
    /// formulas are positive (`None`, with them).
    pub fn verdict(&self) -> (Option<bool>, Vec<&Fraction>) {
        use num_traits::Signed;
        let formulas: Vec<&Fraction> = self
            .conditions
            .iter()
            .filter(|x| x.as_rational().is_none())
            .collect();
        let never = self
            .conditions
            .iter()
            .any(|x| x.as_rational().is_some_and(|q| !q.is_positive()));
        let verdict = if never {
            Some(false)
        } else if formulas.is_empty() {
            Some(true)
        } else {
            None
        };
        (verdict, formulas)
    }
}

/// The conditions for a monic `p(s) = s^m + c₁ s^(m−1) + … + c_m` to be Hurwitz: the leading
/// Hurwitz determinants `Δ₁, …, Δ_(m−1)` and `c_m` positive (Δ_m = c_m Δ_(m−1)). Empty for
/// `p = 1`.
///
/// # Errors
/// [`LinalgError`] (not expected: the matrices are square).
pub fn hurwitz_conditions<F: crate::algebra::Field>(p: &Poly<F>) -> Result<Vec<F>, LinalgError> {
    let m = p.degree().unwrap_or(0);
    if m == 0 {
        return Ok(Vec::new());
    }
    // c_k, the coefficient of s^(m−k), 0 outside 0..=m
    let coeff = |k: i64| -> F {
        if (0..=m as i64).contains(&k) {
            p.coeff(m - k as usize)
        } else {
            F::zero()
        }
    };
    let hurwitz = Matrix::from_fn(m, m, |i, j| coeff(2 * (j as i64 + 1) - (i as i64 + 1)));
    let mut out = Vec::with_capacity(m);
    for k in 1..m {
        out.push(linalg::determinant(&hurwitz.block(0, k, 0, k))?);
    }
    out.push(coeff(m as i64));
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algebra::{MultiPoly, Ring};

    #[test]
    fn hurwitz_conditions_of_a_cubic() {
        // s³ + a s² + b s + c is stable exactly when a > 0, a b − c > 0 and c > 0
        let f = |name: &str| Fraction::of(MultiPoly::var(name));
        let p = Poly::new(
            vec![
                f("c"),
                f("b"),
                f("a"),
                Fraction::constant(Rational::from_i64(1)),
            ],
            "s",
        );
        let shown: Vec<String> = hurwitz_conditions(&p)
            .unwrap()
            .iter()
            .map(Ring::to_input)
            .collect();
        assert_eq!(shown, ["a", "a*b - c", "c"]);
        let one = Poly::new(vec![Fraction::constant(Rational::from_i64(1))], "s");
        assert!(hurwitz_conditions(&one).unwrap().is_empty());
    }
}
