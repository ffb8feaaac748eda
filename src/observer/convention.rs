//! The two sign conventions for an observer gain.

use crate::algebra::Ring;
use crate::linalg::{LinalgError, Matrix};
use std::fmt;

/// How the gain enters the observer matrix.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Convention {
    /// `A − KC` (Di Ruscio, Baranowski): `x̂' = Ax̂ + Bu + K(y − ŷ)`.
    AMinusKC,
    /// `A + LC` (Stoustrup): `x̂' = Ax̂ + Bu + L(Cx̂ − y)`.
    APlusLC,
}

impl Convention {
    /// The command-line spelling, `a-kc` or `a+lc`.
    pub fn flag(self) -> &'static str {
        match self {
            Convention::AMinusKC => "a-kc",
            Convention::APlusLC => "a+lc",
        }
    }
    /// The gain's usual letter.
    pub fn letter(self) -> &'static str {
        match self {
            Convention::AMinusKC => "K",
            Convention::APlusLC => "L",
        }
    }
    /// The label of a design's step showing the gain in this convention: `K` as designed, or
    /// the `L = −K` step that follows it.
    pub fn gain_step(self) -> &'static str {
        match self {
            Convention::AMinusKC => "K",
            Convention::APlusLC => "L = −K",
        }
    }
    /// The factor taking `K` of `A − KC` to this convention's gain: 1, or −1 for `L = −K`
    /// (for float gains; exact ones convert with [`ObserverGain::to_convention`]).
    pub fn sign(self) -> f64 {
        match self {
            Convention::AMinusKC => 1.0,
            Convention::APlusLC => -1.0,
        }
    }
    /// A gain computed in the A − KC sign, written in this convention (K, or L = −K): the one
    /// place the sign flips, through [`ObserverGain::to_convention`].
    pub fn from_a_minus_kc<F: Ring>(self, k: &Matrix<F>) -> Matrix<F> {
        ObserverGain {
            matrix: k.clone(),
            convention: Convention::AMinusKC,
        }
        .to_convention(self)
        .matrix
    }
    /// Parses `a-kc` / `a+lc` (case and spaces ignored).
    pub fn parse(s: &str) -> Option<Self> {
        let t: String = s
            .chars()
            .filter(|c| !c.is_whitespace())
            .collect::<String>()
            .to_lowercase();
        match t.as_str() {
            "a-kc" | "a−kc" => Some(Convention::AMinusKC),
            "a+lc" => Some(Convention::APlusLC),
            _ => None,
        }
    }
}

impl fmt::Display for Convention {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Convention::AMinusKC => "A − KC",
            Convention::APlusLC => "A + LC",
        })
    }
}

/// An observer gain together with the convention it is written in.
#[derive(Clone, PartialEq, Debug)]
pub struct ObserverGain<T: Ring> {
    /// The gain matrix (n × outputs).
    pub matrix: Matrix<T>,
    /// How it enters the observer matrix.
    pub convention: Convention,
}

impl<T: Ring> ObserverGain<T> {
    /// The same observer written in `convention` (`L = −K`).
    pub fn to_convention(&self, convention: Convention) -> Self {
        if convention == self.convention {
            self.clone()
        } else {
            ObserverGain {
                matrix: self.matrix.neg(),
                convention,
            }
        }
    }
    /// The observer matrix `A − KC` or `A + LC`.
    ///
    /// # Errors
    /// [`LinalgError`] on mismatched dimensions.
    pub fn observer_matrix(&self, a: &Matrix<T>, c: &Matrix<T>) -> Result<Matrix<T>, LinalgError> {
        let gc = self.matrix.mul(c)?;
        match self.convention {
            Convention::AMinusKC => a.sub(&gc),
            Convention::APlusLC => a.add(&gc),
        }
    }
}
