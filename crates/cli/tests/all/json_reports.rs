//! One output schema (`docs/output-format.md`): every subcommand's `--json` report, as the binary
//! prints it, starts with `schema_version` and `report`, reads back into its report type, and
//! prints again to the same text (serialize, deserialize, serialize again equal); and nowhere in
//! it is there an upper-case enum value, a point written as an object with `x` and `y`, or an
//! angle field without its unit.

use crate::common;

use common::{fixture, rappel, stderr, stdout, temp_dir};
use rappel::report::{Report, read_report};

/// Runs `args` (which include `--json`), checks the exit code is 0 or 1 (a clean "no" is a
/// report too), reads the report back as `T` and prints it again: the same text.
fn round_trip<T: Report>(args: &[&str]) -> serde_json::Value {
    let o = rappel(args);
    assert!(
        matches!(o.status.code(), Some(0 | 1)),
        "{args:?}: {}",
        stderr(&o)
    );
    let text = stdout(&o);
    let report: T = read_report(&text).unwrap_or_else(|e| panic!("{args:?}: {e}\n{text}"));
    assert_eq!(
        report.to_json(),
        text.trim_end(),
        "{args:?}: not the same text once read back"
    );
    let head = format!(
        "{{\n  \"schema_version\": 1,\n  \"report\": \"{}\",",
        T::KIND
    );
    assert!(text.starts_with(&head), "{args:?}: {text:.80}");
    let v: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    check_convention(&v, T::KIND);
    v
}

/// The convention, checked on every value: enum-like strings are lower-case, points are arrays,
/// and no field is named after an angle without `_deg`.
fn check_convention(v: &serde_json::Value, at: &str) {
    match v {
        serde_json::Value::Object(m) => {
            assert!(
                !(m.contains_key("x") && m.contains_key("y")),
                "{at}: a point written as an object: {v}"
            );
            for (k, x) in m {
                for bare in ["heading", "turning_angle", "total_winding", "psi", "turn"] {
                    assert_ne!(k, bare, "{at}: angle field {k} without its unit");
                }
                assert!(
                    !["free_area", "build_ms", "length", "tension_limit"].contains(&k.as_str()),
                    "{at}: field {k} without its unit"
                );
                check_convention(x, &format!("{at}.{k}"));
            }
        }
        serde_json::Value::Array(a) => a.iter().for_each(|x| check_convention(x, at)),
        // Enum values: a single word in CamelCase would be a Rust name.
        serde_json::Value::String(s) if !s.contains(' ') && !s.contains('/') => {
            let camel = s.len() > 1
                && s.chars().next().is_some_and(|c| c.is_ascii_uppercase())
                && s.chars().skip(1).any(|c| c.is_ascii_lowercase())
                && s.chars().all(|c| c.is_ascii_alphanumeric());
            assert!(!camel, "{at}: Rust-style enum value {s:?}");
        }
        _ => {}
    }
}

#[test]
fn validate_btm_shp_homotopic_and_query_reports_round_trip() {
    let map = fixture("thesis-fig-2-7.ron");
    let v = round_trip::<rappel::input_kind::ValidateReport>(&["validate", &map, "--json"]);
    assert!(v["free_area_m2"].as_f64().unwrap() > 0.0);
    let v = round_trip::<rappel::btm_summary::BtmSummary>(&["btm", &map, "--json"]);
    assert!(v["build_us"].is_u64());
    let west = fixture("paths/fig-2-7-west.json");
    let east = fixture("paths/fig-2-7-east.json");
    let v = round_trip::<rappel::tether::ShpReport>(&["shp", &map, "--path", &west, "--json"]);
    assert!(v["anchors"][0]["turning_angle_deg"].as_f64().unwrap() > 0.0);
    round_trip::<rappel::report::HomotopicReport>(&[
        "homotopic",
        &map,
        "--path",
        &west,
        "--path",
        &east,
        "--json",
    ]);
    let pairs = fixture("queries/fig-2-7-pairs.json");
    let v = round_trip::<rappel::query::QueryReport>(&["query", &map, "--pairs", &pairs, "--json"]);
    assert!(v["answers"][0]["median_ns"].is_u64());
}

#[test]
fn plan_reports_round_trip_with_snake_case_termination() {
    let v = round_trip::<rappel::plan::PlanReport>(&[
        "plan",
        &fixture("plan/golden-queen-two-anchors.ron"),
        "--classes",
        "3",
        "--json",
    ]);
    assert_eq!(v["termination"], "class_count");
    assert!(matches!(
        v["classes"][0]["anchors"][0]["side"].as_str(),
        Some("left" | "right")
    ));
    let v = round_trip::<rappel::plan::PlanReport>(&[
        "plan",
        &fixture("friction/capstan_holds.ron"),
        "--json",
    ]);
    assert!(v["friction"]["tensions"]["t_max_n"].as_f64().is_some());
}

