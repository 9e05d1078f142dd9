//! Independent rows of the `terrain` suite (issue 9): synthetic DEMs of known geometry (planted
//! planes, boulders and pits, thesis §2.1.2), written as ESRI ASCII grids and taken end to end
//! through the path `rappel dem` takes (`rappel::dem::dem_scenario` reading the file) and then
//! `rappel::plan::plan`. Every reference comes from the planted geometry, never from rappel's own
//! output: the number of planes and their slopes, the fall line's azimuth, where the planes break,
//! how many boulders (tether obstacles) and pits (robot obstacles) there are and that each lies
//! inside its obstacle, on a single plane the planned length against the 3D distance on the
//! planted plane, and a planted dome labelled as the one PTFO with its apex height.

use super::case::Case;
use rappel::dem::{DemScenario, dem_scenario};
use rappel::geometry::polygon::{PointInPolygon, Polygon};
use rappel::nalgebra::{Point2, Vector2};
use rappel::plan::{PlanOptions, plan};
use rappel::terrain::esri_ascii::write_esri_ascii;
use rappel::terrain::grid::{GridGeometry, HeightGrid};
use rappel::terrain::ingest::IngestOptions;
use rappel::terrain::slope::FallLine;
use rappel::terrain::synthetic::{ProfilePlane, plane_series_dem, with_box};
use std::ops::Range;
use std::path::PathBuf;

const SUITE: &str = "terrain";

/// Compass azimuth of the planted fall line, degrees (off the grid axes on purpose).
const AZIMUTH_DEG: f64 = 200.0;
/// Cell size of every synthetic grid, metres.
const CELL_M: f64 = 1.0;
/// Height of the planted boulders and depth of the pits, metres: between the thesis' default
/// `H_min` (0.2 m) and `H_max` (2 m).
const BOX_RISE_M: f64 = 1.5;
/// A plane's fitted slope may differ from the planted one by this much, degrees: the fit sees
/// cell-centre samples of an exact plane, so only the cells near a break (mixed into the fit)
/// move it.
const SLOPE_TOL_DEG: f64 = 0.5;
/// The estimated fall line may differ from the planted one by this much, degrees.
const AZIMUTH_TOL_DEG: f64 = 1.0;
/// A detected plane break may lie this many cells from the planted one (the plane regions are
/// made of whole cells).
const BREAK_TOL_CELLS: f64 = 1.5;
/// Relative agreement of the planned length with the 3D distance on a single plane (rounding
/// only: the unfolding of one plane is an isometry).
const LENGTH_REL_TOL: f64 = 1e-9;

/// Boulders (rows, columns) planted on the single-plane scene.
const BOULDERS: [(Range<usize>, Range<usize>); 3] =
    [(10..14, 8..12), (10..14, 36..40), (40..44, 22..26)];
/// Pits planted on the single-plane scene.
const PITS: [(Range<usize>, Range<usize>); 2] = [(26..30, 8..12), (26..30, 36..40)];

fn fall_line() -> Result<FallLine, String> {
    FallLine::from_azimuth(AZIMUTH_DEG).map_err(|e| e.to_string())
}

fn grid(nrows: usize, ncols: usize) -> Result<GridGeometry, String> {
    GridGeometry::new(nrows, ncols, CELL_M, CELL_M, 1000.0, 5000.0).map_err(|e| e.to_string())
}

/// The world (east, north) centre of a planted box.
fn box_centre(g: &GridGeometry, rows: &Range<usize>, cols: &Range<usize>) -> Point2<f64> {
    let r = (rows.start + rows.end) as f64 / 2.0;
    let c = (cols.start + cols.end) as f64 / 2.0;
    Point2::new(g.west + c * g.cell_x, g.north - r * g.cell_y)
}

