//! What every command that designs with parameters shares: reading the parameters, running
//! the symbolic computation under the work budget, collecting where the result breaks, and
//! saying so in text and JSON.

use super::Report;
use crate::algebra::MultiPoly;
use crate::algebra::{Fraction, Rational};
use crate::linalg::Matrix;
use crate::symbolic::{
    check_parameters, parameters, within_budget_left, Exceptions, MAX_ORDER, WORK_BUDGET,
};
use anyhow::{anyhow, bail, Result};
use serde_json::json;
use std::cell::Cell;

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
    /// What is left of the command's symbolic work budget: every step of the command
    /// ([`Parametric::run`], [`Parametric::note`]) spends from it, so a command spends at most
    /// [`WORK_BUDGET`] in all (found by fuzzing: factoring `det O_n` ran outside any budget).
    left: Cell<u64>,
}

impl Parametric {
    /// Reads the parameters of the plant's `A`, checks the order, and records its
    /// denominators; the other inputs come in with [`Parametric::with`].
    ///
    /// # Errors
    /// A reserved name, too many parameters, a plant beyond [`MAX_ORDER`].
    pub fn new(a: &Matrix<Fraction>) -> Result<Self> {
        if a.rows() > MAX_ORDER {
            bail!(
                "in --a: {}",
                crate::symbolic::SymbolicError::TooLarge {
                    order: a.rows(),
                    limit: MAX_ORDER
                }
            );
        }
        Parametric {
            parameters: Vec::new(),
            exceptions: Exceptions::default(),
            left: Cell::new(WORK_BUDGET),
        }
        .with(a.entries(), "A")
    }

    /// Adds the parameters of `values` (checked against the limits) and records their
    /// denominators as "a denominator of `what`".
    ///
    /// # Errors
    /// A reserved name or too many parameters.
    pub fn with(mut self, values: &[Fraction], what: &str) -> Result<Self> {
        let mut names = parameters(values);
        names.extend(std::mem::take(&mut self.parameters));
        names.sort();
        names.dedup();
        check_parameters(&names).map_err(|e| anyhow!("{e}"))?;
        self.parameters = names;
        self.note_denominators(values, &format!("a denominator of {what}"))?;
        Ok(self)
    }

    /// Records the factors of `p` as where the result breaks, for `reason`, under the
    /// command's budget.
    ///
    /// # Errors
    /// The budget ran out.
    pub fn note(&mut self, p: &MultiPoly, reason: &str) -> Result<()> {
        let exceptions = &mut self.exceptions;
        within_budget_left(&self.left, || exceptions.add(p, reason)).map_err(|e| anyhow!("{e}"))
    }

    /// Records the factors of the denominators of `values`, for `reason`, under the command's
    /// budget.
    ///
    /// # Errors
    /// The budget ran out.
    pub fn note_denominators<'a>(
        &mut self,
        values: impl IntoIterator<Item = &'a Fraction>,
        reason: &str,
    ) -> Result<()> {
        let exceptions = &mut self.exceptions;
        within_budget_left(&self.left, || exceptions.add_denominators(values, reason))
            .map_err(|e| anyhow!("{e}"))
    }

    /// Answers in JSON (`json` given: the parameters and where the result breaks added) or in
    /// text: the parameters, what `text` writes, and where the result holds.
    pub fn answer(
        &self,
        rep: &mut Report,
        json: Option<serde_json::Value>,
        text: impl FnOnce(&mut Report),
    ) {
        if let Some(mut out) = json {
            self.add_json(&mut out);
            rep.json(out);
        } else {
            self.describe(rep);
            text(rep);
            self.validity(rep);
        }
    }

    /// Runs `work` under what is left of the command's symbolic work budget.
    ///
    /// # Errors
    /// The budget ran out (the limit named).
    pub fn run<T>(&self, work: impl FnOnce() -> T) -> Result<T> {
        within_budget_left(&self.left, work).map_err(|e| anyhow!("{e}"))
    }

    /// Records where `(a, c)` is unobservable: the factors of `det O_n` (one output) or of
    /// the gcd of the maximal minors' worth, `det(O_nᵀ O_n)` (several outputs).
    ///
    /// # Errors
    /// The budget ran out.
    pub fn observability(&mut self, a: &Matrix<Fraction>, c: &Matrix<Fraction>) -> Result<()> {
        let det = self.run(|| observability_determinant(a, c))?;
        if let Some(d) = det {
            self.note(d.numerator(), "det O_n: the pair is unobservable there")?;
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
            self.note(d.numerator(), "det C_n: the pair is uncontrollable there")?;
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

    /// The lines saying where the result holds and why it breaks elsewhere; the condition is
    /// also kept as a derivation step, so the typeset derivation ends with it.
    pub fn validity(&self, rep: &mut Report) {
        rep.push_step(crate::derivation::Step::new(
            "valid for",
            "where no denominator divided by vanishes",
            &self.exceptions,
        ));
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
