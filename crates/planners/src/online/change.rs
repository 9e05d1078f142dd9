//! Map changes discovered during a descent (thesis §3.5.2; online paper §III-A): every error of
//! the prior map is a new obstacle, a phantom obstacle, a shifted or reshaped obstacle, or a
//! changed boundary, and the first three reduce to adding and removing obstacles (a reshape is a
//! removal followed by an addition). Each addition or removal is a local retriangulation of the
//! BTM (Lemma 3.5.1, [`rappel_geometry::btm::Btm::insert_obstacle`] and
//! [`rappel_geometry::btm::Btm::remove_obstacle`]); a changed boundary rebuilds the BTM, which the
//! session reports as such.

use nalgebra::Point2;
use rappel_geometry::dcel::ObstacleId;
use rappel_geometry::polygon::{PointInPolygon, Polygon};
use serde::Serialize;

/// One change of the map, in the words of thesis §3.5.2.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MapChange {
    /// An entirely new, unforeseen obstacle appears.
    Add(Polygon),
    /// A map obstacle is found to be a phantom: it disappears.
    Remove(ObstacleId),
    /// An obstacle has shifted or its outline is different: removed, then added anew.
    Reshape {
        /// The obstacle as the map has it.
        obstacle: ObstacleId,
        /// Its true outline.
        polygon: Polygon,
    },
    /// The boundary of the planning region is different (a full rebuild, not a local update).
    Boundary(Polygon),
}

impl MapChange {
    /// A short name: `add`, `remove`, `reshape` or `boundary`.
    pub fn kind(&self) -> &'static str {
        match self {
            MapChange::Add(_) => "add",
            MapChange::Remove(_) => "remove",
            MapChange::Reshape { .. } => "reshape",
            MapChange::Boundary(_) => "boundary",
        }
    }

    /// The polygon the change brings into the map, if any.
    pub fn new_polygon(&self) -> Option<&Polygon> {
        match self {
            MapChange::Add(p) | MapChange::Reshape { polygon: p, .. } => Some(p),
            MapChange::Remove(_) | MapChange::Boundary(_) => None,
        }
    }
}

/// `true` when `p` lies in the closed polygon (exact).
pub(crate) fn covers(polygon: &Polygon, p: &Point2<f64>) -> bool {
    polygon.locate(p) != PointInPolygon::Outside
}

/// `true` when `p` is strictly outside the boundary polygon or on it (exact).
pub(crate) fn outside_boundary(boundary: &Polygon, p: &Point2<f64>) -> bool {
    boundary.locate(p) != PointInPolygon::Inside
}

/// A point strictly inside a simple polygon, for its H-signature pole (thesis eq. 2.2): the
/// centroid of the first ear whose centroid is verified (exactly) to lie inside; the vertex
/// average as a last resort for convex input. `None` for a degenerate polygon.
pub(crate) fn interior_point(polygon: &Polygon) -> Option<Point2<f64>> {
    let v = &polygon.vertices;
    let n = v.len();
    let candidates = (0..n).map(|i| {
        let (a, b, c) = (v[(i + n - 1) % n], v[i], v[(i + 1) % n]);
        Point2::from((a.coords + b.coords + c.coords) / 3.0)
    });
    let mean = Point2::from(v.iter().map(|p| p.coords).sum::<nalgebra::Vector2<f64>>() / n as f64);
    std::iter::once(mean)
        .chain(candidates)
        .find(|c| polygon.locate(c) == PointInPolygon::Inside)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interior_points_are_inside() {
        let p = |x, y| Point2::new(x, y);
        // A concave "L": its vertex average lies inside, the notch ear's centroid does not.
        let l = Polygon::new(vec![
            p(0., 0.),
            p(4., 0.),
            p(4., 1.),
            p(1., 1.),
            p(1., 4.),
            p(0., 4.),
        ]);
        let c = interior_point(&l).unwrap();
        assert_eq!(l.locate(&c), PointInPolygon::Inside);
        let tri = Polygon::new(vec![p(0., 0.), p(3., 0.), p(0., 3.)]);
        assert_eq!(
            tri.locate(&interior_point(&tri).unwrap()),
            PointInPolygon::Inside
        );
    }
}
