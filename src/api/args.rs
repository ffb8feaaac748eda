//! Turning raw command-line strings into validated values, naming the flag on error.

use crate::algebra::{Fraction, Quadratic, Rational, Zero};
use crate::linalg::Matrix;
use crate::observer::DesiredPolynomial;
use crate::poly::Poly;
use crate::symbolic::DesiredRequest;
use crate::syntax::Environment;
use crate::syntax::{parse_list, parse_polynomial};
use crate::syntax::{parse_matrix, parse_scalar, FromExpr};
use anyhow::{anyhow, bail, Context, Result};

/// Parses a matrix flag, e.g. `--a "[2 -3; 4 -5]"`.
pub fn matrix<T: FromExpr>(flag: &str, text: &str) -> Result<Matrix<T>> {
    let m = parse_matrix::<T>(text)
        .map_err(|e| anyhow!("{}", e.show_in(text)))
        .with_context(|| format!("in {flag}"))?;
    if m.rows() == 0 || m.cols() == 0 {
        bail!(
            "in {flag}: the matrix is empty ({}×{}); a system has at least one state, one input and one output",
            m.rows(),
            m.cols()
        );
    }
    Ok(m)
}

/// Refuses, for a command that computes in f64, an entry beyond f64's range (|x| > 1.8e308,
/// which would become infinite) or a nonzero entry that would become 0 (|x| < 2.2e-308),
/// naming the flag and the entry.
pub fn float_range(flag: &str, m: &Matrix<Rational>) -> Result<()> {
    for i in 0..m.rows() {
        for j in 0..m.cols() {
            let x = m.get(i, j);
            let f = crate::algebra::rational_to_f64(x);
            if !f.is_finite() {
                bail!(
                    "in {flag}: entry ({}, {}) is beyond the range of f64 (about 1.8e308), which this computation uses",
                    i + 1,
                    j + 1
                );
            }
            if f.abs() < f64::MIN_POSITIVE && !num_traits::Zero::is_zero(x) {
                bail!(
                    "in {flag}: entry ({}, {}) is nonzero but below f64's smallest normal number (about 2.2e-308), which this computation uses",
                    i + 1,
                    j + 1
                );
            }
        }
    }
    Ok(())
}

/// A rational flag of a command that computes with numbers, the values of `--at` substituted.
pub fn rational_at(flag: &str, text: &str, values: &Environment) -> Result<Rational> {
    if !matches!(
        parse_scalar::<Rational>(text),
        Err(crate::syntax::SyntaxError::UnknownSymbol { .. })
    ) {
        return rational(flag, text);
    }
    let x =
        parse_scalar::<Fraction>(text).map_err(|e| anyhow!("in {flag}: {}", e.show_in(text)))?;
    let m = Matrix::from_rows(vec![vec![x]])?;
    if values.is_empty() {
        return Err(needs_values(flag, &m));
    }
    Ok(evaluated(flag, &m, values)?.get(0, 0).clone())
}

/// Parses a rational flag, e.g. `--repeated 1/4`.
pub fn rational(flag: &str, text: &str) -> Result<Rational> {
    parse_scalar::<Rational>(text)
        .map_err(|e| anyhow!("{}", e.show_in(text)))
        .with_context(|| format!("in {flag}"))
}

/// [`json_matrix`] of a matrix a derivation step shows, from the entries the step kept (each
/// converted to decimal once) when it kept them.
pub fn json_matrix_shown<T: crate::algebra::Ring>(
    m: &Matrix<T>,
    step: Option<&crate::derivation::Step>,
) -> serde_json::Value {
    match step.and_then(crate::derivation::Step::cells) {
        Some(cells) if cells.len() == m.rows() * m.cols() && m.cols() > 0 => {
            serde_json::Value::Array(
                cells
                    .chunks(m.cols())
                    .map(|row| {
                        serde_json::Value::Array(
                            row.iter().cloned().map(serde_json::Value::String).collect(),
                        )
                    })
                    .collect(),
            )
        }
        _ => json_matrix(m),
    }
}

