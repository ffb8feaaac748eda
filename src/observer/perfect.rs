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
//!
//! Cost: every row of E and F is a row of T (checked, `ChainRows`), so `det(Es − F)` is one
//! determinant of T and a sign, the reconstruction one solve with T, `T A T⁻¹` p solved rows,
//! and the robustness conditions are written down term by term. At order 60 the time goes to
//! T⁻¹'s n² large fractions, which the reconstruction prints.

use crate::algebra::{Monomial, MultiPoly, One, Rational, Zero};
use crate::derivation::{Derivation, Words};
use crate::linalg::{self, Matrix};
use crate::observability::{require_observable, ObservabilityError};
use crate::poly::Poly;
use crate::system::StateSpace;
use num_traits::Signed;

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
    // row r of E, F and G_u: the shift c_i A^k (T's row q = e[r]) to c_i A^(k+1), or, in the
    // last p rows, output i's algebraic equation
    let rows = ChainRows::of(&indices);
    let mut e = Matrix::zeros(n, n);
    let mut f = Matrix::zeros(n, n);
    let mut gu = Matrix::zeros(n, m);
    let mut gy = Matrix::zeros(n, p);
    for (r, q) in rows.e.iter().enumerate() {
        match *q {
            Some(q) => {
                for j in 0..n {
                    e.set(r, j, t.get(q, j).clone());
                    f.set(r, j, ta.get(q, j).clone());
                }
                for j in 0..m {
                    gu.set(r, j, tb.get(q, j).clone());
                }
            }
            None => {
                let i = r + p - n;
                for j in 0..n {
                    f.set(r, j, c.get(i, j).clone());
                }
                for j in 0..m {
                    gu.set(r, j, d.get(i, j).clone());
                }
                gy.set(r, i, -Rational::one());
            }
        }
    }
    let (pencil_determinant, reconstruction, similar) = match rows.checked(&t, &e, &f) {
        Some(rows) => (
            rows.determinant(&t)?,
            rows.reconstruction(&t, &gu, &gy)?,
            rows.similar(&t, &ta)?,
        ),
        None => (
            pencil_determinant(&e, &f)?,
            reconstruction(&e, &f, &gu, &gy)?,
            linalg::solve(&t.transpose(), &ta.transpose())?.transpose(),
        ),
    };
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
    derivation.push("T A T⁻¹", "a shift in every chain", &similar);
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

/// `E = P_E T` and `F = P_F T`: the row of T that each row of E (`None`: a zero row) and of F
/// is. Every row of both is one by construction (the shifts `c_i A^k`, `k < ν_i`, and the rows
/// of C); [`ChainRows::checked`] checks it entry by entry.
struct ChainRows {
    e: Vec<Option<usize>>,
    f: Vec<usize>,
}

impl ChainRows {
    /// The rows for chains of lengths `indices`: chain i's rows `c_i A^k`, `k < ν_i − 1`, first
    /// (E has T's row, F the next one), then one row per output (E zero, F the chain's first).
    fn of(indices: &[usize]) -> ChainRows {
        let (mut e, mut f, mut starts) = (Vec::new(), Vec::new(), Vec::new());
        let mut start = 0;
        for &nu in indices {
            starts.push(start);
            for k in 0..nu.saturating_sub(1) {
                e.push(Some(start + k));
                f.push(start + k + 1);
            }
            start += nu;
        }
        for s in starts {
            e.push(None);
            f.push(s);
        }
        ChainRows { e, f }
    }

    /// Itself, when every row of E and F is exactly the row of T it is said to be, F's rows are
    /// all of T's (a permutation) and E's nonzero rows distinct ones; else `None`.
    fn checked(
        self,
        t: &Matrix<Rational>,
        e: &Matrix<Rational>,
        f: &Matrix<Rational>,
    ) -> Option<ChainRows> {
        let n = t.rows();
        if self.e.len() != n || self.f.len() != n {
            return None;
        }
        let mut seen_f = vec![false; n];
        let mut seen_e = vec![false; n];
        for r in 0..n {
            let k = self.f[r];
            if k >= n || std::mem::replace(&mut seen_f[k], true) || f.row(r) != t.row(k) {
                return None;
            }
            match self.e[r] {
                Some(k) => {
                    if k >= n || std::mem::replace(&mut seen_e[k], true) || e.row(r) != t.row(k) {
                        return None;
                    }
                }
                None => {
                    if !e.row(r).iter().all(Zero::is_zero) {
                        return None;
                    }
                }
            }
        }
        Some(self)
    }
}

