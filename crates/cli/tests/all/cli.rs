//! End-to-end tests of the `rappel` binary: outputs, exit codes, one-line errors naming the place,
//! and no half-written files.

use crate::common;

use common::*;

#[test]
fn btm_json_reports_the_checked_invariants() {
    let o = rappel(&["btm", &fixture("thesis-fig-2-7.ron"), "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    assert_eq!(v["vertices"], 8 + 3 + 4 + 5 + 6 + 3 + 5 + 4);
    assert_eq!(v["holes"], 7);
    assert_eq!(v["triangles"], 38 + 2 * 7 - 2);
    assert_eq!(v["constrained_delaunay"], true);
    assert!(v["build_us"].as_u64().is_some());
    assert_eq!(v["schema_version"], 1);
    assert_eq!(v["report"], "btm");
}

#[test]
fn btm_writes_an_svg_with_the_legend() {
    let dir = temp_dir("svg");
    let out = dir.join("btm.svg");
    let o = rappel(&[
        "btm",
        &fixture("online-example.ron"),
        "--svg",
        out.to_str().unwrap_or_default(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let svg = std::fs::read_to_string(&out).expect("svg written");
    for needle in ["<svg", "BTM edge", "obstacle", "fall line", " m</text>"] {
        assert!(svg.contains(needle), "missing {needle}");
    }
}

#[test]
fn bad_inputs_exit_2_with_one_located_error() {
    let dir = temp_dir("bad");
    let write = |name: &str, text: &str| {
        let p = dir.join(name);
        std::fs::write(&p, text).expect("write");
        p.display().to_string()
    };
    let syntax = write(
        "syntax.ron",
        "(\n  map: (boundary: [(0.0, 0.0), (1.0 0.0)]),\n)",
    );
    check_error(&["validate", &syntax], "syntax.ron:2:");
    let overlap = write(
        "overlap.json",
        r#"{"map": {"boundary": [[0,0],[10,0],[10,10],[0,10]], "obstacles": [[[2,2],[4,2],[4,4],[2,4]], [[3,3],[5,3],[5,5],[3,5]]]}, "start": [1,9], "goal": [9,1]}"#,
    );
    check_error(&["validate", &overlap], "obstacles 0 and 1 overlap near");
    let goal = write(
        "goal.json",
        r#"{"map": {"boundary": [[0,0],[10,0],[10,10],[0,10]]}, "start": [1,9], "goal": [11,1]}"#,
    );
    check_error(
        &["btm", &goal],
        "goal point (11, 1) is outside the map boundary",
    );
    check_error(
        &["validate", &dir.join("missing.ron").display().to_string()],
        "missing.ron",
    );
    check_error(
        &["validate", &write("x.txt", "")],
        "unknown scenario format",
    );
}

#[test]
fn failed_runs_leave_no_output_file() {
    let dir = temp_dir("atomic");
    // A regular file where a directory should be: nothing can be written below it.
    std::fs::write(dir.join("nope"), "not a directory").expect("write");
    let out = dir.join("nope").join("btm.svg");
    check_error(
        &[
            "btm",
            &fixture("online-example.ron"),
            "--svg",
            out.to_str().unwrap_or_default(),
        ],
        "cannot write",
    );
    assert!(!out.exists());
    let bad = dir.join("bad.ron");
    std::fs::write(&bad, "(map: 1)").expect("write");
    let svg = dir.join("x.svg");
    check_error(
        &[
            "btm",
            bad.to_str().unwrap_or_default(),
            "--svg",
            svg.to_str().unwrap_or_default(),
        ],
        "bad.ron:1:",
    );
    assert!(!svg.exists());
    // Only `nope` and `bad.ron`: no temporary file left behind.
    assert_eq!(
        std::fs::read_dir(&dir).map(|d| d.count()).unwrap_or(0),
        2,
        "stray temporary files"
    );
}

#[test]
fn gen_map_is_reproducible_from_its_seed() {
    let dir = temp_dir("gen");
    let (a, b, c) = (dir.join("a.ron"), dir.join("b.ron"), dir.join("c.json"));
    for (p, seed) in [(&a, "5"), (&b, "5"), (&c, "6")] {
        let o = rappel(&[
            "gen-map",
            "--obstacles",
            "40",
            "--seed",
            seed,
            "--out",
            p.to_str().unwrap_or_default(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let (ta, tb) = (
        std::fs::read_to_string(&a).unwrap_or_default(),
        std::fs::read_to_string(&b).unwrap_or_default(),
    );
    assert!(!ta.is_empty());
    assert_eq!(ta, tb);
    let o = rappel(&["validate", c.to_str().unwrap_or_default()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(String::from_utf8_lossy(&o.stdout).contains("40 obstacles"));
    check_error(
        &[
            "gen-map",
            "--obstacles",
            "3",
            "--out",
            dir.join("x.yaml").to_str().unwrap_or_default(),
        ],
        "unknown scenario format",
    );
}

#[test]
fn stability_map_dots_carry_margins_and_tighter_limits_shrink_the_stable_set() {
    let stable_with = |limit: &str| -> (usize, serde_json::Value) {
        let o = rappel(&[
            "stability",
            &fixture("online-example.ron"),
            "--grid",
            "4",
            "--tension-limit",
            limit,
            "--json",
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
        (v["stable"].as_u64().unwrap_or(0) as usize, v)
    };
    let (loose, v) = stable_with("500");
    let (tight, _) = stable_with("100");
    // 45 degrees, mu 0.4, 35 kg: holding straight below the anchor needs m g (sin - mu cos) = 145.6 N.
    assert!(loose > 0 && tight < loose, "{tight} !< {loose}");
    let dots = v["dots"].as_array().cloned().unwrap_or_default();
    assert!(
        dots.iter()
            .any(|d| d["stable"] == true && d["margin"].as_f64().is_some())
    );
    // Below the obstacles the taut tether wraps an obstacle vertex: its last anchor is a vertex of
    // one of the two triangles (fixtures/online-example.ron), never another point.
    let vertices = [
        (10.0, 40.0),
        (22.0, 40.0),
        (15.0, 31.0),
        (20.0, 24.0),
        (31.0, 24.0),
        (26.0, 15.0),
    ];
    let mut wrapped = 0;
    for d in &dots {
        let a = (
            d["last_anchor"][0].as_f64().unwrap_or(f64::NAN),
            d["last_anchor"][1].as_f64().unwrap_or(f64::NAN),
        );
        if a != (18.0, 57.0) {
            assert!(
                vertices.contains(&a),
                "last anchor {a:?} is neither the start nor an obstacle vertex"
            );
            wrapped += 1;
        }
    }
    assert!(wrapped > 0);
    check_error(
        &["stability", &fixture("online-example.ron"), "--grid", "0"],
        "step must be finite and positive",
    );
}

#[test]
fn dem_makes_a_valid_scenario_from_real_terrain_and_refuses_bad_files() {
    let dir = temp_dir("dem");
    let out = dir.join("mars.ron");
    let svg = dir.join("mars.svg");
    let dem = fixture("terrain/mars_hirise_dteec_010228_1490_crop.asc");
    let o = rappel(&[
        "dem",
        &dem,
        "--out",
        out.to_str().unwrap_or_default(),
        "--svg",
        svg.to_str().unwrap_or_default(),
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    assert!(v["counts"]["planes"].as_u64().unwrap_or(0) >= 1);
    let o = rappel(&["btm", out.to_str().unwrap_or_default(), "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        std::fs::read_to_string(&svg)
            .unwrap_or_default()
            .contains("hillshade")
    );
    let bad = dir.join("bad.asc");
    std::fs::write(
        &bad,
        "ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3\n4 five 6\n",
    )
    .expect("write");
    let target = dir.join("never.ron");
    check_error(
        &[
            "dem",
            bad.to_str().unwrap_or_default(),
            "--out",
            target.to_str().unwrap_or_default(),
        ],
        "bad.asc",
    );
    assert!(!target.exists());
}
