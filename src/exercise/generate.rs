//! Fresh pole-placement exercises whose hand computation stays in small integers: the plant is
//! built backwards from an observer canonical form with integer coefficients and a unimodular
//! integer transformation (det T = ±1, so T⁻¹ is an integer matrix too), and the desired poles
//! are distinct small negative integers. The same seed gives the same exercise.

use crate::algebra::Rational;
use crate::linalg::{self, Matrix};
use crate::poly::Poly;

/// What a generated exercise asks.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Kind {
    /// Observer pole placement through the canonical form (continuous time).
    #[default]
    PolePlacement,
    /// A dead-beat observer of a discrete-time plant (every pole at z = 0).
    DeadBeat,
    /// A reduced-order (Gopinath) observer of a plant measured at its first state.
    ReducedOrder,
    /// An observer gain as a formula: one entry of A is a parameter `a`, the poles are
    /// multiples of a parameter `w`; every answer is a formula in them.
    Formula,
}

impl Kind {
    /// Every kind.
    pub const ALL: [Kind; 4] = [
        Kind::PolePlacement,
        Kind::DeadBeat,
        Kind::ReducedOrder,
        Kind::Formula,
    ];
    /// Its name in ids and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Kind::PolePlacement => "pole-placement",
            Kind::DeadBeat => "dead-beat",
            Kind::ReducedOrder => "reduced-order",
            Kind::Formula => "formula",
        }
    }
    /// The kind of a name.
    pub fn parse(s: &str) -> Option<Self> {
        Kind::ALL.into_iter().find(|k| k.name() == s)
    }
}

/// Settings of a generated exercise.
#[derive(Clone, Debug)]
pub struct Settings {
    /// What it asks (pole placement unless said).
    pub kind: Kind,
    /// Smallest order.
    pub min_order: usize,
    /// Largest order.
    pub max_order: usize,
    /// Seed.
    pub seed: u64,
    /// `a-kc` or `a+lc`.
    pub convention: String,
}

impl Settings {
    /// `N` or `N..M`, as `--order` takes it.
    pub fn order(&self) -> String {
        if self.min_order == self.max_order {
            self.min_order.to_string()
        } else {
            format!("{}..{}", self.min_order, self.max_order)
        }
    }

    /// The command that generates this exercise again, every setting written out.
    pub fn command(&self) -> String {
        format!(
            "owb exercise new --kind {} --order {} --convention {} --seed {}",
            self.kind.name(),
            self.order(),
            self.convention,
            self.seed
        )
    }

    /// The exercise's id: one per seed, order range and convention (the same seed with another
    /// order gives another exercise, so another id).
    pub fn id(&self) -> String {
        format!(
            "generated-{}-{}-order-{}{}",
            self.kind.name(),
            self.seed,
            self.order().replace("..", "-"),
            if self.convention == "a+lc" { "-lc" } else { "" }
        )
    }
}

impl Settings {
    /// A student's own variant: the seed is [`student_seed`] of the id, so the teacher
    /// regenerates the same exercise from the student's id alone (`owb exercise new --student`).
    pub fn for_student(
        student: &str,
        min_order: usize,
        max_order: usize,
        convention: &str,
    ) -> Self {
        Settings {
            kind: Kind::PolePlacement,
            min_order,
            max_order,
            seed: student_seed(student),
            convention: convention.to_string(),
        }
    }

    /// The settings an id names ([`Settings::id`] read back), or `None` if it names no
    /// generated exercise.
    ///
    /// ```
    /// use observer_workbench::exercise::generate::Settings;
    /// let s = Settings::from_id("generated-pole-placement-11-order-2-3-lc").unwrap();
    /// assert_eq!((s.seed, s.min_order, s.max_order, s.convention.as_str()), (11, 2, 3, "a+lc"));
    /// assert_eq!(s.id(), "generated-pole-placement-11-order-2-3-lc");
    /// ```
    pub fn from_id(id: &str) -> Option<Self> {
        let rest = id.strip_prefix("generated-")?;
        let kind = Kind::ALL
            .into_iter()
            .find(|k| rest.starts_with(&format!("{}-", k.name())))?;
        let rest = &rest[kind.name().len() + 1..];
        let (rest, convention) = match rest.strip_suffix("-lc") {
            Some(r) => (r, "a+lc"),
            None => (rest, "a-kc"),
        };
        let (seed, order) = rest.split_once("-order-")?;
        let (lo, hi) = order.split_once('-').unwrap_or((order, order));
        let s = Settings {
            kind,
            min_order: lo.parse().ok()?,
            max_order: hi.parse().ok()?,
            seed: seed.parse().ok()?,
            convention: convention.to_string(),
        };
        // only the id's own spelling (no leading zeros, no `N-N` for one order)
        (s.id() == id).then_some(s)
    }
}

