//! Identities proved, not sampled. A claim whose computation needs values for its free symbols
//! (a time constant `T` in a denominator, symbolic plant coefficients `a1, a2` under an inverse)
//! is checked at random rational points by `verify`; a finite number of points is evidence, not
//! proof. For the computations where the symbols can be carried through exactly, this module
//! recomputes the claim over the field of rational functions Q(T, a, …) and compares it with the
//! print there: equal as rational functions is a proof of the identity for every value of the
//! symbols where both sides are defined.
//!
//! * A desired polynomial of a family with time constant `T` (repeated root, Butterworth,
//!   Bessel): by the family's definition `P_T(s) = T⁻ⁿ P₁(T s)` (the poles of `P₁` scaled by
//!   1/T), with `P₁` computed exactly by the workbench; given poles: `∏ (s − pᵢ)`.
//! * A single-output observer gain: Ackermann's formula `K = P(A) O⁻¹ eₙ` over the rational
//!   functions (the inverse by the adjugate from the Berkowitz characteristic polynomial of
//!   `O`). Where `det O ≢ 0` the gain placing the poles is unique, so every method's gain is
//!   this one. In Di Ruscio's canonical coordinates: `K_o = T_o⁻¹ K = Mᵀ O_n K`.
//!
//! * The gain methods agree (`K = T_o K_o = O_n⁻¹ M⁻ᵀ (c − a) = P(A) O_n⁻¹ eₙ`): with
//!   `T_o = (Mᵀ O_n)⁻¹` all three are one vector exactly when `Mᵀ O_n K = c − a` for
//!   Ackermann's `K`, which is checked over the rational functions.
//!
//! Other identities between procedures stay sampled, and the report says so.
//!
//! Numbers with a square root (`sqrt(2)`, `i`) are carried as a symbol `√d` reduced by
//! `√d² = d`; one radicand per claim, so the normal form is unique and equality is exact.

use super::inputs::Inputs;
use crate::algebra::{Fraction, One, Rational, Zero};
use crate::linalg::{berkowitz, Matrix};
use crate::observer::{Convention, DesiredPolynomial};
use crate::syntax::{evaluate_with, parse_expression, parse_matrix_expressions, Environment};

/// A claim recomputed over the rational functions and compared with its print.
#[derive(Clone, Debug)]
pub struct Proof {
    /// Whether the print equals the recomputation as rational functions.
    pub holds: bool,
    /// The symbols the identity is in.
    pub symbols: Vec<String>,
    /// The recomputed value, in input syntax.
    pub value: String,
    /// How it was recomputed (the formula).
    pub method: &'static str,
}