impl ChainRows {
    /// `det(Es − F) = det(P_E s − P_F) · det T`, where `det(P_E s − P_F) = det(−P_F) ·
    /// det(I − s S)` with `S = P_Fᵀ P_E`. `P_F` is the permutation `r ↦ f[r]`, so
    /// `det(−P_F) = (−1)^n sgn`; `S` has a one at `(f[r], e[r])` and at most one in each row and
    /// column, so `det(I − s S)` is the product of `1 − s^L` over its cycles (length L; its
    /// open paths are nilpotent and give 1). Cost: one determinant of T (multimodular from
    /// order 8) and O(n) for the rest, where fraction-free elimination over polynomials in `s`
    /// took 53 % of the command at order 25.
    fn determinant(&self, t: &Matrix<Rational>) -> Result<Poly<Rational>, linalg::LinalgError> {
        let n = self.f.len();
        // sgn of r ↦ f[r]: (−1)^(n − number of cycles)
        let mut visited = vec![false; n];
        let mut cycles = 0;
        for r in 0..n {
            if !visited[r] {
                cycles += 1;
                let mut i = r;
                while !visited[i] {
                    visited[i] = true;
                    i = self.f[i];
                }
            }
        }
        let negative = (n - cycles) % 2 == 1;
        // S: f[r] → e[r]; the cycles of that partial map
        let mut next = vec![None; n];
        for r in 0..n {
            next[self.f[r]] = self.e[r];
        }
        let mut factor = Poly::new(vec![Rational::one()], "s");
        let mut done = vec![false; n];
        for start in 0..n {
            if done[start] {
                continue;
            }
            let mut path = Vec::new();
            let mut i = Some(start);
            while let Some(k) = i.filter(|&k| !done[k]) {
                done[k] = true;
                path.push(k);
                i = next[k];
            }
            // a cycle: the walk came back to where it started
            if i == Some(start) {
                let mut coeffs = vec![Rational::zero(); path.len() + 1];
                coeffs[0] = Rational::one();
                coeffs[path.len()] = -Rational::one();
                factor = factor * Poly::new(coeffs, "s");
            }
        }
        // det(−P_F) = (−1)^n sgn
        let sign = if negative == (n % 2 == 1) {
            Rational::one()
        } else {
            -Rational::one()
        };
        let det_t = linalg::determinant(t)?;
        Ok(factor.map(|c| c.clone() * sign.clone() * det_t.clone()))
    }

    /// `T A T⁻¹`, the solution X of `X T = T A`: row `e[r]` of T A is row r of F, which is row
    /// `f[r]` of T ([`ChainRows::checked`]), so row `e[r]` of X is the unit row `f[r]`; only the
    /// chains' last rows, `c_i A^ν_i`, are solved for — p right-hand sides instead of n, and
    /// their entries are small where T⁻¹'s are not.
    fn similar(
        &self,
        t: &Matrix<Rational>,
        ta: &Matrix<Rational>,
    ) -> Result<Matrix<Rational>, linalg::LinalgError> {
        let n = t.rows();
        let mut unit: Vec<Option<usize>> = vec![None; n];
        for (q, k) in self.e.iter().zip(&self.f) {
            if let Some(q) = *q {
                unit[q] = Some(*k);
            }
        }
        let rest: Vec<usize> = (0..n).filter(|&q| unit[q].is_none()).collect();
        let mut x = Matrix::zeros(n, n);
        if !rest.is_empty() {
            let rows = Matrix::from_fn(n, rest.len(), |j, c| ta.get(rest[c], j).clone());
            let solved = linalg::solve(&t.transpose(), &rows)?;
            for (c, &q) in rest.iter().enumerate() {
                for j in 0..n {
                    x.set(q, j, solved.get(j, c).clone());
                }
            }
        }
        for (q, k) in unit.iter().enumerate() {
            if let Some(k) = *k {
                x.set(q, k, Rational::one());
            }
        }
        Ok(x)
    }

