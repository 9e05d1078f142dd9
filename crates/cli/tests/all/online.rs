//! End-to-end tests of `rappel online`: exit code 0 at the goal, 1 for a clean "no", 2 with one
//! `error:` line for bad input; the JSON timeline and the pictures.

use crate::common;

use common::*;

#[test]
fn the_worked_example_reaches_the_goal_and_draws_its_frames() {
    let dir = temp_dir("online");
    let svg = dir.join("final.svg");
    let frames = dir.join("frames");
    let o = rappel(&[
        "online",
        &fixture("online-example.ron"),
        "--truth",
        &fixture("online-example-discovered.ron"),
        "--json",
        "--svg",
        svg.to_str().unwrap_or_default(),
        "--frames",
        frames.to_str().unwrap_or_default(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    assert_eq!(v["ending"]["ending"], "goal");
    assert_eq!(v["homotopic"], true);
    assert_eq!(v["timeline"][0]["outcome"]["case"], "split");
    assert!(std::fs::read_to_string(&svg).is_ok_and(|s| s.starts_with("<svg")));
    assert!(frames.join("event-001.svg").exists());
}

#[test]
fn a_blocked_sleeve_without_a_feasible_class_is_exit_1() {
    let o = rappel(&[
        "online",
        &fixture("online-example.ron"),
        "--truth",
        &fixture("online/case-1-blocked.ron"),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stdout(&o).contains("no feasible class"));
}

#[test]
fn bad_options_and_mismatched_scenarios_are_exit_2() {
    for (args, expected) in [
        (vec!["--step", "6"], "sensor range"),
        (vec!["--classes", "0"], "--classes 0"),
    ] {
        let mut all = vec![
            "online".to_string(),
            fixture("online-example.ron"),
            "--truth".to_string(),
            fixture("online-example.ron"),
        ];
        all.extend(args.iter().map(|s| s.to_string()));
        let refs: Vec<&str> = all.iter().map(String::as_str).collect();
        let o = rappel(&refs);
        assert_eq!(o.status.code(), Some(2));
        let err = stderr(&o);
        assert!(err.starts_with("error:") && err.contains(expected), "{err}");
        assert_eq!(err.lines().count(), 1, "{err}");
    }
    let o = rappel(&[
        "online",
        &fixture("online-example.ron"),
        "--truth",
        &fixture("thesis-fig-2-7.ron"),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("differs from the prior"),
        "{}",
        stderr(&o)
    );
}

/// The run is bounded from the map's size (issue 30): a step below 1e-5 of the prior map's
/// diagonal and a step budget over 1,000,000 are refused up front, naming the option and the
/// bound; at the floor the run is accepted.
#[test]
fn tiny_steps_and_huge_budgets_are_refused_up_front() {
    let prior = fixture("online-example.ron");
    let truth = fixture("online-example-discovered.ron");
    let started = std::time::Instant::now();
    check_error(
        &["online", &prior, "--truth", &truth, "--step", "1e-9"],
        "is below the floor of",
    );
    check_error(
        &[
            "online",
            &prior,
            "--truth",
            &truth,
            "--max-steps",
            "1000001",
        ],
        "max_steps 1000001 must be from 1 to 1000000",
    );
    assert!(started.elapsed() < std::time::Duration::from_secs(10));
    let o = rappel(&[
        "online",
        &prior,
        "--truth",
        &truth,
        "--max-steps",
        "1000000",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
}
