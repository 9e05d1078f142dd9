//! The SPT A* search (thesis Alg. 3-4): the first class is the Euclidean shortest path (checked
//! against an independent visibility-graph oracle on 200+ random maps), classes come out pairwise
//! non-homotopic and in non-decreasing length, closed forms around one obstacle, and every
//! termination rule.

use crate::common;

use common::{one_box, random_map};
use nalgebra::Point2;
use rappel_geometry::btm::Btm;
use rappel_geometry::generate::{CraterStripOptions, crater_strip};
use rappel_homotopy::crossing::CrossingSequence;
use rappel_homotopy::funnel::Side;
use rappel_homotopy::h_signature::HSignature;
use rappel_homotopy::shp::shortest_homotopic_path;
use rappel_planners::spt::{QueueOrder, RankedShp, SearchOptions, SptPlanner, Termination};
use rappel_planners::visibility_graph;

/// Relative tolerance of the comparison with the oracle (the 1e-9).
const ORACLE_TOLERANCE: f64 = 1e-9;
/// Lengths come out non-decreasing up to the rounding of their sums.
const ORDER_TOLERANCE: f64 = 1e-12;

fn p(x: f64, y: f64) -> Point2<f64> {
    Point2::new(x, y)
}

fn options(k: Option<usize>) -> SearchOptions {
    SearchOptions::default().with_max_classes(k).unwrap()
}

/// Every structural property a found class must have, checked against homotopy-crate functions
/// that do not use the search.
fn check_class(btm: &Btm, planner: &SptPlanner<'_>, c: &RankedShp) {
    let taut = &c.shp.taut;
    let path = taut.to_path();
    path.validate(btm).expect("the SHP lies in free space");
    let chi = CrossingSequence::reduced_of_path(btm, &path).unwrap();
    assert_eq!(
        chi, c.shp.crossings,
        "the sleeve is the SHP's own reduced sequence"
    );
    let again = shortest_homotopic_path(btm, &path).unwrap();
    assert!((again.taut.length - taut.length).abs() <= 1e-9 * taut.length.max(1.0));
    // The class's signature (in whichever form the planner chose), and its sleeve form through
    // the cut index, both equal the winding form of its SHP's polyline, the oracle.
    let oracle = HSignature::of_path(planner.poles(), &path);
    assert_eq!(c.h_signature, oracle);
    let index = planner.prepare_cut_index().expect("small maps are indexed");
    let from_sleeve = HSignature::of_sleeve(btm, index, taut.start(), taut.goal(), &c.shp.sleeve);
    assert_eq!(from_sleeve, oracle);
}

#[test]
fn the_first_class_is_the_visibility_graph_shortest_path_on_random_maps() {
    let mut checked = 0;
    let mut with_anchors = 0;
    for seed in 0..300u64 {
        let Some(m) = random_map(seed, 6 + (seed % 10) as usize) else {
            continue;
        };
        let btm = Btm::from_map(&m.map).unwrap();
        let planner = SptPlanner::new(&btm);
        let best = planner
            .shortest_path(m.start, m.goal)
            .unwrap()
            .expect("connected");
        let oracle = visibility_graph::shortest_path(&m.map, m.start, m.goal).expect("reachable");
        let rel = (best.length() - oracle.length).abs() / oracle.length.max(1e-12);
        assert!(
            rel <= ORACLE_TOLERANCE,
            "seed {seed}: SPT {} vs visibility graph {} ({:?} vs {:?})",
            best.length(),
            oracle.length,
            best.shp.taut.points,
            oracle.points
        );
        assert_eq!(best.rank, 1);
        check_class(&btm, &planner, &best);
        checked += 1;
        with_anchors += usize::from(!best.shp.taut.anchors.is_empty());
    }
    assert!(checked >= 200, "only {checked} valid random maps");
    assert!(
        with_anchors >= 100,
        "only {with_anchors} maps with a bent shortest path"
    );
}

