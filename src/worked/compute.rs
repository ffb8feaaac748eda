//! Recomputing a claim: the computations a worked example can ask for (`what = …`).

use super::format::{ClaimSpec, ExampleFile};
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
use crate::observer::search::Multistart;
use crate::observer::{
    canonical_gain, design, Convention, DesiredPolynomial, GainMethod, ObserverGain,
};
use crate::poly::exact_roots;
use crate::syntax::{
    evaluate_with, parse_expression, parse_matrix_expressions, rational_function_with, Environment,
};

/// The computations a claim may name.
pub const COMPUTATIONS: &[&str] = &[
    "observability_matrix",
    "observability_matrix_inverse",
    "observability_determinant",
    "observable",
    "characteristic_polynomial",
    "eigenvalues",
    "canonical_transformation",
    "canonical_transformation_inverse",
    "canonical_a",
    "canonical_b",
    "canonical_c",
    "desired_polynomial",
    "canonical_gain",
    "gain",
    "state_feedback",
    "closed_loop_poles",
    "closed_loop_polynomial",
    "controller_transfer_function",
    "closed_loop_transfer_function",
    "observer_characteristic_polynomial",
    "gain_equations",
    "pole_placement_constraints",
    "perfect_observer_e",
    "perfect_observer_f",
    "perfect_observer_input_matrix",
    "perfect_observer_output_matrix",
    "perfect_observer_determinant",
    "identity",
    "minimum_norm_gain",
    "minimum_norm_cost",
    "dynamical_error_cost",
    "minimal_dynamical_error_cost",
    "kalman_bandwidth",
    "natural_frequency",
    "estimation_error_rms",
    "perfect_observer_robustness",
    "perfect_observer_fits",
];

/// The identities a claim with `what = "identity"` may name.
pub const IDENTITIES: &[&str] = &[
    "toeplitz_is_inverse_canonical_observability",
    "toeplitz_is_inverse_canonical_controllability",
    "markov_parameters_agree",
    "gain_methods_agree",
    "lemma_3_1_gives_c_minus_a",
    "canonical_procedures_agree",
    "separation_principle",
];

/// Why a claim could not be recomputed.
#[derive(Debug, Clone, PartialEq)]
pub enum ComputeError {
    /// A field is missing or malformed.
    Input {
        /// The field (`printed`, `A`, `poles`…).
        field: String,
        /// What is wrong.
        message: String,
    },
    /// The computation needs values for these symbols (the caller may sample them).
    NeedsValues(Vec<String>),
    /// The computation itself failed (unobservable pair, singular matrix…).
    Failed(String),
}

impl std::fmt::Display for ComputeError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ComputeError::Input { field, message } => write!(f, "field `{field}`: {message}"),
            ComputeError::NeedsValues(s) => write!(f, "needs values for {}", s.join(", ")),
            ComputeError::Failed(m) => f.write_str(m),
        }
    }
}

