//! Shared inputs for rappel's criterion benchmarks (see `benches/`) and the cross-checks against
//! peers in `tests/`. The benchmarks live in their own crate so that peers used only for
//! comparison (spade, polyanya) stay out of the library crates.

use rappel_geometry::map::Map;
use spade::Point2 as SpadePoint;

/// A map as spade's constrained-Delaunay input: every ring vertex, and every ring edge as a pair
/// of vertex indices.
///
/// ```
/// use nalgebra::Point2;
/// use rappel_geometry::{map::Map, polygon::Polygon};
/// let sq = Polygon::new(vec![Point2::new(0., 0.), Point2::new(1., 0.), Point2::new(1., 1.), Point2::new(0., 1.)]);
/// let (pts, edges) = rappel_benches::spade_input(&Map::new(sq, vec![]));
/// assert_eq!((pts.len(), edges.len()), (4, 4));
/// ```
pub fn spade_input(map: &Map) -> (Vec<SpadePoint<f64>>, Vec<[usize; 2]>) {
    let mut pts = Vec::with_capacity(map.vertex_count());
    let mut edges = Vec::with_capacity(map.vertex_count());
    for (_, ring) in map.rings() {
        let first = pts.len();
        let n = ring.len();
        for (i, p) in ring.vertices.iter().enumerate() {
            pts.push(SpadePoint::new(p.x, p.y));
            edges.push([first + i, first + (i + 1) % n]);
        }
    }
    (pts, edges)
}
