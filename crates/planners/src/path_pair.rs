//! Ascent/descent path pairs (thesis §2.2.4, §2.4.3, Algorithm 6): for the shortest homotopy
//! class whose ascent is feasible, a descent path and an ascent path, homotopic to each other and
//! to the class's SHP, in free space and keeping a clearance around the anchors.
//!
//! # Construction
//! Both paths go round anchors the same way (the private module `around`): a polyline through **nodes**, each a
//! point passed through or an anchor kept on one side at the target clearance, made of the
//! tangents between consecutive nodes and, round each anchor, the circumscribed polygon of the arc
//! between its two tangent points. The path comes back onto its leg (a tether segment, or an
//! ascent leg) [`DETOUR_REACH_CLEARANCES`] target clearances along it from each run of anchors
//! (anchors closer than that along the leg are rounded together), so a detour stays within about
//! a clearance of its anchors and the rest of the leg is the leg itself, which is in free space (a
//! tether segment, or a side of a sweep triangle that Alg. 5 found free): an obstacle lying near
//! the tether far from an anchor does not block the pair. Where no such path exists (two nodes
//! closer than their radii allow a tangent), the anchors' **mitre points** `o_k = a_k + m_k b_k`
//! are used instead, with `b_k` the unit bisector of the tether's outer angle at `a_k` and
//! `m_k = clearance / cos(phi_k / 2)` for the turning angle `phi_k` (capped at [`MITRE_LIMIT`]
//! times the clearance).
//! - **Descent** `start -> goal`: the SHP with each anchor kept on the side the tether turns to,
//!   first offset all along (no return nodes: the path runs a clearance beside the tether, away
//!   from what touches it), else with the returns onto the tether; the first that passes every
//!   check below.
//! - **Ascent** `goal -> start`: the route of Alg. 5 (one waypoint per anchor on its visibility
//!   edge, sometimes preceded by a via point towards the anchor), in order. A leg that passes
//!   closer than the clearance to anchors it has already released goes round them on the leg's
//!   side (the nearest such anchor first with its neighbours along the leg, each anchor at most
//!   once per route leg). On planes that are all tether-free any homotopic pair will do (§2.2.4):
//!   the ascent is the descent reversed.
//!
//! Every corner the construction places around an anchor aims at `clearance` times
//! `1 + `[`PLACEMENT_MARGIN`], so the clearance check that follows (which accepts `clearance`
//! less [`CLEARANCE_TOLERANCE`]) passes whatever the rounding of the corner's coordinates: a
//! corner the planner placed at the clearance is never the reason its own pair fails.
//!
//! # Checks (all exact except the distances)
//! A fixed corner (start, goal, route waypoint) closer than the clearance to an anchor fails the
//! pair before anything is bent: no push moves it (`fixed_corners_clear`). A corner owned by an
//! anchor and still too close to it is pushed outwards along its direction to the offset the
//! closed form gives (at most `PUSH_ROUNDS_PER_CORNER` pushes per corner). Both paths lie in
//! free space ([`Path::validate`]); both have the SHP's reduced crossing sequence (the
//! descent's, and the reversed ascent's), so they are homotopic to each other and to the tether
//! (thesis §2.1.1); both keep at least `clearance` (less [`CLEARANCE_TOLERANCE`]) from every
//! anchor; and on tether-demand planes the ascent is walked with its proximal anchor
//! tracked (it drops from `a_j` to `a_{j-1}` where the path crosses the visibility line `L_j`
//! beyond `a_j`), each stretch inside the wedge of its proximal anchor, band by band. The descent
//! is walked the same way (the proximal anchor rises where it crosses into the next visibility
//! half-plane); when it leaves a wedge the descent falls back to the ascent reversed, as the
//! thesis suggests ("the descent path could also be generated with those same waypoints").
//!
//! Algorithm 6 then takes the classes of the SPT search in order and returns the first with a
//! feasible ascent and a valid pair ([`plan_path_pair`]); the clearance is the scenario's
//! `robot.clearance_m`.

use crate::anchor_index::{AnchorIndex, Evaluation};
use crate::feasibility::{
    CLEARANCE_TOLERANCE, FeasibilityContext, FeasibilityReport, RouteCorner, check_feasibility,
    distance_to_segment,
};
use crate::spt::{
    RankedShp, SearchError, SearchOptions, SearchStats, SptPlanner, SptSearch, Termination,
};
use crate::stop::{CancelFlag, StopReason};
use crate::terrain::PlaneSeries;
use nalgebra::{Point2, Vector2};
use rappel_geometry::btm::Btm;
use rappel_geometry::predicates::orient2d;
use rappel_homotopy::crossing::CrossingSequence;
use rappel_homotopy::funnel::{Side, TautPath};
use rappel_homotopy::path::{Path, PathError};
use serde::{Deserialize, Serialize};

mod around;
mod corner;
pub use around::{ARC_STEP, offset_for_clearance};
use around::{Node, around};
use corner::Corner;
pub use corner::MITRE_LIMIT;

/// Relative margin by which the corners a pair places around an anchor clear its clearance: they
/// aim at `clearance * (1 + PLACEMENT_MARGIN)` (0.5 µm beyond a 0.5 m clearance), so that the check
/// that follows, which accepts `clearance * (1 - CLEARANCE_TOLERANCE)`, passes them whatever the
/// rounding of their coordinates: a few ulps of the map's coordinates, below 1e-6 of the
/// clearance while the coordinates stay under 1e9 clearances.
pub const PLACEMENT_MARGIN: f64 = 1e-6;

/// How far along its leg (a tether segment or an ascent leg) the path comes back onto it from an
/// anchor's foot, in target clearances: `sqrt(2)`. Any value above one leaves a tangent to the
/// clearance circle; larger ones give a flatter detour that runs farther beside the leg.
pub const DETOUR_REACH_CLEARANCES: f64 = std::f64::consts::SQRT_2;

