//! Stability maps: a grid of robot poses over a list of planes, each pose assessed by a
//! [`StabilityCriterion`] in parallel with rayon (Kumar's Fig. 5; the library side of
//! `rappel stability`).
//!
//! Each [`MapPlane`] is a [`SlopePlane`] (slope, wheel friction) with a rectangle of its plane
//! frame to cover. Poses are laid on a square grid of step `step` starting at the rectangle's
//! lower corner, one pose per grid point. The tether at each pose comes from an [`AnchorSource`]
//! (a fixed anchor per plane, or any geometry a caller implements, e.g. anchors found by unfolding
//! a chain of planes); the robot's heading is fixed or faces away from its anchor. Every pose gets
//! a [`PoseVerdict`]; a pose that cannot be placed or solved is reported as
//! [`PoseOutcome::Failed`] with the reason instead of failing the whole map. Results come back in
//! grid order (plane, then row `y`, then column `x`) whatever the thread schedule.

use crate::robot::{PlanarPose, RobotModel, SlopePlane, TetherSpec, place};
use crate::traversability::StabilityCriterion;
use nalgebra::Point2;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// The largest number of poses one map may have (a guard against a mistyped grid step).
pub const MAX_POSES: usize = 10_000_000;
/// Tolerance (in grid steps) for including a rectangle's far edge in the grid.
pub const GRID_EDGE_TOLERANCE: f64 = 1e-9;

/// Why a map could not be made.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum MapError {
    /// The grid step or a plane rectangle is invalid; the message says which.
    #[error("invalid stability grid: {0}")]
    Grid(&'static str),
    /// The grid would have more poses than the limit enforced (at most [`MAX_POSES`]); use a
    /// larger step. The count is at least `.0` (counting stops past the limit).
    #[error("the grid has {0} poses or more, more than the limit {1}; use a larger step")]
    TooManyPoses(usize, usize),
}

/// A plane to cover: its slope and friction, and the rectangle `[x0, x1] × [y0, y1]` of its plane
/// frame (m).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct MapPlane {
    /// Slope and wheel friction.
    pub plane: SlopePlane,
    /// `[x0, x1]` across the slope.
    pub x_range: [f64; 2],
    /// `[y0, y1]` up the slope.
    pub y_range: [f64; 2],
}

/// Where the tether of a robot at a grid pose runs to.
pub trait AnchorSource: Sync {
    /// The tether of a robot at `position` (plane frame) on plane `plane` (index into the map's
    /// planes), or `None` for no tether.
    fn tether_at(&self, plane: usize, position: &Point2<f64>) -> Option<TetherSpec>;
}

/// No tether anywhere.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct NoTether;

impl AnchorSource for NoTether {
    fn tether_at(&self, _: usize, _: &Point2<f64>) -> Option<TetherSpec> {
        None
    }
}

/// One fixed tether per plane (index-aligned with the map's planes; missing entries: no tether).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FixedAnchors(pub Vec<Option<TetherSpec>>);

impl AnchorSource for FixedAnchors {
    fn tether_at(&self, plane: usize, _: &Point2<f64>) -> Option<TetherSpec> {
        self.0.get(plane).copied().flatten()
    }
}

/// How grid poses are oriented.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum Heading {
    /// A fixed heading (radians, counter-clockwise from up-slope).
    Fixed(f64),
    /// Facing away from the anchor (the rappelling pose); downhill without a tether.
    AwayFromAnchor,
}

/// The grid: step and heading rule.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct GridSpec {
    step: f64,
    heading: Heading,
}

impl GridSpec {
    /// A grid of step `step` (m, finite and positive) with heading rule `heading`.
    pub fn new(step: f64, heading: Heading) -> Result<Self, MapError> {
        if !(step.is_finite() && step > 0.0) {
            return Err(MapError::Grid("step must be finite and positive"));
        }
        if let Heading::Fixed(h) = heading
            && !h.is_finite()
        {
            return Err(MapError::Grid("heading must be finite"));
        }
        Ok(GridSpec { step, heading })
    }

    /// The grid step (m).
    pub fn step(&self) -> f64 {
        self.step
    }
}

/// The verdict at one pose.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum PoseOutcome {
    /// Statically stable, with the criterion's margin and the tether tension of the solution.
    Stable {
        /// The criterion's margin (larger is safer).
        margin: f64,
        /// Tether tension (N), if tethered.
        tether_tension: Option<f64>,
    },
    /// No static equilibrium.
    Unstable,
    /// The pose could not be assessed; the reason says why.
    Failed {
        /// The error message.
        reason: String,
    },
}

