//! Ascent feasibility of an SHP (thesis §2.4, Algorithm 5, Definitions 2.1-2.4, eq. 2.7): can the
//! robot climb back from the goal to the start with the tether drawn taut along the SHP, passing
//! its anchors one by one?
//!
//! # Anchors and angles
//! The SHP's anchors are `A = (a_0, a_1, .., a_n)`: the start `a_0` (the initial anchor) and the
//! map vertices the taut tether wraps, in order (thesis §2.4). `psi_j` is the SHP angle of anchor
//! `a_j`: the angle between the fall line (`-y`) and the tether segment from `a_{j-1}` down to
//! `a_j`, in `[0, pi]`. `theta_max_j` is the tether limit ([`TetherLimit`], eq. 2.7 for the point
//! robot) of the plane holding `a_j`.
//!
//! # Anchor reachable sets (Def. 2.1-2.2)
//! While `a_j` is the proximal anchor the robot holds at `q` when
//! - `q` lies in the **friction-cone wedge** of `a_j`: the angle between the fall line and
//!   `q - a_j` is below the tether limit of the plane holding `q` (on a convex series the wedge
//!   narrows band by band down the slope; a tether-free band admits every direction);
//! - `q` lies in the **visibility half-plane** of `a_j` (`j >= 1`): on the side of the line
//!   `L_j` through `a_{j-1}` and `a_j` to which the SHP turns at `a_j`; across `L_j` the tether
//!   leaves `a_j` and `a_{j-1}` becomes proximal (the visibility edge);
//! - `q` is in **free space and visible** from `a_j`: the tether runs straight from `a_j` to `q`.
//!
//! [`AnchorReachableSet`] stores the convex pieces "wedge ∩ half-plane ∩ plane band ∩ map box" as
//! polygons, for pictures; membership of a robot motion is decided as below.
//!
//! # Passability (Def. 2.3, §2.4.2) and Algorithm 5
//! Ascending, the robot starts at the goal with `a_n` proximal (the goal must lie in the wedge of
//! `a_n`: the taut tether must hold it there) and passes `a_n, a_{n-1}, .., a_1` in turn. Anchor
//! `a_j` is passable when
//! 1. `C_j` has a visibility edge: `theta_max_j > psi_j` (the ray `L_j` beyond `a_j` lies in the
//!    wedge of `a_j`);
//! 2. the robot crossing it stays held by `a_{j-1}`: `theta_max_{j-1} > psi_j` (plane of
//!    `a_{j-1}`);
//! 3. Alg. 5 lines 13-19: some point `q'` of the visibility edge `V = L_j ∩ C_j ∩ C_{j-1}`, kept
//!    `clearance` away from `a_j` and from the first obstacle the ray meets, can be reached from
//!    the robot's position `q` inside `C_j`: straight, or first in along the tether towards `a_j`
//!    and then across, the move staying in the wedge of `a_j` band by band and the triangle
//!    swept by the tether obstacle-free (its boundary a contractible loop in free space, exact).
//!    The reachable part of `V` is computed exactly, as intervals along `L_j` between critical
//!    values with one exact evaluation per interval (the private module `feasibility::crossing`
//!    documents the cells), not by trying points; the waypoint is the first point of it, a
//!    clearance in from its start, that keeps `clearance` from every anchor and is reached by a
//!    move keeping `clearance` from the anchors not yet released (else the first reachable one).
//!
//! The waypoints `q'` are the waypoints of the ascent (Alg. 5 line 19). An SHP is feasible
//! (Def. 2.4) when every intermediate anchor is passable; otherwise the report names the first
//! impassable one met on the way up and why ([`Impassability`]).

use crate::anchor_index::AnchorIndex;
pub use crate::anchor_index::Evaluation;
use crate::terrain::PlaneSeries;
use nalgebra::{Point2, Vector2};
use rappel_geometry::btm::Btm;
use rappel_geometry::map::Map;
use rappel_geometry::polygon::{Aabb, Polygon};
use rappel_geometry::predicates::{ray_side, ray_side_at_height};
use rappel_geometry::region::{Region, free_part};
use rappel_homotopy::crossing::Tracer;
use rappel_homotopy::funnel::{Anchor, Side, TautPath};
use rappel_homotopy::path::PathError;
use rappel_mechanics::anchor_traversability::TetherLimit;
use serde::{Deserialize, Serialize};

mod crossing;
pub use crossing::{MAX_PREFERENCE_CELLS, ROOMY_CLEARANCES, TIE_WIDTH_FRACTION};