/// A leg passing closer than this fraction of the clearance to a released anchor runs through it:
/// the detour goes to the released side of `L_k` whichever side the rounded leg passes on (a leg
/// from a waypoint on `L_k` to a via point on `L_k` passes the anchor, which lies on `L_k` too, on
/// the side its rounding chose, a few ulps of the coordinates away: 5e-8 m on a 0.5 m clearance
/// is far above that and far below any robot).
const THROUGH_ANCHOR_FRACTION: f64 = 1e-7;

/// An ascent/descent pair for one homotopy class.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PathPair {
    /// The class's rank in the SPT search.
    pub rank: usize,
    /// Ascent, from the goal to the start.
    pub ascent: Vec<Point2<f64>>,
    /// Descent, from the start to the goal.
    pub descent: Vec<Point2<f64>>,
    /// Length of the ascent, m.
    pub ascent_length: f64,
    /// Length of the descent, m.
    pub descent_length: f64,
    /// `true` when the descent is the ascent reversed (the offset SHP left a friction cone, or
    /// the planes are tether-free and the ascent is the descent reversed).
    pub descent_is_reversed_ascent: bool,
    /// The smallest distance from either path to an anchor, m (infinite without anchors).
    pub min_anchor_distance: f64,
    /// The reduced crossing sequence both paths share with the SHP.
    pub crossings: CrossingSequence,
}

/// Why no pair was built for a feasible class.
#[derive(
    Debug, Clone, PartialEq, Serialize, Deserialize, thiserror::Error, schemars::JsonSchema,
)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum PairFailure {
    /// A path leaves free space.
    #[error("the {which} path leaves free space: {message}")]
    LeavesFreeSpace {
        /// `"ascent"` or `"descent"`.
        which: String,
        /// Where.
        message: String,
    },
    /// A path is not homotopic to the SHP.
    #[error("the {which} path is not homotopic to the taut tether")]
    NotHomotopic {
        /// `"ascent"` or `"descent"`.
        which: String,
    },
    /// Following a path needs more tether than the robot has (the taut tether at its longest
    /// point along the path, with the anchors the path holds there).
    #[error(
        "the {which} path needs {needed:.2} m of tether, more than the robot's {available:.2} m"
    )]
    TetherTooShort {
        /// `"ascent"` or `"descent"`.
        which: String,
        /// The longest taut tether along the path, m.
        needed: f64,
        /// The robot's tether length, m.
        available: f64,
    },
    /// A path comes closer to an anchor than the clearance.
    #[error(
        "the {which} path passes {distance:.6} m from anchor {anchor}, inside its clearance of \
         {clearance} m (less the relative tolerance {CLEARANCE_TOLERANCE:e})"
    )]
    TooClose {
        /// `"ascent"` or `"descent"`.
        which: String,
        /// The anchor index `j`.
        anchor: usize,
        /// The distance, m.
        distance: f64,
        /// The clearance the anchor asks for, m.
        clearance: f64,
    },
    /// The ascent leaves the friction cone of its proximal anchor.
    #[error("the ascent leaves the friction cone of anchor {anchor}")]
    OutsideCone {
        /// The proximal anchor index `j` (0 = start).
        anchor: usize,
    },
}

/// The pair for one feasible class (module docs). `report` must be the class's feasibility.
pub fn path_pair(
    ctx: &FeasibilityContext<'_>,
    class: &RankedShp,
    report: &FeasibilityReport,
) -> Result<PathPair, PairFailure> {
    let taut = &class.shp.taut;
    let keep = vec![AnchorClearance::Keep; taut.anchors.len()];
    path_pair_with(
        ctx,
        PairInput {
            rank: class.rank,
            taut,
            crossings: &class.shp.crossings,
            route: &report.route,
            anchors: &keep,
        },
    )
}

/// How the paths of a pair pass one anchor.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AnchorClearance {
    /// At least the context's clearance away (a geometric anchor, thesis §2.4.3).
    Keep,
    /// Through the anchor itself: a solid friction anchor that the robot may drive over (thesis
    /// Alg. 10), its own waypoint in the ascent route
    /// ([`crate::feasibility::check_feasibility_with`]).
    DriveOver,
}

/// What [`path_pair_with`] builds a pair from: any taut tether with its reduced crossing sequence
/// in `ctx.btm`, the ascent route of its feasibility check, and how each anchor is passed.
#[derive(Debug, Clone, Copy)]
pub struct PairInput<'a> {
    /// The class's rank in the search.
    pub rank: usize,
    /// The taut tether (SHP).
    pub taut: &'a TautPath,
    /// Its reduced crossing sequence in `ctx.btm`.
    pub crossings: &'a CrossingSequence,
    /// The ascent route of its feasibility report.
    pub route: &'a [RouteCorner],
    /// One entry per anchor of `taut`, in order.
    pub anchors: &'a [AnchorClearance],
}

/// The pair of [`path_pair`] for any taut tether whose anchors are passed as `input.anchors`
/// says: anchors to [`AnchorClearance::DriveOver`] get no clearance (their mitre corner is the
/// anchor itself) and are left out of [`PathPair::min_anchor_distance`]; the checks are the same.
/// Used for friction classes ([`crate::frictional::search`]).
pub fn path_pair_with(
    ctx: &FeasibilityContext<'_>,
    input: PairInput<'_>,
) -> Result<PathPair, PairFailure> {
    path_pair_evaluated(ctx, input, Evaluation::Indexed)
}

