//! Shared inputs for rappel's criterion benchmarks (see `benches/`) and the cross-checks against
//! peers in `tests/`. The benchmarks live in their own crate so that peers used only for
//! comparison (spade, polyanya) stay out of the library crates.

pub mod proc_stats;

/// The benchmarks and examples that use this crate (every comparison with polyanya or spade) run
/// on the allocator the `rappel` command line installs (`rappel::huge_pages`: large arrays on
/// 2 MiB pages), both sides of a comparison alike, as they share the process.
#[global_allocator]
static ALLOC: rappel::huge_pages::HugePageAlloc = rappel::huge_pages::HugePageAlloc;

use glam::Vec2;
use nalgebra::Point2;
use polyanya::{Mesh, Polygon as PolyPolygon, Vertex as PolyVertex};
use rappel_geometry::btm::{Btm, Location};
use rappel_geometry::map::Map;
use rappel_geometry::polygon::Polygon;
use spade::Point2 as SpadePoint;
use std::collections::HashMap;

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

/// [`polyanya_mesh`] in polyanya's best configuration for long queries: its triangles merged into
/// convex polygons (`Mesh::merge_polygons`, polyanya's own merger), then baked again (the
/// point-location BVH and the island labels).
pub fn polyanya_mesh_merged(btm: &Btm, origin: Point2<f64>) -> Mesh {
    let mut mesh = polyanya_mesh(btm, origin);
    mesh.merge_polygons();
    mesh.bake();
    mesh
}

/// `p - origin` in polyanya's `f32`.
pub fn to_vec2(p: Point2<f64>, origin: Point2<f64>) -> Vec2 {
    Vec2::new((p.x - origin.x) as f32, (p.y - origin.y) as f32)
}

/// A map from a polyanya v2 mesh file: the free space is the union of its polygons; its boundary
/// edges (neighbour -1) chain into rings, the one of largest area is the map boundary and the
/// others are obstacles. Panics on a malformed file (benchmark input, not user input).
///
/// ```
/// // One square polygon: four vertices (each with one neighbouring polygon) and no neighbours
/// // across its edges.
/// let mesh = "mesh 2 4 1  0 0 1 0  1 0 1 0  1 1 1 0  0 1 1 0  4 0 1 2 3 -1 -1 -1 -1";
/// let map = rappel_benches::map_from_polyanya_v2(mesh);
/// assert_eq!((map.boundary.len(), map.obstacles.len()), (4, 0));
/// ```
pub fn map_from_polyanya_v2(text: &str) -> Map {
    let mut it = text.split_whitespace();
    let mut next = || it.next().expect("complete mesh file");
    assert_eq!(next(), "mesh");
    assert_eq!(next(), "2");
    let nv: usize = next().parse().expect("vertex count");
    let np: usize = next().parse().expect("polygon count");
    let mut points = Vec::with_capacity(nv);
    for _ in 0..nv {
        let x: f64 = next().parse().expect("x");
        let y: f64 = next().parse().expect("y");
        let k: usize = next().parse().expect("neighbour count");
        for _ in 0..k {
            next();
        }
        points.push(Point2::new(x, y));
    }
    // Boundary edge a -> b (polygon counter-clockwise, so free space on its left) keyed by a.
    let mut succ: HashMap<usize, usize> = HashMap::new();
    for _ in 0..np {
        let n: usize = next().parse().expect("polygon size");
        let v: Vec<usize> = (0..n).map(|_| next().parse().expect("vertex")).collect();
        let p: Vec<i64> = (0..n).map(|_| next().parse().expect("neighbour")).collect();
        for i in 0..n {
            // p[i] is across the edge v[i-1] v[i].
            if p[i] == -1 {
                let a = v[(i + n - 1) % n];
                assert!(
                    succ.insert(a, v[i]).is_none(),
                    "a pinch vertex in the arena mesh"
                );
            }
        }
    }
    let mut rings: Vec<Vec<Point2<f64>>> = Vec::new();
    while let Some(&first) = succ.keys().min() {
        let mut ring = Vec::new();
        let mut v = first;
        while let Some(w) = succ.remove(&v) {
            ring.push(points[v]);
            v = w;
        }
        rings.push(ring);
    }
    let area = |r: &[Point2<f64>]| {
        (0..r.len())
            .map(|i| {
                let (a, b) = (r[i], r[(i + 1) % r.len()]);
                a.x * b.y - b.x * a.y
            })
            .sum::<f64>()
    };
    let outer = (0..rings.len())
        .max_by(|&i, &j| area(&rings[i]).total_cmp(&area(&rings[j])))
        .expect("a ring");
    let boundary = Polygon::new(rings.swap_remove(outer));
    Map::new(boundary, rings.into_iter().map(Polygon::new).collect())
}

