//! Recomputing a claim: one function per computation a worked example can ask for
//! (`what = …`, see [`Computation`]).

use super::computation::{Computation, Identity};
use super::compute_course as course;
use super::inputs::{failed, input_error, lift, one_step, ComputeError, Computed, Inputs};
use super::value::Value;
use crate::algebra::{MultiPoly, Quadratic, Rational, Ring, Zero};
use crate::canonical_form::{
    controller_form, observer_form_di_ruscio, observer_form_stoustrup, CanonicalForm,
};
use crate::control::{observer_based_control, state_feedback};
use crate::derivation::Derivation;
use crate::linalg::{self, elimination::determinant_in_domain, Matrix};
use crate::observability::{controllability_matrix, observability_matrix};
use crate::observer::perfect::perfect_observer;
use crate::observer::{canonical_gain, design, Convention, GainMethod, ObserverGain};
use crate::poly::exact_roots;

fn canonical(inputs: &Inputs) -> Result<CanonicalForm<Rational>, ComputeError> {
    let a = inputs.numeric("A")?;
    let c = inputs.numeric("C")?;
    let b = if inputs.has("B") {
        Some(inputs.numeric("B")?)
    } else {
        None
    };
    let r = match inputs.claim.procedure.as_deref().unwrap_or("stoustrup") {
        "stoustrup" => observer_form_stoustrup(&a, b.as_ref(), &c),
        "di-ruscio" => observer_form_di_ruscio(&a, b.as_ref(), &c),
        other => {
            return Err(input_error(
                "procedure",
                format!("'{other}' is neither stoustrup nor di-ruscio"),
            ))
        }
    };
    Ok(r?)
}