/// The seed of a student's own exercise: FNV-1a (64 bits) of the id with surrounding spaces
/// removed and letters lower-cased, so "Alice " and "alice" get the same exercise. The browser
/// (the course book) and `owb exercise new --student` compute it with this same function.
///
/// ```
/// use observer_workbench::exercise::generate::student_seed;
/// assert_eq!(student_seed(" Alice"), student_seed("alice"));
/// assert_ne!(student_seed("alice"), student_seed("bob"));
/// ```
pub fn student_seed(student: &str) -> u64 {
    student
        .trim()
        .to_lowercase()
        .bytes()
        .fold(0xcbf2_9ce4_8422_2325, |h, b| {
            (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
        })
}

struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn range(&mut self, lo: i64, hi: i64) -> i64 {
        lo + (self.next() % (hi - lo + 1) as u64) as i64
    }
}

fn int(x: i64) -> Rational {
    Rational::from_integer(x.into())
}

fn largest(m: &Matrix<Rational>) -> Rational {
    let mut top = int(0);
    for i in 0..m.rows() {
        for j in 0..m.cols() {
            let v = m.get(i, j).clone();
            let a = if v < int(0) { -v } else { v };
            if a > top {
                top = a;
            }
        }
    }
    top
}

/// Why no exercise could be generated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GenerateError {
    /// The order range is empty or too large for hand computation.
    #[error(
        "order range {0}..{1}: give 1 ≤ min ≤ max ≤ 5 (larger orders are no hand computation)"
    )]
    Orders(usize, usize),
    /// Unknown convention.
    #[error("convention '{0}': use a-kc or a+lc")]
    Convention(String),
    /// A reduced-order exercise needs an unmeasured state.
    #[error("order range {0}..{1}: a reduced-order exercise needs order 2 or more (one state is measured)")]
    ReducedOrder(usize, usize),
}

/// A plant `x = T x_o` from a random observer canonical form (small-integer open-loop poles,
/// a unimodular `T` with entries in {−1, 0, 1}) and `n` distinct desired poles in −1 … −6,
/// drawn until every number a student meets stays small.
fn random_plant(
    rng: &mut Rng,
    n: usize,
    keep_first: bool,
) -> (Matrix<Rational>, Matrix<Rational>, Vec<i64>) {
    loop {
        // open-loop poles: small integers (a stable, marginal or unstable plant)
        let open: Vec<Rational> = (0..n).map(|_| int(rng.range(-3, 2))).collect();
        let coeffs = Poly::from_roots(&open, "s");
        // observer canonical form: first column −a_1 … −a_n, superdiagonal ones
        let a_o = Matrix::from_fn(n, n, |i, j| {
            if j == 0 {
                -coeffs.coeff(n - 1 - i)
            } else if j == i + 1 {
                int(1)
            } else {
                int(0)
            }
        });
        let c_o = Matrix::from_fn(1, n, |_, j| if j == 0 { int(1) } else { int(0) });
        // unimodular T: unit lower times unit upper triangular, entries in {−1, 0, 1}
        // (keep_first: T leaves the first coordinate alone, so C stays [1 0 … 0]; the same
        // numbers are drawn either way, so a seed's pole-placement plant does not change)
        let lower = Matrix::from_fn(n, n, |i, j| match i.cmp(&j) {
            std::cmp::Ordering::Equal => int(1),
            std::cmp::Ordering::Greater => {
                let v = rng.range(-1, 1);
                int(if keep_first && j == 0 { 0 } else { v })
            }
            std::cmp::Ordering::Less => int(0),
        });
        let upper = Matrix::from_fn(n, n, |i, j| match i.cmp(&j) {
            std::cmp::Ordering::Equal => int(1),
            std::cmp::Ordering::Less => {
                let v = rng.range(-1, 1);
                int(if keep_first && i == 0 { 0 } else { v })
            }
            std::cmp::Ordering::Greater => int(0),
        });
        let Ok(t) = lower.mul(&upper) else { continue };
        let Ok(t_inv) = linalg::inverse(&t) else {
            continue;
        };
        let (Ok(ta), Ok(c)) = (t.mul(&a_o), c_o.mul(&t_inv)) else {
            continue;
        };
        let Ok(a) = ta.mul(&t_inv) else { continue };
        let mut candidates: Vec<i64> = (1..=6).map(|k| -k).collect();
        let mut poles = Vec::new();
        for _ in 0..n {
            let k = rng.range(0, candidates.len() as i64 - 1) as usize;
            poles.push(candidates.remove(k));
        }
        poles.sort_unstable_by(|x, y| y.cmp(x));
        if largest(&a) <= int(9) && largest(&t_inv) <= int(3) && largest(&c) <= int(3) {
            return (a, c, poles);
        }
    }
}

