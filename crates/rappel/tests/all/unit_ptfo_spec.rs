//! The `ptfo_spec` module's tests (moved out of the source file: the facade's sources hold the
//! code only).
use rappel::ptfo_spec::*;
use rappel::scenario::Scenario;

fn resolve(s: &Scenario) -> Result<ResolvedFriction, String> {
    s.friction
        .as_ref()
        .unwrap()
        .resolve(s.robot.mass_kg, &s.terrain.planes, s.map.obstacles.len())
}

const BASE: &str = r#"(
    map: (boundary: [(0.0, 0.0), (40.0, 0.0), (40.0, 100.0), (0.0, 100.0)],
          obstacles: [[(18.0, 50.0), (22.0, 50.0), (22.0, 54.0), (18.0, 54.0)]]),
    start: (21.0, 95.0), goal: (20.0, 5.0),
    terrain: (planes: [(y_top: 100.0, y_bottom: 50.0, slope_deg: 60.0, friction: 0.4),
                       (y_top: 50.0, y_bottom: 0.0, slope_deg: 30.0, friction: 0.4)]),
    friction: Some((ptfos: [(obstacle: 0, surface: Cylinder(center: (20.0, 52.0), radius: 2.0),
                             friction: (lo: 0.3, hi: 0.4))])),
)"#;

#[test]
fn defaults_are_derived_from_mass_and_slopes() {
    let s = Scenario::from_ron_str(BASE).unwrap();
    let r = resolve(&s).unwrap();
    let w = 35.0 * GRAVITY;
    let t_d = w * 60f64.to_radians().sin();
    let t = r.model.tensions;
    assert!((t.t_d() - t_d).abs() < 1e-9);
    assert!((t.t_max() - 2.0 * t_d).abs() < 1e-9);
    assert!((t.epsilon() - 0.1 * t_d).abs() < 1e-9);
    assert!((t.t_min() - w * 0.5).abs() < 1e-9);
    assert_eq!(r.notes.len(), 4);
}

#[test]
fn json_and_ron_carry_the_same_section() {
    let patch = BASE.replace(
        "Cylinder(center: (20.0, 52.0), radius: 2.0)",
        "HeightField((origin: (17.0, 49.0), spacing: 1.0, cols: 3, \
         heights: [0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0]))",
    );
    for text in [BASE, patch.as_str()] {
        let s = Scenario::from_ron_str(text).unwrap();
        let json = s.to_text(rappel::scenario::Format::Json);
        let back = Scenario::from_json_str(&json).unwrap();
        assert_eq!(back, s);
        assert!(resolve(&back).is_ok());
    }
}

#[test]
fn unknown_fields_and_bad_values_are_errors() {
    let typo = BASE.replace("radius: 2.0", "radius: 2.0, radios: 1.0");
    assert!(Scenario::from_ron_str(&typo).is_err());
    let bad = BASE.replace("obstacle: 0", "obstacle: 3");
    let s = Scenario::from_ron_str(&bad).unwrap();
    let e = resolve(&s).unwrap_err();
    assert!(e.contains("obstacle 3"), "{e}");
    let empty = BASE.replace("lo: 0.3, hi: 0.4", "lo: 0.5, hi: 0.4");
    let s = Scenario::from_ron_str(&empty).unwrap();
    assert!(resolve(&s).is_err());
    let neg = BASE.replace("radius: 2.0", "radius: -2.0");
    let s = Scenario::from_ron_str(&neg).unwrap();
    let e = resolve(&s).unwrap_err();
    assert!(e.contains("ptfos[0].surface"), "{e}");
}