/// A float matrix as a JSON list of rows of strings, each entry as `{:e}` writes it
/// ([`crate::algebra::float_text`]), built as JSON strings directly (not as strings then
/// copied into the value: `zoh` at n = 100 writes 10 100 of them).
pub fn json_exp_matrix(
    rows: usize,
    cols: usize,
    entry: impl Fn(usize, usize) -> f64,
) -> serde_json::Value {
    serde_json::Value::Array(
        (0..rows)
            .map(|i| {
                serde_json::Value::Array(
                    (0..cols)
                        .map(|j| {
                            serde_json::Value::String(crate::algebra::float_text::exp(entry(i, j)))
                        })
                        .collect(),
                )
            })
            .collect(),
    )
}

/// A float matrix of a JSON answer, given as [`json_exp_matrix`] gives it: made a value only
/// when the report keeps values, and otherwise written straight into the text
/// ([`super::Report::json_with_exp_matrices`]; at n = 100 `zoh`'s Φ is 10 000 strings, each
/// its own allocation in a value).
pub enum ExpMatrix<'a> {
    /// Row by row.
    Rows(&'a [Vec<f64>]),
    /// nalgebra's.
    Dense(&'a nalgebra::DMatrix<f64>),
}

impl ExpMatrix<'_> {
    /// Its rows and columns.
    pub fn shape(&self) -> (usize, usize) {
        match self {
            ExpMatrix::Rows(m) => (m.len(), m.first().map_or(0, Vec::len)),
            ExpMatrix::Dense(m) => m.shape(),
        }
    }
    /// Entry (i, j).
    pub fn get(&self, i: usize, j: usize) -> f64 {
        match self {
            ExpMatrix::Rows(m) => m[i][j],
            ExpMatrix::Dense(m) => m[(i, j)],
        }
    }
    /// The matrix as a JSON value, [`json_exp_matrix`].
    pub fn value(&self) -> serde_json::Value {
        let (rows, cols) = self.shape();
        json_exp_matrix(rows, cols, |i, j| self.get(i, j))
    }
}

/// A JSON object from `(key, value)` pairs, each value moved in: `json!` serialises every
/// value it is given into a new one, a second copy of a whole matrix of strings (at n = 100
/// `zoh`'s Φ is 10 000 of them; a canonical form's T at n = 60 megabytes of digits).
pub fn object(pairs: Vec<(&str, serde_json::Value)>) -> serde_json::Value {
    // inserted one by one: collecting a map sorts its pairs first, and that sort's code for
    // these pairs alone is 9 KB of the browser's module
    let mut map = serde_json::Map::new();
    for (key, value) in pairs {
        map.insert(key.to_string(), value);
    }
    serde_json::Value::Object(map)
}

/// A matrix as a JSON list of rows of strings in input syntax.
pub fn json_matrix<T: crate::algebra::Ring>(m: &Matrix<T>) -> serde_json::Value {
    serde_json::Value::Array(
        (0..m.rows())
            .map(|i| {
                serde_json::Value::Array(
                    m.row(i)
                        .iter()
                        .map(|x| serde_json::Value::String(x.to_input()))
                        .collect(),
                )
            })
            .collect(),
    )
}

/// The pair `(A, C)` every design subcommand starts from (`--a`, `--c`), in MATLAB syntax.
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "commands", derive(clap::Args))]
pub struct SystemPair {
    /// The system matrix A, e.g. "[2 -3; 4 -5]".
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long = "a", required_unless_present = "tf")
    )]
    #[serde(default)]
    pub a: Option<String>,
    /// The output matrix C, e.g. "[-3 2]".
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long = "c", required_unless_present = "tf")
    )]
    #[serde(default)]
    pub c: Option<String>,
    /// Instead of A and C: a SISO transfer function in s, e.g. "(s + 1)/(s^2 + 3s + 5)",
    /// realised exactly in observer canonical form (in lowest terms; B and D from it too).
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, conflicts_with_all = ["a", "c"], value_name = "G")
    )]
    #[serde(default)]
    pub tf: Option<String>,
    /// Values for the parameters, e.g. "k=2, m=1/2": the symbolic entries are evaluated there
    /// and the command continues exactly with numbers.
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, value_name = "NAME=VALUE,…")
    )]
    #[serde(default)]
    pub at: Option<String>,
}

/// A plant read from `--a` and `--c`: numbers, or rational functions of parameters.
#[derive(Debug, Clone)]
pub enum Plant {
    /// Every entry a rational number (after `--at`, if given).
    Numeric(Matrix<Rational>, Matrix<Rational>),
    /// Some entry mentions a parameter.
    Symbolic(Matrix<Fraction>, Matrix<Fraction>),
}