/// The exercise file for the drawn plant.
fn exercise_text(
    s: &Settings,
    n: usize,
    a: &Matrix<Rational>,
    c: &Matrix<Rational>,
    poles: &[i64],
) -> String {
    let poles_text = poles
        .iter()
        .map(ToString::to_string)
        .collect::<Vec<_>>()
        .join(", ");
    let letter = if s.convention == "a-kc" { "K" } else { "L" };
    let matrix = if s.convention == "a-kc" {
        "A − KC"
    } else {
        "A + LC"
    };
    format!(
        r#"id = "{id}"
title = "Observer pole placement, order {n} (generated)"
source = "generated by {command}"
statement = """
For the system ẋ = A x, y = C x with

A = {a}, C = {c},

1. form the observability matrix O and decide whether the pair (A, C) is observable;
2. find the transformation T to observer canonical form (x = T x_o, A_o = T⁻¹ A T, C_o = C T = [1 0 … 0]) and A_o, C_o;
3. read off the open-loop characteristic polynomial;
4. write the desired observer polynomial for the poles {poles_text};
5. find the observer gain in canonical coordinates and then the gain {letter} of the original system, for the observer matrix {matrix}.
"""

[system]
A = "{a}"
C = "{c}"

[design]
convention = "{conv}"
poles = "{poles_text}"

[[parts]]
id = "O"
ask = "observability_matrix"
prompt = "the observability matrix O = [C; CA; …]"

[[parts]]
id = "observable"
ask = "observable"
prompt = "is (A, C) observable? (yes / no)"

[[parts]]
id = "T"
ask = "canonical_transformation"
prompt = "the transformation T (x = T x_o)"

[[parts]]
id = "A_o"
ask = "canonical_a"
prompt = "A_o = T⁻¹ A T"

[[parts]]
id = "C_o"
ask = "canonical_c"
prompt = "C_o = C T"

[[parts]]
id = "open_loop"
ask = "characteristic_polynomial"
prompt = "the open-loop characteristic polynomial det(sI − A)"

[[parts]]
id = "desired"
ask = "desired_polynomial"
prompt = "the desired observer polynomial"

[[parts]]
id = "{letter}_o"
ask = "canonical_gain"
prompt = "the gain in canonical coordinates ({matrix} convention)"
partial = {{ sign_convention = 0.5 }}

[[parts]]
id = "{letter}"
ask = "gain"
prompt = "the observer gain {letter} ({matrix})"
points = 2
partial = {{ sign_convention = 0.5, canonical_coordinates = 0.5, slip = 0.5, reversed = 0.25, transposed = 0.75 }}
"#,
        id = s.id(),
        command = s.command(),
        a = a.to_input(),
        c = c.to_input(),
        conv = s.convention,
    )
}

