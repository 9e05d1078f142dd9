//! Euclidean shortest paths in a polygon with holes by the visibility graph and Dijkstra's
//! algorithm (Lozano-Pérez and Wesley, 1979): the brute-force, independent oracle that the SPT
//! search's first class is tested against (tests and `cargo xtask regress`).
//!
//! It shares nothing with the BTM, the funnels or the crossing sequences. The shortest path in a
//! closed polygon with holes is a polyline whose interior vertices are map vertices, so it is the
//! shortest path in the graph whose nodes are the start, the goal and every map vertex, with an
//! edge between two nodes whose segment lies in the closed free space. A segment lies in free
//! space when it properly crosses no map edge and every piece between consecutive map vertices on
//! it either runs along a map edge or has its midpoint in free space (exact point-in-polygon).
//! `O(n^3)` time: for maps of a few hundred vertices.

use crate::min_heap::MinEntry;
use nalgebra::Point2;
use rappel_geometry::map::Map;
use rappel_geometry::polygon::PointInPolygon;
use rappel_geometry::predicates::{SegmentContact, point_on_segment, segment_contact};
use std::collections::BinaryHeap;

/// A shortest path found by the oracle.
#[derive(Debug, Clone, PartialEq)]
pub struct VisibilityPath {
    /// The polyline from start to goal.
    pub points: Vec<Point2<f64>>,
    /// Its length.
    pub length: f64,
}

/// The Euclidean shortest path from `start` to `goal` in the closed free space of `map`, or
/// `None` when the goal cannot be reached (or an endpoint is not in free space).
///
/// ```
/// use nalgebra::Point2;
/// use rappel_geometry::{map::Map, polygon::Polygon};
/// use rappel_planners::visibility_graph::shortest_path;
/// let p = |x, y| Point2::new(x, y);
/// let map = Map::new(
///     Polygon::new(vec![p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)]),
///     vec![Polygon::new(vec![p(4., 4.), p(6., 4.), p(6., 6.), p(4., 6.)])],
/// );
/// let best = shortest_path(&map, p(5., 9.), p(5., 1.)).unwrap();
/// assert!((best.length - (2.0 * 10f64.sqrt() + 2.0)).abs() < 1e-12);
/// ```
pub fn shortest_path(map: &Map, start: Point2<f64>, goal: Point2<f64>) -> Option<VisibilityPath> {
    if !is_free(map, &start) || !is_free(map, &goal) {
        return None;
    }
    let mut nodes = vec![start, goal];
    nodes.extend(map.rings().flat_map(|(_, r)| r.vertices.iter().copied()));
    let n = nodes.len();
    let mut dist = vec![f64::INFINITY; n];
    let mut parent = vec![usize::MAX; n];
    let mut done = vec![false; n];
    let mut heap = BinaryHeap::new();
    dist[0] = 0.0;
    heap.push(MinEntry { key: 0.0, item: 0 });
    while let Some(MinEntry { key: d, item: u }) = heap.pop() {
        if done[u] {
            continue;
        }
        done[u] = true;
        if u == 1 {
            break;
        }
        for v in 0..n {
            if done[v] || v == u {
                continue;
            }
            let nd = d + (nodes[v] - nodes[u]).norm();
            if nd < dist[v] && segment_is_free(map, &nodes[u], &nodes[v]) {
                dist[v] = nd;
                parent[v] = u;
                heap.push(MinEntry { key: nd, item: v });
            }
        }
    }
    if !dist[1].is_finite() {
        return None;
    }
    let mut points = vec![goal];
    let mut x = 1;
    while x != 0 {
        x = parent[x];
        points.push(nodes[x]);
    }
    points.reverse();
    Some(VisibilityPath {
        points,
        length: dist[1],
    })
}

/// `true` when `p` lies in the closed free space of `map`.
fn is_free(map: &Map, p: &Point2<f64>) -> bool {
    map.boundary.locate(p) != PointInPolygon::Outside
        && map
            .obstacles
            .iter()
            .all(|o| o.locate(p) != PointInPolygon::Inside)
}

/// `true` when the closed segment `ab` lies in the closed free space of `map` (module docs).
pub fn segment_is_free(map: &Map, a: &Point2<f64>, b: &Point2<f64>) -> bool {
    let edges: Vec<(Point2<f64>, Point2<f64>)> = map
        .rings()
        .flat_map(|(_, r)| r.edges().map(|(c, d)| (*c, *d)))
        .collect();
    if edges
        .iter()
        .any(|(c, d)| segment_contact(a, b, c, d) == SegmentContact::Crossing)
    {
        return false;
    }
    let along = |p: &Point2<f64>| (p - a).dot(&(b - a));
    let mut stops: Vec<Point2<f64>> = vec![*a, *b];
    stops.extend(
        map.rings()
            .flat_map(|(_, r)| r.vertices.iter())
            .filter(|v| point_on_segment(a, b, v)),
    );
    stops.sort_by(|p, q| along(p).total_cmp(&along(q)));
    stops.dedup();
    stops.windows(2).all(|w| {
        let (p, q) = (w[0], w[1]);
        edges
            .iter()
            .any(|(c, d)| point_on_segment(c, d, &p) && point_on_segment(c, d, &q))
            || is_free(map, &Point2::from((p.coords + q.coords) / 2.0))
    })
}
