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
use crate::algebra::{Fraction, Quadratic, Rational};
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
    /// The design of the gain for (A₂₂, A₁₂) (its steps moved into `derivation` and its
    /// observer matrix into `f`, so that they are held once: its own are empty).
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

/// `rows` completed with unit rows eₖᵀ (in order) to an invertible n × n matrix: eₖ joins
/// when it is independent of the rows and of the units taken before it.
///
/// That greedy choice is decided by one elimination: eₖ depends on the rows and e₀ … eₖ₋₁
/// exactly when some combination of the rows has its last nonzero entry in column k, so the
/// units taken are the columns that are not pivots of the rows' echelon form built from the
/// right — p²n field operations for p independent rows, where testing each candidate's rank
/// costs n of them (at order 20 the tests were a tenth of `detectable`). Rows with parameters
/// (few and small) and dependent rows keep the tests.
pub(crate) fn complete_with_unit_rows<F: crate::algebra::Field>(rows: &Matrix<F>) -> Matrix<F> {
    let n = rows.cols();
    // on rational rows (the numeric commands; symbolic rows are few and small)
    let pivots = linalg::as_rational(rows).and_then(pivots_from_the_right);
    if let Some(pivots) = pivots {
        let units: Vec<usize> = (0..n).filter(|k| !pivots.contains(k)).collect();
        let unit_rows = Matrix::from_fn(units.len(), n, |i, j| {
            if j == units[i] {
                F::one()
            } else {
                F::zero()
            }
        });
        if let Ok(q) = rows.vstack(&unit_rows) {
            return q;
        }
    }
    complete_by_rank_tests(rows)
}

/// The greedy completion by testing each candidate's rank.
fn complete_by_rank_tests<F: crate::algebra::Field>(rows: &Matrix<F>) -> Matrix<F> {
    let n = rows.cols();
    let mut q = rows.clone();
    for k in 0..n {
        if q.rows() == n {
            break;
        }
        let unit = Matrix::from_fn(1, n, |_, j| if j == k { F::one() } else { F::zero() });
        if let Ok(candidate) = q.vstack(&unit) {
            if linalg::rank(&candidate) == candidate.rows() {
                q = candidate;
            }
        }
    }
    q
}

/// The pivot columns of `rows`' echelon form eliminated from the last column to the first
/// (each pivot the last nonzero entry of a combination of the rows), or `None` when the rows
/// are dependent.
fn pivots_from_the_right(rows: &Matrix<Rational>) -> Option<Vec<usize>> {
    let n = rows.cols();
    let mut remaining: Vec<Vec<Rational>> =
        (0..rows.rows()).map(|i| rows.row(i).to_vec()).collect();
    let mut pivots = Vec::with_capacity(remaining.len());
    for col in (0..n).rev() {
        let Some(at) = remaining
            .iter()
            .position(|r| !num_traits::Zero::is_zero(&r[col]))
        else {
            continue;
        };
        let pivot = remaining.swap_remove(at);
        for r in &mut remaining {
            if !num_traits::Zero::is_zero(&r[col]) {
                let factor = crate::algebra::Field::checked_div(&r[col], &pivot[col])?;
                for (x, y) in r.iter_mut().zip(&pivot) {
                    *x = x.clone() - factor.clone() * y.clone();
                }
            }
        }
        pivots.push(col);
    }
    remaining.is_empty().then_some(pivots)
}