/// The first class in every queue order: the A* order, the default wave order and wave orders
/// with coarse bands (down to one band per binade, close to Dijkstra's order by the reach bound,
/// where the goal must wait behind every funnel that could still beat it) all give the length of
/// the independent visibility-graph oracle, and the same length bit for bit (the same path).
#[test]
fn every_queue_order_finds_the_visibility_graph_shortest_path() {
    let orders = [
        QueueOrder::AStar,
        QueueOrder::Auto,
        QueueOrder::Wave { band_bits: 0 },
        QueueOrder::Wave { band_bits: 3 },
        QueueOrder::Wave { band_bits: 52 },
    ];
    let mut checked = 0;
    for seed in 0..200u64 {
        let Some(m) = random_map(7_000 + seed, 4 + (seed % 12) as usize) else {
            continue;
        };
        let btm = Btm::from_map(&m.map).unwrap();
        let planner = SptPlanner::new(&btm);
        let oracle = visibility_graph::shortest_path(&m.map, m.start, m.goal).expect("reachable");
        let lengths: Vec<f64> = orders
            .iter()
            .map(|&order| {
                let options = options(Some(1)).with_queue_order(order);
                let c = planner
                    .search(m.start, m.goal, &options)
                    .unwrap()
                    .next()
                    .expect("a class")
                    .unwrap();
                check_class(&btm, &planner, &c);
                c.length()
            })
            .collect();
        for (order, l) in orders.iter().zip(&lengths) {
            let rel = (l - oracle.length).abs() / oracle.length.max(1e-12);
            assert!(
                rel <= ORACLE_TOLERANCE,
                "seed {seed}, {order:?}: {l} vs visibility graph {}",
                oracle.length
            );
            assert_eq!(*l, lengths[0], "seed {seed}, {order:?}");
        }
        checked += 1;
    }
    assert!(checked >= 150, "only {checked} valid random maps");
}

/// On a crater strip, where the default bands are narrow beside the spread of the keys, every
/// order finds the same shortest path; the wave orders also refuse what they cannot do.
#[test]
fn every_queue_order_agrees_on_a_crater_strip() {
    let g = crater_strip(&CraterStripOptions::new(1_500, 3)).unwrap();
    let btm = Btm::from_map(&g.map).unwrap();
    let planner = SptPlanner::new(&btm);
    let length = |order| {
        let options = options(Some(1)).with_queue_order(order);
        let mut search = planner.search(g.start, g.goal, &options).unwrap();
        search.next_best().unwrap().expect("a class").length()
    };
    let astar = length(QueueOrder::AStar);
    for order in [
        QueueOrder::Auto,
        QueueOrder::Wave { band_bits: 0 },
        QueueOrder::Wave { band_bits: 10 },
    ] {
        assert_eq!(length(order), astar, "{order:?}");
    }
    for bad in [
        options(Some(2)).with_queue_order(QueueOrder::Wave { band_bits: 8 }),
        options(Some(1)).with_queue_order(QueueOrder::Wave { band_bits: 53 }),
        options(Some(1))
            .with_simple_only(true)
            .with_queue_order(QueueOrder::Wave { band_bits: 8 }),
    ] {
        assert!(planner.search(g.start, g.goal, &bad).is_err());
    }
    // Several classes in the automatic order are the A* order's.
    let classes = |order| {
        let options = options(Some(3)).with_queue_order(order);
        let run = planner
            .search(g.start, g.goal, &options)
            .unwrap()
            .run()
            .unwrap();
        run.classes.iter().map(|c| c.length()).collect::<Vec<_>>()
    };
    assert_eq!(classes(QueueOrder::Auto), classes(QueueOrder::AStar));
}

#[test]
fn around_one_convex_obstacle_the_first_two_classes_are_the_two_ways_around() {
    // Box [3, 6] x [4, 6]; start above, goal below: east round 2 sqrt(10) + 2, west 2 sqrt(13) + 2.
    let btm = Btm::from_map(&one_box(3.0, 6.0, 4.0, 6.0)).unwrap();
    let planner = SptPlanner::new(&btm);
    let mut search = planner
        .search(p(5., 9.), p(5., 1.), &options(Some(4)))
        .unwrap();
    let east = search.next_best().unwrap().unwrap();
    let west = search.next_best().unwrap().unwrap();
    assert!((east.length() - (2.0 * 10f64.sqrt() + 2.0)).abs() < 1e-12);
    assert_eq!(
        east.shp.taut.points,
        vec![p(5., 9.), p(6., 6.), p(6., 4.), p(5., 1.)]
    );
    assert!(east.shp.taut.anchors.iter().all(|a| a.side == Side::Right));
    assert!((west.length() - (2.0 * 13f64.sqrt() + 2.0)).abs() < 1e-12);
    assert_eq!(
        west.shp.taut.points,
        vec![p(5., 9.), p(3., 6.), p(3., 4.), p(5., 1.)]
    );
    assert!(west.shp.taut.anchors.iter().all(|a| a.side == Side::Left));
    // The next classes wind around the box: longer by at least its perimeter's worth of turning.
    let third = search.next_best().unwrap().unwrap();
    assert!(third.length() > west.length() + 4.0, "{}", third.length());
    assert!(!third.simple);
    assert!(east.simple && west.simple);
    // The two ways around differ by one turn around the obstacle's pole.
    let o = rappel_geometry::dcel::ObstacleId(0);
    assert_eq!(
        (west.h_signature.winding(o) - east.h_signature.winding(o)).abs(),
        1
    );
}