/// The start-goal pairs of a MovingAI scenario file (a version line, then `bucket map width
/// height start_x start_y goal_x goal_y optimal_length` per query). Panics on a malformed file.
///
/// ```
/// let scen = "version 1\n0 arena.map 49 49 1.5 2.5 30.25 40 45.1\n";
/// let pairs = rappel_benches::scenario_pairs(scen);
/// assert_eq!(pairs, vec![(nalgebra::Point2::new(1.5, 2.5), nalgebra::Point2::new(30.25, 40.0))]);
/// ```
pub fn scenario_pairs(text: &str) -> Vec<(Point2<f64>, Point2<f64>)> {
    text.lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let f: Vec<f64> = l
                .split_whitespace()
                .skip(4)
                .take(4)
                .map(|x| x.parse().expect("a number"))
                .collect();
            (Point2::new(f[0], f[1]), Point2::new(f[2], f[3]))
        })
        .collect()
}

/// The median of `values` under `cmp` (the upper middle one of an even count), `None` when there
/// are none: the statistic the interleaved examples print. Sorts `values` in place.
///
/// ```
/// use rappel_benches::median_by;
/// assert_eq!(median_by(&mut [3.0, 1.0, 2.0, 9.0], f64::total_cmp), Some(3.0));
/// assert_eq!(median_by::<u32>(&mut [], Ord::cmp), None);
/// ```
pub fn median_by<T: Copy>(
    values: &mut [T],
    cmp: impl FnMut(&T, &T) -> std::cmp::Ordering,
) -> Option<T> {
    values.sort_unstable_by(cmp);
    values.get(values.len() / 2).copied()
}

/// `true` when `p` is a point of free space (on a free triangle, edge or map vertex).
fn free(btm: &Btm, p: &Point2<f64>) -> bool {
    matches!(
        btm.locate(p),
        Location::Triangle(_) | Location::Edge(_) | Location::Vertex(_)
    )
}

/// The first free point at or to the right of `p` in steps of 0.25 m (the generated strips leave
/// at least 0.5 m between obstacles, so a few steps suffice); `None` when none is found within
/// 100 m.
pub fn nudge_free(btm: &Btm, p: Point2<f64>) -> Option<Point2<f64>> {
    (0..400)
        .map(|i| Point2::new(p.x + 0.25 * f64::from(i), p.y))
        .find(|q| free(btm, q))
}

/// The benchmarks' short query on a strip whose start and goal are `start` and `goal`: from 20 m
/// left and 25 m above the strip's middle to 20 m right and 25 m below it (about 64 m), each end
/// moved right onto free space ([`nudge_free`]); `None` when either end finds none.
///
/// ```
/// use rappel_geometry::{btm::Btm, generate::{CraterStripOptions, crater_strip}};
/// let g = crater_strip(&CraterStripOptions::new(100, 1)).unwrap();
/// let btm = Btm::from_map(&g.map).unwrap();
/// let (a, b) = rappel_benches::short_query(&btm, g.start, g.goal).unwrap();
/// assert!((a - b).norm() > 60.0 && (a - b).norm() < 70.0);
/// ```
pub fn short_query(
    btm: &Btm,
    start: Point2<f64>,
    goal: Point2<f64>,
) -> Option<(Point2<f64>, Point2<f64>)> {
    let mid = Point2::new(0.5 * (start.x + goal.x), 0.5 * (start.y + goal.y));
    Some((
        nudge_free(btm, Point2::new(mid.x - 20.0, mid.y + 25.0))?,
        nudge_free(btm, Point2::new(mid.x + 20.0, mid.y - 25.0))?,
    ))
}