/// Relative slack on clearance comparisons (distances are computed in floating point).
pub const CLEARANCE_TOLERANCE: f64 = 1e-9;
/// Smallest first step of the ladder of waypoint candidates along a visibility line, as a
/// fraction of the map's extent (the larger side of its bounding box), used when the clearance is
/// smaller: 0.05 m on the thesis' 100 m maps. Relative, so that a map drawn in millimetres or
/// kilometres plans as the same map in metres.
pub const MIN_WAYPOINT_STEP_FRACTION: f64 = 5e-4;

/// The angle between the fall line (`-y`) and the direction `v`, radians in `[0, pi]`.
pub fn angle_from_fall_line(v: &Vector2<f64>) -> f64 {
    v.x.abs().atan2(-v.y)
}

/// Distance from `p` to the closed segment `ab`.
pub fn distance_to_segment(p: &Point2<f64>, a: &Point2<f64>, b: &Point2<f64>) -> f64 {
    let d = b - a;
    let len2 = d.norm_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(&d) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + d * t - p).norm()
}

/// Why an anchor (or the goal) cannot be passed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Impassability {
    /// The taut tether cannot hold the robot at the goal: the last tether segment is at `psi`
    /// from the fall line, beyond the limit `max_angle` of the goal's plane.
    GoalOutsideReachableSet {
        /// Angle of the last tether segment from the fall line, radians.
        psi: f64,
        /// The limit, radians.
        max_angle: f64,
    },
    /// Condition 1 of §2.4.2 fails: `theta_max_j <= psi_j`, the anchor reachable set of `a_j` has
    /// no visibility edge.
    NoVisibilityEdge {
        /// `psi_j`, radians.
        psi: f64,
        /// `theta_max_j`, radians.
        max_angle: f64,
    },
    /// Condition 2 of §2.4.2 fails: `theta_max_{j-1} <= psi_j`, crossing the visibility edge the
    /// robot would not be held by `a_{j-1}`.
    OutsidePreviousReachableSet {
        /// `psi_j`, radians.
        psi: f64,
        /// `theta_max_{j-1}`, radians.
        max_angle: f64,
    },
    /// The taut tether from the start to the goal is longer than the robot's tether: the robot
    /// cannot reach the goal in this class, let alone climb back.
    TetherTooShort {
        /// The taut tether's length, m.
        needed: f64,
        /// The robot's tether length, m.
        available: f64,
    },
    /// Alg. 5 line 14: no point of the visibility edge can be reached from the robot's position
    /// inside the anchor reachable set (obstacles in the way, or the wedge too narrow).
    NoReachableWaypoint {
        /// The length of the usable visibility edge `V ∩ R_{j-1}` examined, m (0 when the
        /// visible ray has no point both wedges admit).
        usable: f64,
    },
}

impl Impassability {
    /// One line for reports.
    pub fn describe(&self) -> String {
        let deg = f64::to_degrees;
        match *self {
            Impassability::GoalOutsideReachableSet { psi, max_angle } => format!(
                "the taut tether cannot hold the robot at the goal: last segment at {:.2}° from the fall line >= theta_max {:.2}°",
                deg(psi),
                deg(max_angle)
            ),
            Impassability::NoVisibilityEdge { psi, max_angle } => format!(
                "no visibility edge: psi {:.2}° >= theta_max {:.2}° of its plane",
                deg(psi),
                deg(max_angle)
            ),
            Impassability::OutsidePreviousReachableSet { psi, max_angle } => format!(
                "crossing its visibility edge leaves the previous anchor's reachable set: psi {:.2}° >= theta_max {:.2}° of the previous anchor's plane",
                deg(psi),
                deg(max_angle)
            ),
            Impassability::TetherTooShort { needed, available } => format!(
                "the taut tether to the goal is {needed:.2} m long, more than the robot's {available:.2} m tether"
            ),
            Impassability::NoReachableWaypoint { usable } => format!(
                "no point of its visibility edge is reachable from the robot's position ({usable:.2} m usable)"
            ),
        }
    }
}

/// Whether an anchor can be passed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Passability {
    /// Passed, at this waypoint.
    Passable {
        /// The waypoint on the visibility edge.
        waypoint: Point2<f64>,
        /// A point the robot moves to first, straight towards the anchor along its tether, when
        /// the direct move would sweep the tether across an obstacle.
        via: Option<Point2<f64>>,
    },
    /// Not passable.
    Impassable(Impassability),
    /// Not examined: the ascent failed lower down.
    NotReached,
}

