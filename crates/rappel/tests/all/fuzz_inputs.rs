//! The fuzz harness of the input edges (issue 9): property tests that feed the scenario loader
//! and the path-file reader malformed, truncated, byte-flipped and overflowing versions of real
//! fixtures, and assert that every outcome is clean: no panic, a typed error naming the file (or
//! a scenario that validates and plans), printable messages without raw bytes, no `-0`, and no
//! file left behind by a failed load. Bounded: a fixed number of cases per property on small maps
//! (about a second in a debug build); set `PROPTEST_CASES` to run longer.

use proptest::prelude::*;
use rappel::plan::PlanOptions;
use rappel::scenario::{Scenario, ScenarioError};
use std::path::PathBuf;

/// A small scenario in RON (one obstacle, two planes, a robot with a tether).
const RON: &str = r#"(
    name: "fuzz",
    map: (
        boundary: [(0.0, 0.0), (40.0, 0.0), (40.0, 60.0), (0.0, 60.0)],
        obstacles: [[(18.0, 30.0), (22.0, 30.0), (22.0, 34.0), (18.0, 34.0)]],
    ),
    start: (21.0, 58.0),
    goal: (20.0, 2.0),
    robot: (model: Point, tether_length_m: 80.0, clearance_m: 0.5),
    terrain: (planes: [
        (y_top: 60.0, y_bottom: 30.0, slope_deg: 40.0, friction: 0.4),
        (y_top: 30.0, y_bottom: 0.0, slope_deg: 50.0, friction: 0.4),
    ]),
)"#;

/// Extreme numbers spliced over numbers of the input.
const EXTREMES: [&str; 10] = [
    "1e308", "-1e308", "-1e151", "1e307", "1e-300", "NaN", "inf", "-0.0", "1e36", "5e-324",
];

/// The scenario as JSON.
fn json() -> String {
    Scenario::from_ron_str(RON)
        .expect("the fixture parses")
        .to_text(rappel::scenario::Format::Json)
}

/// Byte offsets of the numbers in `text` (start, end).
fn numbers(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        if b[i].is_ascii_digit() {
            let s = i;
            while i < b.len() && (b[i].is_ascii_digit() || b[i] == b'.') {
                i += 1;
            }
            out.push((s, i));
        } else {
            i += 1;
        }
    }
    out
}

/// Mutations of a text.
#[derive(Debug, Clone)]
pub(crate) enum Mutation {
    Truncate(usize),
    Flip(usize, u8),
    Number(usize, usize),
    Insert(usize, String),
}

pub(crate) fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        any::<usize>().prop_map(Mutation::Truncate),
        (any::<usize>(), any::<u8>()).prop_map(|(i, b)| Mutation::Flip(i, b)),
        (any::<usize>(), 0..EXTREMES.len()).prop_map(|(i, k)| Mutation::Number(i, k)),
        (
            any::<usize>(),
            prop::sample::select(vec![
                "obstacle: [], ",
                "extra: 1, ",
                "tether_length_m: Some(3.0), ",
                "[[[[[[[[[[[[[[[[",
                "\u{0}\u{1b}[31m",
                "\"",
                ")",
            ])
        )
            .prop_map(|(i, s)| Mutation::Insert(i, s.to_string())),
    ]
}

/// `text` with `m` applied, as bytes (a flip may make them invalid UTF-8).
pub(crate) fn apply(text: &str, m: &Mutation) -> Vec<u8> {
    let mut b = text.as_bytes().to_vec();
    match m {
        Mutation::Truncate(i) => b.truncate(i % (b.len() + 1)),
        Mutation::Flip(i, x) => {
            let i = i % b.len();
            b[i] ^= x | 1;
        }
        Mutation::Number(i, k) => {
            let nums = numbers(text);
            let (s, e) = nums[i % nums.len()];
            b.splice(s..e, EXTREMES[*k].bytes());
        }
        Mutation::Insert(i, s) => {
            let mut i = i % (b.len() + 1);
            while !text.is_char_boundary(i) {
                i -= 1;
            }
            b.splice(i..i, s.bytes());
        }
    }
    b
}

