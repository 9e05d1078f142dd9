//! The `report` module's tests (moved out of the source file: the facade's sources hold the
//! code only).
use rappel::input_kind::ValidateReport;
use rappel::report::*;

#[test]
fn a_report_of_another_kind_or_version_is_refused() {
    let r = ValidateReport {
        file: "s.ron".into(),
        kind: rappel::input_kind::InputKind::Scenario,
        valid: true,
        summary: "1 obstacles, 7 vertices, 0 terrain planes".into(),
        obstacles: Some(1),
        vertices: Some(7),
        terrain_planes: Some(0),
        free_area_m2: Some(12.5),
        ptfos: Some(0),
        georeferenced: Some(false),
    };
    let text = r.to_json();
    assert!(
        text.trim_start()
            .starts_with("{\n  \"schema_version\": 1,\n  \"report\": \"validate\"")
    );
    let (a, b) = round_trip(&r).unwrap();
    assert_eq!(a, b);
    assert!(matches!(
        read_report::<HomotopicReport>(&text),
        Err(ReadReportError::Parse { .. } | ReadReportError::Kind { .. })
    ));
    let old = text.replace("\"schema_version\": 1", "\"schema_version\": 0");
    assert!(matches!(
        read_report::<ValidateReport>(&old),
        Err(ReadReportError::Version { found: 0 })
    ));
}
