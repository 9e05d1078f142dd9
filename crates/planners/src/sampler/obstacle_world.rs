//! Obstacle worlds in `R^2` and `R^3`: axis-aligned boxes and spheres in a bounding box, with
//! OMPL's discrete motion checking, as a [`MotionValidator`] with no history.
//!
//! Semantics (shared with the OMPL peer in `benches/ompl_peer/`): a state is valid if it lies in
//! the closed bounds and in no closed obstacle; a motion is valid if its end state and the
//! interpolated states at `j / n`, `j = 1..n-1`, `n = ceil(length / (resolution * extent))` are
//! valid, where `extent` is the bounds' diagonal (OMPL's `setStateValidityCheckingResolution`),
//! checked in the order of OMPL's `DiscreteMotionValidator`: the end state, then by bisection.
//! Between checked states a motion may clip an obstacle by at most half a check step.

use std::collections::VecDeque;

use serde::{Deserialize, Serialize};
use thiserror::Error;

use super::real_vector::{RealVectorSpace, euclidean};
use super::space::StateSpace;
use super::validator::MotionValidator;

/// An obstacle in `R^D`.
#[derive(Debug, Clone, PartialEq)]
pub enum Obstacle<const D: usize> {
    /// The closed axis-aligned box `[min, max]`.
    Box {
        /// Lower corner.
        min: [f64; D],
        /// Upper corner.
        max: [f64; D],
    },
    /// The closed ball.
    Sphere {
        /// Centre.
        centre: [f64; D],
        /// Radius.
        radius: f64,
    },
}

impl<const D: usize> Obstacle<D> {
    /// Whether `p` is in the closed obstacle.
    pub fn contains(&self, p: &[f64; D]) -> bool {
        match self {
            Self::Box { min, max } => (0..D).all(|i| p[i] >= min[i] && p[i] <= max[i]),
            Self::Sphere { centre, radius } => {
                (0..D).map(|i| (p[i] - centre[i]).powi(2)).sum::<f64>() <= radius * radius
            }
        }
    }
}

/// A planning problem: bounds, obstacles, start, goal and the motion-check resolution.
#[derive(Debug, Clone, PartialEq)]
pub struct ObstacleWorld<const D: usize> {
    /// The state space.
    pub space: RealVectorSpace<D>,
    /// The obstacles.
    pub obstacles: Vec<Obstacle<D>>,
    /// Start state.
    pub start: [f64; D],
    /// Goal state.
    pub goal: [f64; D],
    /// Motion-check step as a fraction of the bounds' diagonal, in `(0, 1]`.
    pub resolution: f64,
}

impl<const D: usize> ObstacleWorld<D> {
    /// The check step length `resolution * extent`.
    pub fn step(&self) -> f64 {
        self.resolution * self.space.extent()
    }

    /// The discrete motion check with the state check `valid` (a counting wrapper in the
    /// tests): the motion's length if `to` and the interpolated states pass, else `None`; both
    /// ends must lie in the bounds. `to` is checked first, then the interior as
    /// [`ObstacleWorld::interior_with`] checks it: exactly OMPL's `DiscreteMotionValidator`.
    pub fn motion_with(
        &self,
        from: &[f64; D],
        to: &[f64; D],
        mut valid: impl FnMut(&[f64; D]) -> bool,
    ) -> Option<f64> {
        if !self.space.contains(from) || !self.space.contains(to) || !valid(to) {
            return None;
        }
        self.interior_with(from, to, valid)
    }

    /// The motion check the planner makes ([`MotionValidator::motion`], and the counting
    /// wrapper of the native OMPL peer): the motion's length if its interpolated states at
    /// `j / n`, `j = 1..n-1`, pass `valid`, else `None`; both ends must lie in the bounds. The
    /// end state `to` is *not* checked: the planner only asks for motions into its graph's
    /// states, each of which passed [`MotionValidator::state_valid`] when it was added, so
    /// OMPL's check of the end state again is one redundant state check per motion (5 % of
    /// the checks to the first solution on `narrow_2d`, `docs/sampler.md`).
    pub fn interior_with(
        &self,
        from: &[f64; D],
        to: &[f64; D],
        mut valid: impl FnMut(&[f64; D]) -> bool,
    ) -> Option<f64> {
        if !self.space.contains(from) || !self.space.contains(to) {
            return None;
        }
        let len = euclidean(from, to);
        // Bounded: both ends lie in the bounds, so length <= diagonal and n <= 1 / resolution + 1.
        let n = (len / self.step()).ceil().max(1.0) as usize;
        if n >= 2 {
            // OMPL's `DiscreteMotionValidator` order: the middle index of an interval of unchecked
            // indices first, the two halves queued first in, first out. The verdict is that of
            // any order; the number of states checked before an invalid one is OMPL's.
            let mut intervals = VecDeque::from([(1, n - 1)]);
            while let Some((a, b)) = intervals.pop_front() {
                let mid = (a + b) / 2;
                let p = self.space.interpolate(from, to, mid as f64 / n as f64);
                if !valid(&p) {
                    return None;
                }
                if a < mid {
                    intervals.push_back((a, mid - 1));
                }
                if b > mid {
                    intervals.push_back((mid + 1, b));
                }
            }
        }
        Some(len)
    }
}

impl<const D: usize> MotionValidator<RealVectorSpace<D>, D> for ObstacleWorld<D> {
    type History = ();

    fn initial_history(&self, _start: &[f64; D]) {}

