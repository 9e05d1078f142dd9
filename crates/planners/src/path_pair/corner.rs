//! The corners of a path pair being built ([`Corner`]: fixed, or pushed off an anchor) and how
//! far a mitre corner may be pushed ([`MITRE_LIMIT`]); shared by the pair's construction
//! ([`super`]) and the arcs around anchors ([`super::around`]).

use nalgebra::{Point2, Vector2};

/// Largest mitre offset, in clearances (a sharp turn would push the mitre point far away).
pub const MITRE_LIMIT: f64 = 4.0;

/// A corner of a path being built: a fixed point (start, goal, waypoint), or a point pushed off
/// anchor `k` along the unit direction `dir` by `m` metres.
#[derive(Debug, Clone, Copy)]
pub(super) struct Corner {
    pub(super) base: Point2<f64>,
    pub(super) owner: Option<(usize, Vector2<f64>, f64)>,
}

impl Corner {
    pub(super) fn fixed(p: Point2<f64>) -> Corner {
        Corner {
            base: p,
            owner: None,
        }
    }

    pub(super) fn point(&self) -> Point2<f64> {
        match self.owner {
            Some((_, dir, m)) => self.base + dir * m,
            None => self.base,
        }
    }
}
