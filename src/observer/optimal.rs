//! Multi-output gains chosen by optimality (Baranowski, §4–5): among all gains `G` that place
//! the observer polynomial exactly, the one of minimum norm `J1 = Σ k_i²`.
//!
//! The constraints are the coefficient equations of `det(λI − (A − GC))` against the desired
//! polynomial, derived symbolically (eq. (15)); their exact Jacobians and Hessians come from
//! differentiating those polynomials. Newton's method on the Karush–Kuhn–Tucker system
//! `2k + Jᵀμ = 0, g(k) = 0` is run from many seeded random starts — converged when the
//! residuals are below 10⁻¹³, or, for plants whose coefficients put that below f64's
//! resolution, below 10⁻¹² of the size of their terms with every coefficient of the reported
//! gain's polynomial, computed exactly, within 10⁻⁶ of the desired one (the report says how
//! close);
//! each converged point is
//! classified (second-order test on the tangent space), and the report says how many starts
//! reached the best minimum, which other minima exist, and whether the best is unique.

use super::search::Multistart;
use crate::algebra::{FloatPoly, Monomial, MultiPoly, Rational, Ring, Zero};
use crate::linalg::{self, Matrix};
use crate::poly::Poly;
use nalgebra::{DMatrix, DVector};
use serde::Serialize;

/// Pole-placement equations `g_i(k) = 0` with exact derivatives.
#[derive(Clone, Debug)]
pub struct Constraints {
    /// The gain symbols, in the order of the gain matrix read column by column.
    pub variables: Vec<String>,
    /// `g_i`: coefficient of `λ^(n−i)` minus the desired one.
    pub equations: Vec<MultiPoly>,
    /// The equations and their first derivatives, compiled for f64 points (coordinates:
    /// `variables`), which Newton's method evaluates at every step.
    float_equations: Vec<FloatPoly>,
    jacobian: Vec<Vec<FloatPoly>>,
    /// The second derivatives that are not identically zero, by entry of the Hessian: most
    /// are (each term has at most one symbol of each output's column, so with two outputs
    /// every second derivative is a constant, and most are 0).
    hessian_entries: Vec<HessianEntry>,
    /// The desired coefficient each equation places, in f64: what a residual is measured
    /// against when the absolute tolerance is out of f64's reach.
    targets: Vec<f64>,
}

/// One entry of the constraints' Hessians: the second derivatives ∂²g_i/∂k_row∂k_column that
/// are not identically zero, with their equations' indices i, increasing.
#[derive(Clone, Debug)]
struct HessianEntry {
    row: usize,
    column: usize,
    terms: Vec<(usize, FloatPoly)>,
}

