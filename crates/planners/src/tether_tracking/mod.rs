//! Tether configuration tracking (Kumar §III-A, Alg. 1 `updateTether`; Paton §IV-B, Alg. 1): the
//! taut tether from a base (Robot 1 or a fixed anchor) to a moving robot, as a stack of anchors
//! updated step by step.
//!
//! All decisions are made in the terrain's frame (the development of the surfaces, see
//! [`rappel_terrain::surface`]), with exact orientation predicates on the input points (the base,
//! the obstacle corners and the robot's waypoints), never on a computed intersection point. The
//! robot's position inside a step is kept implicitly: it is where the step meets the ray from the
//! top anchor (the apex) along the tether's last direction, and that direction is itself given by
//! two input points (`Heading`: towards a waypoint, straight on from the anchor below, or
//! straight on through a released anchor). Free space is closed: the robot may step through a
//! corner or along a side; such a step is decided as the same step moved off the obstacle by an
//! arbitrarily small amount, which is what the homotopy class of the walked path is.
//! - **detach** (`isDetached`): the top obstacle anchor `a_n`, wrapped with turn side `w` after the
//!   previous obstacle or robot anchor `a_{n-1}`, is released when the tether's direction from
//!   `a_n` sweeps onto or across the ray from `a_n` straight on from `a_{n-1}` (the robot reaches
//!   or crosses that ray beyond `a_n`, Kumar's `intersectLines`): `orient2d(a_{n-1}, a_n, ·)` of
//!   the heading and of the step's end, and the sweep side `-w`. A step through `a_n` itself,
//!   or one that stops on `a_n` and leaves it, releases it unless it leaves into the free sector
//!   between its arrival direction and that ray. Kumar's obstacle-normal construction
//!   `Z = X x (n x X)` is the same half-plane test in the frame.
//! - **attach** (`attachAnchor`): the segment from the top anchor to the robot sweeps the triangle
//!   `(a_n, p, p_k+1)`; the obstacle corner in it (strictly inside, or on the segment
//!   `a_n -> p` or on the step, its obstacle ahead of the sweep) at the smallest angle from
//!   `a_n -> p` (nearest first on ties) is the new anchor; repeated until no corner is swept.
//!   Membership is `orient2d` against the heading, the step's line and the end ray; the tie on
//!   one ray is decided by comparing coordinates.
//! - **ground anchors** (`rotatewrtAnchorSurface`): wherever a straight frame segment of the
//!   tether crosses a crest edge ([`EdgeKind::Crest`]) the folded tether rests on the edge; the
//!   anchor is that crossing, so it slides along the edge as the robot moves (Kumar's
//!   Assumption 2.2: the tether slides laterally at slope changes). They are recomputed from the
//!   obstacle anchors after each step (Alg. 1 pops them). Kumar §III-A adds a ground anchor at a
//!   "concave" slope change and none at a "convex" one; which edges those are is a reading of
//!   the paper, chosen with [`GroundAnchorEdges`] ([`TetherTracker::with_ground_anchor_edges`]):
//!   crests by default (the physics of a taut tether), valleys for the other reading.
//!   Whether a segment crosses an edge is exact; the crossing point (a position, not a decision)
//!   is rounded, and so is its order along the segment when two edges cross it.
//!
//! Winding angles `phi_j` are measured on the folded 3D polyline (obstacle anchors at their base
//! corner, `h_t = 0`), and [`TetherTracker::windings`] pairs them with each anchor's friction
//! (the obstacle's; for a ground anchor the smaller of the two surfaces') for Kumar eq. 2.
//!
//! On one plane the tracked configuration is the shortest homotopic path of the robot's path from
//! the base (tested against the homotopy crate's SHP).

pub mod two_robots;

use nalgebra::{Point2, Point3};
use rappel_geometry::compact::Compact;
use rappel_geometry::polygon::PointInPolygon;
use rappel_geometry::predicates::{orient2d, point_on_segment};
use rappel_terrain::surface::{EdgeKind, Terrain};
use serde::{Deserialize, Serialize};

/// Most anchor events (attach or detach) one step may process: a step of ordinary length touches a
/// handful of corners; the bound is 4 per obstacle vertex plus 16, after which the step is refused
/// (degenerate input).
pub const EVENTS_PER_VERTEX: usize = 4;

