//! `rappel navigate` on Paton's ledge: a re-validated path anchored on the lip under the test-1
//! root (exit 0, JSON, SVG), no path under the test-2 root within a small budget (exit 1, the
//! budget named), bad input exits 2.

use crate::common;

use common::*;

#[test]
fn test_1_finds_a_lip_anchored_path_and_test_2_runs_out_of_budget() {
    let dir = temp_dir("navigate");
    let svg = dir.join("n.svg");
    let ledge = fixture("paton/ledge.ron");
    // The start-goal edge is tried first: seed 2 finds the straight descent at once (measured:
    // iteration 1); 60 leaves room.
    let o = rappel(&[
        "navigate",
        &ledge,
        "--seed",
        "2",
        "--iterations",
        "60",
        "--json",
        "--svg",
        svg.to_str().unwrap_or_default(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("json");
    assert_eq!(v["found"], true);
    let anchors = v["anchors"].as_array().expect("anchors");
    assert_eq!(anchors.len(), 2);
    // The lip: x = 0, z = 4 (the scene's closed form).
    assert!(anchors[1][0].as_f64().unwrap_or(9.0).abs() < 0.1);
    assert!((anchors[1][2].as_f64().unwrap_or(0.0) - 4.0).abs() < 0.1);
    let path = v["path"].as_array().expect("path");
    let end = path.last().expect("non-empty");
    assert!((end[0].as_f64().unwrap_or(0.0) - (4.0 / 55f64.to_radians().tan() + 2.0)).abs() < 1e-6);
    assert!(v["min_margin_n"].as_f64().unwrap_or(-1.0) >= 0.0);
    assert!(std::fs::read_to_string(&svg).expect("svg").contains("<svg"));
    // Table I test 2 on the ledge, seed 0, with a budget (it has no path: a budget ends it).
    let test_2 = |budget: &[&str]| {
        let mut args = vec!["navigate", ledge.as_str(), "--seed", "0", "--test", "2"];
        args.extend_from_slice(budget);
        rappel(&args)
    };
    let o = test_2(&["--iterations", "20"]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(String::from_utf8_lossy(&o.stdout).contains("the iterations budget ran out"));
    // A time budget interrupts the search and says so. The iteration budget is far beyond what
    // 0.3 s can reach (test 2 has no path, so the search never ends by itself): with the
    // default 750 the outcome depended on the machine's speed (a fast run spent its 750
    // iterations first and stopped by "iterations").
    let began = std::time::Instant::now();
    let o = test_2(&["--iterations", "1000000", "--time", "0.3", "--json"]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("json");
    assert_eq!(v["stopped_by"], "time");
    assert!(v["iterations"].as_u64().unwrap_or(0) < 1_000_000);
    assert!(began.elapsed() < std::time::Duration::from_secs(20));
}

#[test]
fn bad_navigate_input_exits_2() {
    let ledge = fixture("paton/ledge.ron");
    for extra in [
        vec!["--seed", "0", "--test", "3"],
        vec!["--seed", "0", "--test", "0"],
        vec!["--seed", "0", "--time", "0"],
        vec!["--seed", "0", "--iterations", "0"],
        vec![],
    ] {
        let mut a = vec!["navigate", ledge.as_str()];
        a.extend(extra.iter().copied());
        let o = rappel(&a);
        assert_eq!(o.status.code(), Some(2), "{extra:?}: {}", stderr(&o));
    }
    let o = rappel(&["navigate", "no/such/scene.ron", "--seed", "0"]);
    assert_eq!(o.status.code(), Some(2));
}
