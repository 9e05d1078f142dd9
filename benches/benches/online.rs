//! Online planning benchmarks (issue 11): one map change on the 10,000-obstacle crater strip
//! (`fixtures/generated/crater-strip-10000.ron`) handled by the session (local retriangulation,
//! classification, sleeve and SHP update, the pair and backtrackability checks) versus planning
//! again from scratch on the changed map (BTM build, constrained SPT search, Alg. 5, the pair),
//! in one run; and the backtracking case (a rock across the planned route: replanning with the
//! constrained search, junction and continuation). Sessions are cloned before and dropped after
//! each timed call (`iter_batched_ref`), so neither is counted; each clone gets the headroom a
//! new session reserves (a clone allocates its arrays exactly, so its first update would
//! otherwise copy the whole mesh).

use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use nalgebra::Point2;
use rappel::scenario::Scenario;
use rappel_geometry::polygon::{PointInPolygon, Polygon};
use rappel_mechanics::friction_cone::TetherFrictionCone;
use rappel_planners::online::session::UPDATE_HEADROOM_VERTICES;
use rappel_planners::online::{ChangeCase, Decision, MapChange, OnlineOptions, OnlineSession};
use rappel_planners::terrain::PlaneSeries;
use std::hint::black_box;

fn scenario() -> Scenario {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../fixtures/generated/crater-strip-10000.ron"
    );
    Scenario::load(path).expect("the generated fixture")
}

fn session(s: &Scenario) -> OnlineSession {
    let terrain = PlaneSeries::new(&s.terrain.planes, &TetherFrictionCone).expect("planes");
    OnlineSession::new(&s.map, s.start, s.goal, terrain, OnlineOptions::default()).expect("session")
}

/// A small triangle at the centroid of a sleeve triangle that neither the SHP nor the route meets
/// and that does not change the class: the first one whose change is case (2) or (4) with the plan
/// going on.
fn quiet_change(base: &OnlineSession) -> Polygon {
    let class = base.class().expect("a feasible class on the strip");
    let d = base.btm().dcel();
    for (i, t) in class.shp.sleeve.triangles().iter().enumerate().skip(40) {
        let [a, b, c] = d.triangle_points(*t);
        let g = Point2::from((a.coords + b.coords + c.coords) / 3.0);
        let shrink = |p: Point2<f64>| g + (p - g) * 0.05;
        let rock = Polygon::new(vec![shrink(a), shrink(b), shrink(c)]);
        if rock.locate(&g) != PointInPolygon::Inside {
            continue;
        }
        let mut trial = base.clone();
        if let Ok(out) = trial.apply(&MapChange::Add(rock.clone()))
            && matches!(out[0].case, ChangeCase::GeometryChanged | ChangeCase::Split)
            && out[0].decision == Decision::Continue
        {
            let _ = i;
            return rock;
        }
    }
    panic!("no quiet change found in the sleeve");
}

/// A rock across the planned route some way ahead: the plan must change.
fn blocking_change(base: &OnlineSession) -> Polygon {
    let route = base.route();
    let k = route.len() / 2;
    let (a, b) = (route[k], route[k + 1]);
    let m = a + (b - a) * 0.5;
    Polygon::new(vec![
        m + nalgebra::Vector2::new(-0.3, -0.2),
        m + nalgebra::Vector2::new(0.3, -0.2),
        m + nalgebra::Vector2::new(0.0, 0.3),
    ])
}

/// Times `session.apply(Add(rock))` on a fresh clone of `base` (with a new session's headroom)
/// per call; the clone and its drop are not counted.
fn bench_apply(
    g: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    name: &str,
    base: &OnlineSession,
    rock: &Polygon,
) {
    g.bench_function(name, |bch| {
        bch.iter_batched_ref(
            || {
                let mut s = base.clone();
                s.reserve_for_updates(UPDATE_HEADROOM_VERTICES);
                s
            },
            |session| {
                black_box(
                    session
                        .apply(&MapChange::Add(rock.clone()))
                        .map(|o| o.len()),
                )
            },
            BatchSize::LargeInput,
        )
    });
}

fn change_vs_scratch(c: &mut Criterion) {
    let s = scenario();
    let mut base = session(&s);
    base.advance(50.0);
    let rock = quiet_change(&base);
    let mut changed = s.map.clone();
    changed.obstacles.push(rock.clone());
    let mut g = c.benchmark_group("online_change_10000_obstacles");
    g.sample_size(20);
    bench_apply(&mut g, "session/apply_no_class_change", &base, &rock);
    g.bench_function("scratch/plan_changed_map", |bch| {
        bch.iter(|| {
            let terrain = PlaneSeries::new(&s.terrain.planes, &TetherFrictionCone).expect("planes");
            black_box(
                OnlineSession::new(&changed, s.start, s.goal, terrain, OnlineOptions::default())
                    .map(|x| x.route().len()),
            )
        })
    });
    let block = blocking_change(&base);
    bench_apply(&mut g, "session/apply_route_blocked_replan", &base, &block);
    g.finish();
}

criterion_group!(benches, change_vs_scratch);
criterion_main!(benches);