/// The values of `--at NAME=VALUE, …` (empty without the flag); errors name the flag.
pub fn parameter_values(text: Option<&str>) -> Result<Environment> {
    let mut values = Environment::new();
    let Some(text) = text else {
        return Ok(values);
    };
    for part in text.split(',').map(str::trim).filter(|p| !p.is_empty()) {
        let Some((name, value)) = part.split_once('=') else {
            bail!(
                "in --at: '{}' is not NAME=VALUE",
                crate::files::escape_untrusted(part)
            );
        };
        let name = name.trim();
        let well_formed = name.chars().next().is_some_and(char::is_alphabetic)
            && name.chars().all(|c| c.is_alphanumeric() || c == '_');
        if !well_formed {
            bail!(
                "in --at: '{}' is not a parameter name",
                crate::files::escape_untrusted(name)
            );
        }
        crate::symbolic::check_parameters(&[name.to_string()])
            .map_err(|e| anyhow!("in --at: {e}"))?;
        let v = parse_scalar::<Rational>(value.trim())
            .map_err(|e| anyhow!("in --at: {name} = {}", e.show_in(value.trim())))?;
        if values.insert(name.to_string(), v).is_some() {
            bail!("in --at: {name} is given twice");
        }
    }
    if values.len() > MAX_AT_VALUES {
        bail!("in --at: {} values, at most {MAX_AT_VALUES}", values.len());
    }
    Ok(values)
}

/// The most values `--at` takes.
const MAX_AT_VALUES: usize = 64;

/// A matrix flag read once: plain numbers, or rational functions of the parameters — the
/// symbol error of the numeric reader decides which.
enum Read {
    Numbers(Matrix<Rational>),
    Symbols(Matrix<Fraction>),
    /// Refused by the numeric reader for another reason (its error is given where numbers
    /// are needed).
    Other,
}

fn read_matrix(flag: &str, text: &str) -> Result<Read> {
    Ok(match crate::syntax::parse_rational_matrix(text) {
        Err(crate::syntax::SyntaxError::UnknownSymbol { .. }) => {
            Read::Symbols(matrix::<Fraction>(flag, text)?)
        }
        Ok(m) if m.rows() > 0 && m.cols() > 0 => Read::Numbers(m),
        _ => Read::Other,
    })
}

/// A matrix with the values of `--at` substituted, as numbers; errors name a parameter left
/// without a value.
fn evaluated(flag: &str, m: &Matrix<Fraction>, values: &Environment) -> Result<Matrix<Rational>> {
    let mut rows = Vec::with_capacity(m.rows());
    for i in 0..m.rows() {
        let mut row = Vec::with_capacity(m.cols());
        for x in m.row(i) {
            let v = crate::symbolic::substitute_values(x, values);
            match v.as_rational() {
                Some(q) => row.push(q),
                None => bail!(
                    "in {flag}: entry ({}, {}) = {x} still has {} without a value (give it in --at NAME=VALUE)",
                    i + 1,
                    row.len() + 1,
                    v.symbols().join(", ")
                ),
            }
        }
        rows.push(row);
    }
    Ok(Matrix::from_rows(rows)?)
}

/// A matrix flag of a command that computes with numbers, with the values of `--at`
/// substituted; a parameter left without a value is refused with the way to give it one.
pub fn matrix_at(flag: &str, text: &str, values: &Environment) -> Result<Matrix<Rational>> {
    match read_matrix(flag, text)? {
        Read::Numbers(m) => Ok(m),
        Read::Other => matrix::<Rational>(flag, text),
        Read::Symbols(m) if values.is_empty() => Err(needs_values(flag, &m)),
        Read::Symbols(m) => evaluated(flag, &m, values),
    }
}

/// Whether a matrix flag mentions a parameter.
pub fn mentions_parameters(text: &str) -> bool {
    matches!(
        parse_matrix::<Rational>(text),
        Err(crate::syntax::SyntaxError::UnknownSymbol { .. })
    )
}

