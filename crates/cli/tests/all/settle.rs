//! `rappel settle --svg`: the picture is written (an SVG with the pose's groups), an output that
//! would overwrite the ground file is refused before anything is read or written (exit 2), and a
//! PLY mesh is accepted as ground.

use crate::common;
use common::{check_error, fixture, rappel, stderr, temp_dir};

#[test]
fn settle_draws_the_pose_and_refuses_to_overwrite_its_input() {
    let dir = temp_dir("settle-svg");
    let out = dir.join("pose.svg");
    let ledge = fixture("paton/ledge.ron");
    let o = rappel(&[
        "settle",
        &ledge,
        "--at",
        "-1,0",
        "--yaw",
        "0",
        "--anchor",
        "-3,0,4.5",
        "--svg",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let svg = std::fs::read_to_string(&out).expect("picture written");
    for id in ["ground", "body", "wheels", "boom", "tether"] {
        assert!(svg.contains(&format!("<g id=\"{id}\">")), "{id}");
    }
    // The title gives the QP's verdict of the boom drawn, as the JSON report has it.
    let o = rappel(&[
        "settle", &ledge, "--at", "-1,0", "--yaw", "0", "--anchor", "-3,0,4.5", "--json",
    ]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("json");
    let boom = if svg.contains("data-boom=\"boom inline") {
        "inline"
    } else {
        "in-contact"
    };
    let verdict = v["stability"]
        .as_array()
        .and_then(|a| a.iter().find(|b| b["boom"] == boom))
        .expect("the drawn boom's verdict");
    let said = match verdict["stable"].as_bool() {
        Some(true) => format!(
            ", stable (QP margin {:.3})",
            verdict["margin"].as_f64().unwrap()
        ),
        Some(false) => ", unstable (QP)".to_string(),
        None => ", not checked".to_string(),
    };
    assert!(svg.contains(&said), "{said} not in the title");
    check_error(
        &[
            "settle", &ledge, "--at", "-1,0", "--yaw", "0", "--svg", &ledge,
        ],
        "would overwrite the input file",
    );
}

#[test]
fn settle_reads_a_ply_mesh() {
    let dir = temp_dir("settle-ply");
    let ply = dir.join("plane.ply");
    // A 10 m square tilted 10° about x (z = y tan 10°), two triangles.
    let t = 10f64.to_radians().tan();
    let text = format!(
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n-5 -5 {a}\n5 -5 {a}\n5 5 {b}\n-5 5 {b}\n3 0 1 2\n3 0 2 3\n",
        a = -5.0 * t,
        b = 5.0 * t
    );
    std::fs::write(&ply, text).unwrap();
    let o = rappel(&["settle", ply.to_str().unwrap(), "--at", "0,0", "--yaw", "0"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    // Heading +x across the tilt: no pitch, roll equal to the plane's slope.
    let out = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(out.contains("roll 10.00°, pitch 0.00°"), "{out}");
}

/// Issue 14's bad meshes and typed settling failures through the CLI: a mesh file with a NaN
/// vertex or three triangles on one edge exits 2 with one `error:` line naming the file (and for
/// the edge, its vertices); a pose off the ground is a clean "not settled" (exit 1) naming the failure.
#[test]
fn bad_meshes_exit_2_and_poses_off_the_ground_exit_1() {
    let dir = temp_dir("settle-bad");
    let nan = dir.join("nan.obj");
    std::fs::write(&nan, "v 0 0 0\nv 1 0 0\nv 0 1 nan\nf 1 2 3\n").unwrap();
    let nan = nan.to_str().unwrap();
    check_error(&["settle", nan, "--at", "0,0", "--yaw", "0"], "nan.obj");
    let fan = dir.join("fan.obj");
    std::fs::write(
        &fan,
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n",
    )
    .unwrap();
    for expected in ["fan.obj", "non-manifold edge (0, 1)"] {
        check_error(
            &["settle", fan.to_str().unwrap(), "--at", "0,0", "--yaw", "0"],
            expected,
        );
    }
    let ledge = fixture("paton/ledge.ron");
    // Far off the ground: bad input, named (exit 2).
    check_error(
        &["settle", ledge.as_str(), "--at", "500,0", "--yaw", "0"],
        "--at 500,0: outside the ground, which spans x -20.000 to 17.801",
    );
    // Over the ground's edge (the scene ends at x = 17.8 m, the wheels reach 0.45 m past the
    // axle centre): a clean "no" (exit 1), in text and in JSON.
    for field in [None, Some("0.2")] {
        let mut args = vec!["settle", ledge.as_str(), "--at", "17.7,19.9", "--yaw", "90"];
        args.extend(field.map(|f| ["--field", f]).into_iter().flatten());
        let o = rappel(&args);
        assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
        let out = String::from_utf8_lossy(&o.stdout).into_owned();
        assert!(out.starts_with("not settled: "), "{out}");
        args.push("--json");
        let o = rappel(&args);
        assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
        let json: serde_json::Value =
            serde_json::from_slice(&o.stdout).expect("--json prints JSON when not settled");
        assert_eq!(json["report"], "settle_not_settled");
        assert_eq!(json["at"], serde_json::json!([17.7, 19.9]));
        assert!(json["reason"].as_str().is_some_and(|r| !r.is_empty()));
    }
}

/// `rappel settle --robot four-wheel` on the plane `z = y tan 10°` (an OBJ), heading 30°: all
/// four wheels down, the origin on the plane under the start, the pitch the plane's slope along
/// the heading and the roll its slope along the left axis (closed forms, as for Axel in
/// `crates/mechanics/tests/all/settle.rs`), every contact on the plane; the JSON names the robot.
/// With an anchor, one verdict for the tether fixed to the body (boom `none`).
#[test]
fn four_wheel_settles_on_a_plane_at_the_closed_form_pose() {
    let dir = temp_dir("settle-four-wheel");
    let obj = dir.join("plane.obj");
    let b = 10f64.to_radians().tan();
    std::fs::write(
        &obj,
        format!(
            "v -20 -20 {lo}\nv 20 -20 {lo}\nv 20 20 {hi}\nv -20 20 {hi}\nf 1 2 3\nf 1 3 4\n",
            lo = -20.0 * b,
            hi = 20.0 * b
        ),
    )
    .unwrap();
    let obj = obj.to_str().unwrap();
    let (x, y, yaw_deg) = (1.0, 0.5, 30.0f64);
    // The four-wheel rover settled at (x, y, yaw) on the plane, with `extra` arguments: the report.
    let settle = |extra: &[&str]| -> serde_json::Value {
        let mut args = vec![
            "settle",
            obj,
            "--at",
            "1,0.5",
            "--yaw",
            "30",
            "--robot",
            "four-wheel",
            "--json",
        ];
        args.extend_from_slice(extra);
        let o = rappel(&args);
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        serde_json::from_str(&String::from_utf8_lossy(&o.stdout)).unwrap()
    };
    let v = settle(&[]);
    assert_eq!(v["robot"], "four_wheel");
    assert_eq!(v["support"], serde_json::json!([0, 1, 2, 3]));
    assert!(v["body_clearance_m"].is_null());
    let num = |k: &str| v[k].as_f64().unwrap();
    let origin: Vec<f64> = (0..3).map(|k| v["origin"][k].as_f64().unwrap()).collect();
    assert!((origin[0] - x).abs() < 1e-6 && (origin[1] - y).abs() < 1e-6);
    assert!((origin[2] - b * y).abs() < 1e-6, "{origin:?}");
    let yaw = yaw_deg.to_radians();
    let pitch = (b * yaw.sin()).atan().to_degrees();
    let roll = (b * yaw.cos() / ((1.0 + b * b).sqrt() * (1.0 + (b * yaw.sin()).powi(2)).sqrt()))
        .asin()
        .to_degrees();
    assert!(
        (num("pitch_deg") - pitch).abs() < 1e-6,
        "{} vs {pitch}",
        num("pitch_deg")
    );
    assert!(
        (num("roll_deg") - roll).abs() < 1e-6,
        "{} vs {roll}",
        num("roll_deg")
    );
    let contacts = v["contacts"].as_array().unwrap();
    assert_eq!(contacts.len(), 4);
    for c in contacts {
        let c: Vec<f64> = (0..3).map(|k| c[k].as_f64().unwrap()).collect();
        assert!((c[2] - b * c[1]).abs() < 1e-6, "{c:?}");
    }
    let v = settle(&["--anchor", "1,8,3"]);
    let verdicts = v["stability"].as_array().unwrap();
    assert_eq!(verdicts.len(), 1, "{verdicts:?}");
    assert_eq!(verdicts[0]["boom"], "none");
    assert_eq!(verdicts[0]["stable"], true, "{verdicts:?}");
}

/// Bad `--robot` values exit 2 with one `error:` line naming the flag: an unknown robot on
/// `settle` and `settle-map`, and the four-wheel rover with `settle --svg` (the picture draws
/// Axel).
#[test]
fn bad_robots_exit_2_naming_why() {
    let ledge = fixture("paton/ledge.ron");
    let base = ["settle", ledge.as_str(), "--at", "-1,0", "--yaw", "0"];
    let with = |extra: &[&str]| -> Vec<String> {
        base.iter().chain(extra).map(|s| s.to_string()).collect()
    };
    let run = |args: Vec<String>, expected: &str| {
        let a: Vec<&str> = args.iter().map(String::as_str).collect();
        check_error(&a, expected);
    };
    run(
        with(&["--robot", "tank"]),
        "--robot tank: expected axel or four-wheel",
    );
    let dir = temp_dir("settle-robot-svg");
    let svg = dir.join("x.svg");
    run(
        with(&["--robot", "four-wheel", "--svg", svg.to_str().unwrap()]),
        "draws Axel only",
    );
    assert!(!svg.exists());
    check_error(
        &["settle-map", &ledge, "--test", "1", "--robot", "Axel"],
        "--robot Axel: expected axel or four-wheel",
    );
}