#[test]
fn k_classes_are_pairwise_non_homotopic_and_non_decreasing() {
    for seed in 0..30u64 {
        let Some(m) = random_map(1_000 + seed, 6) else {
            continue;
        };
        let btm = Btm::from_map(&m.map).unwrap();
        let planner = SptPlanner::new(&btm);
        let out = planner
            .search(m.start, m.goal, &options(Some(12)))
            .unwrap()
            .run()
            .unwrap();
        assert_eq!(out.classes.len(), 12, "seed {seed}: {:?}", out.termination);
        assert_eq!(out.termination, Termination::ClassCount);
        for (i, c) in out.classes.iter().enumerate() {
            assert_eq!(c.rank, i + 1);
            check_class(&btm, &planner, c);
            for d in &out.classes[..i] {
                assert_ne!(
                    c.shp.crossings, d.shp.crossings,
                    "seed {seed}: classes repeat"
                );
                assert!(d.length() <= c.length() * (1.0 + ORDER_TOLERANCE));
            }
        }
    }
}

#[test]
fn dominance_pruning_keeps_exactly_the_k_shortest_classes() {
    // The count-limited search prunes dominated funnels; the unlimited one prunes nothing. Both
    // must list the same lengths.
    for seed in 0..20u64 {
        let Some(m) = random_map(2_000 + seed, 5) else {
            continue;
        };
        let btm = Btm::from_map(&m.map).unwrap();
        let planner = SptPlanner::new(&btm);
        let k = 8;
        let pruned = planner
            .search(m.start, m.goal, &options(Some(k)))
            .unwrap()
            .run()
            .unwrap();
        let full: Vec<RankedShp> = planner
            .search(m.start, m.goal, &options(None))
            .unwrap()
            .take(k)
            .collect::<Result<_, _>>()
            .unwrap();
        assert_eq!(pruned.classes.len(), k);
        for (a, b) in pruned.classes.iter().zip(&full) {
            assert!(
                (a.length() - b.length()).abs() <= 1e-9 * b.length(),
                "seed {seed}: {} vs {}",
                a.length(),
                b.length()
            );
        }
        assert!(pruned.stats.pruned_dominated > 0 || pruned.stats.expansions < 200);
    }
}

#[test]
fn the_length_factor_bounds_every_class_and_ends_the_search() {
    let m = random_map(77, 6).expect("valid map");
    let btm = Btm::from_map(&m.map).unwrap();
    let planner = SptPlanner::new(&btm);
    let o = options(None).with_max_length_factor(Some(1.3)).unwrap();
    let out = planner.search(m.start, m.goal, &o).unwrap().run().unwrap();
    assert!(matches!(
        out.termination,
        Termination::LengthFactor | Termination::Exhausted
    ));
    let first = out.classes[0].length();
    assert!(out.classes.iter().all(|c| c.length() <= 1.3 * first));
    // And nothing within the bound was missed: an unbounded search lists the same prefix.
    let full: Vec<RankedShp> = planner
        .search(m.start, m.goal, &options(None))
        .unwrap()
        .take(out.classes.len() + 1)
        .collect::<Result<_, _>>()
        .unwrap();
    assert!(full[out.classes.len()].length() > 1.3 * first);
}

#[test]
fn the_expansion_budget_stops_the_search() {
    let m = random_map(78, 8).expect("valid map");
    let btm = Btm::from_map(&m.map).unwrap();
    let planner = SptPlanner::new(&btm);
    let o = options(None).with_max_expansions(50).unwrap();
    let mut search = planner.search(m.start, m.goal, &o).unwrap();
    while search.next_best().unwrap().is_some() {}
    assert_eq!(search.termination(), Some(Termination::Expansions));
    assert_eq!(search.stats().expansions, 50);
}