/// Recomputes one claim: one function per computation (or family of computations sharing
/// their working).
///
/// # Errors
/// [`ComputeError`]; `NeedsValues` asks the caller to supply (sample) symbol values.
pub fn compute(inputs: &Inputs) -> Result<Computed, ComputeError> {
    use super::compute_optimal as optimal;
    use Computation as C;
    let what = inputs.claim.what;
    let title = format!("{} ({})", inputs.claim.id, what);
    match what {
        C::ObservabilityMatrix => {
            let o = observability_matrix(&inputs.symbolic("A")?, &inputs.symbolic("C")?)?;
            simple(&title, Value::SymbolicMatrix(o))
        }
        C::ObservabilityMatrixInverse => {
            let o = observability_matrix(&inputs.numeric("A")?, &inputs.numeric("C")?)?;
            simple(&title, Value::Matrix(lift(&linalg::inverse(&o)?)))
        }
        C::ObservabilityDeterminant => {
            let o = observability_matrix(&inputs.symbolic("A")?, &inputs.symbolic("C")?)?;
            simple(&title, Value::Symbolic(determinant_in_domain(&o)?))
        }
        C::Observable => observable(inputs, &title),
        C::CharacteristicPolynomial => {
            let var = inputs.var();
            let p = symbolic_charpoly(&inputs.symbolic("A")?, &var)?;
            simple(&title, Value::SymbolicPolynomial(p, var))
        }
        C::Eigenvalues => eigenvalues(inputs, &title),
        C::Stable => stable(inputs, &title),
        C::CanonicalTransformation => canonical_matrix(inputs, &title, CanonicalPart::T),
        C::CanonicalTransformationInverse => {
            canonical_matrix(inputs, &title, CanonicalPart::TInverse)
        }
        C::CanonicalA => canonical_matrix(inputs, &title, CanonicalPart::A),
        C::CanonicalB => canonical_matrix(inputs, &title, CanonicalPart::B),
        C::CanonicalC => canonical_matrix(inputs, &title, CanonicalPart::C),
        C::DesiredPolynomial => {
            let d = inputs.desired()?;
            let p = d
                .exact
                .clone()
                .ok_or_else(|| failed(d.inexact_reason.clone().unwrap_or_default()))?;
            simple(&title, Value::Polynomial(p.with_var(&inputs.var())))
        }
        C::CanonicalGain => canonical_gain_claim(inputs, &title),
        C::EquationReference => super::equation_reference::evaluate(inputs, &title),
        C::MatrixIdentity => super::matrix_expression::evaluate_identity(inputs, &title),
        C::MatrixExpression => super::matrix_expression::evaluate(inputs, &title),
        C::Gain => {
            let desired = inputs.desired()?;
            let (a, c) = (inputs.numeric("A")?, inputs.numeric("C")?);
            let convention = inputs.convention(Convention::AMinusKC)?;
            let d = design(&a, &c, &desired, inputs.method()?, convention)?;
            Ok(Computed {
                value: Value::Matrix(d.gain.matrix.clone()),
                derivation: d.derivation,
            })
        }
        C::StateFeedback => {
            let p = inputs
                .desired()?
                .rational()
                .ok_or_else(|| failed("state feedback needs a rational desired polynomial"))?;
            let f = state_feedback(&inputs.numeric("A")?, &inputs.numeric("B")?, &p)?;
            simple(&title, Value::Matrix(lift(&f)))
        }
        C::ClosedLoopPoles => closed_loop(inputs, LoopPart::Poles),
        C::ClosedLoopPolynomial => closed_loop(inputs, LoopPart::Polynomial),
        C::ControllerTransferFunction => closed_loop(inputs, LoopPart::Controller),
        C::ClosedLoopTransferFunction => closed_loop(inputs, LoopPart::ClosedLoop),
        C::ObserverCharacteristicPolynomial => observer_polynomial(inputs, &title),
        C::GainEquations | C::PolePlacementConstraints => constraints(inputs, &title),
        C::PerfectObserverE => perfect(inputs, PerfectPart::E),
        C::PerfectObserverF => perfect(inputs, PerfectPart::F),
        C::PerfectObserverInputMatrix => perfect(inputs, PerfectPart::InputMatrix),
        C::PerfectObserverOutputMatrix => perfect(inputs, PerfectPart::OutputMatrix),
        C::PerfectObserverDeterminant => perfect(inputs, PerfectPart::Determinant),
        C::Identity => identity(inputs, &title),
        C::MinimumNormGain | C::MinimumNormCost => optimal::minimum_norm(inputs, &title),
        C::DynamicalErrorCost | C::MinimalDynamicalErrorCost => {
            optimal::dynamical_error(inputs, &title)
        }
        C::KalmanBandwidth
        | C::NaturalFrequency
        | C::EstimationErrorRms
        | C::EstimationErrorVariance => optimal::noise(inputs, &title),
        C::PerfectObserverRobustness | C::PerfectObserverFits => {
            optimal::perfect_robustness(inputs, &title)
        }
        C::DiscreteGain => course::discrete(inputs, &title, course::DiscretePart::Gain),
        C::CurrentGain => course::discrete(inputs, &title, course::DiscretePart::CurrentGain),
        C::DiscreteErrorPolynomial => {
            course::discrete(inputs, &title, course::DiscretePart::ErrorPolynomial)
        }
        C::DeadbeatSteps => course::discrete(inputs, &title, course::DiscretePart::DeadbeatSteps),
        C::ZohPhi => course::zoh(inputs, &title, course::ZohPart::Phi),
        C::ZohGamma => course::zoh(inputs, &title, course::ZohPart::Gamma),
        C::ReducedOrderGain => course::reduced(inputs, &title, course::ReducedPart::Gain),
        C::ReducedOrderErrorPolynomial => {
            course::reduced(inputs, &title, course::ReducedPart::ErrorPolynomial)
        }
        C::ReducedOrderNoiseGain => course::reduced(inputs, &title, course::ReducedPart::NoiseGain),
        C::Detectable => course::detectable(inputs, &title, course::DetectablePart::Verdict),
        C::DetectableGain => course::detectable(inputs, &title, course::DetectablePart::Gain),
        C::DetectableObserverPolynomial => {
            course::detectable(inputs, &title, course::DetectablePart::ObserverPolynomial)
        }
        C::DiscreteKalmanGain => course::discrete_kalman(inputs, &title, course::KalmanPart::Gain),
        C::DiscreteKalmanCovariance => {
            course::discrete_kalman(inputs, &title, course::KalmanPart::Covariance)
        }
    }
}

