//! Perfect (descriptor) observers `E x̂' = F x̂ + G_u u + G_y y` (Sławiński, eq. (2), (7)–(8),
//! Examples 1–2), for one or several outputs, with the exact conditions under which one
//! observer stays perfect when the plant changes (the paper's "complete robustness").
//!
//! Construction (our route to the paper's Lemma 1 form): pick rows `c_i A^k` of the
//! observability matrix in the usual order (`C`, then `CA`, …), keeping a row when it is
//! independent of those kept and the previous row of its chain was kept; chain `i` has length
//! `ν_i` (the observability indices) and the kept rows form an invertible `T`. In `x̄ = T x`
//! every chain is a shift: `(c_i A^k x)' = c_i A^(k+1) x + c_i A^k B u` for `k < ν_i − 1`.
//! Those `n − p` equations and the `p` algebraic equations `0 = C x̂ + D u − y` make the
//! observer. `det(Es − F)` is a nonzero constant, so it has no dynamics and `x̂ = x` for all
//! `t > 0`, whatever the initial condition.
//!
//! Robustness: for a plant `(A', B', C', D')` the true state satisfies the observer's equations
//! for all `x`, `u` iff `E A' = F + G_y C'` and `E B' = G_u + G_y D'`; then the error obeys
//! `E e' = F e` and vanishes for `t > 0`. Written with a symbolic plant these are affine
//! equations in its entries: exactly the changes the observer tolerates.

use crate::algebra::{MultiPoly, One, Rational, Ring, Zero};
use crate::derivation::{Derivation, Words};
use crate::linalg::{self, Matrix};
use crate::observability::{require_observable, ObservabilityError};
use crate::poly::Poly;
use crate::system::StateSpace;

/// The coefficients `(U_k, Y_k)` of `u^(k)` and `y^(k)` in the reconstruction of `x̂`.
pub type Term = (Matrix<Rational>, Matrix<Rational>);

/// A perfect observer `E x̂' = F x̂ + G_u u + G_y y`, with its working.
#[derive(Clone, PartialEq, Debug)]
pub struct PerfectObserver {
    /// The transformation `T` (chosen rows `c_i A^k`, chain by chain).
    pub t: Matrix<Rational>,
    /// The chain lengths `ν_i` (observability indices), one per output.
    pub indices: Vec<usize>,
    /// `E` (singular).
    pub e: Matrix<Rational>,
    /// `F`.
    pub f: Matrix<Rational>,
    /// The input matrix `G_u` (multiplies `u`).
    pub input_matrix: Matrix<Rational>,
    /// The output matrix `G_y` (multiplies `y`).
    pub output_matrix: Matrix<Rational>,
    /// `det(Es − F)`.
    pub pencil_determinant: Poly<Rational>,
    /// `x̂ = Σ_k (U_k u^(k) + Y_k y^(k))`: the coefficient matrices `(U_k, Y_k)`, `k = 0, 1, …`.
    pub reconstruction: Vec<Term>,
    /// The steps.
    pub derivation: Derivation,
}

