//! End-to-end tests of `rappel plan` on the plan fixtures: the table, the JSON report, the
//! picture, and one-line errors with exit code 2.

use crate::common;

use common::*;

#[test]
fn the_table_lists_classes_and_the_chosen_pair() {
    let o = rappel(&[
        "plan",
        &fixture("plan/shortest-infeasible.ron"),
        "--classes",
        "2",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    assert!(out.contains("class 1 "), "{out}");
    assert!(out.contains("no visibility edge: psi 33.69°"), "{out}");
    assert!(out.contains("class 2 "), "{out}");
    assert!(
        out.contains("verdict      class 2 is the shortest feasible class"),
        "{out}"
    );
    assert!(out.contains("ascent ") && out.contains("descent "), "{out}");
    assert!(out.contains("waypoints"), "{out}");
}

#[test]
fn json_and_svg_report_the_plan() {
    let dir = temp_dir("json");
    let svg = dir.join("plan.svg");
    let o = rappel(&[
        "plan",
        &fixture("plan/golden-queen-two-anchors.ron"),
        "--classes",
        "3",
        "--max-length-factor",
        "1.5",
        "--json",
        "--svg",
        svg.to_str().unwrap_or_default(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    let classes = v["classes"].as_array().expect("classes");
    assert_eq!(classes.len(), 3);
    assert_eq!(classes[0]["anchors"].as_array().map(Vec::len), Some(2));
    assert_eq!(classes[0]["feasible"], true);
    assert_eq!(v["chosen"]["rank"], 1);
    assert!(v["chosen"]["min_anchor_distance_m"].as_f64().unwrap() >= 0.5 * (1.0 - 1e-9));
    let lengths: Vec<f64> = classes
        .iter()
        .map(|c| c["length_m"].as_f64().unwrap())
        .collect();
    assert!(lengths.windows(2).all(|w| w[0] <= w[1]));
    let picture = std::fs::read_to_string(&svg).expect("picture written");
    for label in [
        "sleeve",
        "friction cone",
        "taut tether (SHP)",
        "anchor",
        "waypoint",
        "ascent path",
        "descent path",
        "visibility line",
    ] {
        assert!(picture.contains(label), "legend lacks {label}");
    }
}

#[test]
fn no_feasible_class_is_a_clean_no_with_the_reason() {
    let o = rappel(&["plan", &fixture("plan/none-feasible.ron"), "--simple-only"]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(
        stderr(&o).is_empty(),
        "a clean no is not an error: {}",
        stderr(&o)
    );
    let out = stdout(&o);
    assert!(
        out.contains("classes      2 (no further class exists"),
        "{out}"
    );
    assert!(
        out.contains("verdict      no feasible class among the 2 found"),
        "{out}"
    );
    assert!(out.contains("cannot hold the robot at the goal"), "{out}");
}

#[test]
fn bad_options_are_one_error_line_with_exit_2() {
    for (args, expected) in [
        (vec!["--classes", "0"], "--classes 0"),
        (
            vec!["--max-length-factor", "0.5"],
            "--max-length-factor 0.5",
        ),
    ] {
        let mut all = vec!["plan".to_string(), fixture("plan/multi-plane.ron")];
        all.extend(args.iter().map(ToString::to_string));
        let refs: Vec<&str> = all.iter().map(String::as_str).collect();
        let o = rappel(&refs);
        assert_eq!(o.status.code(), Some(2));
        let err = stderr(&o);
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(
            err.starts_with("error: ") && err.contains(expected),
            "{err}"
        );
    }
    let o = rappel(&["plan", "no-such-file.ron"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).starts_with("error: no-such-file.ron"));
}

#[test]
fn the_readme_main_job_writes_into_a_missing_directory() {
    let dir = temp_dir("readme");
    let out = dir.join("out").join("default.svg");
    let o = rappel(&[
        "plan",
        &fixture("thesis-fig-2-7.ron"),
        "--svg",
        out.to_str().unwrap_or_default(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("verdict      class 1 is the shortest feasible class"));
    assert!(
        std::fs::read_to_string(&out)
            .expect("written")
            .starts_with("<svg")
    );
}

#[test]
fn a_feasible_plan_exits_zero_and_output_limits_hold() {
    let o = rappel(&["plan", &fixture("plan/garni-straight.ron")]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    check_error(
        &[
            "plan",
            &fixture("plan/garni-straight.ron"),
            "--classes",
            "1000000000",
        ],
        "at most 1000 classes",
    );
    // An exhausted budget is said as such, never as "disconnected".
    let o = rappel(&[
        "plan",
        &fixture("thesis-fig-2-7.ron"),
        "--max-expansions",
        "3",
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let out = stdout(&o);
    assert!(
        out.contains(
            "the search stopped at the given budget of 3 expansions; raise --max-expansions"
        ),
        "{out}"
    );
    assert!(!out.contains("different connected components"), "{out}");
    // The default budget follows the map and names itself when it stops a search; `auto` and
    // a number are the values, anything else an error naming the flag.
    let o = rappel(&[
        "plan",
        &fixture("thesis-fig-2-7.ron"),
        "--max-expansions",
        "auto",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        stdout(&o).contains("of 1000000 expansions"),
        "{}",
        stdout(&o)
    );
    check_error(
        &[
            "plan",
            &fixture("thesis-fig-2-7.ron"),
            "--max-expansions",
            "lots",
        ],
        "--max-expansions",
    );
}

#[test]
fn write_errors_on_stdout_are_errors() {
    let Ok(full) = std::fs::OpenOptions::new().write(true).open("/dev/full") else {
        return; // no /dev/full on this system: nothing to check
    };
    for args in [
        vec!["validate", "thesis-fig-2-7.ron"],
        vec!["btm", "thesis-fig-2-7.ron"],
        vec!["plan", "plan/garni-straight.ron"],
    ] {
        let mut args: Vec<String> = args.iter().map(|s| s.to_string()).collect();
        args[1] = fixture(&args[1]);
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_rappel"))
            .args(&args)
            .stdout(full.try_clone().expect("dup"))
            .output()
            .expect("runs");
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(
            stderr(&o).contains("cannot write to standard output"),
            "{}",
            stderr(&o)
        );
    }
}

#[test]
fn an_output_path_equal_to_the_input_is_refused_before_writing() {
    let dir = temp_dir("same");
    let input = dir.join("s.ron");
    std::fs::copy(fixture("thesis-fig-2-7.ron"), &input).expect("copy");
    let before = std::fs::read(&input).expect("read");
    let i = input.display().to_string();
    let dotted = dir.join(".").join("s.ron").display().to_string();
    for sub in ["btm", "plan", "stability"] {
        check_error(
            &[sub, &i, "--svg", &dotted],
            "would overwrite the input file",
        );
    }
    assert_eq!(std::fs::read(&input).expect("read"), before);
}

#[test]
fn plan_exports_geojson_and_csv_and_refuses_unknown_or_clashing_outputs() {
    let dir = temp_dir("plan-export");
    let input = fixture("thesis-fig-2-7.ron");
    let geojson = dir.join("plan.geojson");
    let g = geojson.to_str().unwrap_or_default();
    let run = rappel(&["plan", &input, "--export", g]);
    assert_eq!(run.status.code(), Some(0), "{}", stderr(&run));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&geojson).expect("written")).expect("JSON");
    assert_eq!(json["type"], "FeatureCollection");
    // Not made from a DEM: planning-frame coordinates, said so.
    assert!(
        json["rappel_frame"]
            .as_str()
            .unwrap_or_default()
            .starts_with("planning frame")
    );
    let layers: Vec<&str> = json["features"]
        .as_array()
        .expect("features")
        .iter()
        .filter_map(|f| f["properties"]["layer"].as_str())
        .collect();
    for l in ["tether", "ascent", "descent", "start", "goal"] {
        assert!(layers.contains(&l), "{l}");
    }
    let csv = dir.join("plan.csv");
    let run = rappel(&["plan", &input, "--export", csv.to_str().unwrap_or_default()]);
    assert_eq!(run.status.code(), Some(0), "{}", stderr(&run));
    let text = std::fs::read_to_string(&csv).expect("csv");
    assert!(text.starts_with("layer,class,index,x,y,psi_deg,obstacle\n"));
    // Anchors keep their attributes; classes are integer ranks.
    for row in text.lines().skip(1) {
        let cells: Vec<&str> = row.split(',').collect();
        assert_eq!(cells.len(), 7, "{row}");
        assert!(
            cells[1].is_empty() || cells[1].parse::<usize>().is_ok(),
            "{row}"
        );
        if cells[0] == "anchor" {
            assert!(cells[5].parse::<f64>().is_ok(), "{row}");
        }
    }
    check_error(
        &["plan", &input, "--export", "plan.txt"],
        "unknown format; use a .fgb, .geojson or .csv file",
    );
    check_error(
        &["plan", &input, "--export", g, "--svg", g],
        "the same file",
    );
}

#[test]
fn query_answers_the_shipped_pairs_and_names_a_bad_pair() {
    let map = fixture("thesis-fig-2-7.ron");
    let pairs = fixture("queries/fig-2-7-pairs.json");
    let run = rappel(&["query", &map, "--pairs", &pairs, "--classes", "2", "--json"]);
    assert_eq!(run.status.code(), Some(0), "{}", stderr(&run));
    let json: serde_json::Value = serde_json::from_str(&stdout(&run)).expect("JSON");
    assert_eq!(json["report"], "query");
    let answers = json["answers"].as_array().expect("answers");
    assert_eq!(answers.len(), 3);
    assert!(
        answers
            .iter()
            .all(|a| a["lengths_m"].as_array().map(Vec::len) == Some(2))
    );
    let dir = temp_dir("query-bad");
    let bad = dir.join("pairs.json");
    std::fs::write(
        &bad,
        r#"[{"start": [31.0, 98.0], "goal": [33.0, 4.0]}, {"start": [31.0, 98.0], "goal": [500.0, 4.0]}]"#,
    )
    .expect("write");
    check_error(
        &["query", &map, "--pairs", bad.to_str().unwrap_or_default()],
        "pair 1:",
    );
    check_error(
        &["query", &map, "--pairs", &pairs, "--repeat", "0"],
        "--repeat 0",
    );
    // A budget that stops a pair's search is named with the flag that raises it, for one class
    // (the path alone) and for several.
    for classes in ["1", "2"] {
        check_error(
            &[
                "query",
                &map,
                "--pairs",
                &pairs,
                "--classes",
                classes,
                "--max-expansions",
                "3",
            ],
            "the search stopped at the given budget of 3 expansions; raise --max-expansions",
        );
    }
}
