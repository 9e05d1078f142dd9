//! The box-bounded Euclidean space `R^D` as an ABIT* state space, with direct informed sampling
//! in the prolate hyperspheroid whose foci are start and goal (Gammell et al. 2018).

use rand::RngExt;
use rand_chacha::ChaCha8Rng;

use super::settings::SettingsError;
use super::space::{Informed, StateSpace};

/// Attempts to hit the bounds when sampling the informed set before reporting
/// [`Informed::Missed`] (and attempts to hit the unit ball by rejection from its cube, whose
/// acceptance rate is at least 52% for D <= 3).
pub const INFORMED_ATTEMPTS: usize = 100;

/// `R^D` restricted to the axis-aligned box `[lo, hi]`; path cost is Euclidean length.
#[derive(Debug, Clone, PartialEq)]
pub struct RealVectorSpace<const D: usize> {
    lo: [f64; D],
    hi: [f64; D],
}

impl<const D: usize> RealVectorSpace<D> {
    /// The box `[lo, hi]`; every bound finite and `lo < hi` on every axis.
    pub fn new(lo: [f64; D], hi: [f64; D]) -> Result<Self, SettingsError> {
        for i in 0..D {
            if !(lo[i].is_finite() && hi[i].is_finite() && lo[i] < hi[i]) {
                return Err(SettingsError::OutOfRange {
                    name: "bounds",
                    value: format!("axis {i}: [{}, {}]", lo[i], hi[i]),
                    reason: "bounds must be finite with lo < hi",
                });
            }
        }
        Ok(Self { lo, hi })
    }

    /// Lower corner.
    pub fn lo(&self) -> [f64; D] {
        self.lo
    }

    /// Upper corner.
    pub fn hi(&self) -> [f64; D] {
        self.hi
    }

    /// Length of the box's diagonal (OMPL's "maximum extent").
    pub fn extent(&self) -> f64 {
        (0..D)
            .map(|i| (self.hi[i] - self.lo[i]).powi(2))
            .sum::<f64>()
            .sqrt()
    }

    /// Whether `p` lies in the closed box.
    pub fn contains(&self, p: &[f64; D]) -> bool {
        (0..D).all(|i| p[i] >= self.lo[i] && p[i] <= self.hi[i])
    }
}

/// Euclidean distance.
pub fn euclidean<const D: usize>(a: &[f64; D], b: &[f64; D]) -> f64 {
    (0..D).map(|i| (a[i] - b[i]).powi(2)).sum::<f64>().sqrt()
}

impl<const D: usize> StateSpace<D> for RealVectorSpace<D> {
    type State = [f64; D];

    fn sample_uniform(&self, rng: &mut ChaCha8Rng) -> [f64; D] {
        std::array::from_fn(|i| rng.random_range(self.lo[i]..self.hi[i]))
    }

    fn sample_informed(
        &self,
        rng: &mut ChaCha8Rng,
        start: &[f64; D],
        goal: &[f64; D],
        max_cost: f64,
    ) -> Informed<[f64; D]> {
        let c_min = euclidean(start, goal);
        if !(max_cost.is_finite() && max_cost > c_min && c_min > 0.0) {
            return Informed::Missed;
        }
        let centre: [f64; D] = std::array::from_fn(|i| 0.5 * (start[i] + goal[i]));
        let a1: [f64; D] = std::array::from_fn(|i| (goal[i] - start[i]) / c_min);
        // The Householder reflection H = I - 2 u u^T / |u|^2 with u = e1 - a1 maps e1 to a1.
        let u: [f64; D] = std::array::from_fn(|i| if i == 0 { 1.0 } else { 0.0 } - a1[i]);
        let uu: f64 = u.iter().map(|v| v * v).sum();
        let r1 = 0.5 * max_cost;
        let rj = 0.5 * (max_cost * max_cost - c_min * c_min).sqrt();
        for _ in 0..INFORMED_ATTEMPTS {
            let Some(ball) = unit_ball::<D>(rng) else {
                continue;
            };
            let l: [f64; D] = std::array::from_fn(|i| ball[i] * if i == 0 { r1 } else { rj });
            let ul: f64 = (0..D).map(|i| u[i] * l[i]).sum();
            let p: [f64; D] = std::array::from_fn(|i| {
                let hl = if uu > 1e-24 {
                    l[i] - 2.0 * u[i] * ul / uu
                } else {
                    l[i]
                };
                centre[i] + hl
            });
            if self.contains(&p) {
                return Informed::Sample(p);
            }
        }
        Informed::Missed
    }

    fn distance(&self, a: &[f64; D], b: &[f64; D]) -> f64 {
        euclidean(a, b)
    }

    fn cost_heuristic(&self, a: &[f64; D], b: &[f64; D]) -> f64 {
        euclidean(a, b)
    }

    fn interpolate(&self, a: &[f64; D], b: &[f64; D], t: f64) -> [f64; D] {
        std::array::from_fn(|i| a[i] + t * (b[i] - a[i]))
    }

    fn key(&self, s: &[f64; D]) -> [f64; D] {
        *s
    }

    fn dimension(&self) -> usize {
        D
    }
}

/// A point uniform in the unit ball, by rejection from the cube (bounded attempts).
fn unit_ball<const D: usize>(rng: &mut ChaCha8Rng) -> Option<[f64; D]> {
    for _ in 0..INFORMED_ATTEMPTS {
        let p: [f64; D] = std::array::from_fn(|_| rng.random_range(-1.0..1.0));
        if p.iter().map(|v| v * v).sum::<f64>() <= 1.0 {
            return Some(p);
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use rand::SeedableRng;

    use super::*;

    #[test]
    fn informed_samples_lie_in_the_ellipse_and_fill_it() {
        let space = RealVectorSpace::new([-10.0, -10.0], [10.0, 10.0]).unwrap();
        let (s, g) = ([-1.0, -1.0], [2.0, 3.0]);
        let c = 7.0;
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let mut far = 0;
        for _ in 0..2000 {
            let Informed::Sample(p) = space.sample_informed(&mut rng, &s, &g, c) else {
                panic!("the ellipse lies inside the bounds");
            };
            let f = euclidean(&s, &p) + euclidean(&p, &g);
            assert!(f <= c + 1e-9, "{p:?} outside the informed set: {f}");
            if f > 0.9 * c {
                far += 1;
            }
        }
        // Uniform in the ellipse: the shell f in (0.9c, c] holds a fixed, large share of the area.
        assert!(
            far > 300,
            "only {far} samples near the boundary: not uniform"
        );
    }

    #[test]
    fn bad_bounds_are_errors() {
        assert!(RealVectorSpace::new([0.0, 1.0], [1.0, 1.0]).is_err());
        assert!(RealVectorSpace::new([f64::NAN], [1.0]).is_err());
    }
}
