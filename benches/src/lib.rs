//! Shared inputs for rappel's criterion benchmarks (see `benches/`) and the cross-checks against
//! peers in `tests/`. The benchmarks live in their own crate so that peers used only for
//! comparison (spade, polyanya) stay out of the library crates.

use glam::Vec2;
use nalgebra::Point2;
use polyanya::{Mesh, Polygon as PolyPolygon, Vertex as PolyVertex};
use rappel_geometry::btm::Btm;
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

/// The polyanya navigation mesh of a BTM's free triangles (counter-clockwise, compact vertices),
/// in coordinates relative to `origin` (polyanya works in `f32`: the origin keeps the long strips'
/// coordinates small). Built directly from the DCEL (each vertex's free triangles in
/// counter-clockwise order, then the obstacle gap at a map vertex): polyanya's own `Trimesh`
/// conversion looks up every vertex's triangles by scanning all triangles, which takes minutes
/// at 100,000 obstacles.
pub fn polyanya_mesh(btm: &Btm, origin: Point2<f64>) -> Mesh {
    let d = btm.dcel();
    let mut tri_index = vec![u32::MAX; d.triangle_capacity()];
    for (i, t) in btm.triangles().enumerate() {
        tri_index[t.index()] = i as u32;
    }
    let mut index = vec![u32::MAX; d.vertex_capacity()];
    let mut vertices = Vec::new();
    let mut polygons = Vec::new();
    for t in btm.triangles() {
        let tri = d.triangle_vertices(t).map(|v| {
            if index[v.index()] == u32::MAX {
                index[v.index()] = vertices.len() as u32;
                let mut around: Vec<u32> = d
                    .edges_around_vertex(v)
                    .map(|h| tri_index[h.triangle().index()])
                    .collect();
                if d.is_map_vertex(v) {
                    around.push(u32::MAX);
                }
                vertices.push(PolyVertex::new(to_vec2(d.point(v), origin), around));
            }
            index[v.index()]
        });
        polygons.push(PolyPolygon::new(tri.to_vec(), false));
    }
    let mut mesh = Mesh::new(vertices, polygons).expect("a BTM is a valid navigation mesh");
    mesh.bake();
    mesh
}

/// `p - origin` in polyanya's `f32`.
pub fn to_vec2(p: Point2<f64>, origin: Point2<f64>) -> Vec2 {
    Vec2::new((p.x - origin.x) as f32, (p.y - origin.y) as f32)
}