/// A value whose working is the value itself.
/// Whether every eigenvalue of A is in the open left half-plane: Routh–Hurwitz on det(sI − A),
/// exact, no root computed.
fn stable(inputs: &Inputs, title: &str) -> Result<Computed, ComputeError> {
    let a = inputs.numeric("A")?;
    let p = crate::linalg::charpoly::characteristic_polynomial(&a, "s")?;
    let stable = crate::poly::is_hurwitz(&p);
    let mut d = Derivation::new(title);
    d.push("det(sI − A)", "", &p);
    let v = Value::Labels(vec![if stable { "stable" } else { "unstable" }.to_string()]);
    d.push(
        "every root in Re s < 0",
        "Routh–Hurwitz, exact (no root computed)",
        &v,
    );
    Ok(Computed {
        value: v,
        derivation: d,
    })
}

fn simple(title: &str, value: Value) -> Result<Computed, ComputeError> {
    Ok(Computed {
        derivation: one_step(title, &value),
        value,
    })
}

/// Whether `(A, C)` is observable, with the rank and the unobservable modes as working.
fn observable(inputs: &Inputs, title: &str) -> Result<Computed, ComputeError> {
    let a = inputs.numeric("A")?;
    let r = crate::observability::observability_report(&a, &inputs.numeric("C")?)?;
    let mut d = Derivation::new(title);
    d.push("O_n", "[C; CA; …]", &r.matrix);
    d.push("rank O_n", "", &Rational::from_i64(r.rank as i64));
    if !r.observable() {
        for v in &r.unobservable_subspace {
            d.push("unobservable direction", "ker O_n", v);
        }
        d.push(
            "unobservable modes",
            "det(sI − A|ker O_n)",
            &r.unobservable_polynomial,
        );
    }
    Ok(Computed {
        value: Value::Bool(r.observable()),
        derivation: d,
    })
}

/// Every root, repeated by its multiplicity.
fn with_multiplicity(roots: &crate::poly::ExactRoots) -> Vec<Quadratic> {
    roots
        .roots
        .iter()
        .flat_map(|(x, m)| std::iter::repeat_n(x.clone(), *m as usize))
        .collect()
}

/// The eigenvalues of A, exactly (all rational or quadratic, or the claim fails).
fn eigenvalues(inputs: &Inputs, title: &str) -> Result<Computed, ComputeError> {
    let p = linalg::characteristic_polynomial(&inputs.numeric("A")?, "s")?;
    let r = exact_roots(&p);
    if !r.complete() {
        return Err(failed(format!(
            "the eigenvalues are not all rational or quadratic: {}",
            r.render()
        )));
    }
    let mut d = Derivation::new(title);
    d.push("det(sI − A)", "", &p);
    let v = Value::Roots(with_multiplicity(&r));
    d.push("eigenvalues", "", &v);
    Ok(Computed {
        value: v,
        derivation: d,
    })
}

/// Which matrix of the observer canonical form a claim asks for.
#[derive(Clone, Copy)]
enum CanonicalPart {
    T,
    TInverse,
    A,
    B,
    C,
}

/// One matrix of the observer canonical form, with the whole form as working.
fn canonical_matrix(
    inputs: &Inputs,
    title: &str,
    part: CanonicalPart,
) -> Result<Computed, ComputeError> {
    let f = canonical(inputs)?;
    let m = match part {
        CanonicalPart::T => &f.t,
        CanonicalPart::TInverse => &f.t_inv,
        CanonicalPart::A => &f.a,
        CanonicalPart::B => &f.b,
        CanonicalPart::C => &f.c,
    };
    let mut d = Derivation::new(title);
    d.push("O_n", "", &f.test_matrix);
    d.push("T", "", &f.t);
    d.push("T⁻¹", "", &f.t_inv);
    d.push("A_o", "T⁻¹AT", &f.a);
    d.push("C_o", "CT", &f.c);
    Ok(Computed {
        value: Value::Matrix(lift(m)),
        derivation: d,
    })
}