#[test]
fn stability_online_track_settle_and_dem_reports_round_trip() {
    let v = round_trip::<rappel::stability::StabilityReport>(&[
        "stability",
        &fixture("online-example.ron"),
        "--grid",
        "8",
        "--tension-limit",
        "300",
        "--json",
    ]);
    let dot = &v["dots"][0];
    assert_eq!(dot["point"].as_array().map(Vec::len), Some(2));
    assert!(dot["heading_deg"].is_number());
    round_trip::<rappel::online::OnlineReport>(&[
        "online",
        &fixture("online-example.ron"),
        "--truth",
        &fixture("online-example-discovered.ron"),
        "--json",
    ]);
    let v = round_trip::<rappel::track::TrackReport>(&[
        "track",
        &fixture("tracking/kumar.json"),
        "--robot1",
        &fixture("tracking/robot1-nearly-full-turn.json"),
        "--robot2",
        &fixture("tracking/robot2-descent.json"),
        "--json",
    ]);
    assert_eq!(v["waypoints"][0]["configuration"][0]["kind"], "robot");
    round_trip::<rappel::settle::SettleReport>(&[
        "settle",
        &fixture("paton/ledge.ron"),
        "--at",
        "-1,0",
        "--yaw",
        "0",
        "--anchor",
        "-3,0,4.5",
        "--json",
    ]);
    let dir = temp_dir("json-dem");
    let out = dir.join("mars.ron");
    let v = round_trip::<rappel::dem::DemReport>(&[
        "dem",
        &fixture("terrain/mars_hirise_dteec_010228_1490_crop.asc"),
        "--out",
        out.to_str().unwrap_or_default(),
        "--json",
    ]);
    // What the text shows is in the JSON too: the fall line and each plane with its class.
    assert!(v["fall_line_azimuth_deg"].is_number());
    let planes = v["planes"].as_array().expect("planes");
    assert_eq!(Some(planes.len() as u64), v["counts"]["planes"].as_u64());
    assert!(
        planes
            .iter()
            .all(|p| matches!(p["class"].as_str(), Some("tether_free" | "tether_demand")))
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn plan_and_stability_write_html_and_honour_a_window() {
    let dir = temp_dir("window");
    let (svg, html) = (dir.join("p.svg"), dir.join("p.html"));
    let file = fixture("plan/shortest-infeasible.ron");
    let o = rappel(&[
        "plan",
        &file,
        "--svg",
        svg.to_str().unwrap_or_default(),
        "--html",
        html.to_str().unwrap_or_default(),
        "--window",
        "30,30,70,95",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let picture = std::fs::read_to_string(&svg).expect("svg");
    // The map viewport frames the window (padded 2%), not the whole map (x from 0).
    let start = picture.find("<svg id=\"rappel-map\"").expect("viewport");
    let tag = &picture[start..start + picture[start..].find('>').unwrap()];
    let vb = &tag[tag.find("viewBox=\"").unwrap() + 9..];
    let min_x: f64 = vb.split(' ').next().unwrap().parse().unwrap();
    assert!((min_x - (30.0 - 0.02 * 65.0)).abs() < 1e-6, "{tag}");
    for needle in [
        "infeasible class (SHP)",
        "blocking anchor",
        "blocks the ascent",
    ] {
        assert!(picture.contains(needle), "missing {needle}");
    }
    assert!(
        std::fs::read_to_string(&html)
            .expect("html")
            .contains("<svg")
    );
    // A bad window is one error line, exit 2.
    let o = rappel(&[
        "plan",
        &file,
        "--svg",
        svg.to_str().unwrap_or_default(),
        "--window",
        "3,0,1",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--window 3,0,1"), "{}", stderr(&o));
    let o = rappel(&[
        "stability",
        &fixture("online-example.ron"),
        "--grid",
        "8",
        "--tension-limit",
        "300",
        "--html",
        html.to_str().unwrap_or_default(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let page = std::fs::read_to_string(&html).expect("html");
    assert!(page.contains("stability margin") && page.contains("stable pose"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn gen_map_and_settle_map_reports_round_trip() {
    let dir = temp_dir("json-gen-map");
    let out = dir.join("strip.ron");
    let v = round_trip::<rappel::report::GenMapReport>(&[
        "gen-map",
        "--obstacles",
        "12",
        "--seed",
        "3",
        "--out",
        out.to_str().unwrap_or_default(),
        "--json",
    ]);
    assert_eq!(v["obstacles"], 12);
    assert!(out.exists());
    let ledge = fixture("paton/ledge.ron");
    let v = round_trip::<rappel::planners::rover::stability_map::StabilityMap>(&[
        "settle-map",
        &ledge,
        "--test",
        "1",
        "--x",
        "-3,1.5",
        "--y",
        "-0.5,0.5",
        "--step",
        "0.5",
        "--json",
    ]);
    assert!(v["cells"][0]["ground"].is_array());
}