/// The constraints for a gain of symbols `k1, k2, …` (filled column by column, as Baranowski's
/// eq. (14)) placing `det(λI − (A − GC))` at `desired`.
///
/// **Algorithm.** With M = λI − A, det(M + GC) = det M · det(I + C M⁻¹ G) (Sylvester's
/// identity), and det(I + X) is the sum of X's principal minors. A minor on the outputs S is
/// multilinear in G's columns b ∈ S, so the polynomial's terms are the products
/// Π_(b∈S) k_(i_b, b) over the subsets S of outputs and the distinct rows i_b, each with the
/// coefficient det[P_(a, i_b)]_(a,b∈S) / (det M)^(|S|−1), where P = C·adj(M). The adjugate
/// comes from Faddeev and LeVerrier's recurrence on the exact characteristic polynomial of A
/// (adj M = Σ_k B_k λ^(n−1−k), B₀ = I, B_k = A B_(k−1) + a_k I). The terms are written down one
/// by one ([`MultiPoly::from_terms`]).
///
/// **Identity.** The same polynomials as the characteristic polynomial of A − GC taken
/// symbolically (Berkowitz over polynomials in the n·p symbols), which a test checks; that
/// path's intermediate polynomials have degree up to n in the symbols, and at order 10 with
/// two outputs it took 14 s.
///
/// **Cost.** n products of n × n rationals for the adjugate, then per term a |S| × |S|
/// determinant of polynomials in λ and one exact division: Σ_s C(p, s)·n!/(n − s)! terms
/// (111 at n = 10, p = 2).
///
/// # Errors
/// A message for mismatched dimensions.
pub fn pole_placement_constraints(
    a: &Matrix<Rational>,
    c: &Matrix<Rational>,
    desired: &Poly<Rational>,
) -> Result<Constraints, linalg::LinalgError> {
    let (n, p) = (a.rows(), c.rows());
    // the shapes A − GC asks for, refused as that product and difference refuse them
    let gc = Matrix::<Rational>::zeros(n, p).mul(c)?;
    a.sub(&gc)?.require_square("characteristic polynomial")?;
    let variables: Vec<String> = (0..n * p).map(|k| format!("k{}", k + 1)).collect();
    let chi = linalg::characteristic_polynomial(a, "λ")?;
    // P = C·adj(λI − A) entry by entry, as polynomials in λ
    let mut b = Matrix::<Rational>::identity(n);
    let mut p_coeffs: Vec<Vec<Vec<Rational>>> = vec![vec![vec![Rational::zero(); n]; n]; p];
    for k in 0..n {
        if k > 0 {
            b = a
                .mul(&b)?
                .add(&Matrix::identity(n).scale(&chi.coeff(n - k)))?;
        }
        let cb = c.mul(&b)?;
        for (l, row) in p_coeffs.iter_mut().enumerate() {
            for (i, coeffs) in row.iter_mut().enumerate() {
                coeffs[n - 1 - k] = cb.get(l, i).clone();
            }
        }
    }
    let p_entry = |l: usize, i: usize| Poly::new(p_coeffs[l][i].clone(), "λ");
    // the terms of det(λI − A + GC), λ's powers apart: terms[d] for λ^d
    let mut terms: Vec<Vec<(Monomial, Rational)>> = vec![Vec::new(); n + 1];
    for (d, coeff) in chi.coeffs().iter().enumerate() {
        terms[d].push((Monomial::one(), coeff.clone()));
    }
    let mut subset = Vec::new();
    let mut rows = Vec::new();
    let mut chi_power = Poly::constant(Rational::from_i64(1), "λ");
    for size in 1..=p.min(n) {
        if size > 1 {
            chi_power = chi_power * chi.clone();
        }
        for_each_choice(p, size, true, &mut subset, &mut |outputs: &[usize]| {
            for_each_choice(n, size, false, &mut rows, &mut |rows: &[usize]| {
                let minor = poly_determinant(size, &|x, y| p_entry(outputs[x], rows[y]));
                if minor.is_zero() {
                    return;
                }
                let Some(q) = minor.divide_exact(&chi_power) else {
                    unreachable!("Sylvester's identity: the minor is a multiple of det(M)^(|S|−1)")
                };
                let monomial = outputs
                    .iter()
                    .zip(rows)
                    .fold(Monomial::one(), |m, (&col, &row)| {
                        m.mul(&Monomial::var(&variables[col * n + row], 1))
                    });
                for (d, coeff) in q.coeffs().iter().enumerate() {
                    if !coeff.is_zero() {
                        terms[d].push((monomial.clone(), coeff.clone()));
                    }
                }
            });
        });
    }
    let equations: Vec<MultiPoly> = (1..=n)
        .map(|i| {
            let mut own = std::mem::take(&mut terms[n - i]);
            own.push((Monomial::one(), -desired.coeff(n - i)));
            MultiPoly::from_terms(own)
        })
        .collect();
    let jacobian: Vec<Vec<MultiPoly>> = equations
        .iter()
        .map(|e| variables.iter().map(|v| e.derivative(v)).collect())
        .collect();
    let m = variables.len();
    let mut hessian_entries = Vec::new();
    for row in 0..m {
        for column in 0..m {
            let terms: Vec<(usize, FloatPoly)> = jacobian
                .iter()
                .enumerate()
                .map(|(i, first)| (i, first[row].derivative(&variables[column])))
                .filter(|(_, second)| !second.is_zero())
                .map(|(i, second)| (i, second.to_float(&variables)))
                .collect();
            if !terms.is_empty() {
                hessian_entries.push(HessianEntry { row, column, terms });
            }
        }
    }
    let float_equations = equations.iter().map(|e| e.to_float(&variables)).collect();
    let jacobian = jacobian
        .iter()
        .map(|row| row.iter().map(|d| d.to_float(&variables)).collect())
        .collect();
    let targets = (1..=n)
        .map(|i| crate::algebra::rational_to_f64(&desired.coeff(n - i)))
        .collect();
    Ok(Constraints {
        variables,
        equations,
        float_equations,
        jacobian,
        hessian_entries,
        targets,
    })
}