    /// [`reconstruction`]'s terms through T: with `N = F⁻¹E = T⁻¹ S T` and
    /// `F⁻¹ = T⁻¹ P_Fᵀ`, `V_k = N^k (−F⁻¹ [G_u G_y]) = T⁻¹ W_k` where `W_0 = −P_Fᵀ [G_u G_y]`
    /// (row r of `[G_u G_y]` moved to row `f[r]`) and `W_(k+1) = S W_k` (row `e[r]` moved to
    /// row `f[r]`): the W's are G's rows moved about, and one solve `T X = [W_0 W_1 …]` (as many
    /// as are nonzero, at most n) gives every term — no product of the large fractions of T⁻¹.
    fn reconstruction(
        &self,
        t: &Matrix<Rational>,
        gu: &Matrix<Rational>,
        gy: &Matrix<Rational>,
    ) -> Result<Vec<Term>, linalg::LinalgError> {
        let (n, m, p) = (t.rows(), gu.cols(), gy.cols());
        let g = gu.hstack(gy)?;
        let mut w = Matrix::zeros(n, m + p);
        for r in 0..n {
            for j in 0..m + p {
                w.set(self.f[r], j, -g.get(r, j).clone());
            }
        }
        let mut ws = Vec::new();
        while ws.len() < n && !w.is_zero() {
            let mut shifted = Matrix::zeros(n, m + p);
            for r in 0..n {
                if let Some(k) = self.e[r] {
                    for j in 0..m + p {
                        shifted.set(self.f[r], j, w.get(k, j).clone());
                    }
                }
            }
            ws.push(std::mem::replace(&mut w, shifted));
        }
        let Some(first) = ws.first() else {
            return Ok(Vec::new());
        };
        let all = ws[1..]
            .iter()
            .try_fold(first.clone(), |acc, w| acc.hstack(w))?;
        let v = linalg::solve(t, &all)?;
        Ok((0..ws.len())
            .map(|k| {
                let at = k * (m + p);
                (v.block(0, n, at, at + m), v.block(0, n, at + m, at + m + p))
            })
            .collect())
    }
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
///
/// The powers are never formed: `V_0 = −F⁻¹ [G_u G_y]` and `V_(k+1) = F⁻¹ (E V_k)`, products
/// of n × n matrices with n × (m + p) ones — O(n²(m + p)) operations a term instead of the
/// O(n³) of `(F⁻¹E)^(k+1) F⁻¹` (at order 25, 57 % of the command went to those products).
fn reconstruction(
    e: &Matrix<Rational>,
    f: &Matrix<Rational>,
    gu: &Matrix<Rational>,
    gy: &Matrix<Rational>,
) -> Result<Vec<Term>, linalg::LinalgError> {
    let (n, m, p) = (e.rows(), gu.cols(), gy.cols());
    let f_inv = linalg::inverse(f)?;
    let mut v = f_inv.mul(&gu.hstack(gy)?)?.neg();
    let mut out = Vec::new();
    for _ in 0..n {
        let (u, y) = (v.block(0, n, 0, m), v.block(0, n, m, m + p));
        if u.is_zero() && y.is_zero() {
            break;
        }
        out.push((u, y));
        v = f_inv.mul(&e.mul(&v)?)?;
    }
    Ok(out)
}

/// The reconstruction `x̂ = Σ_k (U_k u^(k) + Y_k y^(k))`, shown per state.
pub struct Reconstruction<'a>(pub &'a [Term]);

/// One term of a reconstructed state: its coefficient's sign and magnitude (digits made once,
/// as text `n` or `n/d` and as LaTeX), the signal and its derivative order.
struct Piece {
    negative: bool,
    /// `|c| = 1`: no coefficient written.
    unit: bool,
    text: String,
    latex: String,
    signal: String,
    order: usize,
}

