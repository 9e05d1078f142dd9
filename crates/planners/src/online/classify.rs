//! How a map change affects the current sleeve (thesis §3.5.3; online paper §III-B): the four
//! cases of an added obstacle and the two of a removed one, decided from the affected region
//! (the sleeve triangles the local retriangulation replaced) and the sleeve's two sides.
//!
//! # The sides of a sleeve
//! Sleeve triangle `T_i` is entered through portal `d_i` and left through `d_{i+1}`; its third
//! edge lies on the traveller's left or right (the portal's destination is its left endpoint,
//! [`rappel_homotopy::sleeve`]). In the start triangle the two edges other than `d_1`, and in the
//! goal triangle the two other than `d_n`, are assigned by the portal endpoint they touch. The
//! **left side** of the sleeve is the union of its left edges, the **right side** that of its right
//! edges. Side edges are recorded as vertex pairs, whose ids and positions never change, so the
//! classification still reads them after the triangles are gone.
//!
//! # The cases (an added obstacle `O` that meets the sleeve)
//! - `O` crosses both sides: the sleeve is cut across, **(1) blocked**;
//! - `O` crosses neither side: it lies inside the sleeve with free space on both hands, the
//!   sleeve is **(4) split** into a left and a right sleeve;
//! - `O` crosses one side only: the sleeve is narrowed; **(2)** when its SHP is unchanged,
//!   **(3)** when it changed.
//!
//! A removed obstacle that meets the sleeve **opens** it (its wall is gone) and, when the SHP
//! changes, **changes its anchors**. A change that meets no sleeve triangle is outside the
//! sleeve: it is kept for later (§3.5.3, "the retriangulation may be useful later"). Every
//! test is an exact segment-contact predicate on map vertices and the obstacle's input points.

use nalgebra::Point2;
use rappel_geometry::btm::Btm;
use rappel_geometry::dcel::{HalfEdgeId, VertexId};
use rappel_geometry::polygon::Polygon;
use rappel_geometry::predicates::{SegmentContact, segment_contact};
use rappel_homotopy::sleeve::Sleeve;
use serde::{Deserialize, Serialize};

/// What a change did to the current sleeve (thesis §3.5.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum ChangeCase {
    /// The change meets no triangle of the current sleeve: kept for later.
    OutsideSleeve,
    /// (1) The new obstacle cuts the sleeve across: no path of the class stays in it.
    Blocked,
    /// (2) The sleeve's geometry changed, its SHP did not.
    GeometryChanged,
    /// (3) The sleeve is not split but its SHP changed.
    ShpChanged,
    /// (4) The new obstacle lies inside the sleeve: a left and a right sleeve around it.
    Split,
    /// A removed obstacle bordered the sleeve: the sleeve widened, its SHP did not change.
    SleeveOpened,
    /// A removed obstacle changed the SHP (its anchors).
    AnchorsChanged,
    /// The boundary changed: the BTM was rebuilt and the class traced through it again.
    Rebuilt,
}

impl ChangeCase {
    /// The thesis' number of the case, where it has one.
    pub fn number(&self) -> Option<u8> {
        match self {
            ChangeCase::Blocked => Some(1),
            ChangeCase::GeometryChanged => Some(2),
            ChangeCase::ShpChanged => Some(3),
            ChangeCase::Split => Some(4),
            _ => None,
        }
    }

    /// A short phrase for reports.
    pub fn describe(&self) -> &'static str {
        match self {
            ChangeCase::OutsideSleeve => "outside the current sleeve (kept for later)",
            ChangeCase::Blocked => "(1) the sleeve is blocked",
            ChangeCase::GeometryChanged => "(2) the sleeve changed, its SHP did not",
            ChangeCase::ShpChanged => "(3) the SHP changed, the sleeve is not split",
            ChangeCase::Split => "(4) the sleeve split into a left and a right sleeve",
            ChangeCase::SleeveOpened => "a removed obstacle opened the sleeve",
            ChangeCase::AnchorsChanged => "a removed obstacle changed the anchors",
            ChangeCase::Rebuilt => "the boundary changed: BTM rebuilt",
        }
    }
}

/// The side edges of every sleeve triangle, as vertex pairs (module docs).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SleeveSides {
    /// Per sleeve position: its edge on the left, if any (a triangle of the sleeve has at most
    /// one edge on each side besides its portals).
    pub left: Vec<Option<(VertexId, VertexId)>>,
    /// Per sleeve position: its edge on the right, if any.
    pub right: Vec<Option<(VertexId, VertexId)>>,
}

