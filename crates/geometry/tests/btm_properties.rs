//! Property tests of the BTM on random maps: the invariants of `Btm::check_invariants` after a fresh
//! build and after random sequences of local updates, id stability across updates, and point
//! location against an independent brute-force answer.

use nalgebra::Point2;
use proptest::prelude::*;
use rappel_geometry::btm::{Btm, Location};
use rappel_geometry::generate::{CraterStripOptions, crater_strip};
use rappel_geometry::map::Map;
use rappel_geometry::polygon::{PointInPolygon, Polygon};

fn strip(obstacles: usize, seed: u64) -> Map {
    crater_strip(&CraterStripOptions::new(obstacles, seed))
        .expect("valid options")
        .map
}

/// A map with exactly cocircular and collinear vertices: a grid of axis-aligned squares, the
/// worst case for Delaunay tie-breaking.
fn grid_of_squares(k: usize) -> Map {
    let size = 10.0 * k as f64 + 10.0;
    let boundary = Polygon::new(vec![
        Point2::new(0.0, 0.0),
        Point2::new(size, 0.0),
        Point2::new(size, size),
        Point2::new(0.0, size),
    ]);
    let mut obstacles = Vec::new();
    for i in 0..k {
        for j in 0..k {
            let (x, y) = (10.0 * i as f64 + 8.0, 10.0 * j as f64 + 8.0);
            obstacles.push(Polygon::new(vec![
                Point2::new(x, y),
                Point2::new(x + 4.0, y),
                Point2::new(x + 4.0, y + 4.0),
                Point2::new(x, y + 4.0),
            ]));
        }
    }
    Map::new(boundary, obstacles)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn fresh_build_satisfies_invariants(n in 0usize..120, seed in any::<u64>()) {
        let map = strip(n, seed);
        let btm = Btm::from_map(&map).unwrap();
        let r = btm.check_invariants().map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert_eq!(r.triangles, map.vertex_count() + 2 * map.obstacles.len() - 2);
        prop_assert_eq!(r.holes, map.obstacles.len());
    }

    #[test]
    fn updates_keep_invariants_and_ids(n in 2usize..60, seed in any::<u64>(), ops in proptest::collection::vec((any::<bool>(), any::<u16>()), 1..8)) {
        let generated = strip(n + 8, seed);
        // Keep the last 8 obstacles aside as the ones that appear during descent.
        let mut map = generated.clone();
        let mut pending: Vec<Polygon> = map.obstacles.split_off(n);
        let mut btm = Btm::from_map(&map).unwrap();
        for (insert, pick) in ops {
            let before: Vec<_> = btm.triangles().map(|t| (t, btm.dcel().triangle_vertices(t))).collect();
            let report = if insert && !pending.is_empty() {
                let poly = pending.remove(pick as usize % pending.len());
                btm.insert_obstacle(&poly).map_err(|e| TestCaseError::fail(e.to_string()))?.1
            } else {
                let ids: Vec<_> = btm.obstacle_ids().collect();
                if ids.is_empty() { continue; }
                btm.remove_obstacle(ids[pick as usize % ids.len()]).map_err(|e| TestCaseError::fail(e.to_string()))?
            };
            btm.check_invariants().map_err(|e| TestCaseError::fail(e.to_string()))?;
            for (t, verts) in &before {
                if !report.removed.contains(t) {
                    prop_assert!(btm.is_free_triangle(*t), "triangle {} vanished unreported", t);
                    prop_assert_eq!(btm.dcel().triangle_vertices(*t), *verts);
                } else {
                    prop_assert!(!btm.is_free_triangle(*t));
                }
            }
            for t in &report.added {
                prop_assert!(btm.is_free_triangle(*t));
                prop_assert!(!before.iter().any(|(b, _)| b == t));
            }
            // The BTM matches a fresh build of the same map in size.
            let fresh = Btm::from_map(&btm.map()).unwrap();
            prop_assert_eq!(fresh.triangle_count(), btm.triangle_count());
        }
    }

    #[test]
    fn point_location_agrees_with_brute_force(n in 1usize..40, seed in any::<u64>(), qs in proptest::collection::vec((0.0f64..1.0, 0.0f64..1.0), 1..40)) {
        let map = strip(n, seed);
        let btm = Btm::from_map(&map).unwrap();
        let b = map.aabb();
        for (u, v) in qs {
            let p = Point2::new(b.min.x - 5.0 + u * (b.max.x - b.min.x + 10.0), b.min.y - 5.0 + v * (b.max.y - b.min.y + 10.0));
            let expected_free = map.free_space_violation(&p).is_none();
            match btm.locate(&p) {
                Location::Triangle(t) => {
                    prop_assert!(expected_free);
                    let [a, bb, c] = btm.dcel().triangle_points(t);
                    let tri = Polygon::new(vec![a, bb, c]);
                    prop_assert_eq!(tri.locate(&p), PointInPolygon::Inside);
                }
                Location::Edge(_) | Location::Vertex(_) => {}
                Location::Obstacle(o) => {
                    let poly = btm.obstacle_polygon(o).unwrap();
                    prop_assert_eq!(poly.locate(&p), PointInPolygon::Inside);
                }
                Location::Outside => prop_assert!(map.boundary.locate(&p) == PointInPolygon::Outside),
            }
        }
    }
}

