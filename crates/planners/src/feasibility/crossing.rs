//! The crossing of a visibility edge decided exactly (thesis Alg. 5 lines 13-19, issue 10): the
//! part of the usable visibility edge `V ∩ R_{j-1}` that the robot reaches from its position `q`
//! while `a_j` is proximal, computed as intervals of the distance `t` from `a_j` along `L_j`
//! instead of by trying points, and the waypoint chosen on it by a fixed rule.
//!
//! # The reachability model (unchanged from the sampled version)
//! The point `w(t) = a_j + t d` of the visibility line (`d` the unit direction of `L_j`) is reached
//! by one of two routes:
//! - [`Route::Direct`]: the straight move `q -> w(t)`;
//! - [`Route::Via`]: first in along the tether to `v(t) = a_j + s (q - a_j) / |q - a_j|`,
//!   `s = max(t, clearance)`, then across to `w(t)`; it exists while `s < |q - a_j|`.
//!
//! The move `from -> w(t)` is allowed when it lies in the friction-cone wedge of `a_j` band by band
//! ([`in_wedge`]) and the tether's sweep `a_j -> [a_{j+1}] -> from -> w(t) -> a_j` is a
//! contractible loop in free space (the exact tracer; see [`Climb::sweep_clear`]).
//!
//! # Cells
//! Along `t` each condition changes only at **critical values**:
//! - the ends of the usable pieces of `V ∩ R_{j-1}` with their clearance margins;
//! - the route's structure: `t = clearance`, `t = |q - a_j|`, `t = |a_{j+1} - a_j|`;
//! - the wedge: where an end of the move crosses a band edge, and where the move crosses a band
//!   edge exactly on an edge of that band's wedge (the move's ends are linear in `t`, so this is a
//!   quadratic in `t`, solved in closed form);
//! - the sweep: along each route the swept triangles are nested (they grow with `t`, the tether
//!   side fixed, or fixed below the clearance and scaled about `a_j` above it), so the sweep is
//!   clear on a prefix of `t`; its end is found with the exact loop test (the far end first, then
//!   galloping out from `a_j` and bisecting to [`TIE_WIDTH_FRACTION`]); the via route's triangle
//!   lies inside the direct route's, so it is clear at least as far;
//! - for the waypoint preference only (never the verdict): the ends of the clearance disks of the
//!   anchors near `L_j`, and where the direct move's segment passes exactly `clearance` from an
//!   anchor not yet released (a quadratic in `t` for the distance to the move's line, kept where
//!   the foot of the perpendicular lies inside the segment). The anchors with such values are
//!   found with the anchor grid ([`crate::anchor_index`]); each anchor's values depend on the
//!   anchor alone, so the grid changes which anchors are looked at, never the values.
//!
//! Between consecutive critical values every condition is constant, so one evaluation of the
//! exact predicates at a representative point decides the whole cell. The wedge verdict changes
//! only at the verdict's own values (route structure, wedge, sweep ends), so with
//! [`crate::anchor_index::Evaluation::Indexed`] it is evaluated once per span between those and
//! reused for every cell the clearance values split it into ([`Evaluation::Direct`] evaluates
//! every cell; the equivalence tests compare both): a reachable part narrower
//! than the spacing of any ladder is found, and rounding an input in its last bits moves the cell
//! ends by a few ulps but changes a verdict only when a reachable cell is itself that thin (a true
//! tie). Cells narrower than [`TIE_WIDTH_FRACTION`] of the map's extent are such ties and are not
//! used. The representative of a cell `[u, v]` is `u + min(step, (v - u) / 2)` with `step` the
//! clearance (at least [`MIN_WAYPOINT_STEP_FRACTION`] of the extent): near the anchor, well inside.
//!
//! # Waypoint
//! The cells are visited from `a_j` outward, the direct route before the via route. A point is
//! *clear* when its waypoint keeps `clearance` from every anchor and its move keeps it from the
//! anchors not yet released ([`Climb::clear_of_anchors`]). The waypoint is the first clear point at
//! least [`ROOMY_CLEARANCES`] clearances beyond `a_j` (the representative, or that distance itself
//! when it falls inside a reachable cell: the predicates are constant there, and it is checked
//! again exactly); else the first clear representative; else the first reachable one. Only the
//! first [`MAX_PREFERENCE_CELLS`] reachable cells are looked at for the preference.