/// One intermediate anchor `a_j` examined by Alg. 5.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AnchorAssessment {
    /// `j`, from 1 (the anchor nearest the start) to `n`.
    pub index: usize,
    /// The anchor (vertex, obstacle, side, turning angle).
    pub anchor: Anchor,
    /// The plane holding it (`None` without planes).
    pub plane: Option<usize>,
    /// `psi_j`, radians.
    pub psi: f64,
    /// `theta_max_j`: the limit of its plane.
    pub limit: TetherLimit,
    /// `theta_max_{j-1}`: the limit of the previous anchor's plane.
    pub previous_limit: TetherLimit,
    /// The usable part of the visibility edge (`V ∩ R_{j-1}`), if examined and not empty.
    pub visibility_edge: Option<[Point2<f64>; 2]>,
    /// The part of it the robot reaches from its position while `a_j` is proximal, computed
    /// exactly as segments along `L_j`, nearest `a_j` first (empty if not examined or none).
    #[serde(default)]
    pub reachable_part: Vec<[Point2<f64>; 2]>,
    /// The verdict.
    pub passability: Passability,
}

/// An anchor reachable set `C_{i,j}` as convex polygons (module docs) with its visibility line.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AnchorReachableSet {
    /// `j` (0 for the start).
    pub anchor: usize,
    /// The anchor's position.
    pub apex: Point2<f64>,
    /// Convex pieces: wedge ∩ visibility half-plane ∩ band ∩ map box, one per band, each with its
    /// band's tether limit.
    pub pieces: Vec<(Polygon, TetherLimit)>,
    /// The same pieces cut to free space (inside the boundary, outside every obstacle): the
    /// anchor reachable set proper (thesis Def. 2.1), as regions with holes, each with its band's
    /// tether limit. For reports and pictures only, and only when asked for: empty until
    /// [`fill_reachable_areas`] computes them (a polygon overlay per piece; passability never
    /// looks at them).
    pub free_pieces: Vec<(Region, TetherLimit)>,
    /// Why `free_pieces` could not be computed (the overlay refused its input), if it could not.
    /// Passability does not depend on them.
    #[serde(default)]
    pub free_pieces_error: Option<String>,
    /// The visibility line `L_j` from `a_j` to the first obstacle along it (`j >= 1`).
    pub visibility_line: Option<[Point2<f64>; 2]>,
}

/// A corner of the ascent route.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RouteCorner {
    /// Its position.
    pub point: Point2<f64>,
    /// The lowest anchor index already released when the robot leaves this corner: `n + 1` at
    /// the goal and at a via point of `a_n`, `j` at the waypoint of `a_j`.
    pub released_from: usize,
}

/// The first thing that stops the ascent.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Blockage {
    /// The anchor index `j`, or `None` for the goal itself.
    pub anchor: Option<usize>,
    /// Why.
    pub reason: Impassability,
}

/// The outcome of Alg. 5 for one SHP.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FeasibilityReport {
    /// `psi` of the last tether segment (from `a_n` to the goal), radians.
    pub goal_psi: f64,
    /// The tether limit at the goal.
    pub goal_limit: TetherLimit,
    /// The intermediate anchors `a_1 .. a_n` in tether order.
    pub anchors: Vec<AnchorAssessment>,
    /// The anchor reachable sets the ascent met, by anchor index: `C_n` (holding the goal), then
    /// for each anchor `a_j` examined `C_{j-1}` (the set its visibility edge leads into); all of
    /// `C_0 .. C_n` when the ascent reaches the start or fails only at `a_1`. Sets above a
    /// blockage are not built (each traces its visibility line across the map).
    pub reachable_sets: Vec<AnchorReachableSet>,
    /// The waypoints in ascent order (passing `a_n` first).
    pub waypoints: Vec<Point2<f64>>,
    /// The ascent route found on the way: the goal, then for each anchor from `a_n` down to `a_1`
    /// its via point (if any) and its waypoint, then the start.
    pub route: Vec<RouteCorner>,
    /// `None` when feasible (Def. 2.4), else the first blockage met on the way up.
    pub blockage: Option<Blockage>,
}

impl FeasibilityReport {
    /// `true` when every anchor is passable.
    pub fn feasible(&self) -> bool {
        self.blockage.is_none()
    }

    /// One line: `feasible` or what blocks the ascent.
    pub fn describe(&self) -> String {
        match &self.blockage {
            None => "feasible".to_string(),
            Some(Blockage {
                anchor: None,
                reason,
            }) => reason.describe(),
            Some(Blockage {
                anchor: Some(j),
                reason,
            }) => {
                let a = &self.anchors[j - 1].anchor;
                let on = a.obstacle.map_or_else(
                    || "the map boundary".to_string(),
                    |o| format!("obstacle {o}"),
                );
                format!(
                    "anchor {j} (vertex {} on {on}): {}",
                    a.vertex,
                    reason.describe()
                )
            }
        }
    }
}

/// What Alg. 5 needs besides the SHP.
#[derive(Debug, Clone, Copy)]
pub struct FeasibilityContext<'a> {
    /// The BTM of the map.
    pub btm: &'a Btm,
    /// The planes and their tether limits.
    pub terrain: &'a PlaneSeries,
    /// Clearance kept by waypoints from anchors and obstacles along the visibility line, m.
    pub clearance: f64,
    /// The robot's tether length, m (`None`: unlimited). A class whose taut tether is longer is
    /// infeasible ([`Impassability::TetherTooShort`]).
    pub tether_length: Option<f64>,
}