/// Which slope changes hold the tether as ground anchors (Kumar §III-A: "If the angle is concave
/// ... this is added to the tether configuration as a ground anchor ... If the angle between the
/// surfaces is convex, then no changes are made").
///
/// The paper does not say from which side the angle is measured, and the two readings differ:
/// - [`GroundAnchorEdges::Crests`] (the default): the lower surface falls away below the upper
///   one's plane ([`EdgeKind::Crest`]; the angle on the air side is reflex, "concave"). A taut
///   tether between the two surfaces would cut through the ground, so it rests on the edge: the
///   physics, and what rappel models.
/// - [`GroundAnchorEdges::Valleys`]: the slope flattens downhill ([`EdgeKind::Valley`]; concave
///   in the usual sense of a hillside profile, seen from above). The tether is taken to follow the
///   ground through the valley (its geodesic there, straight in the unfolding) and to bend at the
///   edge, where a taut tether would span it through the air. On Kumar's Fig. 5 hillside (flat,
///   55°, 65°, flat) no pose on S1 or S2 then has a ground anchor.
///
/// Either way the anchor slides along its edge (Kumar's Assumption 2.2).
///
/// # Example
/// ```
/// use nalgebra::Point2;
/// use rappel_planners::tether_tracking::{GroundAnchorEdges, TetherTracker};
/// use rappel_terrain::plane_series::TerrainPlane;
/// use rappel_terrain::plane_series_terrain::PlaneSeriesTerrain;
/// // Flat above y = 10, 30 degrees below it: a crest.
/// let planes = [TerrainPlane::new(20.0, 10.0, 0.0, 0.4), TerrainPlane::new(10.0, 0.0, 30.0, 0.4)];
/// let t = PlaneSeriesTerrain::new(&planes, (0.0, 20.0), vec![]).unwrap();
/// let anchors = |edges| {
///     let mut tr = TetherTracker::new(&t, Point2::new(5.0, 15.0), Point2::new(5.0, 12.0))
///         .unwrap()
///         .with_ground_anchor_edges(edges);
///     tr.step(Point2::new(5.0, 5.0)).unwrap();
///     tr.configuration().len() - 2
/// };
/// assert_eq!(anchors(GroundAnchorEdges::Crests), 1);
/// assert_eq!(anchors(GroundAnchorEdges::Valleys), 0);
/// ```
#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum GroundAnchorEdges {
    /// Ground anchors at crests (rappel's default; a taut tether rests on a crest).
    #[default]
    Crests,
    /// Ground anchors at valleys (Kumar's "concave" read as a hillside that flattens downhill).
    Valleys,
}

impl GroundAnchorEdges {
    /// Whether an edge of `kind` holds the tether as a ground anchor.
    pub fn holds(self, kind: EdgeKind) -> bool {
        matches!(
            (self, kind),
            (GroundAnchorEdges::Crests, EdgeKind::Crest)
                | (GroundAnchorEdges::Valleys, EdgeKind::Valley)
        )
    }
}

/// What holds the tether at an anchor (Kumar's anchor `type`: 'r', 'o', 'g').
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum AnchorKind {
    /// The base: Robot 1 or a fixed anchor.
    Robot,
    /// Corner `vertex` of obstacle `obstacle`; `left` when the tether turns counter-clockwise
    /// there (walking from the base to the robot).
    Obstacle {
        /// Obstacle index.
        obstacle: usize,
        /// Vertex index in the obstacle's (counter-clockwise) base.
        vertex: usize,
        /// Turn side seen from the base.
        left: bool,
    },
    /// A crossing of the tether with edge `edge` (a crest, or a valley with
    /// [`GroundAnchorEdges::Valleys`]).
    Ground {
        /// Index into [`Terrain::edges`].
        edge: usize,
    },
}

/// One anchor: its kind, frame point and world point.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct TetherAnchor {
    /// What holds it.
    pub kind: AnchorKind,
    /// Frame point.
    #[schemars(with = "[f64; 2]")]
    pub point: Point2<f64>,
    /// World point (folded).
    #[schemars(with = "[f64; 3]")]
    pub world: Point3<f64>,
}

