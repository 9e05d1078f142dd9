//! Cross-check of rappel's BTM against an independent constrained Delaunay triangulation: spade's
//! `bulk_load_cdt` of the same vertices and map edges, restricted to the free space. For points in
//! general position the CDT is unique, so the two triangle sets must be identical. (spade is a
//! dependency of this dev-only crate only.)

use rappel_geometry::btm::Btm;
use rappel_geometry::generate::{CraterStripOptions, crater_strip};
use rappel_geometry::map::Map;
use spade::{ConstrainedDelaunayTriangulation, Point2 as SpadePoint, Triangulation};

type Tri = [(u64, u64); 3];

fn key(p: (f64, f64)) -> (u64, u64) {
    (p.0.to_bits(), p.1.to_bits())
}

fn canonical(mut t: Tri) -> Tri {
    t.sort_unstable();
    t
}

fn rappel_triangles(map: &Map) -> Vec<Tri> {
    let btm = Btm::from_map(map).expect("valid map");
    let mut out: Vec<Tri> = btm
        .triangles()
        .map(|t| canonical(btm.dcel().triangle_points(t).map(|p| key((p.x, p.y)))))
        .collect();
    out.sort_unstable();
    out
}

fn spade_triangles(map: &Map) -> Vec<Tri> {
    let (pts, edges) = rappel_benches::spade_input(map);
    let cdt = ConstrainedDelaunayTriangulation::<SpadePoint<f64>>::bulk_load_cdt(pts, edges)
        .expect("spade accepts the map");
    let mut out: Vec<Tri> = cdt
        .inner_faces()
        .filter_map(|f| {
            let v = f.vertices().map(|v| {
                let p = v.position();
                (p.x, p.y)
            });
            // Keep the faces in free space: their centroid is neither in an obstacle nor outside.
            let c = nalgebra::Point2::new(
                (v[0].0 + v[1].0 + v[2].0) / 3.0,
                (v[0].1 + v[1].1 + v[2].1) / 3.0,
            );
            map.free_space_violation(&c)
                .is_none()
                .then(|| canonical(v.map(key)))
        })
        .collect();
    out.sort_unstable();
    out
}

#[test]
fn btm_equals_spade_cdt_restricted_to_free_space() {
    for seed in 0..40u64 {
        let n = 5 + (seed as usize * 37) % 300;
        let map = crater_strip(&CraterStripOptions::new(n, seed))
            .expect("valid options")
            .map;
        let ours = rappel_triangles(&map);
        let theirs = spade_triangles(&map);
        assert_eq!(
            ours.len(),
            theirs.len(),
            "seed {seed}: triangle counts differ"
        );
        assert_eq!(ours, theirs, "seed {seed}: triangulations differ");
    }
}