/// Calls `f` with each sequence of `size` distinct elements of `0..count`: only the
/// increasing ones (the subsets) when `increasing`, otherwise every order of them.
fn for_each_choice(
    count: usize,
    size: usize,
    increasing: bool,
    chosen: &mut Vec<usize>,
    f: &mut dyn FnMut(&[usize]),
) {
    if chosen.len() == size {
        return f(chosen);
    }
    let from = match chosen.last() {
        Some(&last) if increasing => last + 1,
        _ => 0,
    };
    for x in from..count {
        if !chosen.contains(&x) {
            chosen.push(x);
            for_each_choice(count, size, increasing, chosen, f);
            chosen.pop();
        }
    }
}

/// The determinant of the `size × size` matrix of polynomials `entry(row, column)`, by
/// expansion along the first row (`size` is the number of outputs in a minor: small).
fn poly_determinant(size: usize, entry: &dyn Fn(usize, usize) -> Poly<Rational>) -> Poly<Rational> {
    fn minor(
        rows: &[usize],
        columns: &[usize],
        entry: &dyn Fn(usize, usize) -> Poly<Rational>,
    ) -> Poly<Rational> {
        let Some((&row, rest)) = rows.split_first() else {
            return Poly::constant(Rational::from_i64(1), "λ");
        };
        let mut sum = Poly::zero("λ");
        for (k, &column) in columns.iter().enumerate() {
            let others: Vec<usize> = columns.iter().copied().filter(|&c| c != column).collect();
            let term = entry(row, column) * minor(rest, &others, entry);
            sum = if k % 2 == 0 { sum + term } else { sum - term };
        }
        sum
    }
    let all: Vec<usize> = (0..size).collect();
    minor(&all, &all, entry)
}

impl Constraints {
    fn values(&self, k: &DVector<f64>) -> DVector<f64> {
        DVector::from_iterator(
            self.float_equations.len(),
            self.float_equations
                .iter()
                .map(|e| e.evaluate(k.as_slice())),
        )
    }
    /// Each equation's residual at `k` read exactly (every f64 is a rational), relative to the
    /// coefficient it places (to 1 when that is smaller): how far the polynomial of the f64
    /// gain reported (`--json` gives all its digits) is from the desired one, without f64's
    /// rounding in the evaluation.
    fn placement_errors(&self, k: &DVector<f64>) -> Option<Vec<f64>> {
        self.equations
            .iter()
            .zip(&self.targets)
            .map(|(e, t)| {
                let exact = e.evaluate_at_floats(&self.variables, k.as_slice())?;
                let r = crate::algebra::rational_to_f64(&exact);
                Some(r.abs() / t.abs().max(1.0))
            })
            .collect()
    }
    /// The size of each equation's terms at `k` (see [`FloatPoly::evaluate_abs`]).
    fn magnitudes(&self, k: &DVector<f64>) -> DVector<f64> {
        DVector::from_iterator(
            self.float_equations.len(),
            self.float_equations
                .iter()
                .map(|e| e.evaluate_abs(k.as_slice())),
        )
    }
    fn jacobian(&self, k: &DVector<f64>) -> DMatrix<f64> {
        DMatrix::from_fn(self.equations.len(), self.variables.len(), |i, j| {
            self.jacobian[i][j].evaluate(k.as_slice())
        })
    }
    /// The Hessian of the Lagrangian, 2I + Σ_i μ_i ∇²g_i(k): each entry summed in increasing
    /// i, as adding the matrices μ_i ∇²g_i one after the other would (the terms skipped are
    /// zeros, which leave the sum's bits as they are).
    fn lagrangian_hessian(&self, k: &DVector<f64>, mu: &DVector<f64>) -> DMatrix<f64> {
        let m = self.variables.len();
        let mut hl = DMatrix::<f64>::identity(m, m) * 2.0;
        for entry in &self.hessian_entries {
            let sum = &mut hl[(entry.row, entry.column)];
            for (i, second) in &entry.terms {
                *sum += second.evaluate(k.as_slice()) * mu[*i];
            }
        }
        hl
    }
}

