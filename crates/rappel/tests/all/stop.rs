//! The one stop condition through the facade (issue 32): a time limit stops `plan` on the
//! 10,000-obstacle crater strip at once, and a cancel flag set from another thread stops `query`
//! and `navigate`; each report names the condition.

use rappel::navigate::{RoverProblem, navigate};
use rappel::plan::PlanOptions;
use rappel::planners::sampler::Termination;
use rappel::planners::stop::{CHECK_INTERVAL, CancelFlag, StopCondition, StopReason};
use rappel::query::{QueryOptions, QueryPair, answer};
use rappel::scenario::Scenario;
use rappel::terrain::paton_scene::PatonScene;
use std::time::{Duration, Instant};

fn strip_10k() -> Scenario {
    Scenario::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../fixtures/generated/crater-strip-10000.ron"
    ))
    .expect("fixture")
}

/// Sets `flag` from another thread after `after`.
fn cancel_later(flag: &CancelFlag, after: Duration) -> std::thread::JoinHandle<()> {
    let flag = flag.clone();
    std::thread::spawn(move || {
        std::thread::sleep(after);
        flag.cancel();
    })
}

#[test]
fn a_time_limit_stops_plan_on_the_10k_strip_and_the_verdict_names_it() {
    let s = strip_10k();
    let limit = Duration::from_millis(1);
    let options = PlanOptions {
        classes: 50,
        stop: StopCondition::time(limit),
        ..Default::default()
    };
    let began = Instant::now();
    let r = rappel::plan(&s, &options).expect("a stopped plan is a report");
    let took = began.elapsed();
    assert_eq!(r.outcome.stop_reason, Some(StopReason::TimeLimit { limit }));
    assert_eq!(
        r.outcome.termination,
        rappel::planners::spt::Termination::TimeLimit
    );
    // The clock counts from the call: the triangulation alone outlasts 1 ms, so the search
    // stops at its first check.
    assert!(
        r.outcome.stats.expansions <= CHECK_INTERVAL,
        "{:?}",
        r.outcome.stats
    );
    assert!(
        r.outcome
            .verdict
            .contains("the search stopped at the time limit of 0.001 s"),
        "{}",
        r.outcome.verdict
    );
    assert!(took < Duration::from_secs(60), "{took:?}");
    // The same plan without the limit goes on (its budget or classes stop it, not a clock).
    let whole = rappel::plan(
        &s,
        &PlanOptions {
            classes: 1,
            ..Default::default()
        },
    )
    .expect("plans");
    assert!(!matches!(
        whole.outcome.stop_reason,
        Some(StopReason::TimeLimit { .. } | StopReason::Cancelled)
    ));
}

#[test]
fn a_cancel_from_another_thread_stops_query() {
    let s = strip_10k();
    let map = s.map.validate().expect("valid map");
    // Far more work than the test waits for: the cancel must cut it short.
    let pairs = vec![
        QueryPair {
            start: s.start,
            goal: s.goal,
        };
        20_000
    ];
    let flag = CancelFlag::new();
    let canceller = cancel_later(&flag, Duration::from_millis(200));
    let began = Instant::now();
    let options = QueryOptions {
        classes: 3,
        stop: StopCondition::cancel(flag.clone()),
        ..Default::default()
    };
    let answers = answer(map, &pairs, &options).expect("answers");
    canceller.join().unwrap();
    assert!(began.elapsed() < Duration::from_secs(120));
    assert_eq!(answers.len(), pairs.len());
    let last = answers.last().unwrap();
    assert_eq!(last.stop_reason, Some(StopReason::Cancelled));
    let error = last.error.as_deref().unwrap();
    assert!(error.contains("a cancel request"), "{error}");
    // Every pair after the first stopped one is stopped too, none is silently empty.
    let first = answers
        .iter()
        .position(|a| a.stop_reason.is_some())
        .expect("some pair was stopped");
    assert!(
        answers[first..]
            .iter()
            .all(|a| a.stop_reason == Some(StopReason::Cancelled) && a.error.is_some())
    );
}

#[test]
fn a_cancel_from_another_thread_stops_navigate() {
    let problem = RoverProblem::paton(&PatonScene::paper(false), 0).unwrap();
    let flag = CancelFlag::new();
    let canceller = cancel_later(&flag, Duration::from_millis(300));
    let began = Instant::now();
    // Without the cancel, a day or a billion iterations.
    let term = Termination::iterations(1_000_000_000).or_time(Duration::from_secs(86_400));
    let r = navigate(&problem, 0, term, &StopCondition::cancel(flag.clone())).unwrap();
    canceller.join().unwrap();
    assert!(began.elapsed() < Duration::from_secs(120));
    assert_eq!(r.stopped_by, rappel::navigate::StoppedBy::Cancelled);
    assert_eq!(r.stop_reason, Some(StopReason::Cancelled));
    assert!(r.iterations < 1_000_000_000);
}

#[test]
fn a_time_limit_of_the_condition_is_time_limit_in_navigate() {
    let problem = RoverProblem::paton(&PatonScene::paper(false), 0).unwrap();
    let limit = Duration::from_millis(200);
    let term = Termination::iterations(1_000_000_000).or_time(Duration::from_secs(86_400));
    let r = navigate(&problem, 0, term, &StopCondition::time(limit)).unwrap();
    assert_eq!(r.stopped_by, rappel::navigate::StoppedBy::TimeLimit);
    assert_eq!(r.stop_reason, Some(StopReason::TimeLimit { limit }));
}