/// A fresh temporary directory for this test process.
pub(crate) fn temp_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("rappel-fuzz-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

/// The properties of one loaded (or refused) file.
fn check_load(file: &std::path::Path) -> Result<(), TestCaseError> {
    match Scenario::load(file) {
        Ok(s) => {
            // Valid: it must plan without a panic, with an error or an answer.
            let options = PlanOptions {
                classes: 2,
                stop: rappel::planners::stop::StopCondition::expansions(20_000),
                ..Default::default()
            };
            if let Err(e) = rappel::plan(&s, &options) {
                check_message(&e.to_string())?;
            }
        }
        Err(e) => {
            let text = e.to_string();
            check_message(&text)?;
            if !matches!(e, ScenarioError::Io { .. }) {
                prop_assert!(
                    text.starts_with(&file.display().to_string()),
                    "the error names the file: {text}"
                );
            }
        }
    }
    Ok(())
}

/// A message is one printable line: no control characters, no `-0`, no 300-digit numbers.
pub(crate) fn check_message(text: &str) -> Result<(), TestCaseError> {
    prop_assert!(!text.chars().any(char::is_control), "raw bytes: {text:?}");
    prop_assert!(
        !text.contains("recursion_limit"),
        "library internals: {text}"
    );
    let longest_digits = text
        .split(|c: char| !c.is_ascii_digit())
        .map(str::len)
        .max()
        .unwrap_or(0);
    prop_assert!(longest_digits < 40, "a huge integer: {text}");
    let bytes = text.as_bytes();
    for (i, _) in text.match_indices("-0") {
        let next = bytes.get(i + 2).copied();
        prop_assert!(
            next.is_some_and(|c| c == b'.' || c.is_ascii_digit())
                && !text[i..].starts_with("-0.0 ")
                && !text[i..].starts_with("-0.000"),
            "negative zero: {text}"
        );
    }
    Ok(())
}

proptest! {
    // A fixed seed: the same cases on every run (set PROPTEST_RNG_SEED to explore others).
    #![proptest_config(ProptestConfig {
        cases: 48,
        rng_seed: proptest::test_runner::RngSeed::Fixed(9),
        ..ProptestConfig::default()
    })]

    #[test]
    fn mutated_ron_scenarios_load_cleanly(m in mutation()) {
        let dir = temp_dir("ron");
        let file = dir.join("s.ron");
        std::fs::write(&file, apply(RON, &m)).expect("write");
        check_load(&file)?;
        // Loading never writes: the directory holds only the input.
        prop_assert_eq!(std::fs::read_dir(&dir).expect("dir").count(), 1);
    }

    #[test]
    fn mutated_json_scenarios_load_cleanly(m in mutation()) {
        let dir = temp_dir("json");
        let file = dir.join("s.json");
        std::fs::write(&file, apply(&json(), &m)).expect("write");
        check_load(&file)?;
        prop_assert_eq!(std::fs::read_dir(&dir).expect("dir").count(), 1);
    }

    #[test]
    fn mutated_path_files_are_read_cleanly(m in mutation()) {
        let s = Scenario::from_ron_str(RON).expect("fixture");
        let btm = rappel::geometry::btm::Btm::from_map(&s.map).expect("btm");
        let dir = temp_dir("path");
        let file = dir.join("p.json");
        std::fs::write(&file, apply("[[21.0, 58.0], [30.0, 32.0], [20.0, 2.0]]", &m)).expect("write");
        match rappel::tether::load_path(&file, &btm) {
            Ok(path) => {
                if let Err(e) = rappel::tether::shp_report(&btm, &path) {
                    check_message(&e.to_string())?;
                }
            }
            Err(e) => check_message(&e.to_string())?,
        }
    }

    /// Scaling a valid map by a power of ten inside the domain keeps it valid and keeps the
    /// same classes: results are invariant under the map's unit.
    #[test]
    fn scaling_the_map_keeps_its_plan(k in -6i32..=6) {
        let s = Scenario::from_ron_str(RON).expect("fixture");
        let f = 10f64.powi(k);
        let mut t = s.clone();
        for p in t.map.boundary.vertices.iter_mut().chain(t.map.obstacles.iter_mut().flat_map(|o| o.vertices.iter_mut())) {
            *p = (p.coords * f).into();
        }
        t.start = (t.start.coords * f).into();
        t.goal = (t.goal.coords * f).into();
        for p in &mut t.terrain.planes {
            p.y_top *= f;
            p.y_bottom *= f;
        }
        t.robot.tether_length_m = t.robot.tether_length_m.map(|l| l * f);
        t.robot.clearance_m *= f;
        prop_assert!(t.validate().is_ok(), "{:?}", t.validate());
        let options = PlanOptions { classes: 3, ..Default::default() };
        let (a, b) = (rappel::plan(&s, &options).expect("plan"), rappel::plan(&t, &options).expect("plan"));
        prop_assert_eq!(a.classes.len(), b.classes.len());
        for (x, y) in a.classes.iter().zip(&b.classes) {
            prop_assert!((x.length_m * f - y.length_m).abs() <= 1e-9 * y.length_m, "{} vs {}", x.length_m * f, y.length_m);
            prop_assert_eq!(x.feasible, y.feasible, "class {}: {} vs {}", x.rank, &x.verdict, &y.verdict);
        }
        prop_assert_eq!(a.outcome.chosen.is_some(), b.outcome.chosen.is_some());
    }
}