/// [`path_pair_with`] with the anchors near each leg found as `evaluation` says:
/// [`Evaluation::Indexed`] (what every planner uses) or [`Evaluation::Direct`] (every anchor
/// tested against every leg: the earlier, quadratic form, the oracle of the equivalence tests;
/// both give identical pairs).
pub fn path_pair_evaluated(
    ctx: &FeasibilityContext<'_>,
    input: PairInput<'_>,
    evaluation: Evaluation,
) -> Result<PathPair, PairFailure> {
    let taut = input.taut;
    let anchors: Vec<Point2<f64>> = taut.anchors.iter().map(|a| a.point).collect();
    let index = AnchorIndex::new(&anchors, 2.0 * ctx.clearance, evaluation);
    let margin = 2.0 * ctx.clearance;
    let clearances: Vec<f64> = (0..anchors.len())
        .map(|k| match input.anchors.get(k) {
            Some(AnchorClearance::DriveOver) => 0.0,
            _ => ctx.clearance,
        })
        .collect();
    let offsets = mitre_offsets(taut, &clearances);
    let near = Near {
        index: &index,
        anchors: &anchors,
        clearances: &clearances,
        margin,
    };
    let word = input.crossings;
    let tether_free = ctx.terrain.all_tether_free();
    // The descent: the SHP offset by the clearance all along (every anchor kept by its arc and the
    // tangents between them), else the SHP left only round its anchors (back on the tether
    // between them: no obstacle near the tether away from an anchor can block it). Each must keep
    // the clearance, lie in free space in the class and, on tether-demand planes, stay in its
    // proximal anchor's wedge.
    let descent = rounded_descent(
        ctx.btm,
        taut,
        &clearances,
        &offsets,
        &near,
        word,
        |d| match walk(ctx.terrain, taut, d, false) {
            Some(anchor) if !tether_free => Err(PairFailure::OutsideCone { anchor }),
            _ => Ok(()),
        },
    );
    let ascent = if tether_free {
        descent.clone().map(|d| d.into_iter().rev().collect())
    } else {
        // The route's waypoints are fixed corners of the ascent: one too close to an anchor fails
        // the pair whatever the bends, so it is told before bending (the bends of a route that
        // hugs a long obstacle are many; see `bend_around_released`).
        fixed_corners_clear("ascent", input.route.iter().map(|c| c.point), &near).and_then(|()| {
            let bent = bend_around_released(input.route, &offsets, taut, &near);
            keep_clear("ascent", bent, &near)
        })
    };
    let ascent = ascent?;
    check_path(ctx.btm, "ascent", &ascent, word, true)?;
    if !tether_free && let Some(j) = walk(ctx.terrain, taut, &ascent, true) {
        return Err(PairFailure::OutsideCone { anchor: j });
    }
    let (descent, reversed) = match descent {
        Ok(d) => (d, tether_free),
        Err(_) => (ascent.iter().rev().copied().collect(), true),
    };
    if let Some(available) = ctx.tether_length {
        for (which, path, up) in [("ascent", &ascent, true), ("descent", &descent, false)] {
            let needed = tether_needed(taut, path, up);
            if needed > available {
                return Err(PairFailure::TetherTooShort {
                    which: which.to_string(),
                    needed,
                    available,
                });
            }
        }
    }
    let length = |p: &[Point2<f64>]| p.windows(2).map(|w| (w[1] - w[0]).norm()).sum::<f64>();
    let min_anchor_distance = anchors
        .iter()
        .zip(&clearances)
        .filter(|(_, c)| **c > 0.0 || ctx.clearance == 0.0)
        .flat_map(|(a, _)| {
            ascent
                .windows(2)
                .chain(descent.windows(2))
                .map(move |w| distance_to_segment(a, &w[0], &w[1]))
        })
        .fold(f64::INFINITY, f64::min);
    Ok(PathPair {
        rank: input.rank,
        ascent_length: length(&ascent),
        descent_length: length(&descent),
        ascent,
        descent,
        descent_is_reversed_ascent: reversed,
        min_anchor_distance,
        crossings: word.clone(),
    })
}

/// The descent of [`path_pair`] alone along any taut tether (the online session's continuation
/// from the robot, `crate::online`): each anchor rounded at the context's clearance, the corners
/// pushed clear, the path checked in free space and with the reduced crossing sequence
/// `crossings`. The path must also keep the clearance from the points `also` (the anchors of the
/// class the continuation belongs to, which it may pass without touching): no corner is placed
/// for them, so passing one too close fails. No ascent is built and the friction-cone walk is
/// not made (the tether's anchors before the path's start are not the path's). Fails as the
/// pair's descent would, with `which = "descent"` and anchors numbered along `taut`'s anchors
/// and then `also`'s.
pub fn descent_with_clearance(
    ctx: &FeasibilityContext<'_>,
    taut: &TautPath,
    crossings: &CrossingSequence,
    also: &[Point2<f64>],
) -> Result<Vec<Point2<f64>>, PairFailure> {
    let mut anchors: Vec<Point2<f64>> = taut.anchors.iter().map(|a| a.point).collect();
    let own = anchors.len();
    for p in also {
        if !anchors.contains(p) {
            anchors.push(*p);
        }
    }
    let index = AnchorIndex::new(&anchors, 2.0 * ctx.clearance, Evaluation::Indexed);
    let clearances = vec![ctx.clearance; anchors.len()];
    let offsets = mitre_offsets(taut, &clearances[..own]);
    let near = Near {
        index: &index,
        anchors: &anchors,
        clearances: &clearances,
        margin: 2.0 * ctx.clearance,
    };
    rounded_descent(
        ctx.btm,
        taut,
        &clearances[..own],
        &offsets,
        &near,
        crossings,
        |_| Ok(()),
    )
}

/// The descent of [`rounded_tether`] kept clear ([`keep_clear`]), in free space and in the class
/// of `word`, and accepted by `accept`: first offset all along, else with the returns onto the
/// tether (module docs); the second try's failure when both fail.
fn rounded_descent(
    btm: &Btm,
    taut: &TautPath,
    clearances: &[f64],
    offsets: &[Corner],
    near: &Near<'_>,
    word: &CrossingSequence,
    accept: impl Fn(&[Point2<f64>]) -> Result<(), PairFailure>,
) -> Result<Vec<Point2<f64>>, PairFailure> {
    let descent_of = |returns: bool| {
        let corners = rounded_tether(taut, clearances, offsets, returns);
        let d = keep_clear("descent", corners, near)?;
        check_path(btm, "descent", &d, word, false)?;
        accept(&d)?;
        Ok(d)
    };
    descent_of(false).or_else(|_| descent_of(true))
}

