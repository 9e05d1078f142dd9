//! The anchors of one taut tether in a uniform grid (issue 10, long obstacles): which anchors can
//! lie near a move, a leg or a region, for the clearance queries of Alg. 5
//! ([`crate::feasibility`]) and Alg. 6 ([`crate::path_pair`]).
//!
//! Around a long convex obstacle every anchor of a class lies in the `x` window of every
//! visibility edge (a star's anchors all sit on one arc), so scanning the anchors per edge, per
//! cell or per leg is quadratic in the anchors. The index answers "the anchors that can come within
//! `margin` of the convex hull of these corners" with the grid cells that hull meets
//! ([`SpatialGrid::visit_near_convex`]): a **superset**, on which the callers evaluate exactly
//! the predicate they evaluated on every anchor before, so every decision is unchanged (the
//! margins the callers pass are twice the distance their predicate looks at, far above the
//! rounding of a distance). [`Evaluation::Direct`] visits every anchor instead: the earlier
//! form, kept as the oracle of the equivalence tests.

use nalgebra::Point2;
use rappel_geometry::polygon::Aabb;
use rappel_geometry::spatial_grid::SpatialGrid;

/// How Alg. 5 and Alg. 6 find the anchors near a move and evaluate the cells of a visibility
/// line.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Evaluation {
    /// The anchor grid for every anchor query, and one exact wedge verdict per span between the
    /// verdict's own critical values (the clearance values only split cells for the waypoint
    /// preference; `feasibility::crossing` module docs).
    #[default]
    Indexed,
    /// Every anchor visited by every query and every cell evaluated on its own: quadratic in the
    /// anchors of a long obstacle. The oracle of the equivalence tests
    /// (`crates/rappel/tests/anchor_index.rs`): both forms give identical reports.
    Direct,
}

/// The anchors `a_1 .. a_n` of one taut tether (ids `1 ..= n`), in a grid.
#[derive(Debug, Clone)]
pub struct AnchorIndex {
    /// `a_1 .. a_n`.
    points: Vec<Point2<f64>>,
    /// `None` for [`Evaluation::Direct`] or no anchors.
    grid: Option<SpatialGrid>,
}

impl AnchorIndex {
    /// The index of `anchors` (`a_1 .. a_n`). `pad` (m, the largest margin the queries will use)
    /// pads the grid's box, which keeps its cells square-ish when the anchors are collinear.
    pub fn new(anchors: &[Point2<f64>], pad: f64, evaluation: Evaluation) -> AnchorIndex {
        let grid = (evaluation == Evaluation::Indexed && !anchors.is_empty()).then(|| {
            let b = Aabb::of_points(anchors.iter());
            let (w, h) = b.size();
            // At least a thousandth of the anchors' extent, so that a zero pad still gives a
            // grid of bounded size.
            let pad = pad.abs().max(1e-3 * w.max(h));
            let bounds = Aabb {
                min: Point2::new(b.min.x - pad, b.min.y - pad),
                max: Point2::new(b.max.x + pad, b.max.y + pad),
            };
            let boxes: Vec<Aabb> = anchors.iter().map(|p| Aabb { min: *p, max: *p }).collect();
            SpatialGrid::packed(bounds, anchors.len(), &boxes)
        });
        AnchorIndex {
            points: anchors.to_vec(),
            grid,
        }
    }

    /// Anchor `a_j` (`j` from 1).
    pub fn point(&self, j: usize) -> Point2<f64> {
        self.points[j - 1]
    }

    /// The number of anchors `n`.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// `true` without anchors.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// The box holding every anchor (inverted and empty without anchors).
    pub fn bounds(&self) -> Aabb {
        Aabb::of_points(self.points.iter())
    }

    /// Calls `f(j)` for every anchor `a_j` that lies within `margin` of the convex hull of
    /// `corners`, and possibly for others (each at most once, in no particular order); with
    /// [`Evaluation::Direct`] for every anchor, in order. Callers decide each anchor with their
    /// own predicate, so the answer never depends on which superset this is.
    pub fn visit_near(&self, corners: &[Point2<f64>], margin: f64, mut f: impl FnMut(usize)) {
        match &self.grid {
            Some(grid) => grid.visit_near_convex(corners, margin, |id| f(id as usize + 1)),
            None => (1..=self.points.len()).for_each(f),
        }
    }

    /// The anchors of [`AnchorIndex::visit_near`], sorted by index.
    pub fn near(&self, corners: &[Point2<f64>], margin: f64) -> Vec<usize> {
        let mut out = Vec::new();
        self.visit_near(corners, margin, |j| out.push(j));
        out.sort_unstable();
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Distance from `p` to the segment `a b`.
    fn to_segment(p: &Point2<f64>, a: &Point2<f64>, b: &Point2<f64>) -> f64 {
        crate::feasibility::distance_to_segment(p, a, b)
    }

    #[test]
    fn the_index_finds_every_anchor_near_a_leg_and_few_others() {
        // The anchors of a long convex obstacle: 2,000 points on an arc.
        let anchors: Vec<Point2<f64>> = (0..2000)
            .map(|i| {
                let a = 1.2 * i as f64 / 2000.0;
                Point2::new(50.0 + 20.0 * a.cos(), 55.0 + 20.0 * a.sin())
            })
            .collect();
        let index = AnchorIndex::new(&anchors, 1.0, Evaluation::Indexed);
        let direct = AnchorIndex::new(&anchors, 1.0, Evaluation::Direct);
        assert_eq!(direct.near(&[Point2::new(0.0, 0.0)], 0.5).len(), 2000);
        let mut visited = 0;
        for k in (0..2000).step_by(37) {
            // A short leg along the tangent at anchor k.
            let a = anchors[k];
            let t = Point2::new(-(a.y - 55.0), a.x - 50.0) / 20.0;
            let leg = [a + t.coords * 0.3, a + t.coords * 2.0];
            let near = index.near(&leg, 1.0);
            visited += near.len();
            for (i, p) in anchors.iter().enumerate() {
                if to_segment(p, &leg[0], &leg[1]) <= 1.0 {
                    assert!(
                        near.contains(&(i + 1)),
                        "anchor {} near leg {k} missed",
                        i + 1
                    );
                }
            }
        }
        // A leg meets the cells of a few metres of the arc (a few hundred anchors), not the whole
        // arc.
        assert!(visited < 55 * 2000 / 4, "{visited} anchors visited");
    }
}
