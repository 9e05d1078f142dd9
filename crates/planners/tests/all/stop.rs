//! The shared stop condition (issue 32) in the planners' long loops: a time limit and a cancel
//! flag stop an SPT search on a large generated map quickly and say so; an expansion budget alone
//! gives exactly the results of `with_budget`; whichever condition fires first is reported; the
//! shortest path map, the sampler and the online simulation honour it too.

use std::sync::OnceLock;
use std::time::{Duration, Instant};

use nalgebra::Point2;
use rappel_geometry::btm::Btm;
use rappel_geometry::generate::{CraterStripOptions, crater_strip};
use rappel_geometry::map::Map;
use rappel_geometry::polygon::Polygon;
use rappel_planners::budget::{BudgetKind, ExpansionBudget};
use rappel_planners::online::simulate::Ending;
use rappel_planners::online::{SimulationOptions, simulate};
use rappel_planners::sampler::{Abit, AbitSettings, ObstacleWorld, RealVectorSpace, Termination};
use rappel_planners::shortest_path_map::ShortestPathMap;
use rappel_planners::spt::{self, SearchError, SearchOptions, SptPlanner};
use rappel_planners::stop::{CancelFlag, StopCondition, StopReason};
use rappel_planners::terrain::PlaneSeries;

/// The 10,000-obstacle crater strip (seed 1), built once for the tests of this file.
fn big() -> &'static (Btm, Point2<f64>, Point2<f64>) {
    static BIG: OnceLock<(Btm, Point2<f64>, Point2<f64>)> = OnceLock::new();
    BIG.get_or_init(|| {
        let g = crater_strip(&CraterStripOptions::new(10_000, 1)).unwrap();
        (Btm::from_map(&g.map).unwrap(), g.start, g.goal)
    })
}

/// No class count and no length bound: without a time limit or a cancel this search runs until
/// its automatic budget of tens of millions of expansions, many seconds.
fn unbounded() -> SearchOptions {
    SearchOptions::default().with_max_classes(None).unwrap()
}

#[test]
fn a_time_limit_stops_a_long_search_quickly() {
    let (btm, start, goal) = big();
    let planner = SptPlanner::new(btm);
    let limit = Duration::from_millis(5);
    let options = unbounded().with_stop(StopCondition::time(limit)).unwrap();
    let began = Instant::now();
    let out = planner
        .search(*start, *goal, &options)
        .unwrap()
        .run()
        .unwrap();
    let took = began.elapsed();
    assert_eq!(out.termination, spt::Termination::TimeLimit);
    assert_eq!(out.stop_reason, Some(StopReason::TimeLimit { limit }));
    assert!(out.stats.expansions < out.stats.expansion_limit);
    assert!(took < Duration::from_secs(2), "{took:?}");
}

#[test]
fn a_cancel_from_another_thread_stops_a_long_search() {
    let (btm, start, goal) = big();
    let planner = SptPlanner::new(btm);
    let flag = CancelFlag::new();
    let options = unbounded()
        .with_stop(StopCondition::cancel(flag.clone()))
        .unwrap();
    let canceller = std::thread::spawn(move || {
        std::thread::sleep(Duration::from_millis(30));
        flag.cancel();
        Instant::now()
    });
    let out = planner
        .search(*start, *goal, &options)
        .unwrap()
        .run()
        .unwrap();
    let ended = Instant::now();
    let cancelled_at = canceller.join().unwrap();
    assert_eq!(out.termination, spt::Termination::Cancelled);
    assert_eq!(out.stop_reason, Some(StopReason::Cancelled));
    assert!(
        ended.duration_since(cancelled_at) < Duration::from_secs(2),
        "the search went on for {:?} after the cancel",
        ended.duration_since(cancelled_at)
    );
}

#[test]
fn an_expansion_limit_gives_the_results_of_a_fixed_budget() {
    let g = crater_strip(&CraterStripOptions::new(300, 4)).unwrap();
    let btm = Btm::from_map(&g.map).unwrap();
    let planner = SptPlanner::new(&btm);
    let base = SearchOptions::default().with_max_classes(Some(6)).unwrap();
    for n in [50, 2_000, 40_000, 10_000_000] {
        let old = base.clone().with_budget(ExpansionBudget::Fixed(n)).unwrap();
        let expected = planner
            .search(g.start, g.goal, &old)
            .unwrap()
            .run()
            .unwrap();
        // The same budget as a stop condition, alone and with a time limit and a flag that
        // never fire: bit-identical classes and counters.
        let flag = CancelFlag::new();
        for stop in [
            StopCondition::expansions(n),
            StopCondition::expansions(n)
                .or_time(Duration::from_secs(3600))
                .or_cancel(flag.clone()),
        ] {
            let new = base.clone().with_stop(stop).unwrap();
            let got = planner
                .search(g.start, g.goal, &new)
                .unwrap()
                .run()
                .unwrap();
            assert_eq!(got, expected, "budget {n}");
        }
        if expected.termination == spt::Termination::Expansions {
            assert_eq!(
                expected.stop_reason,
                Some(StopReason::Expansions {
                    limit: n,
                    budget: BudgetKind::Fixed
                })
            );
        }
    }
}

