//! Observer design: sign conventions, desired observer polynomials, gain methods and the float
//! check.
//!
//! Sign conventions are explicit: Di Ruscio and Baranowski write the observer matrix `A − KC`
//! (gain `K` or `G`), Stoustrup writes `A + LC` (gain `L`); [`ObserverGain`] carries its
//! [`Convention`] and converts with one call.

pub mod ackermann_exact;
mod convention;
pub mod detectability;
pub mod discrete;
pub mod discrete_kalman;
pub mod dynamical_error;
pub mod float_check;
mod gain;
pub(crate) use gain::CHECK_STEP;
pub mod kalman;
pub mod multi_output;
pub mod optimal;
pub mod partial;
pub mod perfect;
pub mod polynomial;
pub mod reduced_order;
pub mod robust;
pub mod search;
pub mod weighted;

pub use convention::{Convention, ObserverGain};
pub use gain::{
    ackermann_gain, bass_gura_gain, canonical_gain, design, design_symbolic, design_with,
    lemma_3_1_gain, CanonicalGain, DesignError, Detail, GainMethod, ObserverDesign, SymbolicDesign,
};
pub use polynomial::{DesiredPolynomial, Family, PolynomialFamily};
