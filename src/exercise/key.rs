//! The answer key: every part recomputed by the worked-example computations, so no answer is
//! ever typed by hand.

use super::format::{ExerciseFile, PartSpec};
use super::ExerciseError;
use crate::algebra::Rational;
use crate::derivation::Derivation;
use crate::syntax::{parse_scalar, Environment};
use crate::worked::{compute, ClaimSpec, Computation, ExampleFile, Inputs, Value};

/// One part with its computed answer.
#[derive(Clone)]
pub struct KeyPart {
    /// The part.
    pub spec: PartSpec,
    /// The claim that computes it (its inputs).
    pub claim: ClaimSpec,
    /// The correct answer.
    pub value: Value,
    /// Its derivation.
    pub derivation: Derivation,
}

/// The answer key of an exercise.
#[derive(Clone)]
pub struct AnswerKey {
    /// The exercise as a worked example (system and parameters).
    pub example: ExampleFile,
    /// Parameter values.
    pub env: Environment,
    /// The parts, in order.
    pub parts: Vec<KeyPart>,
    /// The exercise file (its design, for the formula diagnoses).
    pub exercise: ExerciseFile,
    /// The plant with free parameters, when the answers are formulas.
    pub formula: Option<super::formula::FormulaPlant>,
}

impl AnswerKey {
    /// The part with this id.
    pub fn part(&self, id: &str) -> Option<&KeyPart> {
        self.parts.iter().find(|p| p.spec.id == id)
    }
    /// Recomputes `claim` with other inputs (for diagnoses).
    pub fn recompute(&self, claim: &ClaimSpec) -> Option<Value> {
        compute(&Inputs {
            file: &self.example,
            claim,
            env: &self.env,
        })
        .ok()
        .map(|c| c.value)
    }
}

/// The claim computing `part` under the exercise's design.
pub fn claim_for(ex: &ExerciseFile, part: &PartSpec, gain: Option<String>) -> ClaimSpec {
    let base = &ex.design;
    let over = part.design.clone().unwrap_or_default();
    let pick = |o: &Option<String>, b: &Option<String>| o.clone().or_else(|| b.clone());
    let family_given = over.names_desired();
    let fam =
        |o: &Option<String>, b: &Option<String>| if family_given { o.clone() } else { b.clone() };
    let d = super::format::DesignSpec {
        convention: pick(&over.convention, &base.convention),
        procedure: pick(&over.procedure, &base.procedure),
        poles: fam(&over.poles, &base.poles),
        poly: fam(&over.poly, &base.poly),
        repeated: fam(&over.repeated, &base.repeated),
        butterworth: fam(&over.butterworth, &base.butterworth),
        bessel: fam(&over.bessel, &base.bessel),
        itae: fam(&over.itae, &base.itae),
        feedback: pick(&over.feedback, &base.feedback),
        gain: pick(&over.gain, &base.gain),
    };
    let gain = d.gain.clone().or(gain);
    ClaimSpec {
        id: part.id.clone(),
        source: ex.source.clone(),
        what: part.ask,
        c: part.c.clone(),
        convention: d.convention.clone(),
        procedure: d.procedure.clone(),
        poles: d.poles.clone(),
        poly: d.poly.clone(),
        repeated: d.repeated.clone(),
        butterworth: d.butterworth.clone(),
        bessel: d.bessel.clone(),
        itae: d.itae.clone(),
        feedback: d.feedback.clone(),
        gain,
        ..ClaimSpec::default()
    }
}

/// Computes the key.
///
/// # Errors
/// [`ExerciseError`] naming the part whose answer cannot be computed (bad system, unobservable
/// pair, missing design…).
pub fn answer_key(file: &str, ex: &ExerciseFile) -> Result<AnswerKey, ExerciseError> {
    let mut env = Environment::new();
    for (k, v) in &ex.parameters {
        let r: Rational = parse_scalar(v).map_err(|e| ExerciseError {
            file: file.into(),
            line: 0,
            field: format!("parameters.{k}"),
            message: e.show_in(v),
        })?;
        env.insert(k.clone(), r);
    }
    let example = ExampleFile {
        id: ex.id.clone(),
        title: ex.title.clone(),
        document: ex.source.clone(),
        parameters: ex.parameters.clone(),
        system: ex.system.clone(),
        ..ExampleFile::default()
    };
    let formula = super::formula::plant(ex, &env).map_err(|message| ExerciseError {
        file: file.into(),
        line: 0,
        field: "system".into(),
        message,
    })?;
    if let Some(plant) = &formula {
        let mut parts = Vec::new();
        for part in &ex.parts {
            let (value, derivation) =
                super::formula::key(ex, plant, part, &env).map_err(|message| ExerciseError {
                    file: file.into(),
                    line: 0,
                    field: format!("parts.{}", part.id),
                    message: format!("the answer key cannot be computed: {message}"),
                })?;
            parts.push(KeyPart {
                spec: part.clone(),
                claim: claim_for(ex, part, None),
                value,
                derivation,
            });
        }
        return Ok(AnswerKey {
            example,
            env,
            parts,
            exercise: ex.clone(),
            formula,
        });
    }
    let mut parts: Vec<KeyPart> = Vec::new();
    // the observer gain the control parts use: the computed gain part, if any
    let mut gain_text: Option<String> = None;
    for part in &ex.parts {
        let needs_gain = matches!(
            part.ask,
            Computation::ClosedLoopPoles
                | Computation::ClosedLoopPolynomial
                | Computation::ControllerTransferFunction
                | Computation::ClosedLoopTransferFunction
        );
        let claim = claim_for(ex, part, if needs_gain { gain_text.clone() } else { None });
        let computed = compute(&Inputs {
            file: &example,
            claim: &claim,
            env: &env,
        })
        .map_err(|e| ExerciseError {
            file: file.into(),
            line: 0,
            field: format!("parts.{}", part.id),
            message: format!("the answer key cannot be computed: {e}"),
        })?;
        if part.ask == Computation::Gain {
            gain_text = Some(computed.value.input());
        }
        parts.push(KeyPart {
            spec: part.clone(),
            claim,
            value: concrete(computed.value),
            derivation: computed.derivation,
        });
    }
    Ok(AnswerKey {
        example,
        env,
        parts,
        exercise: ex.clone(),
        formula: None,
    })
}

/// Symbolic results without free symbols as plain numbers (what a student writes).
fn concrete(v: Value) -> Value {
    use crate::algebra::Quadratic;
    match v {
        Value::SymbolicMatrix(m) => {
            let mut ok = true;
            let q = crate::linalg::Matrix::from_fn(m.rows(), m.cols(), |i, j| {
                match m.get(i, j).as_constant() {
                    Some(c) => Quadratic::rational(c),
                    None => {
                        ok = false;
                        Quadratic::rational(Rational::from_integer(0.into()))
                    }
                }
            });
            if ok {
                Value::Matrix(q)
            } else {
                Value::SymbolicMatrix(m)
            }
        }
        Value::SymbolicPolynomial(p, var) => {
            let coeffs: Option<Vec<Quadratic>> = p
                .coefficients_in(&var)
                .iter()
                .map(|c| c.as_constant().map(Quadratic::rational))
                .collect();
            match coeffs {
                Some(c) => Value::Polynomial(crate::poly::Poly::new(c, &var)),
                None => Value::SymbolicPolynomial(p, var),
            }
        }
        other => other,
    }
}