use super::{Climb, Evaluation, MIN_WAYPOINT_STEP_FRACTION, admits_direction, in_wedge};
use nalgebra::{Point2, Vector2};
use rappel_geometry::predicates::orient2d;
use rappel_homotopy::homotopy::{LoopPrefix, is_contractible};
use rappel_homotopy::path::Path;
use rappel_mechanics::anchor_traversability::TetherLimit;
use std::cell::Cell;

/// Cells of the visibility line narrower than this fraction of the map's extent (the larger side
/// of its bounding box) are ties and never used: 10 nm on a 100 m map, far above the rounding of
/// the critical values (a few ulps of the extent) and far below any robot.
pub const TIE_WIDTH_FRACTION: f64 = 1e-10;

/// Bound on the bisection steps that locate the end of the clear sweep (each halves a float
/// interval; 2,100 steps exhaust any pair of finite doubles, the usual count is about 60).
const MAX_BISECTION_STEPS: usize = 2_100;

/// Waypoints at least this many clearances beyond `a_j` are preferred: the ascent leaves the
/// waypoint bending round the released `a_j` at a clearance (the path pair's mitre point), which a
/// waypoint just one clearance beyond leaves no room for.
pub const ROOMY_CLEARANCES: f64 = 2.0;

/// The waypoint preference (clear, then roomy) looks at the first this many reachable cells from
/// `a_j` outward; beyond them the first reachable point is the fallback. Bounds the per-anchor
/// cost where anchors crowd the visibility line (a long obstacle's corners every few centimetres
/// split it into thousands of cells, none clear).
pub const MAX_PREFERENCE_CELLS: usize = 16;

/// The anchor grid's margin for the clearance values, in clearances: twice the distance the
/// values look at, so that the grid's superset holds every anchor with a value, whatever the
/// rounding of a root.
const CANDIDATE_MARGIN_CLEARANCES: f64 = 2.0;

/// Points sampled on each side of a sweep's limit by the debug check of the prefix claim
/// ([`Climb::check_sweep_prefix`]).
const SWEEP_PREFIX_SAMPLES: usize = 4;

/// Bound on the ulp steps that put a via point on the free side of the tether's line
/// ([`Climb::snap_via`]); rounding the via point errs by one or two ulps.
const MAX_SNAP_STEPS: usize = 16;

/// How the robot moves onto the visibility line (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Route {
    /// Straight from the robot's position.
    Direct,
    /// In along the tether towards `a_j`, then across.
    Via,
}

/// What [`Climb::cross`] finds for one anchor.
pub(super) struct Crossing {
    /// The usable visibility edge `V ∩ R_{j-1}` (first to last usable point), if not empty.
    pub edge: Option<[Point2<f64>; 2]>,
    /// Its total usable length, m.
    pub usable: f64,
    /// The reachable part as segments along `L_j`, nearest `a_j` first.
    pub reachable: Vec<[Point2<f64>; 2]>,
    /// The waypoint and its via point, if some point is reachable.
    pub choice: Option<(Point2<f64>, Option<Point2<f64>>)>,
}

/// The critical values of one visibility edge ([`Climb::critical_values`]).
struct CriticalValues {
    /// Every critical value in `(lo, hi)`, sorted: the cells' ends.
    all: Vec<f64>,
    /// The verdict's own (route structure, wedge, sweep ends), sorted: between two of them the
    /// reachability verdict of a route is constant; the others only split cells for the
    /// waypoint preference.
    verdict: Vec<f64>,
    /// `(route, u, v, clear_until)` per span of one route structure.
    sweeps: Vec<(Route, f64, f64, f64)>,
}

/// A number linear in `t`: `c0 + c1 t`.
#[derive(Debug, Clone, Copy)]
struct Lin(f64, f64);

impl Lin {
    fn minus(self, o: Lin) -> Lin {
        Lin(self.0 - o.0, self.1 - o.1)
    }
    /// The product as `[c0, c1, c2]`.
    fn times(self, o: Lin) -> [f64; 3] {
        [self.0 * o.0, self.0 * o.1 + self.1 * o.0, self.1 * o.1]
    }
}