#[test]
fn cocircular_grid_is_constrained_delaunay() {
    for k in [1, 2, 5, 12] {
        let map = grid_of_squares(k);
        let btm = Btm::from_map(&map).unwrap();
        let r = btm.check_invariants().unwrap();
        assert_eq!(r.triangles, 4 + 4 * k * k + 2 * k * k - 2);
    }
}

#[test]
fn points_on_edges_and_vertices_are_reported_as_such() {
    let map = grid_of_squares(1);
    let btm = Btm::from_map(&map).unwrap();
    // A boundary vertex, the middle of a boundary edge, the middle of an obstacle edge.
    assert!(matches!(
        btm.locate(&Point2::new(0.0, 0.0)),
        Location::Vertex(_)
    ));
    match btm.locate(&Point2::new(10.0, 0.0)) {
        Location::Edge(h) => assert!(btm.dcel().is_map_edge(h) && btm.dcel().twin(h).is_none()),
        other => panic!("expected the boundary edge, got {other:?}"),
    }
    match btm.locate(&Point2::new(10.0, 8.0)) {
        Location::Edge(h) => {
            assert!(btm.dcel().is_map_edge(h));
            assert!(btm.is_free_triangle(btm.dcel().incident_face(h)));
        }
        other => panic!("expected the obstacle edge, got {other:?}"),
    }
    assert!(matches!(
        btm.locate(&Point2::new(10.0, 10.0)),
        Location::Obstacle(_)
    ));
}

#[test]
fn refused_updates_leave_the_btm_untouched() {
    let map = grid_of_squares(2);
    let mut btm = Btm::from_map(&map).unwrap();
    let before: Vec<_> = btm.triangles().collect();
    let sq = |x: f64, y: f64, s: f64| {
        Polygon::new(vec![
            Point2::new(x, y),
            Point2::new(x + s, y),
            Point2::new(x + s, y + s),
            Point2::new(x, y + s),
        ])
    };
    // Overlapping, touching, enclosing, crossing the boundary, outside.
    for bad in [
        sq(9.0, 9.0, 2.0),
        sq(12.0, 9.0, 2.0),
        sq(6.0, 6.0, 8.0),
        sq(-1.0, 5.0, 2.0),
        sq(100.0, 100.0, 1.0),
        sq(5.0, 5.0, 0.0),
    ] {
        assert!(btm.insert_obstacle(&bad).is_err(), "{bad:?} accepted");
        assert_eq!(btm.triangles().collect::<Vec<_>>(), before);
    }
    btm.check_invariants().unwrap();
}

#[test]
fn navigation_walks_around_vertices_and_faces() {
    let map = strip(20, 3);
    let btm = Btm::from_map(&map).unwrap();
    let d = btm.dcel();
    for t in btm.triangles() {
        for h in t.half_edges() {
            assert_eq!(d.next(d.prev(h)), h);
            assert_eq!(d.incident_face(h), t);
            if let Some(g) = d.twin(h) {
                assert_eq!(d.twin(g), Some(h));
                assert_eq!(d.origin(g), d.destination(h));
            } else {
                assert!(d.is_map_edge(h));
            }
        }
    }
    for v in btm.vertices() {
        let fan: Vec<_> = d.edges_around_vertex(v).collect();
        assert!(!fan.is_empty());
        // Consecutive fan edges share a face edge: the destination of one is the apex of the last.
        for w in fan.windows(2) {
            assert_eq!(d.destination(d.next(w[0])), d.destination(w[1]));
        }
        // The fan at a map vertex starts and ends on map edges.
        assert!(d.is_map_edge(fan[0]));
        assert!(d.is_map_edge(d.prev(*fan.last().unwrap())));
    }
}