/// Serde's test for a count left out of the JSON when 0.
fn is_zero(x: &usize) -> bool {
    *x == 0
}

/// One local minimum found.
#[derive(Clone, Debug, Serialize)]
pub struct LocalMinimum {
    /// The gain entries `k1, k2, …`.
    pub gain: Vec<f64>,
    /// `J1 = Σ k_i²`.
    pub cost: f64,
    /// How many starts converged to it.
    pub starts: usize,
    /// Largest constraint residual `|g_i|` at it.
    pub constraint_residual: f64,
    /// When Newton's method stopped at f64's resolution for the plant's terms instead of the
    /// absolute tolerance: the largest error of the placed coefficients, relative to the
    /// desired ones (to 1 when smaller), computed exactly from the gain as reported.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub placement_error: Option<f64>,
}

/// The result of the multistart minimum-norm search.
#[derive(Clone, Debug, Serialize)]
pub struct MinimumNormReport {
    /// Starts tried (seeded).
    pub starts: usize,
    /// Starts taken again, first moved by a descent on the constraint set, because none of
    /// them converged from where it began (see [`minimum_norm_gain`]); 0, and left out of the
    /// JSON, otherwise.
    #[serde(skip_serializing_if = "is_zero")]
    pub descended: usize,
    /// Starts that converged to a local minimum.
    pub converged: usize,
    /// Whether the search's time limit stopped it before every start had run (in both passes
    /// when the starts were taken again).
    #[serde(skip)]
    pub out_of_time: bool,
    /// Distinct local minima, best first.
    pub minima: Vec<LocalMinimum>,
    /// Minima whose cost equals the best within 1e-9 (relative): more than one means the
    /// minimiser is not unique.
    pub best_count: usize,
    /// The closest placement among starts that reached f64's resolution for the plant's terms
    /// but whose gains place the polynomial only beyond 10⁻⁶ (relative, computed exactly):
    /// why no gain is reported when none is.
    #[serde(skip)]
    pub unplaced: Option<f64>,
}

/// The residual, relative to the size of an equation's terms (Σ |c| Π |k|^e at the point),
/// that Newton's method is taken to have reached when the absolute 10⁻¹³ is out of reach: f64
/// evaluates an equation to within a few units of roundoff of that size for each term, and a
/// plant with entries up to 10 has order-5 terms of 10⁵ and more.
const RELATIVE_RESIDUAL: f64 = 1e-12;

/// How closely a gain accepted at f64's resolution must still place the polynomial, checked
/// exactly on the gain as reported: each coefficient within this fraction of the desired one
/// (of 1 when that is smaller) — the relative tolerance `gain --float` accepts a float gain
/// with. Past it no f64 gain places this plant's coefficients (dense integer plants: errors of
/// 5·10⁻⁹ at order 8, 2·10⁻⁶ at order 10), and no gain is reported.
const PLACED_COEFFICIENTS: f64 = 1e-6;

