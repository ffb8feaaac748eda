//! Derivations: a result keeps its working as a list of named steps, each value rendered as
//! terminal text, LaTeX (for the book) and input syntax (for `--json` and round trips).

use crate::algebra::Ring;
use crate::algebra::{Field, Rational};
use crate::linalg::Matrix;
use crate::poly::{Factored, Poly, RationalFunction};
use serde::{Deserialize, Serialize};

/// Something a derivation step can show.
pub trait Show {
    /// Terminal text (may span several lines, for matrices).
    fn text(&self) -> String;
    /// LaTeX.
    fn latex(&self) -> String;
    /// The workbench's input syntax.
    fn input(&self) -> String;
    /// `(text, latex, input)` together, for values that can share the work, and — for a
    /// matrix, when the renderings produced them on the way — its entries in input syntax
    /// (row-major): what `--json` lists, so a large matrix shown in a step is converted to
    /// decimal once.
    fn all(&self) -> (String, String, String, Option<Vec<String>>) {
        (self.text(), self.latex(), self.input(), None)
    }
}

impl<T: Ring> Show for Matrix<T> {
    fn text(&self) -> String {
        self.render()
    }
    fn latex(&self) -> String {
        self.to_latex()
    }
    fn input(&self) -> String {
        self.to_input()
    }
    fn all(&self) -> (String, String, String, Option<Vec<String>>) {
        self.renderings_with_cells()
    }
}

impl<T: Ring> Show for Poly<T> {
    fn text(&self) -> String {
        self.render()
    }
    fn latex(&self) -> String {
        self.to_latex()
    }
    fn input(&self) -> String {
        self.to_input()
    }
    fn all(&self) -> (String, String, String, Option<Vec<String>>) {
        let [text, latex, input] = self.renderings();
        (text, latex, input, None)
    }
}

impl<F: Field> Show for RationalFunction<F> {
    fn text(&self) -> String {
        self.to_string()
    }
    fn latex(&self) -> String {
        self.to_latex()
    }
    fn input(&self) -> String {
        self.to_input()
    }
    fn all(&self) -> (String, String, String, Option<Vec<String>>) {
        let [text, latex, input] = self.renderings();
        (text, latex, input, None)
    }
}

impl Show for Factored {
    fn text(&self) -> String {
        self.to_string()
    }
    fn latex(&self) -> String {
        self.to_latex()
    }
    fn input(&self) -> String {
        self.expand().to_input()
    }
}

impl Show for Rational {
    fn text(&self) -> String {
        self.to_string()
    }
    fn latex(&self) -> String {
        Ring::to_latex(self)
    }
    fn input(&self) -> String {
        self.to_input()
    }
}

/// Plain words (a verdict, a remark).
pub struct Words(pub String);

impl Show for Words {
    fn text(&self) -> String {
        self.0.clone()
    }
    fn latex(&self) -> String {
        format!("\\text{{{}}}", self.0.replace('_', "\\_"))
    }
    fn input(&self) -> String {
        self.0.clone()
    }
}

/// One step: a label, the formula it evaluates, and the value.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Step {
    /// Short name, e.g. `"O_n"` or `"K = T_o K_o"`.
    pub label: String,
    /// What is computed, e.g. `"[C; CA]"`.
    pub formula: String,
    /// The value as terminal text.
    pub text: String,
    /// The value in LaTeX.
    pub latex: String,
    /// The value in input syntax.
    pub input: String,
    /// A matrix value's entries in input syntax, row-major, when its rendering produced them
    /// (not serialised: the text above already shows them).
    #[serde(skip)]
    cells: Option<std::sync::Arc<Vec<String>>>,
}

/// Steps are equal when they show the same thing (the kept cells are a by-product of the text).
impl PartialEq for Step {
    fn eq(&self, other: &Self) -> bool {
        (
            &self.label,
            &self.formula,
            &self.text,
            &self.latex,
            &self.input,
        ) == (
            &other.label,
            &other.formula,
            &other.text,
            &other.latex,
            &other.input,
        )
    }
}

impl Step {
    /// A step showing `value`.
    pub fn new(label: &str, formula: &str, value: &dyn Show) -> Self {
        let (text, latex, input, cells) = value.all();
        Step {
            label: label.into(),
            formula: formula.into(),
            text,
            latex,
            input,
            cells: cells.map(std::sync::Arc::new),
        }
    }
    /// A matrix value's entries in input syntax, row-major, when the step kept them.
    pub fn cells(&self) -> Option<&[String]> {
        self.cells.as_deref().map(Vec::as_slice)
    }
    /// The same value under another label and formula: a matrix that two formulas give is
    /// rendered once (a reduced-order observer's F is the observer matrix of its gain design,
    /// and at order 40 rendering it costs more than computing it).
    pub fn renamed(&self, label: &str, formula: &str) -> Step {
        Step {
            label: label.into(),
            formula: formula.into(),
            ..self.clone()
        }
    }
}

/// A titled list of steps.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct Derivation {
    /// What is derived.
    pub title: String,
    /// The steps in order.
    pub steps: Vec<Step>,
}

impl Derivation {
    /// An empty derivation.
    pub fn new(title: &str) -> Self {
        Derivation {
            title: title.into(),
            steps: Vec::new(),
        }
    }
    /// Appends a step.
    pub fn push(&mut self, label: &str, formula: &str, value: &dyn Show) {
        self.steps.push(Step::new(label, formula, value));
    }
    /// Appends a step already rendered (a value shown before under another name).
    pub fn push_step(&mut self, step: Step) {
        self.steps.push(step);
    }
    /// The first step with this label.
    pub fn step(&self, label: &str) -> Option<&Step> {
        self.steps.iter().find(|s| s.label == label)
    }
    /// Appends all steps of another derivation.
    pub fn extend(&mut self, other: Derivation) {
        self.steps.extend(other.steps);
    }
    /// Terminal text: each step as `label = formula`, then its value indented.
    pub fn render(&self) -> String {
        let mut out = format!("{}\n", self.title);
        for s in &self.steps {
            if s.formula.is_empty() {
                out.push_str(&format!("  {}:\n", s.label));
            } else {
                out.push_str(&format!("  {} = {}:\n", s.label, s.formula));
            }
            for line in s.text.lines() {
                out.push_str(&format!("      {line}\n"));
            }
        }
        out
    }
    /// LaTeX: an `align*`-style list, one line per step.
    pub fn to_latex(&self) -> String {
        let lines: Vec<String> = self
            .steps
            .iter()
            .map(|s| format!("{} &= {}", latex_label(&s.label), s.latex))
            .collect();
        format!(
            "\\begin{{aligned}}\n{}\n\\end{{aligned}}",
            lines.join(" \\\\\n")
        )
    }
}

/// A step label in LaTeX: `O_n` stays, words become `\text{…}`.
fn latex_label(label: &str) -> String {
    if label
        .chars()
        .all(|c| c.is_ascii_alphanumeric() || "_^(){}−-+ ".contains(c))
        && !label.contains(' ')
    {
        // A_cl is A with subscript "cl": braces keep the whole subscript down
        match label.replace('−', "-").split_once('_') {
            Some((base, sub)) if sub.chars().count() > 1 && !sub.contains(['{', '_', '^']) => {
                format!("{base}_{{{sub}}}")
            }
            _ => label.replace('−', "-"),
        }
    } else {
        format!("\\text{{{}}}", label.replace('_', "\\_"))
    }
}
