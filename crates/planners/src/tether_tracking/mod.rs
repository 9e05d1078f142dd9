//! Tether configuration tracking (Kumar §III-A, Alg. 1 `updateTether`; Paton §IV-B, Alg. 1): the
//! taut tether from a base (Robot 1 or a fixed anchor) to a moving robot, as a stack of anchors
//! updated step by step.
//!
//! All decisions are made in the terrain's frame (the development of the surfaces, see
//! [`rappel_terrain::surface`]), with exact orientation predicates:
//! - **detach** (`isDetached`): the top obstacle anchor `a_n`, wrapped with turn side `w` after the
//!   previous obstacle or robot anchor `a_{n-1}`, is released when the robot crosses the ray from
//!   `a_n` straight on from `a_{n-1}`; the robot's intermediate position `v_s1` is where the step
//!   crosses that ray (`intersectLines`). Kumar's obstacle-normal construction `Z = X x (n x X)`
//!   is the same half-plane test in the frame.
//! - **attach** (`attachAnchor`): the segment from the top anchor to the robot sweeps the triangle
//!   `(a_n, p_k, p_k+1)`; the obstacle corner strictly inside it at the smallest angle from
//!   `a_n -> p_k` (nearest first on ties) is the new anchor, the robot having reached the point
//!   where the line `a_n -> corner` crosses its step; repeated until no corner is swept.
//! - **ground anchors** (`rotatewrtAnchorSurface`): wherever a straight frame segment of the
//!   tether crosses a crest edge ([`EdgeKind::Crest`], Kumar's "concave" change) the folded tether
//!   rests on the edge; the anchor is that crossing, so it slides along the edge as the robot
//!   moves. They are recomputed from the obstacle anchors after each step (Alg. 1 pops them).
//!
//! Winding angles `phi_j` are measured on the folded 3D polyline (obstacle anchors at their base
//! corner, `h_t = 0`), and [`TetherTracker::windings`] pairs them with each anchor's friction
//! (the obstacle's; for a ground anchor the smaller of the two surfaces') for Kumar eq. 2.
//!
//! On one plane the tracked configuration is the shortest homotopic path of the robot's path from
//! the base (tested against the homotopy crate's SHP).

pub mod two_robots;

use nalgebra::{Point2, Point3};
use rappel_geometry::polygon::PointInPolygon;
use rappel_geometry::predicates::orient2d;
use rappel_terrain::surface::{EdgeKind, Terrain};
use serde::{Deserialize, Serialize};

/// Most anchor events (attach or detach) one step may process: a step of ordinary length touches a
/// handful of corners; the bound is 4 per obstacle vertex plus 16, after which the step is refused
/// (degenerate input).
pub const EVENTS_PER_VERTEX: usize = 4;

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
    /// A crossing of the tether with crest edge `edge`.
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

