//! The `builder` module's tests (moved out of the source file: the facade's sources hold the
//! code only).
use rappel::builder::*;
use rappel::scenario::{Scenario, ScenarioError};

fn square() -> ScenarioBuilder {
    Scenario::builder().boundary([[0.0, 0.0], [10.0, 0.0], [10.0, 20.0], [0.0, 20.0]])
}

#[test]
fn a_built_scenario_equals_the_same_scenario_read_from_a_file() {
    let built = square()
        .name("t")
        .obstacle([(4.0, 8.0), (6.0, 8.0), (5.0, 10.0)])
        .start(5.0, 19.0)
        .goal(5.0, 1.0)
        .plane(20.0, 0.0, 45.0, 0.4)
        .build()
        .unwrap();
    let read = Scenario::from_ron_str(
        r#"(name: "t",
            map: (boundary: [(0.0, 0.0), (10.0, 0.0), (10.0, 20.0), (0.0, 20.0)],
                  obstacles: [[(4.0, 8.0), (6.0, 8.0), (5.0, 10.0)]]),
            start: (5.0, 19.0), goal: (5.0, 1.0),
            terrain: (planes: [(y_top: 20.0, y_bottom: 0.0, slope_deg: 45.0, friction: 0.4)]))"#,
    )
    .unwrap();
    assert_eq!(built, read);
}

#[test]
fn missing_parts_and_defects_are_typed_errors() {
    let e = square().start(5.0, 19.0).build().unwrap_err();
    assert!(
        matches!(e, ScenarioError::Incomplete { missing: "goal" }),
        "{e}"
    );
    assert!(e.to_string().contains(".goal("), "{e}");
    let e = Scenario::builder()
        .start(1.0, 1.0)
        .goal(2.0, 2.0)
        .build()
        .unwrap_err();
    assert!(matches!(
        e,
        ScenarioError::Incomplete {
            missing: "boundary"
        }
    ));
    // A start outside the boundary is the map error a file gets.
    let e = square()
        .start(50.0, 19.0)
        .goal(5.0, 1.0)
        .build()
        .unwrap_err();
    assert!(matches!(e, ScenarioError::Map { .. }), "{e}");
    // A plane steeper than the models allow.
    let e = square()
        .start(5.0, 19.0)
        .goal(5.0, 1.0)
        .plane(20.0, 0.0, 89.5, 0.4)
        .build()
        .unwrap_err();
    assert!(matches!(e, ScenarioError::Plane { .. }), "{e}");
}