/// Numbers from values read with `--at` substituted; a value still holding a parameter is
/// named, with the flag.
pub fn numbers(flag: &str, read: Vec<Fraction>) -> Result<Vec<Quadratic>> {
    read.iter()
        .map(|x| {
            x.as_quadratic().ok_or_else(|| {
                anyhow!(
                    "in {flag}: {x} still has {} without a value (give it in --at NAME=VALUE)",
                    x.symbols().join(", ")
                )
            })
        })
        .collect()
}

/// A polynomial flag in `s` with the values of `--at` substituted.
pub fn polynomial_at(flag: &str, text: &str, values: &Environment) -> Result<Poly<Rational>> {
    let read = DesiredRequest::Poly(text)
        .values(values)
        .map_err(|e| anyhow!("in {flag}: {e}"))?;
    let coeffs = read
        .iter()
        .map(|x| {
            x.as_rational().ok_or_else(|| {
                anyhow!(
                    "in {flag}: {x} still has {} without a value (give it in --at NAME=VALUE)",
                    x.symbols().join(", ")
                )
            })
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(Poly::new(coeffs, "s"))
}

/// A numeric command met a parameter: say how to give it a value.
fn needs_values(flag: &str, m: &Matrix<Fraction>) -> anyhow::Error {
    let names = crate::symbolic::parameters(m.entries());
    anyhow!(
        "in {flag}: {} {}; this command computes with numbers — give {} with --at {}",
        names.join(", "),
        if names.len() == 1 {
            "is a parameter"
        } else {
            "are parameters"
        },
        if names.len() == 1 {
            "its value"
        } else {
            "their values"
        },
        names
            .iter()
            .map(|n| format!("{n}=…"))
            .collect::<Vec<_>>()
            .join(",")
    )
}

/// A plant realised from `--tf`: its matrices and how they were formed.
#[derive(Debug, Clone)]
pub struct Realisation {
    /// The transfer function as read, in lowest terms.
    pub transfer_function: String,
    /// A, B, C, D of the observer canonical form.
    pub a: Matrix<Rational>,
    /// B.
    pub b: Matrix<Rational>,
    /// C.
    pub c: Matrix<Rational>,
    /// D.
    pub d: Matrix<Rational>,
}

impl Realisation {
    /// The lines saying what was realised and in which form.
    pub fn describe(&self) -> String {
        format!(
            "Plant from --tf: G(s) = {} (lowest terms), realised in observer canonical form — the denominator's coefficients −a_(n−1) … −a_0 down A's first column, ones above the diagonal, the numerator's in B, C = [1 0 … 0]:\n  A = {}\n  B = {}\n  C = {}\n  D = {}\n",
            self.transfer_function,
            self.a.to_input(),
            self.b.to_input(),
            self.c.to_input(),
            self.d.to_input()
        )
    }

    /// The same as JSON.
    pub fn json(&self) -> serde_json::Value {
        serde_json::json!({
            "transfer_function": self.transfer_function,
            "form": "observer canonical (A's first column −a_(n−1) … −a_0, C = [1 0 … 0])",
            "a": json_matrix(&self.a),
            "b": json_matrix(&self.b),
            "c": json_matrix(&self.c),
            "d": json_matrix(&self.d),
        })
    }
}

impl SystemPair {
    /// Both matrices, exact; errors name the flag and the column.
    pub fn parse(&self) -> Result<(Matrix<Rational>, Matrix<Rational>)> {
        match self.plant()? {
            Plant::Numeric(a, c) => Ok((a, c)),
            Plant::Symbolic(a, c) => Err(if a.entries().iter().any(|x| !x.symbols().is_empty()) {
                needs_values("--a", &a)
            } else {
                needs_values("--c", &c)
            }),
        }
    }

    /// The values of `--at`.
    pub fn values(&self) -> Result<Environment> {
        parameter_values(self.at.as_deref())
    }

    /// The plant, numeric or with parameters; `--at` substitutes values (and then every
    /// parameter needs one).
    pub fn plant(&self) -> Result<Plant> {
        self.plant_named("--c")
    }

    /// [`SystemPair::plant`] with the second matrix read under another flag's name (`--b` for
    /// state feedback, whose pair is (A, B)).
    pub fn plant_named(&self, second: &str) -> Result<Plant> {
        if let Some(r) = self.realisation()? {
            if self.at.is_some() {
                bail!("in --at: --tf takes numbers only");
            }
            return Ok(Plant::Numeric(r.a, r.c));
        }
        let (Some(a), Some(c)) = (&self.a, &self.c) else {
            bail!("give the plant: --a and --c, or --tf");
        };
        let values = self.values()?;
        let feedback = second == "--b";
        let shapes = |a: &Matrix<Rational>, c: &Matrix<Rational>| {
            if feedback {
                check_plant(a, Some(c), &Matrix::zeros(0, a.cols()), None)
            } else {
                check_plant(a, None, c, None)
            }
        };
        let (ra, rc) = (read_matrix("--a", a)?, read_matrix(second, c)?);
        if !matches!(ra, Read::Symbols(_)) && !matches!(rc, Read::Symbols(_)) {
            let numbers = |r: Read, flag: &str, text: &str| match r {
                Read::Numbers(m) => Ok(m),
                _ => matrix::<Rational>(flag, text),
            };
            let (a, c) = (numbers(ra, "--a", a)?, numbers(rc, second, c)?);
            if !feedback {
                shapes(&a, &c)?;
            }
            return Ok(Plant::Numeric(a, c));
        }
        let symbols = |r: Read, flag: &str, text: &str| match r {
            Read::Symbols(m) => Ok(m),
            _ => matrix::<Fraction>(flag, text),
        };
        let (a, c) = (symbols(ra, "--a", a)?, symbols(rc, second, c)?);
        if values.is_empty() {
            let names = crate::symbolic::parameters(a.entries().iter().chain(c.entries()));
            crate::symbolic::check_parameters(&names)
                .map_err(|e| anyhow!("in --a/{second}: {e}"))?;
            shapes(&a.map(|_| Rational::zero()), &c.map(|_| Rational::zero()))?;
            return Ok(Plant::Symbolic(a, c));
        }
        let (a, c) = (
            evaluated("--a", &a, &values)?,
            evaluated(second, &c, &values)?,
        );
        if !feedback {
            shapes(&a, &c)?;
        }
        Ok(Plant::Numeric(a, c))
    }

    /// The input matrix: `--b` as given, or the realisation's B when the plant is `--tf`.
    pub fn input(&self, b: Option<&str>) -> Result<Option<Matrix<Rational>>> {
        match (self.realisation()?, b) {
            (Some(_), Some(_)) => {
                bail!("in --b: with --tf, B comes from the transfer function")
            }
            (Some(r), None) => Ok(Some(r.b)),
            (None, b) => {
                let values = self.values()?;
                b.map(|t| matrix_at("--b", t, &values)).transpose()
            }
        }
    }

    /// The plant realised from `--tf`, when it is given.
    pub fn realisation(&self) -> Result<Option<Realisation>> {
        let Some(text) = &self.tf else {
            return Ok(None);
        };
        if self.a.is_some() || self.c.is_some() {
            bail!("in --tf: give either --tf or --a and --c, not both");
        }
        let g = crate::syntax::parse_rational_function::<Rational>(text, "s")
            .map_err(|e| anyhow!("in --tf: {}", e.show_in(text)))?;
        // (the parser bounds the degree by 200, the largest exact order)
        let (a, b, c, d) =
            crate::system::observer_form_of(&g).map_err(|e| anyhow!("in --tf: {e}"))?;
        Ok(Some(Realisation {
            transfer_function: g.to_string(),
            a,
            b,
            c,
            d,
        }))
    }
}

/// The worked-example folder as given (relative to the working folder). There is no fallback
/// to the folder the program was built from: an installed `owb` must not read a checkout's
/// files behind the user's back.
///
/// # Errors
/// A folder that does not exist, named with the way to give another.
pub fn examples_folder(dir: &std::path::Path) -> Result<std::path::PathBuf> {
    if dir.is_dir() {
        return Ok(dir.to_path_buf());
    }
    bail!(
        "in --dir: there is no worked-example folder {} here (run from the repository's root, or give --dir FOLDER)",
        crate::files::escape_untrusted(&dir.display().to_string())
    )
}

/// A worked example by file path or by id (file stem) among `all`.
pub fn find_example(
    dir: &std::path::Path,
    all: &[std::path::PathBuf],
    name: &str,
) -> Result<std::path::PathBuf> {
    let p = std::path::Path::new(name);
    if p.is_file() {
        return Ok(p.to_path_buf());
    }
    all.iter()
        .find(|f| f.file_stem().is_some_and(|s| s == name))
        .cloned()
        .ok_or_else(|| {
            anyhow!(
                "no worked example '{name}' in {} (give an id or a file path)",
                dir.display()
            )
        })
}

#[cfg(feature = "plot")]
/// Refuses two output flags naming the same file (`--svg f --csv f` would keep only one).
pub fn distinct_outputs(outputs: &[(&str, Option<&std::path::Path>)]) -> Result<()> {
    let named: Vec<(&str, &std::path::Path)> = outputs
        .iter()
        .filter_map(|(f, p)| Some((*f, (*p)?)))
        .collect();
    for (k, (flag, path)) in named.iter().enumerate() {
        for (other, path2) in &named[k + 1..] {
            let same = path == path2
                || matches!((path.canonicalize(), path2.canonicalize()), (Ok(x), Ok(y)) if x == y);
            if same {
                bail!(
                    "{flag} and {other} both name {}: one would overwrite the other",
                    path.display()
                );
            }
        }
    }
    Ok(())
}

/// A float matrix as rows (for JSON).
pub fn float_rows(m: &nalgebra::DMatrix<f64>) -> Vec<Vec<f64>> {
    (0..m.nrows())
        .map(|i| m.row(i).iter().copied().collect())
        .collect()
}

/// A float matrix in input syntax, each entry formatted by `entry`.
pub fn float_matrix_text(m: &nalgebra::DMatrix<f64>, entry: impl Fn(f64) -> String) -> String {
    let r: Vec<String> = float_rows(m)
        .iter()
        .map(|r| r.iter().map(|x| entry(*x)).collect::<Vec<_>>().join(", "))
        .collect();
    format!("[{}]", r.join("; "))
}

/// The input side of a plant (`--b`, and `--d` defaulting to zero), for the subcommands that
/// need the whole (A, B, C, D).
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "commands", derive(clap::Args))]
pub struct InputMatrices {
    /// The input matrix B.
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long = "b", required_unless_present = "tf")
    )]
    #[serde(default)]
    pub b: Option<String>,
    /// The feedthrough D (default zero).
    #[cfg_attr(feature = "commands", arg(allow_hyphen_values = true, long = "d"))]
    #[serde(default)]
    pub d: Option<String>,
}

