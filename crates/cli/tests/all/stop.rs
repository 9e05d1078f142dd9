//! `--time-limit SECONDS` on the long commands (issue 32): refused unless a positive, finite
//! number (exit 2, one `error:` line); on the 10,000-obstacle crater strip a tiny limit ends the
//! plan with the time limit's words and the clean "no" (exit 1).

use crate::common;

use common::*;

#[test]
fn non_positive_or_non_finite_time_limits_are_refused() {
    let strip = fixture("generated/crater-strip-100.ron");
    for bad in ["0", "-1", "nan", "inf", "-0.5"] {
        check_error(&["plan", &strip, "--time-limit", bad], "--time-limit");
    }
    check_error(
        &["stability", &strip, "--time-limit", "0"],
        "must be a positive number of seconds",
    );
    check_error(
        &["online", &strip, "--truth", &strip, "--time-limit", "0"],
        "must be a positive number of seconds",
    );
    check_error(
        &[
            "query",
            &strip,
            "--pairs",
            "no-such-pairs.json",
            "--time-limit",
            "0",
        ],
        "must be a positive number of seconds",
    );
    check_error(
        &[
            "navigate",
            &fixture("paton/ledge.ron"),
            "--seed",
            "0",
            "--time-limit",
            "0",
        ],
        "must be a positive number of seconds",
    );
    check_error(
        &[
            "settle-map",
            &fixture("paton/ledge.ron"),
            "--test",
            "1",
            "--time-limit",
            "0",
        ],
        "must be a positive number of seconds",
    );
}

#[test]
fn a_tiny_time_limit_stops_the_plan_on_the_10k_strip() {
    let o = rappel(&[
        "plan",
        &fixture("generated/crater-strip-10000.ron"),
        "--time-limit",
        "0.001",
    ]);
    let (out, err) = (stdout(&o), stderr(&o));
    assert_eq!(o.status.code(), Some(1), "{out}\n{err}");
    assert!(
        out.contains("the search stopped at the time limit of 0.001 s"),
        "{out}"
    );
    assert!(err.contains("stopped: the time limit of 0.001 s"), "{err}");
    let o = rappel(&[
        "plan",
        &fixture("generated/crater-strip-10000.ron"),
        "--time-limit",
        "0.001",
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("json");
    assert_eq!(v["termination"], "time_limit");
    assert_eq!(v["stop_reason"]["kind"], "time_limit");
    assert_eq!(v["stop_reason"]["limit_s"], 0.001);
}