/// Writes `dem` as an ESRI ASCII grid and ingests it as `rappel dem` does.
fn ingest_file(name: &str, dem: &HeightGrid) -> Result<DemScenario, String> {
    let dir: PathBuf = std::env::temp_dir().join(format!("rappel-regress-{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let path = dir.join(format!("{name}.asc"));
    std::fs::write(&path, write_esri_ascii(dem, -9999.0))
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let d = dem_scenario(&path, &IngestOptions::default()).map_err(|e| format!("{name}: {e}"));
    let _ = std::fs::remove_file(&path);
    d
}

/// The planted downhill unit vector of [`AZIMUTH_DEG`] (east, north), computed here, not by
/// rappel.
fn planted_downhill() -> Vector2<f64> {
    let a = AZIMUTH_DEG.to_radians();
    Vector2::new(a.sin(), a.cos())
}

/// Signed difference between two compass azimuths, degrees in (-180, 180].
fn azimuth_difference(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(360.0);
    if d > 180.0 { d - 360.0 } else { d }
}

/// How many of `polygons` hold `p` strictly inside.
fn holders(polygons: &[Polygon], p: &Point2<f64>) -> usize {
    polygons
        .iter()
        .filter(|o| o.locate(p) == PointInPolygon::Inside)
        .count()
}

/// Rows of the single-plane scene with boulders and pits, and of the same plane bare.
fn single_plane(cases: &mut Vec<Case>) -> Result<(), String> {
    let g = grid(60, 50)?;
    let fall = fall_line()?;
    let slope = 25.0;
    let bare = plane_series_dem(g, &fall, 500.0, &[ProfilePlane::new(1e4, slope)])
        .map_err(|e| e.to_string())?;
    let mut dem = bare.clone();
    for (rows, cols) in &BOULDERS {
        dem = with_box(&dem, rows.clone(), cols.clone(), BOX_RISE_M).map_err(|e| e.to_string())?;
    }
    for (rows, cols) in &PITS {
        dem = with_box(&dem, rows.clone(), cols.clone(), -BOX_RISE_M).map_err(|e| e.to_string())?;
    }
    let scene = "synthetic 25° plane, 3 boulders, 2 pits";
    let d = ingest_file("boulders", &dem)?;
    let planes = &d.scenario.terrain.planes;
    cases.push(Case::closed_form(
        SUITE,
        format!("{scene}: planes"),
        planes.len().to_string(),
        "1 (planted)",
        planes.len() == 1,
    ));
    if let Some(p) = planes.first() {
        cases.push(Case::closed_form(
            SUITE,
            format!("{scene}: plane slope, deg"),
            format!("{:.3}", p.slope_deg),
            format!("{slope} ± {SLOPE_TOL_DEG} (planted)"),
            (p.slope_deg - slope).abs() <= SLOPE_TOL_DEG,
        ));
    }
    let az = d.ingested.frame.fall_line_azimuth_deg();
    cases.push(Case::closed_form(
        SUITE,
        format!("{scene}: fall line azimuth, deg"),
        format!("{az:.3}"),
        format!("{AZIMUTH_DEG} ± {AZIMUTH_TOL_DEG} (planted)"),
        azimuth_difference(az, AZIMUTH_DEG).abs() <= AZIMUTH_TOL_DEG,
    ));
    let tether = &d.scenario.map.obstacles;
    cases.push(Case::closed_form(
        SUITE,
        format!("{scene}: tether obstacles"),
        tether.len().to_string(),
        format!(
            "{} (the planted boulders; pits pose no obstacle to the tether, §2.1.2)",
            BOULDERS.len()
        ),
        tether.len() == BOULDERS.len(),
    ));
    let robot = &d.ingested.robot_obstacles;
    cases.push(Case::closed_form(
        SUITE,
        format!("{scene}: robot obstacles"),
        robot.len().to_string(),
        format!("{} (the planted pits)", PITS.len()),
        robot.len() == PITS.len(),
    ));
    let frame = &d.ingested.frame;
    let inside = |boxes: &[(Range<usize>, Range<usize>)], layer: &[Polygon]| -> Vec<usize> {
        boxes
            .iter()
            .map(|(r, c)| holders(layer, &frame.to_planning(&box_centre(&g, r, c))))
            .collect()
    };
    let b_in_t = inside(&BOULDERS, tether);
    let p_in_t = inside(&PITS, tether);
    cases.push(Case::closed_form(
        SUITE,
        format!("{scene}: tether obstacles holding each boulder / pit centre"),
        format!("{b_in_t:?} / {p_in_t:?}"),
        "1 each / 0 each (planted positions)",
        b_in_t.iter().all(|&n| n == 1) && p_in_t.iter().all(|&n| n == 0),
    ));
    let p_in_r = inside(&PITS, robot);
    let b_in_r = inside(&BOULDERS, robot);
    cases.push(Case::closed_form(
        SUITE,
        format!("{scene}: robot obstacles holding each pit / boulder centre"),
        format!("{p_in_r:?} / {b_in_r:?}"),
        "1 each / 0 each (planted positions)",
        p_in_r.iter().all(|&n| n == 1) && b_in_r.iter().all(|&n| n == 0),
    ));

    // The bare plane: no obstacle, so the shortest SHP is the straight segment, and its unfolded
    // length must be the 3D distance between its ends on the planted plane.
    let scene = "synthetic 25° plane, bare";
    let d = ingest_file("bare", &bare)?;
    let report = plan(&d.scenario, &PlanOptions::default()).map_err(|e| format!("{scene}: {e}"))?;
    let (a, b) = (
        d.ingested.frame.to_world(&d.scenario.start),
        d.ingested.frame.to_world(&d.scenario.goal),
    );
    let dp = b - a;
    let dh = slope.to_radians().tan() * dp.dot(&planted_downhill());
    let distance_3d = (dp.norm_squared() + dh * dh).sqrt();
    let length = report.classes.first().map(|c| c.length_m);
    cases.push(Case::closed_form(
        SUITE,
        format!("{scene}: shortest SHP, m"),
        length.map_or("no class".to_string(), |l| format!("{l:.6}")),
        format!("{distance_3d:.6} (3D distance on the planted plane between start and goal)"),
        length.is_some_and(|l| (l - distance_3d).abs() <= LENGTH_REL_TOL * distance_3d),
    ));
    Ok(())
}

/// Rows of a two-plane profile: the planes, their slopes, and where they break.
fn two_planes(cases: &mut Vec<Case>) -> Result<(), String> {
    let g = grid(80, 50)?;
    let fall = fall_line()?;
    let (upper, lower, run) = (15.0, 35.0, 30.0);
    let dem = plane_series_dem(
        g,
        &fall,
        500.0,
        &[ProfilePlane::new(run, upper), ProfilePlane::new(1e4, lower)],
    )
    .map_err(|e| e.to_string())?;
    let scene = format!("synthetic {upper}° over {lower}° planes");
    let d = ingest_file("two-planes", &dem)?;
    let planes = &d.scenario.terrain.planes;
    cases.push(Case::closed_form(
        SUITE,
        format!("{scene}: planes"),
        planes.len().to_string(),
        "2 (planted)",
        planes.len() == 2,
    ));
    if planes.len() != 2 {
        return Ok(());
    }
    let slopes = [planes[0].slope_deg, planes[1].slope_deg];
    cases.push(Case::closed_form(
        SUITE,
        format!("{scene}: slopes top first, deg"),
        format!("{:.3}, {:.3}", slopes[0], slopes[1]),
        format!("{upper}, {lower} ± {SLOPE_TOL_DEG} (planted)"),
        (slopes[0] - upper).abs() <= SLOPE_TOL_DEG && (slopes[1] - lower).abs() <= SLOPE_TOL_DEG,
    ));
    // The planted break: `run` metres horizontally below the grid's uphill-most sample corner.
    let uphill = -planted_downhill();
    let s_top = g
        .sample_corners()
        .iter()
        .map(|c| c.coords.dot(&uphill))
        .fold(f64::NEG_INFINITY, f64::max);
    let planted = s_top - run;
    let frame = &d.ingested.frame;
    let found_world = frame.to_world(&Point2::new(0.0, planes[0].y_bottom));
    let found = found_world.coords.dot(&uphill);
    cases.push(Case::closed_form(
        SUITE,
        format!("{scene}: break below the top, horizontal m"),
        format!("{:.3}", s_top - found),
        format!("{run} ± {BREAK_TOL_CELLS} cells (planted)"),
        (found - planted).abs() <= BREAK_TOL_CELLS * CELL_M,
    ));
    Ok(())
}

/// Sphere radius of the planted dome, m: its curvature `-1/8` 1/m is beyond the default
/// convexity tolerance at 1 m cells (0.1 1/m).
const DOME_SPHERE_M: f64 = 8.0;
/// Height of the planted dome above the slope (vertical), m.
const DOME_HEIGHT_M: f64 = 1.5;

/// Rows of PTFO labelling (thesis §3.4: "finding any convex terrain"): a smooth spherical dome
/// and a box boulder on a plane; the dome, and only it, becomes a PTFO.
fn dome(cases: &mut Vec<Case>) -> Result<(), String> {
    use rappel::dem_ptfo::{PtfoLabelOptions, label_ptfos};
    use rappel::mechanics::ptfo_surface::PtfoSurface;
    use rappel::ptfo_spec::FrictionRange;
    let g = grid(60, 50)?;
    let fall = fall_line()?;
    let slope = 25.0;
    let plane = plane_series_dem(g, &fall, 500.0, &[ProfilePlane::new(1e4, slope)])
        .map_err(|e| e.to_string())?;
    let centre = Point2::new(g.west + 25.0, g.north - 30.0);
    let (r, h) = (DOME_SPHERE_M, DOME_HEIGHT_M);
    let domed = plane
        .map(|row, col, z| {
            let d2 = (g.cell_center(row, col) - centre).norm_squared();
            let cap = (r * r - d2).max(0.0).sqrt() - (r - h);
            z.map(|z| z + cap.max(0.0))
        })
        .map_err(|e| e.to_string())?;
    let boulder = (10..14, 8..12);
    let dem = with_box(&domed, boulder.0.clone(), boulder.1.clone(), BOX_RISE_M)
        .map_err(|e| e.to_string())?;
    let scene = "synthetic dome and boulder on a 25° plane";
    let mut d = ingest_file("dome", &dem)?;
    let opts = PtfoLabelOptions::with_friction(FrictionRange { lo: 0.4, hi: 0.6 });
    let labels = label_ptfos(&mut d, &opts).map_err(|e| format!("{scene}: {e}"))?;
    cases.push(Case::closed_form(
        SUITE,
        format!("{scene}: PTFOs labelled"),
        labels.ptfos.to_string(),
        "1 (the planted dome; the boulder is a geometric obstacle)",
        labels.ptfos == 1,
    ));
    let frame = &d.ingested.frame;
    let Some(spec) = d.scenario.friction.as_ref().and_then(|f| f.ptfos.first()) else {
        return Ok(());
    };
    let outline = &d.scenario.map.obstacles[spec.obstacle];
    let dome_at = frame.to_planning(&centre);
    let boulder_at = frame.to_planning(&box_centre(&g, &boulder.0, &boulder.1));
    let holds = (outline.locate(&dome_at), outline.locate(&boulder_at));
    cases.push(Case::closed_form(
        SUITE,
        format!("{scene}: the PTFO holds the dome's centre, not the boulder's"),
        format!("{:?} / {:?}", holds.0, holds.1),
        "Inside / Outside (planted positions)",
        holds == (PointInPolygon::Inside, PointInPolygon::Outside),
    ));
    if let PtfoSurface::HeightField(patch) = &spec.surface {
        let apex = patch
            .heights
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max);
        let want = h * slope.to_radians().cos();
        // How far below the apex the highest node may read, from the planted geometry: the
        // nearest node is at most half a diagonal of the node grid from the apex (the sphere
        // drops `d² / 2R` there); bilinear sampling between cell centres loses at most
        // `κ c² / 8` along each axis; the fitted plane rises by at most the planted volume
        // (dome cap and boulder) spread over the grid.
        let half_diagonal = patch.spacing * std::f64::consts::SQRT_2 / 2.0;
        let node = half_diagonal.powi(2) / (2.0 * r);
        let bilinear = 2.0 * CELL_M * CELL_M / (8.0 * r);
        let cap_volume = std::f64::consts::PI * h * h * (3.0 * r - h) / 3.0;
        let boulder_volume =
            (boulder.0.len() * boulder.1.len()) as f64 * CELL_M * CELL_M * BOX_RISE_M;
        let area = (g.nrows * g.ncols) as f64 * CELL_M * CELL_M;
        let tol = node + bilinear + (cap_volume + boulder_volume) / area;
        cases.push(Case::closed_form(
            SUITE,
            format!("{scene}: PTFO surface's apex above the plane, m"),
            format!("{apex:.3}"),
            format!(
                "{want:.3} (dome height along the normal, h cos 25°) - {tol:.3}..0 (sampling and fit bounds)"
            ),
            apex <= want + 1e-9 && apex >= want - tol,
        ));
    }
    Ok(())
}

/// The synthetic rows of the `terrain` suite.
pub fn cases() -> Result<Vec<Case>, String> {
    let mut cases = Vec::new();
    single_plane(&mut cases)?;
    two_planes(&mut cases)?;
    dome(&mut cases)?;
    Ok(cases)
}
