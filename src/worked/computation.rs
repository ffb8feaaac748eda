//! What a claim (`what = …`) or an exercise part (`ask = …`) asks the workbench to compute, and
//! which identity a `what = "identity"` claim states: typed, with the names the files use.

use crate::names::named_enum;

named_enum! {
    /// A computation a worked-example claim may name; exercises ask for the
    /// [`askable`](Computation::askable) ones.
    pub enum Computation ("computation") {
        /// `O_n = [C; CA; …; CA^(n−1)]`, symbols allowed.
        ObservabilityMatrix = "observability_matrix",
        /// `O_n⁻¹`.
        ObservabilityMatrixInverse = "observability_matrix_inverse",
        /// `det O_n`, symbols allowed.
        ObservabilityDeterminant = "observability_determinant",
        /// Whether `(A, C)` is observable, with the unobservable modes.
        Observable = "observable",
        /// `det(sI − A)`, symbols allowed.
        CharacteristicPolynomial = "characteristic_polynomial",
        /// Whether every eigenvalue of `A` lies in the open left half-plane (Routh–Hurwitz on
        /// `det(sI − A)`, exact; no root computed).
        Stable = "stable",
        /// The eigenvalues of `A`, exactly.
        Eigenvalues = "eigenvalues",
        /// `T` of the observer canonical form.
        CanonicalTransformation = "canonical_transformation",
        /// `T⁻¹`.
        CanonicalTransformationInverse = "canonical_transformation_inverse",
        /// `A_o = T⁻¹AT`.
        CanonicalA = "canonical_a",
        /// `B_o = T⁻¹B`.
        CanonicalB = "canonical_b",
        /// `C_o = CT`.
        CanonicalC = "canonical_c",
        /// The desired observer (or feedback) polynomial.
        DesiredPolynomial = "desired_polynomial",
        /// The gain in observer-canonical coordinates.
        CanonicalGain = "canonical_gain",
        /// The observer gain, with its derivation.
        Gain = "gain",
        /// The state-feedback row placing the desired polynomial.
        StateFeedback = "state_feedback",
        /// Poles of observer-based control.
        ClosedLoopPoles = "closed_loop_poles",
        /// Characteristic polynomial of observer-based control.
        ClosedLoopPolynomial = "closed_loop_polynomial",
        /// The controller's transfer function.
        ControllerTransferFunction = "controller_transfer_function",
        /// The closed loop's transfer function.
        ClosedLoopTransferFunction = "closed_loop_transfer_function",
        /// `det(sI − (A ∓ KC))` with a symbolic gain.
        ObserverCharacteristicPolynomial = "observer_characteristic_polynomial",
        /// Coefficient equations for a symbolic gain.
        GainEquations = "gain_equations",
        /// The same, as constraints of the optimal designs.
        PolePlacementConstraints = "pole_placement_constraints",
        /// `E` of the perfect observer.
        PerfectObserverE = "perfect_observer_e",
        /// `F` of the perfect observer.
        PerfectObserverF = "perfect_observer_f",
        /// The perfect observer's input matrix.
        PerfectObserverInputMatrix = "perfect_observer_input_matrix",
        /// The perfect observer's output matrix.
        PerfectObserverOutputMatrix = "perfect_observer_output_matrix",
        /// The determinant of the perfect observer's pencil.
        PerfectObserverDeterminant = "perfect_observer_determinant",
        /// A stated identity, proved or sampled (see [`Identity`]).
        Identity = "identity",
        /// Baranowski's minimum-norm gain.
        MinimumNormGain = "minimum_norm_gain",
        /// Its cost `J1`.
        MinimumNormCost = "minimum_norm_cost",
        /// `J2` of a given gain.
        DynamicalErrorCost = "dynamical_error_cost",
        /// The minimal `J2` over the placing gains.
        MinimalDynamicalErrorCost = "minimal_dynamical_error_cost",
        /// The Kalman filter's bandwidth.
        KalmanBandwidth = "kalman_bandwidth",
        /// Natural frequency of a pole pair.
        NaturalFrequency = "natural_frequency",
        /// Steady-state RMS of the estimation error, `√(trace Σ)`.
        EstimationErrorRms = "estimation_error_rms",
        /// Steady-state variance of the estimation error, `trace Σ`.
        EstimationErrorVariance = "estimation_error_variance",
        /// Robustness conditions of the perfect observer.
        PerfectObserverRobustness = "perfect_observer_robustness",
        /// Whether the perfect observer still fits a changed plant.
        PerfectObserverFits = "perfect_observer_fits",
        /// A printed matrix formula (`expression`, e.g. `Q T A T^-1`) evaluated as printed over
        /// the claim's matrices (`[claims.matrices]`) and the system's.
        MatrixExpression = "matrix_expression",
        /// A printed equality of two matrix formulas, both sides evaluated as printed
        /// (`expression` = `printed`), compared exactly — an identity in the symbols.
        MatrixIdentity = "matrix_identity",
        /// A printed equation reference ("A, B and C₁ are given by (3), (4) and (7)") checked by
        /// finding the equations that hold each referent (`refers`, `[claims.equations]`).
        EquationReference = "equation_reference",
        /// A discrete-time observer's prediction gain K (A − KC) for poles in z.
        DiscreteGain = "discrete_gain",
        /// The current (filtered) estimator's gain L_c = A⁻¹ K.
        CurrentGain = "current_gain",
        /// The discrete-time error polynomial det(zI − error matrix).
        DiscreteErrorPolynomial = "discrete_error_polynomial",
        /// Dead-beat: the number of steps after which the error is exactly zero.
        DeadbeatSteps = "deadbeat_steps",
        /// Zero-order hold: Φ = e^(AT) (exact for nilpotent A; `period`).
        ZohPhi = "zoh_phi",
        /// Zero-order hold: Γ = ∫₀ᵀ e^(Aτ) dτ B.
        ZohGamma = "zoh_gamma",
        /// Reduced-order observer (Gopinath): the gain L of A₂₂ − L A₁₂.
        ReducedOrderGain = "reduced_order_gain",
        /// Reduced-order observer: det(sI − (A₂₂ − L A₁₂)), degree n − p.
        ReducedOrderErrorPolynomial = "reduced_order_error_polynomial",
        /// Reduced-order observer: Σ D_y², how much measurement noise reaches x̂ directly.
        ReducedOrderNoiseGain = "reduced_order_noise_gain",
        /// Whether every unobservable mode is stable.
        Detectable = "detectable",
        /// The gain placing the observable part's poles (Kalman decomposition).
        DetectableGain = "detectable_gain",
        /// det(sI − (A − KC)) of that gain: the chosen poles times the fixed ones.
        DetectableObserverPolynomial = "detectable_observer_polynomial",
        /// The discrete steady-state Kalman filter's prediction gain L = A P Cᵀ (C P Cᵀ + R_n)⁻¹
        /// (`[claims.matrices]` G, Qn, Rn): exact when the Riccati solution is rational.
        DiscreteKalmanGain = "discrete_kalman_gain",
        /// Its a-priori error covariance P.
        DiscreteKalmanCovariance = "discrete_kalman_covariance",
    }
}