#[test]
fn the_simple_classes_mode_is_finite() {
    // One box: exactly the two ways around are simple.
    let btm = Btm::from_map(&one_box(3.0, 6.0, 4.0, 6.0)).unwrap();
    let planner = SptPlanner::new(&btm);
    let o = options(None).with_simple_only(true);
    let out = planner
        .search(p(5., 9.), p(5., 1.), &o)
        .unwrap()
        .run()
        .unwrap();
    assert_eq!(out.termination, Termination::Exhausted);
    assert_eq!(out.classes.len(), 2);
    // Random maps: the search ends by itself and returns simple, distinct classes.
    for seed in 0..6u64 {
        let Some(m) = random_map(3_000 + seed, 3) else {
            continue;
        };
        let btm = Btm::from_map(&m.map).unwrap();
        let planner = SptPlanner::new(&btm);
        let out = planner.search(m.start, m.goal, &o).unwrap().run().unwrap();
        assert_eq!(out.termination, Termination::Exhausted, "seed {seed}");
        assert!(out.classes.len() >= 2, "seed {seed}");
        for (i, c) in out.classes.iter().enumerate() {
            assert!(c.simple);
            assert!(
                out.classes[..i]
                    .iter()
                    .all(|d| d.shp.crossings != c.shp.crossings)
            );
        }
    }
}

#[test]
fn start_and_goal_in_one_triangle_and_on_vertices() {
    let btm = Btm::from_map(&one_box(3.0, 6.0, 4.0, 6.0)).unwrap();
    let planner = SptPlanner::new(&btm);
    // Same point: the trivial class of length zero comes first.
    let best = planner
        .shortest_path(p(1., 1.), p(1., 1.))
        .unwrap()
        .unwrap();
    assert_eq!(best.length(), 0.0);
    // Start on an obstacle corner, goal on another: along the box's edge.
    let best = planner
        .shortest_path(p(6., 6.), p(6., 4.))
        .unwrap()
        .unwrap();
    assert_eq!(best.length(), 2.0);
    // Bad input is a typed error.
    assert!(
        planner
            .search(p(5., 5.), p(1., 1.), &options(Some(1)))
            .is_err()
    );
    assert!(
        planner
            .search(p(f64::NAN, 5.), p(1., 1.), &options(Some(1)))
            .is_err()
    );
}

#[test]
fn the_goal_distance_bounds_never_exceed_the_geodesic_distance() {
    // Checked against the visibility-graph oracle from each vertex to the goal.
    let mut exact = 0;
    for seed in 0..40u64 {
        let Some(m) = random_map(4_000 + seed, 6) else {
            continue;
        };
        let btm = Btm::from_map(&m.map).unwrap();
        let planner = SptPlanner::new(&btm);
        let h = planner
            .goal_distances(m.start, m.goal)
            .unwrap()
            .expect("connected");
        let shortest = visibility_graph::shortest_path(&m.map, m.start, m.goal)
            .unwrap()
            .length;
        for v in btm.vertices() {
            let p = btm.dcel().point(v);
            let truth = visibility_graph::shortest_path(&m.map, p, m.goal)
                .unwrap()
                .length;
            let hv = h[v.index()];
            assert!(
                hv <= truth * (1.0 + 1e-12) + 1e-12,
                "seed {seed}: vertex {v}: {hv} > {truth}"
            );
            // Inside the ellipse of the shortest path the bound is exact.
            if truth + (p - m.start).norm() < shortest * (1.0 - 1e-9) {
                assert!(
                    (hv - truth).abs() <= 1e-9 * truth.max(1.0),
                    "seed {seed}: vertex {v}"
                );
                exact += 1;
            }
        }
    }
    assert!(exact >= 15, "only {exact} vertices inside the ellipses");
}

#[test]
fn a_planner_reused_across_queries_answers_like_a_fresh_one() {
    // One planner answers a mix of queries (one class, several classes, the simple-classes mode,
    // swapped endpoints), so its pooled scratch space (generation-stamped lifts, reused tree,
    // queue and trail) carries state from every kind of query into the next. Each answer must
    // equal a fresh planner's, counters included, and the first class the visibility-graph
    // oracle's length.
    let mut incumbent_pruned = 0;
    for seed in 0..40u64 {
        let Some(m) = random_map(7_000 + seed, 6 + (seed % 7) as usize) else {
            continue;
        };
        let btm = Btm::from_map(&m.map).unwrap();
        let reused = SptPlanner::new(&btm);
        let oracle = visibility_graph::shortest_path(&m.map, m.start, m.goal).expect("reachable");
        let queries = [
            (m.start, m.goal, options(Some(1))),
            (m.start, m.goal, options(Some(4))),
            (m.goal, m.start, options(Some(1))),
            (m.start, m.goal, options(Some(3)).with_simple_only(true)),
            (m.start, m.goal, options(Some(1))),
            (m.goal, m.start, options(Some(6))),
            (m.start, m.goal, options(Some(1))),
        ];
        for (round, (a, b, o)) in queries.iter().enumerate() {
            let warm = reused.search(*a, *b, o).unwrap().run().unwrap();
            let fresh_planner = SptPlanner::new(&btm);
            let fresh = fresh_planner.search(*a, *b, o).unwrap().run().unwrap();
            assert_eq!(warm, fresh, "seed {seed} round {round}");
            let first = warm.classes.first().expect("connected").length();
            let rel = (first - oracle.length).abs() / oracle.length;
            assert!(rel <= ORACLE_TOLERANCE, "seed {seed} round {round}");
            incumbent_pruned += warm.stats.pruned_incumbent;
            // The taut-path-only query on the same warm planner: the same path.
            let taut = reused
                .shortest_taut_path(*a, *b)
                .unwrap()
                .expect("connected");
            let best = fresh_planner
                .shortest_path(*a, *b)
                .unwrap()
                .expect("connected");
            assert_eq!(taut, best.shp.taut, "seed {seed} round {round}");
        }
    }
    assert!(incumbent_pruned > 0, "the incumbent never pruned a funnel");
}