/// The gain for (A₂₂, one row of A₁₂): the first output whose row observes A₂₂, with its
/// design (`design` designs for one row). With one output, the design's own refusal says why
/// (the reduced pair is unobservable exactly when (A, C) is).
fn design_for_one_row<F: crate::algebra::Field, D>(
    a12: &Matrix<F>,
    mut design: impl FnMut(&Matrix<F>) -> Result<D, DesignError>,
) -> Result<(usize, D), ReducedOrderError> {
    let (p, m) = (a12.rows(), a12.cols());
    for k in 0..p {
        let row = a12.block(k, k + 1, 0, m);
        match design(&row) {
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

/// The observer's matrices from the blocks of Q A Q⁻¹ (and Q B), Q⁻¹ and the gain L, over any
/// field (Q(√d) for numbers, the rational functions of the parameters with parameters): the
/// formulas of the module doc, each a named step.
struct Assembled<F> {
    f: Matrix<F>,
    g: Matrix<F>,
    h: Option<Matrix<F>>,
    direct: Matrix<F>,
    from_w: Matrix<F>,
    noise_gain: F,
}

/// The blocks [A₁₁ A₁₂; A₂₁ A₂₂] of Q A Q⁻¹ and [B₁; B₂] of Q B, with p measured rows.
struct Blocks<F> {
    a11: Matrix<F>,
    a12: Matrix<F>,
    a21: Matrix<F>,
    a22: Matrix<F>,
    b: Option<(Matrix<F>, Matrix<F>)>,
}

impl<F: crate::algebra::Field> Blocks<F> {
    fn of(a_bar: &Matrix<F>, b_bar: Option<&Matrix<F>>, p: usize) -> Self {
        let n = a_bar.rows();
        Blocks {
            a11: a_bar.block(0, p, 0, p),
            a12: a_bar.block(0, p, p, n),
            a21: a_bar.block(p, n, 0, p),
            a22: a_bar.block(p, n, p, n),
            b: b_bar.map(|b| (b.block(0, p, 0, b.cols()), b.block(p, n, 0, b.cols()))),
        }
    }
}

/// L with `column` as its column `k` and zeros elsewhere ((n − p) × p).
fn gain_matrix<F: crate::algebra::Field>(column: &Matrix<F>, k: usize, p: usize) -> Matrix<F> {
    Matrix::from_fn(column.rows(), p, |i, j| {
        if j == k {
            column.get(i, 0).clone()
        } else {
            F::zero()
        }
    })
}

/// `shown_f`: F's step from [`moved_design_steps`], when the design showed its observer matrix;
/// `known_f`: that matrix, when the design kept it (F is then not formed again).
fn assemble<F: crate::algebra::Field>(
    blocks: &Blocks<F>,
    q_inv: &Matrix<F>,
    l: &Matrix<F>,
    (shown_f, known_f): (Option<crate::derivation::Step>, Option<Matrix<F>>),
    d: &mut Derivation,
) -> Result<Assembled<F>, LinalgError>
where
    Matrix<F>: crate::derivation::Show,
{
    let (p, m) = (l.cols(), l.rows());
    let f = match known_f {
        Some(f) => f,
        None => blocks.a22.sub(&l.mul(&blocks.a12)?)?,
    };
    // G = F L + A₂₁ − L A₁₁ = A₂₂ L + A₂₁ − L (A₁₂ L + A₁₁): the same matrix, without
    // multiplying F, whose entries carry L's large numbers, by L
    let a12_l = blocks.a12.mul(l)?.add(&blocks.a11)?;
    let g = blocks.a22.mul(l)?.add(&blocks.a21)?.sub(&l.mul(&a12_l)?)?;
    d.push("L", "gain for the pair (A₂₂, A₁₂)", l);
    match shown_f {
        Some(step) => d.push_step(step),
        None => d.push("F", "A₂₂ − L A₁₂", &f),
    }
    d.push("G", "F L + A₂₁ − L A₁₁", &g);
    let h = match &blocks.b {
        Some((b1, b2)) => {
            let h = b2.sub(&l.mul(b1)?)?;
            d.push("H", "B₂ − L B₁", &h);
            Some(h)
        }
        None => None,
    };
    let direct = q_inv.mul(&Matrix::identity(p).vstack(l)?)?;
    let from_w = q_inv.mul(&Matrix::zeros(p, m).vstack(&Matrix::identity(m))?)?;
    d.push("D_y", "Q⁻¹ [I; L]: y straight into x̂", &direct);
    d.push("M", "Q⁻¹ [0; I]: w into x̂", &from_w);
    // Σ of the squared entries, as the trace of D_yᵀ D_y: each diagonal entry one dot product
    // on the fraction-free path, reduced once, instead of a reduction per term
    let gram = direct.transpose().mul(&direct)?;
    let noise_gain = (0..p).fold(F::zero(), |acc, i| acc + gram.get(i, i).clone());
    Ok(Assembled {
        f,
        g,
        h,
        direct,
        from_w,
        noise_gain,
    })
}

/// The gain design's steps moved into the observer's derivation `d` (held once: at order 40
/// they are 10 MB), and F's step: the design's observer matrix `A₂₂ − K a₁₂ₖ` is F (L is K in
/// column k and zeros elsewhere, so `L A₁₂ = K a₁₂ₖ`), its rendering reused under F's name.
fn moved_design_steps(
    design: &mut Derivation,
    d: &mut Derivation,
) -> Option<crate::derivation::Step> {
    let shown_f = design
        .step(super::gain::OBSERVER_MATRIX_STEP)
        .map(|step| step.renamed("F", "A₂₂ − L A₁₂"));
    d.extend(std::mem::take(design));
    shown_f
}

/// C's checks: full row rank, fewer rows than states.
fn check_c(c: &Matrix<Rational>, n: usize) -> Result<usize, ReducedOrderError> {
    let p = c.rows();
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
    Ok(p)
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
    let p = check_c(c, a.rows())?;
    let mut d = Derivation::new("Reduced-order observer (Gopinath), A₂₂ − L A₁₂ convention");
    let q = complete_with_unit_rows(c);
    let q_inv = linalg::inverse(&q)?;
    d.push("Q", "[C; R], R unit rows completing C", &q);
    let a_bar = q.mul(a)?.mul(&q_inv)?;
    d.push("Q A Q⁻¹", "[A₁₁ A₁₂; A₂₁ A₂₂]", &a_bar);
    let blocks = Blocks::of(&a_bar, None, p);
    let (k, mut design) = design_for_one_row(&blocks.a12, |row| {
        design_with(
            &blocks.a22,
            row,
            desired,
            method,
            Convention::AMinusKC,
            Detail::Full,
        )
    })?;
    let shown_f = moved_design_steps(&mut design.derivation, &mut d);
    let l = gain_matrix(&design.gain.matrix, k, p);
    let b_bar = b.map(|b| q.mul(b)).transpose()?;
    let lifted = Blocks::of(&lift(&a_bar), b_bar.map(|b| lift(&b)).as_ref(), p);
    let Assembled {
        f,
        g,
        h,
        direct,
        from_w,
        noise_gain,
    } = assemble(
        &lifted,
        &lift(&q_inv),
        &l,
        (shown_f, design.observer_matrix.take()),
        &mut d,
    )?;
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

/// A reduced-order observer designed with parameters ([`reduced_order_symbolic`]).
#[derive(Debug, Clone)]
pub struct SymbolicReduced {
    /// Q = [C; R] (C in numbers).
    pub q: Matrix<Rational>,
    /// Q A Q⁻¹.
    pub a_bar: Matrix<Fraction>,
    /// The gain L in the A₂₂ − L A₁₂ sign.
    pub l: Matrix<Fraction>,
    /// Which output's row of A₁₂ the gain was designed with (0-based), when p > 1.
    pub output: Option<usize>,
    /// F = A₂₂ − L A₁₂.
    pub f: Matrix<Fraction>,
    /// G = F L + A₂₁ − L A₁₁.
    pub g: Matrix<Fraction>,
    /// H = B₂ − L B₁ (when B is given).
    pub h: Option<Matrix<Fraction>>,
    /// D_y = Q⁻¹ [I; L].
    pub direct: Matrix<Fraction>,
    /// M = Q⁻¹ [0; I].
    pub from_w: Matrix<Fraction>,
    /// det(sI − F), recomputed from the gain by the rank-one update.
    pub error_polynomial: Poly<Fraction>,
    /// Whether it equals the desired polynomial identically in s and the parameters.
    pub identity: bool,
    /// Σ D_y².
    pub noise_gain: Fraction,
    /// The reduced pair designed for: A₂₂ and the row of A₁₂ (where it is unobservable, the
    /// design breaks).
    pub reduced_pair: (Matrix<Fraction>, Matrix<Fraction>),
    /// The steps, in symbols.
    pub derivation: Derivation,
}

/// [`reduced_order_observer`] for a plant with parameters in A (and B) and C in numbers (the
/// measured combinations): Q = [C; R] in numbers, the blocks of Q A Q⁻¹ and the gain for
/// (A₂₂, a row of A₁₂) as rational functions of the parameters, the error polynomial checked as
/// an identity.
///
/// # Errors
/// As [`reduced_order_observer`]; an unobservable reduced pair means unobservable for every
/// value of the parameters.
pub fn reduced_order_symbolic(
    a: &Matrix<Fraction>,
    b: Option<&Matrix<Fraction>>,
    c: &Matrix<Rational>,
    desired: &Poly<Fraction>,
    method: GainMethod,
) -> Result<SymbolicReduced, ReducedOrderError> {
    let p = check_c(c, a.rows())?;
    let lift = |m: &Matrix<Rational>| m.map(|x| Fraction::constant(x.clone()));
    let mut d = Derivation::new("Reduced-order observer (Gopinath), A₂₂ − L A₁₂ convention");
    let q = complete_with_unit_rows(c);
    let q_inv = linalg::inverse(&q)?;
    d.push("Q", "[C; R], R unit rows completing C", &q);
    let a_bar = lift(&q).mul(a)?.mul(&lift(&q_inv))?;
    d.push("Q A Q⁻¹", "[A₁₁ A₁₂; A₂₁ A₂₂]", &a_bar);
    let b_bar = b.map(|b| lift(&q).mul(b)).transpose()?;
    let blocks = Blocks::of(&a_bar, b_bar.as_ref(), p);
    let (k, mut design) = design_for_one_row(&blocks.a12, |row| {
        super::design_symbolic(
            &blocks.a22,
            row,
            desired,
            method,
            Convention::AMinusKC,
            Detail::Full,
        )
    })?;
    let shown_f = moved_design_steps(&mut design.derivation, &mut d);
    let l = gain_matrix(&design.gain.matrix, k, p);
    let Assembled {
        f,
        g,
        h,
        direct,
        from_w,
        noise_gain,
    } = assemble(&blocks, &lift(&q_inv), &l, (shown_f, None), &mut d)?;
    // as in the numeric design: F is the rank-one update of A₂₂ the design checked
    let error_polynomial = design.achieved.clone();
    d.push(
        "det(sI − F)",
        "check: the error polynomial, degree n − p",
        &error_polynomial,
    );
    let m = blocks.a12.cols();
    Ok(SymbolicReduced {
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
        identity: design.identity,
        noise_gain,
        reduced_pair: (blocks.a22.clone(), blocks.a12.block(k, k + 1, 0, m)),
        derivation: d,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algebra::Fraction;
    use crate::syntax::parse_matrix;

    proptest::proptest! {
        /// The completion by one elimination from the right takes the units the rank tests
        /// take, for independent and dependent rows alike.
        #[test]
        fn completion_by_pivots_is_the_greedy_one(
            entries in proptest::collection::vec(-2i64..=2, 1..=20),
            p in 1usize..4,
            n in 1usize..6,
        ) {
            let p = p.min(n);
            let rows = Matrix::from_fn(p, n, |i, j| {
                Rational::from_integer(entries[(i * n + j) % entries.len()].into())
            });
            proptest::prop_assert_eq!(complete_with_unit_rows(&rows), complete_by_rank_tests(&rows));
        }
    }

    /// F's step reuses the gain design's rendering of its observer matrix: it must be F's
    /// own rendering, with two outputs (L zero outside column k) and with parameters.
    #[test]
    fn the_f_step_shows_f() {
        let a = parse_matrix::<Rational>("[1 2 0 3; -1 0 2 1; 0 1 -2 4; 2 0 1 -1]").unwrap();
        let c = parse_matrix::<Rational>("[1 0 0 0; 0 1 0 0]").unwrap();
        let pole = |x: i64| Quadratic::rational(Rational::from_integer(x.into()));
        let desired = DesiredPolynomial::from_poles(&[pole(-1), pole(-2)]).unwrap();
        let r = reduced_order_observer(&a, None, &c, &desired, GainMethod::Ackermann).unwrap();
        let step = r.derivation.step("F").unwrap();
        assert_eq!(
            (step.text.clone(), step.latex.clone(), step.input.clone()),
            r.f.renderings()
        );
        // and `--json`'s F from the step's kept entries is F's own
        assert!(step.cells().is_some());
        assert_eq!(
            crate::api::args::json_matrix_shown(&r.f, Some(step)),
            crate::api::args::json_matrix(&r.f)
        );

        let a = parse_matrix::<Fraction>("[0 1 0; 0 0 1; -a0 -a1 -a2]").unwrap();
        let c = parse_matrix::<Rational>("[1 0 0]").unwrap();
        // (s + p)(s + 2p), lowest power first
        let coeffs = parse_matrix::<Fraction>("[2*p^2 3*p 1]").unwrap();
        let p = crate::poly::Poly::new(coeffs.entries().to_vec(), "s");
        let r = reduced_order_symbolic(&a, None, &c, &p, GainMethod::Ackermann).unwrap();
        let step = r.derivation.step("F").unwrap();
        assert_eq!(
            (step.text.clone(), step.latex.clone(), step.input.clone()),
            r.f.renderings()
        );
    }
}