/// One assessed grid pose.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PoseVerdict {
    /// Index of the plane.
    pub plane: usize,
    /// The pose (plane frame).
    pub pose: PlanarPose,
    /// The verdict.
    pub outcome: PoseOutcome,
}

impl PoseVerdict {
    /// Whether the pose is stable.
    pub fn is_stable(&self) -> bool {
        matches!(self.outcome, PoseOutcome::Stable { .. })
    }
}

fn axis(range: [f64; 2], step: f64, limit: usize) -> Result<Vec<f64>, MapError> {
    if !(range[0].is_finite() && range[1].is_finite() && range[0] <= range[1]) {
        return Err(MapError::Grid("plane ranges must be finite with lo <= hi"));
    }
    let steps = ((range[1] - range[0]) / step + GRID_EDGE_TOLERANCE).floor();
    if steps >= limit as f64 {
        return Err(MapError::TooManyPoses(limit.saturating_add(1), limit));
    }
    Ok((0..=steps as usize)
        .map(|k| range[0] + k as f64 * step)
        .collect())
}

/// The grid positions of every plane, in grid order, at most [`MAX_POSES`].
pub fn grid_positions(
    planes: &[MapPlane],
    grid: &GridSpec,
) -> Result<Vec<(usize, Point2<f64>)>, MapError> {
    grid_positions_within(planes, grid, MAX_POSES)
}

/// [`grid_positions`] with at most `limit` poses (itself at most [`MAX_POSES`]): the count is
/// checked, plane by plane, before any position is stored, and the error names `limit`.
pub fn grid_positions_within(
    planes: &[MapPlane],
    grid: &GridSpec,
    limit: usize,
) -> Result<Vec<(usize, Point2<f64>)>, MapError> {
    let limit = limit.min(MAX_POSES);
    let mut total = 0usize;
    let mut axes = Vec::with_capacity(planes.len());
    for p in planes {
        let (xs, ys) = (
            axis(p.x_range, grid.step, limit)?,
            axis(p.y_range, grid.step, limit)?,
        );
        total = total.saturating_add(xs.len().saturating_mul(ys.len()));
        if total > limit {
            return Err(MapError::TooManyPoses(total, limit));
        }
        axes.push((xs, ys));
    }
    let mut out = Vec::with_capacity(total);
    for (i, (xs, ys)) in axes.iter().enumerate() {
        for y in ys {
            for x in xs {
                out.push((i, Point2::new(*x, *y)));
            }
        }
    }
    Ok(out)
}

fn heading_at(rule: Heading, position: &Point2<f64>, tether: Option<&TetherSpec>) -> f64 {
    match (rule, tether) {
        (Heading::Fixed(h), _) => h,
        (Heading::AwayFromAnchor, Some(t)) => {
            let (fx, fy) = (position.x - t.anchor.x, position.y - t.anchor.y);
            if fx.hypot(fy) > 0.0 {
                (-fx).atan2(fy)
            } else {
                std::f64::consts::PI
            }
        }
        (Heading::AwayFromAnchor, None) => std::f64::consts::PI,
    }
}

/// Assesses `robot` at every grid pose of `planes` with `criterion`, in parallel.
///
/// # Example
/// ```
/// use nalgebra::Point3;
/// use rappel_mechanics::four_wheel::FourWheelRover;
/// use rappel_mechanics::robot::{SlopePlane, TetherSpec};
/// use rappel_mechanics::stability_map::{stability_map, FixedAnchors, GridSpec, Heading, MapPlane};
/// use rappel_mechanics::tension_lp::TensionLimitedLp;
/// let plane = MapPlane { plane: SlopePlane::new(0.96, 0.4).unwrap(), x_range: [-4.0, 4.0], y_range: [0.0, 4.0] };
/// let anchors = FixedAnchors(vec![Some(TetherSpec { anchor: Point3::new(0.0, 10.0, 0.0), max_tension: Some(300.0) })]);
/// let grid = GridSpec::new(2.0, Heading::AwayFromAnchor).unwrap();
/// let map = stability_map(&FourWheelRover::default(), &TensionLimitedLp::default(), &[plane], &anchors, &grid).unwrap();
/// assert_eq!(map.len(), 15);
/// assert!(map.iter().any(|v| v.is_stable()) && map.iter().any(|v| !v.is_stable()));
/// ```
pub fn stability_map(
    robot: &dyn RobotModel,
    criterion: &dyn StabilityCriterion,
    planes: &[MapPlane],
    anchors: &dyn AnchorSource,
    grid: &GridSpec,
) -> Result<Vec<PoseVerdict>, MapError> {
    stability_map_until(robot, criterion, planes, anchors, grid, &|| false)
}