/// Which point or step a [`TrackError`] is about, typed so that a caller can tell whose input
/// it was (the two-robot problem blames Robot 1 or Robot 2 by it) and printed as the error's
/// words.
///
/// ```
/// use rappel_planners::tether_tracking::TrackSubject;
/// assert_eq!(TrackSubject::Step(3).to_string(), "step 3");
/// assert_eq!(TrackSubject::Base.to_string(), "the base");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TrackSubject {
    /// The tracker's base (the tether's fixed end).
    Base,
    /// The robot's start.
    RobotStart,
    /// The initial tether, straight from the base to the robot's start.
    InitialTether,
    /// The robot's step with this index (0 for the first).
    Step(usize),
    /// A caller's own words for one of the above ([`TrackError::renamed`]).
    Named(&'static str),
}

impl std::fmt::Display for TrackSubject {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            TrackSubject::Base => f.write_str("the base"),
            TrackSubject::RobotStart => f.write_str("the robot's start"),
            TrackSubject::InitialTether => f.write_str("the initial tether"),
            TrackSubject::Step(i) => write!(f, "step {i}"),
            TrackSubject::Named(s) => f.write_str(s),
        }
    }
}

/// Why a step cannot be tracked.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TrackError {
    /// A point is not finite.
    #[error("{what} is not finite")]
    NonFinite {
        /// Which point.
        what: TrackSubject,
    },
    /// A point is off every surface.
    #[error("{what} ({}, {}) is off the terrain's surfaces", Compact(*.x), Compact(*.y))]
    OffTerrain {
        /// Which point.
        what: TrackSubject,
        /// Frame x.
        x: f64,
        /// Frame y.
        y: f64,
    },
    /// A step passes through an obstacle, or a point is inside one.
    #[error("{what} passes through obstacle {obstacle}")]
    ThroughObstacle {
        /// Which step or point.
        what: TrackSubject,
        /// Obstacle index.
        obstacle: usize,
    },
    /// The event bound of one step was exceeded (degenerate, collinear input).
    #[error("step {step}: more than {limit} anchor events (degenerate input)")]
    EventLimit {
        /// Step index.
        step: usize,
        /// The bound.
        limit: usize,
    },
}

impl TrackError {
    /// Which point or step the error is about (`None` for the event limit).
    pub fn what(&self) -> Option<TrackSubject> {
        match self {
            TrackError::NonFinite { what }
            | TrackError::OffTerrain { what, .. }
            | TrackError::ThroughObstacle { what, .. } => Some(*what),
            TrackError::EventLimit { .. } => None,
        }
    }

    /// The error with its point or step named in the caller's words (for a caller that knows
    /// better which robot's point it is); the event limit keeps its step.
    pub fn renamed(mut self, name: &'static str) -> Self {
        if let TrackError::NonFinite { what }
        | TrackError::OffTerrain { what, .. }
        | TrackError::ThroughObstacle { what, .. } = &mut self
        {
            *what = TrackSubject::Named(name);
        }
        self
    }
}

/// The tracker: the base, the obstacle-anchor stack and the robot.
#[derive(Debug, Clone)]
pub struct TetherTracker<'t, T: Terrain + ?Sized> {
    terrain: &'t T,
    base: Point2<f64>,
    /// Obstacle anchors, base side first.
    stack: Vec<TetherAnchor>,
    robot: Point2<f64>,
    /// The tether's last direction when the robot stands on the top anchor (the way it arrived),
    /// `None` when unknown.
    heading: Option<Heading>,
    steps: usize,
    event_limit: usize,
    /// Which slope changes hold the tether.
    ground_edges: GroundAnchorEdges,
}

/// The exact direction of the tether's last segment from the apex (the top anchor, or the base):
/// towards `through` when `forward`, away from it otherwise. The apex and `through` are input
/// points (waypoints, corners, the base), so every side test against the direction is an
/// `orient2d` of input points.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Heading {
    through: Point2<f64>,
    forward: bool,
}

impl Heading {
    /// The exact side (-1, 0, 1) of `v` against the line from `apex` along the heading.
    fn side(&self, apex: &Point2<f64>, v: &Point2<f64>) -> i8 {
        let s = sign(orient2d(apex, &self.through, v));
        if self.forward { s } else { -s }
    }

    /// For `v` on the heading's line (`v != apex`): `true` when it lies on the heading's ray.
    fn ahead(&self, apex: &Point2<f64>, v: &Point2<f64>) -> bool {
        same_way(apex, &self.through, v) == self.forward
    }
}