/// Newton's method on the KKT system from one start; `Some` when it converges to a point
/// satisfying the second-order condition for a minimum.
///
/// Converged means the constraints below 10⁻¹³ and the Lagrangian's gradient below 10⁻¹²,
/// absolute; or, when eighty steps do not reach that, both below [`RELATIVE_RESIDUAL`] times
/// the size of their terms at the last point (the iteration has reached the resolution of f64
/// for this plant's numbers) with every coefficient placed to [`PLACED_COEFFICIENTS`], checked
/// exactly.
fn newton_kkt(cons: &Constraints, start: DVector<f64>) -> Option<Converged> {
    let m = cons.variables.len();
    let r = cons.equations.len();
    let mut k = start;
    // restoration onto g = 0, absolute; on without it when 60 steps do not get there
    gauss_newton(cons, &mut k, |g, _| g.amax() < 1e-13)?;
    let jac = cons.jacobian(&k);
    let mut mu = multipliers(&jac, &k)?;
    for _ in 0..80 {
        let jac = cons.jacobian(&k);
        let g = cons.values(&k);
        let grad = &k * 2.0 + jac.transpose() * &mu;
        if grad.amax() < 1e-12 && g.amax() < 1e-13 {
            return second_order_minimum(cons, k, &mu, &jac).map(|(k, cost)| Converged::Minimum {
                k,
                cost,
                placement_error: None,
            });
        }
        let d = kkt_step(&cons.lagrangian_hessian(&k, &mu), &jac, &grad, &g)?;
        k += d.rows(0, m);
        mu += d.rows(m, r);
        if !k.iter().all(|x| x.is_finite()) || k.amax() > 1e6 {
            return None;
        }
    }
    // not reached absolutely: reached to the resolution of the plant's numbers?
    let jac = cons.jacobian(&k);
    let g = cons.values(&k);
    let grad = &k * 2.0 + jac.transpose() * &mu;
    let size = cons.magnitudes(&k);
    // the gradient's terms: 2|k_j| and |∂g_i/∂k_j| |μ_i|
    let grad_size = k.abs() * 2.0 + jac.abs().transpose() * mu.abs();
    let within = |residual: &DVector<f64>, size: &DVector<f64>| {
        residual
            .iter()
            .zip(size.iter())
            .all(|(x, s)| x.abs() <= RELATIVE_RESIDUAL * s.max(1.0))
    };
    if !(within(&g, &size) && within(&grad, &grad_size)) {
        return None;
    }
    // the placement checked exactly, on the gain as it is reported
    let errors = cons.placement_errors(&k)?;
    let worst = errors.iter().copied().fold(0.0, f64::max);
    if worst > PLACED_COEFFICIENTS {
        return Some(Converged::Unplaced(worst));
    }
    second_order_minimum(cons, k, &mu, &jac).map(|(k, cost)| Converged::Minimum {
        k,
        cost,
        placement_error: Some(worst),
    })
}

/// The Newton step on the KKT system `2k + Jᵀμ = 0, g(k) = 0`: the solution (d_k, d_μ) of
/// `[H Jᵀ; J 0] d = −[∇L; g]`, H the Lagrangian's Hessian; `None` when that matrix is singular.
fn kkt_step(
    hl: &DMatrix<f64>,
    jac: &DMatrix<f64>,
    grad: &DVector<f64>,
    g: &DVector<f64>,
) -> Option<DVector<f64>> {
    let (r, m) = jac.shape();
    let mut kkt = DMatrix::<f64>::zeros(m + r, m + r);
    kkt.view_mut((0, 0), (m, m)).copy_from(hl);
    kkt.view_mut((0, m), (m, r)).copy_from(&jac.transpose());
    kkt.view_mut((m, 0), (r, m)).copy_from(jac);
    let mut rhs = DVector::<f64>::zeros(m + r);
    rhs.rows_mut(0, m).copy_from(&(-grad));
    rhs.rows_mut(m, r).copy_from(&(-g));
    kkt.lu().solve(&rhs)
}

