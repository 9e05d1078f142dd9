//! The options of the ABIT* planner as a validated builder: every setter checks its value and
//! returns a typed [`SettingsError`] naming the option, never panicking.

use thiserror::Error;

/// A rejected planner option.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SettingsError {
    /// An option's value is outside its documented range.
    #[error("setting `{name}` = {value}: {reason}")]
    OutOfRange {
        /// The option's name.
        name: &'static str,
        /// The rejected value, printed.
        value: String,
        /// The documented range.
        reason: &'static str,
    },
}

/// The options of [`super::Abit`]. Build with [`AbitSettings::default`] and the `with_*` setters.
///
/// | option | default | meaning |
/// |---|---|---|
/// | `batch_size` | 100 | samples added per batch (OMPL's `samples_per_batch`) |
/// | `rgg_k_factor` | 1.1 | OMPL's rewire factor: the RGG's `k = ceil(rgg_k_factor (e + e/d) ln n)`, the state itself among its k nearest, `n` counted before each batch (OMPL 1.5.2's `ImplicitGraph::calculateK`; 1.0 = Karaman & Frazzoli's minimum `k_RGG = e (1 + 1/d)`, 1.1 = OMPL's default) |
/// | `initial_inflation` | 1e6 | inflation of the cost-to-go in the first search of a batch (a greedy search) |
/// | `inflation_scaling` | 10.0 | the final search of a batch (once a solution exists) uses `1 + inflation_scaling / q` (q = OMPL's `numVertices + numSamples`: states in the tree plus locations) |
/// | `truncation_scaling` | 5.0 | a search stops once `(1 + truncation_scaling / q) f_min >= c_best` (q as above) |
/// | `history_copy_fraction` | 0.0 | fraction of new samples that copy a neighbour's history (Paton §V-A) |
/// | `biased_sample_fraction` | 0.0 | fraction of new samples drawn from the space's bias distribution ([`super::StateSpace::sample_biased`]); 0 = uniform (and informed) sampling only |
/// | `max_sample_attempts` | 10000 | rejection-sampling attempts per batch per requested sample, the bound of the sampling loop |
/// | `history_copies_on_expansion` | false | expanding a state next to one that a different history class claimed cheaper creates a copy of that location with undetermined history for this class (see `docs/sampler.md`) |
/// | `cascading_rewirings` | true | every expansion of a state queues its edges to states already in the tree (rewirings), as OMPL's ABIT* does; off, only a state's first expansion ever does, as OMPL's BIT* does (`SearchQueue::enqueueEdges`, `hasEverBeenExpandedAsRewiring`) |
/// | `seed` | 0 | the ChaCha8 seed: same seed, same settings, same iterations give the same path |
#[derive(Debug, Clone, PartialEq)]
pub struct AbitSettings {
    pub(crate) batch_size: usize,
    pub(crate) rgg_k_factor: f64,
    pub(crate) initial_inflation: f64,
    pub(crate) inflation_scaling: f64,
    pub(crate) truncation_scaling: f64,
    pub(crate) history_copy_fraction: f64,
    pub(crate) biased_sample_fraction: f64,
    pub(crate) max_sample_attempts: usize,
    pub(crate) history_copies_on_expansion: bool,
    pub(crate) cascading_rewirings: bool,
    pub(crate) seed: u64,
}

impl Default for AbitSettings {
    fn default() -> Self {
        Self {
            batch_size: 100,
            rgg_k_factor: 1.1,
            initial_inflation: 1e6,
            inflation_scaling: 10.0,
            truncation_scaling: 5.0,
            history_copy_fraction: 0.0,
            biased_sample_fraction: 0.0,
            max_sample_attempts: 10_000,
            history_copies_on_expansion: false,
            cascading_rewirings: true,
            seed: 0,
        }
    }
}

fn finite_at_least(
    name: &'static str,
    v: f64,
    lo: f64,
    reason: &'static str,
) -> Result<f64, SettingsError> {
    if v.is_finite() && v >= lo {
        Ok(v)
    } else {
        Err(SettingsError::OutOfRange {
            name,
            value: v.to_string(),
            reason,
        })
    }
}

impl AbitSettings {
    /// Samples per batch, in `1..=1_000_000`.
    pub fn with_batch_size(mut self, n: usize) -> Result<Self, SettingsError> {
        if !(1..=1_000_000).contains(&n) {
            return Err(SettingsError::OutOfRange {
                name: "batch_size",
                value: n.to_string(),
                reason: "must be in 1..=1000000",
            });
        }
        self.batch_size = n;
        Ok(self)
    }

