//! End-to-end tests of `rappel shp` and `rappel homotopic` on the thesis Fig. 2.7 fixture.

use crate::common;

use common::{rappel, stderr, stdout};
use std::path::{Path, PathBuf};

fn fixture() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/thesis-fig-2-7.ron")
        .display()
        .to_string()
}

/// Writes path files into a fresh temporary directory.
fn path_files(tag: &str, paths: &[(&str, &str)]) -> (PathBuf, Vec<String>) {
    let d = std::env::temp_dir().join(format!("rappel-shp-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    let files = paths
        .iter()
        .map(|(name, json)| {
            let f = d.join(name);
            std::fs::write(&f, json).expect("write path file");
            f.display().to_string()
        })
        .collect();
    (d, files)
}

/// Down the west side of obstacles 3 and 6, then east of obstacle 7's west end.
const WEST: &str = "[[31, 98], [30, 70], [20, 68], [20, 40], [38, 36], [38, 10], [33, 4]]";
/// The same class, drawn differently.
const WEST2: &str = "[[31, 98], [22, 72], [21, 50], [36, 37], [37, 8], [33, 4]]";
/// Down the east edge of the plane.
const EAST: &str = "[[31, 98], [56, 90], [58, 30], [55, 8], [33, 4]]";

#[test]
fn shp_json_reports_a_taut_tether_no_longer_than_the_path() {
    let (dir, files) = path_files("json", &[("west.json", WEST)]);
    let svg = dir.join("shp.svg");
    let o = rappel(&[
        "shp",
        &fixture(),
        "--path",
        &files[0],
        "--json",
        "--svg",
        svg.to_str().unwrap_or_default(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    let (len, path_len) = (
        v["length_m"].as_f64().unwrap(),
        v["path_length_m"].as_f64().unwrap(),
    );
    assert!(len > 0.0 && len < path_len);
    let anchors = v["anchors"].as_array().unwrap();
    assert!(!anchors.is_empty());
    assert!(anchors.iter().all(|a| a["obstacle"].is_u64()));
    // One schema: angles in degrees in (0, 180), lower-case sides, points as [x, y].
    assert!(anchors.iter().all(|a| {
        let t = a["turning_angle_deg"].as_f64().unwrap();
        t > 0.0 && t < 180.0 && (a["side"] == "left" || a["side"] == "right")
    }));
    assert!(
        anchors
            .iter()
            .all(|a| a["point"].as_array().map(Vec::len) == Some(2))
    );
    assert_eq!(v["schema_version"], 1);
    assert_eq!(v["points"].as_array().unwrap().len(), anchors.len() + 2);
    assert!(v["reduced_crossings"].as_u64().unwrap() <= v["crossings"].as_u64().unwrap());
    assert_eq!(v["h_signature"]["digest"].as_str().unwrap().len(), 16);
    let picture = std::fs::read_to_string(&svg).expect("svg written");
    for needle in ["sleeve", "taut tether (SHP)", "anchor", "BTM edge", "path"] {
        assert!(picture.contains(needle), "missing {needle}");
    }
    // The table names the anchors.
    let o = rappel(&["shp", &fixture(), "--path", &files[0]]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        out.contains("SHP length") && out.contains("anchors"),
        "{out}"
    );
}

#[test]
fn homotopic_answers_yes_with_exit_zero_and_no_with_exit_one() {
    let (_, files) = path_files(
        "homotopic",
        &[("w.json", WEST), ("w2.json", WEST2), ("e.json", EAST)],
    );
    for (a, b, expected, code) in [(0, 1, "homotopic", 0), (0, 2, "not homotopic", 1)] {
        let o = rappel(&[
            "homotopic",
            &fixture(),
            "--path",
            &files[a],
            "--path",
            &files[b],
        ]);
        assert_eq!(o.status.code(), Some(code), "{}", stderr(&o));
        assert_eq!(String::from_utf8_lossy(&o.stdout).trim(), expected);
    }
}

#[test]
fn bad_paths_exit_two_naming_the_segment_or_position() {
    let (_, files) = path_files(
        "bad",
        &[
            ("through.json", "[[31, 98], [31, 70], [31, 4]]"),
            ("garbled.json", "[[31, 98], [31 70]]"),
            ("west.json", WEST),
            ("short.json", "[[31, 98], [30, 70]]"),
        ],
    );
    for (args, expected) in [
        (vec!["shp", &fixture(), "--path", &files[0]], "segment 1"),
        (
            vec!["shp", &fixture(), "--path", &files[1]],
            "garbled.json:1:",
        ),
        (
            vec![
                "homotopic",
                &fixture(),
                "--path",
                &files[2],
                "--path",
                &files[3],
            ],
            "do not share their endpoints",
        ),
        (
            vec!["homotopic", &fixture(), "--path", &files[2]],
            "exactly two",
        ),
    ] {
        let o = rappel(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        let err = stderr(&o);
        let lines: Vec<_> = err.lines().collect();
        assert_eq!(lines.len(), 1, "{err}");
        assert!(
            lines[0].starts_with("error: ") && lines[0].contains(expected),
            "{err}"
        );
    }
}

/// The shipped path files (README examples): two paths west of the central obstacles, one a
/// detour of the other with no obstacle between them, and one east of them.
#[test]
fn shipped_path_files_answer_homotopic_in_text_and_json() {
    let map = fixture();
    let path = |name: &str| common::fixture(&format!("paths/fig-2-7-{name}.json"));
    let (west, detour, east) = (path("west"), path("west-detour"), path("east"));
    let run = rappel(&[
        "homotopic",
        &map,
        "--path",
        &west,
        "--path",
        &detour,
        "--json",
    ]);
    assert_eq!(run.status.code(), Some(0), "{}", stderr(&run));
    let json: serde_json::Value = serde_json::from_str(&stdout(&run)).expect("JSON");
    assert_eq!(json["homotopic"], true);
    assert_eq!(json["reduced_crossings"][0], json["reduced_crossings"][1]);
    let run = rappel(&[
        "homotopic",
        &map,
        "--path",
        &west,
        "--path",
        &east,
        "--json",
    ]);
    assert_eq!(run.status.code(), Some(1), "{}", stderr(&run));
    let json: serde_json::Value = serde_json::from_str(&stdout(&run)).expect("JSON");
    assert_eq!(json["homotopic"], false);
    let run = rappel(&["validate", &map, "--json"]);
    assert_eq!(run.status.code(), Some(0));
    let json: serde_json::Value = serde_json::from_str(&stdout(&run)).expect("JSON");
    assert_eq!(json["obstacles"], 7);
    assert_eq!(json["valid"], true);
}