/// Least-norm Gauss–Newton steps onto g = 0 from `k`, at most 60, until `reached(g, k)`:
/// `Some(true)` when it is, `Some(false)` when 60 steps do not get there, `None` when J Jᵀ is
/// singular or `k` leaves the finite numbers (from where no start converges).
fn gauss_newton(
    cons: &Constraints,
    k: &mut DVector<f64>,
    reached: impl Fn(&DVector<f64>, &DVector<f64>) -> bool,
) -> Option<bool> {
    for _ in 0..60 {
        let g = cons.values(k);
        if reached(&g, k) {
            return Some(true);
        }
        let jac = cons.jacobian(k);
        let step = jac.transpose() * (&jac * jac.transpose()).try_inverse()? * g;
        *k -= step;
        if !k.iter().all(|x| x.is_finite()) {
            return None;
        }
    }
    Some(false)
}

/// The least-squares multipliers at `k`, μ = −(J Jᵀ)⁻¹ J (2k): those that make the
/// Lagrangian's gradient 2k + Jᵀμ smallest (at a feasible point, the projected gradient).
fn multipliers(jac: &DMatrix<f64>, k: &DVector<f64>) -> Option<DVector<f64>> {
    Some(-(jac * jac.transpose()).try_inverse()? * (jac * (k * 2.0)))
}

/// Onto the constraint set from `k` (see [`gauss_newton`]), until each residual is below
/// 10⁻¹³ or [`RELATIVE_RESIDUAL`] of the size of its terms: `None` when it does not get there.
fn restore(cons: &Constraints, mut k: DVector<f64>) -> Option<DVector<f64>> {
    let reached = gauss_newton(cons, &mut k, |g, k| {
        let size = cons.magnitudes(k);
        g.iter()
            .zip(size.iter())
            .all(|(x, s)| x.abs() <= (RELATIVE_RESIDUAL * s).max(1e-13))
    })?;
    reached.then_some(k)
}

/// A start for [`newton_kkt`] near a local minimum: from `start` brought onto the constraint
/// set, up to 200 moves, each the KKT step (or, where that does not descend, minus the
/// projected gradient) scaled by the first of 1, ½, ¼, … after which [`restore`] brings the
/// point back onto the set with a smaller `J1`. It stops where the projected gradient is below
/// 10⁻⁹ of the gain's largest entry, no scale helps or the search's time is up; `None` when
/// `start` cannot be brought onto the set. A feasible descent method (a merit function on the set itself): Newton's
/// own steps, undamped, are what leave the set on larger plants.
fn descend_on_constraints(
    cons: &Constraints,
    start: DVector<f64>,
    search: &Multistart,
) -> Option<DVector<f64>> {
    let m = cons.variables.len();
    let mut k = restore(cons, start)?;
    for _ in 0..200 {
        if search.out_of_time() {
            break;
        }
        let jac = cons.jacobian(&k);
        let mu = multipliers(&jac, &k)?;
        let grad = &k * 2.0 + jac.transpose() * &mu;
        if grad.amax() <= 1e-9 * k.amax().max(1.0) {
            break;
        }
        let g = cons.values(&k);
        let mut d = match kkt_step(&cons.lagrangian_hessian(&k, &mu), &jac, &grad, &g) {
            Some(d) => d.rows(0, m).into_owned(),
            None => -grad.clone(),
        };
        if d.dot(&grad) >= 0.0 {
            d = -grad.clone();
        }
        let cost = k.norm_squared();
        let mut alpha = 1.0;
        let mut moved = false;
        while alpha > 1e-10 {
            if let Some(next) = restore(cons, &k + &d * alpha) {
                if next.norm_squared() < cost {
                    k = next;
                    moved = true;
                    break;
                }
            }
            alpha /= 2.0;
        }
        if !moved {
            break;
        }
    }
    Some(k)
}

/// Where a start's iteration ended, when it converged.
enum Converged {
    /// At a local minimum.
    Minimum {
        k: DVector<f64>,
        cost: f64,
        /// See [`LocalMinimum::placement_error`].
        placement_error: Option<f64>,
    },
    /// At f64's resolution for the plant's terms, with the polynomial placed only to this
    /// relative error, beyond [`PLACED_COEFFICIENTS`].
    Unplaced(f64),
}