pub(super) fn failed(e: impl std::fmt::Display) -> ComputeError {
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

pub(super) fn input_error(field: &str, message: impl Into<String>) -> ComputeError {
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
        let (claim, system) = match name {
            "A" => (&self.claim.a, &self.file.system.a),
            "B" => (&self.claim.b, &self.file.system.b),
            "C" => (&self.claim.c, &self.file.system.c),
            "D" => (&None, &self.file.system.d),
            "gain" => (&self.claim.gain, &None),
            "feedback" => (&self.claim.feedback, &None),
            "weight" => (&self.claim.weight, &None),
            _ => (&None, &None),
        };
        claim.as_deref().or(system.as_deref())
    }

    /// A matrix with symbols (those with values substituted).
    pub fn symbolic(&self, name: &str) -> Result<Matrix<MultiPoly>, ComputeError> {
        let text = self
            .matrix_text(name)
            .ok_or_else(|| input_error(name, "missing"))?;
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

    /// A matrix of exact numbers; [`ComputeError::NeedsValues`] when symbols remain.
    pub fn numeric(&self, name: &str) -> Result<Matrix<Rational>, ComputeError> {
        to_numeric(&self.symbolic(name)?)
    }

    pub(super) fn has(&self, name: &str) -> bool {
        self.matrix_text(name).is_some()
    }

    fn rational(&self, field: &str, text: &str) -> Result<Rational, ComputeError> {
        let e = parse_expression(text).map_err(|e| input_error(field, e.show_in(text)))?;
        let v = evaluate_with::<MultiPoly>(&e, self.env)
            .map_err(|e| input_error(field, e.show_in(text)))?;
        v.as_constant()
            .ok_or_else(|| ComputeError::NeedsValues(v.variables()))
    }

    fn order(&self) -> Result<usize, ComputeError> {
        if self.has("A") {
            Ok(self.symbolic("A")?.rows())
        } else {
            self.claim
                .order
                .ok_or_else(|| input_error("order", "give A or order"))
        }
    }

    fn convention(&self, default: Convention) -> Result<Convention, ComputeError> {
        match &self.claim.convention {
            None => Ok(default),
            Some(c) => Convention::parse(c).ok_or_else(|| {
                input_error("convention", format!("'{c}' is neither a-kc nor a+lc"))
            }),
        }
    }

    fn method(&self) -> Result<GainMethod, ComputeError> {
        match &self.claim.method {
            None => Ok(GainMethod::Ackermann),
            Some(m) => GainMethod::parse(m)
                .ok_or_else(|| input_error("method", format!("unknown method '{m}'"))),
        }
    }

    /// The claim's `gain` as Stoustrup's `L` (A + LC); the claim's convention defaults to it.
    fn observer_gain_a_plus_lc(&self) -> Result<Matrix<Rational>, ComputeError> {
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
        let n = self.order()?;
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
        } else if let Some(t) = &c.repeated {
            DesiredPolynomial::repeated(&self.rational("repeated", t)?, n)
        } else if let Some(t) = &c.butterworth {
            DesiredPolynomial::butterworth(&self.rational("butterworth", t)?, n)
        } else if let Some(t) = &c.bessel {
            DesiredPolynomial::bessel(&self.rational("bessel", t)?, n)
        } else {
            return Err(input_error(
                "poles",
                "give poles, poly, repeated, butterworth or bessel",
            ));
        };
        r.map_err(|e| input_error("desired polynomial", e.to_string()))
    }
}

/// A symbol without a value in a desired-polynomial field means "sample it"; anything else is an
/// input error.
fn symbol_or_input(field: &str, text: &str, e: crate::syntax::SyntaxError) -> ComputeError {
    if let crate::syntax::SyntaxError::NotAllowed { what, .. } = &e {
        if let Some(name) = what
            .strip_prefix("the symbol '")
            .and_then(|s| s.strip_suffix('\''))
        {
            return ComputeError::NeedsValues(vec![name.to_string()]);
        }
    }
    input_error(field, e.show_in(text))
}

fn to_numeric(m: &Matrix<MultiPoly>) -> Result<Matrix<Rational>, ComputeError> {
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
        Matrix::from_rows(rows).map_err(failed)
    } else {
        missing.sort();
        missing.dedup();
        Err(ComputeError::NeedsValues(missing))
    }
}

fn lift(m: &Matrix<Rational>) -> Matrix<Quadratic> {
    m.map(|x| Quadratic::rational(x.clone()))
}

fn one_step(title: &str, value: &Value) -> Derivation {
    let mut d = Derivation::new(title);
    d.push("value", "", value);
    d
}

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
    r.map_err(failed)
}