#[test]
fn the_cut_index_is_built_once_it_pays_and_never_on_short_strip_queries() {
    use rappel_geometry::map::Map;
    use rappel_geometry::polygon::Polygon;
    // 60 x 8 unit squares on a 3 m pitch: a path down the map passes 8 rows, each holding 60
    // poles in its band, through a sleeve of a few dozen triangles. The winding form tests
    // about ten times what the sleeve form costs, so after enough classes the planner builds
    // the index and reads signatures from sleeves, still equal to the oracle's.
    let squares = (0..8)
        .flat_map(|row| {
            (0..60).map(move |col| (3.0 * f64::from(col) + 1.0, 3.0 * f64::from(row) + 1.5))
        })
        .map(|(x, y)| {
            Polygon::new(vec![
                p(x, y),
                p(x + 1.0, y),
                p(x + 1.0, y + 1.0),
                p(x, y + 1.0),
            ])
        })
        .collect();
    let map = Map::new(
        Polygon::new(vec![p(0., 0.), p(181., 0.), p(181., 26.), p(0., 26.)]),
        squares,
    );
    let btm = Btm::from_map(&map).unwrap();
    let planner = SptPlanner::new(&btm);
    let mut built_after = None;
    for i in 0..2_000 {
        let x = 0.5 + 3.0 * f64::from(i % 60);
        let best = planner
            .shortest_path(p(x, 25.5), p(x + 0.2, 0.5))
            .unwrap()
            .unwrap();
        let path = best.shp.taut.to_path();
        assert_eq!(
            best.h_signature,
            HSignature::of_path(planner.poles(), &path)
        );
        if planner.cut_index().is_some() {
            built_after = Some(i + 1);
            break;
        }
    }
    let n = built_after.expect("the index pays on this map");
    assert!(n > 1, "built on the first class already");
    // Once built, later classes are read from sleeves (and still agree).
    let c = planner
        .shortest_path(p(90.5, 25.5), p(20.5, 0.5))
        .unwrap()
        .unwrap();
    check_class(&btm, &planner, &c);
    // Repeated queries on a small random map (few poles in any band) never build it.
    let Some(m) = random_map(3, 8) else {
        panic!("random map 3 exists");
    };
    let btm = Btm::from_map(&m.map).unwrap();
    let planner = SptPlanner::new(&btm);
    for _ in 0..50 {
        planner.shortest_path(m.start, m.goal).unwrap().unwrap();
    }
    assert!(planner.cut_index().is_none());
}

#[test]
fn sleeves_traced_from_the_shps_equal_the_trails() {
    // With the trail dropped at once (limit 0) or midway, every class is the same as with the
    // trail: same SHP, sleeve, crossings and signature.
    let mut compared = 0;
    for seed in 0..40u64 {
        let Some(m) = random_map(seed, 6 + (seed % 6) as usize) else {
            continue;
        };
        let btm = Btm::from_map(&m.map).unwrap();
        let planner = SptPlanner::new(&btm);
        let run = |o: SearchOptions| planner.search(m.start, m.goal, &o).unwrap().run().unwrap();
        let with_trail = run(options(Some(6)));
        for limit in [0, 7] {
            let traced = run(options(Some(6)).with_trail_limit(limit));
            assert_eq!(
                traced.classes, with_trail.classes,
                "seed {seed}, limit {limit}"
            );
            for c in &traced.classes {
                check_class(&btm, &planner, c);
            }
        }
        compared += with_trail.classes.len();
    }
    assert!(compared > 100, "{compared}");
}
