//! Input signals `u(t)`.

use serde::Deserialize;

/// An input signal; in worked examples a TOML table with `kind = "…"`.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Signal {
    /// Zero.
    Zero,
    /// `amplitude` from `at` on (0 before).
    Step {
        /// Height.
        amplitude: f64,
        /// Switching time.
        #[serde(default)]
        at: f64,
    },
    /// `amplitude · sin(frequency · t + phase)`, frequency in rad/s.
    Sine {
        /// Amplitude.
        amplitude: f64,
        /// Angular frequency (rad/s).
        frequency: f64,
        /// Phase (rad).
        #[serde(default)]
        phase: f64,
    },
    /// ±`amplitude`, starting positive, with the given period (s).
    Square {
        /// Amplitude.
        amplitude: f64,
        /// Period (s).
        period: f64,
    },
    /// Piecewise constant: `values[i]` from `times[i]` on.
    Piecewise {
        /// Switching times, increasing.
        times: Vec<f64>,
        /// Values.
        values: Vec<f64>,
    },
    /// Samples, linearly interpolated (held at the ends), e.g. read from a CSV file.
    Samples {
        /// Times, increasing.
        times: Vec<f64>,
        /// Values.
        values: Vec<f64>,
    },
}

impl Signal {
    /// Checks the parameters.
    ///
    /// # Errors
    /// A message naming the bad parameter.
    pub fn check(&self) -> Result<(), String> {
        let finite = |x: f64, what: &str| {
            if x.is_finite() {
                Ok(())
            } else {
                Err(format!("{what} must be finite"))
            }
        };
        match self {
            Signal::Zero => Ok(()),
            Signal::Step { amplitude, at } => {
                finite(*amplitude, "amplitude").and(finite(*at, "at"))
            }
            Signal::Sine {
                amplitude,
                frequency,
                phase,
            } => finite(*amplitude, "amplitude")
                .and(finite(*frequency, "frequency"))
                .and(finite(*phase, "phase")),
            Signal::Square { amplitude, period } => {
                finite(*amplitude, "amplitude")?;
                if !(*period > 0.0 && period.is_finite()) {
                    return Err("period must be positive".into());
                }
                Ok(())
            }
            Signal::Piecewise { times, values } | Signal::Samples { times, values } => {
                if times.is_empty() || times.len() != values.len() {
                    return Err(format!(
                        "times and values must be non-empty and of equal length ({} and {})",
                        times.len(),
                        values.len()
                    ));
                }
                if times.windows(2).any(|w| w[1] < w[0])
                    || times.iter().chain(values).any(|x| !x.is_finite())
                {
                    return Err("times must increase and all entries be finite".into());
                }
                Ok(())
            }
        }
    }

    /// `u(t)`.
    pub fn value(&self, t: f64) -> f64 {
        match self {
            Signal::Zero => 0.0,
            Signal::Step { amplitude, at } => {
                if t >= *at {
                    *amplitude
                } else {
                    0.0
                }
            }
            Signal::Sine {
                amplitude,
                frequency,
                phase,
            } => amplitude * (frequency * t + phase).sin(),
            Signal::Square { amplitude, period } => {
                if (t / period).rem_euclid(1.0) < 0.5 {
                    *amplitude
                } else {
                    -amplitude
                }
            }
            Signal::Piecewise { times, values } => {
                let k = times.partition_point(|&s| s <= t);
                if k == 0 {
                    0.0
                } else {
                    values[k - 1]
                }
            }
            Signal::Samples { times, values } => {
                let k = times.partition_point(|&s| s <= t);
                if k == 0 {
                    values[0]
                } else if k == times.len() {
                    values[k - 1]
                } else {
                    let (t0, t1) = (times[k - 1], times[k]);
                    let w = if t1 > t0 { (t - t0) / (t1 - t0) } else { 0.0 };
                    values[k - 1] + w * (values[k] - values[k - 1])
                }
            }
        }
    }

    /// Reads `t,u` samples from CSV text (a header line is skipped if not numeric).
    ///
    /// # Errors
    /// The line and what is wrong with it.
    pub fn from_csv(text: &str) -> Result<Signal, String> {
        let mut times = Vec::new();
        let mut values = Vec::new();
        for (i, line) in text.lines().enumerate() {
            let line = line.trim();
            if line.is_empty() {
                continue;
            }
            let fields: Vec<&str> = line.split(',').map(str::trim).collect();
            let parsed: Result<Vec<f64>, _> = fields.iter().map(|f| f.parse::<f64>()).collect();
            match parsed {
                Ok(v) if v.len() >= 2 => {
                    times.push(v[0]);
                    values.push(v[1]);
                }
                Ok(_) => return Err(format!("line {}: expected 't,u'", i + 1)),
                Err(_) if i == 0 => continue,
                Err(e) => return Err(format!("line {}: {e}", i + 1)),
            }
        }
        let s = Signal::Samples { times, values };
        s.check()?;
        Ok(s)
    }
}