/// A generated exercise file (TOML text) of the settings' kind (the name is historical: every
/// kind is generated here).
///
/// # Errors
/// [`GenerateError`] for a bad order range or convention.
pub fn pole_placement(s: &Settings) -> Result<String, GenerateError> {
    if s.min_order == 0 || s.min_order > s.max_order || s.max_order > 5 {
        return Err(GenerateError::Orders(s.min_order, s.max_order));
    }
    if s.convention != "a-kc" && s.convention != "a+lc" {
        return Err(GenerateError::Convention(s.convention.clone()));
    }
    if s.kind == Kind::ReducedOrder && s.min_order < 2 {
        return Err(GenerateError::ReducedOrder(s.min_order, s.max_order));
    }
    let mut rng = Rng(s.seed ^ 0x5EED_0B5E_7E7E_0001);
    let n = rng.range(s.min_order as i64, s.max_order as i64) as usize;
    let (a, c, poles) = random_plant(&mut rng, n, s.kind == Kind::ReducedOrder);
    Ok(match s.kind {
        Kind::PolePlacement => exercise_text(s, n, &a, &c, &poles),
        Kind::DeadBeat => deadbeat_text(s, n, &a, &c),
        Kind::ReducedOrder => reduced_order_text(s, n, &a, &poles[..n - 1]),
        Kind::Formula => formula_text(s, n, &parametrised(&mut rng, &a, &c), &c, &poles),
    })
}

/// A with one entry made the parameter `a`: the drawn entry if det O_n then depends on `a` (so
/// that "for which a is the pair unobservable?" has an answer), else the first such entry in
/// reading order, else one that keeps det O_n a nonzero number. Returns A as text.
fn parametrised(rng: &mut Rng, a: &Matrix<Rational>, c: &Matrix<Rational>) -> String {
    use crate::algebra::{Fraction, MultiPoly};
    let n = a.rows();
    let with_parameter = |k: usize| {
        Matrix::from_fn(n, n, |i, j| {
            if i * n + j == k {
                Fraction::of(MultiPoly::var("a"))
            } else {
                Fraction::constant(a.get(i, j).clone())
            }
        })
    };
    let lifted_c = c.map(|x| Fraction::constant(x.clone()));
    // 2: det O_n depends on a; 1: a nonzero number; 0: identically zero
    let grade = |k: usize| {
        let det = crate::observability::observability_matrix(&with_parameter(k), &lifted_c)
            .ok()
            .and_then(|o| linalg::determinant(&o).ok());
        match det {
            Some(d) if d.as_rational().is_none() => 2,
            Some(d) if !crate::algebra::Zero::is_zero(&d) => 1,
            _ => 0,
        }
    };
    let drawn = rng.range(0, (n * n) as i64 - 1) as usize;
    let order = || std::iter::once(drawn).chain(0..n * n);
    let k = order()
        .find(|&k| grade(k) == 2)
        .or_else(|| order().find(|&k| grade(k) == 1))
        .unwrap_or(drawn);
    let rows: Vec<String> = (0..n)
        .map(|i| {
            (0..n)
                .map(|j| {
                    if i * n + j == k {
                        "a".to_string()
                    } else {
                        a.get(i, j).to_string()
                    }
                })
                .collect::<Vec<_>>()
                .join(" ")
        })
        .collect();
    format!("[{}]", rows.join("; "))
}

/// The formula exercise: the gain and what it rests on, in the letters `a` and `w`.
fn formula_text(s: &Settings, n: usize, a: &str, c: &Matrix<Rational>, poles: &[i64]) -> String {
    let (letter, matrix) = letter_and_matrix(s);
    let poles_text = poles
        .iter()
        .map(|p| match p {
            -1 => "-w".to_string(),
            p => format!("{p}*w"),
        })
        .collect::<Vec<_>>()
        .join(", ");
    format!(
        r#"id = "{id}"
title = "An observer gain as a formula, order {n} (generated)"
source = "generated by {command}"
statement = """
For the system ẋ = A x, y = C x with

A = {a}, C = {c},

where a is a free parameter, and the observer poles {poles_text} (w > 0 sets the speed),
leave a and w as letters: every answer is a formula in them.

1. Give det O_n, the determinant of the observability matrix; for which a is the pair unobservable?
2. Give the desired observer polynomial.
3. Give the gain {letter} for the observer matrix {matrix}, as a formula in a and w.
"""

[system]
A = "{a}"
C = "{c}"

[design]
convention = "{conv}"
poles = "{poles_text}"

[[parts]]
id = "det_O"
ask = "observability_determinant"
prompt = "det O_n, as a formula in a"
partial = {{ negated = 0.5 }}

[[parts]]
id = "desired"
ask = "desired_polynomial"
prompt = "the desired observer polynomial, in s and w"
partial = {{ negated = 0.25 }}

[[parts]]
id = "{letter}"
ask = "gain"
prompt = "the observer gain {letter} ({matrix}) as a formula in a and w"
points = 2
partial = {{ sign_convention = 0.5, slip = 0.5, reversed = 0.25, transposed = 0.5, canonical_coordinates = 0.5, only_at_some_values = 0.25 }}
"#,
        id = s.id(),
        command = s.command(),
        c = c.to_input(),
        conv = s.convention,
    )
}