/// Why a step cannot be tracked.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TrackError {
    /// A point is not finite.
    #[error("{what} is not finite")]
    NonFinite {
        /// Which point.
        what: String,
    },
    /// A point is off every surface.
    #[error("{what} ({x}, {y}) is off the terrain's surfaces")]
    OffTerrain {
        /// Which point.
        what: String,
        /// Frame x.
        x: f64,
        /// Frame y.
        y: f64,
    },
    /// A step passes through an obstacle, or a point is inside one.
    #[error("{what} passes through obstacle {obstacle}")]
    ThroughObstacle {
        /// Which step or point.
        what: String,
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

/// The tracker: the base, the obstacle-anchor stack and the robot.
#[derive(Debug, Clone)]
pub struct TetherTracker<'t, T: Terrain + ?Sized> {
    terrain: &'t T,
    base: Point2<f64>,
    /// Obstacle anchors, base side first.
    stack: Vec<TetherAnchor>,
    robot: Point2<f64>,
    steps: usize,
    event_limit: usize,
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
            steps: 0,
            event_limit: EVENTS_PER_VERTEX * n + 16,
        };
        t.check_point("the base", &base)?;
        t.check_point("the robot's start", &robot)?;
        t.check_segment("the initial tether", &base, &robot)?;
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
        t.check_point("the robot's start", &robot)?;
        Ok(t)
    }

    fn check_point(&self, what: &str, p: &Point2<f64>) -> Result<(), TrackError> {
        if !(p.x.is_finite() && p.y.is_finite()) {
            return Err(TrackError::NonFinite { what: what.into() });
        }
        if self.terrain.surface_at(p).is_none() {
            return Err(TrackError::OffTerrain {
                what: what.into(),
                x: p.x,
                y: p.y,
            });
        }
        for (k, o) in self.terrain.obstacles().iter().enumerate() {
            if o.base.locate(p) == PointInPolygon::Inside {
                return Err(TrackError::ThroughObstacle {
                    what: what.into(),
                    obstacle: k,
                });
            }
        }
        Ok(())
    }

    /// Refuses a segment crossing an obstacle's interior (a proper crossing of a base edge).
    fn check_segment(
        &self,
        what: &str,
        p: &Point2<f64>,
        q: &Point2<f64>,
    ) -> Result<(), TrackError> {
        for (k, o) in self.terrain.obstacles().iter().enumerate() {
            let crosses = o.base.edges().any(|(a, b)| {
                sign(orient2d(p, q, a)) * sign(orient2d(p, q, b)) < 0
                    && sign(orient2d(a, b, p)) * sign(orient2d(a, b, q)) < 0
            });
            let mid = Point2::from((p.coords + q.coords) * 0.5);
            if crosses || o.base.locate(&mid) == PointInPolygon::Inside {
                return Err(TrackError::ThroughObstacle {
                    what: what.into(),
                    obstacle: k,
                });
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

    /// The first corner swept by the segment `apex -> x` as `x` moves from `p` to `q`, with the
    /// sweep side.
    fn first_swept(
        &self,
        apex: &Point2<f64>,
        p: &Point2<f64>,
        q: &Point2<f64>,
    ) -> Option<(usize, usize, i8)> {
        let s = sign(orient2d(apex, p, q));
        if s == 0 {
            return None;
        }
        let mut best: Option<(usize, usize, Point2<f64>)> = None;
        for (k, o) in self.terrain.obstacles().iter().enumerate() {
            let n = o.base.len();
            for (i, v) in o.base.vertices.iter().enumerate() {
                if v == apex {
                    continue;
                }
                let a0 = sign(orient2d(apex, p, v));
                let inside = sign(orient2d(p, q, v)) == s && sign(orient2d(q, apex, v)) == s;
                if !inside {
                    continue;
                }
                // The sweeping segment first touches a corner with its obstacle ahead: a neighbour
                // strictly on the sweep side of the ray apex -> v. This also keeps a corner just
                // released (its obstacle behind the ray) from being caught again through rounding.
                let (pv, nv) = (
                    &o.base.vertices[(i + n - 1) % n],
                    &o.base.vertices[(i + 1) % n],
                );
                if sign(orient2d(apex, v, pv)) != s && sign(orient2d(apex, v, nv)) != s {
                    continue;
                }
                // A corner on the segment apex -> p itself is swept too.
                let on_start = a0 == 0 && (v - apex).dot(&(p - v)) > 0.0;
                if a0 != s && !on_start {
                    continue;
                }
                let better = match &best {
                    None => true,
                    Some((_, _, b)) => {
                        let o2 = sign(orient2d(apex, b, v));
                        o2 == -s
                            || (o2 == 0 && (v - apex).norm_squared() < (b - apex).norm_squared())
                    }
                };
                if better {
                    best = Some((k, i, *v));
                }
            }
        }
        best.map(|(k, i, _)| (k, i, s))
    }

    /// Moves the robot to `q` along a straight step (Kumar Alg. 1).
    pub fn step(&mut self, q: Point2<f64>) -> Result<(), TrackError> {
        let what = format!("step {}", self.steps);
        self.check_point(&what, &q)?;
        self.check_segment(&what, &self.robot, &q)?;
        let mut p = self.robot;
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
            // isDetached: the robot crosses the ray from a straight on from the anchor below.
            if let Some(top) = self.stack.last() {
                let AnchorKind::Obstacle { left, .. } = top.kind else {
                    unreachable!("the stack holds obstacle anchors only")
                };
                let w: i8 = if left { 1 } else { -1 };
                let b = self.point_below_top();
                let m = intersect_lines(b, a, p, q);
                // Only a crossing of the ray beyond a releases it; a robot stepping over the
                // tether segment b -> a (or behind b) leaves the wrap in place.
                if sign(orient2d(&b, &a, &p)) == w
                    && sign(orient2d(&b, &a, &q)) != w
                    && (m - a).dot(&(a - b)) > 0.0
                {
                    // Corners swept before the release point attach first.
                    if let Some((k, i, s)) = self.first_swept(&a, &p, &m) {
                        p = self.attach(a, k, i, s, p, m);
                        continue;
                    }
                    self.stack.pop();
                    p = m;
                    continue;
                }
            }
            match self.first_swept(&a, &p, &q) {
                Some((k, i, s)) => p = self.attach(a, k, i, s, p, q),
                None => break,
            }
        }
        self.robot = q;
        self.steps += 1;
        Ok(())
    }

    fn attach(
        &mut self,
        apex: Point2<f64>,
        k: usize,
        i: usize,
        s: i8,
        p: Point2<f64>,
        q: Point2<f64>,
    ) -> Point2<f64> {
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
        intersect_lines(apex, v, p, q)
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
            pts.extend(ground_anchors(t, &a, &e.point));
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

/// The ground anchors where the frame segment `a -> b` crosses crest edges, in order from `a`.
pub fn ground_anchors<T: Terrain + ?Sized>(
    t: &T,
    a: &Point2<f64>,
    b: &Point2<f64>,
) -> Vec<TetherAnchor> {
    let mut hits: Vec<(f64, TetherAnchor)> = Vec::new();
    for (i, e) in t.edges().iter().enumerate() {
        if e.kind != EdgeKind::Crest {
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