/// Why a perfect observer could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PerfectObserverError {
    /// C has dependent rows: an output repeats the others.
    #[error("the rows of C are linearly dependent (rank {rank} < {rows} outputs): drop the redundant outputs")]
    DependentOutputs {
        /// rank C.
        rank: usize,
        /// rows of C.
        rows: usize,
    },
    /// The pair is not observable: no perfect observer exists.
    #[error(transparent)]
    Observability(#[from] ObservabilityError),
    /// A matrix computation failed.
    #[error(transparent)]
    Linalg(#[from] linalg::LinalgError),
}

/// The chosen observability rows `c_i A^k` chain by chain, and the chain lengths.
fn observability_chains(
    a: &Matrix<Rational>,
    c: &Matrix<Rational>,
) -> Result<(Matrix<Rational>, Vec<usize>), PerfectObserverError> {
    let (n, p) = (a.rows(), c.rows());
    let rank_c = linalg::rank(c);
    if rank_c < p {
        return Err(PerfectObserverError::DependentOutputs {
            rank: rank_c,
            rows: p,
        });
    }
    require_observable(a, c)?;
    let mut current: Vec<Matrix<Rational>> = (0..p).map(|i| c.block(i, i + 1, 0, n)).collect();
    let mut alive = vec![true; p];
    let mut chains: Vec<Vec<Matrix<Rational>>> = vec![Vec::new(); p];
    let mut kept: Option<Matrix<Rational>> = None;
    let mut count = 0;
    while count < n {
        for i in 0..p {
            if !alive[i] || count == n {
                continue;
            }
            let trial = match &kept {
                Some(k) => k.vstack(&current[i])?,
                None => current[i].clone(),
            };
            if linalg::rank(&trial) > count {
                count += 1;
                kept = Some(trial);
                chains[i].push(current[i].clone());
                current[i] = current[i].mul(a)?;
            } else {
                alive[i] = false;
            }
        }
    }
    let indices: Vec<usize> = chains.iter().map(Vec::len).collect();
    let mut rows = chains.into_iter().flatten();
    let first = rows.next().unwrap_or_else(|| Matrix::zeros(0, n));
    let t = rows.try_fold(first, |acc, r| acc.vstack(&r))?;
    Ok((t, indices))
}

/// Builds the perfect observer of an observable system with independent outputs.
///
/// # Example
/// ```
/// use observer_workbench::algebra::Rational;
/// use observer_workbench::observer::perfect::perfect_observer;
/// use observer_workbench::syntax::parse_matrix;
/// use observer_workbench::system::StateSpace;
/// let m = |s: &str| parse_matrix::<Rational>(s).unwrap();
/// let plant = StateSpace::new(m("[0 1 0; 0 0 1; -6 -11 -6]"), Some(m("[3; 2; 1]")), m("[1 0 0]"), None).unwrap();
/// let p = perfect_observer(&plant).unwrap();
/// assert_eq!(p.f.to_input(), "[0, 1, 0; 0, 0, 1; 1, 0, 0]");
/// assert_eq!(p.output_matrix.to_input(), "[0; 0; -1]");
/// assert_eq!(p.pencil_determinant.to_string(), "-1");
/// ```
///
/// # Errors
/// [`PerfectObserverError`] for an unobservable pair or dependent outputs.
pub fn perfect_observer(
    plant: &StateSpace<Rational>,
) -> Result<PerfectObserver, PerfectObserverError> {
    let (a, b, c, d) = (plant.a(), plant.b(), plant.c(), plant.d());
    let (n, m, p) = (plant.order(), plant.inputs(), plant.outputs());
    let (t, indices) = observability_chains(a, c)?;
    let tb = t.mul(b)?;
    let ta = t.mul(a)?;
    let mut e = Matrix::zeros(n, n);
    let mut f = Matrix::zeros(n, n);
    let mut gu = Matrix::zeros(n, m);
    let mut gy = Matrix::zeros(n, p);
    let mut row = 0;
    let mut start = 0;
    for &nu in &indices {
        for k in 0..nu.saturating_sub(1) {
            for j in 0..n {
                e.set(row, j, t.get(start + k, j).clone());
                f.set(row, j, ta.get(start + k, j).clone());
            }
            for j in 0..m {
                gu.set(row, j, tb.get(start + k, j).clone());
            }
            row += 1;
        }
        start += nu;
    }
    for i in 0..p {
        for j in 0..n {
            f.set(row, j, c.get(i, j).clone());
        }
        for j in 0..m {
            gu.set(row, j, d.get(i, j).clone());
        }
        gy.set(row, i, -Rational::one());
        row += 1;
    }
    let pencil_determinant = pencil_determinant(&e, &f)?;
    let reconstruction = reconstruction(&e, &f, &gu, &gy)?;
    let mut derivation = Derivation::new(&format!(
        "Perfect observer E x̂' = F x̂ + G_u u + G_y y ({p} output{})",
        if p == 1 { "" } else { "s" }
    ));
    let nu_text: Vec<String> = indices.iter().map(ToString::to_string).collect();
    derivation.push(
        "ν",
        "chain lengths (observability indices)",
        &Words(nu_text.join(", ")),
    );
    derivation.push("T", "rows c_i A^k, k < ν_i, chain by chain", &t);
    derivation.push(
        "T A T⁻¹",
        "a shift in every chain",
        &ta.mul(&linalg::inverse(&t)?)?,
    );
    derivation.push("T B", "", &tb);
    derivation.push("E", "[rows c_i A^k, k < ν_i − 1; 0]", &e);
    derivation.push("F", "[rows c_i A^(k+1); C]", &f);
    derivation.push("G_u", "[rows c_i A^k B; D]", &gu);
    derivation.push("G_y", "[0; −I]", &gy);
    derivation.push("det(Es − F)", "a nonzero constant", &pencil_determinant);
    derivation.push(
        "x̂",
        "(Es − F)⁻¹ (G_u u + G_y y): y, u and their derivatives",
        &Reconstruction(&reconstruction),
    );
    Ok(PerfectObserver {
        t,
        indices,
        e,
        f,
        input_matrix: gu,
        output_matrix: gy,
        pencil_determinant,
        reconstruction,
        derivation,
    })
}

/// `det(Es − F)` over the polynomials in `s` (fraction-free, division-free).
fn pencil_determinant(
    e: &Matrix<Rational>,
    f: &Matrix<Rational>,
) -> Result<Poly<Rational>, linalg::LinalgError> {
    let s = MultiPoly::var("s");
    let pencil = Matrix::from_fn(e.rows(), e.cols(), |i, j| {
        s.clone() * MultiPoly::constant(e.get(i, j).clone())
            - MultiPoly::constant(f.get(i, j).clone())
    });
    let det = linalg::elimination::determinant_in_domain(&pencil)?;
    let coeffs: Vec<Rational> = det
        .coefficients_in("s")
        .iter()
        .map(|c| c.as_constant().unwrap_or_default())
        .collect();
    Ok(Poly::new(coeffs, "s"))
}

/// `(Es − F)⁻¹ = −Σ_k s^k (F⁻¹E)^k F⁻¹` (`F⁻¹E` is nilpotent when `det(Es − F)` is constant),
/// applied to `[G_u G_y]`: the coefficients of `u^(k)` and `y^(k)` in `x̂`.
fn reconstruction(
    e: &Matrix<Rational>,
    f: &Matrix<Rational>,
    gu: &Matrix<Rational>,
    gy: &Matrix<Rational>,
) -> Result<Vec<Term>, linalg::LinalgError> {
    let n = e.rows();
    let f_inv = linalg::inverse(f)?;
    let nil = f_inv.mul(e)?;
    let mut power = f_inv.neg();
    let mut out = Vec::new();
    for _ in 0..n {
        let u = power.mul(gu)?;
        let y = power.mul(gy)?;
        if u.is_zero() && y.is_zero() {
            break;
        }
        out.push((u, y));
        power = nil.mul(&power)?;
    }
    Ok(out)
}

/// The reconstruction `x̂ = Σ_k (U_k u^(k) + Y_k y^(k))`, shown per state.
pub struct Reconstruction<'a>(pub &'a [Term]);

