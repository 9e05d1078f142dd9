//! Saddle PTFOs from a DEM (`rappel dem --ptfo-saddles`, thesis §3.3.3 and §3.4): a planted saddle
//! on a 20° slope that is convex along the fall line (it bends down the way a descending tether
//! runs) is labelled with saddles on and not without; the same saddle turned a quarter turn
//! (convex only across the fall line) is never labelled.

use rappel::dem::dem_scenario;
use rappel::dem_ptfo::{PtfoLabelOptions, label_ptfos};
use rappel::geometry::polygon::PointInPolygon;
use rappel::nalgebra::Point2;
use rappel::ptfo_spec::FrictionRange;
use rappel::terrain::esri_ascii::write_esri_ascii;
use rappel::terrain::grid::GridGeometry;
use rappel::terrain::ingest::IngestOptions;
use rappel::terrain::slope::FallLine;
use rappel::terrain::synthetic::{ProfilePlane, plane_series_dem};

/// Whether a PTFO is labelled over the saddle's centre, for a saddle of curvature `along` along
/// the fall line (north-south) and `across` east-west (negative: convex).
fn labelled_over_centre(along: f64, across: f64, saddles: bool, tag: &str) -> bool {
    let cell = 0.25;
    let g = GridGeometry::new(160, 120, cell, cell, 0.0, 40.0).expect("grid");
    let south = FallLine::from_azimuth(180.0).expect("fall line");
    let plane = plane_series_dem(g, &south, 100.0, &[ProfilePlane::new(1e3, 20.0)]).expect("plane");
    let centre = Point2::new(15.0, 20.0);
    let sigma: f64 = 1.5;
    let dem = plane
        .map(|r, c, z| {
            let d = g.cell_center(r, c) - centre;
            let window = (-(d.norm_squared()) / (2.0 * sigma * sigma)).exp();
            let saddle = 0.5 * (along * d.y * d.y + across * d.x * d.x);
            z.map(|z| z + window * saddle)
        })
        .expect("saddle");
    let dir = std::env::temp_dir().join(format!("rappel-saddle-{}-{tag}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let file = dir.join("saddle.asc");
    std::fs::write(&file, write_esri_ascii(&dem, -9999.0)).expect("write");
    // The saddle's relief (about a metre) is terrain to drive over, not a geometric obstacle.
    let mut ingest = IngestOptions::default();
    ingest.obstacles.h_min_m = 2.0;
    ingest.obstacles.h_max_m = 3.0;
    let mut d = dem_scenario(&file, &ingest).expect("ingests");
    let _ = std::fs::remove_dir_all(&dir);
    let geometric = d.scenario.map.obstacles.len();
    let mut opts = PtfoLabelOptions::with_friction(FrictionRange { lo: 0.4, hi: 0.4 });
    opts.saddles = saddles;
    let labels = label_ptfos(&mut d, &opts).expect("labels");
    if !saddles {
        assert_eq!(labels.saddle_cells, 0);
    }
    d.scenario.validate().expect("a valid scenario");
    let c = d.ingested.frame.to_planning(&centre);
    d.scenario.map.obstacles[geometric..]
        .iter()
        .any(|o| o.locate(&c) != PointInPolygon::Outside)
}

#[test]
fn a_saddle_convex_along_the_fall_line_is_labelled_only_with_saddles_on() {
    // Convex (bending down) along the fall line, concave across it.
    assert!(labelled_over_centre(-1.2, 1.2, true, "on"));
    assert!(!labelled_over_centre(-1.2, 1.2, false, "off"));
}

#[test]
fn a_saddle_convex_only_across_the_fall_line_is_never_labelled() {
    assert!(!labelled_over_centre(1.2, -1.2, true, "across"));
}
