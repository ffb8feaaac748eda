//! The reduced-order (minimal-order) observer of Luenberger, in Gopinath's construction: the p
//! measured combinations y = Cx need no estimate, so only n − p states are observed, with an
//! observer polynomial of degree n − p. Exact throughout.
//!
//! Coordinates z = Q x with Q = [C; R] (R: unit rows completing C to an invertible matrix), so
//! z₁ = y. Partition Q A Q⁻¹ = [A₁₁ A₁₂; A₂₁ A₂₂] and Q B = [B₁; B₂]. With w = z₂ − L y,
//!
//! ```text
//! ẇ = F w + G y + H u,  F = A₂₂ − L A₁₂,  G = F L + A₂₁ − L A₁₁,  H = B₂ − L B₁,
//! x̂ = Q⁻¹ [y; w + L y],
//! ```
//!
//! and the error e₂ = z₂ − ẑ₂ obeys ė₂ = F e₂: L places the eigenvalues of A₂₂ − L A₁₂, an
//! observer design for the pair (A₂₂, A₁₂), observable exactly when (A, C) is. The price is that
//! x̂ passes y straight through, x̂ = D_y y + Q⁻¹ [0; I] w with D_y = Q⁻¹ [I; L]: measurement noise
//! reaches the estimate unfiltered, which the full-order observer (no direct term) avoids.

use super::DesiredPolynomial;
use super::{design_with, Convention, DesignError, Detail, GainMethod, ObserverDesign};
use crate::algebra::{Quadratic, Rational, Ring, Zero};
use crate::derivation::Derivation;
use crate::linalg::{self, LinalgError, Matrix};
use crate::poly::Poly;