/// Why a claim is not proved here (it stays sampled): said in the verification report.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum NoProof {
    /// A reason in words (a symbol without a definition, a family without an exact
    /// polynomial, input that does not read, …).
    #[error("{0}")]
    Reason(String),
    /// A matrix computation refused (shapes, a singular matrix).
    #[error(transparent)]
    Linalg(#[from] crate::linalg::LinalgError),
    /// The claim's own inputs refused.
    #[error(transparent)]
    Inputs(#[from] super::inputs::ComputeError),
    /// The desired polynomial refused.
    #[error(transparent)]
    Polynomial(#[from] crate::observer::polynomial::PolynomialError),
}

impl From<String> for NoProof {
    fn from(reason: String) -> Self {
        NoProof::Reason(reason)
    }
}

impl From<&str> for NoProof {
    fn from(reason: &str) -> Self {
        NoProof::Reason(reason.to_string())
    }
}

/// Proves (or refutes) a sampled claim over the rational functions of its symbols: a desired
/// polynomial or a single-output gain. `env` holds the values the claim fixes; `penv` the
/// print's (with the claim's `where` definitions).
///
/// # Errors
/// Why this claim's computation is not carried out symbolically here.
pub fn prove(inputs: &Inputs, printed: &str, penv: &Environment) -> Result<Proof, NoProof> {
    use super::Computation as C;
    match inputs.claim.what {
        C::DesiredPolynomial => desired_claim(inputs, printed, penv),
        C::Gain | C::CanonicalGain => gain_claim(inputs, printed, penv),
        C::Identity if inputs.claim.identity == Some(super::Identity::GainMethodsAgree) => {
            methods_agree_claim(inputs)
        }
        C::Identity if inputs.claim.identity == Some(super::Identity::PlacementAnyPolynomial) => {
            placement_claim(inputs)
        }
        other => Err(format!("no symbolic recomputation of '{other}'").into()),
    }
}

fn one_radicand(values: &[&Fraction]) -> Result<(), NoProof> {
    let mut all: Vec<i64> = values.iter().flat_map(|v| v.radicands()).collect();
    all.sort_unstable();
    all.dedup();
    if all.len() > 1 {
        return Err(format!("square roots of {all:?} together").into());
    }
    Ok(())
}

/// The symbols of the values a proof compares, sorted, once each (one square root at most).
fn symbols_of(all: &[&Fraction]) -> Result<Vec<String>, NoProof> {
    one_radicand(all)?;
    let mut symbols: Vec<String> = all.iter().flat_map(|v| v.symbols()).collect();
    symbols.sort();
    symbols.dedup();
    Ok(symbols)
}

fn read(text: &str, env: &Environment) -> Result<Fraction, NoProof> {
    let e = parse_expression(text).map_err(|e| e.show_in(text))?;
    Ok(evaluate_with::<Fraction>(&e, env).map_err(|e| e.show_in(text))?)
}

/// The print's value with the claim's `where` definitions (`k2 = "-c2/a"`) substituted, as
/// often as they refer to one another.
fn with_definitions(v: Fraction, inputs: &Inputs, penv: &Environment) -> Result<Fraction, NoProof> {
    let defs = &inputs.claim.definitions;
    let mut v = v;
    for _ in 0..=defs.len() {
        for (name, text) in defs {
            if penv.contains_key(name) || !v.symbols().contains(name) {
                continue;
            }
            let d = read(text, penv).map_err(|e| format!("where.{name}: {e}"))?;
            v = v.substitute(name, &d);
        }
    }
    Ok(v)
}

/// The desired polynomial's coefficients (lowest power first) over the rational functions.
pub(super) fn symbolic_desired(inputs: &Inputs, n: usize) -> Result<Vec<Fraction>, NoProof> {
    let c = inputs.claim;
    let env = inputs.env;
    let scaled =
        |t: &str, p1: Result<DesiredPolynomial, NoProof>| -> Result<Vec<Fraction>, NoProof> {
            // P_T(s) = T^-n P_1(T s): the coefficient of s^k is p_k T^(k - n)
            let t = read(t, env)?;
            let p1 = p1?.exact.ok_or("the family has no exact polynomial")?;
            let inv = Fraction::one()
                .checked_div(&t)
                .ok_or("a zero time constant")?;
            Ok((0..=n)
                .map(|k| {
                    let mut v = Fraction::quadratic(&p1.coeff(k));
                    for _ in k..n {
                        v = v * inv.clone();
                    }
                    v
                })
                .collect())
        };
    let one = Rational::one();
    if let Some((family, t)) = c.family() {
        scaled(t, family.polynomial(&one, n).map_err(NoProof::from))
    } else if let Some(p) = &c.poles {
        let rows = parse_matrix_expressions(p).map_err(|e| e.show_in(p))?;
        let poles: Vec<Fraction> = rows
            .iter()
            .flatten()
            .map(|e| evaluate_with::<Fraction>(e, env).map_err(|e| e.show_in(p)))
            .collect::<Result<_, _>>()?;
        if poles.len() != n {
            return Err(format!("{} poles for order {n}", poles.len()).into());
        }
        let mut coeffs = vec![Fraction::one()];
        for p in &poles {
            // multiply by (s - p)
            let mut next = vec![Fraction::zero(); coeffs.len() + 1];
            for (k, c) in coeffs.iter().enumerate() {
                next[k + 1] = next[k + 1].clone() + c.clone();
                next[k] = next[k].clone() - c.clone() * p.clone();
            }
            coeffs = next;
        }
        Ok(coeffs)
    } else if let Some(p) = &c.poly {
        let v = read(p, env)?;
        let coeffs = v
            .coefficients_in("s")
            .ok_or("s in a denominator of the polynomial")?;
        if coeffs.len() != n + 1 {
            return Err(
                format!("a polynomial of degree {} for order {n}", coeffs.len() - 1).into(),
            );
        }
        Ok(coeffs)
    } else {
        Err("no desired polynomial".into())
    }
}

fn desired_claim(inputs: &Inputs, printed: &str, penv: &Environment) -> Result<Proof, NoProof> {
    let n = inputs.order()?;
    let coeffs = symbolic_desired(inputs, n)?;
    let var = inputs.var();
    let x = Fraction::symbol(&var);
    let mut value = Fraction::zero();
    for c in coeffs.iter().rev() {
        value = value * x.clone() + c.clone();
    }
    let print = with_definitions(read(printed, penv)?, inputs, penv)?;
    one_radicand(&[&value, &print])?;
    let mut symbols = value.symbols();
    symbols.extend(print.symbols());
    symbols.retain(|s| *s != var);
    symbols.sort();
    symbols.dedup();
    Ok(Proof {
        holds: value == print,
        symbols,
        value: value.termwise(),
        method: "the family's definition P_T(s) = T⁻ⁿ P₁(T s), P₁ computed exactly",
    })
}

/// `P(A) O⁻¹ eₙ` over the rational functions: Ackermann's formula.
fn ackermann(
    a: &Matrix<Fraction>,
    c: &Matrix<Fraction>,
    coeffs: &[Fraction],
) -> Result<(Matrix<Fraction>, Matrix<Fraction>), NoProof> {
    let n = a.rows();
    let mut o = c.clone();
    let mut row = c.clone();
    for _ in 1..n {
        row = row.mul(a)?;
        o = o.vstack(&row)?;
    }
    // adj(O) from the characteristic polynomial s^n + p_{n-1} s^{n-1} + … + p_0 of O:
    // O adj(O) = det(O) I with det O = (-1)^n p_0 and adj O = (-1)^(n-1) (O^(n-1) + … + p_1 I)
    let chi = berkowitz(&o, "s")?;
    let p = chi.coeffs();
    let sign = |k: usize| {
        if k.is_multiple_of(2) {
            Fraction::one()
        } else {
            -Fraction::one()
        }
    };
    let det = sign(n) * p[0].clone();
    if det.is_zero() {
        return Err("det O ≡ 0: not observable for any value of the symbols".into());
    }
    let mut adj = Matrix::identity(n);
    for k in (1..n).rev() {
        // Horner: adj = adj·O + p_k I, starting from I (the leading coefficient)
        adj = adj.mul(&o)?;
        adj = adj.add(&Matrix::identity(n).scale(&p[k]))?;
    }
    let adj = adj.scale(&sign(n - 1));
    let last = Matrix::from_fn(n, 1, |i, _| {
        adj.get(i, n - 1)
            .checked_div(&det)
            .unwrap_or_else(Fraction::zero)
    });
    // P(A) by Horner
    let mut pa = Matrix::zeros(n, n);
    for c in coeffs.iter().rev() {
        pa = pa.mul(a)?;
        pa = pa.add(&Matrix::identity(n).scale(c))?;
    }
    Ok((pa.mul(&last)?, o))
}

fn symbolic_matrix(inputs: &Inputs, name: &str) -> Result<Matrix<Fraction>, NoProof> {
    let m = inputs.symbolic(name)?;
    Ok(m.map(|x| Fraction::of(x.clone())))
}

/// The gain in Di Ruscio's observer canonical coordinates: `K_o = T_o⁻¹ K = Mᵀ O_n K`, with
/// `M` the upper-triangular Toeplitz matrix of the open-loop coefficients (eq. (18)).
fn in_canonical_coordinates(
    a: &Matrix<Fraction>,
    o: &Matrix<Fraction>,
    k: &Matrix<Fraction>,
) -> Result<Matrix<Fraction>, NoProof> {
    let n = a.rows();
    let chi = berkowitz(a, "s")?;
    // a_k is the coefficient of s^(n−k)
    let m = Matrix::from_fn(n, n, |i, j| {
        if j >= i {
            chi.coeff(n - (j - i))
        } else {
            Fraction::zero()
        }
    });
    Ok(m.transpose().mul(o).and_then(|x| x.mul(k))?)
}

/// The claim's `A` and `C` over the rational functions, `C` one row.
fn single_output_pair(inputs: &Inputs) -> Result<(Matrix<Fraction>, Matrix<Fraction>), NoProof> {
    let a = symbolic_matrix(inputs, "A")?;
    let c = symbolic_matrix(inputs, "C")?;
    if c.rows() != 1 || !a.is_square() || c.cols() != a.rows() {
        return Err("not a single-output pair".into());
    }
    Ok((a, c))
}

fn methods_agree_claim(inputs: &Inputs) -> Result<Proof, NoProof> {
    let (a, c) = single_output_pair(inputs)?;
    let n = a.rows();
    let desired = symbolic_desired(inputs, n)?;
    let (k, o) = ackermann(&a, &c, &desired)?;
    let k_o = in_canonical_coordinates(&a, &o, &k)?;
    let chi = berkowitz(&a, "s")?;
    // c − a: the i-th entry is the difference of the coefficients of s^(n−i)
    let c_minus_a: Vec<Fraction> = (1..=n)
        .map(|i| desired[n - i].clone() - chi.coeff(n - i))
        .collect();
    let mut all: Vec<&Fraction> = k.entries().iter().collect();
    all.extend(c_minus_a.iter());
    let symbols = symbols_of(&all)?;
    Ok(Proof {
        holds: k_o.entries().iter().zip(&c_minus_a).all(|(x, y)| x == y),
        symbols,
        value: format!(
            "K = [{}], Mᵀ O_n K = c − a = [{}]",
            k.entries().iter().map(Fraction::termwise).collect::<Vec<_>>().join("; "),
            c_minus_a.iter().map(Fraction::termwise).collect::<Vec<_>>().join("; ")
        ),
        method: "Ackermann's K = P(A) O⁻¹ eₙ over the rational functions, then Mᵀ O_n K = c − a, so T_o K_o = O_n⁻¹ M⁻ᵀ (c − a) = K with T_o = (Mᵀ O_n)⁻¹",
    })
}

/// Every polynomial is reachable from one output: Ackermann's gain over the rational functions of
/// the symbols, and `det(sI − (A − KC))` computed from it equals the desired polynomial
/// coefficient by coefficient — an identity wherever `det O_n ≠ 0`.
fn placement_claim(inputs: &Inputs) -> Result<Proof, NoProof> {
    let (a, c) = single_output_pair(inputs)?;
    let desired = symbolic_desired(inputs, a.rows())?;
    let (k, _) = ackermann(&a, &c, &desired)?;
    let achieved = berkowitz(&a.sub(&k.mul(&c)?)?, "s")?;
    let mut all: Vec<&Fraction> = k.entries().iter().collect();
    all.extend(desired.iter());
    let symbols = symbols_of(&all)?;
    Ok(Proof {
        holds: (0..=a.rows()).all(|i| achieved.coeff(i) == desired[i]),
        symbols,
        value: format!(
            "K = [{}], det(sI − (A − KC)) = the desired polynomial",
            k.entries().iter().map(Fraction::termwise).collect::<Vec<_>>().join("; ")
        ),
        method: "Ackermann's K = P(A) O⁻¹ eₙ over the rational functions, then det(sI − (A − KC)) by Berkowitz, compared coefficient by coefficient",
    })
}

fn gain_claim(inputs: &Inputs, printed: &str, penv: &Environment) -> Result<Proof, NoProof> {
    let (a, c) = single_output_pair(inputs)?;
    let coeffs = symbolic_desired(inputs, a.rows())?;
    let (mut k, o) = ackermann(&a, &c, &coeffs)?;
    let canonical = inputs.claim.what == super::Computation::CanonicalGain;
    if canonical {
        k = in_canonical_coordinates(&a, &o, &k)?;
    }
    if inputs.convention(Convention::AMinusKC)? == Convention::APlusLC {
        k = k.neg();
    }
    let rows = parse_matrix_expressions(printed).map_err(|e| e.show_in(printed))?;
    let print: Vec<Fraction> = rows
        .iter()
        .flatten()
        .map(|e| {
            let v = evaluate_with::<Fraction>(e, penv).map_err(|e| e.show_in(printed))?;
            with_definitions(v, inputs, penv)
        })
        .collect::<Result<_, _>>()?;
    let shape_ok = rows.len() == k.rows() && rows.iter().all(|r| r.len() == 1);
    let mut all: Vec<&Fraction> = k.entries().iter().collect();
    all.extend(print.iter());
    let symbols = symbols_of(&all)?;
    let holds = shape_ok && k.entries().iter().zip(&print).all(|(x, y)| x == y);
    Ok(Proof {
        holds,
        symbols,
        value: format!(
            "[{}]",
            k.entries()
                .iter()
                .map(Fraction::termwise)
                .collect::<Vec<_>>()
                .join("; ")
        ),
        method: if canonical {
            "K_o = Mᵀ O_n K with Ackermann's K = P(A) O⁻¹ eₙ, over the rational functions (the gain is unique where det O ≠ 0)"
        } else {
            "Ackermann's formula K = P(A) O⁻¹ eₙ over the rational functions (the gain is unique where det O ≠ 0)"
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn f(text: &str) -> Fraction {
        read(text, &Environment::new()).unwrap()
    }

    #[test]
    fn equal_rational_functions_are_equal_and_others_are_not() {
        assert_eq!(f("(T^2 - 1)/(T - 1)"), f("T + 1"));
        assert_eq!(f("sqrt(2)*sqrt(2)/T"), f("2/T"));
        assert_eq!(f("1/(a T^2) + 2/T"), f("(1 + 2 a T)/(a T^2)"));
        assert_ne!(f("sqrt(2)/T"), f("1.4142/T"));
        assert_ne!(f("1/(a T)"), f("1/(a T^2)"));
        let k2 = f("-c2/a");
        assert_eq!(f("c1 + a - k2").substitute("k2", &k2), f("c1 + a + c2/a"));
        assert_eq!(f("(a T^2 + sqrt(2) T)/T^3").termwise(), "sqrt(2)/T^2 + a/T");
        assert!(
            read("T/(T - T)", &Environment::new()).is_err(),
            "a zero denominator"
        );
    }
}