/// For `t` and `v` collinear with `apex` and both different from it: `true` when they lie on the
/// same ray from `apex`. Exact: coordinate comparisons only.
fn same_way(apex: &Point2<f64>, t: &Point2<f64>, v: &Point2<f64>) -> bool {
    let way = |x: f64, o: f64| (x > o) as i8 - (x < o) as i8;
    if t.x != apex.x {
        way(t.x, apex.x) == way(v.x, apex.x)
    } else {
        way(t.y, apex.y) == way(v.y, apex.y)
    }
}

/// For `v` and `w` on one ray from `apex`: `true` when `v` is strictly nearer. Exact.
fn nearer(apex: &Point2<f64>, v: &Point2<f64>, w: &Point2<f64>) -> bool {
    if w.x != apex.x {
        if w.x > apex.x { v.x < w.x } else { v.x > w.x }
    } else if w.y > apex.y {
        v.y < w.y
    } else {
        v.y > w.y
    }
}

/// Where the sweep of the tether's last segment ends.
#[derive(Debug, Clone, Copy)]
enum SweepEnd {
    /// At the step's end point.
    Target,
    /// At the release ray of the top anchor, straight on from the given anchor below it.
    Release(Point2<f64>),
}

fn sign(x: f64) -> i8 {
    if x > 0.0 {
        1
    } else if x < 0.0 {
        -1
    } else {
        0
    }
}

/// Intersection of line `(a, b)` with line `(p, q)` (not parallel).
fn intersect_lines(a: Point2<f64>, b: Point2<f64>, p: Point2<f64>, q: Point2<f64>) -> Point2<f64> {
    let (r, s) = (b - a, q - p);
    let den = r.x * s.y - r.y * s.x;
    if den == 0.0 {
        return q;
    }
    // The parameter along the robot's step, clamped to it.
    let u = ((p - a).x * r.y - (p - a).y * r.x) / den;
    p + s * u.clamp(0.0, 1.0)
}

impl<'t, T: Terrain + ?Sized> TetherTracker<'t, T> {
    /// A straight tether from `base` to `robot` (both on the terrain, the segment clear of
    /// obstacles).
    pub fn new(terrain: &'t T, base: Point2<f64>, robot: Point2<f64>) -> Result<Self, TrackError> {
        let n: usize = terrain.obstacles().iter().map(|o| o.base.len()).sum();
        let t = TetherTracker {
            terrain,
            base,
            stack: Vec::new(),
            robot,
            heading: None,
            steps: 0,
            event_limit: EVENTS_PER_VERTEX * n + 16,
            ground_edges: GroundAnchorEdges::default(),
        };
        t.check_point(TrackSubject::Base, &base)?;
        t.check_point(TrackSubject::RobotStart, &robot)?;
        t.check_segment(TrackSubject::InitialTether, &base, &robot)?;
        Ok(t)
    }

    /// Resumes from a configuration: `anchors` are the obstacle anchors base side first (ground
    /// anchors are skipped), as returned by [`TetherTracker::obstacle_anchors`].
    pub fn with_anchors(
        terrain: &'t T,
        base: Point2<f64>,
        anchors: Vec<TetherAnchor>,
        robot: Point2<f64>,
    ) -> Result<Self, TrackError> {
        let mut t = TetherTracker::new(terrain, base, base)?;
        t.stack = anchors
            .into_iter()
            .filter(|a| matches!(a.kind, AnchorKind::Obstacle { .. }))
            .collect();
        t.robot = robot;
        t.check_point(TrackSubject::RobotStart, &robot)?;
        Ok(t)
    }

    /// The same tracker with ground anchors at the slope changes `edges` selects (default:
    /// crests; see [`GroundAnchorEdges`]). Only [`TetherTracker::configuration`] and what is
    /// computed from it (length, windings) depend on it; the obstacle anchors do not.
    pub fn with_ground_anchor_edges(mut self, edges: GroundAnchorEdges) -> Self {
        self.ground_edges = edges;
        self
    }

    /// Which slope changes hold the tether.
    pub fn ground_anchor_edges(&self) -> GroundAnchorEdges {
        self.ground_edges
    }