impl SleeveSides {
    /// The sides of `sleeve` in `btm` (module docs). Linear in the sleeve's length.
    pub fn of(btm: &Btm, sleeve: &Sleeve) -> SleeveSides {
        let d = btm.dcel();
        let tris = sleeve.triangles();
        let portals = sleeve.portals();
        let n = tris.len();
        let mut sides = SleeveSides {
            left: vec![None; n],
            right: vec![None; n],
        };
        let pair = |h: HalfEdgeId| (d.origin(h), d.destination(h));
        for i in 0..n {
            let exit = portals.get(i).copied();
            let entry = if i > 0 { d.twin(portals[i - 1]) } else { None };
            match (entry, exit) {
                (_, Some(e)) => {
                    // next(e) starts at the exit's left endpoint, prev(e) ends at its right one.
                    let (l, r) = (e.next(), e.prev());
                    if Some(l) != entry {
                        sides.left[i] = Some(pair(l));
                    }
                    if Some(r) != entry {
                        sides.right[i] = Some(pair(r));
                    }
                }
                (Some(g), None) => {
                    // Entering across g: g starts at the left endpoint.
                    sides.left[i] = Some(pair(g.prev()));
                    sides.right[i] = Some(pair(g.next()));
                }
                (None, None) => {}
            }
        }
        sides
    }
}

/// `true` when the closed polygon's boundary meets the closed segment `ab` (exact).
pub fn polygon_meets_segment(polygon: &Polygon, a: &Point2<f64>, b: &Point2<f64>) -> bool {
    polygon
        .edges()
        .any(|(p, q)| segment_contact(p, q, a, b) != SegmentContact::Disjoint)
}

/// Which sides of the sleeve the new obstacle crosses, looking at the affected positions only.
pub fn cut_sides(
    btm: &Btm,
    sides: &SleeveSides,
    affected: &[usize],
    polygon: &Polygon,
) -> (bool, bool) {
    let d = btm.dcel();
    let meets = |edge: &Option<(VertexId, VertexId)>| {
        edge.is_some_and(|(a, b)| polygon_meets_segment(polygon, &d.point(a), &d.point(b)))
    };
    let left = affected.iter().any(|&i| meets(&sides.left[i]));
    let right = affected.iter().any(|&i| meets(&sides.right[i]));
    (left, right)
}

/// The case of an added obstacle from the sides it cuts and whether the SHP changed.
pub fn case_of_addition(left_cut: bool, right_cut: bool, shp_changed: bool) -> ChangeCase {
    match (left_cut, right_cut) {
        (true, true) => ChangeCase::Blocked,
        (false, false) => ChangeCase::Split,
        _ if shp_changed => ChangeCase::ShpChanged,
        _ => ChangeCase::GeometryChanged,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rappel_geometry::map::Map;
    use rappel_homotopy::path::Path;
    use rappel_homotopy::shp::shortest_homotopic_path;

    #[test]
    fn every_side_edge_is_an_edge_of_its_triangle_and_sides_cover_the_rest() {
        let p = |x, y| Point2::new(x, y);
        let map = Map::new(
            Polygon::new(vec![p(0., 0.), p(20., 0.), p(20., 20.), p(0., 20.)]),
            vec![Polygon::new(vec![p(8., 8.), p(12., 8.), p(10., 12.)])],
        );
        let btm = Btm::from_map(&map).unwrap();
        let path = Path::new(vec![p(10., 19.), p(3., 10.), p(10., 1.)]).unwrap();
        let shp = shortest_homotopic_path(&btm, &path).unwrap();
        let sides = SleeveSides::of(&btm, &shp.sleeve);
        let d = btm.dcel();
        for (i, t) in shp.sleeve.triangles().iter().enumerate() {
            let vs = d.triangle_vertices(*t);
            let portals = usize::from(i > 0) + usize::from(i + 1 < sides.left.len());
            let count =
                usize::from(sides.left[i].is_some()) + usize::from(sides.right[i].is_some());
            assert_eq!(count + portals, 3, "position {i}");
            for (a, b) in sides.left[i].iter().chain(&sides.right[i]) {
                assert!(vs.contains(a) && vs.contains(b));
            }
        }
        // The sleeve goes west of the obstacle: the obstacle's edges are on its left (east).
        let on_left = sides.left.iter().flatten().any(|&(a, b)| {
            btm.obstacle_of_vertex(a).is_some() && btm.obstacle_of_vertex(b).is_some()
        });
        let on_right = sides.right.iter().flatten().any(|&(a, b)| {
            btm.obstacle_of_vertex(a).is_some() && btm.obstacle_of_vertex(b).is_some()
        });
        assert!(on_left && !on_right);
    }

    #[test]
    fn cases_follow_the_cut_sides() {
        assert_eq!(case_of_addition(true, true, true), ChangeCase::Blocked);
        assert_eq!(case_of_addition(false, false, false), ChangeCase::Split);
        assert_eq!(
            case_of_addition(true, false, false),
            ChangeCase::GeometryChanged
        );
        assert_eq!(case_of_addition(false, true, true), ChangeCase::ShpChanged);
    }
}