#[test]
fn the_issue_reproducers_give_named_outcomes() {
    let s = |from: &str, to: &str| Scenario::from_ron_str(&RON.replace(from, to));
    // A boundary vertex at -1e151: refused at validation with the domain named.
    let e = s("(0.0, 0.0), (40.0", "(-1e151, 0.0), (40.0")
        .expect("parses")
        .validate()
        .expect_err("refused");
    assert!(
        e.to_string().contains("outside the coordinate domain") && e.to_string().contains("-1e151"),
        "{e}"
    );
    // An obstacle vertex at 1e307: refused, no "free area -4.5e307".
    let e = s("(22.0, 30.0)", "(1e307, 24.0)")
        .expect("parses")
        .validate()
        .expect_err("refused");
    assert!(e.to_string().contains("1e307"), "{e}");
    // `obstacle:` for `obstacles:` is an error naming the field.
    let e = s("obstacles:", "obstacle:")
        .expect_err("refused")
        .to_string();
    assert!(e.contains("obstacle"), "{e}");
    // An unknown field inside a plane is an error.
    let e = s(
        "friction: 0.4),\n        (y_top: 30.0",
        "friction: 0.4, frictoin: 1.0),\n        (y_top: 30.0",
    )
    .expect_err("refused")
    .to_string();
    assert!(e.contains("frictoin"), "{e}");
    // The documented plain number for the tether.
    assert_eq!(
        s("tether_length_m: 80.0", "tether_length_m: 20.0")
            .expect("plain number")
            .robot
            .tether_length_m,
        Some(20.0)
    );
    // Slope 89.999 is refused by validate, as plan would refuse it.
    let e = s("slope_deg: 50.0", "slope_deg: 89.999")
        .expect("parses")
        .validate()
        .expect_err("refused");
    assert!(e.to_string().contains("89.999"), "{e}");
    // A 20 m tether makes every class (the shortest is ~56 m) infeasible with that reason.
    let t = s("tether_length_m: 80.0", "tether_length_m: 20.0").expect("parses");
    let r = rappel::plan(
        &t,
        &PlanOptions {
            classes: 2,
            ..Default::default()
        },
    )
    .expect("plan");
    assert!(r.outcome.chosen.is_none());
    assert!(
        r.classes
            .iter()
            .all(|c| !c.feasible && c.verdict.to_string().contains("20.00 m tether")),
        "{:?}",
        r.classes.iter().map(|c| &c.verdict).collect::<Vec<_>>()
    );
}

#[test]
fn stability_maps_name_their_robot_honour_the_tether_and_cap_their_poses() {
    use rappel::stability::{MAX_SCENARIO_POSES, StabilityOptions, stability_over_scenario};
    let s = Scenario::from_ron_str(&RON.replace("tether_length_m: 80.0", "tether_length_m: 20.0"))
        .expect("parses");
    let options = StabilityOptions {
        grid_step: 5.0,
        tension_limit: None,
        ..Default::default()
    };
    let r = stability_over_scenario(s.validate().expect("valid scenario"), &options).expect("map");
    assert!(
        r.stand_in_for.is_some(),
        "a point robot is judged by a stand-in, said so"
    );
    // Reference from the input: a pose farther than 20 m from the start (straight-line distance is
    // a lower bound of the taut tether) is beyond reach; every pose within 20 m in plain view is not.
    for d in &r.dots {
        let straight = (d.point - s.start).norm();
        if straight > 20.0 {
            assert!(d.beyond_tether && !d.stable, "{d:?}");
        }
    }
    assert!(r.dots.iter().any(|d| !d.beyond_tether));
    // Each position once, even on the edge between the planes (y = 30 is on both planes' 5 m grid).
    let mut seen = std::collections::HashSet::new();
    assert!(
        r.dots
            .iter()
            .all(|d| seen.insert((d.point.x.to_bits(), d.point.y.to_bits())))
    );
    assert!(
        r.dots
            .iter()
            .any(|d| d.point.y == 30.0 + 2.0 || d.point.y == 30.0 || d.point.y == 28.0)
    );
    let fine = StabilityOptions {
        grid_step: 0.05,
        tension_limit: None,
        ..Default::default()
    };
    let e = stability_over_scenario(s.validate().expect("valid scenario"), &fine)
        .expect_err("capped")
        .to_string();
    assert!(e.contains(&MAX_SCENARIO_POSES.to_string()), "{e}");
    // Far over the mechanics' own cap too: the message still names the limit enforced here.
    let finest = StabilityOptions {
        grid_step: 0.0005,
        ..fine
    };
    let e = stability_over_scenario(s.validate().expect("valid scenario"), &finest)
        .expect_err("capped")
        .to_string();
    assert!(
        e.contains(&format!("the limit {MAX_SCENARIO_POSES}")) && !e.contains("10000000"),
        "{e}"
    );
}