/// Why no reduced-order observer could be designed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ReducedOrderError {
    /// The gain design for (A₂₂, A₁₂) failed.
    #[error(transparent)]
    Design(#[from] DesignError),
    /// A matrix computation failed.
    #[error(transparent)]
    Linalg(#[from] LinalgError),
    /// C must have full row rank.
    #[error("C ({rows}×{cols}) must have full row rank for a reduced-order observer; its rank is {rank}")]
    RankDeficientC {
        /// Rows of C.
        rows: usize,
        /// Columns of C.
        cols: usize,
        /// Its rank.
        rank: usize,
    },
    /// Nothing to observe.
    #[error("C measures all {0} states: there is nothing left to observe (x = C⁻¹ y)")]
    NothingToObserve(usize),
    /// The reduced pair is not observable (exactly when (A, C) is not).
    #[error("the reduced pair (A₂₂, A₁₂) is not observable, so neither is (A, C): {0}")]
    ReducedPairUnobservable(String),
    /// No single row of A₁₂ observes the unmeasured part.
    #[error("no single measured output observes the unmeasured states through A₁₂ = {0}; the pair (A, C) is not observable, or needs several outputs at once")]
    NoObservingRow(String),
}

/// A reduced-order observer.
#[derive(Debug, Clone)]
pub struct ReducedOrderObserver {
    /// Q = [C; R].
    pub q: Matrix<Rational>,
    /// Q A Q⁻¹.
    pub a_bar: Matrix<Rational>,
    /// The gain L ((n − p) × p), in the A₂₂ − L A₁₂ sign.
    pub l: Matrix<Quadratic>,
    /// Which output's row of A₁₂ the gain was designed with (0-based), when p > 1.
    pub output: Option<usize>,
    /// F = A₂₂ − L A₁₂.
    pub f: Matrix<Quadratic>,
    /// G = F L + A₂₁ − L A₁₁.
    pub g: Matrix<Quadratic>,
    /// H = B₂ − L B₁ (when B is given).
    pub h: Option<Matrix<Quadratic>>,
    /// D_y = Q⁻¹ [I; L]: how y reaches x̂ directly.
    pub direct: Matrix<Quadratic>,
    /// M = Q⁻¹ [0; I]: how w reaches x̂.
    pub from_w: Matrix<Quadratic>,
    /// det(sI − F), recomputed.
    pub error_polynomial: Poly<Quadratic>,
    /// Σ of the squared entries of D_y: white measurement noise of unit variance on every
    /// output adds this much to the summed variance of x̂, at every frequency.
    pub noise_gain: Quadratic,
    /// The design of the gain for (A₂₂, A₁₂).
    pub design: ObserverDesign,
    /// The steps.
    pub derivation: Derivation,
}

impl ReducedOrderObserver {
    /// The gain in the convention asked for: L of A₂₂ − L A₁₂, or its negative for a+lc.
    pub fn gain(&self, convention: Convention) -> Matrix<Quadratic> {
        convention.from_a_minus_kc(&self.l)
    }
}

fn lift(m: &Matrix<Rational>) -> Matrix<Quadratic> {
    m.map(|x| Quadratic::rational(x.clone()))
}

/// `rows` completed with unit rows eₖᵀ (in order) to an invertible n × n matrix.
pub(crate) fn complete_with_unit_rows(rows: &Matrix<Rational>) -> Matrix<Rational> {
    let n = rows.cols();
    let mut q = rows.clone();
    for k in 0..n {
        if q.rows() == n {
            break;
        }
        let unit = Matrix::from_fn(1, n, |_, j| {
            if j == k {
                Rational::from_i64(1)
            } else {
                Rational::zero()
            }
        });
        if let Ok(candidate) = q.vstack(&unit) {
            if linalg::rank(&candidate) == candidate.rows() {
                q = candidate;
            }
        }
    }
    q
}

/// The gain for (A₂₂, one row of A₁₂): the first output whose row observes A₂₂, with its
/// design. With one output, the design's own refusal says why (the reduced pair is
/// unobservable exactly when (A, C) is).
fn design_for_one_row(
    a22: &Matrix<Rational>,
    a12: &Matrix<Rational>,
    desired: &DesiredPolynomial,
    method: GainMethod,
) -> Result<(usize, ObserverDesign), ReducedOrderError> {
    let (p, m) = (a12.rows(), a12.cols());
    for k in 0..p {
        let row = a12.block(k, k + 1, 0, m);
        match design_with(
            a22,
            &row,
            desired,
            method,
            Convention::AMinusKC,
            Detail::Full,
        ) {
            Ok(design) => return Ok((k, design)),
            // one output: the design's own refusal is the reason, told of the reduced pair
            Err(DesignError::Observability(o)) if p == 1 => {
                return Err(ReducedOrderError::ReducedPairUnobservable(
                    o.to_string()
                        .replace("the pair (A, C) is not observable: ", "")
                        .replace("unobservable direction", "unobservable direction of z₂"),
                ))
            }
            Err(e) if p == 1 => return Err(e.into()),
            Err(_) => {}
        }
    }
    Err(ReducedOrderError::NoObservingRow(a12.to_input()))
}

/// Designs a reduced-order observer for (A, C) (and B, when given) whose error polynomial is
/// `desired`, of degree n − p, in the convention asked for (the gain printed as L of
/// A₂₂ − L A₁₂, or its negative for a+lc).
///
/// # Errors
/// [`ReducedOrderError`]: C without full row rank or measuring every state, an unobservable
/// pair, a desired polynomial of the wrong degree.
pub fn reduced_order_observer(
    a: &Matrix<Rational>,
    b: Option<&Matrix<Rational>>,
    c: &Matrix<Rational>,
    desired: &DesiredPolynomial,
    method: GainMethod,
) -> Result<ReducedOrderObserver, ReducedOrderError> {
    let (n, p) = (a.rows(), c.rows());
    let rank = linalg::rank(c);
    if rank != p || c.cols() != n {
        return Err(ReducedOrderError::RankDeficientC {
            rows: p,
            cols: c.cols(),
            rank,
        });
    }
    if p == n {
        return Err(ReducedOrderError::NothingToObserve(n));
    }
    let mut d = Derivation::new("Reduced-order observer (Gopinath), A₂₂ − L A₁₂ convention");
    let q = complete_with_unit_rows(c);
    let q_inv = linalg::inverse(&q)?;
    d.push("Q", "[C; R], R unit rows completing C", &q);
    let a_bar = q.mul(a)?.mul(&q_inv)?;
    d.push("Q A Q⁻¹", "[A₁₁ A₁₂; A₂₁ A₂₂]", &a_bar);
    let a11 = a_bar.block(0, p, 0, p);
    let a12 = a_bar.block(0, p, p, n);
    let a21 = a_bar.block(p, n, 0, p);
    let a22 = a_bar.block(p, n, p, n);
    let (k, design) = design_for_one_row(&a22, &a12, desired, method)?;
    d.extend(design.derivation.clone());
    let column = design.gain.matrix.clone();
    let l = Matrix::from_fn(n - p, p, |i, j| {
        if j == k {
            column.get(i, 0).clone()
        } else {
            Quadratic::zero()
        }
    });
    let f = lift(&a22).sub(&l.mul(&lift(&a12))?)?;
    let g = f.mul(&l)?.add(&lift(&a21))?.sub(&l.mul(&lift(&a11))?)?;
    d.push("L", "gain for the pair (A₂₂, A₁₂)", &l);
    d.push("F", "A₂₂ − L A₁₂", &f);
    d.push("G", "F L + A₂₁ − L A₁₁", &g);
    let h = match b {
        Some(b) => {
            let b_bar = q.mul(b)?;
            let (b1, b2) = (
                b_bar.block(0, p, 0, b.cols()),
                b_bar.block(p, n, 0, b.cols()),
            );
            let h = lift(&b2).sub(&l.mul(&lift(&b1))?)?;
            d.push("H", "B₂ − L B₁", &h);
            Some(h)
        }
        None => None,
    };
    let stacked_direct = Matrix::identity(p).vstack(&l)?;
    let direct = lift(&q_inv).mul(&stacked_direct)?;
    let from_w = lift(&q_inv).mul(&Matrix::zeros(p, n - p).vstack(&Matrix::identity(n - p))?)?;
    d.push("D_y", "Q⁻¹ [I; L]: y straight into x̂", &direct);
    d.push("M", "Q⁻¹ [0; I]: w into x̂", &from_w);
    // F = A₂₂ − l a₁₂ₖ with l the one nonzero column k of L: a rank-one update of A₂₂, so
    // det(sI − F) is the polynomial the design recomputed from its gain for the pair
    // (A₂₂, a₁₂ₖ) by the rank-one update (det(sI − A₂₂) + a₁₂ₖ adj(sI − A₂₂) l), whatever the
    // size of l's numbers — no characteristic polynomial of F itself
    let error_polynomial = design.achieved.clone();
    d.push(
        "det(sI − F)",
        "check: the error polynomial, degree n − p",
        &error_polynomial,
    );
    let noise_gain = direct
        .entries()
        .iter()
        .fold(Quadratic::zero(), |acc, x| acc + x.clone() * x.clone());
    Ok(ReducedOrderObserver {
        q,
        a_bar,
        l,
        output: (p > 1).then_some(k),
        f,
        g,
        h,
        direct,
        from_w,
        error_polynomial,
        noise_gain,
        design,
        derivation: d,
    })
}