/// The observer gain: the workbench's central computation (a claim names its own).
impl Default for Computation {
    fn default() -> Self {
        Computation::Gain
    }
}

impl Computation {
    /// Whether an exercise part may ask for it: the computations whose answers a student writes
    /// (no optimisations, simulations or identities).
    pub fn askable(self) -> bool {
        use Computation::*;
        matches!(
            self,
            ObservabilityMatrix
                | ObservabilityDeterminant
                | Observable
                | CharacteristicPolynomial
                | Eigenvalues
                | CanonicalTransformation
                | CanonicalTransformationInverse
                | CanonicalA
                | CanonicalB
                | CanonicalC
                | DesiredPolynomial
                | CanonicalGain
                | Gain
                | StateFeedback
                | ClosedLoopPoles
                | ClosedLoopPolynomial
                | ControllerTransferFunction
                | ClosedLoopTransferFunction
                | PerfectObserverE
                | PerfectObserverF
                | PerfectObserverInputMatrix
                | PerfectObserverOutputMatrix
                | DiscreteGain
                | DeadbeatSteps
                | ReducedOrderGain
                | ReducedOrderErrorPolynomial
                | Detectable
                | DetectableGain
                | DetectableObserverPolynomial
        )
    }

    /// The askable computations, comma-separated (for error messages).
    pub fn known_askable() -> String {
        Self::ALL
            .iter()
            .filter(|c| c.askable())
            .map(|c| c.name())
            .collect::<Vec<_>>()
            .join(", ")
    }
}

named_enum! {
    /// An identity a claim with `what = "identity"` states.
    pub enum Identity ("identity") {
        /// Di Ruscio: the Toeplitz matrix of the coefficients inverts the canonical observability matrix.
        ToeplitzIsInverseCanonicalObservability = "toeplitz_is_inverse_canonical_observability",
        /// … and the canonical controllability matrix.
        ToeplitzIsInverseCanonicalControllability = "toeplitz_is_inverse_canonical_controllability",
        /// Markov parameters of the system and of its canonical form agree.
        MarkovParametersAgree = "markov_parameters_agree",
        /// The gain methods give the same gain.
        GainMethodsAgree = "gain_methods_agree",
        /// Lemma 3.1's `K̃_o = C P(A) O_n⁻¹` is the canonical gain `c − a` (reversed).
        Lemma31GivesCMinusA = "lemma_3_1_gives_c_minus_a",
        /// Stoustrup's and Di Ruscio's canonical procedures agree.
        CanonicalProceduresAgree = "canonical_procedures_agree",
        /// The closed loop's poles are the feedback's and the observer's.
        SeparationPrinciple = "separation_principle",
        /// Pole placement from one output: Ackermann's `K = P(A) O_n⁻¹ e_n` gives
        /// `det(sI − (A − KC)) = P(s)` — for a general system with symbols, an identity over the
        /// rational functions (wherever `det O_n ≠ 0`), i.e. every polynomial is reachable.
        PlacementAnyPolynomial = "placement_any_polynomial",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_read_back() {
        for c in Computation::ALL {
            assert_eq!(Computation::parse(c.name()), Ok(*c));
        }
        let e = Computation::parse("gian").unwrap_err();
        assert!(e
            .to_string()
            .starts_with("unknown computation 'gian'; known: observability_matrix,"));
        assert_eq!(
            Identity::parse("separation_principle"),
            Ok(Identity::SeparationPrinciple)
        );
    }
}