/// `k` with its cost when the Hessian of the Lagrangian is positive definite on the tangent
/// space of the constraints (a strict local minimum); `None` otherwise.
fn second_order_minimum(
    cons: &Constraints,
    k: DVector<f64>,
    mu: &DVector<f64>,
    jac: &DMatrix<f64>,
) -> Option<(DVector<f64>, f64)> {
    let m = cons.variables.len();
    let r = cons.equations.len();
    let hl = cons.lagrangian_hessian(&k, mu);
    // tangent basis: the right singular vectors of the smallest singular values of the
    // Jacobian padded to square (its null space)
    let mut padded = DMatrix::zeros(m, m);
    padded.view_mut((0, 0), (r, m)).copy_from(jac);
    let svd = crate::linalg::float::try_svd(&padded, false, true)?;
    let vt = svd.v_t?;
    let mut idx: Vec<usize> = (0..m).collect();
    idx.sort_by(|&a, &b| svd.singular_values[a].total_cmp(&svd.singular_values[b]));
    let z = DMatrix::from_fn(m, m - r, |i, j| vt[(idx[j], i)]);
    let reduced = z.transpose() * hl * &z;
    // NaN when it cannot be computed: not a minimum
    let min_eig =
        crate::linalg::float::symmetric_eigen(&reduced).map_or(f64::NAN, |e| e.eigenvalues.min());
    let cost = k.norm_squared();
    (min_eig > 1e-9).then_some((k, cost))
}

/// Minimises `J1 = Σ k_i²` subject to the constraints from `starts` seeded random starts
/// (entries uniform in [−15, 15]), each by Newton's method on the KKT system.
///
/// When none of them converges — nor reaches f64's resolution with an unplaced gain — the same
/// starts are taken again, each first moved by a descent on the constraint set
/// (`descend_on_constraints`): on larger plants (order 15 and more, entries near 1) Newton's
/// undamped steps leave the constraint set from every random start. The minima are still those
/// Newton's method accepts, with the same tests.
pub fn minimum_norm_gain(cons: &Constraints, search: Multistart) -> MinimumNormReport {
    let m = cons.variables.len();
    let draw =
        |uniform: &mut dyn FnMut() -> f64| DVector::from_fn(m, |_, _| 30.0 * uniform() - 15.0);
    let mut uniform = super::search::seeded_uniform(search.seed);
    let mut found = Found::default();
    let mut starts = 0;
    let mut out_of_time = false;
    for _ in 0..search.starts {
        if search.out_of_time() {
            out_of_time = true;
            break;
        }
        starts += 1;
        let start = draw(&mut uniform);
        found.add(cons, newton_kkt(cons, start));
        search.started();
    }
    let mut descended = 0;
    if found.converged == 0 && found.unplaced.is_none() {
        let mut uniform = super::search::seeded_uniform(search.seed);
        for _ in 0..starts {
            if search.out_of_time() {
                out_of_time = true;
                break;
            }
            descended += 1;
            let start = draw(&mut uniform);
            if let Some(start) = descend_on_constraints(cons, start, &search) {
                found.add(cons, newton_kkt(cons, start));
            }
        }
    }
    let Found {
        mut minima,
        converged,
        unplaced,
    } = found;
    minima.sort_by(|a, b| a.cost.total_cmp(&b.cost));
    let best = minima.first().map_or(f64::NAN, |x| x.cost);
    let best_count = minima
        .iter()
        .filter(|x| (x.cost - best).abs() <= 1e-9 * best.abs().max(1.0))
        .count();
    MinimumNormReport {
        starts,
        descended,
        converged,
        out_of_time,
        minima,
        best_count,
        unplaced,
    }
}

/// What the starts have found so far.
#[derive(Default)]
struct Found {
    minima: Vec<LocalMinimum>,
    converged: usize,
    unplaced: Option<f64>,
}

