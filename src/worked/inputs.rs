//! The inputs of one claim under one set of symbol values, read from the claim and its
//! example's `[system]` (the claim's matrices first), and the error a computation reports.

use super::format::{ClaimSpec, ExampleFile};
use super::value::Value;
use crate::algebra::{MultiPoly, Quadratic, Rational, Zero};
use crate::derivation::Derivation;
use crate::linalg::Matrix;
use crate::observer::Family;
use crate::observer::{Convention, DesiredPolynomial, GainMethod, ObserverGain};
use crate::syntax::{
    evaluate_with, parse_expression, parse_matrix_expressions, rational_function_with, Environment,
};
use crate::system::StateSpace;

/// Why a claim could not be recomputed: a field of the file, symbols without values, or the
/// computation's own typed error (its message unchanged).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ComputeError {
    /// A field is missing or malformed.
    #[error("field `{field}`: {message}")]
    Input {
        /// The field (`printed`, `A`, `poles`…).
        field: String,
        /// What is wrong.
        message: String,
    },
    /// The computation needs values for these symbols (the caller may sample them).
    #[error("needs values for {}", .0.join(", "))]
    NeedsValues(Vec<String>),
    /// Matrix arithmetic failed (shapes, a singular matrix).
    #[error(transparent)]
    Linalg(#[from] crate::linalg::LinalgError),
    /// An observer design failed (unobservable pair, …).
    #[error(transparent)]
    Design(#[from] crate::observer::DesignError),
    /// A canonical form does not exist.
    #[error(transparent)]
    CanonicalForm(#[from] crate::canonical_form::CanonicalFormError),
    /// Observer-based control or state feedback failed.
    #[error(transparent)]
    Control(#[from] crate::control::ControlError),
    /// The perfect observer does not exist.
    #[error(transparent)]
    PerfectObserver(#[from] crate::observer::perfect::PerfectObserverError),
    /// The observability test failed.
    #[error(transparent)]
    Observability(#[from] crate::observability::ObservabilityError),
    /// The minimal-dynamical-error design failed.
    #[error(transparent)]
    DynamicalError(#[from] crate::observer::dynamical_error::DynamicalErrorError),
    /// The Kalman filter failed.
    #[error(transparent)]
    Kalman(#[from] crate::observer::kalman::KalmanError),
    /// The robust (orthogonal-eigenvector) design failed.
    #[error(transparent)]
    Robust(#[from] crate::observer::robust::RobustError),
    /// The weighted-measurement design failed.
    #[error(transparent)]
    Weighted(#[from] crate::observer::weighted::WeightedError),
    /// The plant's matrices do not fit together.
    #[error(transparent)]
    System(#[from] crate::system::SystemError),
    /// The computation failed otherwise (said in words).
    #[error("{0}")]
    Failed(String),
}

impl ComputeError {
    /// Whether the computation itself failed (a singular matrix, an unobservable pair…), as
    /// opposed to a malformed field or symbols without values: at sampled symbol values, such a
    /// failure may belong to the point, not to the claim.
    pub fn is_failure(&self) -> bool {
        !matches!(
            self,
            ComputeError::Input { .. } | ComputeError::NeedsValues(_)
        )
    }
}

pub(crate) fn failed(e: impl std::fmt::Display) -> ComputeError {
    ComputeError::Failed(e.to_string())
}

/// A recomputed claim with its working.
pub struct Computed {
    /// The value.
    pub value: Value,
    /// The steps that produced it.
    pub derivation: Derivation,
}

/// The inputs of one claim under one set of symbol values.
pub struct Inputs<'a> {
    /// The example.
    pub file: &'a ExampleFile,
    /// The claim.
    pub claim: &'a ClaimSpec,
    /// Symbol values.
    pub env: &'a Environment,
}

pub(crate) fn input_error(field: &str, message: impl Into<String>) -> ComputeError {
    ComputeError::Input {
        field: field.into(),
        message: message.into(),
    }
}

impl Inputs<'_> {
    fn matrix_text(&self, name: &str) -> Option<&str> {
        match (name, &self.file.noise) {
            ("input_noise", Some(n)) => return Some(&n.input),
            ("output_noise", Some(n)) => return Some(&n.output),
            _ => {}
        }
        match name {
            "A" | "B" | "C" | "D" => {
                let own = [&self.claim.a, &self.claim.b, &self.claim.c];
                // a claim's own D (a formula over a general plant) is one of its matrices
                self.file
                    .system
                    .resolve(own, name)
                    .or_else(|| self.claim.matrices.get(name).map(String::as_str))
            }
            "gain" => self.claim.gain.as_deref(),
            "feedback" => self.claim.feedback.as_deref(),
            "weight" => self.claim.weight.as_deref(),
            other => self.claim.matrices.get(other).map(String::as_str),
        }
    }

    /// A matrix with symbols (those with values substituted).
    pub fn symbolic(&self, name: &str) -> Result<Matrix<MultiPoly>, ComputeError> {
        let text = self
            .matrix_text(name)
            .ok_or_else(|| input_error(name, "missing"))?;
        self.read_matrix(name, text)
    }

    /// `text` read as a matrix with symbols (those with values substituted); errors name `field`.
    pub(crate) fn read_matrix(
        &self,
        field: &str,
        text: &str,
    ) -> Result<Matrix<MultiPoly>, ComputeError> {
        let name = field;
        let rows =
            parse_matrix_expressions(text).map_err(|e| input_error(name, e.show_in(text)))?;
        let values = rows
            .iter()
            .map(|r| {
                r.iter()
                    .map(|e| evaluate_with::<MultiPoly>(e, self.env))
                    .collect::<Result<Vec<_>, _>>()
            })
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| input_error(name, e.show_in(text)))?;
        Matrix::from_rows(values).map_err(|e| input_error(name, e.to_string()))
    }

    /// The plant `(A, B, C, D)` the claim works on, exact and shape-checked (`D = 0` unless
    /// `[system]` gives it with its own `C`).
    pub fn plant(&self) -> Result<StateSpace<Rational>, ComputeError> {
        let d = if self.has("D") {
            Some(self.numeric("D")?)
        } else {
            None
        };
        Ok(StateSpace::new(
            self.numeric("A")?,
            Some(self.numeric("B")?),
            self.numeric("C")?,
            d,
        )?)
    }

    /// A matrix of exact numbers; [`ComputeError::NeedsValues`] when symbols remain.
    pub fn numeric(&self, name: &str) -> Result<Matrix<Rational>, ComputeError> {
        to_numeric(&self.symbolic(name)?)
    }

    pub(crate) fn has(&self, name: &str) -> bool {
        self.matrix_text(name).is_some()
    }

    pub(crate) fn rational(&self, field: &str, text: &str) -> Result<Rational, ComputeError> {
        let e = parse_expression(text).map_err(|e| input_error(field, e.show_in(text)))?;
        let v = evaluate_with::<MultiPoly>(&e, self.env)
            .map_err(|e| input_error(field, e.show_in(text)))?;
        v.as_constant()
            .ok_or_else(|| ComputeError::NeedsValues(v.variables()))
    }

    pub(crate) fn order(&self) -> Result<usize, ComputeError> {
        if self.has("A") {
            Ok(self.symbolic("A")?.rows())
        } else {
            self.claim
                .order
                .ok_or_else(|| input_error("order", "give A or order"))
        }
    }

    pub(crate) fn convention(&self, default: Convention) -> Result<Convention, ComputeError> {
        match &self.claim.convention {
            None => Ok(default),
            Some(c) => Convention::parse(c).ok_or_else(|| {
                input_error("convention", format!("'{c}' is neither a-kc nor a+lc"))
            }),
        }
    }

    pub(crate) fn method(&self) -> Result<GainMethod, ComputeError> {
        match &self.claim.method {
            None => Ok(GainMethod::Ackermann),
            Some(m) => GainMethod::parse(m)
                .ok_or_else(|| input_error("method", format!("unknown method '{m}'"))),
        }
    }

    /// The claim's `gain` as Stoustrup's `L` (A + LC); the claim's convention defaults to it.
    pub(crate) fn observer_gain_a_plus_lc(&self) -> Result<Matrix<Rational>, ComputeError> {
        Ok(ObserverGain {
            matrix: self.numeric("gain")?,
            convention: self.convention(Convention::APlusLC)?,
        }
        .to_convention(Convention::APlusLC)
        .matrix)
    }

    /// The printed variable: `var`, else `λ` when the print uses it, else `s`.
    pub fn var(&self) -> String {
        self.claim.var.clone().unwrap_or_else(|| {
            if self.claim.printed.contains('λ') {
                "λ".into()
            } else {
                "s".into()
            }
        })
    }

    /// The desired observer (or feedback) polynomial.
    pub fn desired(&self) -> Result<DesiredPolynomial, ComputeError> {
        self.desired_of_order(self.order()?)
    }

    /// The desired polynomial of degree `n` (a reduced-order observer's n − p, the observable
    /// part's rank).
    pub fn desired_of_order(&self, n: usize) -> Result<DesiredPolynomial, ComputeError> {
        let c = self.claim;
        let r = if let Some(p) = &c.poles {
            let rows =
                parse_matrix_expressions(p).map_err(|e| input_error("poles", e.show_in(p)))?;
            let poles: Vec<Quadratic> = rows
                .iter()
                .flatten()
                .map(|e| evaluate_with::<Quadratic>(e, self.env))
                .collect::<Result<_, _>>()
                .map_err(|e| symbol_or_input("poles", p, e))?;
            if poles.len() != n {
                return Err(input_error(
                    "poles",
                    format!("{} poles for order {n}", poles.len()),
                ));
            }
            DesiredPolynomial::from_poles(&poles)
        } else if let Some(p) = &c.poly {
            let e = parse_expression(p).map_err(|e| input_error("poly", e.show_in(p)))?;
            let rf = rational_function_with::<Quadratic>(&e, "s", Some(self.env))
                .map_err(|e| symbol_or_input("poly", p, e))?;
            let poly = rf.numerator().clone();
            DesiredPolynomial::from_polynomial(poly, n)
        } else if let Some((family, t)) = c.family() {
            family.polynomial(&self.rational(family.name(), t)?, n)
        } else {
            return Err(input_error(
                "poles",
                format!("give poles, poly or one of {}", Family::known()),
            ));
        };
        r.map_err(|e| input_error("desired polynomial", e.to_string()))
    }
}

/// A symbol without a value in a desired-polynomial field means "sample it"; anything else is an
/// input error.
pub(crate) fn symbol_or_input(
    field: &str,
    text: &str,
    e: crate::syntax::SyntaxError,
) -> ComputeError {
    match e {
        crate::syntax::SyntaxError::UnknownSymbol { name, .. } => {
            ComputeError::NeedsValues(vec![name])
        }
        e => input_error(field, e.show_in(text)),
    }
}

pub(crate) fn to_numeric(m: &Matrix<MultiPoly>) -> Result<Matrix<Rational>, ComputeError> {
    let mut missing: Vec<String> = Vec::new();
    let rows = (0..m.rows())
        .map(|i| {
            m.row(i)
                .iter()
                .map(|x| {
                    x.as_constant().unwrap_or_else(|| {
                        missing.extend(x.variables());
                        Rational::zero()
                    })
                })
                .collect()
        })
        .collect();
    if missing.is_empty() {
        Ok(Matrix::from_rows(rows)?)
    } else {
        missing.sort();
        missing.dedup();
        Err(ComputeError::NeedsValues(missing))
    }
}

pub(crate) fn lift(m: &Matrix<Rational>) -> Matrix<Quadratic> {
    m.map(|x| Quadratic::rational(x.clone()))
}

pub(crate) fn one_step(title: &str, value: &Value) -> Derivation {
    let mut d = Derivation::new(title);
    d.push("value", "", value);
    d
}