impl InputMatrices {
    /// B, and D if given; from the realisation when the plant is a transfer function.
    pub fn parse(
        &self,
        system: &SystemPair,
    ) -> Result<(Matrix<Rational>, Option<Matrix<Rational>>)> {
        if let Some(r) = system.realisation()? {
            if self.b.is_some() || self.d.is_some() {
                bail!("in --b: with --tf, B and D come from the transfer function");
            }
            return Ok((r.b, Some(r.d)));
        }
        let Some(b) = &self.b else {
            bail!("give the input matrix --b");
        };
        let values = system.values()?;
        let b = matrix_at("--b", b, &values)?;
        let d = self
            .d
            .as_deref()
            .map(|t| matrix_at("--d", t, &values))
            .transpose()?;
        Ok((b, d))
    }
}

/// The desired observer polynomial (`--poles`, `--poly`, `--repeated T`, `--butterworth T`,
/// `--bessel T`, `--itae T`), shared by the design subcommands.
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "commands", derive(clap::Args))]
pub struct DesiredArgs {
    /// Desired observer poles, e.g. "-4, -5" or "-1+2i, -1-2i, -3".
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, group = "desired")
    )]
    #[serde(default)]
    pub poles: Option<String>,
    /// Desired observer polynomial, e.g. "s^2 + 9s + 20".
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, group = "desired")
    )]
    #[serde(default)]
    pub poly: Option<String>,
    /// All n poles at −1/T.
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, group = "desired", value_name = "T")
    )]
    #[serde(default)]
    pub repeated: Option<String>,
    /// Order-n Butterworth polynomial with time constant T.
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, group = "desired", value_name = "T")
    )]
    #[serde(default)]
    pub butterworth: Option<String>,
    /// Order-n Bessel (Thomson) polynomial with low-frequency delay T.
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, group = "desired", value_name = "T")
    )]
    #[serde(default)]
    pub bessel: Option<String>,
    /// Order-n ITAE polynomial (orders 1 to 6) with time constant T.
    #[cfg_attr(
        feature = "commands",
        arg(allow_hyphen_values = true, long, group = "desired", value_name = "T")
    )]
    #[serde(default)]
    pub itae: Option<String>,
}