/// Where the ascent stands while Alg. 5 walks up the anchors.
struct Climb<'c, 'a> {
    ctx: &'c FeasibilityContext<'a>,
    /// `a_0 .. a_n`.
    points: Vec<Point2<f64>>,
    /// Map box, for rays and polygons.
    bounds: Aabb,
    /// The intermediate anchors `a_1 .. a_n` in a grid, for the clearance queries.
    index: AnchorIndex,
    /// How anchor queries and cells are evaluated.
    evaluation: Evaluation,
    /// `own_waypoint[j]`: anchor `a_j` is its own waypoint (a solid friction anchor the robot
    /// drives over, thesis Alg. 10), index 0 unused.
    own_waypoint: Vec<bool>,
}

/// Runs Alg. 5 on the taut path `taut` (thesis §2.4.1-2.4.2; module docs).
///
/// ```
/// use nalgebra::Point2;
/// use rappel_geometry::{btm::Btm, map::Map, polygon::Polygon};
/// use rappel_terrain::plane_series::TerrainPlane;
/// use rappel_mechanics::friction_cone::TetherFrictionCone;
/// use rappel_planners::feasibility::{check_feasibility, FeasibilityContext};
/// use rappel_planners::spt::SptPlanner;
/// use rappel_planners::terrain::PlaneSeries;
/// let p = |x, y| Point2::new(x, y);
/// let map = Map::new(
///     Polygon::new(vec![p(0., 0.), p(40., 0.), p(40., 100.), p(0., 100.)]),
///     vec![Polygon::new(vec![p(18., 50.), p(22., 50.), p(22., 54.), p(18., 54.)])],
/// );
/// let btm = Btm::from_map(&map).unwrap();
/// let plane = TerrainPlane { y_top: 100.0, y_bottom: 0.0, slope_deg: 45.0, friction: 0.4 };
/// let terrain = PlaneSeries::new(&[plane], &TetherFrictionCone).unwrap();
/// let best = SptPlanner::new(&btm).shortest_path(p(21., 95.), p(20., 5.)).unwrap().unwrap();
/// let ctx = FeasibilityContext { btm: &btm, terrain: &terrain, clearance: 0.5, tether_length: None };
/// let report = check_feasibility(&ctx, &best.shp.taut);
/// assert!(report.feasible(), "{}", report.describe());
/// assert_eq!(report.waypoints.len(), best.shp.taut.anchors.len());
/// ```
pub fn check_feasibility(ctx: &FeasibilityContext<'_>, taut: &TautPath) -> FeasibilityReport {
    check_feasibility_with(ctx, taut, &|_| false)
}

/// [`check_feasibility`] where the anchors `a_j` with `own_waypoint(j)` (`j` from 1) are their
/// own waypoints: the robot drives along the tether onto the anchor itself, with no clearance
/// (thesis Alg. 10 at solid friction anchors: the robot may drive over a friction anchor). The
/// move is the tether's own segment toward `a_j`, in free space and in `C_j`; conditions 1 and 2
/// of §2.4.2 are still checked.
pub fn check_feasibility_with(
    ctx: &FeasibilityContext<'_>,
    taut: &TautPath,
    own_waypoint: &dyn Fn(usize) -> bool,
) -> FeasibilityReport {
    check_feasibility_evaluated(ctx, taut, own_waypoint, Evaluation::Indexed)
}

/// [`check_feasibility_with`] with the anchor queries and cells evaluated as `evaluation` says:
/// [`Evaluation::Indexed`] is what every planner uses; [`Evaluation::Direct`] is the earlier,
/// quadratic form, kept as the oracle of the equivalence tests (both give identical reports).
pub fn check_feasibility_evaluated(
    ctx: &FeasibilityContext<'_>,
    taut: &TautPath,
    own_waypoint: &dyn Fn(usize) -> bool,
    evaluation: Evaluation,
) -> FeasibilityReport {
    let d = ctx.btm.dcel();
    let bounds = Aabb::of_points(
        ctx.btm
            .boundary_vertices()
            .iter()
            .map(|&v| d.point(v))
            .collect::<Vec<_>>()
            .iter(),
    );
    let mut points = vec![taut.start()];
    points.extend(taut.anchors.iter().map(|a| a.point));
    let index = AnchorIndex::new(&points[1..], 2.0 * ctx.clearance, evaluation);
    let own_waypoint = (0..points.len())
        .map(|j| j > 0 && own_waypoint(j))
        .collect();
    let climb = Climb {
        ctx,
        points,
        bounds,
        index,
        evaluation,
        own_waypoint,
    };
    climb.run(taut)
}