impl Found {
    /// One start's end: a minimum counted (a new one, or one more start reaching one found
    /// before), or the closest unplaced point kept.
    fn add(&mut self, cons: &Constraints, end: Option<Converged>) {
        let (k, cost, placement_error) = match end {
            Some(Converged::Minimum {
                k,
                cost,
                placement_error,
            }) => (k, cost, placement_error),
            Some(Converged::Unplaced(error)) => {
                self.unplaced = Some(self.unplaced.map_or(error, |e: f64| e.min(error)));
                return;
            }
            None => return,
        };
        self.converged += 1;
        let residual = cons.values(&k).amax();
        match self.minima.iter_mut().find(|x| {
            x.gain
                .iter()
                .zip(k.iter())
                .all(|(a, b)| (a - b).abs() < 1e-6 * (1.0 + a.abs()))
        }) {
            Some(x) => x.starts += 1,
            None => self.minima.push(LocalMinimum {
                gain: k.iter().copied().collect(),
                cost,
                starts: 1,
                constraint_residual: residual,
                placement_error,
            }),
        }
    }
}

/// The gain as an `n × p` matrix from `k1, k2, …` filled column by column.
pub fn gain_matrix(k: &[f64], n: usize, p: usize) -> DMatrix<f64> {
    DMatrix::from_fn(n, p, |i, j| k[j * n + i])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::syntax::parse_matrix;

    proptest::proptest! {
        /// The constraints written down from Sylvester's identity are the coefficients of the
        /// characteristic polynomial of A − GC taken symbolically, on random plants of orders
        /// 1–5 with one to three outputs (rank-deficient C included).
        #[test]
        fn constraints_are_the_symbolic_characteristic_polynomial(
            n in 1usize..=5,
            p in 1usize..=3,
            entries in proptest::collection::vec(-4i64..=4, 25 + 15 + 5),
        ) {
            let a = Matrix::from_fn(n, n, |i, j| Rational::from_i64(entries[5 * i + j]));
            let c = Matrix::from_fn(p, n, |i, j| Rational::from_i64(entries[25 + 5 * i + j]));
            let desired = Poly::new(
                (0..n).map(|k| Rational::from_i64(entries[40 + k])).chain([Rational::from_i64(1)]).collect(),
                "λ",
            );
            let ours = pole_placement_constraints(&a, &c, &desired).unwrap();
            let g = Matrix::from_fn(n, p, |i, j| MultiPoly::var(&ours.variables[j * n + i]));
            let lift = |m: &Matrix<Rational>| m.map(|x| MultiPoly::constant(x.clone()));
            let obs = lift(&a).sub(&g.mul(&lift(&c)).unwrap()).unwrap();
            let cp = linalg::berkowitz(&obs, "λ").unwrap();
            for i in 1..=n {
                let symbolic = cp.coeff(n - i) - MultiPoly::constant(desired.coeff(n - i));
                proptest::prop_assert_eq!(&ours.equations[i - 1], &symbolic, "λ^{}", n - i);
            }
        }
    }

    #[test]
    fn baranowski_minimum_norm_gain() {
        let a = parse_matrix::<Rational>("[-2 1 0; 1 -2 1; 0 1 -2]").unwrap();
        let c = parse_matrix::<Rational>("[1 0 0; 0 0 1]").unwrap();
        let desired = Poly::from_roots(
            &[
                Rational::from_i64(-4),
                Rational::from_i64(-4),
                Rational::from_i64(-4),
            ],
            "s",
        );
        let cons = pole_placement_constraints(&a, &c, &desired).unwrap();
        let r = minimum_norm_gain(&cons, Multistart::new(60, 2024));
        assert!(r.converged > 0);
        let best = &r.minima[0];
        assert!(best.constraint_residual < 1e-10);
        // the mirror image of the ladder maps a minimiser to another one with the same cost
        assert!(r.best_count >= 1);
        assert!(
            (best.cost - 29.0466).abs() < 5e-5,
            "printed J1 = 29.0466, found {}",
            best.cost
        );
    }
}
