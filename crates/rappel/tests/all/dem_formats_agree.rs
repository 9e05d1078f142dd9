//! The Mars HiRISE patch read as an ESRI ASCII grid and as a float32 GeoTIFF (the same grid,
//! its elevations rounded to float32) must plan to the same verdicts class by class (issue 10):
//! feasibility is decided exactly, so rounding the input in its last bits cannot flip it. The
//! reference is the other format's plan, computed from an independently read file.

use rappel::dem::dem_scenario;
use rappel::plan::{PlanOptions, plan};
use rappel::terrain::ingest::IngestOptions;

fn plan_of(file: &str) -> rappel::plan::PlanReport {
    let path = format!(
        "{}/../../fixtures/terrain/{file}",
        env!("CARGO_MANIFEST_DIR")
    );
    let d = dem_scenario(path.as_ref(), &IngestOptions::default()).expect("dem");
    plan(
        &d.scenario,
        &PlanOptions {
            classes: 10,
            ..Default::default()
        },
    )
    .expect("plan")
}

#[test]
fn mars_asc_and_tif_agree_class_by_class() {
    let asc = plan_of("mars_hirise_dteec_010228_1490_crop.asc");
    let tif = plan_of("mars_hirise_dteec_010228_1490_crop.tif");
    assert_eq!(asc.classes.len(), tif.classes.len());
    assert!(asc.classes.len() >= 5, "{} classes", asc.classes.len());
    let mut feasible = 0;
    for (a, t) in asc.classes.iter().zip(&tif.classes) {
        // float32 elevations move the obstacle corners by ~1e-6 m.
        assert!(
            (a.length_m - t.length_m).abs() < 1e-4,
            "class {}: {} vs {}",
            a.rank,
            a.length_m,
            t.length_m
        );
        assert_eq!(a.anchors.len(), t.anchors.len(), "class {}", a.rank);
        assert_eq!(
            a.feasible, t.feasible,
            "class {}: asc {} / tif {}",
            a.rank, a.verdict, t.verdict
        );
        for (x, y) in a.anchors.iter().zip(&t.anchors) {
            // The sentence (angles to 0.01°): the two files' cells differ in the last digits.
            assert_eq!(
                x.passability.to_string(),
                y.passability.to_string(),
                "class {}",
                a.rank
            );
        }
        feasible += usize::from(a.feasible);
    }
    // Before the fix the .tif lost two of them (issue 10): both must keep them.
    assert!(feasible >= 5, "{feasible} feasible classes");
    assert_eq!(asc.outcome.chosen.is_some(), tif.outcome.chosen.is_some());
}