    fn check_point(&self, what: TrackSubject, p: &Point2<f64>) -> Result<(), TrackError> {
        if !(p.x.is_finite() && p.y.is_finite()) {
            return Err(TrackError::NonFinite { what });
        }
        if self.terrain.surface_at(p).is_none() {
            return Err(TrackError::OffTerrain {
                what,
                x: p.x,
                y: p.y,
            });
        }
        for (k, o) in self.terrain.obstacles().iter().enumerate() {
            if o.base.locate(p) == PointInPolygon::Inside {
                return Err(TrackError::ThroughObstacle { what, obstacle: k });
            }
        }
        Ok(())
    }

    /// Refuses a segment entering an obstacle's interior: a proper crossing of a base edge, or a
    /// departure into the interior from a corner or a side point on the segment (exact: at a
    /// corner `v` with neighbours `u`, `w`, the direction towards the segment's far end is tested
    /// against the interior angle with `orient2d`; no rounded midpoint is used).
    fn check_segment(
        &self,
        what: TrackSubject,
        p: &Point2<f64>,
        q: &Point2<f64>,
    ) -> Result<(), TrackError> {
        for (k, o) in self.terrain.obstacles().iter().enumerate() {
            let crosses = o.base.edges().any(|(a, b)| {
                sign(orient2d(p, q, a)) * sign(orient2d(p, q, b)) < 0
                    && sign(orient2d(a, b, p)) * sign(orient2d(a, b, q)) < 0
            });
            if crosses || enters_interior(&o.base.vertices, p, q) {
                return Err(TrackError::ThroughObstacle { what, obstacle: k });
            }
        }
        Ok(())
    }

    /// The robot's current frame position.
    pub fn robot(&self) -> Point2<f64> {
        self.robot
    }

    /// The base's frame position.
    pub fn base(&self) -> Point2<f64> {
        self.base
    }

    /// The obstacle anchors, base side first.
    pub fn obstacle_anchors(&self) -> &[TetherAnchor] {
        &self.stack
    }

    /// The anchor below the top of the stack (the base when there is one obstacle anchor).
    fn point_below_top(&self) -> Point2<f64> {
        if self.stack.len() >= 2 {
            self.stack[self.stack.len() - 2].point
        } else {
            self.base
        }
    }

    fn top(&self) -> Point2<f64> {
        self.stack.last().map_or(self.base, |a| a.point)
    }

    /// The top obstacle anchor's wrap: the point below it and its turn side `w` (±1).
    fn top_wrap(&self) -> Option<(Point2<f64>, i8)> {
        let top = self.stack.last()?;
        let AnchorKind::Obstacle { left, .. } = top.kind else {
            unreachable!("the stack holds obstacle anchors only")
        };
        Some((self.point_below_top(), if left { 1 } else { -1 }))
    }

    /// With the robot standing on the top anchor `a`, having arrived along `arrival`: `true` when
    /// the step to `q` releases `a`. It stays only when `q` is on its turn side and inside the free
    /// sector from the arrival direction to the release ray (the robot goes round the corner on
    /// its free side, as a step moved off the corner would).
    fn leaves_apex(&self, arrival: Option<Heading>, q: &Point2<f64>) -> bool {
        let Some((b, w)) = self.top_wrap() else {
            return false;
        };
        let a = self.top();
        if sign(orient2d(&b, &a, q)) != w {
            return true;
        }
        arrival.is_some_and(|h| {
            let c = h.side(&a, q);
            !(c == -w || (c == 0 && h.ahead(&a, q)))
        })
    }