/// The mitre corners `o_j` (module docs), owned by their anchors.
fn mitre_offsets(taut: &TautPath, clearances: &[f64]) -> Vec<Corner> {
    let p = &taut.points;
    taut.anchors
        .iter()
        .enumerate()
        .map(|(k, a)| {
            let i = p.iter().position(|x| *x == a.point).unwrap_or(1);
            let (prev, next) = (p[i.saturating_sub(1)], p[(i + 1).min(p.len() - 1)]);
            let outer = (a.point - prev).normalize() - (next - a.point).normalize();
            let clearance = clearances[k];
            if clearance == 0.0 || outer.norm() == 0.0 {
                return Corner::fixed(a.point);
            }
            let m =
                (target(clearance) / (a.turning_angle / 2.0).cos()).min(MITRE_LIMIT * clearance);
            Corner {
                base: a.point,
                owner: Some((k + 1, outer.normalize(), m)),
            }
        })
        .collect()
}

/// The clearance a corner placed around an anchor of clearance `clearance` aims at (module docs).
fn target(clearance: f64) -> f64 {
    clearance * (1.0 + PLACEMENT_MARGIN)
}

/// The descent's corners before any push: the SHP from the start to the goal with each anchor of
/// non-zero clearance kept on the side the tether turns to at the target clearance ([`around`]);
/// with `returns`, the path back on the tether [`DETOUR_REACH_CLEARANCES`] target clearances along
/// each segment from its anchors where the segment has room for both (else offset all along); or
/// the mitre points `offsets` where no such path exists. An anchor of clearance zero is passed
/// through.
fn rounded_tether(
    taut: &TautPath,
    clearances: &[f64],
    offsets: &[Corner],
    returns: bool,
) -> Vec<Corner> {
    let mut nodes = vec![Node::through(taut.start())];
    // The previous node's reach along the tether (0 for a pass-through node).
    let mut reach_back = 0.0;
    for (i, a) in taut.anchors.iter().enumerate() {
        let c = target(clearances[i]);
        let reach = if returns && clearances[i] > 0.0 {
            DETOUR_REACH_CLEARANCES * c
        } else {
            0.0
        };
        push_returns(&mut nodes, reach_back, &a.point, reach);
        nodes.push(if clearances[i] > 0.0 {
            Node {
                point: a.point,
                rho: match a.side {
                    Side::Left => c,
                    Side::Right => -c,
                },
                k: i + 1,
            }
        } else {
            Node::through(a.point)
        });
        reach_back = reach;
    }
    push_returns(&mut nodes, reach_back, &taut.goal(), 0.0);
    nodes.push(Node::through(taut.goal()));
    around(&nodes).unwrap_or_else(|| {
        let mut out = vec![Corner::fixed(taut.start())];
        out.extend_from_slice(offsets);
        out.push(Corner::fixed(taut.goal()));
        out
    })
}

/// Appends the pass-through nodes on the straight piece from the last node of `nodes` to `to`:
/// `reach_back` along it from its start and `reach` before its end, where they fit in order
/// (nothing where one of them is 0 or they would overlap).
fn push_returns(nodes: &mut Vec<Node>, reach_back: f64, to: &Point2<f64>, reach: f64) {
    let from = nodes[nodes.len() - 1].point;
    let v = to - from;
    let len = v.norm();
    if (reach_back + reach).partial_cmp(&len) != Some(std::cmp::Ordering::Less) {
        return;
    }
    let dir = v / len;
    if reach_back > 0.0 {
        nodes.push(Node::through(from + dir * reach_back));
    }
    if reach > 0.0 {
        nodes.push(Node::through(to - dir * reach));
    }
}

/// The anchors of a pair's checks with their clearances, and the grid that finds the ones near a
/// leg.
struct Near<'a> {
    index: &'a AnchorIndex,
    /// `a_1 .. a_n` (`anchors[k - 1]` is `a_k`).
    anchors: &'a [Point2<f64>],
    /// The clearance kept from each, m.
    clearances: &'a [f64],
    /// Twice the largest clearance: the grid's margin, a superset of the anchors within any
    /// clearance of a leg.
    margin: f64,
}

impl Near<'_> {
    /// Calls `f(k, d)` with `d` the distance from `a_k` to the leg `p -> q` for every anchor
    /// `a_k` closer than its clearance (less [`CLEARANCE_TOLERANCE`]), in no particular order.
    fn too_close(&self, p: &Point2<f64>, q: &Point2<f64>, mut f: impl FnMut(usize, f64)) {
        // Per site: the distance is the point's, computed once for the anchors at it.
        self.index
            .visit_sites_near(&[*p, *q], self.margin, |a, ids| {
                let d = distance_to_segment(a, p, q);
                for &k in ids {
                    let k = k as usize;
                    if d < self.clearances[k - 1] * (1.0 - CLEARANCE_TOLERANCE) {
                        f(k, d);
                    }
                }
            });
    }
}