/// Cuts every anchor reachable set of `report` to free space ([`AnchorReachableSet::free_pieces`]),
/// for reports and pictures: only when asked for, never in the decision path, and locally: with a
/// tether length, each set is first cut to the square of half-side "tether left at its anchor"
/// around the anchor (the robot cannot be farther), so the overlay sees only the obstacles there. Each piece is
/// overlaid with the boundary and with the obstacles whose bounding box meets the piece's (the
/// others are skipped by [`free_part`]); the map's polygons are gathered once per report. An
/// overlay that refuses its input leaves that set's `free_pieces_error` set.
///
/// ```
/// use nalgebra::Point2;
/// use rappel_geometry::{btm::Btm, map::Map, polygon::Polygon};
/// use rappel_terrain::plane_series::TerrainPlane;
/// use rappel_mechanics::friction_cone::TetherFrictionCone;
/// use rappel_planners::feasibility::{check_feasibility, fill_reachable_areas, FeasibilityContext};
/// use rappel_planners::spt::SptPlanner;
/// use rappel_planners::terrain::PlaneSeries;
/// let p = |x, y| Point2::new(x, y);
/// let map = Map::new(
///     Polygon::new(vec![p(0., 0.), p(40., 0.), p(40., 100.), p(0., 100.)]),
///     vec![Polygon::new(vec![p(18., 50.), p(22., 50.), p(22., 54.), p(18., 54.)])],
/// );
/// let btm = Btm::from_map(&map).unwrap();
/// let plane = TerrainPlane { y_top: 100.0, y_bottom: 0.0, slope_deg: 45.0, friction: 0.4 };
/// let terrain = PlaneSeries::new(&[plane], &TetherFrictionCone).unwrap();
/// let best = SptPlanner::new(&btm).shortest_path(p(21., 95.), p(20., 5.)).unwrap().unwrap();
/// let ctx = FeasibilityContext { btm: &btm, terrain: &terrain, clearance: 0.5, tether_length: None };
/// let mut report = check_feasibility(&ctx, &best.shp.taut);
/// assert!(report.reachable_sets.iter().all(|s| s.free_pieces.is_empty()));
/// fill_reachable_areas(&ctx, &mut report);
/// assert!(report.reachable_sets.iter().all(|s| !s.free_pieces.is_empty()));
/// ```
pub fn fill_reachable_areas(ctx: &FeasibilityContext<'_>, report: &mut FeasibilityReport) {
    let map: Map = ctx.btm.map();
    // The tether used up to each anchor: start, a_1, .., a_n along the taut path.
    let start = report.route.last().map(|c| c.point);
    let mut used = vec![0.0];
    if let Some(mut at) = start {
        for a in &report.anchors {
            used.push(used[used.len() - 1] + (a.anchor.point - at).norm());
            at = a.anchor.point;
        }
    }
    for set in &mut report.reachable_sets {
        set.free_pieces.clear();
        set.free_pieces_error = None;
        // With a tether of known length the set lies within the tether left at its anchor of
        // it: each piece is cut to that square around the anchor first, so only the obstacles
        // near the anchor enter the overlay.
        let reach = ctx
            .tether_length
            .zip(used.get(set.anchor))
            .map(|(total, used)| total - used);
        for (poly, limit) in &set.pieces {
            let local;
            let poly = match reach {
                Some(r) if r <= 0.0 => continue,
                Some(r) => {
                    let mut v = poly.vertices.clone();
                    let a = set.apex;
                    for (origin, dir) in [
                        (Point2::new(a.x, a.y - r), Vector2::new(1.0, 0.0)),
                        (Point2::new(a.x + r, a.y), Vector2::new(0.0, 1.0)),
                        (Point2::new(a.x, a.y + r), Vector2::new(-1.0, 0.0)),
                        (Point2::new(a.x - r, a.y), Vector2::new(0.0, -1.0)),
                    ] {
                        v = clip(&v, &origin, &dir);
                    }
                    if v.len() < 3 {
                        continue;
                    }
                    local = Polygon::new(v);
                    &local
                }
                None => poly,
            };
            match free_part(poly, &map.boundary, &map.obstacles) {
                Ok(regions) => set
                    .free_pieces
                    .extend(regions.into_iter().map(|r| (r, *limit))),
                Err(e) => set.free_pieces_error = Some(e.to_string()),
            }
        }
    }
}