/// The gain in observer-canonical coordinates, in the claim's convention.
fn canonical_gain_claim(inputs: &Inputs, title: &str) -> Result<Computed, ComputeError> {
    let p = inputs
        .desired()?
        .rational()
        .ok_or_else(|| failed("the canonical gain claim needs a rational desired polynomial"))?;
    let k_o = canonical_gain(&inputs.numeric("A")?, &inputs.numeric("C")?, &p)?.canonical;
    let g = ObserverGain {
        matrix: lift(&k_o),
        convention: Convention::AMinusKC,
    }
    .to_convention(inputs.convention(Convention::AMinusKC)?);
    simple(title, Value::Matrix(g.matrix))
}

/// What of observer-based control a claim asks for.
#[derive(Clone, Copy)]
enum LoopPart {
    Poles,
    Polynomial,
    Controller,
    ClosedLoop,
}

/// Observer-based control: the closed loop's poles or polynomial, or a transfer function.
fn closed_loop(inputs: &Inputs, part: LoopPart) -> Result<Computed, ComputeError> {
    let l = inputs.observer_gain_a_plus_lc()?;
    let r = observer_based_control(&inputs.plant()?, &inputs.numeric("feedback")?, &l)?;
    let value = match part {
        LoopPart::Poles => Value::Roots(with_multiplicity(&exact_roots(&r.closed_loop_polynomial))),
        LoopPart::Polynomial => Value::Polynomial(
            r.closed_loop_polynomial
                .map(|x| Quadratic::rational(x.clone()))
                .with_var(&inputs.var()),
        ),
        LoopPart::Controller => Value::Transfer(r.controller.clone()),
        LoopPart::ClosedLoop => Value::Transfer(r.closed_loop.clone()),
    };
    Ok(Computed {
        value,
        derivation: r.derivation,
    })
}

/// `det(λI − (A ∓ GC))` with a symbolic gain.
fn observer_polynomial(inputs: &Inputs, title: &str) -> Result<Computed, ComputeError> {
    let var = inputs.var();
    let a = inputs.symbolic("A")?;
    let convention = inputs.convention(Convention::AMinusKC)?;
    let gain = ObserverGain {
        matrix: inputs.symbolic("gain")?,
        convention,
    };
    let obs = gain.observer_matrix(&a, &inputs.symbolic("C")?)?;
    let p = symbolic_charpoly(&obs, &var)?;
    let mut d = Derivation::new(title);
    d.push("observer matrix", &convention.to_string(), &obs);
    let v = Value::SymbolicPolynomial(p, var);
    d.push("characteristic polynomial", "det(λI − observer matrix)", &v);
    Ok(Computed {
        value: v,
        derivation: d,
    })
}

/// Which part of the perfect observer a claim asks for.
#[derive(Clone, Copy)]
enum PerfectPart {
    E,
    F,
    InputMatrix,
    OutputMatrix,
    Determinant,
}

/// One matrix of the perfect observer, or its pencil's determinant.
fn perfect(inputs: &Inputs, part: PerfectPart) -> Result<Computed, ComputeError> {
    let p = perfect_observer(&inputs.plant()?)?;
    let value = match part {
        PerfectPart::E => Value::Matrix(lift(&p.e)),
        PerfectPart::F => Value::Matrix(lift(&p.f)),
        PerfectPart::InputMatrix => Value::Matrix(lift(&p.input_matrix)),
        PerfectPart::OutputMatrix => Value::Matrix(lift(&p.output_matrix)),
        PerfectPart::Determinant => Value::Polynomial(
            p.pencil_determinant
                .map(|x| Quadratic::rational(x.clone()))
                .with_var(&inputs.var()),
        ),
    };
    Ok(Computed {
        value,
        derivation: p.derivation,
    })
}

