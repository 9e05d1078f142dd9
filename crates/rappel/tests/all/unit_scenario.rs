//! The scenario file's parsing and validation through the public API: RON and JSON round trips,
//! parse errors with their line and column, and semantic errors naming the problem.

use rappel::scenario::{Format, Scenario, ScenarioError};

const TINY: &str = r#"(
    map: (
        boundary: [(0.0, 0.0), (10.0, 0.0), (10.0, 20.0), (0.0, 20.0)],
        obstacles: [[(4.0, 8.0), (6.0, 8.0), (5.0, 10.0)]],
    ),
    start: (5.0, 19.0),
    goal: (5.0, 1.0),
    terrain: (planes: [(y_top: 20.0, y_bottom: 0.0, slope_deg: 45.0, friction: 0.4)]),
)"#;

#[test]
fn ron_and_json_round_trip_to_the_same_scenario() {
    let s = Scenario::from_ron_str(TINY).unwrap();
    s.validate().unwrap();
    let json = s.to_text(Format::Json);
    assert_eq!(Scenario::from_json_str(&json).unwrap(), s);
    assert_eq!(Scenario::from_ron_str(&s.to_text(Format::Ron)).unwrap(), s);
}

#[test]
fn parse_errors_carry_line_and_column() {
    let broken = TINY.replace("goal: (5.0, 1.0)", "goal: (5.0, 1.0 oops)");
    match Scenario::from_ron_str(&broken) {
        Err(ScenarioError::Parse { line, .. }) => assert_eq!(line, 7),
        other => panic!("expected a parse error, got {other:?}"),
    }
    match Scenario::from_json_str("{\n  \"map\": 3\n}") {
        Err(ScenarioError::Parse { line, column, .. }) => assert_eq!((line, column), (2, 10)), // the `3`: two spaces, "map", colon, space
        other => panic!("expected a parse error, got {other:?}"),
    }
    let typo = TINY.replace("goal:", "gaol:");
    assert!(matches!(
        Scenario::from_ron_str(&typo),
        Err(ScenarioError::Parse { .. })
    ));
}

#[test]
fn semantic_errors_name_the_problem() {
    let s = Scenario::from_ron_str(&TINY.replace("goal: (5.0, 1.0)", "goal: (5.0, 9.0)")).unwrap();
    let e = s.validate().unwrap_err().to_string();
    assert!(e.contains("goal point (5, 9) is inside obstacle 0"), "{e}");
    let s = Scenario::from_ron_str(&TINY.replace("slope_deg: 45.0", "slope_deg: 95.0")).unwrap();
    assert!(matches!(
        s.validate(),
        Err(ScenarioError::Plane { plane: 0, .. })
    ));
}