    /// The first corner swept by the tether's last segment, from the apex along `h` (the robot
    /// on the step `p0 -> q`) turning with side `s` (±1) until `end`: `(obstacle, vertex, on the
    /// step)`, the last `true` when the corner lies on the step itself (the robot reaches it).
    fn first_swept(
        &self,
        apex: &Point2<f64>,
        h: &Heading,
        (p0, q): (&Point2<f64>, &Point2<f64>),
        s: i8,
        end: SweepEnd,
    ) -> Option<(usize, usize, bool)> {
        // The apex's side of the step's line (not 0: the sweep would be empty).
        let oa = sign(orient2d(p0, q, apex));
        let mut best: Option<(usize, usize, Point2<f64>, bool)> = None;
        for (k, o) in self.terrain.obstacles().iter().enumerate() {
            let n = o.base.len();
            for (i, v) in o.base.vertices.iter().enumerate() {
                if v == apex {
                    continue;
                }
                // On the sweep side of the heading, or on its ray (between the apex and the
                // robot, the robot's position included).
                let st = h.side(apex, v);
                if st == -s || (st == 0 && !h.ahead(apex, v)) {
                    continue;
                }
                // Not beyond the step's line.
                let os = sign(orient2d(p0, q, v));
                if os == -oa {
                    continue;
                }
                // Strictly before the sweep's end.
                let before = match end {
                    SweepEnd::Target => sign(orient2d(apex, q, v)) == -s,
                    SweepEnd::Release(b) => sign(orient2d(&b, apex, v)) == -s,
                };
                if !before {
                    continue;
                }
                // The sweeping segment first touches a corner with its obstacle ahead: a neighbour
                // strictly on the sweep side of the ray apex -> v. This also keeps a corner just
                // released (its obstacle behind the ray) from being caught again.
                let (pv, nv) = (
                    &o.base.vertices[(i + n - 1) % n],
                    &o.base.vertices[(i + 1) % n],
                );
                if sign(orient2d(apex, v, pv)) != s && sign(orient2d(apex, v, nv)) != s {
                    continue;
                }
                // A corner on the step is reached by the robot itself: it is swept only when its
                // obstacle lies in the triangle next to it, on the apex's side of the step (when
                // the robot stands on it, between the tether and the step).
                if os == 0 {
                    let meets = if st == 0 {
                        wedge_meets_cone(pv, v, nv, apex, q)
                    } else {
                        orient2d(pv, v, nv) <= 0.0
                            || sign(orient2d(p0, q, pv)) == oa
                            || sign(orient2d(p0, q, nv)) == oa
                    };
                    if !meets {
                        continue;
                    }
                }
                let better = match &best {
                    None => true,
                    Some((_, _, b, _)) => {
                        let o2 = sign(orient2d(apex, b, v));
                        o2 == -s || (o2 == 0 && nearer(apex, v, b))
                    }
                };
                if better {
                    best = Some((k, i, *v, os == 0));
                }
            }
        }
        best.map(|(k, i, _, on_step)| (k, i, on_step))
    }

    /// Moves the robot to `q` along a straight step (Kumar Alg. 1).
    pub fn step(&mut self, q: Point2<f64>) -> Result<(), TrackError> {
        let what = TrackSubject::Step(self.steps);
        self.check_point(what, &q)?;
        self.check_segment(what, &self.robot, &q)?;
        let p0 = self.robot;
        if p0 == q {
            self.steps += 1;
            return Ok(());
        }
        // The robot is where the step meets the ray from the apex along `heading`; `at_apex` when
        // it stands on the apex itself (then `heading` is the way it arrived).
        let mut at_apex = p0 == self.top();
        let mut heading = if at_apex {
            self.heading
        } else {
            Some(Heading {
                through: p0,
                forward: true,
            })
        };
        let mut events = 0usize;
        loop {
            events += 1;
            if events > self.event_limit {
                return Err(TrackError::EventLimit {
                    step: self.steps,
                    limit: self.event_limit,
                });
            }
            let a = self.top();
            if at_apex {
                // On the apex, leaving it for `q` (`q != a`): released, or moving straight out.
                at_apex = false;
                if self.leaves_apex(heading, &q) {
                    self.stack.pop();
                    heading = Some(Heading {
                        through: a,
                        forward: true,
                    });
                    continue;
                }
                heading = Some(Heading {
                    through: q,
                    forward: true,
                });
                break;
            }
            let h = heading.expect("known unless the robot stands on the apex");
            let s = h.side(&a, &q);
            if s == 0 {
                // The step runs along the heading's line: straight out (or onto the apex), or
                // through the apex to the far side.
                if q != a && !h.ahead(&a, &q) {
                    at_apex = true;
                    continue;
                }
                break;
            }
            // isDetached: the heading turns (side s) onto or across the ray from a straight on
            // from the anchor below; only the ray beyond a releases it, a robot stepping over
            // the tether segment b -> a (or behind b) leaves the wrap in place.
            let mut end = SweepEnd::Target;
            if let Some((b, w)) = self.top_wrap() {
                let side_h = if h.forward { 1 } else { -1 } * sign(orient2d(&b, &a, &h.through));
                let on_ray = side_h == 0 && same_way(&a, &b, &h.through) != h.forward;
                if s == -w && (on_ray || (side_h == w && sign(orient2d(&b, &a, &q)) != w)) {
                    end = SweepEnd::Release(b);
                }
            }
            // attachAnchor: corners swept before the release (or the step's end) attach first.
            match self.first_swept(&a, &h, (&p0, &q), s, end) {
                Some((k, i, on_step)) => {
                    self.attach(k, i, s);
                    heading = Some(if on_step {
                        // The robot reaches the corner and walks straight away from it.
                        Heading {
                            through: q,
                            forward: true,
                        }
                    } else {
                        // Straight on from the old apex through the new one.
                        Heading {
                            through: a,
                            forward: false,
                        }
                    });
                }
                None if matches!(end, SweepEnd::Release(_)) => {
                    self.stack.pop();
                    heading = Some(Heading {
                        through: a,
                        forward: true,
                    });
                }
                None => break,
            }
        }
        self.heading = heading;
        self.robot = q;
        self.steps += 1;
        Ok(())
    }