#[test]
fn whichever_condition_fires_first_is_reported() {
    let (btm, start, goal) = big();
    let planner = SptPlanner::new(btm);
    let run = |stop: StopCondition| {
        let options = unbounded().with_stop(stop).unwrap();
        planner
            .search(*start, *goal, &options)
            .unwrap()
            .run()
            .unwrap()
    };
    // The budget first.
    let out = run(StopCondition::expansions(1_000).or_time(Duration::from_secs(3600)));
    assert_eq!(out.termination, spt::Termination::Expansions);
    assert_eq!(out.stats.expansions, 1_000);
    assert_eq!(
        out.stop_reason,
        Some(StopReason::Expansions {
            limit: 1_000,
            budget: BudgetKind::Fixed
        })
    );
    // The time limit first.
    let limit = Duration::from_millis(3);
    let out = run(StopCondition::expansions(usize::MAX / 2).or_time(limit));
    assert_eq!(out.stop_reason, Some(StopReason::TimeLimit { limit }));
    // A flag set before the start: nothing is expanded.
    let flag = CancelFlag::new();
    flag.cancel();
    let out = run(StopCondition::time(Duration::from_secs(3600)).or_cancel(flag.clone()));
    assert_eq!(out.stop_reason, Some(StopReason::Cancelled));
    assert_eq!(out.stats.expansions, 0);
    // The single query reports a stop as an error naming it.
    let e = planner
        .shortest_taut_path_until(*start, *goal, &StopCondition::cancel(flag))
        .unwrap_err();
    assert_eq!(
        e,
        SearchError::Stopped {
            reason: StopReason::Cancelled,
            expansions: 0
        }
    );
    assert!(e.to_string().contains("a cancel request"), "{e}");
}

#[test]
fn the_shortest_path_map_stops_on_time_and_cancel() {
    let (btm, start, _) = big();
    let limit = Duration::from_millis(2);
    let began = Instant::now();
    let e = ShortestPathMap::build_until(btm, *start, &StopCondition::time(limit)).unwrap_err();
    assert!(began.elapsed() < Duration::from_secs(2));
    assert!(
        matches!(
            e,
            SearchError::Stopped {
                reason: StopReason::TimeLimit { .. },
                ..
            }
        ),
        "{e:?}"
    );
    let flag = CancelFlag::new();
    flag.cancel();
    assert_eq!(
        ShortestPathMap::build_until(btm, *start, &StopCondition::cancel(flag)).unwrap_err(),
        SearchError::Stopped {
            reason: StopReason::Cancelled,
            expansions: 0
        }
    );
}

fn open_square() -> ObstacleWorld<2> {
    ObstacleWorld {
        space: RealVectorSpace::new([0.0, 0.0], [1.0, 1.0]).unwrap(),
        obstacles: Vec::new(),
        start: [0.1, 0.1],
        goal: [0.9, 0.9],
        resolution: 0.01,
    }
}

#[test]
fn the_sampler_stops_on_cancel_and_on_the_shared_time_limit() {
    let w = open_square();
    let settings = AbitSettings::default();
    let mut abit = Abit::new(&w.space, &w, w.start, w.goal, settings.clone()).unwrap();
    let flag = CancelFlag::new();
    let other = flag.clone();
    let canceller = std::thread::spawn(move || {
        std::thread::sleep(Duration::from_millis(30));
        other.cancel();
    });
    let began = Instant::now();
    let st = abit
        .solve_until(
            Termination::iterations(u64::MAX),
            &StopCondition::cancel(flag),
        )
        .unwrap();
    canceller.join().unwrap();
    assert_eq!(st.stop_reason, Some(StopReason::Cancelled));
    assert_eq!(st.stopped_by, None);
    assert!(began.elapsed() < Duration::from_secs(5));
    // The shared time limit, and a fixed budget counted in iterations, whichever comes first.
    let mut abit = Abit::new(&w.space, &w, w.start, w.goal, settings.clone()).unwrap();
    let limit = Duration::from_millis(20);
    let st = abit
        .solve_until(
            Termination::iterations(u64::MAX),
            &StopCondition::time(limit),
        )
        .unwrap();
    assert_eq!(st.stop_reason, Some(StopReason::TimeLimit { limit }));
    let mut abit = Abit::new(&w.space, &w, w.start, w.goal, settings).unwrap();
    let st = abit
        .solve_until(
            Termination::time(Duration::from_secs(3600)),
            &StopCondition::expansions(25),
        )
        .unwrap();
    assert_eq!(st.stop_reason, Some(StopReason::Iterations { limit: 25 }));
    assert_eq!(st.iterations, 25);
}

#[test]
fn the_online_simulation_honours_a_cancel() {
    let p = |x, y| Point2::new(x, y);
    let map = Map::new(
        Polygon::new(vec![p(0., 0.), p(20., 0.), p(20., 40.), p(0., 40.)]),
        vec![Polygon::new(vec![p(4., 20.), p(8., 20.), p(6., 23.)])],
    );
    let flag = CancelFlag::new();
    let mut options = SimulationOptions::default();
    options.session.search = options
        .session
        .search
        .with_stop(StopCondition::cancel(flag.clone()))
        .unwrap();
    // Not cancelled: the goal.
    let (report, _) = simulate(
        &map,
        &map,
        p(10., 38.),
        p(10., 2.),
        PlaneSeries::flat(),
        &options,
    )
    .unwrap();
    assert_eq!(report.ending, Ending::Goal);
    assert_eq!(report.stopped_by, None);
    // Cancelled before the start: the first search stops, and the report says why.
    flag.cancel();
    let (report, _) = simulate(
        &map,
        &map,
        p(10., 38.),
        p(10., 2.),
        PlaneSeries::flat(),
        &options,
    )
    .unwrap();
    assert_eq!(report.stopped_by, Some(StopReason::Cancelled));
    assert_ne!(report.ending, Ending::Goal);
}
