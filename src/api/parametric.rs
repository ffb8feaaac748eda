//! What every command that designs with parameters shares: reading the parameters, running
//! the symbolic computation under the work budget, collecting where the result breaks, and
//! saying so in text and JSON.

use super::Report;
use crate::algebra::{Fraction, Rational};
use crate::linalg::Matrix;
use crate::symbolic::{check_parameters, parameters, within_budget, Exceptions, MAX_ORDER};
use anyhow::{anyhow, bail, Result};
use serde_json::json;

/// A rational matrix as constant rational functions.
pub fn lift(m: &Matrix<Rational>) -> Matrix<Fraction> {
    m.map(|x| Fraction::constant(x.clone()))
}

/// The parameters of a symbolic request and the values where its result breaks.
#[derive(Debug, Clone)]
pub struct Parametric {
    /// The parameters it saw, sorted.
    pub parameters: Vec<String>,
    /// Where the result does not hold.
    pub exceptions: Exceptions,
}

impl Parametric {
    /// Reads the parameters of `a`, `c` and `extra` (a desired polynomial's coefficients),
    /// checks the limits, and records the denominators of the inputs.
    ///
    /// # Errors
    /// A reserved name, too many parameters, a plant beyond [`MAX_ORDER`].
    pub fn new(a: &Matrix<Fraction>, c: &Matrix<Fraction>, extra: &[Fraction]) -> Result<Self> {
        let names = parameters(a.entries().iter().chain(c.entries()).chain(extra));
        check_parameters(&names).map_err(|e| anyhow!("{e}"))?;
        if a.rows() > MAX_ORDER {
            bail!(
                "in --a: {}",
                crate::symbolic::SymbolicError::TooLarge {
                    order: a.rows(),
                    limit: MAX_ORDER
                }
            );
        }
        let mut exceptions = Exceptions::default();
        exceptions.add_denominators(a.entries(), "a denominator of A");
        exceptions.add_denominators(c.entries(), "a denominator of C");
        exceptions.add_denominators(extra, "a denominator of the desired polynomial");
        Ok(Parametric {
            parameters: names,
            exceptions,
        })
    }

    /// Runs `work` under the symbolic work budget.
    ///
    /// # Errors
    /// The budget ran out (the limit named).
    pub fn run<T>(&self, work: impl FnOnce() -> T) -> Result<T> {
        within_budget(work).map_err(|e| anyhow!("{e}"))
    }

    /// Records where `(a, c)` is unobservable: the factors of `det O_n` (one output) or of
    /// the gcd of the maximal minors' worth, `det(O_nᵀ O_n)` (several outputs).
    ///
    /// # Errors
    /// The budget ran out.
    pub fn observability(&mut self, a: &Matrix<Fraction>, c: &Matrix<Fraction>) -> Result<()> {
        let det = self.run(|| observability_determinant(a, c))?;
        if let Some(d) = det {
            self.exceptions
                .add(d.numerator(), "det O_n: the pair is unobservable there");
        }
        Ok(())
    }

    /// Records where `(a, b)` is uncontrollable: the factors of `det C_n` (one input).
    ///
    /// # Errors
    /// The budget ran out.
    pub fn controllability(&mut self, a: &Matrix<Fraction>, b: &Matrix<Fraction>) -> Result<()> {
        let det = self.run(|| observability_determinant(&a.transpose(), &b.transpose()))?;
        if let Some(d) = det {
            self.exceptions
                .add(d.numerator(), "det C_n: the pair is uncontrollable there");
        }
        Ok(())
    }

    /// The parameters, `c, k, m, w`.
    pub fn names(&self) -> String {
        self.parameters.join(", ")
    }

    /// The opening line naming the parameters (a typo shows here).
    pub fn describe(&self, rep: &mut Report) {
        outln!(
            rep,
            "Parameters: {} (the result is a formula in them)",
            self.names()
        );
    }

    /// The lines saying where the result holds and why it breaks elsewhere.
    pub fn validity(&self, rep: &mut Report) {
        if self.exceptions.is_empty() {
            outln!(rep, "  valid for every value of the parameters");
            return;
        }
        outln!(rep, "  valid for {}", self.exceptions.text());
        for e in &self.exceptions.0 {
            outln!(
                rep,
                "    breaks where {} = 0: {}",
                e.factor.replace('*', " "),
                e.reason
            );
        }
    }

    /// Adds `parameters` and `valid_unless` to a JSON answer.
    pub fn add_json(&self, out: &mut serde_json::Value) {
        out["symbolic"] = json!(true);
        out["parameters"] = json!(self.parameters);
        out["valid_unless"] = serde_json::to_value(&self.exceptions).unwrap_or_default();
    }
}

/// `det O_n` for one output, `det(O_nᵀ O_n)` for several (zero exactly where the rank drops,
/// for real parameter values); `None` when the pair is unobservable for every value.
pub fn observability_determinant(a: &Matrix<Fraction>, c: &Matrix<Fraction>) -> Option<Fraction> {
    let o = crate::observability::observability_matrix(a, c).ok()?;
    let square = if o.rows() == o.cols() {
        o
    } else {
        o.transpose().mul(&o).ok()?
    };
    let d = crate::linalg::determinant(&square).ok()?;
    (!num_traits::Zero::is_zero(&d)).then_some(d)
}