/// A point moving linearly in `t`.
#[derive(Debug, Clone, Copy)]
struct Moving {
    x: Lin,
    y: Lin,
}

impl Moving {
    fn fixed(p: Point2<f64>) -> Moving {
        Moving {
            x: Lin(p.x, 0.0),
            y: Lin(p.y, 0.0),
        }
    }
    fn ray(p: Point2<f64>, d: Vector2<f64>) -> Moving {
        Moving {
            x: Lin(p.x, d.x),
            y: Lin(p.y, d.y),
        }
    }
}

/// The real roots of `c[0] + c[1] t + c[2] t^2` (numerically stable form; a double root counts
/// once, none when the polynomial is zero), without allocating (called per anchor per edge).
fn roots(c: [f64; 3]) -> impl Iterator<Item = f64> {
    let [c0, c1, c2] = c;
    let mut out = [f64::NAN; 2];
    if c2 == 0.0 {
        if c1 != 0.0 {
            out[0] = -c0 / c1;
        }
    } else {
        let disc = c1 * c1 - 4.0 * c2 * c0;
        if disc >= 0.0 {
            let q = -0.5 * (c1 + c1.signum() * disc.sqrt());
            out[0] = q / c2;
            if q != 0.0 {
                out[1] = c0 / q;
            }
        }
    }
    out.into_iter().filter(|t| t.is_finite())
}

impl Climb<'_, '_> {
    /// The larger side of the map's bounding box, m: the scale of every relative tolerance.
    fn extent(&self) -> f64 {
        let (w, h) = self.bounds.size();
        w.max(h)
    }

    /// Where the move onto `w(t)` starts on `route`, if the route exists at `t`.
    fn route_start(&self, j: usize, q: &Point2<f64>, route: Route, t: f64) -> Option<Point2<f64>> {
        match route {
            Route::Direct => Some(*q),
            Route::Via => {
                let apex = self.points[j];
                let r = (q - apex).norm();
                let s = t.max(self.ctx.clearance);
                (s < r).then(|| self.snap_via(j, q, apex + (q - apex) * (s / r), t))
            }
        }
    }

    /// The via point `v` on the tether `a_j -> q`, moved by at most [`MAX_SNAP_STEPS`] ulps so
    /// that it lies on the tether's line or on the side of it the move goes to (exact
    /// orientation test). The tether may run along an obstacle edge (`a_j` and the released
    /// `a_{j+1}` consecutive corners of one obstacle): `v` is then on that edge, a true tie that
    /// rounding would put inside the obstacle or not; snapped, the verdict does not depend on
    /// those bits. The line is `a_j -> a_{j+1}` while `v` is nearer than `a_{j+1}`, else
    /// `a_j -> q`.
    fn snap_via(&self, j: usize, q: &Point2<f64>, v: Point2<f64>, t: f64) -> Point2<f64> {
        let apex = self.points[j];
        let end = match self.points.get(j + 1) {
            Some(released) if (v - apex).norm_squared() < (released - apex).norm_squared() => {
                *released
            }
            _ => *q,
        };
        let w = apex + self.direction(j) * t;
        let side = orient2d(&apex, &end, &w);
        if side == 0.0 {
            return v;
        }
        // The normal of the line towards the move's side.
        let d = end - apex;
        let n = Vector2::new(-d.y, d.x) * side.signum();
        let mut v = v;
        for _ in 0..MAX_SNAP_STEPS {
            let o = orient2d(&apex, &end, &v);
            if o == 0.0 || o.signum() == side.signum() {
                break;
            }
            let step = |x: f64, towards: f64| {
                if towards > 0.0 {
                    x.next_up()
                } else if towards < 0.0 {
                    x.next_down()
                } else {
                    x
                }
            };
            v = Point2::new(step(v.x, n.x), step(v.y, n.y));
        }
        v
    }

