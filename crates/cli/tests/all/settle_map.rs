//! `rappel settle-map` on Paton's ledge: the JSON map's slope cells past the lip (the boom swept
//! against the mesh rests on the lip within its reach) are stable under the test-1 root (anchored on the lip) and unstable under the test-2
//! root; the four-wheel rover's map is red on the slope under the test-2 root; bad input exits 2.

use crate::common;

use common::*;

/// Paton Fig. 8's view at 0.5 m (over the lip and down the slope, y within 2 m), as JSON.
const FIG8_VIEW: [&str; 7] = ["--x", "-2,2.5", "--y", "-2,2", "--step", "0.5", "--json"];

fn slope_cells(v: &serde_json::Value) -> Vec<&serde_json::Value> {
    // The paper's ledge: lip at x = 0, slope foot at x = 4 / tan 55° = 2.80 m.
    v["cells"]
        .as_array()
        .expect("cells")
        .iter()
        .filter(|c| {
            let x = c["ground"][0].as_f64().unwrap_or(f64::NAN);
            x > 0.0 && x < 2.5 && c["ground"][1].as_f64().is_some_and(|y| y.abs() <= 2.0)
        })
        .collect()
}

/// The slope cells where the robot settled, asserting there are at least 27 of them.
fn settled_slope_cells(v: &serde_json::Value) -> Vec<&serde_json::Value> {
    let slope: Vec<_> = slope_cells(v)
        .into_iter()
        .filter(|c| !c["pose"].is_null())
        .collect();
    assert!(slope.len() >= 27, "{} settled slope cells", slope.len());
    slope
}

#[test]
fn ledge_map_is_green_under_test_1_and_red_under_test_2() {
    let dir = temp_dir("settle-map");
    let svg = dir.join("m.svg");
    let ledge = fixture("paton/ledge.ron");
    let args = FIG8_VIEW;
    let mut one: Vec<&str> = vec!["settle-map", &ledge, "--test", "1", "--svg"];
    one.push(svg.to_str().unwrap_or_default());
    one.extend(args);
    let o = rappel(&one);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    assert_eq!(v["report"], "settle_map");
    let cells = slope_cells(&v);
    assert!(cells.len() >= 36, "{}", cells.len());
    for c in &cells {
        assert_eq!(c["pose"]["stable"], serde_json::Value::Bool(true), "{c}");
        let last = c["pose"]["anchors"]
            .as_array()
            .and_then(|a| a.last())
            .expect("anchor");
        assert!(last[0].as_f64().is_some_and(|x| x.abs() < 0.1), "{c}");
    }
    assert!(std::fs::read_to_string(&svg).is_ok_and(|s| s.contains("stability map")));
    let mut two: Vec<&str> = vec!["settle-map", &ledge, "--test", "2"];
    two.extend(args);
    let o = rappel(&two);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    for c in slope_cells(&v) {
        assert_eq!(c["pose"]["stable"], serde_json::Value::Bool(false), "{c}");
    }
}

#[test]
fn bad_settle_map_input_exits_2() {
    let ledge = fixture("paton/ledge.ron");
    for extra in [
        vec!["--test", "7"],
        vec!["--test", "1", "--step", "0"],
        vec!["--root", "1,2"],
        vec![],
        vec!["--test", "1", "--start", "99,0"],
    ] {
        let mut a = vec!["settle-map", ledge.as_str()];
        a.extend(extra.iter().copied());
        let o = rappel(&a);
        assert_eq!(o.status.code(), Some(2), "{extra:?}: {}", stderr(&o));
    }
}

/// `--field RES`: settling and anchor prediction through the sparse distance field shade the
/// slope like the exact path (test-1 root: every slope cell stable, anchored on the lip); a bad
/// resolution exits 2 naming the flag and the value (more in `tests/field.rs`).
#[test]
fn field_option_shades_the_slope_and_refuses_bad_resolutions() {
    let ledge = fixture("paton/ledge.ron");
    let mut base = vec!["settle-map", ledge.as_str(), "--test", "1"];
    base.extend(FIG8_VIEW);
    let mut args = base.clone();
    args.extend(["--field", "0.1"]);
    let o = rappel(&args);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    let cells = slope_cells(&v);
    assert!(cells.len() >= 36, "{}", cells.len());
    for c in &cells {
        assert_eq!(c["pose"]["stable"], serde_json::Value::Bool(true), "{c}");
    }
    let mut bad = base;
    bad.extend(["--field", "0"]);
    check_error(
        &bad,
        "--field 0: the resolution must be a positive, finite number",
    );
}

/// `--robot four-wheel`: the rigid rover's map (tether fixed to its body, one verdict without a
/// boom). Under the test-2 root the tether from a slope cell runs toward the anchor 8.2 m in front
/// of the start and 2 m above it: away from the 55° slope and not uphill along it, so it cannot
/// hold the rover, and wheel friction 0.6 (`SCENE_FRICTION`) is below tan 55° = 1.43: every
/// settled slope cell must be unstable. On the flat top, far enough from the lip for all four
/// wheels, the rover rests on its wheels without the tether: stable. The rover does not settle
/// straddling the lip (its rest iteration does not converge there), so the slope's histories
/// are predicted across that row from the top. Under the test-1 root the slope cells anchor on
/// the lip and the tether, running up the slope, holds them.
#[test]
fn four_wheel_map_is_red_on_the_slope_under_test_2() {
    let ledge = fixture("paton/ledge.ron");
    let map = |test: &str| -> serde_json::Value {
        let mut args = vec![
            "settle-map",
            &ledge,
            "--test",
            test,
            "--robot",
            "four-wheel",
        ];
        args.extend(FIG8_VIEW);
        let o = rappel(&args);
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        serde_json::from_slice(&o.stdout).expect("JSON")
    };
    let one = map("1");
    let slope = settled_slope_cells(&one);
    for c in &slope {
        assert_eq!(c["pose"]["stable"], serde_json::Value::Bool(true), "{c}");
        // From x = 1 m on, the straight tether from the root to the tether exit would pass more
        // than 0.3 m under the lip (at x = 0.5 m only about 5 cm, the prediction's sampling
        // depth), so the last anchor is on the lip.
        if c["ground"][0].as_f64().is_some_and(|x| x >= 1.0) {
            let last = c["pose"]["anchors"]
                .as_array()
                .and_then(|a| a.last())
                .expect("anchor");
            assert!(last[0].as_f64().is_some_and(|x| x.abs() < 0.1), "{c}");
        }
    }
    let v = map("2");
    assert_eq!(v["robot"], "four_wheel");
    let slope = settled_slope_cells(&v);
    for c in &slope {
        assert_eq!(c["pose"]["stable"], serde_json::Value::Bool(false), "{c}");
        assert_eq!(c["pose"]["verdicts"][0]["boom"], "none", "{c}");
    }
    let top: Vec<_> = v["cells"]
        .as_array()
        .expect("cells")
        .iter()
        .filter(|c| c["ground"][0].as_f64().is_some_and(|x| x <= -1.0))
        .collect();
    assert!(top.len() >= 18, "{} top cells", top.len());
    for c in &top {
        assert_eq!(c["pose"]["stable"], serde_json::Value::Bool(true), "{c}");
    }
}
