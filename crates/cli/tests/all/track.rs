//! `rappel track` on Kumar's environment (fixtures/tracking): exit 0 when Robot 2 holds at every
//! waypoint, 1 at the first unstable one (named), 2 on a path through an obstacle.

use crate::common;

use common::*;

fn track(robot1: &str, robot2: &str, extra: &[&str]) -> std::process::Output {
    let mut args = vec![
        "track".to_string(),
        fixture("tracking/kumar.json"),
        "--robot1".into(),
        robot1.to_string(),
        "--robot2".into(),
        robot2.to_string(),
    ];
    args.extend(extra.iter().map(|s| s.to_string()));
    let refs: Vec<&str> = args.iter().map(String::as_str).collect();
    rappel(&refs)
}

#[test]
fn a_wound_tether_holds_robot_2_down_the_slopes() {
    let dir = temp_dir("track");
    let svg = dir.join("t.svg");
    let svg3d = dir.join("t3d.svg");
    let o = track(
        &fixture("tracking/robot1-nearly-full-turn.json"),
        &fixture("tracking/robot2-descent.json"),
        &[
            "--json",
            "--svg",
            svg.to_str().unwrap_or_default(),
            "--svg3d",
            svg3d.to_str().unwrap_or_default(),
        ],
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    let w = v["waypoints"].as_array().expect("waypoints");
    assert_eq!(w.len(), 9);
    // eq. 2 with F_0 = 0: T2max = 0.4 * 35 * 9.81 * exp(0.4 * total winding) at the start.
    let phi = w[0]["total_winding_deg"]
        .as_f64()
        .expect("winding")
        .to_radians();
    let t2 = w[0]["t2max_n"].as_f64().expect("t2max");
    assert!((t2 - 0.4 * 35.0 * 9.81 * (0.4 * phi).exp()).abs() < 1e-9 * t2);
    // Down on the slopes the last anchor is a ground anchor at the crest above.
    assert_eq!(w[4]["ground_anchored"], true);
    assert!(std::fs::read_to_string(&svg).expect("svg").contains("<svg"));
    // The 3D view: 4 surfaces, 2 prisms of 4 sides and a top each.
    let s3 = std::fs::read_to_string(&svg3d).expect("svg3d");
    assert_eq!(s3.matches("<polygon").count(), 4 + 2 * 5);
}

#[test]
fn a_fixed_anchor_without_winding_cannot_hold_robot_2_on_55_degrees() {
    let o = track(
        &fixture("tracking/robot1-fixed.json"),
        &fixture("tracking/robot2-descent.json"),
        &[],
    );
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("not stable at waypoint 1"), "{out}");
}

#[test]
fn a_path_through_an_obstacle_is_a_positioned_error() {
    let dir = temp_dir("track-bad");
    let p = dir.join("through.json");
    // Across O2 ([10, 12] x [3, 5] in the frame).
    std::fs::write(&p, "[[13, 2], [9, 6]]").expect("write");
    check_error(
        &[
            "track",
            &fixture("tracking/kumar.json"),
            "--robot1",
            p.to_str().unwrap_or_default(),
            "--robot2",
            &fixture("tracking/robot2-descent.json"),
        ],
        "robot 1: step 0 passes through obstacle 1",
    );
}

/// The scenario's `model` (Kumar's text against rappel's defaults): with ground anchors at
/// valleys no pose on Kumar's convex hillside is ground-anchored, the report names the model,
/// and an unknown field of `model` is an error.
#[test]
fn the_scenario_model_chooses_the_reading_of_kumar_and_refuses_unknown_fields() {
    let dir = temp_dir("track-model");
    let mut s: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(fixture("tracking/kumar.json")).expect("read"),
    )
    .expect("JSON");
    s["model"] = serde_json::json!({"ground_anchors": "valleys", "robot2": "body"});
    let kumar = dir.join("kumar-text.json");
    std::fs::write(&kumar, s.to_string()).expect("write");
    let run = |scenario: &std::path::Path| {
        rappel(&[
            "track",
            scenario.to_str().unwrap_or_default(),
            "--robot1",
            &fixture("tracking/robot1-nearly-full-turn.json"),
            "--robot2",
            &fixture("tracking/robot2-descent.json"),
            "--json",
        ])
    };
    let o = run(&kumar);
    assert!(matches!(o.status.code(), Some(0 | 1)), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    assert_eq!(v["model"]["ground_anchors"], "valleys");
    assert_eq!(v["model"]["robot2"], "body");
    assert_eq!(v["model"]["friction_pyramid"], "circumscribed");
    let w = v["waypoints"].as_array().expect("waypoints");
    // The default model puts a ground anchor at the crest above waypoint 4 (the test above);
    // Kumar's "concave" read as a valley puts none anywhere on this hillside.
    assert!(w.iter().all(|x| x["ground_anchored"] == false));
    assert!(w.iter().all(|x| x["t2max_n"] == x["t2max_obstacles_n"]));
    s["model"] = serde_json::json!({"robot_2": "body"});
    let bad = dir.join("bad-model.json");
    std::fs::write(&bad, s.to_string()).expect("write");
    let o = run(&bad);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("robot_2"), "{}", stderr(&o));
}
