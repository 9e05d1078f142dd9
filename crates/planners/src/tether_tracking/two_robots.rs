//! Two robots on one tether (Kumar Problem 1): Robot 1 moves on the top surface and winds the
//! tether around obstacles while Robot 2 waits at its start; then Robot 2 descends, and at each of
//! its waypoints we report the tether configuration, Robot 1's holding limit (eq. 1), `T_2max` from
//! the actual windings (eq. 2, ground anchors included) and Robot 2's tension-limited stability LP
//! (eqs. 3a-3e) with the tether pulling towards its last anchor.
//!
//! How the paper's text is read where rappel's default differs is a [`TrackModel`]: which slope
//! changes hold ground anchors ([`GroundAnchorEdges`]), Robot 2 as its wheels or as Kumar's free
//! body of Fig. 4 ([`Robot2Contact`]), and the friction pyramid of eq. 3c ([`PyramidChoice`]).
//! [`TrackModel::default`] is rappel's model, [`TrackModel::kumar`] the paper's text as written.
//! The tether slides laterally at slope changes (Kumar's Assumption 2.2) in both: a ground anchor
//! is where the straight unfolded tether crosses the edge, recomputed at every step.
//!
//! Both phases use one [`TetherTracker`]: phase 1 with Robot 2's start as the base and Robot 1 as
//! the moving end, phase 2 on the reversed anchor list (turn sides flipped) with Robot 1 as the base
//! (Kumar: "the same algorithm can be used ... for the motion of Robot 1").

use super::{
    AnchorKind, GroundAnchorEdges, TetherAnchor, TetherTracker, TrackError, TrackSubject,
    windings_of,
};
use nalgebra::{Point2, Point3};
use rappel_mechanics::point_body::PointBody;
use rappel_mechanics::robot::{PlanarPose, RobotModel, SlopePlane, TetherSpec, place};
use rappel_mechanics::stability_error::StabilityError;
use rappel_mechanics::tension_limit::{HoldingRobot, TensionLimitError, tension_limit};
use rappel_mechanics::tension_lp::{FrictionPyramid, TensionLimitedLp};
use rappel_terrain::surface::Terrain;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// How Robot 2 meets the ground in the stability LP (Kumar eqs. 3a-3e).
#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum Robot2Contact {
    /// The robot model given ([`TwoRobots::robot2`]): a friction pyramid per wheel and a rigid
    /// body whose moments balance, the tether leaving at its exit height (rappel's default).
    #[default]
    Wheels,
    /// Kumar's free body (Fig. 4, eq. 3c): one ground force `(F_X, F_Y, F_Z)` in one pyramid
    /// aligned with the tether, weight, ground force and tether concurrent (a
    /// [`PointBody`] of the model's mass), the tether parallel to the surface.
    Body,
}

/// The friction pyramid of the stability LP (Kumar eq. 3c).
#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum PyramidChoice {
    /// Kumar's eq. 3c, `|F_X|, |F_Y| <= μ F_Z`: it contains the friction cone (optimistic off
    /// its axes by up to `sqrt 2`); the default.
    #[default]
    Circumscribed,
    /// `|F_X|, |F_Y| <= μ F_Z / sqrt 2`: inside the cone (conservative).
    Inscribed,
}

impl PyramidChoice {
    /// The mechanics crate's pyramid.
    pub fn pyramid(self) -> FrictionPyramid {
        match self {
            PyramidChoice::Circumscribed => FrictionPyramid::Circumscribed,
            PyramidChoice::Inscribed => FrictionPyramid::Inscribed,
        }
    }
}

/// How Kumar's text is read where rappel's default model departs from it (the input file's
/// `model` of `rappel track`; unknown fields are refused).
///
/// # Example
/// ```
/// use rappel_planners::tether_tracking::GroundAnchorEdges;
/// use rappel_planners::tether_tracking::two_robots::{PyramidChoice, Robot2Contact, TrackModel};
/// let ours = TrackModel::default();
/// assert_eq!(ours.ground_anchors, GroundAnchorEdges::Crests);
/// assert_eq!(ours.robot2, Robot2Contact::Wheels);
/// let paper = TrackModel::kumar();
/// assert_eq!(paper.ground_anchors, GroundAnchorEdges::Valleys);
/// assert_eq!(paper.robot2, Robot2Contact::Body);
/// assert_eq!(paper.friction_pyramid, PyramidChoice::Circumscribed);
/// let m: TrackModel = serde_json::from_str(r#"{"robot2": "body"}"#).unwrap();
/// assert_eq!(m.ground_anchors, GroundAnchorEdges::Crests);
/// assert!(serde_json::from_str::<TrackModel>(r#"{"robot_2": "body"}"#).is_err());
/// ```
#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(default, deny_unknown_fields)]
pub struct TrackModel {
    /// Which slope changes hold the tether as ground anchors (Kumar §III-A's "concave" changes;
    /// see [`GroundAnchorEdges`]).
    pub ground_anchors: GroundAnchorEdges,
    /// Robot 2 as its wheels or as Kumar's free body (Fig. 4).
    pub robot2: Robot2Contact,
    /// The friction pyramid (Kumar eq. 3c).
    pub friction_pyramid: PyramidChoice,
}