/// `det(var·I − M)` over the symbolic ring, as a polynomial containing `var`.
pub(super) fn symbolic_charpoly(
    m: &Matrix<MultiPoly>,
    var: &str,
) -> Result<MultiPoly, ComputeError> {
    let p = linalg::berkowitz(m, var)?;
    let x = MultiPoly::var(var);
    Ok(p.coeffs()
        .iter()
        .rev()
        .fold(MultiPoly::zero(), |acc, c| acc * x.clone() + c.clone()))
}

/// Pole-placement equations for a symbolic gain: coefficient by coefficient of
/// `det(λI − (A − GC))` against the desired polynomial.
fn constraints(inputs: &Inputs, title: &str) -> Result<Computed, ComputeError> {
    let a = inputs.symbolic("A")?;
    let c = inputs.symbolic("C")?;
    let g = inputs.symbolic("gain")?;
    let n = a.rows();
    let obs = a.sub(&g.mul(&c)?)?;
    let p = linalg::berkowitz(&obs, "λ")?;
    let desired = inputs
        .desired()?
        .rational()
        .ok_or_else(|| failed("pole-placement equations need a rational desired polynomial"))?;
    let mut d = Derivation::new(title);
    d.push("A − GC", "", &obs);
    // coefficient of λ^(n−i) for i = 1…n
    let eqs: Vec<MultiPoly> = (1..=n)
        .map(|i| p.coeff(n - i) - MultiPoly::constant(desired.coeff(n - i)))
        .collect();
    if inputs.claim.what == Computation::PolePlacementConstraints {
        let v = Value::Equations(eqs);
        d.push(
            "equations",
            "coefficients of det(λI − (A − GC)) = desired",
            &v,
        );
        return Ok(Computed {
            value: v,
            derivation: d,
        });
    }
    // linear in the gain symbols: M g = desired − constant part
    let symbols: Vec<String> = (0..g.rows())
        .map(|i| g.get(i, 0).variables().first().cloned().unwrap_or_default())
        .collect();
    let mut m = Matrix::<Rational>::zeros(n, symbols.len());
    let mut rhs = Matrix::<Rational>::zeros(n, 1);
    for (i, e) in eqs.iter().enumerate() {
        let mut rest = e.clone();
        for (j, s) in symbols.iter().enumerate() {
            let coeffs = rest.coefficients_in(s);
            if coeffs.len() > 2 || coeffs.get(1).is_some_and(|c| c.as_constant().is_none()) {
                return Err(failed(format!("equation {} is not linear in {s}", i + 1)));
            }
            if let Some(k) = coeffs.get(1) {
                m.set(i, j, k.as_constant().unwrap_or_default());
            }
            rest = coeffs.first().cloned().unwrap_or_default();
        }
        let constant = rest.as_constant().ok_or_else(|| {
            failed(format!(
                "equation {} has a non-constant remainder {rest}",
                i + 1
            ))
        })?;
        rhs.set(i, 0, -constant);
    }
    let v = Value::LinearSystem(m, rhs);
    d.push("linear equations", "M g = r", &v);
    Ok(Computed {
        value: v,
        derivation: d,
    })
}