/// `n` poles from a flag (`--poles "-4, -5"`), as the desired polynomial; errors name the flag.
pub fn poles_flag(flag: &str, text: &str, n: usize) -> Result<DesiredPolynomial> {
    let poles =
        parse_list::<Quadratic>(text).map_err(|e| anyhow!("in {flag}: {}", e.show_in(text)))?;
    if poles.len() != n {
        bail!(
            "in {flag}: {} poles given, the system has order {n}",
            poles.len()
        );
    }
    Ok(DesiredPolynomial::from_poles(&poles)?)
}

/// `--method` of the design subcommands other than `gain`: ackermann, bass-gura or canonical.
pub fn gain_method(text: &str) -> Result<crate::observer::GainMethod> {
    use crate::observer::GainMethod;
    GainMethod::parse(text)
        .filter(|m| *m != GainMethod::Lemma31)
        .ok_or_else(|| {
            anyhow!("in --method: unknown method '{text}' (ackermann, bass-gura or canonical)")
        })
}

/// `--convention` of the observer subcommands.
pub fn observer_convention(text: &str) -> Result<crate::observer::Convention> {
    crate::observer::Convention::parse(text)
        .ok_or_else(|| anyhow!("in --convention: unknown convention '{text}' (a-kc or a+lc)"))
}

