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
    /// (`crates/rappel/tests/all/anchor_index.rs`): both forms give identical reports.
    Direct,
}

/// The anchors `a_1 .. a_n` of one taut tether (ids `1 ..= n`), in a grid of their distinct
/// points ("sites").
///
/// A class that winds `w` times round an obstacle touches each of its hull vertices `w` times:
/// `w` anchors at one point. A grid of the anchors would hold `w` entries per point, and every
/// query near the obstacle would visit `w` times as many, so a class's queries would cost its
/// anchors times its windings (the star's K = 100 classes, up to fifty windings, spent most of
/// their time there). The grid holds each point once, with the ids of the anchors at it
/// (ascending), so a query costs the points near it; [`AnchorIndex::visit_sites_near`] hands a
/// point over once with its ids, for callers whose predicate depends on the point and at most on
/// the smallest id. With [`Evaluation::Direct`] every anchor is its own site (no grid, no
/// merging): the earlier form.
#[derive(Debug, Clone)]
pub struct AnchorIndex {
    /// `a_1 .. a_n`.
    points: Vec<Point2<f64>>,
    /// The sites' points.
    sites: Vec<Point2<f64>>,
    /// The ids at site `s`: `ids[starts[s] .. starts[s + 1]]`, ascending.
    starts: Vec<u32>,
    ids: Vec<u32>,
    /// Over the sites; `None` for [`Evaluation::Direct`] or no anchors.
    grid: Option<SpatialGrid>,
}

impl AnchorIndex {
    /// The index of `anchors` (`a_1 .. a_n`). `pad` (m, the largest margin the queries will use)
    /// pads the grid's box, which keeps its cells square-ish when the anchors are collinear.
    /// Anchors with bit-identical coordinates share a site.
    pub fn new(anchors: &[Point2<f64>], pad: f64, evaluation: Evaluation) -> AnchorIndex {
        let indexed = evaluation == Evaluation::Indexed && !anchors.is_empty();
        // Anchor ids (from 0) grouped by point: sorted by the coordinates' bits, then by id.
        let mut order: Vec<u32> = (0..anchors.len() as u32).collect();
        if indexed {
            let key = |i: u32| {
                let p = anchors[i as usize];
                (p.x.to_bits(), p.y.to_bits(), i)
            };
            order.sort_unstable_by_key(|&i| key(i));
        }
        let (mut sites, mut starts, mut ids) =
            (Vec::new(), Vec::new(), Vec::with_capacity(order.len()));
        for &i in &order {
            let p = anchors[i as usize];
            let same = indexed
                && sites.last().is_some_and(|q: &Point2<f64>| {
                    q.x.to_bits() == p.x.to_bits() && q.y.to_bits() == p.y.to_bits()
                });
            if !same {
                starts.push(ids.len() as u32);
                sites.push(p);
            }
            ids.push(i + 1);
        }
        starts.push(ids.len() as u32);
        let grid = indexed.then(|| {
            let b = Aabb::of_points(sites.iter());
            let (w, h) = b.size();
            // At least a thousandth of the anchors' extent, so that a zero pad still gives a
            // grid of bounded size.
            let pad = pad.abs().max(1e-3 * w.max(h));
            let bounds = Aabb {
                min: Point2::new(b.min.x - pad, b.min.y - pad),
                max: Point2::new(b.max.x + pad, b.max.y + pad),
            };
            let boxes: Vec<Aabb> = sites.iter().map(|p| Aabb { min: *p, max: *p }).collect();
            SpatialGrid::packed(bounds, sites.len(), &boxes)
        });
        AnchorIndex {
            points: anchors.to_vec(),
            sites,
            starts,
            ids,
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

    /// The number of distinct anchor points (sites); `n` with [`Evaluation::Direct`].
    pub fn site_count(&self) -> usize {
        self.sites.len()
    }

    /// `true` without anchors.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// The box holding every anchor (inverted and empty without anchors).
    pub fn bounds(&self) -> Aabb {
        Aabb::of_points(self.points.iter())
    }

    /// Calls `f(p, ids)` for every site `p` that lies within `margin` of the convex hull of
    /// `corners`, and possibly for others (each at most once, in no particular order), with the
    /// ids `j` of the anchors `a_j = p` (ascending, at least one); with [`Evaluation::Direct`] for
    /// every anchor, in order, each alone. Callers decide each site with their own predicate, so
    /// the answer never depends on which superset this is.
    pub fn visit_sites_near(
        &self,
        corners: &[Point2<f64>],
        margin: f64,
        mut f: impl FnMut(&Point2<f64>, &[u32]),
    ) {
        let mut site = |s: usize| {
            let ids = &self.ids[self.starts[s] as usize..self.starts[s + 1] as usize];
            f(&self.sites[s], ids);
        };
        match &self.grid {
            Some(grid) => grid.visit_near_convex(corners, margin, |id| site(id as usize)),
            None => (0..self.sites.len()).for_each(site),
        }
    }

    /// Calls `f(j)` for every anchor `a_j` that lies within `margin` of the convex hull of
    /// `corners`, and possibly for others (each at most once, in no particular order); with
    /// [`Evaluation::Direct`] for every anchor, in order. Callers decide each anchor with their
    /// own predicate, so the answer never depends on which superset this is.
    pub fn visit_near(&self, corners: &[Point2<f64>], margin: f64, mut f: impl FnMut(usize)) {
        self.visit_sites_near(corners, margin, |_, ids| {
            ids.iter().for_each(|&j| f(j as usize));
        });
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