    fn state_valid(&self, s: &[f64; D]) -> bool {
        self.space.contains(s) && !self.obstacles.iter().any(|o| o.contains(s))
    }

    /// [`ObstacleWorld::interior_with`]: `to` is a graph state, valid already.
    fn motion(&self, from: &[f64; D], _history: &(), to: &[f64; D]) -> Option<(f64, ())> {
        self.interior_with(from, to, |p| self.state_valid(p))
            .map(|c| (c, ()))
    }
}

/// The JSON form of an [`ObstacleWorld`], read by the OMPL peer script too.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WorldFile {
    /// A name for reports.
    pub name: String,
    /// Lower corner of the bounds.
    pub lo: Vec<f64>,
    /// Upper corner of the bounds.
    pub hi: Vec<f64>,
    /// Axis-aligned boxes.
    #[serde(default)]
    pub boxes: Vec<BoxFile>,
    /// Spheres.
    #[serde(default)]
    pub spheres: Vec<SphereFile>,
    /// Start state.
    pub start: Vec<f64>,
    /// Goal state.
    pub goal: Vec<f64>,
    /// Motion-check step as a fraction of the bounds' diagonal.
    pub resolution: f64,
}

/// A box in a [`WorldFile`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoxFile {
    /// Lower corner.
    pub min: Vec<f64>,
    /// Upper corner.
    pub max: Vec<f64>,
}

/// A sphere in a [`WorldFile`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphereFile {
    /// Centre.
    pub centre: Vec<f64>,
    /// Radius.
    pub radius: f64,
}

/// A world file that does not describe a valid world, with the field at fault.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum WorldError {
    /// A vector has the wrong number of coordinates.
    #[error("{field}: expected {expected} coordinates, found {found}")]
    Dimension {
        /// The field, e.g. `boxes[2].min`.
        field: String,
        /// The world's dimension.
        expected: usize,
        /// What the file has.
        found: usize,
    },
    /// A value is non-finite or out of range.
    #[error("{field}: {reason}")]
    Value {
        /// The field.
        field: String,
        /// What is wrong.
        reason: String,
    },
}

fn arr<const D: usize>(field: String, v: &[f64]) -> Result<[f64; D], WorldError> {
    let a: [f64; D] = v.try_into().map_err(|_| WorldError::Dimension {
        field: field.clone(),
        expected: D,
        found: v.len(),
    })?;
    if a.iter().any(|c| !c.is_finite()) {
        return Err(WorldError::Value {
            field,
            reason: "non-finite coordinate".into(),
        });
    }
    Ok(a)
}

impl WorldFile {
    /// The world in `D` dimensions, checked field by field.
    pub fn to_world<const D: usize>(&self) -> Result<ObstacleWorld<D>, WorldError> {
        let lo = arr::<D>("lo".into(), &self.lo)?;
        let hi = arr::<D>("hi".into(), &self.hi)?;
        let space = RealVectorSpace::new(lo, hi).map_err(|e| WorldError::Value {
            field: "lo/hi".into(),
            reason: e.to_string(),
        })?;
        let mut obstacles = Vec::with_capacity(self.boxes.len() + self.spheres.len());
        for (i, b) in self.boxes.iter().enumerate() {
            let min = arr::<D>(format!("boxes[{i}].min"), &b.min)?;
            let max = arr::<D>(format!("boxes[{i}].max"), &b.max)?;
            if (0..D).any(|k| min[k] > max[k]) {
                return Err(WorldError::Value {
                    field: format!("boxes[{i}]"),
                    reason: "min > max on some axis".into(),
                });
            }
            obstacles.push(Obstacle::Box { min, max });
        }
        for (i, s) in self.spheres.iter().enumerate() {
            let centre = arr::<D>(format!("spheres[{i}].centre"), &s.centre)?;
            if !(s.radius.is_finite() && s.radius > 0.0) {
                return Err(WorldError::Value {
                    field: format!("spheres[{i}].radius"),
                    reason: format!("{} is not a positive finite radius", s.radius),
                });
            }
            obstacles.push(Obstacle::Sphere {
                centre,
                radius: s.radius,
            });
        }
        if !(self.resolution.is_finite() && self.resolution > 0.0 && self.resolution <= 1.0) {
            return Err(WorldError::Value {
                field: "resolution".into(),
                reason: format!("{} is not in (0, 1]", self.resolution),
            });
        }
        Ok(ObstacleWorld {
            space,
            obstacles,
            start: arr::<D>("start".into(), &self.start)?,
            goal: arr::<D>("goal".into(), &self.goal)?,
            resolution: self.resolution,
        })
    }

    /// The file form of `world`.
    pub fn from_world<const D: usize>(name: &str, world: &ObstacleWorld<D>) -> Self {
        let mut boxes = Vec::new();
        let mut spheres = Vec::new();
        for o in &world.obstacles {
            match o {
                Obstacle::Box { min, max } => boxes.push(BoxFile {
                    min: min.to_vec(),
                    max: max.to_vec(),
                }),
                Obstacle::Sphere { centre, radius } => spheres.push(SphereFile {
                    centre: centre.to_vec(),
                    radius: *radius,
                }),
            }
        }
        Self {
            name: name.into(),
            lo: world.space.lo().to_vec(),
            hi: world.space.hi().to_vec(),
            boxes,
            spheres,
            start: world.start.to_vec(),
            goal: world.goal.to_vec(),
            resolution: world.resolution,
        }
    }
}
