//! The mistakes the checker names: keys of a part's `partial` credit table and the `mistake`
//! column of a grade report. Each is recognised by computing (see [`super::diagnose`]).

use crate::names::named_enum;

named_enum! {
    /// A recognised mistake (its name is what files and reports use).
    pub enum Mistake ("mistake") {
        /// −K: the gain of the other sign convention.
        SignConvention = "sign_convention",
        /// The gain left in observer-canonical coordinates.
        CanonicalCoordinates = "canonical_coordinates",
        /// A row where a column is asked, or the reverse.
        Transposed = "transposed",
        /// The entries in reverse order.
        Reversed = "reversed",
        /// Another polynomial family, time constant, or mirrored poles.
        WrongPolynomial = "wrong_polynomial",
        /// One entry wrong, everything else right.
        Slip = "slip",
        /// The transpose (controller form) of the observer canonical form.
        OtherCanonicalForm = "other_canonical_form",
        /// `T⁻¹` for `T`, or the reverse.
        Inverse = "inverse",
        /// A polynomial or transfer function with the wrong sign.
        Negated = "negated",
        /// The right answer to another part of the exercise.
        AnotherPart = "another_part",
        /// Right rows or columns in another order.
        Permuted = "permuted",
        /// The other canonical-form procedure's answer.
        OtherProcedure = "other_procedure",
        /// `K` of `u = −Kx` where `F` of `u = Fx` is asked.
        FeedbackSign = "feedback_sign",
        /// The current estimator's gain L_c = A⁻¹K where the prediction gain K is asked.
        CurrentEstimator = "current_estimator",
        /// A formula that equals the key only at particular values of the parameters.
        OnlyAtSomeValues = "only_at_some_values",
        /// The right gain of the same system measured through another output (another state).
        AnotherOutput = "another_output",
    }
}

impl Mistake {
    /// In words, for feedback: the name with spaces.
    pub fn words(self) -> String {
        self.name().replace('_', " ")
    }
}
