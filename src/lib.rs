//! # observer-workbench
//!
//! Exact design and verification of Luenberger state observers.
//!
//! Layers point one way: [`algebra`] (number types) → [`linalg`] and [`poly`] (matrices,
//! polynomials, rational functions) → [`syntax`] (reading and printing what users type) →
//! [`system`], [`observability`], [`canonical_form`], [`observer`], [`control`] (the control
//! engineering, each step recorded as a [`derivation`]) → [`worked`] and [`exercise`] (the
//! documents' claims and students' answers as data) → [`simulation`] → [`api`] (every command
//! as a function from a request to a report, which every front end calls), and, behind the
//! default `cli` feature, the front ends [`cli`] and [`book`]. Every example below runs as a
//! test.
//!
//! [`algebra`] — exact numbers: rationals, `Q(√d)`, multivariate polynomials.
//! ```
//! use observer_workbench::algebra::{MultiPoly, Quadratic, Rational};
//! let r2 = Quadratic::sqrt_of_rational(&Rational::from_integer(2.into())).unwrap();
//! assert_eq!((r2.clone() * r2).to_string(), "2");
//! let k = MultiPoly::var("k1") + MultiPoly::var("k2");
//! assert_eq!((k.clone() * k).to_string(), "k1^2 + 2 k1 k2 + k2^2");
//! ```
//! [`poly`] — polynomials, their exact roots, Routh–Hurwitz.
//! ```
//! use observer_workbench::algebra::Rational;
//! use observer_workbench::poly::{exact_roots, is_hurwitz};
//! use observer_workbench::syntax::parse_polynomial;
//! let p = parse_polynomial::<Rational>("(s + 4)(s + 5)", "s").unwrap();
//! assert!(is_hurwitz(&p));
//! assert_eq!(exact_roots(&p).render(), "-4, -5");
//! ```
//! [`linalg`] — exact matrices: characteristic polynomials, inverses, ranks.
//! ```
//! use observer_workbench::algebra::Rational;
//! use observer_workbench::linalg::{characteristic_polynomial, inverse};
//! use observer_workbench::syntax::parse_matrix;
//! let a = parse_matrix::<Rational>("[2 -3; 4 -5]").unwrap();
//! assert_eq!(characteristic_polynomial(&a, "s").unwrap().to_string(), "s^2 + 3s + 2");
//! assert_eq!(inverse(&a).unwrap().to_input(), "[-5/2, 3/2; -2, 1]");
//! ```
//! [`syntax`] — MATLAB-style input with exact decimals and readable errors.
//! ```
//! use observer_workbench::algebra::Rational;
//! use observer_workbench::syntax::parse_matrix;
//! assert_eq!(parse_matrix::<Rational>("[0.1 1/3]").unwrap().to_input(), "[1/10, 1/3]");
//! let e = parse_matrix::<Rational>("[1 2; 3]").unwrap_err();
//! assert!(e.to_string().contains("row"), "{e}");
//! ```
//! [`system`] — a state-space plant whose shapes are checked once.
//! ```
//! use observer_workbench::algebra::Rational;
//! use observer_workbench::syntax::parse_matrix;
//! use observer_workbench::system::StateSpace;
//! let m = |s: &str| parse_matrix::<Rational>(s).unwrap();
//! let plant = StateSpace::new(m("[0 1; 0 0]"), Some(m("[0; 1]")), m("[1 0]"), None).unwrap();
//! assert_eq!((plant.order(), plant.inputs(), plant.outputs()), (2, 1, 1));
//! assert!(StateSpace::new(m("[0 1; 0 0]"), None, m("[1 0 0]"), None).is_err());
//! ```
//! [`observability`] — the observability matrix, its rank and the unobservable modes.
//! ```
//! use observer_workbench::algebra::Rational;
//! use observer_workbench::observability::observability_report;
//! use observer_workbench::syntax::parse_matrix;
//! let m = |s: &str| parse_matrix::<Rational>(s).unwrap();
//! let r = observability_report(&m("[1 0; 0 2]"), &m("[1 0]")).unwrap();
//! assert!(!r.observable());
//! assert_eq!(r.unobservable_polynomial.to_string(), "s − 2");
//! ```
//! [`canonical_form`] — the observer canonical form and its transformation.
//! ```
//! use observer_workbench::algebra::Rational;
//! use observer_workbench::canonical_form::observer_form_stoustrup;
//! use observer_workbench::syntax::parse_matrix;
//! let m = |s: &str| parse_matrix::<Rational>(s).unwrap();
//! let f = observer_form_stoustrup(&m("[2 -3; 4 -5]"), None, &m("[-3 2]")).unwrap();
//! assert_eq!(f.c.to_input(), "[1, 0]");
//! ```
//! [`observer`] — observer gains with their derivation, sign convention explicit.
//! ```
//! use observer_workbench::algebra::{Quadratic, Rational};
//! use observer_workbench::observer::{design, Convention, DesiredPolynomial, GainMethod};
//! use observer_workbench::syntax::{parse_list, parse_matrix};
//! let m = |s: &str| parse_matrix::<Rational>(s).unwrap();
//! let desired = DesiredPolynomial::from_poles(&parse_list::<Quadratic>("-4, -5").unwrap()).unwrap();
//! let d = design(&m("[2 -3; 4 -5]"), &m("[-3 2]"), &desired, GainMethod::Ackermann, Convention::APlusLC).unwrap();
//! assert_eq!(d.gain.matrix.to_input(), "[-6; -12]");
//! ```
//! [`control`] — state feedback and observer-based control.
//! ```
//! use observer_workbench::algebra::Rational;
//! use observer_workbench::control::state_feedback;
//! use observer_workbench::syntax::{parse_matrix, parse_polynomial};
//! let m = |s: &str| parse_matrix::<Rational>(s).unwrap();
//! let p = parse_polynomial::<Rational>("s^2 + 2s + 2", "s").unwrap();
//! let f = state_feedback(&m("[0 1; 0 0]"), &m("[0; 1]"), &p).unwrap();
//! assert_eq!(f.to_input(), "[-2, -2]"); // u = F x
//! ```
//! [`feedback`] — state feedback on its own, by duality, `u = F x` or `u = −K x` explicit.
//! ```
//! use observer_workbench::algebra::{Quadratic, Rational};
//! use observer_workbench::feedback::{design_feedback, FeedbackConvention};
//! use observer_workbench::observer::{DesiredPolynomial, Detail, GainMethod};
//! use observer_workbench::syntax::{parse_list, parse_matrix};
//! let m = |s: &str| parse_matrix::<Rational>(s).unwrap();
//! let p = DesiredPolynomial::from_poles(&parse_list::<Quadratic>("-1, -1").unwrap()).unwrap();
//! let d = design_feedback(&m("[0 1; 0 0]"), &m("[0; 1]"), &p, GainMethod::BassGura,
//!     FeedbackConvention::UEqualsMinusKx, Detail::Summary).unwrap();
//! assert_eq!(d.gain.to_input(), "[1, 2]"); // u = −[1 2] x: s² + 2s + 1
//! ```
//! [`derivation`] — the working of a result, rendered as text and LaTeX.
//! ```
//! use observer_workbench::algebra::Rational;
//! use observer_workbench::derivation::Derivation;
//! let mut d = Derivation::new("a step");
//! d.push("x", "1 + 1", &Rational::from_integer(2.into()));
//! assert!(d.render().contains("x = 1 + 1"));
//! ```
//! [`worked`] — a document's printed claims, recomputed.
//! ```
//! use observer_workbench::worked::{parse_example, Computation};
//! let raw = std::fs::read_to_string("worked_examples/stoustrup-pole-assignment.toml").unwrap();
//! let ex = parse_example("stoustrup-pole-assignment.toml", &raw).unwrap();
//! assert!(ex.claims.iter().any(|c| c.what == Computation::Gain));
//! ```
//! [`exercise`] — a student's answers checked, mistakes named.
//! ```
//! use observer_workbench::exercise::{answer_key, check_answers, format::{parse_answers, parse_exercise}};
//! use std::path::Path;
//! let raw = std::fs::read_to_string("worked_examples/exercises/stoustrup-pole-assignment.toml").unwrap();
//! let key = answer_key("ex", &parse_exercise(Path::new("ex.toml"), &raw).unwrap()).unwrap();
//! let answers = parse_answers(Path::new("a.toml"), "[answers]\nL = \"[6; 12]\"").unwrap();
//! let report = check_answers(&key, &answers, "Ada");
//! assert!(report.text().contains("sign convention"), "{}", report.text());
//! ```
//! [`simulation`] — the observer loop in time (RK4, Dormand–Prince, discrete).
//! ```
//! use nalgebra::DMatrix;
//! use observer_workbench::simulation::{simulate, Integrator, Loop, Setup, Signal};
//! let l = Loop { a: DMatrix::from_element(1, 1, -1.0), b: DMatrix::from_element(1, 1, 1.0),
//!     c: DMatrix::from_element(1, 1, 1.0), d: DMatrix::zeros(1, 1),
//!     gain: DMatrix::from_element(1, 1, 4.0), feedback: None };
//! let s = Setup { horizon: 2.0, step: 0.01, integrator: Integrator::Rk4, input: vec![Signal::Zero],
//!     output_noise: None, process_noise: None, x0: vec![1.0], xhat0: vec![0.0] };
//! let t = simulate(&l, &s).unwrap();
//! let end = t.x.len() - 1;
//! assert!((t.x[end][0] - t.xhat[end][0]).abs() < 1e-4); // the error decays like e^(−5t)
//! ```
//! [`fuzzing`] — the entry points the fuzz campaigns drive: any bytes, no panic.
//! ```
//! observer_workbench::fuzzing::syntax(b"[((1)^1000)^1000");
//! observer_workbench::fuzzing::answers(b"\xff\xfe not toml");
//! ```
//! [`api`] — every command as a library function: a request (from JSON, or a command line's
//! words) in, a report out; what the command line, the book and the browser call.
//! ```
//! use observer_workbench::api::{run, Command};
//! let request = Command::from_json(r#"{"command": "observe", "a": "[1 0; 0 2]", "c": "[1 0]"}"#).unwrap();
//! let report = run(request).unwrap();
//! assert!(report.text.contains("unobservable eigenvalues: 2"), "{}", report.text);
//! ```
//! [`cli`] — the `owb` command line: its arguments parsed into an [`api::Command`], the report
//! printed.
//! [`book`] — the mdBook preprocessor that renders the course from the code.
//! ```
//! let input = r#"[{"root": "book"}, {"items": [{"Chapter": {"name": "x", "content": "no directive", "sub_items": []}}]}]"#;
//! let out = observer_workbench::book::preprocess_with(input, None, false).unwrap();
//! assert!(out.contains("no directive"));
//! ```
#![warn(missing_docs)]

pub mod names;

pub mod algebra;
pub mod api;
#[cfg(feature = "cli")]
pub mod book;
pub mod canonical_form;
#[cfg(feature = "commands")]
pub mod cli;
pub mod control;
pub mod derivation;
pub mod exercise;
pub mod feedback;
pub mod files;
pub mod fuzzing;
pub mod linalg;
pub mod observability;
pub mod observer;
pub mod poly;
pub mod simulation;
pub mod symbolic;
pub mod syntax;
pub mod system;
pub mod worked;
