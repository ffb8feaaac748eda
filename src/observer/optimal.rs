//! Multi-output gains chosen by optimality (Baranowski, §4–5): among all gains `G` that place
//! the observer polynomial exactly, the one of minimum norm `J1 = Σ k_i²`.
//!
//! The constraints are the coefficient equations of `det(λI − (A − GC))` against the desired
//! polynomial, derived symbolically (eq. (15)); their exact Jacobians and Hessians come from
//! differentiating those polynomials. Newton's method on the Karush–Kuhn–Tucker system
//! `2k + Jᵀμ = 0, g(k) = 0` is run from many seeded random starts — converged when the
//! residuals are below 10⁻¹³, or, for plants whose coefficients put that below f64's
//! resolution, below 10⁻¹² of the size of their terms (the report then gives the residual);
//! each converged point is
//! classified (second-order test on the tangent space), and the report says how many starts
//! reached the best minimum, which other minima exist, and whether the best is unique.

use super::search::Multistart;
use crate::algebra::{MultiPoly, Rational};
use crate::linalg::{self, Matrix};
use crate::poly::Poly;
use nalgebra::{DMatrix, DVector};
use serde::Serialize;
use std::collections::BTreeMap;

/// Pole-placement equations `g_i(k) = 0` with exact derivatives.
#[derive(Clone, Debug)]
pub struct Constraints {
    /// The gain symbols, in the order of the gain matrix read column by column.
    pub variables: Vec<String>,
    /// `g_i`: coefficient of `λ^(n−i)` minus the desired one.
    pub equations: Vec<MultiPoly>,
    jacobian: Vec<Vec<MultiPoly>>,
    hessians: Vec<Vec<Vec<MultiPoly>>>,
}

/// The constraints for a gain of symbols `k1, k2, …` (filled column by column, as Baranowski's
/// eq. (14)) placing `det(λI − (A − GC))` at `desired`.
///
/// # Errors
/// A message for mismatched dimensions.
pub fn pole_placement_constraints(
    a: &Matrix<Rational>,
    c: &Matrix<Rational>,
    desired: &Poly<Rational>,
) -> Result<Constraints, linalg::LinalgError> {
    let (n, p) = (a.rows(), c.rows());
    let variables: Vec<String> = (0..n * p).map(|k| format!("k{}", k + 1)).collect();
    let g = Matrix::from_fn(n, p, |i, j| MultiPoly::var(&variables[j * n + i]));
    let lift = |m: &Matrix<Rational>| m.map(|x| MultiPoly::constant(x.clone()));
    let obs = lift(a).sub(&g.mul(&lift(c))?)?;
    let cp = linalg::berkowitz(&obs, "λ")?;
    let equations: Vec<MultiPoly> = (1..=n)
        .map(|i| cp.coeff(n - i) - MultiPoly::constant(desired.coeff(n - i)))
        .collect();
    let jacobian: Vec<Vec<MultiPoly>> = equations
        .iter()
        .map(|e| variables.iter().map(|v| e.derivative(v)).collect())
        .collect();
    let hessians = jacobian
        .iter()
        .map(|row| {
            row.iter()
                .map(|d| variables.iter().map(|v| d.derivative(v)).collect())
                .collect()
        })
        .collect();
    Ok(Constraints {
        variables,
        equations,
        jacobian,
        hessians,
    })
}

impl Constraints {
    fn point(&self, k: &DVector<f64>) -> BTreeMap<String, f64> {
        self.variables
            .iter()
            .cloned()
            .zip(k.iter().copied())
            .collect()
    }
    fn values(&self, k: &DVector<f64>) -> DVector<f64> {
        let x = self.point(k);
        DVector::from_iterator(
            self.equations.len(),
            self.equations.iter().map(|e| e.evaluate_f64(&x)),
        )
    }
    /// The size of each equation's terms at `k` (see [`MultiPoly::evaluate_abs_f64`]).
    fn magnitudes(&self, k: &DVector<f64>) -> DVector<f64> {
        let x = self.point(k);
        DVector::from_iterator(
            self.equations.len(),
            self.equations.iter().map(|e| e.evaluate_abs_f64(&x)),
        )
    }
    fn jacobian(&self, k: &DVector<f64>) -> DMatrix<f64> {
        let x = self.point(k);
        DMatrix::from_fn(self.equations.len(), self.variables.len(), |i, j| {
            self.jacobian[i][j].evaluate_f64(&x)
        })
    }
    fn hessian(&self, i: usize, k: &DVector<f64>) -> DMatrix<f64> {
        let x = self.point(k);
        let m = self.variables.len();
        DMatrix::from_fn(m, m, |a, b| self.hessians[i][a][b].evaluate_f64(&x))
    }
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
}

/// The result of the multistart minimum-norm search.
#[derive(Clone, Debug, Serialize)]
pub struct MinimumNormReport {
    /// Starts tried (seeded).
    pub starts: usize,
    /// Starts that converged to a local minimum.
    pub converged: usize,
    /// Distinct local minima, best first.
    pub minima: Vec<LocalMinimum>,
    /// Minima whose cost equals the best within 1e-9 (relative): more than one means the
    /// minimiser is not unique.
    pub best_count: usize,
}