#[test]
fn compaction_after_many_updates_keeps_every_triangle() {
    let generated = strip(60, 11);
    let mut map = generated.clone();
    let pending: Vec<Polygon> = map.obstacles.split_off(40);
    let mut btm = Btm::from_map(&map).unwrap();
    for poly in &pending {
        let (id, _) = btm.insert_obstacle(poly).unwrap();
        btm.remove_obstacle(id).unwrap();
        btm.insert_obstacle(poly).unwrap();
    }
    let before: Vec<_> = btm
        .triangles()
        .map(|t| (t, btm.dcel().triangle_vertices(t)))
        .collect();
    let dead = btm.dcel().triangle_capacity() - btm.dcel().face_count_alive();
    assert!(dead > 0, "updates retire ids");
    let renumber = btm.compact();
    btm.check_invariants().unwrap();
    assert_eq!(
        btm.dcel().triangle_capacity(),
        btm.dcel().face_count_alive()
    );
    for (t, verts) in before {
        let new = renumber[t.index()].expect("live triangles keep an id");
        assert_eq!(btm.dcel().triangle_vertices(new), verts);
        assert!(btm.is_free_triangle(new));
    }
    // Updates keep working on the compacted structure.
    let id = btm.obstacle_ids().next().unwrap();
    btm.remove_obstacle(id).unwrap();
    btm.check_invariants().unwrap();
}

/// The free triangles of a BTM as sorted triples of their corners' coordinates (bits), sorted.
fn free_triangles_by_points(btm: &Btm) -> Vec<[(u64, u64); 3]> {
    let d = btm.dcel();
    let mut out: Vec<[(u64, u64); 3]> = btm
        .triangles()
        .map(|t| {
            let mut c = d.triangle_points(t).map(|p| (p.x.to_bits(), p.y.to_bits()));
            c.sort_unstable();
            c
        })
        .collect();
    out.sort_unstable();
    out
}

/// The build works in its own (Hilbert) vertex numbering and numbers back in map order (issue
/// 10): the ids users see are the map's, ring after ring (boundary first, then each obstacle in
/// turn, three scaffold ids before them), each at its map point and on its ring; every ring edge is
/// a map edge with free space on its left; and the free triangles do not depend on the order the
/// obstacles are listed in.
#[test]
fn vertex_ids_follow_the_map_and_the_triangles_not_its_listing_order() {
    for seed in [1, 2, 3] {
        let map = strip(150, seed);
        let btm = Btm::from_map(&map).expect("valid strip");
        let d = btm.dcel();
        let mut next_id = 3usize;
        let rings = std::iter::once(btm.boundary_vertices()).chain(
            btm.obstacle_ids()
                .map(|o| btm.obstacle_vertices(o).expect("live obstacle")),
        );
        let polygons = std::iter::once(&map.boundary).chain(&map.obstacles);
        for (k, (ids, polygon)) in rings.zip(polygons).enumerate() {
            // The ring's points, read in the orientation that puts free space on the left.
            let points: Vec<Point2<f64>> = ids.iter().map(|&v| d.point(v)).collect();
            let mut backwards = polygon.vertices.clone();
            backwards.reverse();
            assert!(
                points == polygon.vertices || points == backwards,
                "ring {k}: the vertices are not the ring's, in order"
            );
            for (i, v) in ids.iter().enumerate() {
                assert_eq!(v.index(), next_id + i, "ring {k}: ids in map order");
                let expected = (k > 0).then(|| rappel_geometry::dcel::ObstacleId(k as u32 - 1));
                assert_eq!(btm.obstacle_of_vertex(*v), expected);
                // The edge to the next vertex of the ring is a map edge, free on its left.
                let w = ids[(i + 1) % ids.len()];
                let h = d
                    .edges_around_vertex(*v)
                    .find(|&h| d.destination(h) == w)
                    .unwrap_or_else(|| panic!("ring {k}: edge {i} missing"));
                assert!(d.is_map_edge(h));
                assert!(
                    btm.is_free_triangle(d.incident_face(h)),
                    "ring {k}: edge {i}"
                );
            }
            next_id += ids.len();
        }
        assert_eq!(next_id, 3 + map.vertex_count());
        let mut reversed = map.clone();
        reversed.obstacles.reverse();
        let other = Btm::from_map(&reversed).expect("valid strip");
        assert_eq!(
            free_triangles_by_points(&btm),
            free_triangles_by_points(&other),
            "seed {seed}"
        );
        btm.check_invariants().expect("invariants hold");
    }
}