/// The dead-beat exercise: the plant read as discrete-time, every observer pole at z = 0.
fn deadbeat_text(s: &Settings, n: usize, a: &Matrix<Rational>, c: &Matrix<Rational>) -> String {
    let (letter, matrix) = letter_and_matrix(s);
    let zeros = vec!["0"; n].join(", ");
    format!(
        r#"id = "{id}"
title = "Dead-beat observer, order {n} (generated)"
source = "generated by {command}"
statement = """
For the discrete-time system x(k+1) = A x(k), y(k) = C x(k) with

A = {a}, C = {c},

1. form the observability matrix O;
2. give the open-loop characteristic polynomial det(λI − A);
3. design the prediction estimator x̄(k+1) = A x̄(k) + … with every observer pole at z = 0 (dead-beat): give the gain {letter} for the observer matrix {matrix};
4. after how many steps is the estimation error exactly zero, whatever the initial error?
"""

[system]
A = "{a}"
C = "{c}"

[design]
convention = "{conv}"
poles = "{zeros}"

[[parts]]
id = "O"
ask = "observability_matrix"
prompt = "the observability matrix O = [C; CA; …]"

[[parts]]
id = "open_loop"
ask = "characteristic_polynomial"
prompt = "the open-loop polynomial det(λI − A)"

[[parts]]
id = "{letter}"
ask = "discrete_gain"
prompt = "the dead-beat gain {letter} ({matrix}, prediction estimator)"
points = 2
partial = {{ sign_convention = 0.5, current_estimator = 0.5, slip = 0.5, transposed = 0.75 }}

[[parts]]
id = "steps"
ask = "deadbeat_steps"
prompt = "the number of steps after which the error is zero"
"#,
        id = s.id(),
        command = s.command(),
        a = a.to_input(),
        c = c.to_input(),
        conv = s.convention,
    )
}

/// The reduced-order exercise: the plant measured at its first state, n − 1 observer poles.
fn reduced_order_text(s: &Settings, n: usize, a: &Matrix<Rational>, poles: &[i64]) -> String {
    let poles_text = poles
        .iter()
        .map(ToString::to_string)
        .collect::<Vec<_>>()
        .join(", ");
    let (sign, word) = if s.convention == "a-kc" {
        ("−", "A₂₂ − L A₁₂")
    } else {
        ("+", "A₂₂ + L A₁₂")
    };
    let c = (0..n)
        .map(|j| if j == 0 { "1" } else { "0" })
        .collect::<Vec<_>>()
        .join(" ");
    format!(
        r#"id = "{id}"
title = "Reduced-order observer, order {n} (generated)"
source = "generated by {command}"
statement = """
The system ẋ = A x, y = C x with

A = {a}, C = [{c}]

measures its first state. Design a reduced-order (Gopinath) observer for the other {m}:

1. split A into A₁₁ (1×1), A₁₂, A₂₁, A₂₂ (x₁ measured, x₂ … x_n not);
2. choose L so that the error matrix {word} has the poles {poles_text}: give L;
3. give the error polynomial det(sI − ({word})).
"""

[system]
A = "{a}"
C = "[{c}]"

[design]
convention = "{conv}"
poles = "{poles_text}"

[[parts]]
id = "L"
ask = "reduced_order_gain"
prompt = "the reduced-order gain L (error matrix A₂₂ {sign} L A₁₂)"
points = 2
partial = {{ sign_convention = 0.5, slip = 0.5, transposed = 0.75 }}

[[parts]]
id = "error_polynomial"
ask = "reduced_order_error_polynomial"
prompt = "the error polynomial, degree {m}"
"#,
        id = s.id(),
        command = s.command(),
        a = a.to_input(),
        m = n - 1,
        conv = s.convention,
    )
}

fn letter_and_matrix(s: &Settings) -> (&'static str, &'static str) {
    if s.convention == "a-kc" {
        ("K", "A − KC")
    } else {
        ("L", "A + LC")
    }
}