impl TrackModel {
    /// Kumar's text as written: ground anchors at valleys (§III-A's "concave" read as a
    /// hillside flattening downhill), Robot 2 as the free body of Fig. 4, the pyramid of eq. 3c.
    pub const fn kumar() -> Self {
        TrackModel {
            ground_anchors: GroundAnchorEdges::Valleys,
            robot2: Robot2Contact::Body,
            friction_pyramid: PyramidChoice::Circumscribed,
        }
    }
}

/// Why a two-robot run failed.
#[derive(Debug, thiserror::Error)]
pub enum TwoRobotError {
    /// A path step is refused.
    #[error("robot {robot}: {source}")]
    Track {
        /// 1 or 2.
        robot: u8,
        /// The tracker's objection.
        source: TrackError,
    },
    /// eq. 1-2 inputs are invalid.
    #[error(transparent)]
    Limit(#[from] TensionLimitError),
    /// The stability LP failed.
    #[error("robot 2 at waypoint {waypoint}: {source}")]
    Stability {
        /// Waypoint index.
        waypoint: usize,
        /// The LP's error.
        source: StabilityError,
    },
    /// Robot 2's surface is refused by the robot model (e.g. steeper than 89 degrees).
    #[error("robot 2 at waypoint {waypoint}: surface {surface} is out of the model's range")]
    Surface {
        /// Waypoint index.
        waypoint: usize,
        /// Surface index.
        surface: usize,
    },
}

/// Robot 2 at one waypoint.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
pub struct WaypointReport {
    /// Waypoint index in Robot 2's path.
    pub waypoint: usize,
    /// Robot 2's frame position.
    #[schemars(with = "[f64; 2]")]
    pub position: Point2<f64>,
    /// The surface it stands on.
    pub surface: usize,
    /// The tether from Robot 1 to Robot 2 (robot, obstacle and ground anchors).
    pub configuration: Vec<TetherAnchor>,
    /// Total winding angle (Kumar Definition 3), radians (reported in degrees).
    #[serde(
        rename = "total_winding_deg",
        with = "crate::report_units::radians_as_degrees"
    )]
    #[schemars(with = "f64")]
    pub total_winding: f64,
    /// `T_1` limit `F_0 + mu_s0 m_1 g` (eq. 1), N.
    pub t1_limit_n: f64,
    /// `T_2max` from the obstacle windings only (the paper's depicted values), N.
    pub t2max_obstacles_n: f64,
    /// `T_2max` from all windings, ground anchors included (eq. 2), N.
    pub t2max_n: f64,
    /// Whether a ground anchor lies between Robot 2 and its last obstacle anchor.
    pub ground_anchored: bool,
    /// The LP's verdict.
    pub stable: bool,
    /// The least tension that holds Robot 2, when stable.
    pub required_tension_n: Option<f64>,
}

/// Kumar's two robots.
pub struct TwoRobots<'a, T: Terrain + ?Sized> {
    /// The terrain.
    pub terrain: &'a T,
    /// Robot 1 (holding) parameters for eq. 1.
    pub holding: HoldingRobot,
    /// Gravity, m/s^2.
    pub gravity: f64,
    /// Robot 2's model.
    pub robot2: &'a (dyn RobotModel + Sync),
    /// Height of Robot 2's tether exit (the anchor height `h_t` in its plane frame), m.
    pub tether_height: f64,
    /// How the paper is read where rappel departs from it (default: rappel's model).
    pub model: TrackModel,
}

/// Reverses a configuration's obstacle anchors (base becomes end): turn sides flip.
fn reversed(anchors: &[TetherAnchor]) -> Vec<TetherAnchor> {
    anchors
        .iter()
        .rev()
        .map(|a| {
            let mut a = *a;
            if let AnchorKind::Obstacle { left, .. } = &mut a.kind {
                *left = !*left;
            }
            a
        })
        .collect()
}

