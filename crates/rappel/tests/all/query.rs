//! `rappel::query` against the brute-force visibility-graph oracle: on seeded random pairs in the
//! free space of the Fig. 2.7 map, each pair's first length is the Euclidean shortest path.

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rappel::geometry::polygon::PointInPolygon;
use rappel::nalgebra::Point2;
use rappel::planners::visibility_graph::shortest_path;
use rappel::query::{QueryOptions, QueryPair, answer};
use rappel::scenario::Scenario;

#[test]
fn query_lengths_match_the_visibility_graph() {
    let s = Scenario::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../fixtures/thesis-fig-2-7.ron"
    ))
    .expect("fixture");
    let map = &s.map;
    let b = map.aabb();
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut free = || loop {
        let p = Point2::new(
            rng.random_range(b.min.x..b.max.x),
            rng.random_range(b.min.y..b.max.y),
        );
        if map.boundary.locate(&p) == PointInPolygon::Inside
            && map
                .obstacles
                .iter()
                .all(|o| o.locate(&p) == PointInPolygon::Outside)
        {
            return p;
        }
    };
    let pairs: Vec<QueryPair> = (0..40)
        .map(|_| QueryPair {
            start: free(),
            goal: free(),
        })
        .collect();
    let answers = answer(
        map.validate().expect("valid map"),
        &pairs,
        &QueryOptions {
            classes: 2,
            ..Default::default()
        },
    )
    .expect("answers");
    for (pair, a) in pairs.iter().zip(&answers) {
        assert!(a.error.is_none(), "{a:?}");
        let oracle = shortest_path(map, pair.start, pair.goal).expect("connected");
        assert!(
            (a.lengths_m[0] - oracle.length).abs() <= 1e-9 * oracle.length.max(1.0),
            "pair {}: {} vs {}",
            a.index,
            a.lengths_m[0],
            oracle.length
        );
        assert!(a.lengths_m.windows(2).all(|w| w[0] <= w[1] + 1e-9));
    }
}
