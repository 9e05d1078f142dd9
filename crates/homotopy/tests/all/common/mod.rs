//! Shared helpers for the integration tests: small maps, an independent exact free-space check for
//! segments, and seeded random walks in free space.

#![allow(dead_code)]

use nalgebra::Point2;
use rappel_geometry::btm::Btm;
use rappel_geometry::generate::{CraterStripOptions, GeneratedMap, crater_strip};
use rappel_geometry::map::Map;
use rappel_geometry::polygon::Polygon;
use rappel_geometry::predicates::{SegmentContact, orient2d, segment_contact};

/// Relative slack allowed when comparing a length computed along one polyline with another's:
/// sums of square roots differ by a few ulps per segment.
pub const LENGTH_SLACK: f64 = 1e-9;

/// Shorthand for a point.
pub fn p(x: f64, y: f64) -> Point2<f64> {
    Point2::new(x, y)
}

/// A 10 x 10 square map with the square obstacle `[4, 6]^2`.
pub fn square_map() -> (Map, Btm) {
    let map = Map::new(
        Polygon::new(vec![p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)]),
        vec![Polygon::new(vec![
            p(4., 4.),
            p(6., 4.),
            p(6., 6.),
            p(4., 6.),
        ])],
    );
    let btm = Btm::from_map(&map).expect("valid map");
    (map, btm)
}

/// A small, dense crater strip: `n` convex obstacles in a 40 m wide strip.
pub fn small_strip(n: usize, seed: u64) -> (GeneratedMap, Btm) {
    let options = CraterStripOptions {
        obstacles: n,
        seed,
        width: 40.0,
        min_radius: 1.0,
        max_radius: 4.0,
        area_per_obstacle: 120.0,
        clearance: 0.5,
    };
    let g = crater_strip(&options).expect("valid options");
    let btm = Btm::from_map(&g.map).expect("generated maps are valid");
    (g, btm)
}

/// Counter-clockwise obstacle polygons of a map.
fn ccw_obstacles(map: &Map) -> Vec<Vec<Point2<f64>>> {
    map.obstacles
        .iter()
        .map(|o| o.to_counter_clockwise().vertices)
        .collect()
}

/// Independent exact check that the segment `ab` stays in the closed free space of a map whose
/// obstacles are convex, given that `a` is in free space. It may touch obstacles only at its own
/// endpoints when those are obstacle vertices, or run exactly along one obstacle edge.
pub fn segment_clear(map: &Map, a: &Point2<f64>, b: &Point2<f64>) -> bool {
    if a == b {
        return false;
    }
    for ring in std::iter::once(map.boundary.vertices.clone()).chain(ccw_obstacles(map)) {
        let n = ring.len();
        for i in 0..n {
            let (e0, e1) = (ring[i], ring[(i + 1) % n]);
            match segment_contact(a, b, &e0, &e1) {
                SegmentContact::Disjoint => {}
                SegmentContact::Crossing => return false,
                SegmentContact::Touching => {
                    let is_edge = (*a == e0 && *b == e1) || (*a == e1 && *b == e0);
                    let shares = *a == e0 || *a == e1 || *b == e0 || *b == e1;
                    let collinear = orient2d(a, b, &e0) == 0.0 && orient2d(a, b, &e1) == 0.0;
                    if !(is_edge || (shares && !collinear)) {
                        return false;
                    }
                }
            }
        }
    }
    // At an endpoint on an obstacle vertex the segment must leave outside the obstacle's (convex)
    // interior angle.
    for ring in ccw_obstacles(map) {
        let n = ring.len();
        for k in 0..n {
            let (prev, v, next) = (ring[(k + n - 1) % n], ring[k], ring[(k + 1) % n]);
            for (end, other) in [(a, b), (b, a)] {
                if *end == v && orient2d(&v, &next, other) > 0.0 && orient2d(&prev, &v, other) > 0.0
                {
                    return false;
                }
            }
        }
    }
    true
}

/// One step of a random walk: either a free move (`angle`, `length`) or, when `snap`, a move to
/// the `pick`-th nearest obstacle vertex.
#[derive(Debug, Clone, Copy)]
pub struct Step {
    pub snap: bool,
    pub angle: f64,
    pub length: f64,
    pub pick: usize,
}

/// A random walk from `start` taking the steps that [`segment_clear`] accepts (others are skipped).
pub fn random_walk(map: &Map, start: Point2<f64>, steps: &[Step]) -> Vec<Point2<f64>> {
    let vertices: Vec<Point2<f64>> = map
        .obstacles
        .iter()
        .flat_map(|o| o.vertices.iter().copied())
        .collect();
    let mut points = vec![start];
    for s in steps {
        let a = *points.last().expect("non-empty");
        let b = if s.snap && !vertices.is_empty() {
            let mut near = vertices.clone();
            near.sort_by(|u, v| (u - a).norm().total_cmp(&(v - a).norm()));
            near[s.pick % near.len().min(6)]
        } else {
            Point2::new(
                a.x + s.length * s.angle.cos(),
                a.y + s.length * s.angle.sin(),
            )
        };
        if segment_clear(map, &a, &b) {
            points.push(b);
        }
    }
    points
}

/// proptest strategy for walk steps.
pub fn steps(max: usize) -> impl proptest::strategy::Strategy<Value = Vec<Step>> {
    use proptest::prelude::*;
    prop::collection::vec(
        (0u8..10, 0.0..std::f64::consts::TAU, 1.0..15.0f64, 0usize..6),
        1..max,
    )
    .prop_map(|v| {
        v.into_iter()
            .map(|(k, angle, length, pick)| Step {
                snap: k < 3,
                angle,
                length,
                pick,
            })
            .collect()
    })
}