impl<'a, T: Terrain + Sync + ?Sized> TwoRobots<'a, T> {
    /// Runs Problem 1: Robot 1 from `path1[0]` along `path1`, Robot 2 waiting at `path2[0]`, then
    /// Robot 2 along `path2`; one report per waypoint of `path2` (its start included).
    pub fn run(
        &self,
        path1: &[Point2<f64>],
        path2: &[Point2<f64>],
    ) -> Result<Vec<WaypointReport>, TwoRobotError> {
        let t1 = |source| TwoRobotError::Track { robot: 1, source };
        let t2 = |source| TwoRobotError::Track { robot: 2, source };
        let (Some(&s1), Some(&s2)) = (path1.first(), path2.first()) else {
            return Ok(Vec::new());
        };
        // Phase 1's tracker runs from Robot 2's start (its base) to Robot 1's start: an
        // objection to the base is about Robot 2's path, not Robot 1's.
        let edges = self.model.ground_anchors;
        let mut phase1 = TetherTracker::new(self.terrain, s2, s1).map_err(|e| match e.what() {
            Some(TrackSubject::Base) => t2(e.renamed("the start")),
            Some(TrackSubject::RobotStart) => t1(e.renamed("the start")),
            Some(TrackSubject::InitialTether) => t1(e.renamed("the tether from Robot 2's start")),
            _ => t1(e),
        })?;
        phase1.follow(&path1[1..]).map_err(t1)?;
        let r1 = phase1.robot();
        let anchors = reversed(phase1.obstacle_anchors());
        let mut phase2 = TetherTracker::with_anchors(self.terrain, r1, anchors, s2)
            .map_err(t2)?
            .with_ground_anchor_edges(edges);
        let t1_limit = self.holding.holding_limit(self.gravity)?;
        let mut out = Vec::with_capacity(path2.len());
        let mut lasts = Vec::with_capacity(path2.len());
        for (i, q) in path2.iter().enumerate() {
            if i > 0 {
                phase2.step(*q).map_err(t2)?;
            }
            let configuration = phase2.configuration();
            let windings = windings_of(self.terrain, &configuration);
            let obstacle_windings: Vec<(f64, f64)> = configuration
                .windows(3)
                .zip(&windings)
                .filter(|(w, _)| matches!(w[1].kind, AnchorKind::Obstacle { .. }))
                .map(|(_, x)| *x)
                .collect();
            let total_winding = windings.iter().map(|w| w.1).sum();
            let t2max = tension_limit(t1_limit, &windings)?;
            let t2max_obstacles = tension_limit(t1_limit, &obstacle_windings)?;
            let n = configuration.len();
            let last = configuration[n - 2];
            let ground_anchored = matches!(last.kind, AnchorKind::Ground { .. });
            let surface = self.terrain.surface_at(q).unwrap_or(0);
            lasts.push(last);
            // The verdict is filled in below, all waypoints at once.
            let (stable, required_tension) = (false, None);
            out.push(WaypointReport {
                waypoint: i,
                position: *q,
                surface,
                configuration,
                total_winding,
                t1_limit_n: t1_limit,
                t2max_obstacles_n: t2max_obstacles,
                t2max_n: t2max,
                ground_anchored,
                stable,
                required_tension_n: required_tension,
            });
        }
        // Robot 2's LP at every waypoint: independent of each other once the tether is tracked,
        // so in parallel (the first error by waypoint is reported, as a sequential run would).
        let verdicts: Vec<Result<(bool, Option<f64>), TwoRobotError>> = out
            .par_iter()
            .zip(lasts.par_iter())
            .map(|(w, last)| self.assess(w.waypoint, w.surface, &w.position, last, w.t2max_n))
            .collect();
        for (w, v) in out.iter_mut().zip(verdicts) {
            (w.stable, w.required_tension_n) = v?;
        }
        Ok(out)
    }

    /// Robot 2's LP on its surface, the tether pulling towards `last` (unfolded into the surface's
    /// plane, at the exit height), facing away from it.
    fn assess(
        &self,
        waypoint: usize,
        surface: usize,
        q: &Point2<f64>,
        last: &TetherAnchor,
        t2max: f64,
    ) -> Result<(bool, Option<f64>), TwoRobotError> {
        let plane = SlopePlane::new(
            self.terrain.slope_rad(surface),
            self.terrain.friction(surface),
        )
        .map_err(|_| TwoRobotError::Surface { waypoint, surface })?;
        // The surface's plane frame: x across, y up the fall line, from the robot's position.
        let chart = self.terrain.chart(surface);
        let n = self.terrain.normal(surface);
        let up = {
            let g = nalgebra::Vector3::z() - n * n.z;
            g.try_normalize(1e-12)
        };
        let anchor_world = self.terrain.fold(surface, &last.point);
        let here = chart.fold(q);
        let d = anchor_world - here;
        let (ax, ay) = match up {
            Some(up) => {
                let across = up.cross(&n);
                (d.dot(&across), d.dot(&up))
            }
            // A flat surface: any frame will do; use the chart's axes.
            None => (d.dot(&chart.u3), d.dot(&chart.w3)),
        };
        let heading = if ax.hypot(ay) > 0.0 {
            ax.atan2(-ay)
        } else {
            std::f64::consts::PI
        };
        let body;
        let (robot, height): (&dyn RobotModel, f64) = match self.model.robot2 {
            Robot2Contact::Wheels => (self.robot2, self.tether_height),
            Robot2Contact::Body => {
                body = PointBody::new(self.robot2.total_mass())
                    .map_err(|_| TwoRobotError::Surface { waypoint, surface })?;
                (&body, 0.0)
            }
        };
        let tether = TetherSpec {
            anchor: Point3::new(ax, ay, height),
            max_tension: Some(t2max),
        };
        let placed = place(
            robot,
            &PlanarPose::new(0.0, 0.0, heading),
            &plane,
            Some(&tether),
        )
        .map_err(|_| TwoRobotError::Surface { waypoint, surface })?;
        let r = TensionLimitedLp::default()
            .with_pyramid(self.model.friction_pyramid.pyramid())
            .check(&placed)
            .map_err(|source| TwoRobotError::Stability { waypoint, source })?;
        Ok((r.stable, r.required_tension))
    }
}
