//! The worked-example file format (TOML), documented for teachers in
//! `worked_examples/README.md`.

use crate::names::named_enum;
use serde::Deserialize;
use std::collections::BTreeMap;

/// One worked example: a system, and what a document printed about it.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExampleFile {
    /// Stable identifier (`stoustrup-pole-assignment`).
    pub id: String,
    /// Human title.
    pub title: String,
    /// The source document's file name in `shared/seeds/`.
    pub document: String,
    /// A short description in our own words.
    #[serde(default)]
    pub summary: String,
    /// Exact values for symbols (`T = "0.125"`); symbols without a value stay symbolic.
    #[serde(default)]
    pub parameters: BTreeMap<String, String>,
    /// The state-space matrices (input syntax; may contain symbols).
    #[serde(default)]
    pub system: SystemSpec,
    /// What the document printed, each to be recomputed.
    #[serde(default)]
    pub claims: Vec<ClaimSpec>,
    /// White-noise intensities for the noise computations (Kalman filter, error covariance).
    pub noise: Option<IntensitySpec>,
    /// Simulation scenarios reproducing the document's figures.
    #[serde(default)]
    pub scenarios: Vec<ScenarioSpec>,
    /// Printed values recorded now and verified by a later part of the workbench.
    #[serde(default)]
    pub printed_only: Vec<PrintedRecord>,
}

/// Matrices of a state-space model, as text.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SystemSpec {
    /// System matrix.
    #[serde(rename = "A")]
    pub a: Option<String>,
    /// Input matrix.
    #[serde(rename = "B")]
    pub b: Option<String>,
    /// Output matrix.
    #[serde(rename = "C")]
    pub c: Option<String>,
    /// Feedthrough matrix.
    #[serde(rename = "D")]
    pub d: Option<String>,
}

impl SystemSpec {
    /// The text of `A`, `B`, `C` or `D` for a claim or scenario whose own `A`, `B`, `C` are
    /// `own` (written over these): its own matrix first, else this system's; `D` only with this
    /// system's own `C` (a `C` of other outputs has no feedthrough here, so `D = 0`).
    pub fn resolve<'a>(&'a self, own: [&'a Option<String>; 3], name: &str) -> Option<&'a str> {
        let [a, b, c] = own;
        let pick =
            |own: &'a Option<String>, sys: &'a Option<String>| own.as_deref().or(sys.as_deref());
        match name {
            "A" => pick(a, &self.a),
            "B" => pick(b, &self.b),
            "C" => pick(c, &self.c),
            "D" if c.is_none() => self.d.as_deref(),
            _ => None,
        }
    }
}

/// White-noise intensities: on the measured input (`C_U`) and on the outputs (`C_Y`).
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IntensitySpec {
    /// `C_U`, m×m.
    pub input: String,
    /// `C_Y`, p×p.
    pub output: String,
}

impl ClaimSpec {
    /// The desired-polynomial family set by a time constant, if the claim gives one
    /// (`repeated = "T"`, `butterworth = "T"` …), with its value.
    pub fn family(&self) -> Option<(crate::observer::Family, &String)> {
        crate::observer::Family::given([
            self.repeated.as_ref(),
            self.butterworth.as_ref(),
            self.bessel.as_ref(),
            self.itae.as_ref(),
        ])
    }
}

/// One printed claim.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ClaimSpec {
    /// Identifier, unique in the file.
    pub id: String,
    /// Where the document prints it: `eq. (77)`, `slide 'Example: pole assignment'`.
    pub source: String,
    /// The computation that recomputes it (see the README for the list).
    pub what: super::Computation,
    /// The value exactly as printed (in input syntax; decimals as printed).
    pub printed: String,
    /// The coverage statements (their `where`) this claim checks, when it checks more than one:
    /// a claim is credited to several statements only when each is listed here.
    #[serde(default)]
    pub checks: Vec<String>,
    /// A remark shown with the claim.
    #[serde(default)]
    pub note: String,
    /// Per-claim matrices replacing those of `[system]`.
    #[serde(rename = "A")]
    pub a: Option<String>,
    /// Per-claim B.
    #[serde(rename = "B")]
    pub b: Option<String>,
    /// Per-claim C.
    #[serde(rename = "C")]
    pub c: Option<String>,
    /// Gain method (`ackermann`, `bass-gura`, `canonical`, `lemma-3.1`).
    pub method: Option<String>,
    /// `a-kc` or `a+lc`.
    pub convention: Option<String>,
    /// Canonical-form procedure: `di-ruscio` or `stoustrup`.
    pub procedure: Option<String>,
    /// Desired poles.
    pub poles: Option<String>,
    /// Desired polynomial.
    pub poly: Option<String>,
    /// Repeated root: time constant T.
    pub repeated: Option<String>,
    /// Butterworth: time constant T.
    pub butterworth: Option<String>,
    /// Bessel: time constant T.
    pub bessel: Option<String>,
    /// ITAE: time constant T.
    pub itae: Option<String>,
    /// Order of a desired polynomial when no system is given.
    pub order: Option<usize>,
    /// A gain matrix (numbers or symbols such as `[k1; k2]`).
    pub gain: Option<String>,
    /// A weight matrix (`D` of Baranowski's dynamical-error index).
    pub weight: Option<String>,
    /// For the weighted-derivative observer: the output measuring a derivative (1-based).
    pub derivative_output: Option<usize>,
    /// … and the state whose derivative it measures (1-based).
    pub derivative_state: Option<usize>,
    /// A state-feedback row `F` (u = F x̂).
    pub feedback: Option<String>,
    /// Discrete-time estimator: `prediction` (default) or `current`.
    pub estimator: Option<String>,
    /// Sampling period T (zero-order hold).
    pub period: Option<String>,
    /// For `what = "matrix_expression"`: the formula as printed (`Q T A T^-1`).
    pub expression: Option<String>,
    /// For `what = "equation_reference"`: what the sentence refers to (`A`, `B`, `C1`, or
    /// `gain`), in the order of the printed labels.
    #[serde(default)]
    pub refers: Vec<String>,
    /// … and the document's numbered equations as printed (label → matrix, or words).
    #[serde(default)]
    pub equations: BTreeMap<String, String>,
    /// Further named matrices the expression uses (`Q`, `T`), as printed.
    #[serde(default)]
    pub matrices: BTreeMap<String, String>,
    /// The variable of printed polynomials (default `s`, or `λ` when the print uses it).
    pub var: Option<String>,
    /// For `what = "identity"`: which identity.
    pub identity: Option<super::Identity>,
    /// Parameters kept symbolic for this claim (a general formula stated before the numbers).
    #[serde(default)]
    pub symbols: Vec<String>,
    /// Definitions used by the printed value (`k2 = "-c2/a"`).
    #[serde(default, rename = "where")]
    pub definitions: BTreeMap<String, String>,
    /// The documented erratum, when the print is wrong.
    pub erratum: Option<ErratumSpec>,
    /// The print is a design target, a graph reading or a rounded value: it holds within a
    /// stated tolerance, for a stated reason.
    pub approximate: Option<ApproximateSpec>,
    /// The document leaves undefined what the print is: each reading is computed and shown.
    pub unreproducible: Option<UnreproducibleSpec>,
}