impl Climb<'_, '_> {
    fn run(&self, taut: &TautPath) -> FeasibilityReport {
        let terrain = self.ctx.terrain;
        let n = taut.anchors.len();
        let goal = taut.goal();
        let goal_psi = if goal == self.points[n] {
            0.0
        } else {
            angle_from_fall_line(&(goal - self.points[n]))
        };
        let goal_limit = terrain.limit_at(&goal);
        let mut anchors: Vec<AnchorAssessment> = taut
            .anchors
            .iter()
            .enumerate()
            .map(|(i, a)| {
                let j = i + 1;
                AnchorAssessment {
                    index: j,
                    anchor: *a,
                    plane: terrain.plane_index(a.point.y),
                    psi: angle_from_fall_line(&(self.points[j] - self.points[j - 1])),
                    limit: terrain.limit_at(&self.points[j]),
                    previous_limit: terrain.limit_at(&self.points[j - 1]),
                    visibility_edge: None,
                    reachable_part: Vec::new(),
                    passability: Passability::NotReached,
                }
            })
            .collect();
        // Built only for the anchors the ascent examines (each traces its visibility line across
        // the map): a class blocked at the goal or low down costs nothing for the anchors above.
        let mut reachable_sets: Vec<AnchorReachableSet> = vec![self.reachable_set(n, taut)];
        let mut waypoints = Vec::with_capacity(n);
        let mut route = vec![RouteCorner {
            point: goal,
            released_from: n + 1,
        }];
        let mut blockage = None;
        if !admits_direction(&goal_limit, &self.points[n], &goal) {
            blockage = Some(Blockage {
                anchor: None,
                reason: Impassability::GoalOutsideReachableSet {
                    psi: goal_psi,
                    max_angle: goal_limit.max_angle().unwrap_or(std::f64::consts::PI),
                },
            });
        }
        if blockage.is_none()
            && let Some(available) = self.ctx.tether_length
            && taut.length > available
        {
            blockage = Some(Blockage {
                anchor: None,
                reason: Impassability::TetherTooShort {
                    needed: taut.length,
                    available,
                },
            });
        }
        let mut q = goal;
        for j in (1..=n).rev() {
            if blockage.is_some() {
                break;
            }
            let a = &mut anchors[j - 1];
            let (psi, limit, previous) = (a.psi, a.limit, a.previous_limit);
            let (from, to) = (self.points[j - 1], self.points[j]);
            let reason = if !admits_direction(&limit, &from, &to) {
                Some(Impassability::NoVisibilityEdge {
                    psi,
                    max_angle: limit.max_angle().unwrap_or(std::f64::consts::PI),
                })
            } else if !admits_direction(&previous, &from, &to) {
                Some(Impassability::OutsidePreviousReachableSet {
                    psi,
                    max_angle: previous.max_angle().unwrap_or(std::f64::consts::PI),
                })
            } else {
                None
            };
            if let Some(reason) = reason {
                a.passability = Passability::Impassable(reason);
                blockage = Some(Blockage {
                    anchor: Some(j),
                    reason,
                });
                break;
            }
            reachable_sets.push(self.reachable_set(j - 1, taut));
            let set = reachable_sets
                .iter()
                .find(|set| set.anchor == j)
                .expect("C_j is built before a_j is examined");
            let reach = set.visibility_line.map_or(0.0, |[a, b]| (b - a).norm());
            let crossing = self.cross(j, q, reach);
            let choice = if self.own_waypoint[j] {
                Some((self.points[j], None))
            } else {
                crossing.choice
            };
            a.visibility_edge = crossing.edge;
            a.reachable_part = crossing.reachable;
            match choice {
                Some((w, via)) => {
                    a.passability = Passability::Passable { waypoint: w, via };
                    if let Some(v) = via {
                        route.push(RouteCorner {
                            point: v,
                            released_from: j + 1,
                        });
                    }
                    route.push(RouteCorner {
                        point: w,
                        released_from: j,
                    });
                    waypoints.push(w);
                    q = w;
                }
                None => {
                    let reason = Impassability::NoReachableWaypoint {
                        usable: crossing.usable,
                    };
                    a.passability = Passability::Impassable(reason);
                    blockage = Some(Blockage {
                        anchor: Some(j),
                        reason,
                    });
                }
            }
        }
        reachable_sets.sort_by_key(|set| set.anchor);
        for set in &mut reachable_sets {
            set.pieces.retain(|(poly, _)| poly.len() >= 3);
        }
        route.push(RouteCorner {
            point: taut.start(),
            released_from: 1,
        });
        FeasibilityReport {
            goal_psi,
            goal_limit,
            anchors,
            reachable_sets,
            waypoints,
            route,
            blockage,
        }
    }