/// Bends every ascent leg that passes within the clearance of anchors it has already released
/// around them: by the path of [`leg_detour`] on the side of the leg away from them, or
/// through the nearest one's mitre corner where the leg has no room. The nearest such anchor first
/// (the lowest index among equally near ones) with its neighbours along the leg, then the pieces
/// the bend leaves, each checked again; each anchor bends a route leg at most once, so a route leg
/// gets at most `n` bends and `3 n` corners.
fn bend_around_released(
    route: &[RouteCorner],
    offsets: &[Corner],
    taut: &TautPath,
    near: &Near<'_>,
) -> Vec<Corner> {
    let n = near.anchors.len();
    let mut out = vec![Corner::fixed(route[0].point)];
    // `bent_on[k] == leg + 1`: anchor `k` already bends route leg `leg`.
    let mut bent_on = vec![0usize; n + 1];
    for (leg, w) in route.windows(2).enumerate() {
        let released = w[0].released_from.max(1)..=n;
        // The corners still to reach, the next one last: the piece checked runs from the last
        // corner placed to it.
        let mut pending = vec![Corner::fixed(w[1].point)];
        let mut from = Corner::fixed(w[0].point);
        while let Some(to) = pending.last().copied() {
            let (p, q) = (from.point(), to.point());
            let mut close: Vec<(usize, f64)> = Vec::new();
            near.too_close(&p, &q, |k, d| {
                if released.contains(&k) && bent_on[k] != leg + 1 {
                    close.push((k, d));
                }
            });
            let Some(&(k, _)) = close
                .iter()
                .min_by(|(ka, da), (kb, db)| da.total_cmp(db).then(ka.cmp(kb)))
            else {
                pending.pop();
                out.push(to);
                from = to;
                continue;
            };
            let bend = match leg_detour(k, &close, &p, &q, taut, near) {
                Some((members, corners)) => {
                    for j in members {
                        bent_on[j] = leg + 1;
                    }
                    corners
                }
                None => {
                    bent_on[k] = leg + 1;
                    vec![offsets[k - 1]]
                }
            };
            pending.extend(bend.into_iter().rev());
        }
    }
    out
}

/// The side of the leg `p -> q` (direction `dir`) on which the path keeps the released anchor
/// `a_k`: the sign of its node's radius ([`Node::rho`]; positive: `a_k` on the path's left), from
/// the side of the leg on which `a_k` lies (decided exactly, [`orient2d`]), or the released side
/// of `L_k` when the leg runs through `a_k` (within [`THROUGH_ANCHOR_FRACTION`] of its clearance
/// of its foot `foot`): the path passes on the released side.
fn keep_side(
    k: usize,
    p: &Point2<f64>,
    q: &Point2<f64>,
    dir: &Vector2<f64>,
    foot: &Point2<f64>,
    taut: &TautPath,
    near: &Near<'_>,
) -> f64 {
    let a = near.anchors[k - 1];
    let through = (foot - a).norm() < THROUGH_ANCHOR_FRACTION * near.clearances[k - 1];
    let o = orient2d(p, q, &a);
    if !through && o != 0.0 {
        return o.signum();
    }
    // Through the anchor: the path goes to the released side of `L_k`, so the anchor lies on
    // the side of the leg towards which the tether turns at it.
    let prev = if k == 1 {
        taut.start()
    } else {
        near.anchors[k - 2]
    };
    let l = a - prev;
    let towards_turn = match taut.anchors[k - 1].side {
        Side::Left => Vector2::new(-l.y, l.x),
        Side::Right => Vector2::new(l.y, -l.x),
    };
    let left = Vector2::new(-dir.y, dir.x);
    if left.dot(&towards_turn) > 0.0 {
        1.0
    } else {
        -1.0
    }
}

/// The path of the leg `p -> q` around the released anchor `a_k` and the anchors of `close`
/// (released, too close to the leg, with their distances) that chain to it along the leg (feet
/// closer than twice [`DETOUR_REACH_CLEARANCES`] target clearances apart), each kept on its side
/// ([`keep_side`]) by [`around`], back on the leg that reach before the first foot and after the
/// last where the leg has room; with the members it takes. The corners exclude `p` and `q`.
/// `None` when the foot of `a_k` is not inside the leg or no such path exists.
fn leg_detour(
    k: usize,
    close: &[(usize, f64)],
    p: &Point2<f64>,
    q: &Point2<f64>,
    taut: &TautPath,
    near: &Near<'_>,
) -> Option<(Vec<usize>, Vec<Corner>)> {
    let v = q - p;
    let len = v.norm();
    if len.is_nan() || len <= 0.0 {
        return None;
    }
    let dir = v / len;
    let reach = |j: usize| DETOUR_REACH_CLEARANCES * target(near.clearances[j - 1]);
    // (along the leg, k) of each candidate whose foot lies inside the leg.
    let mut along: Vec<(f64, usize)> = close
        .iter()
        .map(|&(j, _)| ((near.anchors[j - 1] - p).dot(&dir), j))
        .filter(|&(t, _)| t > 0.0 && t < len)
        .collect();
    along.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
    let at = along.iter().position(|x| x.1 == k)?;
    let link = |x: &(f64, usize), y: &(f64, usize)| y.0 - x.0 < reach(x.1) + reach(y.1);
    let (mut lo, mut hi) = (at, at);
    while lo > 0 && link(&along[lo - 1], &along[lo]) {
        lo -= 1;
    }
    while hi + 1 < along.len() && link(&along[hi], &along[hi + 1]) {
        hi += 1;
    }
    let run = &along[lo..=hi];
    let mut nodes = vec![Node::through(*p)];
    let (t0, k0) = run[0];
    if t0 > reach(k0) {
        nodes.push(Node::through(p + dir * (t0 - reach(k0))));
    }
    for &(t, j) in run {
        let side = keep_side(j, p, q, &dir, &(p + dir * t), taut, near);
        nodes.push(Node {
            point: near.anchors[j - 1],
            rho: side * target(near.clearances[j - 1]),
            k: j,
        });
    }
    let (t1, k1) = run[run.len() - 1];
    if len - t1 > reach(k1) {
        nodes.push(Node::through(p + dir * (t1 + reach(k1))));
    }
    nodes.push(Node::through(*q));
    let corners = around(&nodes)?;
    Some((
        run.iter().map(|x| x.1).collect(),
        corners[1..corners.len() - 1].to_vec(),
    ))
}