    /// The start of the move on `route` as a point linear in `t` on `[from, to]` (one route
    /// structure), or `None` when the route does not exist there.
    fn route_start_moving(
        &self,
        j: usize,
        q: &Point2<f64>,
        route: Route,
        mid: f64,
    ) -> Option<Moving> {
        match route {
            Route::Direct => Some(Moving::fixed(*q)),
            Route::Via => {
                let apex = self.points[j];
                let r = (q - apex).norm();
                if r == 0.0 || mid.max(self.ctx.clearance) >= r {
                    return None;
                }
                let e = (q - apex) / r;
                Some(if mid < self.ctx.clearance {
                    Moving::fixed(apex + e * self.ctx.clearance)
                } else {
                    Moving::ray(apex, e)
                })
            }
        }
    }

    /// `true` when the tether's sweep for the move `from -> w` with `a_j` proximal is a
    /// contractible loop in free space.
    ///
    /// Below `a_n` the robot starts on the visibility line `L_{j+1}` it has just crossed (or on
    /// the tether towards `a_j`), so the tether `a_j -> from` runs through the released anchor
    /// `a_{j+1}`: a true tie, which rounding `from` in its last bits would put on either side of
    /// `a_{j+1}`'s obstacle. The loop therefore goes through `a_{j+1}` itself
    /// (`a_j -> a_{j+1} -> from`, the tether as it lies, a vertex the exact tracer handles)
    /// whenever `from` is beyond it from `a_j`, so the verdict does not depend on those bits.
    pub(super) fn sweep_clear(&self, j: usize, from: &Point2<f64>, w: &Point2<f64>) -> bool {
        let apex = self.points[j];
        if Self::sweep_degenerates(&apex, from, w) {
            return true;
        }
        let mut corners = self.tether_to(j, from);
        corners.extend([*w, apex]);
        Path::new(corners)
            .ok()
            .and_then(|loop_| is_contractible(self.ctx.btm, &loop_).ok())
            .unwrap_or(false)
    }

    /// `true` when the sweep `a_j -> from -> w -> a_j` degenerates to a part of the tether or of
    /// the visible ray, both free (so clear).
    fn sweep_degenerates(apex: &Point2<f64>, from: &Point2<f64>, w: &Point2<f64>) -> bool {
        w == apex || from == apex || from == w
    }

    /// The sweep loop's tether part, `a_j -> [a_{j+1}] -> from` ([`Climb::sweep_clear`]: through
    /// the released anchor when `from` is beyond it from `a_j`).
    fn tether_to(&self, j: usize, from: &Point2<f64>) -> Vec<Point2<f64>> {
        let apex = self.points[j];
        let mut corners = vec![apex];
        if let Some(released) = self.points.get(j + 1)
            && (from - apex).norm_squared() > (released - apex).norm_squared()
        {
            corners.push(*released);
        }
        corners.push(*from);
        corners
    }

    /// The start of the move on `route` at `t` if `w(t)` is reached on that route (module docs).
    fn reaches(&self, j: usize, q: &Point2<f64>, route: Route, t: f64) -> Option<Point2<f64>> {
        let apex = self.points[j];
        let w = apex + self.direction(j) * t;
        let from = self.route_start(j, q, route, t)?;
        (in_wedge(self.ctx.terrain, &apex, &from, &w) && self.sweep_clear(j, &from, &w))
            .then_some(from)
    }

    /// The unit direction of `L_j`, from `a_{j-1}` through `a_j`.
    fn direction(&self, j: usize) -> Vector2<f64> {
        (self.points[j] - self.points[j - 1]).normalize()
    }

    /// The sweep of `route` at `t`, with the route's start continued where the route does not
    /// exist (the via point then stops at the robot): continuous in `t`, for the bisection.
    fn sweep_at(&self, j: usize, q: &Point2<f64>, route: Route, t: f64) -> bool {
        let apex = self.points[j];
        let from = match route {
            Route::Direct => *q,
            Route::Via => self.route_start(j, q, route, t).unwrap_or(*q),
        };
        self.sweep_clear(j, &from, &(apex + self.direction(j) * t))
    }