    /// `true` when the waypoint `w` keeps the clearance from every intermediate anchor and the
    /// move `q -> w` from the anchors not yet released (`a_1 .. a_j`; a path pair bends around
    /// the released ones).
    ///
    /// Only the anchors whose `x` lies within the clearance of the move's `x` range are looked at,
    /// and of those only the ones the anchor grid finds within twice the clearance of the move
    /// (the others are farther than the clearance, so they pass), so a class wrapping thousands
    /// of vertices costs per candidate the anchors near the move, not all of them.
    fn clear_of_anchors(&self, j: usize, q: &Point2<f64>, w: &Point2<f64>) -> bool {
        let c = self.ctx.clearance * (1.0 - CLEARANCE_TOLERANCE);
        let (lo, hi) = (q.x.min(w.x) - c, q.x.max(w.x) + c);
        let mut clear = true;
        // Per site: the anchors at one point pass or fail together, except for the released
        // test `i > j`, which the smallest of their ids decides.
        self.index.visit_sites_near(&[*q, *w], 2.0 * c, |a, ids| {
            if clear && lo <= a.x && a.x <= hi {
                let first = ids[0] as usize;
                clear = (first > j || distance_to_segment(a, q, w) >= c) && (a - w).norm() >= c;
            }
        });
        clear
    }

    /// `C_j` as convex pieces, with its visibility line.
    fn reachable_set(&self, j: usize, taut: &TautPath) -> AnchorReachableSet {
        let apex = self.points[j];
        let b = &self.bounds;
        let bands: Vec<(f64, f64, TetherLimit)> = if self.ctx.terrain.planes().is_empty() {
            vec![(b.min.y, b.max.y, TetherLimit::TetherFree)]
        } else {
            let planes = self.ctx.terrain.planes();
            let last = planes.len() - 1;
            planes
                .iter()
                .zip(self.ctx.terrain.limits())
                .enumerate()
                .map(|(k, (p, l))| {
                    let top = if k == 0 { b.max.y } else { p.y_top };
                    let bottom = if k == last { b.min.y } else { p.y_bottom };
                    (bottom.max(b.min.y), top.min(b.max.y), *l)
                })
                .filter(|(lo, hi, _)| hi > lo)
                .collect()
        };
        let half_plane = (j >= 1).then(|| {
            let (from, to) = (self.points[j - 1], apex);
            match taut.anchors[j - 1].side {
                Side::Left => (from, to - from),
                Side::Right => (to, from - to),
            }
        });
        let pieces: Vec<(Polygon, TetherLimit)> = bands
            .into_iter()
            .map(|(lo, hi, limit)| {
                let mut poly = vec![
                    Point2::new(b.min.x, lo),
                    Point2::new(b.max.x, lo),
                    Point2::new(b.max.x, hi),
                    Point2::new(b.min.x, hi),
                ];
                if let TetherLimit::Cone { max_angle } = limit {
                    let (s, c) = max_angle.sin_cos();
                    poly = clip(&poly, &apex, &Vector2::new(-s, -c));
                    poly = clip(&poly, &apex, &-Vector2::new(s, -c));
                }
                if let Some((origin, dir)) = half_plane {
                    poly = clip(&poly, &origin, &dir);
                }
                (Polygon::new(poly), limit)
            })
            .collect();
        let visibility_line = (j >= 1).then(|| {
            let dir = (apex - self.points[j - 1]).normalize();
            let (w, h) = b.size();
            let far = apex + dir * (2.0 * (w + h) + 1.0);
            let end = match Tracer::new(self.ctx.btm, apex).map(|mut t| t.push(far)) {
                Ok(Err(PathError::LeavesFreeSpace { near, .. })) => near,
                Ok(Ok(())) => far,
                _ => apex,
            };
            [apex, end]
        });
        AnchorReachableSet {
            anchor: j,
            apex,
            pieces,
            free_pieces: Vec::new(),
            free_pieces_error: None,
            visibility_line,
        }
    }
}

/// The directions of the two edges of the friction-cone wedge of half-angle `max_angle` about the
/// fall line: `[right, left]`, `(±sin, -cos)`. The wedge of an apex `a` is the open cone
/// between the rays from `a` along them; these two vectors, computed once from the limit, *are*
/// its definition for every membership verdict, which [`ray_side`] then decides exactly.
pub fn wedge_edges(max_angle: f64) -> [Vector2<f64>; 2] {
    let (s, c) = max_angle.sin_cos();
    [Vector2::new(s, -c), Vector2::new(-s, -c)]
}

/// The wedge verdict from the exact sides of a point against the right and left wedge edges
/// ([`wedge_edges`]): strictly inside the open cone (thesis §2.4.2's strict inequality).
fn inside_cone(right_side: f64, left_side: f64) -> bool {
    right_side < 0.0 && left_side > 0.0
}