impl DesiredArgs {
    /// The family set by a time constant, if one is given, with its value.
    pub fn family(&self) -> Option<(crate::observer::Family, &String)> {
        crate::observer::Family::given([
            self.repeated.as_ref(),
            self.butterworth.as_ref(),
            self.bessel.as_ref(),
            self.itae.as_ref(),
        ])
    }

    /// The flag that is given and the request it holds.
    fn request(&self) -> Option<(String, DesiredRequest<'_>)> {
        if let Some(p) = &self.poles {
            Some(("--poles".into(), DesiredRequest::Poles(p)))
        } else if let Some(p) = &self.poly {
            Some(("--poly".into(), DesiredRequest::Poly(p)))
        } else {
            self.family()
                .map(|(f, t)| (format!("--{f}"), DesiredRequest::Family(f, t)))
        }
    }

    /// The desired polynomial as requested, `poles -w, -w`.
    pub fn describe(&self) -> String {
        let text = |r: DesiredRequest<'_>| match r {
            DesiredRequest::Poles(t) | DesiredRequest::Poly(t) | DesiredRequest::Family(_, t) => {
                t.to_string()
            }
        };
        self.request()
            .map(|(flag, r)| format!("{} {}", flag.trim_start_matches('-'), text(r)))
            .unwrap_or_default()
    }

    /// Whether the desired polynomial mentions a parameter (`s` in `--poly` is the variable).
    pub fn mentions_parameters(&self) -> bool {
        self.request()
            .is_some_and(|(_, r)| r.mentions_parameters(&Environment::new()))
    }

    /// The desired polynomial of degree `n` as a polynomial in `s` over the rational functions
    /// of the parameters (`--poles "-w, -w"`, `--poly "s^2 + 2 zeta w s + w^2"`, `--repeated T`
    /// with a symbolic `T`); errors name the flag.
    pub fn symbolic(&self, n: usize) -> Result<Poly<Fraction>> {
        let Some((flag, request)) = self.request() else {
            bail!("give the desired observer polynomial: --poles, --poly, --repeated T, --butterworth T, --bessel T or --itae T");
        };
        request
            .polynomial(&Environment::new(), n)
            .map_err(|e| anyhow!("in {flag}: {e}"))
    }

    /// The desired polynomial of degree `n` with the parameters' `values` substituted (as
    /// [`DesiredArgs::parse`] without values); errors name the flag.
    pub fn parse_at(&self, n: usize, values: &Environment) -> Result<DesiredPolynomial> {
        let Some((flag, request)) = self.request() else {
            return self.parse(n);
        };
        if values.is_empty() || !request.mentions_parameters(&Environment::new()) {
            return self.parse(n);
        }
        let numbers = |xs: Vec<Fraction>| numbers(&flag, xs);
        let read = request
            .values(values)
            .map_err(|e| anyhow!("in {flag}: {e}"))?;
        match request {
            DesiredRequest::Poles(_) => {
                if read.len() != n {
                    bail!(
                        "in {flag}: {} poles given, the system has order {n}",
                        read.len()
                    );
                }
                Ok(DesiredPolynomial::from_poles(&numbers(read)?)?)
            }
            DesiredRequest::Poly(_) => Ok(DesiredPolynomial::from_polynomial(
                Poly::new(numbers(read)?, "s"),
                n,
            )?),
            DesiredRequest::Family(family, _) => {
                let t = numbers(read)?.remove(0);
                let Some(t) = t.as_rational().cloned() else {
                    bail!("in {flag}: the time constant must be rational");
                };
                family
                    .polynomial(&t, n)
                    .with_context(|| format!("in {flag}"))
            }
        }
    }

    /// The desired polynomial of degree `n`; errors name the flag.
    pub fn parse(&self, n: usize) -> Result<DesiredPolynomial> {
        Ok(if let Some(p) = &self.poles {
            poles_flag("--poles", p, n)?
        } else if let Some(p) = &self.poly {
            let poly = parse_polynomial::<Quadratic>(p, "s")
                .map_err(|e| anyhow!("in --poly: {}", e.show_in(p)))?;
            DesiredPolynomial::from_polynomial(poly, n)?
        } else if let Some((family, t)) = self.family() {
            let flag = format!("--{family}");
            family
                .polynomial(&rational(&flag, t)?, n)
                .with_context(|| format!("in {flag}"))?
        } else {
            bail!("give the desired observer polynomial: --poles, --poly, --repeated T, --butterworth T, --bessel T or --itae T")
        })
    }
}