/// [`stability_map`] that asks `halt` before each pose (poses run in parallel) and leaves out
/// the poses it halts: once `halt` says `true` the map is partial (the poses assessed so far, in
/// grid order). The caller's condition (a time limit, a cancel flag) and its reason are the
/// caller's to keep; `|| false` is [`stability_map`].
///
/// ```
/// use nalgebra::Point3;
/// use rappel_mechanics::four_wheel::FourWheelRover;
/// use rappel_mechanics::robot::{SlopePlane, TetherSpec};
/// use rappel_mechanics::stability_map::{stability_map_until, FixedAnchors, GridSpec, Heading, MapPlane};
/// use rappel_mechanics::tension_lp::TensionLimitedLp;
/// let plane = MapPlane { plane: SlopePlane::new(0.96, 0.4).unwrap(), x_range: [-4.0, 4.0], y_range: [0.0, 4.0] };
/// let anchors = FixedAnchors(vec![None]);
/// let grid = GridSpec::new(2.0, Heading::AwayFromAnchor).unwrap();
/// let lp = TensionLimitedLp::default();
/// let none = stability_map_until(&FourWheelRover::default(), &lp, &[plane], &anchors, &grid, &|| true).unwrap();
/// assert!(none.is_empty());
/// ```
pub fn stability_map_until(
    robot: &dyn RobotModel,
    criterion: &dyn StabilityCriterion,
    planes: &[MapPlane],
    anchors: &dyn AnchorSource,
    grid: &GridSpec,
    halt: &(dyn Fn() -> bool + Sync),
) -> Result<Vec<PoseVerdict>, MapError> {
    let positions = grid_positions(planes, grid)?;
    Ok(positions
        .par_iter()
        .filter(|_| !halt())
        .map(|(i, position)| {
            let tether = anchors.tether_at(*i, position);
            let pose = PlanarPose {
                position: *position,
                heading: heading_at(grid.heading, position, tether.as_ref()),
            };
            let outcome = match place(robot, &pose, &planes[*i].plane, tether.as_ref()) {
                Err(e) => PoseOutcome::Failed {
                    reason: e.to_string(),
                },
                Ok(placed) => match criterion.assess(&placed) {
                    Ok(a) if a.stable => PoseOutcome::Stable {
                        margin: a.margin,
                        tether_tension: a.tether_tension,
                    },
                    Ok(_) => PoseOutcome::Unstable,
                    Err(e) => PoseOutcome::Failed {
                        reason: e.to_string(),
                    },
                },
            };
            PoseVerdict {
                plane: *i,
                pose,
                outcome,
            }
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_counts_and_validation() {
        let plane = MapPlane {
            plane: SlopePlane::new(0.2, 0.5).unwrap(),
            x_range: [0.0, 1.0],
            y_range: [0.0, 0.5],
        };
        let g = GridSpec::new(0.25, Heading::Fixed(0.0)).unwrap();
        assert_eq!(
            grid_positions(&[plane, plane], &g).unwrap().len(),
            2 * 5 * 3
        );
        assert!(GridSpec::new(0.0, Heading::AwayFromAnchor).is_err());
        let tiny = GridSpec::new(1e-6, Heading::AwayFromAnchor).unwrap();
        let big = MapPlane {
            x_range: [0.0, 100.0],
            y_range: [0.0, 100.0],
            ..plane
        };
        assert!(matches!(
            grid_positions(&[big], &tiny),
            Err(MapError::TooManyPoses(_, MAX_POSES))
        ));
        let bad = MapPlane {
            x_range: [1.0, 0.0],
            ..plane
        };
        assert!(grid_positions(&[bad], &g).is_err());
    }

    #[test]
    fn away_from_anchor_faces_downhill_below_the_anchor() {
        let t = TetherSpec {
            anchor: nalgebra::Point3::new(0.0, 10.0, 0.0),
            max_tension: None,
        };
        let h = heading_at(Heading::AwayFromAnchor, &Point2::new(0.0, 0.0), Some(&t));
        assert!((h.abs() - std::f64::consts::PI).abs() < 1e-12);
        let h = heading_at(Heading::AwayFromAnchor, &Point2::new(-10.0, 0.0), Some(&t));
        // Anchor up and to the right: forward points down-left, heading between π/2 and π.
        assert!(h > std::f64::consts::FRAC_PI_2 && h < std::f64::consts::PI);
    }
}