impl Reconstruction<'_> {
    /// Per state, the terms `(coefficient, signal, derivative order)`, highest order first.
    fn terms(&self) -> Vec<Vec<(Rational, String, usize)>> {
        let Some((u0, y0)) = self.0.first() else {
            return Vec::new();
        };
        let (n, m, p) = (u0.rows(), u0.cols(), y0.cols());
        let name = |base: &str, j: usize, count: usize| {
            if count > 1 {
                format!("{base}{}", j + 1)
            } else {
                base.to_string()
            }
        };
        (0..n)
            .map(|i| {
                let mut out = Vec::new();
                for (k, (u, y)) in self.0.iter().enumerate().rev() {
                    for j in 0..p {
                        out.push((y.get(i, j).clone(), name("y", j, p), k));
                    }
                    for j in 0..m {
                        out.push((u.get(i, j).clone(), name("u", j, m), k));
                    }
                }
                out.retain(|t| !t.0.is_zero());
                out
            })
            .collect()
    }

    fn render(
        &self,
        signal: impl Fn(&str, usize) -> String,
        coefficient: impl Fn(&Rational) -> String,
        lhs: impl Fn(usize) -> String,
        sep: &str,
    ) -> String {
        self.terms()
            .iter()
            .enumerate()
            .map(|(i, terms)| {
                let mut text = String::new();
                for (t, (c, name, k)) in terms.iter().enumerate() {
                    let negative = *c < Rational::zero();
                    let magnitude = if negative { -c.clone() } else { c.clone() };
                    let sign = match (t, negative) {
                        (0, false) => "",
                        (0, true) => "−",
                        (_, false) => " + ",
                        (_, true) => " − ",
                    };
                    let coef = if magnitude.is_one() {
                        String::new()
                    } else {
                        coefficient(&magnitude)
                    };
                    text.push_str(&format!("{sign}{coef}{}", signal(name, *k)));
                }
                if terms.is_empty() {
                    text.push('0');
                }
                format!("{} = {text}", lhs(i))
            })
            .collect::<Vec<_>>()
            .join(sep)
    }
}