    /// Alg. 5 lines 9-19 for anchor `j` with the robot at `q`, exactly (module docs).
    pub(super) fn cross(&self, j: usize, q: Point2<f64>, reach: f64) -> Crossing {
        let apex = self.points[j];
        let dir = self.direction(j);
        // V ∩ R_{j-1}: the parts of the visible ray whose band admits psi (both wedges see the ray
        // at psi from the fall line).
        let intervals: Vec<(f64, f64)> = self
            .ctx
            .terrain
            .pieces(apex, apex + dir * reach)
            .into_iter()
            .filter(|(_, _, limit)| admits_direction(limit, &self.points[j - 1], &apex))
            .map(|(a, b, _)| ((a - apex).norm(), (b - apex).norm()))
            .filter(|(t0, t1)| t1 > t0)
            .collect();
        let (Some(first), Some(last)) = (intervals.first(), intervals.last()) else {
            return Crossing {
                edge: None,
                usable: 0.0,
                reachable: Vec::new(),
                choice: None,
            };
        };
        let edge = Some([apex + dir * first.0, apex + dir * last.1]);
        let usable = intervals.iter().map(|(a, b)| b - a).sum();
        let c = self.ctx.clearance;
        let extent = self.extent();
        let tie = TIE_WIDTH_FRACTION * extent;
        let step = c.max(MIN_WAYPOINT_STEP_FRACTION * extent);
        // The clearance margins: kept `clearance` (at most a quarter of the piece) from `a_j`, from
        // the first obstacle on the ray and from band edges where psi stops being admitted.
        let pieces: Vec<(f64, f64)> = intervals
            .iter()
            .map(|&(t0, t1)| {
                let margin = c.min((t1 - t0) / 4.0);
                (t0 + margin, t1 - margin)
            })
            .collect();
        let (lo_all, hi_all) = (pieces[0].0, pieces[pieces.len() - 1].1);
        let values = self.critical_values(j, &q, lo_all, hi_all, step, tie);
        let (cuts, limits) = (&values.all, &values.sweeps);
        // The wedge verdict of the current span between verdict values, per route: constant
        // there (module docs), so evaluated once per span and piece with `Evaluation::Indexed`,
        // in every cell with `Evaluation::Direct`. Cells are visited in increasing `t`.
        let wedge_cache: Cell<(usize, usize, [Option<bool>; 2])> = Cell::new((0, 0, [None; 2]));
        // `w(t)` on `route` per the cells: the route exists, the move is in the wedge, and `t`
        // is within the clear prefix of the sweep (exact loop tests in `sweep_limit`).
        let reaches_cell = |piece: usize, route: Route, t: f64| -> Option<Point2<f64>> {
            let clear = limits
                .iter()
                .any(|&(r, u, v, until)| r == route && u <= t && t <= v && t < until);
            if !clear {
                return None;
            }
            let from = self.route_start(j, &q, route, t)?;
            let evaluate = || in_wedge(self.ctx.terrain, &apex, &from, &(apex + dir * t));
            let inside = match self.evaluation {
                Evaluation::Direct => evaluate(),
                Evaluation::Indexed => {
                    let span = values.verdict.partition_point(|&v| v < t);
                    let (p, sp, mut known) = wedge_cache.get();
                    if (p, sp) != (piece, span) {
                        known = [None; 2];
                    }
                    let slot = usize::from(route == Route::Via);
                    let inside = *known[slot].get_or_insert_with(evaluate);
                    wedge_cache.set((piece, span, known));
                    inside
                }
            };
            inside.then_some(from)
        };
        let mut reachable: Vec<(f64, f64)> = Vec::new();
        // Preferred: clear and roomy; then clear; then any reachable point.
        let (mut choice, mut clear, mut fallback) = (None, None, None);
        let mut preference_cells = 0;
        for (piece, &(lo, hi)) in pieces.iter().enumerate() {
            let mut ends: Vec<f64> = std::iter::once(lo)
                .chain(cuts.iter().copied().filter(|&t| lo < t && t < hi))
                .chain(std::iter::once(hi))
                .collect();
            ends.dedup();
            for cell in ends.windows(2) {
                let (u, v) = (cell[0], cell[1]);
                if v - u <= tie {
                    continue;
                }
                let t = u + step.min((v - u) / 2.0);
                if t <= 0.0 {
                    continue;
                }
                let w = apex + dir * t;
                // The roomy point of the cell: [`ROOMY_CLEARANCES`] clearances beyond `a_j` when
                // that lies inside the cell (or the representative, if farther already).
                let roomy = t.max(ROOMY_CLEARANCES * c);
                let mut any = false;
                for route in [Route::Direct, Route::Via] {
                    let Some(from) = reaches_cell(piece, route, t) else {
                        continue;
                    };
                    any = true;
                    let via = (route == Route::Via).then_some(from);
                    // Candidates for the waypoint are checked again with the exact predicates;
                    // the preference looks at the first MAX_PREFERENCE_CELLS reachable cells.
                    // The exact re-check of the representative, done at most once per route.
                    let mut exact = None;
                    let mut reached = |climb: &Self| {
                        *exact.get_or_insert_with(|| climb.reaches(j, &q, route, t).is_some())
                    };
                    if fallback.is_none() && reached(self) {
                        fallback = Some((w, via));
                    }
                    if preference_cells >= MAX_PREFERENCE_CELLS {
                        continue;
                    }
                    if clear.is_none() && self.clear_of_anchors(j, &from, &w) && reached(self) {
                        clear = Some((w, via));
                    }
                    if choice.is_none() && roomy < v - tie {
                        let wr = apex + dir * roomy;
                        if let Some(from) = self.route_start(j, &q, route, roomy)
                            && self.clear_of_anchors(j, &from, &wr)
                            && self.reaches(j, &q, route, roomy).is_some()
                        {
                            choice = Some((wr, (route == Route::Via).then_some(from)));
                        }
                    }
                }
                preference_cells += usize::from(any);
                if any {
                    match reachable.last_mut() {
                        Some(last) if last.1 == u => last.1 = v,
                        _ => reachable.push((u, v)),
                    }
                }
            }
        }
        Crossing {
            edge,
            usable,
            reachable: reachable
                .into_iter()
                .map(|(u, v)| [apex + dir * u, apex + dir * v])
                .collect(),
            choice: choice.or(clear).or(fallback),
        }
    }