/// Rounds of [`keep_clear`] per corner of the path (each round pushes the corners of the worst
/// offence to the offset that clears it, [`offset_for_clearance`]): with one more corner, the
/// documented bound on its loop.
const PUSH_ROUNDS_PER_CORNER: usize = 8;

/// Fails with [`PairFailure::TooClose`] when one of the fixed corners `points` (start, goal,
/// route waypoints) lies closer to an anchor than its clearance (less [`CLEARANCE_TOLERANCE`]):
/// the corners [`keep_clear`] pushes are owned by anchors, a fixed one never moves, so every
/// path through it fails the clearance however the rest is bent. Names the closest (the first
/// corner, then the lowest anchor, among equally close ones), at its distance.
fn fixed_corners_clear(
    which: &str,
    points: impl Iterator<Item = Point2<f64>>,
    near: &Near<'_>,
) -> Result<(), PairFailure> {
    let mut worst: Option<(usize, usize, f64)> = None;
    for (i, p) in points.enumerate() {
        near.too_close(&p, &p, |k, d| {
            if worst.is_none_or(|(iw, kw, dw)| d < dw || (d == dw && i == iw && k < kw)) {
                worst = Some((i, k, d));
            }
        });
    }
    match worst {
        Some((_, anchor, distance)) => Err(PairFailure::TooClose {
            which: which.to_string(),
            anchor,
            distance,
            clearance: near.clearances[anchor - 1],
        }),
        None => Ok(()),
    }
}

/// Pushes owned corners away from their anchors until every segment keeps the clearance from
/// every anchor; fails naming the anchor when a segment that no owned corner can move is too
/// close, at once when a fixed corner is ([`fixed_corners_clear`]).
/// The worst offence is the smallest distance, the first leg and then the lowest anchor among
/// equal ones.
fn keep_clear(
    which: &str,
    mut corners: Vec<Corner>,
    near: &Near<'_>,
) -> Result<Vec<Point2<f64>>, PairFailure> {
    let clearances = near.clearances;
    let fixed = corners
        .iter()
        .filter(|c| c.owner.is_none())
        .map(Corner::point);
    fixed_corners_clear(which, fixed, near)?;
    let rounds = PUSH_ROUNDS_PER_CORNER * (corners.len() + 1);
    for round in 0..=rounds {
        let mut worst: Option<(usize, usize, f64)> = None;
        for i in 0..corners.len().saturating_sub(1) {
            let (p, q) = (corners[i].point(), corners[i + 1].point());
            near.too_close(&p, &q, |k, d| {
                if worst.is_none_or(|w| d < w.2 || (d == w.2 && w.0 == i && k < w.1)) {
                    worst = Some((i, k, d));
                }
            });
        }
        let Some((i, k, d)) = worst else {
            let mut points: Vec<Point2<f64>> = corners.iter().map(Corner::point).collect();
            points.dedup();
            return Ok(points);
        };
        let mut moved = false;
        let clearance = clearances[k - 1];
        let a = near.anchors[k - 1];
        for (this, other) in [(i, i + 1), (i + 1, i)] {
            let other = corners[other].point();
            if let Some((owner, dir, m)) = &mut corners[this].owner
                && *owner == k
                && round < rounds
            {
                // The offset that clears this segment with the other end where it is, and at
                // least a little outwards (the other end may move too); where no offset clears
                // it, the proportional step of the distance short.
                let step = *m * (clearance / d.max(1e-3 * clearance)).min(2.0) * (1.0 + 1e-6);
                let exact = offset_for_clearance(&a, &other, dir, target(clearance));
                *m = exact.map_or(step, |e| e.max(*m * (1.0 + PLACEMENT_MARGIN)));
                moved = true;
            }
        }
        if !moved {
            return Err(PairFailure::TooClose {
                which: which.to_string(),
                anchor: k,
                distance: d,
                clearance,
            });
        }
    }
    // The last round moves no corner and returns above; this is its answer should it not.
    Err(PairFailure::TooClose {
        which: which.to_string(),
        anchor: 0,
        distance: 0.0,
        clearance: 0.0,
    })
}

/// Free space and homotopy checks of one path (`reversed`: it runs goal to start).
fn check_path(
    btm: &Btm,
    which: &str,
    points: &[Point2<f64>],
    word: &CrossingSequence,
    reversed: bool,
) -> Result<(), PairFailure> {
    let forward: Vec<Point2<f64>> = if reversed {
        points.iter().rev().copied().collect()
    } else {
        points.to_vec()
    };
    let leaves = |e: PathError| PairFailure::LeavesFreeSpace {
        which: which.to_string(),
        message: e.to_string(),
    };
    let path = Path::new(forward).map_err(leaves)?;
    let chi = CrossingSequence::reduced_of_path(btm, &path).map_err(leaves)?;
    if &chi != word {
        return Err(PairFailure::NotHomotopic {
            which: which.to_string(),
        });
    }
    Ok(())
}

/// Walks `points` tracking the proximal anchor (`up`: an ascent from the goal, starting at `a_n`;
/// else a descent from the start, at `a_0`) and checks every stretch against the wedge of its
/// proximal anchor. The proximal anchor changes where the path crosses a visibility line `L_k`
/// past `a_k`: upwards out of the half-plane of `a_k` (releasing it), downwards into the
/// half-plane of `a_{k+1}`. Returns the first anchor whose wedge a stretch leaves.
fn walk(terrain: &PlaneSeries, taut: &TautPath, points: &[Point2<f64>], up: bool) -> Option<usize> {
    walk_stretches(taut, points, up, |_, apex, s, e| held(terrain, apex, s, e))
}