    /// Pushes corner `i` of obstacle `k`, wrapped with turn side `s`.
    fn attach(&mut self, k: usize, i: usize, s: i8) {
        let o = &self.terrain.obstacles()[k];
        let v = o.base.vertices[i];
        self.stack.push(TetherAnchor {
            kind: AnchorKind::Obstacle {
                obstacle: k,
                vertex: i,
                left: s > 0,
            },
            point: v,
            world: self.terrain.fold(o.surface, &v),
        });
    }

    /// Follows a path of waypoints (the first is taken as a step target too; a repeated point is
    /// a no-op step).
    pub fn follow(&mut self, path: &[Point2<f64>]) -> Result<(), TrackError> {
        path.iter().try_for_each(|q| self.step(*q))
    }

    /// The whole configuration from the base to the robot: base, obstacle and ground anchors, and
    /// the robot as the last element (kind `Robot`).
    pub fn configuration(&self) -> Vec<TetherAnchor> {
        let t = self.terrain;
        let fold = |p: &Point2<f64>| t.world(p).unwrap_or_else(|| t.fold(0, p));
        let mut pts: Vec<TetherAnchor> = Vec::with_capacity(self.stack.len() + 2);
        pts.push(TetherAnchor {
            kind: AnchorKind::Robot,
            point: self.base,
            world: fold(&self.base),
        });
        let ends: Vec<TetherAnchor> = self
            .stack
            .iter()
            .copied()
            .chain(std::iter::once(TetherAnchor {
                kind: AnchorKind::Robot,
                point: self.robot,
                world: fold(&self.robot),
            }))
            .collect();
        for e in ends {
            let a = pts.last().map_or(self.base, |x| x.point);
            pts.extend(ground_anchors_at(t, &a, &e.point, self.ground_edges));
            pts.push(e);
        }
        pts
    }

    /// Length of the tether (folded), metres.
    pub fn length(&self) -> f64 {
        self.configuration()
            .windows(2)
            .map(|w| (w[1].world - w[0].world).norm())
            .sum()
    }

    /// `(mu_aj, phi_j)` at each interior anchor (Kumar Definition 3, eq. 2 inputs).
    pub fn windings(&self) -> Vec<(f64, f64)> {
        windings_of(self.terrain, &self.configuration())
    }
}

/// `true` when the interior of the counter-clockwise polygon at its corner `v` (previous corner
/// `u`, next `w`) meets the open cone at `v` between the rays towards `c1` and `c2` (not
/// collinear with `v`). Exact: `orient2d` and coordinate comparisons.
fn wedge_meets_cone(
    u: &Point2<f64>,
    v: &Point2<f64>,
    w: &Point2<f64>,
    c1: &Point2<f64>,
    c2: &Point2<f64>,
) -> bool {
    let convex = orient2d(u, v, w) > 0.0;
    let in_wedge = |t: &Point2<f64>| {
        let (l1, l2) = (orient2d(u, v, t) > 0.0, orient2d(v, w, t) > 0.0);
        if convex { l1 && l2 } else { l1 || l2 }
    };
    if in_wedge(c1) || in_wedge(c2) {
        return true;
    }
    if !convex {
        // The cone lies in the closed exterior, a convex sector.
        return false;
    }
    let sigma = sign(orient2d(v, c1, c2));
    let in_cone =
        |t: &Point2<f64>| sign(orient2d(v, c1, t)) == sigma && sign(orient2d(v, c2, t)) == -sigma;
    let on_ray = |t: &Point2<f64>, c: &Point2<f64>| orient2d(v, c, t) == 0.0 && same_way(v, c, t);
    in_cone(u) || in_cone(w) || (on_ray(u, c1) && on_ray(w, c2)) || (on_ray(u, c2) && on_ray(w, c1))
}