impl Reconstruction<'_> {
    /// Per state, the nonzero terms, highest derivative order first.
    fn pieces(&self) -> Vec<Vec<Piece>> {
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
        let piece = |c: &Rational, signal: String, order: usize| {
            let negative = *c < Rational::zero();
            let unit = c.numer().magnitude().is_one() && c.denom().is_one();
            let (numer, denom) = if unit {
                (String::new(), String::new())
            } else {
                (
                    crate::algebra::decimal::decimal(&c.numer().abs()),
                    crate::algebra::decimal::decimal(c.denom()),
                )
            };
            let text = if unit || denom == "1" {
                numer.clone()
            } else {
                format!("{numer}/{denom}")
            };
            Piece {
                negative,
                unit,
                latex: if unit {
                    String::new()
                } else {
                    crate::algebra::latex_of_parts(&numer, &denom)
                },
                text,
                signal,
                order,
            }
        };
        (0..n)
            .map(|i| {
                let mut out = Vec::new();
                for (k, (u, y)) in self.0.iter().enumerate().rev() {
                    for j in 0..p {
                        let c = y.get(i, j);
                        if !c.is_zero() {
                            out.push(piece(c, name("y", j, p), k));
                        }
                    }
                    for j in 0..m {
                        let c = u.get(i, j);
                        if !c.is_zero() {
                            out.push(piece(c, name("u", j, m), k));
                        }
                    }
                }
                out
            })
            .collect()
    }

    fn render(
        pieces: &[Vec<Piece>],
        signal: impl Fn(&str, usize) -> String,
        coefficient: impl Fn(&Piece) -> String,
        lhs: impl Fn(usize) -> String,
        sep: &str,
    ) -> String {
        pieces
            .iter()
            .enumerate()
            .map(|(i, terms)| {
                let mut text = String::new();
                for (t, piece) in terms.iter().enumerate() {
                    let sign = match (t, piece.negative) {
                        (0, false) => "",
                        (0, true) => "−",
                        (_, false) => " + ",
                        (_, true) => " − ",
                    };
                    let coef = if piece.unit {
                        String::new()
                    } else {
                        coefficient(piece)
                    };
                    text.push_str(&format!(
                        "{sign}{coef}{}",
                        signal(&piece.signal, piece.order)
                    ));
                }
                if terms.is_empty() {
                    text.push('0');
                }
                format!("{} = {text}", lhs(i))
            })
            .collect::<Vec<_>>()
            .join(sep)
    }

    fn text_of(pieces: &[Vec<Piece>]) -> String {
        Self::render(
            pieces,
            |name, k| match k {
                0 => name.to_string(),
                1 => format!("{name}'"),
                2 => format!("{name}''"),
                _ => format!("{name}^({k})"),
            },
            |c| format!("{} ", c.text),
            |i| format!("x̂{}", i + 1),
            "\n",
        )
    }

    fn latex_of(pieces: &[Vec<Piece>]) -> String {
        let body = Self::render(
            pieces,
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
            |c| format!("{} ", c.latex).replace("−", "-"),
            |i| format!("\\hat{{x}}_{{{}}}", i + 1),
            " \\\\ ",
        );
        format!(
            "\\begin{{gathered}} {} \\end{{gathered}}",
            body.replace('−', "-")
        )
    }
}

impl crate::derivation::Show for Reconstruction<'_> {
    fn text(&self) -> String {
        Self::text_of(&self.pieces())
    }
    fn latex(&self) -> String {
        Self::latex_of(&self.pieces())
    }
    fn input(&self) -> String {
        self.text().replace('\n', "; ")
    }
    /// Every coefficient's digits made once for the text, the LaTeX and the input syntax.
    fn all(&self) -> (String, String, String, Option<Vec<String>>) {
        let pieces = self.pieces();
        let text = Self::text_of(&pieces);
        let input = text.replace('\n', "; ");
        (text, Self::latex_of(&pieces), input, None)
    }
}

