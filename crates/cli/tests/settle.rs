//! `rappel settle --svg`: the picture is written (an SVG with the pose's groups), an output that
//! would overwrite the ground file is refused before anything is read or written (exit 2), and a
//! PLY mesh is accepted as ground.

mod common;
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
    for field in [None, Some("0.2")] {
        let mut args = vec!["settle", ledge.as_str(), "--at", "500,0", "--yaw", "0"];
        args.extend(field.map(|f| ["--field", f]).into_iter().flatten());
        let o = rappel(&args);
        assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
        let out = String::from_utf8_lossy(&o.stdout).into_owned();
        assert!(
            out.starts_with("not settled: no ground under the footprint"),
            "{out}"
        );
    }
}