impl crate::derivation::Show for Reconstruction<'_> {
    fn text(&self) -> String {
        self.render(
            |name, k| match k {
                0 => name.to_string(),
                1 => format!("{name}'"),
                2 => format!("{name}''"),
                _ => format!("{name}^({k})"),
            },
            |c| format!("{c} "),
            |i| format!("x̂{}", i + 1),
            "\n",
        )
    }
    fn latex(&self) -> String {
        let body = self.render(
            |name, k| {
                let (base, index) = name.split_at(1);
                let sym = if index.is_empty() {
                    base.to_string()
                } else {
                    format!("{base}_{{{index}}}")
                };
                match k {
                    0 => sym,
                    1 => format!("\\dot{{{sym}}}"),
                    2 => format!("\\ddot{{{sym}}}"),
                    _ => format!("{sym}^{{({k})}}"),
                }
            },
            |c| format!("{} ", Ring::to_latex(c)).replace("−", "-"),
            |i| format!("\\hat{{x}}_{{{}}}", i + 1),
            " \\\\ ",
        );
        format!(
            "\\begin{{gathered}} {} \\end{{gathered}}",
            body.replace('−', "-")
        )
    }
    fn input(&self) -> String {
        self.text().replace('\n', "; ")
    }
}

/// The conditions on a changed plant `(A', B', C', D')` under which `observer` stays perfect:
/// the nonzero entries of `E A' − F − G_y C'` and `E B' − G_u − G_y D'` with every entry of the
/// plant a symbol (`a11 … , b11 …, c11 …, d11 …`), each an affine equation `… = 0`.
/// An empty list would mean the observer fits every plant.
pub fn robustness_conditions(observer: &PerfectObserver) -> Vec<MultiPoly> {
    let (n, m, p) = (
        observer.e.rows(),
        observer.input_matrix.cols(),
        observer.output_matrix.cols(),
    );
    let sym = |name: &str, rows: usize, cols: usize| {
        Matrix::from_fn(rows, cols, |i, j| {
            MultiPoly::var(&format!("{name}{}{}", i + 1, j + 1))
        })
    };
    let lift = |x: &Matrix<Rational>| x.map(|v| MultiPoly::constant(v.clone()));
    let (a, b, c, d) = (
        sym("a", n, n),
        sym("b", n, m),
        sym("c", p, n),
        sym("d", p, m),
    );
    let (e, f, gu, gy) = (
        lift(&observer.e),
        lift(&observer.f),
        lift(&observer.input_matrix),
        lift(&observer.output_matrix),
    );
    let residual = |x: Result<Matrix<MultiPoly>, linalg::LinalgError>| x.ok();
    let ra = residual(
        e.mul(&a)
            .and_then(|ea| ea.sub(&f))
            .and_then(|r| r.sub(&gy.mul(&c)?)),
    );
    let rb = residual(
        e.mul(&b)
            .and_then(|eb| eb.sub(&gu))
            .and_then(|r| r.sub(&gy.mul(&d)?)),
    );
    [ra, rb]
        .into_iter()
        .flatten()
        .flat_map(|r| {
            let mut entries = Vec::new();
            for i in 0..r.rows() {
                for j in 0..r.cols() {
                    entries.push(r.get(i, j).clone());
                }
            }
            entries
        })
        .filter(|x| !x.is_zero())
        .collect()
}