/// The conditions on a changed plant `(A', B', C', D')` under which `observer` stays perfect:
/// the nonzero entries of `E A' − F − G_y C'` and `E B' − G_u − G_y D'` with every entry of the
/// plant a symbol (`a11 … , b11 …, c11 …, d11 …`; `a1_12` once an index has two digits, so that
/// row 1, column 11 and row 11, column 1 are not both `a111`), each an affine equation `… = 0`.
/// An empty list would mean the observer fits every plant.
///
/// Each entry is written down term by term — `Σ_k E_ik x_kj − Y_ij − Σ_l (G_y)_il z_lj`, every
/// symbol once — where products of symbolic matrices merged growing polynomials n times per
/// entry (O(n⁴) term copies; 23 % of the command at order 60).
pub fn robustness_conditions(observer: &PerfectObserver) -> Vec<MultiPoly> {
    let (n, m, p) = (
        observer.e.rows(),
        observer.input_matrix.cols(),
        observer.output_matrix.cols(),
    );
    let wide = n.max(m).max(p) >= 10;
    let symbol = |name: &str, i: usize, j: usize| {
        let text = if wide {
            format!("{name}{}_{}", i + 1, j + 1)
        } else {
            format!("{name}{}{}", i + 1, j + 1)
        };
        Monomial::var(&text, 1)
    };
    let (e, gy) = (&observer.e, &observer.output_matrix);
    // the entries of E X − Y − G_y Z, X and Z symbolic (named x and z), row by row
    let residual = |x: &str, cols: usize, y: &Matrix<Rational>, z: &str| {
        let mut entries = Vec::with_capacity(n * cols);
        for i in 0..n {
            for j in 0..cols {
                let plant = (0..n).map(|k| (symbol(x, k, j), e.get(i, k).clone()));
                let output = (0..p).map(|l| (symbol(z, l, j), -gy.get(i, l).clone()));
                let constant = std::iter::once((Monomial::one(), -y.get(i, j).clone()));
                entries.push(MultiPoly::from_terms(
                    plant
                        .filter(|(_, c)| !c.is_zero())
                        .chain(constant)
                        .chain(output.filter(|(_, c)| !c.is_zero())),
                ));
            }
        }
        entries
    };
    let mut conditions = residual("a", n, &observer.f, "c");
    conditions.extend(residual("b", m, &observer.input_matrix, "d"));
    conditions.retain(|x| !x.is_zero());
    conditions
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
    use crate::algebra::Ring;
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

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(48))]
        /// The pencil's determinant, the reconstruction and T A T⁻¹ read from the chain
        /// structure (`ChainRows`) equal the general computations — fraction-free elimination
        /// over polynomials in s, the powers of F⁻¹E applied to [G_u G_y], one solve for all of
        /// T A T⁻¹ — on random plants of
        /// orders 1–7 with one to three outputs (chains of unequal lengths included), D nonzero.
        #[test]
        fn the_chain_structure_gives_the_general_results(
            n in 1usize..8,
            p in 1usize..4,
            entries in proptest::collection::vec(-4i64..5, 7 * 7 + 7 * 2 + 3 * 7 + 3 * 2),
        ) {
            let p = p.min(n);
            let mut it = entries.iter().map(|&x| Rational::from_i64(x));
            let mut take = |r: usize, c: usize| {
                let v: Vec<Vec<Rational>> = (0..r)
                    .map(|_| (0..c).map(|_| it.next().unwrap_or_default()).collect())
                    .collect();
                Matrix::from_rows(v).unwrap()
            };
            let (a, b, c, d) = (take(n, n), take(n, 2), take(p, n), take(p, 2));
            let plant = StateSpace::new(a, Some(b), c, Some(d)).unwrap();
            let Ok(observer) = perfect_observer(&plant) else {
                // unobservable or dependent outputs: refused before any of this
                return Ok(());
            };
            let general = pencil_determinant(&observer.e, &observer.f).unwrap();
            proptest::prop_assert_eq!(&observer.pencil_determinant, &general);
            proptest::prop_assert_eq!(general.degree(), Some(0));
            let terms = reconstruction(
                &observer.e,
                &observer.f,
                &observer.input_matrix,
                &observer.output_matrix,
            )
            .unwrap();
            proptest::prop_assert_eq!(&observer.reconstruction, &terms);
            // T A T⁻¹ from the unit rows and p solves, against one solve for all of it
            let ta = observer.t.mul(plant.a()).unwrap();
            let similar = linalg::solve(&observer.t.transpose(), &ta.transpose())
                .unwrap()
                .transpose();
            let shown = observer.derivation.step("T A T⁻¹").map(|s| s.input.clone());
            proptest::prop_assert_eq!(shown, Some(similar.to_input()));
        }
    }

    /// With eleven states the plant's symbols carry a separator (`a1_11`, `a11_1`: without it
    /// both would be `a111`), and every condition vanishes at the plant's own entries while a
    /// change of the entry at row 11, column 1 alone breaks one of them.
    #[test]
    fn robustness_conditions_name_two_digit_indices_apart() {
        let n = 11;
        // a shift with a last row of small integers, a generic B, a C that weighs every state
        // (so that E has no zero column, and every entry of A' enters the conditions)
        let a = Matrix::from_fn(n, n, |i, j| {
            if i + 1 == j {
                Rational::one()
            } else if i + 1 == n {
                Rational::from_i64([3, -1, 2, 0, 1, -2, 1, 0, -1, 2, 1][j])
            } else {
                Rational::zero()
            }
        });
        let b = Matrix::from_fn(n, 1, |i, _| Rational::from_i64(i as i64 % 3 - 1));
        let c = Matrix::from_fn(1, n, |_, j| Rational::from_i64(j as i64 % 2 + 1));
        let plant = StateSpace::new(a.clone(), Some(b.clone()), c.clone(), None).unwrap();
        let observer = perfect_observer(&plant).unwrap();
        let conditions = robustness_conditions(&observer);
        let names: std::collections::BTreeSet<String> =
            conditions.iter().flat_map(MultiPoly::variables).collect();
        assert!(
            names.contains("a1_11") && names.contains("a11_1"),
            "{names:?}"
        );
        assert!(!names.contains("a111"));
        let values = |a: &Matrix<Rational>| {
            let mut v = std::collections::BTreeMap::new();
            let mut put = |name: &str, m: &Matrix<Rational>| {
                for i in 0..m.rows() {
                    for j in 0..m.cols() {
                        v.insert(format!("{name}{}_{}", i + 1, j + 1), m.get(i, j).clone());
                    }
                }
            };
            put("a", a);
            put("b", &b);
            put("c", &c);
            put("d", &Matrix::zeros(1, 1));
            v
        };
        let own = values(&a);
        assert!(conditions
            .iter()
            .all(|x| x.evaluate(&own) == Some(Rational::zero())));
        let mut changed = a.clone();
        changed.set(10, 0, Rational::from_i64(4));
        let other = values(&changed);
        assert!(conditions
            .iter()
            .any(|x| x.evaluate(&other) != Some(Rational::zero())));
    }

    /// The chain structure is used only when every row of E and F is the row of T it is said
    /// to be: a row out of place, a repeated row, or a nonzero row where E has zeros sends the
    /// observer to the general computations.
    #[test]
    fn rows_out_of_place_are_not_read_as_chains() {
        let t = m("[1 0 0; 0 1 0; 0 0 1]");
        let e = m("[1 0 0; 0 1 0; 0 0 0]");
        let f = m("[0 1 0; 0 0 1; 1 0 0]");
        let rows = |e: &[Option<usize>], f: &[usize]| ChainRows {
            e: e.to_vec(),
            f: f.to_vec(),
        };
        let (e_rows, f_rows) = ([Some(0), Some(1), None], [1, 2, 0]);
        // the rows a single chain of length 3 gives
        let chain = ChainRows::of(&[3]);
        assert_eq!((&chain.e[..], &chain.f[..]), (&e_rows[..], &f_rows[..]));
        assert!(chain.checked(&t, &e, &f).is_some());
        assert!(rows(&e_rows, &[2, 1, 0]).checked(&t, &e, &f).is_none());
        assert!(rows(&e_rows, &[1, 1, 0]).checked(&t, &e, &f).is_none());
        assert!(rows(&[Some(0), Some(0), None], &f_rows)
            .checked(&t, &e, &f)
            .is_none());
        assert!(rows(&e_rows, &f_rows).checked(&t, &f, &f).is_none());
        assert!(rows(&[Some(0), Some(1), Some(2)], &f_rows)
            .checked(&t, &e, &f)
            .is_none());
        // det(Es − F) for the 3-cycle: (−1)³ · sgn(3-cycle) = −1, no cycle in S
        let checked = rows(&e_rows, &f_rows).checked(&t, &e, &f).unwrap();
        assert_eq!(
            checked.determinant(&t).unwrap(),
            pencil_determinant(&e, &f).unwrap()
        );
        // E = I (S = P_Fᵀ, one 3-cycle): det(Is − F) = s³ − 1, against elimination
        let eye = m("[1 0 0; 0 1 0; 0 0 1]");
        let checked = rows(&[Some(0), Some(1), Some(2)], &f_rows)
            .checked(&t, &eye, &f)
            .unwrap();
        let det = checked.determinant(&t).unwrap();
        assert_eq!(det, pencil_determinant(&eye, &f).unwrap());
        assert_eq!(det.degree(), Some(3));
    }
}