    /// OMPL's rewire factor, the multiplier of the RGG's minimum `k_RGG = e (1 + 1/d)`:
    /// `k = ceil(f (e + e/d) ln n)` nearest locations, the state's own included (default 1.1,
    /// OMPL's; `docs/sampler.md`, "OMPL's neighbour count"). Finite and `>= 0.1`.
    pub fn with_rgg_k_factor(mut self, f: f64) -> Result<Self, SettingsError> {
        self.rgg_k_factor = finite_at_least("rgg_k_factor", f, 0.1, "must be finite and >= 0.1")?;
        Ok(self)
    }

    /// Inflation of the first search of each batch, finite and `>= 1`.
    pub fn with_initial_inflation(mut self, f: f64) -> Result<Self, SettingsError> {
        self.initial_inflation =
            finite_at_least("initial_inflation", f, 1.0, "must be finite and >= 1")?;
        Ok(self)
    }

    /// Scaling of the later inflation factors `1 + s / n`, finite and `>= 0`.
    pub fn with_inflation_scaling(mut self, s: f64) -> Result<Self, SettingsError> {
        self.inflation_scaling =
            finite_at_least("inflation_scaling", s, 0.0, "must be finite and >= 0")?;
        Ok(self)
    }

    /// Scaling of the truncation factor `1 + s / n`, finite and `>= 0`.
    pub fn with_truncation_scaling(mut self, s: f64) -> Result<Self, SettingsError> {
        self.truncation_scaling =
            finite_at_least("truncation_scaling", s, 0.0, "must be finite and >= 0")?;
        Ok(self)
    }

    /// Fraction of new samples that copy a neighbour's history, in `[0, 1]`.
    pub fn with_history_copy_fraction(mut self, f: f64) -> Result<Self, SettingsError> {
        if !(0.0..=1.0).contains(&f) {
            return Err(SettingsError::OutOfRange {
                name: "history_copy_fraction",
                value: f.to_string(),
                reason: "must be in [0, 1]",
            });
        }
        self.history_copy_fraction = f;
        Ok(self)
    }

    /// Fraction of new samples drawn from the space's bias distribution, in `[0, 1]`.
    pub fn with_biased_sample_fraction(mut self, f: f64) -> Result<Self, SettingsError> {
        if !(0.0..=1.0).contains(&f) {
            return Err(SettingsError::OutOfRange {
                name: "biased_sample_fraction",
                value: f.to_string(),
                reason: "must be in [0, 1]",
            });
        }
        self.biased_sample_fraction = f;
        Ok(self)
    }

    /// Rejection-sampling attempts per requested sample, in `1..=1_000_000`.
    pub fn with_max_sample_attempts(mut self, n: usize) -> Result<Self, SettingsError> {
        if !(1..=1_000_000).contains(&n) {
            return Err(SettingsError::OutOfRange {
                name: "max_sample_attempts",
                value: n.to_string(),
                reason: "must be in 1..=1000000",
            });
        }
        self.max_sample_attempts = n;
        Ok(self)
    }

    /// Whether expansions copy locations for other history classes (see the settings table).
    pub fn with_history_copies_on_expansion(mut self, on: bool) -> Self {
        self.history_copies_on_expansion = on;
        self
    }

    /// Whether every expansion of a state queues its rewiring edges (OMPL's ABIT*, the default)
    /// or only its first expansion ever (OMPL's BIT*); see the settings table.
    pub fn with_cascading_rewirings(mut self, on: bool) -> Self {
        self.cascading_rewirings = on;
        self
    }

    /// The random seed (any value).
    pub fn with_seed(mut self, seed: u64) -> Self {
        self.seed = seed;
        self
    }

    /// The random seed.
    pub fn seed(&self) -> u64 {
        self.seed
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_options_are_typed_errors_naming_the_option() {
        let s = AbitSettings::default();
        for (r, name) in [
            (s.clone().with_batch_size(0), "batch_size"),
            (s.clone().with_rgg_k_factor(f64::NAN), "rgg_k_factor"),
            (s.clone().with_initial_inflation(0.5), "initial_inflation"),
            (s.clone().with_inflation_scaling(-1.0), "inflation_scaling"),
            (
                s.clone().with_truncation_scaling(f64::INFINITY),
                "truncation_scaling",
            ),
            (
                s.clone().with_history_copy_fraction(1.5),
                "history_copy_fraction",
            ),
            (s.clone().with_max_sample_attempts(0), "max_sample_attempts"),
            (
                s.clone().with_biased_sample_fraction(f64::NAN),
                "biased_sample_fraction",
            ),
            (
                s.clone().with_biased_sample_fraction(-0.1),
                "biased_sample_fraction",
            ),
        ] {
            match r {
                Err(SettingsError::OutOfRange { name: n, .. }) => assert_eq!(n, name),
                Ok(_) => panic!("{name} accepted a bad value"),
            }
        }
        assert!(
            s.with_batch_size(50)
                .and_then(|s| s.with_history_copy_fraction(0.3))
                .is_ok()
        );
    }
}
