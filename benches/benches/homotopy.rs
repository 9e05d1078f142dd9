//! Homotopy benchmarks (issue 3) on the generated 10,000-obstacle crater strip:
//! - the Funnel Algorithm over sleeves of 250, 500, 1,000 and 2,000 triangles (linear time; target
//!   under 100 us for 1,000 triangles), and the funnel-state primitive advanced over the same
//!   sleeves;
//! - the crossing sequence (raw and reduced) and the SHP of a 10,000-segment random walk (target
//!   under 20 ms for the SHP);
//! - the H-signature of a 1,000-segment path among the 10,000 obstacles.
//!
//! Walks are seeded (ChaCha8) and every step is checked in free space by the tracer.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use nalgebra::Point2;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rappel_geometry::btm::Btm;
use rappel_geometry::generate::{CraterStripOptions, crater_strip};
use rappel_homotopy::crossing::{CrossingSequence, Tracer};
use rappel_homotopy::funnel_state::{FunnelState, FunnelTree};
use rappel_homotopy::h_signature::{HSignature, Poles};
use rappel_homotopy::path::Path;
use rappel_homotopy::shp::shortest_homotopic_path;
use rappel_homotopy::sleeve::Sleeve;
use rappel_homotopy::{TautPath, shortest_path_in_sleeve};
use std::hint::black_box;

/// A seeded random walk of `segments` free-space steps of 1-6 m from `start`; `drift` pulls each
/// step down the fall line (0 for an unbiased walk).
fn random_walk(btm: &Btm, start: Point2<f64>, segments: usize, drift: f64, seed: u64) -> Path {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut tracer = Tracer::new(btm, start).expect("start in free space");
    let mut points = vec![start];
    while points.len() <= segments {
        let a = tracer.point();
        let angle = rng.random_range(0.0..std::f64::consts::TAU);
        let len = rng.random_range(1.0..6.0);
        let q = Point2::new(a.x + len * angle.cos(), a.y + len * (angle.sin() - drift));
        if tracer.push(q).is_ok() {
            points.push(q);
        }
    }
    Path::new(points).expect("finite points")
}

/// The centroid of the last triangle of a sleeve: a goal inside it.
fn goal_in(btm: &Btm, sleeve: &Sleeve) -> Point2<f64> {
    let [a, b, c] = btm.dcel().triangle_points(sleeve.goal_triangle());
    Point2::new((a.x + b.x + c.x) / 3.0, (a.y + b.y + c.y) / 3.0)
}

/// The funnel-state primitive advanced portal by portal, then reaching the goal.
fn advance_along(btm: &Btm, sleeve: &Sleeve, s: Point2<f64>, g: Point2<f64>) -> TautPath {
    let mut tree = FunnelTree::new(s);
    let portals = sleeve.portals();
    let mut f = FunnelState::through(&mut tree, btm, portals[0]).expect("open portal");
    for &h in &portals[1..] {
        f = f.advance(&mut tree, btm, h).expect("sleeve portal");
    }
    let node = f.reach(&mut tree, g);
    tree.taut_path(btm, node)
}

fn funnel(c: &mut Criterion) {
    let gen_map = crater_strip(&CraterStripOptions::new(10_000, 1)).expect("valid options");
    let btm = Btm::from_map(&gen_map.map).expect("valid map");
    // A meandering walk down the strip gives a long, realistic sleeve.
    let walk = random_walk(&btm, gen_map.start, 4_000, 0.8, 7);
    let chi = CrossingSequence::reduced_of_path(&btm, &walk).expect("free walk");
    let sleeve = Sleeve::from_crossing_sequence(&btm, &chi).expect("reduced chain");
    assert!(
        sleeve.len() >= 2_000,
        "sleeve of {} triangles",
        sleeve.len()
    );
    let mut g = c.benchmark_group("funnel_sleeve");
    for n in [250usize, 500, 1_000, 2_000] {
        let prefix = sleeve.prefix(n);
        let goal = goal_in(&btm, &prefix);
        let a = shortest_path_in_sleeve(&btm, &prefix, walk.start(), goal).expect("funnel");
        let b = advance_along(&btm, &prefix, walk.start(), goal);
        assert_eq!(a.points, b.points);
        g.throughput(Throughput::Elements(n as u64));
        g.bench_with_input(BenchmarkId::new("funnel_algorithm", n), &n, |bench, _| {
            bench.iter(|| {
                shortest_path_in_sleeve(&btm, black_box(&prefix), walk.start(), goal)
                    .map(|t| t.length)
            })
        });
        g.bench_with_input(
            BenchmarkId::new("funnel_state_advance", n),
            &n,
            |bench, _| {
                bench.iter(|| advance_along(&btm, black_box(&prefix), walk.start(), goal).length)
            },
        );
    }
    g.finish();
}

fn long_walk(c: &mut Criterion) {
    let gen_map = crater_strip(&CraterStripOptions::new(10_000, 1)).expect("valid options");
    let btm = Btm::from_map(&gen_map.map).expect("valid map");
    let mid = Point2::new(gen_map.start.x, (gen_map.start.y + gen_map.goal.y) / 2.0);
    let start = match btm.locate(&mid) {
        rappel_geometry::btm::Location::Triangle(_) => mid,
        _ => gen_map.start,
    };
    let walk = random_walk(&btm, start, 10_000, 0.0, 11);
    let raw = CrossingSequence::of_path(&btm, &walk).expect("free walk");
    let shp = shortest_homotopic_path(&btm, &walk).expect("free walk");
    eprintln!(
        "10,000-segment walk: {} raw crossings, {} reduced, SHP {} anchors, {:.0} m (walk {:.0} m)",
        raw.len(),
        shp.crossings.len(),
        shp.taut.anchors.len(),
        shp.taut.length,
        walk.length()
    );
    let mut g = c.benchmark_group("walk_10000_segments");
    g.sample_size(30);
    g.bench_function("crossing_sequence_raw", |b| {
        b.iter(|| CrossingSequence::of_path(&btm, black_box(&walk)).map(|x| x.len()))
    });
    g.bench_function("crossing_sequence_reduced", |b| {
        b.iter(|| CrossingSequence::reduced_of_path(&btm, black_box(&walk)).map(|x| x.len()))
    });
    g.bench_function("shp", |b| {
        b.iter(|| shortest_homotopic_path(&btm, black_box(&walk)).map(|s| s.taut.length))
    });
    g.finish();

    let poles = Poles::new(&btm);
    let short = Path::new(walk.points()[..=1_000].to_vec()).expect("finite points");
    let mut g = c.benchmark_group("h_signature_10000_obstacles");
    g.bench_function("path_1000_segments", |b| {
        b.iter(|| {
            HSignature::of_path(black_box(&poles), black_box(&short))
                .windings()
                .len()
        })
    });
    g.bench_function("poles", |b| b.iter(|| Poles::new(black_box(&btm)).len()));
    g.finish();
}

criterion_group!(benches, funnel, long_walk);
criterion_main!(benches);
