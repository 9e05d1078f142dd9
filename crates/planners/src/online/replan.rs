//! Replanning from where the robot is (thesis Alg. 13, `A*(H_c, update)`; online paper §III-B):
//! the SPT search continues over the updated BTM with the H-signatures of rejected classes as
//! constraints, and each candidate class is reached from the robot's position either directly
//! (its sleeve begins with the tether already laid) or by **backtracking**: ascending along the
//! travelled descent to the **junction**, then descending the new sleeve.
//!
//! # The junction
//! The new sleeve leaves the current one after their last common anchor. The junction is the
//! last point of the travelled path at which the taut laid tether wraps a prefix of the new
//! class's anchors (same map vertices, same sides, same order): up to there the tether is laid
//! as the new class needs it, and nothing has to be unwound. Comparing anchors rather than raw
//! crossing sequences matters: the robot's own path crosses diagonals the new SHP's sleeve does
//! not (it wanders inside a triangle fan beside the taut line), which the continuation undoes
//! without any ascent; only a wrong wrap around an obstacle needs the robot to climb back.
//!
//! # The continuation
//! With the tether laid along `tau` (start to robot), the robot must end in class `C` at the goal:
//! it moves along some `q` with `tau . q` in `C`. The shortest such `q` from junction `j` is the
//! SHP of the path `reverse(tau[..j]) . pi_C` (back to the start along the laid tether, then down
//! `C`'s SHP) with its endpoints fixed: the funnel pulls it taut, so it never revisits the laid
//! part. Only the ascent to the junction follows the travelled path itself, which is known to be
//! traversable (the thesis' backtracking). The session descends along it with the clearance
//! (`session`, [`crate::path_pair::descent_with_clearance`]).
//!
//! # Constraints
//! H-signatures are homology invariants ([`rappel_homotopy::h_signature`]), as in the thesis; a
//! rejected class is recorded with the obstacles that existed when it was rejected, and a
//! candidate matches it when their winding counts agree on those obstacles (an obstacle added
//! later splits the rejected class, and every part of it stays rejected). A removal may make a
//! rejected class feasible again (an anchor disappears), so removals clear the constraints.

use nalgebra::Point2;
use rappel_geometry::btm::Btm;
use rappel_geometry::dcel::ObstacleId;
use rappel_homotopy::funnel::Side;
use rappel_homotopy::h_signature::HSignature;
use rappel_homotopy::path::Path;
use rappel_homotopy::shp::{ShortestHomotopicPath, shortest_homotopic_path};
use rappel_homotopy::{HomotopyError, TautPath};
use serde::Serialize;

/// A class rejected as infeasible (Alg. 12 line 18, Alg. 13 line 13).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RejectedClass {
    /// Its H-signature.
    pub h_signature: HSignature,
    /// The obstacles alive when it was rejected, sorted.
    pub obstacles: Vec<ObstacleId>,
    /// Its SHP length when rejected, m.
    pub length: f64,
    /// Why it was rejected.
    pub reason: String,
}

impl RejectedClass {
    /// `true` when `h` winds like this class around every obstacle it knew that still exists
    /// (`alive` tells which do).
    pub fn matches(&self, h: &HSignature, alive: impl Fn(ObstacleId) -> bool) -> bool {
        self.obstacles
            .iter()
            .filter(|o| alive(**o))
            .all(|&o| h.winding(o) == self.h_signature.winding(o))
    }
}

/// Where and how far the robot backtracks for a candidate class.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Junction {
    /// Index in the travelled path of the junction point.
    pub index: usize,
    /// The junction point.
    pub point: Point2<f64>,
    /// Length of the ascent back along the travelled path, m (0 when the class continues from
    /// the robot's position).
    pub backtrack: f64,
}

/// `(vertex, side)` of each anchor of a taut path.
fn anchor_word(taut: &TautPath) -> Vec<(u32, Side)> {
    taut.anchors.iter().map(|a| (a.vertex.0, a.side)).collect()
}

/// The junction of the laid tether `travelled` (start to robot, in free space) with the class
/// whose SHP is `class`: the last travelled point where the taut laid tether wraps a prefix of
/// the class's anchors, on the same sides (module docs). The start always qualifies, so this
/// never fails on a valid path. Quadratic in the travelled path's length, which the simulator's
/// step budget bounds.
pub fn junction(
    btm: &Btm,
    travelled: &[Point2<f64>],
    class: &TautPath,
) -> Result<Junction, HomotopyError> {
    let word = anchor_word(class);
    let mut back = 0.0;
    for k in (1..travelled.len()).rev() {
        let prefix = Path::new(travelled[..=k].to_vec())?;
        let laid = anchor_word(&shortest_homotopic_path(btm, &prefix)?.taut);
        if word.starts_with(&laid) {
            return Ok(Junction {
                index: k,
                point: travelled[k],
                backtrack: back,
            });
        }
        back += (travelled[k] - travelled[k - 1]).norm();
    }
    Ok(Junction {
        index: 0,
        point: travelled[0],
        backtrack: back,
    })
}

/// The taut continuation from `travelled[index]` to the goal in the class of `class_shp` (module
/// docs): the SHP of `reverse(travelled[..=index]) . class_shp`, with its reduced crossing
/// sequence (what a descent with clearance along it must keep).
pub fn continuation(
    btm: &Btm,
    travelled: &[Point2<f64>],
    index: usize,
    class_shp: &[Point2<f64>],
) -> Result<ShortestHomotopicPath, HomotopyError> {
    let mut pts: Vec<Point2<f64>> = travelled[..=index].iter().rev().copied().collect();
    for p in class_shp {
        if pts.last() != Some(p) {
            pts.push(*p);
        }
    }
    let path = Path::new(pts)?;
    shortest_homotopic_path(btm, &path)
}

/// Length of a polyline, m.
pub fn polyline_length(points: &[Point2<f64>]) -> f64 {
    points.windows(2).map(|w| (w[1] - w[0]).norm()).sum()
}