fn identity(inputs: &Inputs, title: &str) -> Result<Computed, ComputeError> {
    let name = inputs
        .claim
        .identity
        .ok_or_else(|| input_error("identity", "missing"))?;
    let a = inputs.numeric("A")?;
    let mut d = Derivation::new(title);
    let holds = match name {
        Identity::ToeplitzIsInverseCanonicalObservability => {
            let c = inputs.numeric("C")?;
            let f = observer_form_di_ruscio(&a, None, &c)?;
            let o_o = observability_matrix(&f.a, &f.c)?;
            d.push("M", "", &f.toeplitz);
            d.push("O_n^o", "observability matrix of (A_o, C_o)", &o_o);
            f.toeplitz.transpose().mul(&o_o)? == Matrix::identity(a.rows())
        }
        Identity::ToeplitzIsInverseCanonicalControllability => {
            let b = inputs.numeric("B")?;
            let f = controller_form(&a, &b, None)?;
            let c_c = controllability_matrix(&f.a, &f.b)?;
            d.push("M", "", &f.toeplitz);
            d.push("C_n^c", "controllability matrix of (A_c, B_c)", &c_c);
            f.toeplitz.mul(&c_c)? == Matrix::identity(a.rows())
        }
        Identity::MarkovParametersAgree => {
            let b = inputs.numeric("B")?;
            let c = inputs.numeric("C")?;
            let o = observer_form_di_ruscio(&a, Some(&b), &c)?;
            let k = controller_form(&a, &b, Some(&c))?;
            let markov = |a: &Matrix<Rational>,
                          b: &Matrix<Rational>,
                          c: &Matrix<Rational>|
             -> Result<Vec<Matrix<Rational>>, ComputeError> {
                (0..=a.rows())
                    .map(|i| Ok(c.mul(&a.pow(i as u32)?)?.mul(b)?))
                    .collect()
            };
            let h = markov(&a, &b, &c)?;
            let row = Matrix::row_vector(h.iter().map(|m| m.get(0, 0).clone()).collect());
            d.push("C A^(i−1) B", "i = 1 … n + 1", &row);
            h == markov(&o.a, &o.b, &o.c)? && h == markov(&k.a, &k.b, &k.c)?
        }
        Identity::GainMethodsAgree | Identity::Lemma31GivesCMinusA => {
            let c = inputs.numeric("C")?;
            let desired = inputs.desired()?;
            let gains: Vec<Matrix<Quadratic>> = GainMethod::ALL
                .iter()
                .map(|m| {
                    design(&a, &c, &desired, *m, Convention::AMinusKC)
                        .map(|d| d.gain.matrix)
                        .map_err(ComputeError::from)
                })
                .collect::<Result<_, _>>()?;
            for (m, g) in GainMethod::ALL.iter().zip(&gains) {
                d.push(&format!("K by {m}"), "", g);
            }
            if name == Identity::GainMethodsAgree {
                gains.windows(2).all(|w| w[0] == w[1])
            } else {
                let p = desired
                    .rational()
                    .ok_or_else(|| failed("needs a rational desired polynomial"))?;
                let (_, k_tilde) = crate::observer::lemma_3_1_gain(&a, &c, &p)?;
                let k_o = canonical_gain(&a, &c, &p)?.canonical;
                let n = a.rows();
                d.push("K̃_o", "C P(A) O_n⁻¹", &k_tilde);
                d.push("c − a", "", &k_o);
                (0..n).all(|i| k_tilde.get(0, n - 1 - i) == k_o.get(i, 0))
            }
        }
        Identity::CanonicalProceduresAgree => {
            let c = inputs.numeric("C")?;
            let x = observer_form_di_ruscio(&a, None, &c)?;
            let y = observer_form_stoustrup(&a, None, &c)?;
            d.push("T_o (Di Ruscio)", "(Mᵀ O_n)⁻¹", &x.t);
            d.push("T (Stoustrup)", "[t_1 … t_n]", &y.t);
            x.t == y.t
        }
        Identity::PlacementAnyPolynomial => {
            let c = inputs.numeric("C")?;
            let desired = inputs.desired()?;
            let g = design(
                &a,
                &c,
                &desired,
                GainMethod::Ackermann,
                Convention::AMinusKC,
            )?;
            let closed = lift(&a).sub(&g.gain.matrix.mul(&lift(&c))?)?;
            let achieved = crate::linalg::charpoly::characteristic_polynomial(&closed, "s")?;
            d.push("K", "P(A) O_n⁻¹ e_n", &g.gain.matrix);
            d.push("det(sI − (A − KC))", "", &achieved);
            desired
                .exact
                .as_ref()
                .is_some_and(|p| *p == achieved.with_var(p.var()))
        }
        Identity::SeparationPrinciple => {
            let l = inputs.observer_gain_a_plus_lc()?;
            let r = observer_based_control(&inputs.plant()?, &inputs.numeric("feedback")?, &l)?;
            d.extend(r.derivation);
            r.separation_holds
        }
    };
    let v = Value::Bool(holds);
    d.push("holds", "", &v);
    Ok(Computed {
        value: v,
        derivation: d,
    })
}