/// `true` when the direction `from -> to` is strictly inside the wedge of `limit` (its angle from
/// the fall line below the limit), decided exactly on the inputs ([`wedge_edges`], [`ray_side`]);
/// a zero direction counts as the fall line (angle 0).
///
/// ```
/// use nalgebra::Point2;
/// use rappel_mechanics::anchor_traversability::TetherLimit;
/// use rappel_planners::feasibility::admits_direction;
/// let cone = TetherLimit::Cone { max_angle: 0.5 };
/// let o = Point2::new(3.0, 7.0);
/// assert!(admits_direction(&cone, &o, &Point2::new(3.1, 6.0)));
/// assert!(!admits_direction(&cone, &o, &Point2::new(4.0, 6.0)));
/// assert!(admits_direction(&TetherLimit::TetherFree, &o, &Point2::new(4.0, 9.0)));
/// ```
pub fn admits_direction(limit: &TetherLimit, from: &Point2<f64>, to: &Point2<f64>) -> bool {
    match *limit {
        TetherLimit::TetherFree => true,
        TetherLimit::Cone { .. } if from == to => limit.admits(0.0),
        TetherLimit::Cone { max_angle } => {
            let [r, l] = wedge_edges(max_angle);
            inside_cone(ray_side(from, &r, to), ray_side(from, &l, to))
        }
    }
}

/// One end of a piece of a move cut at band edges: an input point, or the move's point at a band
/// edge's height (never rounded: [`ray_side_at_height`] decides it).
#[derive(Clone, Copy)]
enum PieceEnd {
    At(Point2<f64>),
    Height(f64),
}

impl PieceEnd {
    fn y(&self) -> f64 {
        match *self {
            PieceEnd::At(p) => p.y,
            PieceEnd::Height(y) => y,
        }
    }
}

/// `true` when every point of the segment `q -> w` lies in the friction-cone wedge of `apex`,
/// band by band (each band's wedge is convex, so each piece's ends decide; `apex` itself counts
/// as inside). Decided exactly: the band edges the move crosses are compared exactly with its
/// ends' heights, and each piece end, an input point or the move's exact point at a band edge,
/// is put on its side of each wedge edge ([`wedge_edges`]) by the exact predicates
/// ([`ray_side`], [`ray_side_at_height`]), so no verdict depends on rounding.
pub fn in_wedge(
    terrain: &PlaneSeries,
    apex: &Point2<f64>,
    q: &Point2<f64>,
    w: &Point2<f64>,
) -> bool {
    let planes = terrain.planes();
    if planes.is_empty() {
        return true;
    }
    let (lo, hi) = (q.y.min(w.y), q.y.max(w.y));
    let mut cuts: Vec<f64> = planes
        .iter()
        .skip(1)
        .map(|p| p.y_top)
        .filter(|&y| lo < y && y < hi)
        .collect();
    // Along the move: descending heights when it goes down.
    cuts.sort_by(f64::total_cmp);
    if w.y < q.y {
        cuts.reverse();
    }
    let ends: Vec<PieceEnd> = std::iter::once(PieceEnd::At(*q))
        .chain(cuts.into_iter().map(PieceEnd::Height))
        .chain(std::iter::once(PieceEnd::At(*w)))
        .collect();
    let inside = |end: &PieceEnd, edges: &[Vector2<f64>; 2]| match *end {
        PieceEnd::At(x) => {
            x == *apex || inside_cone(ray_side(apex, &edges[0], &x), ray_side(apex, &edges[1], &x))
        }
        PieceEnd::Height(y) => {
            let at_apex =
                y == apex.y && ray_side_at_height(apex, &Vector2::new(0.0, 1.0), q, w, y) == 0.0;
            at_apex
                || inside_cone(
                    ray_side_at_height(apex, &edges[0], q, w, y),
                    ray_side_at_height(apex, &edges[1], q, w, y),
                )
        }
    };
    ends.windows(2).all(|piece| {
        let mid = Point2::new(apex.x, (piece[0].y() + piece[1].y()) / 2.0);
        match terrain.limit_at(&mid) {
            TetherLimit::TetherFree => true,
            TetherLimit::Cone { max_angle } => {
                let edges = wedge_edges(max_angle);
                piece.iter().all(|end| inside(end, &edges))
            }
        }
    })
}

/// Sutherland-Hodgman: the part of the convex polygon `poly` left of the line through `origin`
/// along `dir` (closed). Floating point, for reachable-set polygons and pictures only.
pub fn clip(poly: &[Point2<f64>], origin: &Point2<f64>, dir: &Vector2<f64>) -> Vec<Point2<f64>> {
    let side = |p: &Point2<f64>| dir.x * (p.y - origin.y) - dir.y * (p.x - origin.x);
    let mut out = Vec::with_capacity(poly.len() + 1);
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        let (sa, sb) = (side(&a), side(&b));
        if sa >= 0.0 {
            out.push(a);
        }
        if (sa >= 0.0) != (sb >= 0.0) {
            out.push(a + (b - a) * (sa / (sa - sb)));
        }
    }
    out
}