named_enum! {
    /// Why a print may hold only approximately.
    pub enum ApproximationKind ("kind of approximation") {
        /// A target the design aims at ("poles selected for 600 rad/s").
        DesignTarget = "design_target",
        /// A value read off a figure.
        GraphReading = "graph_reading",
        /// A value rounded as the document says it rounds.
        StatedRounding = "stated_rounding",
        /// A value computed by a method the document does not state (its own numerics).
        UnstatedMethod = "unstated_method",
    }
}

impl ApproximationKind {
    /// In words.
    pub fn words(self) -> &'static str {
        match self {
            ApproximationKind::DesignTarget => "a design target",
            ApproximationKind::GraphReading => "read off a figure",
            ApproximationKind::StatedRounding => "rounded as stated",
            ApproximationKind::UnstatedMethod => "computed by a method the document does not state",
        }
    }
}

/// A print that holds within a tolerance, for a reason.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ApproximateSpec {
    /// Relative (`"1.5%"`) or absolute (`"0.5"`) tolerance on every entry.
    pub tolerance: String,
    /// Why an approximation is what the document means.
    pub kind: ApproximationKind,
    /// The reason, in our words.
    pub reason: String,
}

/// A print the document does not define well enough to recompute.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UnreproducibleSpec {
    /// What the document leaves undefined.
    pub undefined: String,
    /// The reasonable readings, each computed.
    #[serde(default)]
    pub readings: Vec<ReadingSpec>,
}

/// One reading of an undefined print: the claim recomputed as another computation.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReadingSpec {
    /// The reading, in our words.
    pub reading: String,
    /// The computation it amounts to (the claim's other fields kept).
    pub what: super::Computation,
}

named_enum! {
    /// How much an erratum matters.
    pub enum Severity ("severity") {
        /// A misprint that changes a result (a number, a sign, a matrix).
        ChangesResult = "changes_result",
        /// A slip that changes what a stated formula or theorem says — its dimensions, an index
        /// set — while the examples' results stand.
        ChangesStatement = "changes_statement",
        /// A notation or cross-reference slip: the result stands.
        Notation = "notation",
    }
}