    /// Every critical value of `t` in `(lo, hi)` (module docs), sorted, the verdict's own among
    /// them, and the sweep limits.
    fn critical_values(
        &self,
        j: usize,
        q: &Point2<f64>,
        lo: f64,
        hi: f64,
        step: f64,
        tie: f64,
    ) -> CriticalValues {
        let mut sweeps = Vec::new();
        let apex = self.points[j];
        let dir = self.direction(j);
        let c = self.ctx.clearance;
        let r = (q - apex).norm();
        // Route structure.
        let mut structure = vec![lo, hi, c, r];
        if let Some(released) = self.points.get(j + 1) {
            structure.push((released - apex).norm());
        }
        structure.retain(|&t| lo <= t && t <= hi);
        structure.sort_by(f64::total_cmp);
        structure.dedup();
        let mut cuts = structure.clone();
        let w = Moving::ray(apex, dir);
        let planes = self.ctx.terrain.planes();
        let limits = self.ctx.terrain.limits();
        for span in structure.windows(2) {
            let (u, v) = (span[0], span[1]);
            let mid = (u + v) / 2.0;
            for route in [Route::Direct, Route::Via] {
                let Some(p) = self.route_start_moving(j, q, route, mid) else {
                    continue;
                };
                // Wedge: ends of the move crossing band edges, and the move crossing a band edge on
                // an edge of the wedge of either band beside it.
                for k in 1..planes.len() {
                    let yb = planes[k].y_top;
                    cuts.extend(roots([p.y.0 - yb, p.y.1, 0.0]));
                    cuts.extend(roots([w.y.0 - yb, w.y.1, 0.0]));
                    for limit in [limits[k - 1], limits[k]] {
                        let TetherLimit::Cone { max_angle } = limit else {
                            continue;
                        };
                        let tan = max_angle.tan();
                        if !tan.is_finite() {
                            continue;
                        }
                        for s in [tan * (apex.y - yb), -tan * (apex.y - yb)] {
                            // (Px - ax - s)(Wy - Py) + (yb - Py)(Wx - Px) = 0.
                            let a = p.x.minus(Lin(apex.x + s, 0.0)).times(w.y.minus(p.y));
                            let b = Lin(yb, 0.0).minus(p.y).times(w.x.minus(p.x));
                            cuts.extend(roots([a[0] + b[0], a[1] + b[1], a[2] + b[2]]));
                        }
                    }
                }
            }
        }
        // Sweeps: each route's swept triangles are nested over its whole range (the direct
        // route's start is fixed; the via point is fixed below the clearance and scales with
        // `t` above it), so each is clear on one prefix; and the via triangle lies inside the
        // direct one, so the via route is clear at least as far as the direct route.
        let direct = self.sweep_limit(j, q, Route::Direct, lo, hi, step, tie);
        sweeps.push((Route::Direct, lo, hi, direct));
        cuts.push(direct);
        let via_end = hi.min(r);
        if lo < via_end {
            let via = if direct >= via_end {
                via_end
            } else {
                self.sweep_limit(j, q, Route::Via, direct.max(lo), via_end, step, tie)
            };
            sweeps.push((Route::Via, lo, via_end, via));
            cuts.push(via);
        }
        let tidy = |cuts: &mut Vec<f64>| {
            cuts.retain(|t| t.is_finite() && lo < *t && *t < hi);
            cuts.sort_by(f64::total_cmp);
            cuts.dedup();
        };
        let mut verdict = cuts.clone();
        tidy(&mut verdict);
        self.clearance_values(j, q, lo, hi, &mut cuts);
        tidy(&mut cuts);
        CriticalValues {
            all: cuts,
            verdict,
            sweeps,
        }
    }

