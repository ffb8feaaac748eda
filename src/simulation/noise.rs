//! Seeded noise. The generator is SplitMix64 (fixed algorithm, no platform dependence);
//! Gaussian samples use the Box–Muller transform.

use serde::Deserialize;

/// A noise source; in worked examples a TOML table with `kind = "…"`.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum NoiseSpec {
    /// Uniform in `[−amplitude, amplitude]` (Baranowski's "amplitude 0.1").
    Uniform {
        /// Half-width.
        amplitude: f64,
        /// Seed.
        #[serde(default)]
        seed: u64,
    },
    /// Gaussian with standard deviation `sigma`.
    Gaussian {
        /// Standard deviation.
        sigma: f64,
        /// Seed.
        #[serde(default)]
        seed: u64,
    },
}

/// A running noise source.
#[derive(Clone, Debug)]
pub struct Noise {
    spec: NoiseSpec,
    state: u64,
    spare: Option<f64>,
}

impl Noise {
    /// A source from its spec.
    pub fn new(spec: &NoiseSpec) -> Noise {
        let seed = match spec {
            NoiseSpec::Uniform { seed, .. } | NoiseSpec::Gaussian { seed, .. } => *seed,
        };
        Noise {
            spec: spec.clone(),
            state: seed ^ 0x9E37_79B9_7F4A_7C15,
            spare: None,
        }
    }

    fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)`.
    fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// The next sample.
    pub fn sample(&mut self) -> f64 {
        match self.spec {
            NoiseSpec::Uniform { amplitude, .. } => amplitude * (2.0 * self.unit() - 1.0),
            NoiseSpec::Gaussian { sigma, .. } => {
                if let Some(s) = self.spare.take() {
                    return sigma * s;
                }
                let u1 = 1.0 - self.unit(); // (0, 1]
                let u2 = self.unit();
                let r = (-2.0 * u1.ln()).sqrt();
                let (s, c) = (2.0 * std::f64::consts::PI * u2).sin_cos();
                self.spare = Some(r * s);
                sigma * r * c
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_noise_has_the_stated_range_and_variance() {
        let mut n = Noise::new(&NoiseSpec::Uniform {
            amplitude: 0.1,
            seed: 7,
        });
        let v: Vec<f64> = (0..100_000).map(|_| n.sample()).collect();
        assert!(v.iter().all(|x| x.abs() <= 0.1));
        let var = v.iter().map(|x| x * x).sum::<f64>() / v.len() as f64;
        assert!((var - 0.01 / 3.0).abs() < 1e-4, "{var}");
    }

    #[test]
    fn gaussian_noise_has_the_stated_sigma() {
        let mut n = Noise::new(&NoiseSpec::Gaussian {
            sigma: 2.0,
            seed: 3,
        });
        let v: Vec<f64> = (0..100_000).map(|_| n.sample()).collect();
        let mean = v.iter().sum::<f64>() / v.len() as f64;
        let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / v.len() as f64;
        assert!(
            mean.abs() < 0.03 && (var.sqrt() - 2.0).abs() < 0.03,
            "{mean} {var}"
        );
    }
}
