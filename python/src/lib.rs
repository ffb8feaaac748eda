//! The observer workbench's Python extension (`observer_workbench._native`): the library's
//! commands reached through [`api::run`] with JSON requests, and the exercise checker — the same
//! functions the `owb` command line, the course book and the browser call. The Python package
//! (`observer_workbench/__init__.py`) turns Python values into requests and reports into
//! Python values; nothing is computed here that the library does not compute.

use observer_workbench::api::{self, Command, Outcome};
use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;

create_exception!(
    _native,
    WorkbenchError,
    PyException,
    "A request the workbench refuses (bad input, an impossible design, an unreadable file), with the same message as the command line."
);

/// The error of a failed command: its message with its causes, as the command line prints
/// them (`error: …` and `caused by: …` lines, joined).
fn refusal(e: &anyhow::Error) -> PyErr {
    let causes: Vec<String> = e.chain().skip(1).map(|c| c.to_string()).collect();
    let mut message = e.to_string();
    for c in causes {
        message.push_str("\n  caused by: ");
        message.push_str(&c);
    }
    WorkbenchError::new_err(message)
}

/// Runs one request (`{"command": "gain", "a": …}`, keys named as the command line's flags).
/// Returns `(status, text, latex, warnings)`: status 0 (ok) or 1 (a check or verification
/// found something wrong), the report as the command line prints it (its JSON when the
/// request asks for `json`), the derivation typeset in LaTeX (or `None`), and the warnings.
///
/// Raises `WorkbenchError` for a refused request.
#[pyfunction]
fn run(py: Python<'_>, request: &str) -> PyResult<(u8, String, Option<String>, Vec<String>)> {
    let command = Command::from_json(request).map_err(|e| WorkbenchError::new_err(e.0))?;
    if command.writes_files() {
        return Err(WorkbenchError::new_err(
            "this request writes files; run it with the owb command line",
        ));
    }
    // the computation holds no Python object: other Python threads may run meanwhile
    let result = py.allow_threads(|| api::run(command));
    match result {
        Ok(report) => {
            let status = match report.outcome {
                Outcome::Ok => 0,
                Outcome::Failed => 1,
            };
            let latex = report.latex();
            Ok((status, report.text, latex, report.warnings))
        }
        Err(failure) => Err(refusal(&failure.error)),
    }
}

/// Checks answers against an exercise, both as TOML text (`name` names the exercise in
/// messages). Returns the report as JSON text: what `owb check --json` prints.
///
/// Raises `WorkbenchError` when a file does not read.
#[pyfunction]
fn check_text(
    py: Python<'_>,
    exercise_name: &str,
    exercise: &str,
    answers: &str,
) -> PyResult<String> {
    let report = py
        .allow_threads(|| {
            observer_workbench::exercise::check::check_text(
                (exercise_name, exercise),
                ("answers.toml", answers),
            )
        })
        .map_err(|e| WorkbenchError::new_err(e.to_string()))?;
    let mut value = serde_json::to_value(&report)
        .map_err(|e| WorkbenchError::new_err(format!("the report does not serialise: {e}")))?;
    value["text"] = serde_json::Value::String(report.text());
    Ok(value.to_string())
}

/// The text of a built-in exercise (`stoustrup-pole-assignment`, …), or `None`.
#[pyfunction]
fn builtin_exercise(id: &str) -> Option<&'static str> {
    observer_workbench::exercise::builtin(id).map(|(_, text)| text)
}

/// The ids of the built-in exercises.
#[pyfunction]
fn builtin_exercises() -> Vec<&'static str> {
    observer_workbench::exercise::BUILTIN_EXERCISES
        .iter()
        .map(|(id, _)| *id)
        .collect()
}

/// The workbench's version.
#[pyfunction]
fn version() -> &'static str {
    env!("CARGO_PKG_VERSION")
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("WorkbenchError", m.py().get_type::<WorkbenchError>())?;
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(check_text, m)?)?;
    m.add_function(wrap_pyfunction!(builtin_exercise, m)?)?;
    m.add_function(wrap_pyfunction!(builtin_exercises, m)?)?;
    m.add_function(wrap_pyfunction!(version, m)?)?;
    Ok(())
}