    /// How far the sweep of `route` stays clear on the span `[u, v]` of one route structure,
    /// where it is clear on a prefix (module docs): `v` when clear at `v`, `u` when blocked just
    /// after `u`, else the last clear `t` found by galloping out from `u` (steps doubling from
    /// `step`, so the loops traced stay as small as the clear part) and bisecting with the exact
    /// loop test until the bracket is narrower than `tie` (a cell that thin is a tie and unused).
    #[allow(clippy::too_many_arguments)]
    fn sweep_limit(
        &self,
        j: usize,
        q: &Point2<f64>,
        route: Route,
        u: f64,
        v: f64,
        step: f64,
        tie: f64,
    ) -> f64 {
        // The direct route's tether `a_j -> [a_{j+1}] -> q` is the same loop part at every `t`:
        // traced once, each probe walks only `q -> w(t) -> a_j` (same verdicts as
        // [`Climb::sweep_at`], which debug builds compare in `check_sweep_prefix`).
        let apex = self.points[j];
        let mut tether = match route {
            Route::Direct => Some(LoopPrefix::new(self.ctx.btm, &self.tether_to(j, q))),
            Route::Via => None,
        };
        let mut sweep_at = |t: f64| match &mut tether {
            None => self.sweep_at(j, q, route, t),
            Some(tether) => {
                let w = apex + self.direction(j) * t;
                Self::sweep_degenerates(&apex, q, &w)
                    || tether
                        .as_mut()
                        .is_ok_and(|tether| tether.closes_contractibly(&[w, apex]).unwrap_or(false))
            }
        };
        if sweep_at(v) {
            return v;
        }
        let (mut clear, mut blocked) = (u, v);
        let mut probe = u + step.min((v - u) / 2.0);
        for _ in 0..MAX_BISECTION_STEPS {
            if probe >= blocked {
                break;
            }
            if sweep_at(probe) {
                clear = probe;
                probe = u + 2.0 * (probe - u);
            } else {
                blocked = probe;
                break;
            }
        }
        if clear == u && !sweep_at(u) {
            return u;
        }
        for _ in 0..MAX_BISECTION_STEPS {
            let mid = clear + (blocked - clear) / 2.0;
            if blocked - clear <= tie || mid <= clear || mid >= blocked {
                break;
            }
            if sweep_at(mid) {
                clear = mid;
            } else {
                blocked = mid;
            }
        }
        if cfg!(debug_assertions) {
            self.check_sweep_prefix(j, q, route, u, clear, blocked, v);
        }
        clear
    }