/// Whether `observer` stays perfect for the plant `(A', B', C', D')`: the residual matrices
/// `E A' − F − G_y C'` and `E B' − G_u − G_y D'`, both zero iff it does.
///
/// # Errors
/// A dimension mismatch.
pub fn robustness_residuals(
    observer: &PerfectObserver,
    plant: &StateSpace<Rational>,
) -> Result<(Matrix<Rational>, Matrix<Rational>), linalg::LinalgError> {
    let (a, b, c, d) = (plant.a(), plant.b(), plant.c(), plant.d());
    let ra = observer
        .e
        .mul(a)?
        .sub(&observer.f)?
        .sub(&observer.output_matrix.mul(c)?)?;
    let rb = observer
        .e
        .mul(b)?
        .sub(&observer.input_matrix)?
        .sub(&observer.output_matrix.mul(d)?)?;
    Ok((ra, rb))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::syntax::parse_matrix;

    fn m(s: &str) -> Matrix<Rational> {
        parse_matrix(s).unwrap()
    }

    #[test]
    fn two_outputs_give_a_constant_pencil_and_exact_reconstruction() {
        let a = m("[0 1 0 0; -2 -3 1 0; 0 0 0 1; 1 0 -4 -1]");
        let b = m("[0; 1; 0; 2]");
        let c = m("[1 0 0 0; 0 0 1 0]");
        let plant = StateSpace::new(a, Some(b.clone()), c.clone(), None).unwrap();
        let p = perfect_observer(&plant).unwrap();
        assert_eq!(p.indices, vec![2, 2]);
        assert_eq!(p.pencil_determinant.degree(), Some(0));
        assert!(!p.pencil_determinant.coeff(0).is_zero());
        // the plant itself satisfies the observer's equations
        let (ra, rb) = robustness_residuals(&p, &plant).unwrap();
        assert!(ra.is_zero() && rb.is_zero());
        // a change in a row the observer uses breaks it
        let changed = StateSpace::new(
            m("[0 2 0 0; -2 -3 1 0; 0 0 0 1; 1 0 -4 -1]"),
            Some(b),
            c,
            None,
        )
        .unwrap();
        let (ra, _) = robustness_residuals(&p, &changed).unwrap();
        assert!(!ra.is_zero());
    }

    #[test]
    fn dependent_outputs_are_refused() {
        let plant =
            StateSpace::new(m("[0 1; -1 0]"), Some(m("[0; 1]")), m("[1 0; 2 0]"), None).unwrap();
        let err = perfect_observer(&plant).unwrap_err();
        assert!(matches!(
            err,
            PerfectObserverError::DependentOutputs { rank: 1, rows: 2 }
        ));
    }
}