/// The longest taut tether along `points` (an ascent from the goal when `up`, else a descent from
/// the start), m: on each stretch the tether runs over the anchors `a_1 .. a_j` held there and
/// then straight to the robot; its length is the anchors' prefix plus the distance to `a_j`,
/// a convex function along a straight stretch, so its largest value is at a stretch's end.
pub fn tether_needed(taut: &TautPath, points: &[Point2<f64>], up: bool) -> f64 {
    let mut corners = vec![taut.start()];
    corners.extend(taut.anchors.iter().map(|a| a.point));
    let mut prefix = vec![0.0];
    for w in corners.windows(2) {
        prefix.push(prefix[prefix.len() - 1] + (w[1] - w[0]).norm());
    }
    let mut needed: f64 = 0.0;
    walk_stretches(taut, points, up, |j, apex, s, e| {
        needed = needed.max(prefix[j] + (s - apex).norm().max((e - apex).norm()));
        true
    });
    needed
}

/// The walk of [`walk`]: calls `visit(j, a_j, s, e)` for every stretch `s -> e` held by the
/// proximal anchor `a_j` (`a_0` is the start) and returns the first `j` for which it says
/// `false`.
fn walk_stretches(
    taut: &TautPath,
    points: &[Point2<f64>],
    up: bool,
    mut visit: impl FnMut(usize, &Point2<f64>, &Point2<f64>, &Point2<f64>) -> bool,
) -> Option<usize> {
    let mut corners = vec![taut.start()];
    corners.extend(taut.anchors.iter().map(|a| a.point));
    let n = corners.len() - 1;
    // Positive inside the visibility half-plane of `a_k`, negative on its released side.
    let side = |k: usize, x: &Point2<f64>| {
        let o = orient2d(&corners[k - 1], &corners[k], x);
        match taut.anchors[k - 1].side {
            Side::Left => o,
            Side::Right => -o,
        }
    };
    let beyond =
        |k: usize, x: &Point2<f64>| (x - corners[k]).dot(&(corners[k] - corners[k - 1])) > 0.0;
    let mut j = if up { n } else { 0 };
    for w in points.windows(2) {
        let (mut s, e) = (w[0], w[1]);
        // A robot standing on an anchor it drives over (a solid friction anchor, its own
        // waypoint) has no tether beyond it: the anchor before it holds the robot from there.
        while up && j >= 1 && s == corners[j] {
            j -= 1;
        }
        while !up && j < n && s == corners[j + 1] {
            j += 1;
        }
        while up && j >= 1 && side(j, &s) < 0.0 && beyond(j, &s) {
            j -= 1;
        }
        while !up && j < n && side(j + 1, &s) > 0.0 && beyond(j + 1, &s) {
            j += 1;
        }
        loop {
            let line = if up {
                (j >= 1).then_some(j)
            } else {
                (j < n).then_some(j + 1)
            };
            let crossing = line.and_then(|k| {
                let (vs, ve) = (side(k, &s), side(k, &e));
                let crosses = if up {
                    vs >= 0.0 && ve < 0.0
                } else {
                    vs <= 0.0 && ve > 0.0
                };
                let x = s + (e - s) * (vs / (vs - ve));
                (crosses && beyond(k, &x)).then_some(x)
            });
            let end = crossing.unwrap_or(e);
            if !visit(j, &corners[j], &s, &end) {
                return Some(j);
            }
            match crossing {
                Some(x) => {
                    j = if up { j - 1 } else { j + 1 };
                    s = x;
                }
                None => break,
            }
        }
    }
    None
}

/// `true` when the leg `a -> b` stays in the wedge of `apex`.
fn held(terrain: &PlaneSeries, apex: &Point2<f64>, a: &Point2<f64>, b: &Point2<f64>) -> bool {
    crate::feasibility::in_wedge(terrain, apex, a, b)
}

/// One homotopy class examined by Alg. 6.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ClassOutcome {
    /// The class and its SHP.
    pub class: RankedShp,
    /// Alg. 5 on its SHP.
    pub feasibility: FeasibilityReport,
    /// Why no pair was built although the class is feasible (`None` when a pair was built or the
    /// class is infeasible).
    pub pair_failure: Option<PairFailure>,
}

/// What Alg. 6 returns.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PairPlan {
    /// Every class examined, shortest first.
    pub classes: Vec<ClassOutcome>,
    /// The chosen pair: the shortest feasible class with a valid pair.
    pub pair: Option<PathPair>,
    /// Why the SPT search stopped.
    pub termination: Termination,
    /// Which condition of the options' [`crate::stop::StopCondition`] stopped the search (the
    /// expansion budget with its limit, the time limit, a cancel flag; `None` when it ended by
    /// its own rules).
    #[serde(default)]
    pub stop_reason: Option<crate::stop::StopReason>,
    /// The search's counters.
    pub stats: crate::spt::SearchStats,
}