    /// Debug builds check the claim [`Climb::sweep_limit`] rests on, that the sweep is clear on a
    /// prefix of `[u, v]` (module docs: the swept triangles are nested): [`SWEEP_PREFIX_SAMPLES`]
    /// evenly spaced points of `[u, clear]` must be clear and as many of `[blocked, v]` blocked,
    /// exactly; a counterexample panics with the anchor, route and parameters. Every test built
    /// in debug exercises it (the release regression suites do not).
    #[allow(clippy::too_many_arguments)]
    fn check_sweep_prefix(
        &self,
        j: usize,
        q: &Point2<f64>,
        route: Route,
        u: f64,
        clear: f64,
        blocked: f64,
        v: f64,
    ) {
        for i in 0..=SWEEP_PREFIX_SAMPLES {
            let f = i as f64 / SWEEP_PREFIX_SAMPLES as f64;
            let t = u + (clear - u) * f;
            assert!(
                self.sweep_at(j, q, route, t),
                "sweep not clear on a prefix: anchor {j}, {route:?} route from {q:?}: blocked at t = {t} below the clear t = {clear}"
            );
            let t = blocked + (v - blocked) * f;
            assert!(
                t <= blocked || !self.sweep_at(j, q, route, t),
                "sweep not clear on a prefix: anchor {j}, {route:?} route from {q:?}: clear at t = {t} beyond the blocked t = {blocked}"
            );
        }
    }

    /// The waypoint preference's critical values (module docs): where `w(t)` enters or leaves
    /// the clearance disk of an anchor near `L_j`, and where the direct move from `q` passes
    /// exactly `clearance` from an anchor not yet released (the distance to the move's segment:
    /// the roots of the distance to its line whose foot lies inside the segment; the distance to
    /// its end `w(t)` is the disk's).
    ///
    /// Each anchor's values are a function of the anchor alone, and only anchors within the
    /// clearance of the segment `[w_lo, w_hi]` or of the triangle `q, w_lo, w_hi` have any in
    /// `(lo, hi)`: the anchor grid visits those (and others, which add nothing), so the values do
    /// not depend on the grid. Around a long obstacle that is a few anchors per edge, where the
    /// distance to the move's whole line (used before) put a value for nearly every anchor ahead
    /// into every edge.
    fn clearance_values(&self, j: usize, q: &Point2<f64>, lo: f64, hi: f64, cuts: &mut Vec<f64>) {
        let c = self.ctx.clearance;
        if c <= 0.0 {
            return;
        }
        let apex = self.points[j];
        let dir = self.direction(j);
        let (w_lo, w_hi) = (apex + dir * lo, apex + dir * hi);
        let margin = CANDIDATE_MARGIN_CLEARANCES * c;
        // Per site: the values are the point's, the same for every anchor at it (the cuts are
        // a set: sorted and deduplicated).
        self.index.visit_sites_near(&[w_lo, w_hi], margin, |a, _| {
            let rel = a - apex;
            // |w(t) - a| = c.
            cuts.extend(roots([
                rel.norm_squared() - c * c,
                -2.0 * rel.dot(&dir),
                1.0,
            ]));
        });
        self.index
            .visit_sites_near(&[*q, w_lo, w_hi], margin, |&a, ids| {
                // Some anchor at this point not yet released (the smallest id decides).
                if ids[0] as usize > j {
                    return;
                }
                // Distance from a to the line through q and w(t) equal to c:
                // cross(w - q, a - q)^2 = c^2 |w - q|^2, with w - q = d0 + t dir; kept where the
                // foot of the perpendicular lies strictly inside the segment q -> w(t).
                let (d0, aq) = (apex - q, a - q);
                let m = Lin(d0.x * aq.y - d0.y * aq.x, dir.x * aq.y - dir.y * aq.x);
                let sq = m.times(m);
                let n = [d0.norm_squared(), 2.0 * d0.dot(&dir), dir.norm_squared()];
                let inside = |t: &f64| {
                    let wq = d0 + dir * *t;
                    let foot = aq.dot(&wq);
                    0.0 < foot && foot < wq.norm_squared()
                };
                cuts.extend(
                    roots([
                        sq[0] - c * c * n[0],
                        sq[1] - c * c * n[1],
                        sq[2] - c * c * n[2],
                    ])
                    .filter(inside),
                );
            });
    }
}
