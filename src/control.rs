//! Observer-based control: state feedback, the separation principle, and exact transfer
//! functions (Stoustrup, Lecture 3, "Observer based control", "The separation principle").
//!
//! Conventions follow Stoustrup: `u = F x̂`, observer `x̂' = Ax̂ + Bu + L(Cx̂ − y)`, so the closed
//! loop in `(x, e)` has the block-triangular matrix `[A + BF, BF; 0, A + LC]`.
//!
//! Transfer functions are computed without inverting `sI − A` symbolically: for a column `b` and
//! a row `c`, the matrix determinant lemma gives
//! `c (sI − A)⁻¹ b = (det(sI − A + b c) − det(sI − A)) / det(sI − A)`, two characteristic
//! polynomials by Berkowitz.

use crate::algebra::{Field, Rational};
use crate::derivation::Derivation;
use crate::linalg::{self, LinalgError, Matrix};
use crate::observer::DesignError;
use crate::poly::{Factored, Poly, RationalFunction};
use crate::system::StateSpace;

/// Why a control computation failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ControlError {
    /// The gain design failed (uncontrollable, unobservable, wrong degree…).
    #[error(transparent)]
    Design(#[from] DesignError),
    /// A matrix computation failed.
    #[error(transparent)]
    Linalg(#[from] LinalgError),
    /// A single-input, single-output system was needed.
    #[error("{what} needs a single-input single-output plant; it has {inputs} inputs and {outputs} outputs")]
    NotSiso {
        /// What was attempted.
        what: &'static str,
        /// Inputs.
        inputs: usize,
        /// Outputs.
        outputs: usize,
    },
    /// The desired polynomial does not fit the plant (its degree is not the order).
    #[error(transparent)]
    Polynomial(#[from] crate::observer::polynomial::PolynomialError),
    /// The state feedback refused (an uncontrollable pair, its modes named; a polynomial of
    /// the wrong degree).
    #[error(transparent)]
    Feedback(#[from] crate::feedback::FeedbackError),
    /// The plant has a direct feedthrough, which the observer-based controller here leaves out.
    #[error("the plant has a direct feedthrough D = {0}: the observer-based controller analysed here assumes D = 0")]
    Feedthrough(String),
    /// A designed gain's own check found other eigenvalues than those asked for.
    #[error("the designed gain does not place the eigenvalues of {what}: its characteristic polynomial is {achieved}")]
    NotPlaced {
        /// The matrix whose eigenvalues were placed.
        what: &'static str,
        /// Its characteristic polynomial, as the check computed it.
        achieved: String,
    },
    /// `1 − K(s)G(s)` is identically zero.
    #[error("the loop 1 − K(s)G(s) is identically zero: the closed loop is not defined")]
    DegenerateLoop,
}

/// State feedback `F` (row) placing the eigenvalues of `A + BF` at the roots of `desired`: the
/// gain of [`crate::feedback::design_feedback`] (by duality, Ackermann, `u = F x`) without its
/// working — one state-feedback design in the crate.
///
/// # Example
/// ```
/// use observer_workbench::algebra::Rational;
/// use observer_workbench::control::state_feedback;
/// use observer_workbench::syntax::{parse_matrix, parse_polynomial};
/// let a = parse_matrix::<Rational>("[2 -3; 4 -5]").unwrap();
/// let b = parse_matrix::<Rational>("[2; 3]").unwrap();
/// let p = parse_polynomial::<Rational>("s^2 + 9s + 20", "s").unwrap();
/// assert_eq!(state_feedback(&a, &b, &p).unwrap().to_input(), "[42, -30]");
/// ```
///
/// # Errors
/// [`ControlError::Feedback`] for an uncontrollable pair (its modes named), a polynomial of the
/// wrong degree or a B with more than one column.
pub fn state_feedback(
    a: &Matrix<Rational>,
    b: &Matrix<Rational>,
    desired: &Poly<Rational>,
) -> Result<Matrix<Rational>, ControlError> {
    use crate::feedback::{design_feedback, FeedbackConvention};
    use crate::observer::{Detail, GainMethod};
    let n = a.rows();
    let desired = crate::observer::DesiredPolynomial::from_polynomial(
        desired.map(|c| crate::algebra::Quadratic::rational(c.clone())),
        n,
    )?;
    let d = design_feedback(
        a,
        b,
        &desired,
        GainMethod::Ackermann,
        FeedbackConvention::UEqualsFx,
        Detail::Summary,
    )?;
    Ok(linalg::rational_entries(&d.gain)
        .expect("a rational plant and polynomial give a rational gain"))
}

/// The observer gain `L` (column) placing the eigenvalues of `A + LC` at the roots of
/// `desired`: the gain of [`crate::observer::design_with`] (Ackermann, reported for `A + LC`)
/// without its working — the observer's counterpart of [`state_feedback`], so that a
/// controller can be asked for by its two polynomials.
///
/// # Example
/// ```
/// use observer_workbench::algebra::Rational;
/// use observer_workbench::control::observer_gain;
/// use observer_workbench::linalg::characteristic_polynomial;
/// use observer_workbench::syntax::{parse_matrix, parse_polynomial};
/// let a = parse_matrix::<Rational>("[0 1; -2 -3]").unwrap();
/// let c = parse_matrix::<Rational>("[1 0]").unwrap();
/// let p = parse_polynomial::<Rational>("s^2 + 9s + 20", "s").unwrap();
/// // A + LC = [l₁ 1; l₂ − 2 −3]: s² + (3 − l₁)s + 2 − 3l₁ − l₂ = s² + 9s + 20
/// let l = observer_gain(&a, &c, &p).unwrap();
/// assert_eq!(l.to_input(), "[-6; 0]");
/// let a_lc = a.add(&l.mul(&c).unwrap()).unwrap();
/// assert_eq!(characteristic_polynomial(&a_lc, "s").unwrap(), p);
/// ```
///
/// # Errors
/// [`ControlError::Design`] for an unobservable pair (its modes named) or a C with more than
/// one row; [`ControlError::Polynomial`] for a polynomial of the wrong degree;
/// [`ControlError::NotPlaced`] if the design's own check found other eigenvalues.
pub fn observer_gain(
    a: &Matrix<Rational>,
    c: &Matrix<Rational>,
    desired: &Poly<Rational>,
) -> Result<Matrix<Rational>, ControlError> {
    use crate::observer::{Convention, Detail, GainMethod};
    let wanted = crate::observer::DesiredPolynomial::from_polynomial(
        desired.map(|c| crate::algebra::Quadratic::rational(c.clone())),
        a.rows(),
    )?;
    let d = crate::observer::design_with(
        a,
        c,
        &wanted,
        GainMethod::Ackermann,
        Convention::APlusLC,
        Detail::Summary,
    )?;
    if !d.places_exactly() {
        return Err(ControlError::NotPlaced {
            what: "A + LC",
            achieved: d.achieved.to_string(),
        });
    }
    Ok(linalg::rational_entries(&d.gain.matrix)
        .expect("a rational plant and polynomial give a rational gain"))
}

/// `c (sI − A)⁻¹ b + d` for a column `b` and a row `c`, in lowest terms.
///
/// # Errors
/// [`LinalgError`] on mismatched dimensions.
pub fn siso_transfer_function<F: Field>(
    a: &Matrix<F>,
    b: &Matrix<F>,
    c: &Matrix<F>,
    d: &F,
) -> Result<RationalFunction<F>, LinalgError> {
    let open = linalg::characteristic_polynomial(a, "s")?;
    let perturbed = linalg::characteristic_polynomial(&a.sub(&b.mul(c)?)?, "s")?;
    let num = perturbed - open.clone() + open.scale(d);
    Ok(RationalFunction::new(num, open).expect("a characteristic polynomial is monic, never zero"))
}

/// The transfer matrix `C (sI − A)⁻¹ B + D`, entry by entry.
///
/// # Errors
/// [`LinalgError`] on mismatched dimensions.
pub fn transfer_matrix<F: Field>(
    a: &Matrix<F>,
    b: &Matrix<F>,
    c: &Matrix<F>,
    d: &Matrix<F>,
) -> Result<Vec<Vec<RationalFunction<F>>>, LinalgError> {
    (0..c.rows())
        .map(|i| {
            (0..b.cols())
                .map(|j| {
                    let bj = Matrix::column(b.col(j));
                    let ci = Matrix::row_vector(c.row(i).to_vec());
                    siso_transfer_function(a, &bj, &ci, d.get(i, j))
                })
                .collect()
        })
        .collect()
}

/// A polynomial factored over Q when it is rational (its rational roots shown), as it is
/// otherwise (coefficients with parameters or √d).
fn factored<F: Field>(p: &Poly<F>) -> Box<dyn crate::derivation::Show> {
    match crate::algebra::from_concrete::<Poly<Rational>, _>(p.clone()) {
        Some(q) => Box::new(Factored::of(&q)),
        None => Box::new(p.clone()),
    }
}

/// The loop's determinants as updates of A of rank one and two, from the numbers `x Aʲ y`
/// alone (the rank-one check of a gain design, [`linalg::rank_one_update`], twice
/// over). With `d = det(sI − A)` and `m_xy = x adj(sI − A) y` (degree below n), the matrix
/// determinant lemma gives `det(sI − A − y x) = d − m_xy` and, for `U = [u₁ u₂]` and
/// `V = [v₁; v₂]`, `det(sI − A − U V) = ((d − m₁₁)(d − m₂₂) − m₁₂ m₂₁) / d` with
/// `m_ij = v_i adj u_j` — exact, and whatever the size of F's and L's numbers: the
/// characteristic polynomial of `A + BF + LC` itself, large numbers in a whole row and a
/// whole column, needed thousands of primes at order 20.
struct LoopUpdates<F: Field> {
    /// `det(sI − A)`.
    open: Poly<F>,
    /// `F adj(sI − A) B`.
    fb: Poly<F>,
    /// `F adj(sI − A) L`.
    fl: Poly<F>,
    /// `C adj(sI − A) B`.
    cb: Poly<F>,
    /// `C adj(sI − A) L`.
    cl: Poly<F>,
}

impl<F: Field> LoopUpdates<F> {
    fn new(
        a: &Matrix<F>,
        b: &Matrix<F>,
        c: &Matrix<F>,
        f: &Matrix<F>,
        l: &Matrix<F>,
    ) -> Result<Self, LinalgError> {
        let open = linalg::characteristic_polynomial(a, "s")?;
        if let Some(updates) = Self::on_integers(a, b, c, f, l, &open) {
            return Ok(updates);
        }
        let (o_f, o_c) = (
            crate::observability::observability_matrix(a, f)?,
            crate::observability::observability_matrix(a, c)?,
        );
        // x adj(sI − A) y: the rank-one polynomial d + x adj y, less d
        let m = |o: &Matrix<F>, y: &Matrix<F>| -> Result<Poly<F>, LinalgError> {
            Ok(linalg::rank_one_update(o, &open, y)? - open.clone())
        };
        Ok(LoopUpdates {
            fb: m(&o_f, b)?,
            fl: m(&o_f, l)?,
            cb: m(&o_c, b)?,
            cl: m(&o_c, l)?,
            open,
        })
    }

    /// [`LoopUpdates::new`] for a rational plant with an integer `A`, single input and output:
    /// `F·A^k` and `C·A^k` kept on integers over their rows' denominators
    /// ([`crate::observability::integer_observability_rows`],
    /// [`linalg::adjugate_product_on_integers`]), where reducing every entry of `F·A^k` and
    /// scaling it back for each product cost a fifth of `control` at order 60. `None` for any
    /// other loop (the general path then runs).
    fn on_integers(
        a: &Matrix<F>,
        b: &Matrix<F>,
        c: &Matrix<F>,
        f: &Matrix<F>,
        l: &Matrix<F>,
        open: &Poly<F>,
    ) -> Option<Self> {
        let (a, b, c, f, l) = (
            linalg::as_rational(a)?,
            linalg::as_rational(b)?,
            linalg::as_rational(c)?,
            linalg::as_rational(f)?,
            linalg::as_rational(l)?,
        );
        let open_q = open.as_rational()?;
        if f.rows() != 1 || c.rows() != 1 {
            return None;
        }
        let (o_f, d_f) = crate::observability::integer_observability_rows(a, f)?;
        let (o_c, d_c) = crate::observability::integer_observability_rows(a, c)?;
        let m = |o: &[Vec<crate::algebra::BigInt>],
                 d: &crate::algebra::BigInt,
                 y: &Matrix<Rational>|
         -> Option<Poly<F>> {
            crate::algebra::from_concrete(linalg::adjugate_product_on_integers(o, d, open_q, y)?)
        };
        Some(LoopUpdates {
            fb: m(&o_f, &d_f[0], b)?,
            fl: m(&o_f, &d_f[0], l)?,
            cb: m(&o_c, &d_c[0], b)?,
            cl: m(&o_c, &d_c[0], l)?,
            open: open.clone(),
        })
    }

    /// `det(sI − A − U V)` from `m_ij = v_i adj u_j`, when d divides (it always does; `None`
    /// would be a bug, and the caller then computes the determinant directly).
    fn rank_two(
        &self,
        m11: &Poly<F>,
        m12: &Poly<F>,
        m21: &Poly<F>,
        m22: &Poly<F>,
    ) -> Option<Poly<F>> {
        let d = &self.open;
        if let (Some(d), Some(m)) = (
            d.as_rational(),
            [m11, m12, m21, m22]
                .map(Poly::as_rational)
                .into_iter()
                .collect::<Option<Vec<_>>>(),
        ) {
            if let Some(p) = rank_two_on_integers(d, [m[0], m[1], m[2], m[3]]) {
                return crate::algebra::from_concrete(p);
            }
        }
        let product =
            (d.clone() - m11.clone()) * (d.clone() - m22.clone()) - m12.clone() * m21.clone();
        product.divide_exact(d)
    }

    /// `det(sI − (A + BF + LC))`: U = [B L], V = [F; C].
    fn controller_polynomial(&self) -> Option<Poly<F>> {
        self.rank_two(&self.fb, &self.fl, &self.cb, &self.cl)
    }

    /// `det(sI − (A + BF + LC + LF))`, the controller's state matrix less `L·(−F)`: U =
    /// [B + L, L], V = [F; C].
    fn perturbed_controller_polynomial(&self) -> Option<Poly<F>> {
        let f_u1 = self.fb.clone() + self.fl.clone();
        let c_u1 = self.cb.clone() + self.cl.clone();
        self.rank_two(&f_u1, &self.fl, &c_u1, &self.cl)
    }
}

/// [`LoopUpdates::rank_two`] over the rationals for an integral `d` (a plant with integral A):
/// the four m's over one denominator D (`integer_numerators`), `(D d − M₁₁)(D d − M₂₂) −
/// M₁₂ M₂₁` — D² times the numerator — on integers and divided by d exactly there, then one
/// reduction per coefficient; where the products over the rationals reduced every coefficient
/// of every product and difference (a gcd of large numbers each). `None` for a fractional d.
fn rank_two_on_integers(d: &Poly<Rational>, m: [&Poly<Rational>; 4]) -> Option<Poly<Rational>> {
    use crate::algebra::gcd::{fraction, integer_numerators};
    let (d_int, one) = integer_numerators(d.coeffs());
    if !num_traits::One::is_one(&one) {
        return None;
    }
    let all: Vec<Rational> = m.iter().flat_map(|p| p.coeffs().iter().cloned()).collect();
    let (ints, den) = integer_numerators(&all);
    let var = d.var();
    let mut at = 0;
    let mut next = |p: &Poly<Rational>| {
        let part = Poly::new(ints[at..at + p.coeffs().len()].to_vec(), var);
        at += p.coeffs().len();
        part
    };
    let [m11, m12, m21, m22] = m.map(&mut next);
    let scaled = Poly::new(d_int.clone(), var).scale(&den);
    let product = (scaled.clone() - m11) * (scaled - m22) - m12 * m21;
    let quotient = crate::poly::divide_exact_integers(product.coeffs().to_vec(), &d_int)?;
    let square = &den * &den;
    let coeffs = quotient
        .into_iter()
        .map(|c| fraction(c, square.clone()))
        .collect();
    Some(Poly::new(coeffs, var))
}

/// An observer-based controller with its working.
#[derive(Clone, PartialEq, Debug)]
pub struct ObserverBasedControl<F: Field = Rational> {
    /// `det(sI − (A + BF))`.
    pub feedback_polynomial: Poly<F>,
    /// `det(sI − (A + LC))`.
    pub observer_polynomial: Poly<F>,
    /// `det(sI − [A + BF, BF; 0, A + LC])`.
    pub closed_loop_polynomial: Poly<F>,
    /// Whether the closed-loop polynomial is the product of the two (it must be).
    pub separation_holds: bool,
    /// The plant `G(s) = C (sI − A)⁻¹ B`.
    pub plant: RationalFunction<F>,
    /// The controller `K(s) = −F (sI − A − BF − LC)⁻¹ L` (from y to u).
    pub controller: RationalFunction<F>,
    /// `G (1 − K G)⁻¹`.
    pub closed_loop: RationalFunction<F>,
    /// The steps.
    pub derivation: Derivation,
}

/// `det(sI − A_cl)` for the closed loop `[A + BF, BF; 0, A + LC]`, computed from the matrix
/// itself: the product of its diagonal blocks' polynomials ([`linalg::characteristic_polynomial`]
/// splits a block triangular matrix), each block taken on its own. With an integral A and a B
/// or C of several nonzero entries, a gain's fractions fill the whole block, and scaling it by
/// their denominator multiplies the primes the multimodular polynomial needs by n (order 40:
/// 6 s). So the closed loop is first brought, by a similarity with integer entries and
/// determinant 1 ([`one_line_basis`]), to a basis where B and Cᵀ have one nonzero entry each:
/// there each diagonal block's fractions lie in one row or one column, which the polynomial
/// takes as a rank-one update of the block's integral rest. The polynomial does not depend on
/// the basis; the steps show A_cl as formed.
fn closed_loop_polynomial<F: Field>(
    closed: &Matrix<F>,
    a: &Matrix<F>,
    b: &Matrix<F>,
    c: &Matrix<F>,
) -> Result<Poly<F>, LinalgError> {
    if let (Some(m), Some(a), Some(b), Some(c)) = (
        linalg::as_rational(closed),
        linalg::as_rational(a),
        linalg::as_rational(b),
        linalg::as_rational(c),
    ) {
        let (b_steps, c_steps) = (euclid_steps(b.entries()), euclid_steps(c.entries()));
        // (B and Cᵀ of one nonzero entry each, B = e₁ and C = e₁ᵀ: the basis is already so)
        let moves = !(b_steps.is_empty() && c_steps.is_empty());
        if moves && a.entries().iter().all(Rational::is_integer) {
            let similar = one_line_basis(m, b.rows(), &b_steps, &c_steps);
            let p = linalg::characteristic_polynomial(&similar, "s")?;
            if let Some(p) = crate::algebra::from_concrete::<Poly<F>, _>(p) {
                return Ok(p);
            }
        }
    }
    linalg::characteristic_polynomial(closed, "s")
}

/// `S·M·S⁻¹` for the 2n × 2n closed loop `M` and `S = diag(U, W⁻¹)`, integer matrices of
/// determinant 1 with `U b` and `c W` each of one nonzero entry: Euclid's algorithm on the
/// entries of b (of c), each step an elementary similarity `P = I − q e_t e_sᵀ` (row t minus q
/// times row s, then column s plus q times column t). Then `U (A + b f) U⁻¹ = U A U⁻¹ + (U b)(f
/// U⁻¹)`, an integral matrix plus fractions in one row, and `W⁻¹ (A + l c) W` the same in one
/// column. The steps run on M's numerators over one common denominator (integer row and column
/// operations, no gcd), each entry brought to lowest terms once at the end.
/// `b_steps` and `c_steps` are [`euclid_steps`] of b and of c; n is the plant's order.
fn one_line_basis(
    m: &Matrix<Rational>,
    n: usize,
    b_steps: &[(usize, usize, crate::algebra::BigInt)],
    c_steps: &[(usize, usize, crate::algebra::BigInt)],
) -> Matrix<Rational> {
    let size = m.rows();
    let (mut w, d) = crate::algebra::gcd::integer_numerators(m.entries());
    // M ← P M P⁻¹ for P = I − q e_t e_sᵀ: row t −= q·row s, then column s += q·column t
    let mut similarity = |t: usize, s: usize, q: &crate::algebra::BigInt| {
        for j in 0..size {
            let step = q * &w[s * size + j];
            w[t * size + j] -= step;
        }
        for i in 0..size {
            let step = q * &w[i * size + t];
            w[i * size + s] += step;
        }
    };
    // P b: b_t −= q b_s
    for (t, s, q) in b_steps {
        similarity(*t, *s, q);
    }
    // c P⁻¹ with P = I + q e_s e_tᵀ: c_t −= q c_s (the bottom block's indices)
    for (t, s, q) in c_steps {
        similarity(n + s, n + t, &-q);
    }
    let mut entries = w.into_iter();
    Matrix::from_fn(size, size, |_, _| {
        crate::algebra::gcd::fraction(entries.next().unwrap_or_default(), d.clone())
    })
}

/// Euclid's algorithm on the integer direction of `v` (its entries over their common
/// denominator): steps `(t, s, q)`, each `v_t −= q v_s`, until one entry is nonzero. Each round
/// reduces every other entry modulo the smallest in magnitude, so the smallest shrinks.
fn euclid_steps(v: &[Rational]) -> Vec<(usize, usize, crate::algebra::BigInt)> {
    use num_integer::Integer;
    use num_traits::Zero;
    let (mut w, _) = crate::algebra::gcd::integer_numerators(v);
    let mut steps = Vec::new();
    loop {
        let nonzero: Vec<usize> = (0..w.len()).filter(|&i| !w[i].is_zero()).collect();
        if nonzero.len() <= 1 {
            return steps;
        }
        let k = nonzero
            .iter()
            .copied()
            .min_by(|&i, &j| w[i].magnitude().cmp(w[j].magnitude()))
            .unwrap_or(nonzero[0]);
        for &i in &nonzero {
            if i != k {
                let q = w[i].div_floor(&w[k]);
                let step = &q * &w[k];
                w[i] -= step;
                steps.push((i, k, q));
            }
        }
    }
}

/// Analyses the observer-based controller `u = F x̂` with observer gain `L` (A + LC) on a SISO
/// plant.
///
/// # Errors
/// [`ControlError`] for non-SISO plants, a plant with feedthrough, or mismatched dimensions.
pub fn observer_based_control<F: Field>(
    plant: &StateSpace<F>,
    f: &Matrix<F>,
    l: &Matrix<F>,
) -> Result<ObserverBasedControl<F>, ControlError> {
    let (a, b, c) = (plant.a(), plant.b(), plant.c());
    if !plant.d().is_zero() {
        return Err(ControlError::Feedthrough(plant.d().to_input()));
    }
    if b.cols() != 1 || c.rows() != 1 {
        return Err(ControlError::NotSiso {
            what: "the controller transfer function",
            inputs: b.cols(),
            outputs: c.rows(),
        });
    }
    let mut d = Derivation::new("Observer-based control (u = F x̂, observer matrix A + LC)");
    let bf = b.mul(f)?;
    let a_bf = a.add(&bf)?;
    let a_lc = a.add(&l.mul(c)?)?;
    d.push("A + BF", "state-feedback matrix", &a_bf);
    d.push("A + LC", "observer matrix", &a_lc);
    // det(sI − (A + BF)) = d − F adj B and det(sI − (A + LC)) = d − C adj L; the closed
    // loop's polynomial below is computed from its blocks on their own, which checks them
    let updates = LoopUpdates::new(a, b, c, f, l)?;
    let feedback_polynomial = updates.open.clone() - updates.fb.clone();
    let observer_polynomial = updates.open.clone() - updates.cl.clone();
    d.push(
        "det(sI − (A + BF))",
        "",
        factored(&feedback_polynomial).as_ref(),
    );
    d.push(
        "det(sI − (A + LC))",
        "",
        factored(&observer_polynomial).as_ref(),
    );
    let n = a.rows();
    let top = a_bf.hstack(&bf)?;
    let bottom = Matrix::zeros(n, n).hstack(&a_lc)?;
    let closed = top.vstack(&bottom)?;
    d.push("A_cl", "[A + BF, BF; 0, A + LC] in (x, e)", &closed);
    let closed_loop_polynomial = closed_loop_polynomial(&closed, a, b, c)?;
    d.push(
        "det(sI − A_cl)",
        "",
        factored(&closed_loop_polynomial).as_ref(),
    );
    let separation_holds =
        closed_loop_polynomial == feedback_polynomial.clone() * observer_polynomial.clone();
    let zero = F::zero();
    let plant = siso_transfer_function(a, b, c, &zero)?;
    d.push("G(s)", "C (sI − A)⁻¹ B", &plant);
    let a_k = a_bf.add(&l.mul(c)?)?;
    d.push("A + BF + LC", "controller state matrix", &a_k);
    // −F (sI − A_k)⁻¹ L = (det(sI − A_k − L·(−F)) − det(sI − A_k)) / det(sI − A_k), both
    // determinants rank-two updates of A
    let controller = match (
        updates.controller_polynomial(),
        updates.perturbed_controller_polynomial(),
    ) {
        (Some(open_k), Some(perturbed)) => {
            RationalFunction::new(perturbed - open_k.clone(), open_k)
                .expect("a characteristic polynomial is monic, never zero")
        }
        _ => siso_transfer_function(&a_k, l, &f.neg(), &zero)?,
    };
    d.push("K(s)", "−F (sI − A − BF − LC)⁻¹ L", &controller);
    // G (1 − K G)⁻¹ = n_G d_K / (d_G d_K − n_K n_G), reduced once at the end (the same lowest
    // terms as reducing after each operation, with one polynomial gcd instead of three)
    let (n_g, d_g) = (plant.numerator(), plant.denominator());
    let (n_k, d_k) = (controller.numerator(), controller.denominator());
    let loop_denominator = d_g.clone() * d_k.clone() - n_k.clone() * n_g.clone();
    let closed_loop = RationalFunction::new(n_g.clone() * d_k.clone(), loop_denominator)
        .ok_or(ControlError::DegenerateLoop)?;
    d.push("G (1 − K G)⁻¹", "closed loop", &closed_loop);
    d.push(
        "denominator",
        "factored",
        factored(closed_loop.denominator()).as_ref(),
    );
    Ok(ObserverBasedControl {
        feedback_polynomial,
        observer_polynomial,
        closed_loop_polynomial,
        separation_holds,
        plant,
        controller,
        closed_loop,
        derivation: d,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::syntax::parse_matrix;

    proptest::proptest! {
        /// The loop's polynomials from the rank-one and rank-two updates are the
        /// characteristic polynomials of A + BF, A + LC, A + BF + LC and A + BF + LC + LF
        /// themselves, for any F and L (fractions, of either sign).
        #[test]
        fn rank_updates_are_the_characteristic_polynomials(
            n in 1usize..6,
            entries in proptest::collection::vec(-3i64..=3, 25),
            vectors in proptest::collection::vec((-9i64..=9, 1i64..=4), 20),
        ) {
            let q = |(p, d): (i64, i64)| Rational::new(p.into(), d.into());
            let a = Matrix::from_fn(n, n, |i, j| <Rational as crate::algebra::Ring>::from_i64(entries[5 * i + j]));
            let b = Matrix::from_fn(n, 1, |i, _| q(vectors[i]));
            let c = Matrix::from_fn(1, n, |_, j| q(vectors[5 + j]));
            let f = Matrix::from_fn(1, n, |_, j| q(vectors[10 + j]));
            let l = Matrix::from_fn(n, 1, |i, _| q(vectors[15 + i]));
            let u = LoopUpdates::new(&a, &b, &c, &f, &l).unwrap();
            let chi = |m: &Matrix<Rational>| linalg::characteristic_polynomial(m, "s").unwrap();
            let a_bf = a.add(&b.mul(&f).unwrap()).unwrap();
            let a_lc = a.add(&l.mul(&c).unwrap()).unwrap();
            let a_k = a_bf.add(&l.mul(&c).unwrap()).unwrap();
            let perturbed = a_k.add(&l.mul(&f).unwrap()).unwrap();
            proptest::prop_assert_eq!(u.open.clone() - u.fb.clone(), chi(&a_bf));
            proptest::prop_assert_eq!(u.open.clone() - u.cl.clone(), chi(&a_lc));
            proptest::prop_assert_eq!(u.controller_polynomial(), Some(chi(&a_k)));
            proptest::prop_assert_eq!(u.perturbed_controller_polynomial(), Some(chi(&perturbed)));
        }
    }

    proptest::proptest! {
        /// The closed loop in the basis of one line has the same characteristic polynomial
        /// (Berkowitz on both), and its diagonal blocks' fractions lie in one row (the top
        /// block) and one column (the bottom block): for integral A, b and c of any entries,
        /// rational F and L.
        #[test]
        fn one_line_basis_keeps_the_polynomial_and_confines_the_fractions(
            n in 2usize..6,
            entries in proptest::collection::vec(-3i64..=3, 25),
            integers in proptest::collection::vec(-9i64..=9, 10),
            gains in proptest::collection::vec((-9i64..=9, 1i64..=7), 10),
        ) {
            let z = |x: i64| <Rational as crate::algebra::Ring>::from_i64(x);
            let q = |(p, d): (i64, i64)| Rational::new(p.into(), d.into());
            let a = Matrix::from_fn(n, n, |i, j| z(entries[5 * i + j]));
            let b = Matrix::from_fn(n, 1, |i, _| z(integers[i]));
            let c = Matrix::from_fn(1, n, |_, j| z(integers[5 + j]));
            let f = Matrix::from_fn(1, n, |_, j| q(gains[j]));
            let l = Matrix::from_fn(n, 1, |i, _| q(gains[5 + i]));
            let bf = b.mul(&f).unwrap();
            let top = a.add(&bf).unwrap().hstack(&bf).unwrap();
            let bottom = Matrix::zeros(n, n).hstack(&a.add(&l.mul(&c).unwrap()).unwrap()).unwrap();
            let closed = top.vstack(&bottom).unwrap();
            let (b_steps, c_steps) = (euclid_steps(b.entries()), euclid_steps(c.entries()));
            let similar = one_line_basis(&closed, n, &b_steps, &c_steps);
            proptest::prop_assert_eq!(
                linalg::charpoly::berkowitz(&similar, "s").unwrap(),
                linalg::charpoly::berkowitz(&closed, "s").unwrap()
            );
            let fractional = |i: usize, j: usize| !similar.get(i, j).is_integer();
            let rows = (0..n).filter(|&i| (0..n).any(|j| fractional(i, j))).count();
            let columns = (n..2 * n).filter(|&j| (n..2 * n).any(|i| fractional(i, j))).count();
            proptest::prop_assert!(rows <= 1 && columns <= 1, "{} rows, {} columns", rows, columns);
            proptest::prop_assert!((0..n).all(|i| (0..n).all(|j| *similar.get(n + i, j) == z(0))));
        }
    }

    #[test]
    fn stoustrup_observer_based_control() {
        let m = |s: &str| parse_matrix::<Rational>(s).unwrap();
        let plant =
            StateSpace::new(m("[2 -3; 4 -5]"), Some(m("[2; 3]")), m("[-3 2]"), None).unwrap();
        let r = observer_based_control(&plant, &m("[42 -30]"), &m("[-6; -12]")).unwrap();
        assert!(r.separation_holds);
        assert_eq!(
            Factored::of(&r.closed_loop_polynomial).to_string(),
            "(s + 4)^2(s + 5)^2"
        );
        assert_eq!(r.plant.to_string(), "1/(s^2 + 3s + 2)");
        assert_eq!(r.controller.to_string(), "(-108s − 252)/(s^2 + 15s + 74)");
        // as printed on the slide, in factored form
        let printed = crate::syntax::parse_rational_function::<Rational>(
            "(s^2 + 15 s + 74)/((s + 5)^2 (s + 4)^2)",
            "s",
        )
        .unwrap();
        assert_eq!(r.closed_loop, printed);
    }
}
