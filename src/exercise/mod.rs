//! Exercises for students: the statement and the parts to answer are data, the answer key is
//! computed by the workbench (never typed), and a student's answers are checked with feedback
//! that names the mistake — computed, not canned.
//!
//! * [`format`](mod@format): exercise files (`worked_examples/exercises/*.toml`) and answer files.
//! * [`key`]: the answer key, each part recomputed through the worked-example computations.
//! * [`check`]: one student's answers — verdict, score (partial credit per diagnosed mistake)
//!   and feedback per part.
//! * [`diagnose`]: the mistakes recognised: sign convention, gain left in canonical
//!   coordinates, transposed or reversed vector, the wrong observer polynomial (another family or
//!   another time constant, found from the poles the answer actually places), a single slip, an
//!   answer for another canonical-form convention, a negated polynomial or transfer function.
//! * [`generate`]: fresh pole-placement exercises whose hand computation stays in small integers.
//! * [`statement`]: a statement laid out for a page (paragraphs, numbered steps, the system
//!   typeset); [`hint`]: the method a part asks for, not its answer.
//! * [`formula`]: exercises with free parameters — the key a formula, answers checked as
//!   identities, mistakes named symbolically, right-only-at-some-values said with the values.

pub mod check;
pub mod diagnose;
pub mod format;
pub mod formula;
pub mod generate;
pub mod key;
pub mod mistake;
pub mod statement;

pub use check::{check_answers, PartResult, PartVerdict, Report};
pub use format::{
    load_answers, load_exercise, parse_answers, parse_exercise, AnswerFile, ExerciseFile, PartSpec,
};
pub use key::{answer_key, AnswerKey};
pub use mistake::Mistake;

/// A hint for a part asking this computation: the method, not the answer.
pub fn hint(what: crate::worked::Computation) -> Option<&'static str> {
    use crate::worked::Computation as C;
    Some(match what {
        C::ObservabilityMatrix => "stack C, CA, CA², … (n blocks); one row per output and power",
        C::ObservabilityDeterminant => "for one output O is square: expand its determinant; zero means not observable",
        C::Observable => "observable exactly when rank O = n (for one output: det O ≠ 0)",
        C::CharacteristicPolynomial => "det(λI − A); for 2×2, λ² − (trace A)λ + det A",
        C::Eigenvalues => "the roots of det(λI − A)",
        C::CanonicalTransformation | C::CanonicalTransformationInverse => "last column t_n = O⁻¹ e_n, then t_(k−1) = A t_k; T = (t₁ … t_n)",
        C::CanonicalA | C::CanonicalB | C::CanonicalC => "A_o = T⁻¹ A T, B_o = T⁻¹ B, C_o = C T; C_o must come out as (1 0 … 0)",
        C::DesiredPolynomial => "multiply out ∏ (λ − p_i) over the desired poles",
        C::CanonicalGain => "in canonical coordinates the gain is the difference of coefficients; mind the sign of the convention",
        C::Gain => "Ackermann: K = P(A) O⁻¹ e_n, or K = T K_o; then check det(sI − (A − KC)) = P(s). A + LC means L = −K",
        C::StateFeedback => "the dual of the observer gain: design for (Aᵀ, Bᵀ) and transpose; u = Fx means F = −K",
        C::ClosedLoopPoles | C::ClosedLoopPolynomial => "separation principle: the poles of A + BF together with those of A + LC",
        C::ControllerTransferFunction => "K(s) = −F (sI − A − BF − LC)⁻¹ L in the A + LC convention",
        C::ClosedLoopTransferFunction => "G (I − K G)⁻¹ with G = C (sI − A)⁻¹ B",
        C::PerfectObserverE | C::PerfectObserverF | C::PerfectObserverInputMatrix | C::PerfectObserverOutputMatrix => {
            "keep the middle n − p state rows and replace the last rows by the output equation (E singular)"
        }
        C::DiscreteGain => "the same formulas as continuous time, with the polynomial in z; dead-beat: every pole at 0",
        C::DeadbeatSteps => "the error is (A − KC)ᵏ e(0): find the first power of the error matrix that is zero",
        C::ReducedOrderGain => "split A with x₁ measured: place the poles of A₂₂ − L A₁₂, an observer design for the pair (A₂₂, A₁₂)",
        C::ReducedOrderErrorPolynomial => "det(sI − (A₂₂ − L A₁₂)), of degree n − p",
        C::Detectable => "find the unobservable modes (ker O); detectable when every one of them is stable",
        C::DetectableGain => "decompose into observable and unobservable parts; place the observable poles, the others stay",
        C::DetectableObserverPolynomial => "the chosen polynomial times the unobservable modes' polynomial",
        _ => return None,
    })
}

/// A file that cannot be used, located by file, line and field.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{file}:{line}: {field}: {message}")]
pub struct ExerciseError {
    /// The file.
    pub file: String,
    /// 1-based line (0 when unknown).
    pub line: usize,
    /// The field.
    pub field: String,
    /// What is wrong.
    pub message: String,
}

// `BUILTIN_EXERCISES`, written by build.rs from worked_examples/exercises/*.toml
include!(concat!(env!("OUT_DIR"), "/builtin_exercises.rs"));

/// A built-in exercise by id: `(id, text)`.
pub fn builtin(id: &str) -> Option<(&'static str, &'static str)> {
    BUILTIN_EXERCISES.iter().copied().find(|(i, _)| *i == id)
}