/// A documented, checkable erratum.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ErratumSpec {
    /// What is wrong, in our words.
    pub explanation: String,
    /// How much it matters (default: it changes a result).
    pub severity: Option<Severity>,
    /// Parameter values with which the printed value is reproduced (the tool confirms).
    #[serde(default)]
    pub parameters: BTreeMap<String, String>,
    /// The corrected value (the tool confirms that it holds).
    pub corrected: Option<String>,
    /// Corrected input matrices (`[claims.erratum.matrices]`, replacing the claim's): the
    /// misprint is in a matrix the formula uses, and with these the print is reproduced (the
    /// tool confirms).
    #[serde(default)]
    pub matrices: BTreeMap<String, String>,
}

/// A printed value recorded for a later part of the workbench to verify.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PrintedRecord {
    /// Identifier.
    pub id: String,
    /// Where printed.
    pub source: String,
    /// As printed.
    pub printed: String,
    /// What will verify it.
    pub verified_by: String,
}

/// A simulation scenario: one figure of the document, with the assumptions it leaves open.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScenarioSpec {
    /// Name, unique in the file (`fig-7`).
    pub name: String,
    /// The figure(s) it reproduces, e.g. "Fig. 7 and 8".
    pub figure: String,
    /// What the document leaves open and this scenario assumes.
    #[serde(default)]
    pub assumptions: String,
    /// Parameter values for this scenario (override `[parameters]`).
    #[serde(default)]
    pub parameters: BTreeMap<String, String>,
    /// Plant matrices replacing those of `[system]` (the observer of a perfect scenario is still
    /// built from `[system]`: a changed plant).
    #[serde(rename = "A")]
    pub a: Option<String>,
    /// Per-scenario B.
    #[serde(rename = "B")]
    pub b: Option<String>,
    /// Per-scenario C (the outputs the observer uses).
    #[serde(rename = "C")]
    pub c: Option<String>,
    /// The observer gain (input syntax, parameters allowed)…
    pub gain: Option<String>,
    /// … or the id of a claim whose recomputed value is the gain.
    pub gain_claim: Option<String>,
    /// `a-kc` (default) or `a+lc`.
    pub convention: Option<String>,
    /// A state feedback `F` in `u = r + F x̂`.
    pub feedback: Option<String>,
    /// Use the perfect observer of `[system]` instead of a gain.
    #[serde(default)]
    pub perfect: bool,
    /// End time.
    pub horizon: f64,
    /// Output interval and RK4 step.
    pub step: f64,
    /// `rk4` (default), `dormand-prince` or `discrete`.
    pub integrator: Option<String>,
    /// Plant initial state.
    pub x0: Option<String>,
    /// Observer initial state (default zero).
    pub xhat0: Option<String>,
    /// One signal per input (default zero).
    #[serde(default)]
    pub input: Vec<crate::simulation::Signal>,
    /// Or: CSV files of `t,u` samples, one per input (paths relative to the example file),
    /// linearly interpolated.
    #[serde(default)]
    pub input_csv: Vec<String>,
    /// Measurement noise on every output.
    pub output_noise: Option<crate::simulation::noise::NoiseSpec>,
    /// Noise on the plant input, unseen by the observer.
    pub process_noise: Option<crate::simulation::noise::NoiseSpec>,
    /// States to plot (1-based; default all).
    #[serde(default)]
    pub plot: Vec<usize>,
    /// Time unit for the axis (default "s").
    pub time_unit: Option<String>,
    /// What the figure claims, checked by numbers.
    #[serde(default)]
    pub checks: Vec<CheckSpec>,
}

/// One checked statement about a figure: a metric of one state's estimation error compared with
/// a bound or with the same metric in another scenario.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CheckSpec {
    /// What the document says, quoted or paraphrased with its place.
    pub source: String,
    /// `ise`, `overshoot`, `settling_time`, `steady_rms` or `max_relative_error`.
    pub metric: String,
    /// The state (1-based).
    pub state: usize,
    /// Holds when the metric is below this.
    pub below: Option<f64>,
    /// Holds when the metric is above this.
    pub above: Option<f64>,
    /// Holds when the metric is below the same metric in these scenarios.
    #[serde(default)]
    pub less_than: Vec<String>,
    /// Holds when the metric is above the same metric in these scenarios.
    #[serde(default)]
    pub greater_than: Vec<String>,
    /// The statement depends on the initial state the scenario assumes: the check is repeated
    /// with this `x(0)` for this scenario and every one it is compared with, and the verdict
    /// says whether it holds for the assumed state only.
    pub also_from_x0: Option<String>,
}
