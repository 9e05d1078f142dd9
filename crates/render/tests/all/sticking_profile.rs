//! Where a tether may stick along its length (thesis Figs. 3.13-3.15) against closed forms: a
//! cylindrical ridge across a 20° slope, crossed straight down the fall line.

use rappel::dem::dem_scenario;
use rappel::nalgebra::Point2;
use rappel::sticking_profile::sticking_profile;
use rappel::terrain::esri_ascii::write_esri_ascii;
use rappel::terrain::grid::GridGeometry;
use rappel::terrain::ingest::IngestOptions;
use rappel::terrain::slope::FallLine;
use rappel::terrain::synthetic::{ProfilePlane, plane_series_dem};
use rappel_render::dem::{HILL_VIEW_ARROWS, hill_view};

#[test]
fn a_ridge_across_the_slope_holds_at_its_crest_with_the_closed_form_curvature() {
    let (cell, slope, radius, rise) = (0.25, 20.0f64, 5.0, 1.0);
    let g = GridGeometry::new(160, 120, cell, cell, 0.0, 40.0).expect("grid");
    let south = FallLine::from_azimuth(180.0).expect("fall line");
    let plane =
        plane_series_dem(g, &south, 100.0, &[ProfilePlane::new(1e3, slope)]).expect("plane");
    // A cylindrical ridge of radius 5 m along east-west at northing 20, standing 1 m proud.
    let crest_north = 20.0;
    let dem = plane
        .map(|r, c, z| {
            let d = g.cell_center(r, c).y - crest_north;
            let cap = (radius * radius - d * d).max(0.0).sqrt() - (radius - rise);
            z.map(|z| z + cap.max(0.0))
        })
        .expect("ridge");
    let dir = std::env::temp_dir().join(format!("rappel-sticking-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let file = dir.join("ridge.asc");
    std::fs::write(&file, write_esri_ascii(&dem, -9999.0)).expect("write");
    let d = dem_scenario(&file, &IngestOptions::default()).expect("ingests");
    let frame = &d.ingested.frame;
    // Straight down the fall line across the ridge, in the planning frame.
    let top = frame.to_planning(&Point2::new(15.0, 30.0));
    let bottom = frame.to_planning(&Point2::new(15.0, 10.0));
    let mu = 0.4;
    let samples = sticking_profile(&d, &[top, bottom], mu, cell / 2.0);
    assert!(samples.len() > 100);
    // At the crest: the plane section of a cylinder of radius R seen along a slope of gradient
    // g = tan 20°: κ_n = -1 / (R (1 + g²)^(3/2)), no geodesic curvature, φ = ±π: it may stick.
    let crest = samples
        .iter()
        .min_by(|a, b| {
            let da = (frame.to_world(&a.at).y - crest_north).abs();
            let db = (frame.to_world(&b.at).y - crest_north).abs();
            da.total_cmp(&db)
        })
        .expect("a sample near the crest");
    let grad = slope.to_radians().tan();
    let want = -1.0 / (radius * (1.0 + grad * grad).powf(1.5));
    assert!(
        (crest.normal_curvature - want).abs() < 0.05 * want.abs(),
        "{} vs {want}",
        crest.normal_curvature
    );
    assert!(
        crest.geodesic_curvature.abs() < 1e-6 * want.abs(),
        "{crest:?}"
    );
    assert!(crest.may_stick);
    assert!((crest.phi.expect("curved").abs() - std::f64::consts::PI).abs() < 1e-6);
    // Fig. 3.14's vectors at the crest: the surface normal is the slope's (tilted 20° from the
    // vertical towards the fall line), and the tether's curve normal points straight into the
    // ridge, against it.
    let up = crest.surface_normal;
    assert!((up.norm() - 1.0).abs() < 1e-12);
    // (The nearest cell may lie half a cell off the crest, where the ridge tilts the ground by
    // up to (cell / 2) / R more; twice that is allowed.)
    assert!(
        (up.z.acos() - slope.to_radians()).abs() < cell / radius,
        "{up:?}"
    );
    assert!(
        up.x.abs() < 1e-9 && up.y < 0.0,
        "tilted towards the fall line (south): {up:?}"
    );
    let n = crest.curve_normal.expect("curved at the crest");
    assert!((n.dot(&up) + 1.0).abs() < 1e-6, "{n:?} vs {up:?}");
    // The sample's height is the DEM's: the planted plane plus the ridge's cap there.
    let at = frame.to_world(&crest.at);
    let dy = at.y - crest_north;
    // The planted plane rises linearly northwards: read it off two of its cells.
    let (top, bottom) = (g.cell_center(0, 0), g.cell_center(159, 0));
    let (z_top, z_bottom) = (
        plane.height(0, 0).expect("known"),
        plane.height(159, 0).expect("known"),
    );
    let plane_height =
        |p: &Point2<f64>| z_bottom + (p.y - bottom.y) * (z_top - z_bottom) / (top.y - bottom.y);
    let cap = (radius * radius - dy * dy).max(0.0).sqrt() - (radius - rise);
    let z_expected = plane_height(&at) + cap.max(0.0);
    assert!(
        (crest.world.z - z_expected).abs() < 0.5 * cell * grad,
        "{} vs {z_expected}",
        crest.world.z
    );
    // The 3D view draws the terrain, the tether, and the normals: one surface normal per shown
    // sample, a curve normal only where the tether is curved, no more than the documented cap.
    let svg = hill_view(&d, &samples, "ridge").expect("samples");
    let surface = svg.matches("class=\"surface-normal\"").count();
    let curve = svg.matches("class=\"curve-normal\"").count();
    assert!((1..=HILL_VIEW_ARROWS).contains(&surface), "{surface}");
    assert!(curve >= 1 && curve < surface, "{curve} of {surface}");
    assert!(svg.contains("<g id=\"terrain\">\n<polygon"));
    // Off the ridge the draped tether is straight: nothing to stick on.
    let flat: Vec<_> = samples
        .iter()
        .filter(|s| (frame.to_world(&s.at).y - crest_north).abs() > radius + 2.0 * cell)
        .collect();
    assert!(!flat.is_empty());
    assert!(
        flat.iter().all(|s| s.phi.is_none() && !s.may_stick),
        "{flat:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