/// Checks the plant's shapes, errors in the flags' words (`in --b: B is 3×1, expected 2 rows
/// (the order of A)`), before any computation can meet a mismatch in its own terms.
pub fn check_plant(
    a: &Matrix<Rational>,
    b: Option<&Matrix<Rational>>,
    c: &Matrix<Rational>,
    d: Option<&Matrix<Rational>>,
) -> Result<()> {
    use crate::system::{StateSpace, SystemError};
    StateSpace::check_shapes(a, b, c, d).map_err(|e| {
        let flag = match &e {
            SystemError::NonSquareA { .. } => "--a".to_string(),
            SystemError::Shape { matrix, .. } => format!("--{}", matrix.to_lowercase()),
        };
        anyhow!("in {flag}: {e}")
    })
}

/// Checks that a matrix flag has the shape the plant asks for; `why` says where it comes from
/// (`"states × outputs"`).
pub fn expect_shape<T: crate::algebra::Ring>(
    flag: &str,
    m: &Matrix<T>,
    rows: usize,
    cols: usize,
    why: &str,
) -> Result<()> {
    if m.shape() != (rows, cols) {
        bail!(
            "in {flag}: the matrix is {}×{}, expected {rows}×{cols} ({why})",
            m.rows(),
            m.cols()
        );
    }
    Ok(())
}

/// The defaults of the requests' fields, one place for both readers: clap shows and applies
/// them (`default_value_t`), serde fills them into requests read from JSON.
pub(crate) mod defaults {
    pub fn kalman_grid() -> usize {
        1001
    }
    pub fn time_limit() -> f64 {
        10.0
    }
    pub fn placed_output() -> usize {
        1
    }
    pub fn tolerance() -> f64 {
        1e-6
    }
    pub fn seed() -> u64 {
        2024
    }
    pub fn new_exercise_orders() -> String {
        "2..3".into()
    }
    pub fn class_order() -> String {
        "3".into()
    }
    pub fn starts() -> usize {
        40
    }
    pub fn method() -> String {
        "ackermann".into()
    }
    pub fn observer_convention() -> String {
        "a-kc".into()
    }
    pub fn control_convention() -> String {
        "a+lc".into()
    }
    pub fn index() -> String {
        "j1".into()
    }
    pub fn exercise_kind() -> String {
        "pole-placement".into()
    }
    pub fn estimator() -> String {
        "prediction".into()
    }
    pub fn feedback_convention() -> String {
        "u=-kx".into()
    }
    pub fn examples_folder() -> std::path::PathBuf {
        "worked_examples".into()
    }
}
