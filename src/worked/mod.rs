//! Worked examples as data: load a document's printed claims, recompute each one exactly, and
//! say whether the print holds, is a documented (and checked) erratum, or is a mismatch.
//!
//! The format is described for teachers in `worked_examples/README.md`. A claim names a
//! computation (`what`) and its inputs; the printed value is kept verbatim. Claims whose inputs
//! keep free symbols are computed symbolically when the computation never divides (observability
//! matrices, characteristic polynomials, pole-placement equations); otherwise they are checked in
//! exact arithmetic at several seeded random rational values of those symbols, and the report
//! says so.

mod checking;
mod computation;
mod compute;
mod compute_course;
mod compute_optimal;
pub mod coverage;
mod equation_reference;
mod format;
mod inputs;
mod load;
mod matrix_expression;
mod outcome;
pub mod proof;
mod report;
mod scenario;
mod value;
mod verdicts;
mod verify;

pub use computation::{Computation, Identity};
pub use compute::compute;
pub use format::{
    CheckSpec, ClaimSpec, ErratumSpec, ExampleFile, IntensitySpec, PrintedRecord, ScenarioSpec,
    SystemSpec,
};
pub use inputs::{ComputeError, Computed, Inputs};
pub use load::{load_example, load_folder, parse_example, WorkedError};
pub(crate) use load::{locate, toml_field};
pub use outcome::{ClaimReport, ExampleReport, Summary, Verdict};
pub use report::{
    errata_markdown, errata_markdown_titled, render_derivations, render_table, report_json,
};
pub use scenario::{run_scenarios, CheckResult, ScenarioRun};
pub use value::{compare, read_formula, Agreement, PrintError, Value};
pub use verify::verify_example;