/// Recomputes one claim.
///
/// # Errors
/// [`ComputeError`]; `NeedsValues` asks the caller to supply (sample) symbol values.
pub fn compute(inputs: &Inputs) -> Result<Computed, ComputeError> {
    let what = inputs.claim.what.as_str();
    let var = inputs.var();
    let title = format!("{} ({})", inputs.claim.id, what);
    let simple = |value: Value| {
        Ok(Computed {
            derivation: one_step(&title, &value),
            value,
        })
    };
    match what {
        "observability_matrix" => {
            let o = observability_matrix(&inputs.symbolic("A")?, &inputs.symbolic("C")?)
                .map_err(failed)?;
            simple(Value::SymbolicMatrix(o))
        }
        "observability_matrix_inverse" => {
            let o = observability_matrix(&inputs.numeric("A")?, &inputs.numeric("C")?)
                .map_err(failed)?;
            simple(Value::Matrix(lift(&linalg::inverse(&o).map_err(failed)?)))
        }
        "observability_determinant" => {
            let o = observability_matrix(&inputs.symbolic("A")?, &inputs.symbolic("C")?)
                .map_err(failed)?;
            simple(Value::Symbolic(determinant_in_domain(&o).map_err(failed)?))
        }
        "observable" => {
            let a = inputs.numeric("A")?;
            let r = crate::observability::observability_report(&a, &inputs.numeric("C")?)
                .map_err(failed)?;
            let mut d = Derivation::new(&title);
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
        "characteristic_polynomial" => {
            let a = inputs.symbolic("A")?;
            let p = symbolic_charpoly(&a, &var)?;
            simple(Value::SymbolicPolynomial(p, var))
        }
        "eigenvalues" => {
            let p =
                linalg::characteristic_polynomial(&inputs.numeric("A")?, "s").map_err(failed)?;
            let r = exact_roots(&p);
            if !r.complete() {
                return Err(failed(format!(
                    "the eigenvalues are not all rational or quadratic: {}",
                    r.render()
                )));
            }
            let roots = r
                .roots
                .iter()
                .flat_map(|(x, m)| std::iter::repeat_n(x.clone(), *m as usize))
                .collect();
            let mut d = Derivation::new(&title);
            d.push("det(sI − A)", "", &p);
            let v = Value::Roots(roots);
            d.push("eigenvalues", "", &v);
            Ok(Computed {
                value: v,
                derivation: d,
            })
        }
        "canonical_transformation"
        | "canonical_transformation_inverse"
        | "canonical_a"
        | "canonical_b"
        | "canonical_c" => {
            let f = canonical(inputs)?;
            let m = match what {
                "canonical_transformation" => &f.t,
                "canonical_transformation_inverse" => &f.t_inv,
                "canonical_a" => &f.a,
                "canonical_b" => &f.b,
                _ => &f.c,
            };
            let mut d = Derivation::new(&title);
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
        "desired_polynomial" => {
            let d = inputs.desired()?;
            let p = d
                .exact
                .clone()
                .ok_or_else(|| failed(d.inexact_reason.clone().unwrap_or_default()))?;
            simple(Value::Polynomial(p.with_var(&var)))
        }
        "canonical_gain" => {
            let desired = inputs.desired()?;
            let p = desired.rational().ok_or_else(|| {
                failed("the canonical gain claim needs a rational desired polynomial")
            })?;
            let k_o = canonical_gain(&inputs.numeric("A")?, &inputs.numeric("C")?, &p)
                .map_err(failed)?
                .canonical;
            let g = ObserverGain {
                matrix: lift(&k_o),
                convention: Convention::AMinusKC,
            }
            .to_convention(inputs.convention(Convention::AMinusKC)?);
            simple(Value::Matrix(g.matrix))
        }
        "gain" => {
            let desired = inputs.desired()?;
            let d = design(
                &inputs.numeric("A")?,
                &inputs.numeric("C")?,
                &desired,
                inputs.method()?,
                inputs.convention(Convention::AMinusKC)?,
            )
            .map_err(failed)?;
            Ok(Computed {
                value: Value::Matrix(d.gain.matrix.clone()),
                derivation: d.derivation,
            })
        }
        "state_feedback" => {
            let p = inputs
                .desired()?
                .rational()
                .ok_or_else(|| failed("state feedback needs a rational desired polynomial"))?;
            let f =
                state_feedback(&inputs.numeric("A")?, &inputs.numeric("B")?, &p).map_err(failed)?;
            simple(Value::Matrix(lift(&f)))
        }
        "closed_loop_poles"
        | "closed_loop_polynomial"
        | "controller_transfer_function"
        | "closed_loop_transfer_function" => {
            let l = inputs.observer_gain_a_plus_lc()?;
            let r = observer_based_control(
                &inputs.numeric("A")?,
                &inputs.numeric("B")?,
                &inputs.numeric("C")?,
                &inputs.numeric("feedback")?,
                &l,
            )
            .map_err(failed)?;
            let value = match what {
                "closed_loop_poles" => {
                    let roots = exact_roots(&r.closed_loop_polynomial);
                    Value::Roots(
                        roots
                            .roots
                            .iter()
                            .flat_map(|(x, m)| std::iter::repeat_n(x.clone(), *m as usize))
                            .collect(),
                    )
                }
                "closed_loop_polynomial" => Value::Polynomial(
                    r.closed_loop_polynomial
                        .map(|x| Quadratic::rational(x.clone()))
                        .with_var(&var),
                ),
                "controller_transfer_function" => Value::Transfer(r.controller.clone()),
                _ => Value::Transfer(r.closed_loop.clone()),
            };
            Ok(Computed {
                value,
                derivation: r.derivation,
            })
        }
        "observer_characteristic_polynomial" => {
            let a = inputs.symbolic("A")?;
            let c = inputs.symbolic("C")?;
            let g = inputs.symbolic("gain")?;
            let gc = g.mul(&c).map_err(failed)?;
            let obs = match inputs.convention(Convention::AMinusKC)? {
                Convention::AMinusKC => a.sub(&gc),
                Convention::APlusLC => a.add(&gc),
            }
            .map_err(failed)?;
            let p = symbolic_charpoly(&obs, &var)?;
            let mut d = Derivation::new(&title);
            d.push(
                "observer matrix",
                &inputs.convention(Convention::AMinusKC)?.to_string(),
                &obs,
            );
            let v = Value::SymbolicPolynomial(p, var);
            d.push("characteristic polynomial", "det(λI − observer matrix)", &v);
            Ok(Computed {
                value: v,
                derivation: d,
            })
        }
        "gain_equations" | "pole_placement_constraints" => constraints(inputs, &title),
        "perfect_observer_e"
        | "perfect_observer_f"
        | "perfect_observer_input_matrix"
        | "perfect_observer_output_matrix"
        | "perfect_observer_determinant" => {
            let d = if inputs.has("D") {
                Some(inputs.numeric("D")?)
            } else {
                None
            };
            let p = perfect_observer(
                &inputs.numeric("A")?,
                &inputs.numeric("B")?,
                &inputs.numeric("C")?,
                d.as_ref(),
            )
            .map_err(failed)?;
            let value = match what {
                "perfect_observer_e" => Value::Matrix(lift(&p.e)),
                "perfect_observer_f" => Value::Matrix(lift(&p.f)),
                "perfect_observer_input_matrix" => Value::Matrix(lift(&p.input_matrix)),
                "perfect_observer_output_matrix" => Value::Matrix(lift(&p.output_matrix)),
                _ => Value::Polynomial(
                    p.pencil_determinant
                        .map(|x| Quadratic::rational(x.clone()))
                        .with_var(&var),
                ),
            };
            Ok(Computed {
                value,
                derivation: p.derivation,
            })
        }
        "identity" => identity(inputs, &title),
        "minimum_norm_gain" | "minimum_norm_cost" => minimum_norm(inputs, &title),
        "dynamical_error_cost" | "minimal_dynamical_error_cost" => {
            super::compute_optimal::dynamical_error(inputs, &title)
        }
        "kalman_bandwidth" | "natural_frequency" | "estimation_error_rms" => {
            super::compute_optimal::noise(inputs, &title)
        }
        "perfect_observer_robustness" | "perfect_observer_fits" => {
            super::compute_optimal::perfect_robustness(inputs, &title)
        }
        other => Err(input_error(
            "what",
            format!(
                "unknown computation '{other}'; known: {}",
                COMPUTATIONS.join(", ")
            ),
        )),
    }
}

/// Seeded starts of the minimum-norm search (documented in the report).
pub(super) const OPTIMISER_STARTS: usize = 60;
pub(super) const OPTIMISER_SEED: u64 = 2024;

fn minimum_norm(inputs: &Inputs, title: &str) -> Result<Computed, ComputeError> {
    use crate::observer::optimal::{minimum_norm_gain, pole_placement_constraints};
    let a = inputs.numeric("A")?;
    let c = inputs.numeric("C")?;
    let desired = inputs
        .desired()?
        .rational()
        .ok_or_else(|| failed("the optimal design needs a rational desired polynomial"))?;
    let cons = pole_placement_constraints(&a, &c, &desired).map_err(failed)?;
    let r = minimum_norm_gain(&cons, Multistart::new(OPTIMISER_STARTS, OPTIMISER_SEED));
    let best: Vec<_> = r.minima.iter().take(r.best_count).collect();
    if best.is_empty() {
        return Err(failed("no start converged to a minimum"));
    }
    let (n, p) = (a.rows(), c.rows());
    let note = format!(
        "J1 minimised by Newton on the KKT system with exact constraint derivatives from {} seeded starts: {} converged; {} equally good minimiser(s), reached by {} start(s); {} other local minima",
        r.starts,
        r.converged,
        best.len(),
        best.iter().map(|m| m.starts.to_string()).collect::<Vec<_>>().join(" + "),
        r.minima.len() - best.len()
    );
    let mut d = Derivation::new(title);
    d.push(
        "constraints",
        "coefficients of det(λI − (A − GC)) = desired",
        &Value::Equations(cons.equations.clone()),
    );
    let value = if inputs.claim.what == "minimum_norm_gain" {
        Value::Approximate {
            rows: n,
            cols: p,
            candidates: best
                .iter()
                .map(|m| (0..n * p).map(|k| m.gain[(k % p) * n + k / p]).collect())
                .collect(),
            note,
        }
    } else {
        Value::Approximate {
            rows: 1,
            cols: 1,
            candidates: vec![vec![best[0].cost]],
            note,
        }
    };
    d.push("minimisers", "", &value);
    Ok(Computed {
        value,
        derivation: d,
    })
}

/// `det(var·I − M)` over the symbolic ring, as a polynomial containing `var`.
fn symbolic_charpoly(m: &Matrix<MultiPoly>, var: &str) -> Result<MultiPoly, ComputeError> {
    let p = linalg::berkowitz(m, var).map_err(failed)?;
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
    let obs = a.sub(&g.mul(&c).map_err(failed)?).map_err(failed)?;
    let p = linalg::berkowitz(&obs, "λ").map_err(failed)?;
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
    if inputs.claim.what == "pole_placement_constraints" {
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
        .as_deref()
        .ok_or_else(|| input_error("identity", "missing"))?;
    let a = inputs.numeric("A")?;
    let mut d = Derivation::new(title);
    let holds = match name {
        "toeplitz_is_inverse_canonical_observability" => {
            let c = inputs.numeric("C")?;
            let f = observer_form_di_ruscio(&a, None, &c).map_err(failed)?;
            let o_o = observability_matrix(&f.a, &f.c).map_err(failed)?;
            d.push("M", "", &f.toeplitz);
            d.push("O_n^o", "observability matrix of (A_o, C_o)", &o_o);
            f.toeplitz.transpose().mul(&o_o).map_err(failed)? == Matrix::identity(a.rows())
        }
        "toeplitz_is_inverse_canonical_controllability" => {
            let b = inputs.numeric("B")?;
            let f = controller_form(&a, &b, None).map_err(failed)?;
            let c_c = controllability_matrix(&f.a, &f.b).map_err(failed)?;
            d.push("M", "", &f.toeplitz);
            d.push("C_n^c", "controllability matrix of (A_c, B_c)", &c_c);
            f.toeplitz.mul(&c_c).map_err(failed)? == Matrix::identity(a.rows())
        }
        "markov_parameters_agree" => {
            let b = inputs.numeric("B")?;
            let c = inputs.numeric("C")?;
            let o = observer_form_di_ruscio(&a, Some(&b), &c).map_err(failed)?;
            let k = controller_form(&a, &b, Some(&c)).map_err(failed)?;
            let markov = |a: &Matrix<Rational>,
                          b: &Matrix<Rational>,
                          c: &Matrix<Rational>|
             -> Result<Vec<Matrix<Rational>>, ComputeError> {
                (0..=a.rows())
                    .map(|i| {
                        c.mul(&a.pow(i as u32).map_err(failed)?)
                            .map_err(failed)?
                            .mul(b)
                            .map_err(failed)
                    })
                    .collect()
            };
            let h = markov(&a, &b, &c)?;
            let row = Matrix::row_vector(h.iter().map(|m| m.get(0, 0).clone()).collect());
            d.push("C A^(i−1) B", "i = 1 … n + 1", &row);
            h == markov(&o.a, &o.b, &o.c)? && h == markov(&k.a, &k.b, &k.c)?
        }
        "gain_methods_agree" | "lemma_3_1_gives_c_minus_a" => {
            let c = inputs.numeric("C")?;
            let desired = inputs.desired()?;
            let gains: Vec<Matrix<Quadratic>> = GainMethod::ALL
                .iter()
                .map(|m| {
                    design(&a, &c, &desired, *m, Convention::AMinusKC)
                        .map(|d| d.gain.matrix)
                        .map_err(failed)
                })
                .collect::<Result<_, _>>()?;
            for (m, g) in GainMethod::ALL.iter().zip(&gains) {
                d.push(&format!("K by {m}"), "", g);
            }
            if name == "gain_methods_agree" {
                gains.windows(2).all(|w| w[0] == w[1])
            } else {
                let p = desired
                    .rational()
                    .ok_or_else(|| failed("needs a rational desired polynomial"))?;
                let (_, k_tilde) = crate::observer::lemma_3_1_gain(&a, &c, &p).map_err(failed)?;
                let k_o = canonical_gain(&a, &c, &p).map_err(failed)?.canonical;
                let n = a.rows();
                d.push("K̃_o", "C P(A) O_n⁻¹", &k_tilde);
                d.push("c − a", "", &k_o);
                (0..n).all(|i| k_tilde.get(0, n - 1 - i) == k_o.get(i, 0))
            }
        }
        "canonical_procedures_agree" => {
            let c = inputs.numeric("C")?;
            let x = observer_form_di_ruscio(&a, None, &c).map_err(failed)?;
            let y = observer_form_stoustrup(&a, None, &c).map_err(failed)?;
            d.push("T_o (Di Ruscio)", "(Mᵀ O_n)⁻¹", &x.t);
            d.push("T (Stoustrup)", "[t_1 … t_n]", &y.t);
            x.t == y.t
        }
        "separation_principle" => {
            let l = inputs.observer_gain_a_plus_lc()?;
            let r = observer_based_control(
                &a,
                &inputs.numeric("B")?,
                &inputs.numeric("C")?,
                &inputs.numeric("feedback")?,
                &l,
            )
            .map_err(failed)?;
            d.extend(r.derivation);
            r.separation_holds
        }
        other => {
            return Err(input_error(
                "identity",
                format!(
                    "unknown identity '{other}'; known: {}",
                    IDENTITIES.join(", ")
                ),
            ))
        }
    };
    let v = Value::Bool(holds);
    d.push("holds", "", &v);
    Ok(Computed {
        value: v,
        derivation: d,
    })
}
