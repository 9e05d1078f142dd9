//! Exports land where they came from (issue 16): a plan on a scenario made from a DEM, exported
//! as GeoJSON, puts every waypoint and anchor in the DEM cell whose planning-frame footprint holds
//! it. The footprint is computed forward (cell corners to the planning frame), independently of
//! the export's inverse mapping.

use rappel::dem::dem_scenario;
use rappel::geometry::polygon::{PointInPolygon, Polygon};
use rappel::nalgebra::Point2;
use rappel::plan::{PlanOptions, plan};
use rappel::terrain::ingest::IngestOptions;
use rappel_render::export::{ExportFormat, export_plan};

#[test]
fn exported_points_fall_on_the_dem_cells_they_came_from() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../fixtures/terrain/mars_hirise_dteec_010228_1490_crop.asc"
    );
    let d = dem_scenario(path.as_ref(), &IngestOptions::default()).expect("ingests");
    let report = plan(&d.scenario, &PlanOptions::default()).expect("plans");
    let geo = d
        .scenario
        .georeference
        .as_ref()
        .expect("a DEM scenario is georeferenced");
    let text =
        String::from_utf8(export_plan(&report, Some(geo), ExportFormat::GeoJson).expect("exports"))
            .expect("UTF-8");
    let json: serde_json::Value = serde_json::from_str(&text).expect("valid JSON");
    assert_eq!(json["type"], "FeatureCollection");
    let g = d.grid.geometry();
    let frame = &d.ingested.frame;
    let chosen = report.outcome.chosen.as_ref().expect("a feasible class");
    let class = report
        .classes
        .iter()
        .find(|c| c.rank == chosen.rank)
        .expect("the chosen class");
    let mut checked = 0;
    for f in json["features"].as_array().expect("features") {
        let layer = f["properties"]["layer"].as_str().unwrap_or_default();
        let expected: Vec<Point2<f64>> = match layer {
            "waypoint" => class.waypoints.clone(),
            "anchor" => class.anchors.iter().map(|a| a.point).collect(),
            "start" => vec![report.setting.start],
            "goal" => vec![report.setting.goal],
            _ => continue,
        };
        let c = &f["geometry"]["coordinates"];
        let world = Point2::new(c[0].as_f64().expect("x"), c[1].as_f64().expect("y"));
        let (fr, fc) = g.world_to_grid(&world);
        let (row, col) = (fr.floor() as usize, fc.floor() as usize);
        let footprint = Polygon::new(
            g.cell_corners(row, col)
                .iter()
                .map(|w| frame.to_planning(w))
                .collect(),
        );
        // The planning point this feature came from is one of the expected ones, inside the
        // footprint of the cell its exported coordinates name.
        assert!(
            expected
                .iter()
                .any(|p| footprint.locate(p) != PointInPolygon::Outside),
            "{layer} at {world:?}: cell ({row}, {col})"
        );
        checked += 1;
    }
    // Start, goal, and the chosen class's anchor and waypoint.
    assert!(checked >= 4, "{checked}");
    // CSV: a header with the DEM coordinates, one row per vertex.
    let csv =
        String::from_utf8(export_plan(&report, Some(geo), ExportFormat::Csv).expect("exports"))
            .expect("UTF-8");
    assert!(csv.starts_with("layer,class,index,x,y,psi_deg,obstacle,east,north\n"));
    let vertices: usize = report.classes.iter().map(|c| c.points.len()).sum();
    assert!(csv.lines().count() > vertices);
}
