//! `--time-limit SECONDS` on the long commands (issue 32): refused unless a positive, finite
//! number (exit 2, one `error:` line); on the 10,000-obstacle crater strip a tiny limit ends the
//! plan with the time limit's words and the clean "no" (exit 1); a real SIGINT (Ctrl-C) stops a
//! long plan at once, keeping the pair it found and naming the cancel request.

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

/// Ctrl-C as a terminal sends it: SIGINT to the process while it lists 1,000 classes of the
/// 10,000-obstacle strip (about 8 s of work). The search stops at its next check: the report
/// keeps the classes and the pair found so far, names the cancel request, and exits 0 (a pair
/// was found) soon after the signal.
#[test]
fn ctrl_c_stops_a_long_plan_and_says_so() {
    use std::io::{BufRead, BufReader, Read};
    use std::process::{Command, Stdio};
    use std::time::{Duration, Instant};
    let mut child = Command::new(env!("CARGO_BIN_EXE_rappel"))
        .args([
            "plan",
            &fixture("generated/crater-strip-10000.ron"),
            "--classes",
            "1000",
            "--max-expansions",
            "2000000000",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    let mut out = BufReader::new(child.stdout.take().expect("stdout"));
    // The first class is printed once the search runs (the handler is installed before).
    let mut text = String::new();
    while !text.contains("class 2 ") {
        let mut line = String::new();
        if out.read_line(&mut line).expect("read") == 0 {
            panic!("the plan ended before its second class: {text}");
        }
        text.push_str(&line);
    }
    let signalled = Instant::now();
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(kill.success());
    out.read_to_string(&mut text).expect("read the rest");
    let status = child.wait().expect("wait");
    let waited = signalled.elapsed();
    let mut err = String::new();
    child
        .stderr
        .take()
        .expect("stderr")
        .read_to_string(&mut err)
        .expect("stderr");
    assert_eq!(status.code(), Some(0), "{err}");
    assert!(
        waited < Duration::from_secs(5),
        "stopped {waited:?} after the signal"
    );
    assert!(
        text.contains("the search stopped at a cancel request"),
        "{text}"
    );
    assert!(err.contains("stopped: a cancel request"), "{err}");
    let classes = text.lines().filter(|l| l.starts_with("class ")).count();
    assert!((2..1000).contains(&classes), "{classes} classes");
}