/// The largest residual Newton's method is taken to reach on equations whose terms have size
/// `magnitude`, relative: f64 evaluates such an equation to within a few units of roundoff of
/// it for each of its terms, and a plant with entries up to 10 has order-5 terms of 10⁵ and
/// more, where the absolute 10⁻¹³ the iteration first asks for is below f64's resolution.
const RELATIVE_RESIDUAL: f64 = 1e-12;

/// Newton's method on the KKT system from one start; `Some` when it converges to a point
/// satisfying the second-order condition for a minimum.
///
/// Converged means the constraints below 10⁻¹³ and the Lagrangian's gradient below 10⁻¹²,
/// absolute; or, when eighty steps do not reach that, both below [`RELATIVE_RESIDUAL`] times
/// the size of their terms at the last point (the iteration has reached the resolution of f64
/// for this plant's numbers).
fn newton_kkt(cons: &Constraints, start: DVector<f64>) -> Option<(DVector<f64>, f64)> {
    let m = cons.variables.len();
    let r = cons.equations.len();
    let mut k = start;
    // restoration: least-norm Gauss–Newton steps onto g = 0
    for _ in 0..60 {
        let g = cons.values(&k);
        if g.amax() < 1e-13 {
            break;
        }
        let jac = cons.jacobian(&k);
        let step = jac.transpose() * (&jac * jac.transpose()).try_inverse()? * g;
        k -= step;
    }
    let jac = cons.jacobian(&k);
    let mut mu = -(&jac * jac.transpose()).try_inverse()? * (&jac * (&k * 2.0));
    for _ in 0..80 {
        let jac = cons.jacobian(&k);
        let g = cons.values(&k);
        let grad = &k * 2.0 + jac.transpose() * &mu;
        if grad.amax() < 1e-12 && g.amax() < 1e-13 {
            return second_order_minimum(cons, k, &mu, &jac);
        }
        let mut kkt = DMatrix::<f64>::zeros(m + r, m + r);
        let mut hl = DMatrix::<f64>::identity(m, m) * 2.0;
        for i in 0..r {
            hl += cons.hessian(i, &k) * mu[i];
        }
        kkt.view_mut((0, 0), (m, m)).copy_from(&hl);
        kkt.view_mut((0, m), (m, r)).copy_from(&jac.transpose());
        kkt.view_mut((m, 0), (r, m)).copy_from(&jac);
        let mut rhs = DVector::<f64>::zeros(m + r);
        rhs.rows_mut(0, m).copy_from(&(-grad));
        rhs.rows_mut(m, r).copy_from(&(-g));
        let d = kkt.lu().solve(&rhs)?;
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
    if within(&g, &size) && within(&grad, &grad_size) {
        return second_order_minimum(cons, k, &mu, &jac);
    }
    None
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
    let mut hl = DMatrix::<f64>::identity(m, m) * 2.0;
    for i in 0..r {
        hl += cons.hessian(i, &k) * mu[i];
    }
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
/// (entries uniform in [−15, 15]).
pub fn minimum_norm_gain(cons: &Constraints, search: Multistart) -> MinimumNormReport {
    let m = cons.variables.len();
    let mut starts = 0;
    let mut uniform = super::search::seeded_uniform(search.seed);
    let mut minima: Vec<LocalMinimum> = Vec::new();
    let mut converged = 0;
    for _ in 0..search.starts {
        if search.out_of_time() {
            break;
        }
        starts += 1;
        let start = DVector::from_fn(m, |_, _| 30.0 * uniform() - 15.0);
        let found = newton_kkt(cons, start);
        search.started();
        let Some((k, cost)) = found else {
            continue;
        };
        converged += 1;
        let residual = cons.values(&k).amax();
        match minima.iter_mut().find(|x| {
            x.gain
                .iter()
                .zip(k.iter())
                .all(|(a, b)| (a - b).abs() < 1e-6 * (1.0 + a.abs()))
        }) {
            Some(x) => x.starts += 1,
            None => minima.push(LocalMinimum {
                gain: k.iter().copied().collect(),
                cost,
                starts: 1,
                constraint_residual: residual,
            }),
        }
    }
    minima.sort_by(|a, b| a.cost.total_cmp(&b.cost));
    let best = minima.first().map_or(f64::NAN, |x| x.cost);
    let best_count = minima
        .iter()
        .filter(|x| (x.cost - best).abs() <= 1e-9 * best.abs().max(1.0))
        .count();
    MinimumNormReport {
        starts,
        converged,
        minima,
        best_count,
    }
}

/// The gain as an `n × p` matrix from `k1, k2, …` filled column by column.
pub fn gain_matrix(k: &[f64], n: usize, p: usize) -> DMatrix<f64> {
    DMatrix::from_fn(n, p, |i, j| k[j * n + i])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algebra::Ring;
    use crate::syntax::parse_matrix;

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