/// `true` when the segment `p -> q`, crossing no edge properly, still enters the interior of the
/// counter-clockwise polygon `ring`: it leaves a corner on it, or a side point at one of its ends,
/// into the interior. Exact (`orient2d` and coordinate comparisons).
fn enters_interior(ring: &[Point2<f64>], p: &Point2<f64>, q: &Point2<f64>) -> bool {
    let n = ring.len();
    for (i, v) in ring.iter().enumerate() {
        if !point_on_segment(p, q, v) {
            continue;
        }
        let (u, w) = (&ring[(i + n - 1) % n], &ring[(i + 1) % n]);
        let convex = orient2d(u, v, w) >= 0.0;
        let inside = |t: &Point2<f64>| {
            let (l1, l2) = (orient2d(u, v, t) > 0.0, orient2d(v, w, t) > 0.0);
            if convex { l1 && l2 } else { l1 || l2 }
        };
        if (v != q && inside(q)) || (v != p && inside(p)) {
            return true;
        }
    }
    ring.iter().zip(ring.iter().cycle().skip(1)).any(|(a, b)| {
        [(p, q), (q, p)].iter().any(|(e, t)| {
            e != &a && e != &b && point_on_segment(a, b, e) && orient2d(a, b, t) > 0.0
        })
    })
}

/// The ground anchors where the frame segment `a -> b` crosses crest edges, in order from `a`.
pub fn ground_anchors<T: Terrain + ?Sized>(
    t: &T,
    a: &Point2<f64>,
    b: &Point2<f64>,
) -> Vec<TetherAnchor> {
    ground_anchors_at(t, a, b, GroundAnchorEdges::Crests)
}

/// The ground anchors where the frame segment `a -> b` crosses the edges `edges` selects, in
/// order from `a`.
pub fn ground_anchors_at<T: Terrain + ?Sized>(
    t: &T,
    a: &Point2<f64>,
    b: &Point2<f64>,
    edges: GroundAnchorEdges,
) -> Vec<TetherAnchor> {
    let mut hits: Vec<(f64, TetherAnchor)> = Vec::new();
    for (i, e) in t.edges().iter().enumerate() {
        if !edges.holds(e.kind) {
            continue;
        }
        let (sa, sb) = (sign(orient2d(&e.a, &e.b, a)), sign(orient2d(&e.a, &e.b, b)));
        let (sc, sd) = (sign(orient2d(a, b, &e.a)), sign(orient2d(a, b, &e.b)));
        if sa * sb < 0 && sc * sd <= 0 {
            let p = intersect_lines(e.a, e.b, *a, *b);
            let along = ((p - a).norm() / (b - a).norm().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
            hits.push((
                along,
                TetherAnchor {
                    kind: AnchorKind::Ground { edge: i },
                    point: p,
                    world: t.fold(e.from, &p),
                },
            ));
        }
    }
    hits.sort_by(|x, y| x.0.total_cmp(&y.0));
    hits.into_iter().map(|h| h.1).collect()
}

/// `(mu_aj, phi_j)` at each interior point of a configuration (base first, robot last).
pub fn windings_of<T: Terrain + ?Sized>(t: &T, config: &[TetherAnchor]) -> Vec<(f64, f64)> {
    config
        .windows(3)
        .filter_map(|w| {
            let (u, v) = (w[1].world - w[0].world, w[2].world - w[1].world);
            let (nu, nv) = (u.norm(), v.norm());
            if nu == 0.0 || nv == 0.0 {
                return None;
            }
            let phi = (u.dot(&v) / (nu * nv)).clamp(-1.0, 1.0).acos();
            let mu = match w[1].kind {
                AnchorKind::Obstacle { obstacle, .. } => t.obstacles()[obstacle].friction,
                AnchorKind::Ground { edge } => {
                    let e = &t.edges()[edge];
                    t.friction(e.from).min(t.friction(e.to))
                }
                AnchorKind::Robot => 0.0,
            };
            Some((mu, phi))
        })
        .collect()
}