/// Algorithm 6: search the classes in order (under `options`), check each for feasibility and
/// build the pair of the first feasible one. Examines every class the options allow (so that a
/// report can list them), and stops early only when `stop_at_first` is set.
///
/// ```
/// use nalgebra::Point2;
/// use rappel_geometry::{btm::Btm, map::Map, polygon::Polygon};
/// use rappel_terrain::plane_series::TerrainPlane;
/// use rappel_mechanics::friction_cone::TetherFrictionCone;
/// use rappel_planners::feasibility::FeasibilityContext;
/// use rappel_planners::path_pair::plan_path_pair;
/// use rappel_planners::spt::{SearchOptions, SptPlanner};
/// use rappel_planners::terrain::PlaneSeries;
/// let p = |x, y| Point2::new(x, y);
/// let map = Map::new(
///     Polygon::new(vec![p(0., 0.), p(40., 0.), p(40., 100.), p(0., 100.)]),
///     vec![Polygon::new(vec![p(18., 50.), p(22., 50.), p(22., 54.), p(18., 54.)])],
/// );
/// let btm = Btm::from_map(&map).unwrap();
/// let plane = TerrainPlane { y_top: 100.0, y_bottom: 0.0, slope_deg: 45.0, friction: 0.4 };
/// let terrain = PlaneSeries::new(&[plane], &TetherFrictionCone).unwrap();
/// let ctx = FeasibilityContext { btm: &btm, terrain: &terrain, clearance: 0.5, tether_length: None };
/// let options = SearchOptions::default().with_max_classes(Some(3)).unwrap();
/// let plan = plan_path_pair(&SptPlanner::new(&btm), p(21., 95.), p(20., 5.), &options, &ctx, false).unwrap();
/// let pair = plan.pair.expect("a feasible class");
/// assert_eq!(pair.rank, 1);
/// assert!(pair.min_anchor_distance >= 0.5 * (1.0 - 1e-9));
/// ```
pub fn plan_path_pair(
    planner: &SptPlanner<'_>,
    start: Point2<f64>,
    goal: Point2<f64>,
    options: &SearchOptions,
    ctx: &FeasibilityContext<'_>,
    stop_at_first: bool,
) -> Result<PairPlan, SearchError> {
    let mut classes = Vec::new();
    let mut plan = plan_path_pair_each(
        planner,
        start,
        goal,
        options,
        ctx,
        stop_at_first,
        &mut |c| classes.push(c),
    )?;
    plan.classes = classes;
    Ok(plan)
}

/// [`plan_path_pair`] handing each class to `on_class` as soon as it is decided (searched, Alg. 5
/// run, its pair built if it is the first feasible one) instead of keeping it: the returned plan's
/// `classes` is empty, so a caller streaming a report of K classes holds one class's geometry
/// (sleeve, reachable sets) at a time.
///
/// **Pipelined.** The SPT search runs on a thread of its own, at most [`CLASSES_AHEAD`] classes
/// ahead of the checks, which run (with `on_class`) on the calling thread in class order: on two
/// cores the next class is searched while this one's Alg. 5 runs. The answer does not depend on
/// it: the search never reads what the checks decide, every class is checked and handed over in
/// the order found, and the termination, stop reason and counters returned are the search's as
/// they stood when the last class handed over was found (a search that ran ahead is stopped by a
/// flag of its own and its extra classes dropped). Only a time limit, a wall-clock condition,
/// sees more classes found in the same time.
pub fn plan_path_pair_each(
    planner: &SptPlanner<'_>,
    start: Point2<f64>,
    goal: Point2<f64>,
    options: &SearchOptions,
    ctx: &FeasibilityContext<'_>,
    stop_at_first: bool,
    on_class: &mut dyn FnMut(ClassOutcome),
) -> Result<PairPlan, SearchError> {
    // The search's own stop flag, raised when the checks stop early (`stop_at_first`).
    let ahead = CancelFlag::new();
    let search_options = options
        .clone()
        .with_stop(options.stop().clone().or_cancel(ahead.clone()))?;
    std::thread::scope(|scope| {
        let (found, classes) = std::sync::mpsc::sync_channel::<Found>(CLASSES_AHEAD);
        scope.spawn(move || {
            let mut search = match planner.search(start, goal, &search_options) {
                Ok(search) => search,
                Err(e) => {
                    let _ = found.send(Found::Failed(e));
                    return;
                }
            };
            loop {
                let next = search.next_best();
                let state = SearchState::of(&search);
                let message = match next {
                    Ok(Some(class)) => Found::Class(Box::new(class), state),
                    Ok(None) => Found::End(state),
                    Err(e) => Found::Failed(e),
                };
                let last = !matches!(message, Found::Class(..));
                // A send fails once the checks have stopped listening: stop too.
                if found.send(message).is_err() || last {
                    return;
                }
            }
        });
        let mut pair = None;
        let outcome = loop {
            let (class, state) = match classes.recv() {
                Ok(Found::Class(class, state)) => (*class, state),
                Ok(Found::End(state)) => break Ok(state),
                Ok(Found::Failed(e)) => break Err(e),
                Err(_) => {
                    break Err(SearchError::Internal(
                        "the search thread ended without an answer".into(),
                    ));
                }
            };
            let feasibility = check_feasibility(ctx, &class.shp.taut);
            let mut pair_failure = None;
            if pair.is_none() && feasibility.feasible() {
                match path_pair(ctx, &class, &feasibility) {
                    Ok(p) => pair = Some(p),
                    Err(e) => pair_failure = Some(e),
                }
            }
            on_class(ClassOutcome {
                class,
                feasibility,
                pair_failure,
            });
            if stop_at_first && pair.is_some() {
                break Ok(state);
            }
        };
        // Stops a search that ran ahead (the scope then joins its thread).
        ahead.cancel();
        drop(classes);
        let state = outcome?;
        Ok(PairPlan {
            classes: Vec::new(),
            pair,
            termination: state.termination.unwrap_or(Termination::ClassCount),
            stop_reason: state.stop_reason,
            stats: state.stats,
        })
    })
}

/// How many classes the pipelined search ([`plan_path_pair_each`]) may have found and queued
/// beyond the one being checked: one, so that it stays at most a class or two ahead (a class
/// holds its SHP and sleeve).
pub const CLASSES_AHEAD: usize = 1;

/// What the search thread of [`plan_path_pair_each`] hands over.
enum Found {
    /// A class, with the search's state right after finding it.
    Class(Box<RankedShp>, SearchState),
    /// No more classes: the search's final state.
    End(SearchState),
    /// The search failed.
    Failed(SearchError),
}

/// The search's termination, stop reason and counters at one moment.
#[derive(Debug, Clone, Copy)]
struct SearchState {
    termination: Option<Termination>,
    stop_reason: Option<StopReason>,
    stats: SearchStats,
}

impl SearchState {
    fn of(search: &SptSearch<'_>) -> SearchState {
        SearchState {
            termination: search.termination(),
            stop_reason: search.stop_reason(),
            stats: search.stats(),
        }
    }
}
