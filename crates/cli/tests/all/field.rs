//! `--field RES` on `rappel settle`, `settle-map` and `navigate` (one shared flag,
//! `crates/cli/src/field_arg.rs`): the JSON reports state the distance source; settling through
//! the field agrees with the exact path within the field's error bound; navigate's path through
//! the field is re-validated on the exact mesh; bad resolutions exit 2 with one `error:` line
//! naming the flag and the value.

use crate::common;

use common::*;

fn json(args: &[&str]) -> serde_json::Value {
    let o = rappel(args);
    assert_eq!(o.status.code(), Some(0), "{args:?}: {}", stderr(&o));
    serde_json::from_slice(&o.stdout).expect("JSON")
}

fn f(v: &serde_json::Value) -> f64 {
    v.as_f64().unwrap_or(f64::NAN)
}

/// `settle --field 0.1` against the exact path on poses of both ledge scenes: same settled
/// origin within the field's stated error bound, the report naming the source.
#[test]
fn settle_through_the_field_agrees_with_the_exact_path() {
    for scene in ["paton/ledge.ron", "paton/ledge-pole.ron"] {
        let file = fixture(scene);
        // On the top, mid-slope, 1.3 m from the pole, on the ground past the foot, with yaws.
        for (at, yaw) in [
            ("-1,0", "0"),
            ("1.4,0.5", "0"),
            ("-1.6,-0.9", "30"),
            ("3.5,-2", "200"),
        ] {
            let base = ["settle", file.as_str(), "--at", at, "--yaw", yaw, "--json"];
            let exact = json(&base);
            let mut args = base.to_vec();
            args.extend(["--field", "0.1"]);
            let field = json(&args);
            assert_eq!(exact["distance_source"]["source"], "exact");
            assert_eq!(field["distance_source"]["source"], "field");
            assert_eq!(f(&field["distance_source"]["resolution_m"]), 0.1);
            let bound = f(&field["distance_source"]["error_bound_m"]);
            // sqrt(3)/2 h + 0.25 h (docs/mesh.md) plus f32 rounding.
            assert!(bound > 0.11 && bound < 0.12, "{bound}");
            for k in 0..3 {
                let (e, g) = (f(&exact["origin"][k]), f(&field["origin"][k]));
                assert!((e - g).abs() <= bound, "{scene} {at}: {e} vs {g}");
            }
        }
    }
}

/// `navigate --field 0.1` on the test-1 ledge: the planner's checks read the field, the path it
/// reports passes re-validation on the exact mesh (`found` is only true then) and anchors on the
/// lip.
#[test]
fn navigate_through_the_field_finds_a_revalidated_path() {
    let ledge = fixture("paton/ledge.ron");
    // Seed 2 finds the straight descent at once on the exact path (tests/navigate.rs).
    let run = |extra: &[&str]| {
        let mut args = vec!["navigate", ledge.as_str(), "--seed", "2", "--json"];
        args.extend(["--iterations", "60"]);
        args.extend(extra);
        json(&args)
    };
    let v = run(&["--field", "0.1"]);
    assert_eq!(v["found"], true, "{v}");
    assert!(v["unsafe_reason"].is_null());
    assert_eq!(v["distance_source"]["source"], "field");
    assert_eq!(f(&v["distance_source"]["resolution_m"]), 0.1);
    let anchors = v["anchors"].as_array().expect("anchors");
    assert_eq!(anchors.len(), 2, "{v}");
    assert!(f(&anchors[1][0]).abs() < 0.1 && (f(&anchors[1][2]) - 4.0).abs() < 0.1);
    assert!(f(&v["min_margin_n"]) >= 0.0);
    assert_eq!(run(&[])["distance_source"]["source"], "exact");
}

/// The map states its source.
#[test]
fn settle_map_states_its_distance_source() {
    let ledge = fixture("paton/ledge.ron");
    let mut args = vec!["settle-map", ledge.as_str(), "--test", "1", "--json"];
    args.extend(["--x", "-1.5,0.5", "--y", "-0.5,0.5", "--step", "0.5"]);
    assert_eq!(json(&args)["distance_source"]["source"], "exact");
    args.extend(["--field", "0.2"]);
    let v = json(&args);
    assert_eq!(v["distance_source"]["source"], "field");
    assert_eq!(f(&v["distance_source"]["resolution_m"]), 0.2);
}

/// Zero, negative, NaN, infinite and too-fine resolutions: exit 2, one `error:` line naming
/// `--field` and the value, on every command that takes the flag.
#[test]
fn bad_field_resolutions_name_the_flag_and_the_value() {
    let ledge = fixture("paton/ledge.ron");
    let commands: [Vec<&str>; 3] = [
        vec!["settle", &ledge, "--at", "-1,0", "--yaw", "0"],
        vec!["settle-map", &ledge, "--test", "1", "--step", "0.5"],
        vec!["navigate", &ledge, "--seed", "0", "--iterations", "5"],
    ];
    for cmd in &commands {
        for (value, named, why) in [
            ("0", "--field 0:", "positive, finite"),
            ("-0.1", "--field -0.1:", "positive, finite"),
            // Refused by the option's parser, which names the option.
            ("NaN", "'NaN' for '--field <RES>'", "not a finite number"),
            ("inf", "'inf' for '--field <RES>'", "not a finite number"),
            ("1e300", "--field 1e300:", "positive, finite"),
            // 1 mm over the ledge scene's 44 x 44 x 8 m box: over the block index's cap.
            ("0.001", "--field 0.001:", "cannot build the distance field"),
        ] {
            let mut args = cmd.clone();
            args.extend(["--field", value]);
            check_error(&args, named);
            check_error(&args, why);
        }
    }
}
