//! Exports read back by GDAL, the independent oracle (issue 34): the Mars equirectangular
//! fixture, the EPSG:32610 fixture and the shipped HiRISE crop (a local grid) go
//! `rappel dem` -> `rappel stability --geotiff` -> `gdalinfo` / `gdalsrsinfo` / `gdal_translate`.
//! Checked: the CRS GDAL reads from the export is the one it reads from the DEM (same PROJ
//! string, or the same WKT 1 for a local grid), the grid is the DEM's (size and geotransform), and every cell GDAL
//! reads equals the value computed here from the JSON report's poses, binned with GDAL's own
//! geotransform.
//!
//! The plan's FlatGeobuf export goes the same way (`rappel plan --export OUT.fgb` -> `gdalsrsinfo`,
//! `ogr2ogr -f GeoJSON`): the same CRS as the DEM, every vertex inside the DEM's footprint, and
//! every tether vertex GDAL reads lying in the planning-frame footprint (cell corners mapped
//! forward into the planning frame) of the DEM cell GDAL's coordinates name, for the vertex the
//! planner reported.
//!
//! Without GDAL (`gdalinfo` not on PATH) the tests print why and pass, unless
//! `RAPPEL_REQUIRE_GDAL=1` (set by CI, which installs `gdal-bin`): then a missing GDAL fails.

use crate::common::*;
use std::collections::HashMap;
use std::path::Path;
use std::process::Command;

/// `true` when GDAL's tools run; `false` (after saying so) when they are absent and not required.
fn gdal_available() -> bool {
    let ok = Command::new("gdalinfo")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if !ok {
        assert!(
            std::env::var("RAPPEL_REQUIRE_GDAL").as_deref() != Ok("1"),
            "RAPPEL_REQUIRE_GDAL=1 but GDAL's gdalinfo does not run: install gdal-bin"
        );
        eprintln!("skipped: GDAL (gdalinfo) is not installed; the GDAL read-back is not checked");
    }
    ok
}

/// Runs a GDAL tool and returns its standard output.
fn gdal(tool: &str, args: &[&str]) -> String {
    let o = Command::new(tool).args(args).output().expect("GDAL runs");
    assert!(o.status.success(), "{tool} {args:?}: {}", stderr(&o));
    stdout(&o)
}

/// GDAL's reading of a dataset's CRS, for comparison: its PROJ string (the system's
/// definition, whatever order or names its WKT uses), or its WKT 1 when it has no PROJ string
/// (an engineering `LOCAL_CS`); whitespace removed. An empty reading (no CRS) fails.
fn crs_of(path: &str) -> String {
    let squash = |s: String| s.split_whitespace().collect::<String>();
    let proj = squash(gdal("gdalsrsinfo", &["-o", "proj4", path]));
    let crs = if proj.is_empty() {
        squash(gdal("gdalsrsinfo", &["-o", "wkt1", path]))
    } else {
        proj
    };
    assert!(!crs.is_empty(), "{path}: GDAL reads no CRS");
    crs
}

/// `(ncols, nrows, geotransform)` as `gdalinfo -json` reads them.
fn grid_of(path: &str) -> (usize, usize, [f64; 6]) {
    let v: serde_json::Value =
        serde_json::from_str(&gdal("gdalinfo", &["-json", path])).expect("gdalinfo JSON");
    let size: Vec<usize> = serde_json::from_value(v["size"].clone()).expect("size");
    let gt: [f64; 6] = serde_json::from_value(v["geoTransform"].clone()).expect("geotransform");
    (size[0], size[1], gt)
}

/// Band `b` as GDAL reads it, row-major, through an ESRI ASCII grid GDAL writes (9 significant
/// digits: float32 exactly).
fn band_of(path: &str, b: usize, dir: &Path) -> Vec<f32> {
    let out = dir.join(format!("band{b}.asc"));
    let o = out.to_str().unwrap_or_default();
    let bs = b.to_string();
    gdal(
        "gdal_translate",
        &[
            "-q",
            "-b",
            &bs,
            "-of",
            "AAIGrid",
            "-co",
            "SIGNIFICANT_DIGITS=9",
            path,
            o,
        ],
    );
    let text = std::fs::read_to_string(&out).expect("ASCII grid");
    text.lines()
        .skip_while(|l| {
            l.split_whitespace()
                .next()
                .is_some_and(|w| w.parse::<f64>().is_err())
        })
        .flat_map(|l| {
            l.split_whitespace()
                .map(|w| w.parse::<f32>().expect("a value"))
                .collect::<Vec<_>>()
        })
        .collect()
}

/// DEM -> scenario -> stability map -> GeoTIFF -> GDAL, for one fixture; `grid` is the pose step.
fn check_stability_geotiff(fixture_name: &str, grid: &str, expected_crs: &str) {
    if !gdal_available() {
        return;
    }
    let dir = temp_dir(&format!("gdal-{fixture_name}"));
    let dem = fixture(&format!("terrain/{fixture_name}.tif"));
    check_dem(&dir, fixture_name, &dem, grid, expected_crs);
}

/// [`check_stability_geotiff`] of the DEM at `dem`, working in `dir`.
fn check_dem(dir: &Path, fixture_name: &str, dem: &str, grid: &str, expected_crs: &str) {
    let scenario = dir.join("s.ron");
    let s = scenario.to_str().unwrap_or_default();
    let o = rappel(&["dem", dem, "--out", s]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let tif = dir.join("stability.tif");
    let t = tif.to_str().unwrap_or_default();
    let o = rappel(&["stability", s, "--grid", grid, "--geotiff", t, "--json"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    // The export says which CRS it wrote.
    assert!(
        stderr(&o).contains(&format!("CRS {expected_crs}")),
        "{}",
        stderr(&o)
    );
    let report: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");

    // The CRS: GDAL reads the same system from the DEM and from the export.
    let dem_crs = if dem.ends_with(".asc") {
        dem.replace(".asc", ".prj")
    } else {
        dem.to_string()
    };
    assert_eq!(crs_of(&dem_crs), crs_of(t), "{fixture_name}");
    // The grid: the DEM's size and geotransform (so inside its footprint).
    let (ncols, nrows, gt) = grid_of(dem);
    assert_eq!(grid_of(t), (ncols, nrows, gt), "{fixture_name}");

    // The values: every pose of the report, mapped to DEM coordinates through the scenario's
    // georeference and binned with GDAL's geotransform.
    let sc = rappel::scenario::Scenario::load(&scenario).expect("scenario");
    let geo = sc.georeference.expect("georeference");
    let mut cells: HashMap<usize, (bool, f32)> = HashMap::new();
    let dots = report["dots"].as_array().expect("dots");
    assert!(!dots.is_empty());
    for d in dots {
        let p = rappel::nalgebra::Point2::new(
            d["point"][0].as_f64().expect("x"),
            d["point"][1].as_f64().expect("y"),
        );
        let w = geo.to_world(&p);
        let (col, row) = ((w.x - gt[0]) / gt[1], (w.y - gt[3]) / gt[5]);
        assert!(
            col >= 0.0 && row >= 0.0 && col < ncols as f64 && row < nrows as f64,
            "{fixture_name}: pose {p} at {w} is outside the DEM"
        );
        let i = row.floor() as usize * ncols + col.floor() as usize;
        let stable = d["stable"].as_bool().expect("stable");
        let m = d["margin"].as_f64().map_or(f32::NAN, |m| m as f32);
        let e = cells.entry(i).or_insert((true, f32::INFINITY));
        e.0 &= stable;
        e.1 = e.1.min(m);
    }
    let (verdict, margin) = (band_of(t, 1, dir), band_of(t, 2, dir));
    assert_eq!(
        (verdict.len(), margin.len()),
        (ncols * nrows, ncols * nrows)
    );
    for i in 0..ncols * nrows {
        let (v, m) = match cells.get(&i) {
            None => (-9999.0, -9999.0),
            Some((true, m)) => (1.0, *m),
            Some((false, _)) => (0.0, -9999.0),
        };
        assert_eq!((verdict[i], margin[i]), (v, m), "{fixture_name}: cell {i}");
    }
    assert!(
        cells.values().any(|c| c.0),
        "{fixture_name}: no stable cell"
    );
}

#[test]
fn mars_equirectangular_stability_reads_back_in_gdal() {
    check_stability_geotiff(
        "mars_equirectangular_crop",
        "3",
        "PROJCS \"Mars 2000 Equirectangular, clon 180, lat_ts -30\"",
    );
}

#[test]
fn epsg_stability_reads_back_in_gdal() {
    check_stability_geotiff("earth_mt_st_helens_utm10n", "20", "EPSG:32610");
}

#[test]
fn local_grid_stability_reads_back_in_gdal() {
    check_stability_geotiff(
        "mars_hirise_dteec_010228_1490_crop",
        "3",
        "LOCAL_CS \"unnamed\"",
    );
}

/// A CRS the GeoKeys cannot hold (an orthographic projection of Mars, from an ESRI grid's
/// `.prj`): the WKT goes to the `.aux.xml` sidecar and GDAL reads the same system.
#[test]
fn wkt_beyond_geokeys_reads_back_through_the_sidecar() {
    if !gdal_available() {
        return;
    }
    let dir = temp_dir("gdal-ortho");
    let dem = dir.join("ortho.asc");
    std::fs::copy(
        fixture("terrain/mars_hirise_dteec_010228_1490_crop.asc"),
        &dem,
    )
    .expect("copy");
    std::fs::write(
        dir.join("ortho.prj"),
        r#"PROJCS["Mars orthographic",GEOGCS["Mars sphere",DATUM["Mars",SPHEROID["Mars",3396190,0]],PRIMEM["Reference meridian",0],UNIT["degree",0.0174532925199433]],PROJECTION["Orthographic"],PARAMETER["latitude_of_origin",-30],PARAMETER["central_meridian",180],PARAMETER["false_easting",0],PARAMETER["false_northing",0],UNIT["metre",1]]"#,
    )
    .expect("prj");
    check_dem(
        &dir,
        "ortho",
        dem.to_str().unwrap_or_default(),
        "3",
        "PROJCS \"Mars orthographic\" (WKT in the .aux.xml beside it)",
    );
    assert!(dir.join("stability.tif.aux.xml").exists());
}

/// How close to a grid line, in cells, a vertex read back counts as on it: the export's
/// coordinates and GDAL's decimal text round in the last digits (1e-9 of a cell is a micrometre
/// on a 1 m grid, far below any planning decision).
const EDGE_TOLERANCE: f64 = 1e-9;

/// DEM -> scenario -> plan -> FlatGeobuf -> GDAL, for one fixture (module docs).
fn check_plan_flatgeobuf(fixture_name: &str) {
    use rappel::geometry::polygon::{PointInPolygon, Polygon};
    use rappel::nalgebra::Point2;
    if !gdal_available() {
        return;
    }
    let dir = temp_dir(&format!("gdal-plan-{fixture_name}"));
    let dem = fixture(&format!("terrain/{fixture_name}.tif"));
    let scenario = dir.join("s.ron");
    let s = scenario.to_str().unwrap_or_default();
    let o = rappel(&["dem", &dem, "--out", s]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let fgb = dir.join("plan.fgb");
    let f = fgb.to_str().unwrap_or_default();
    let o = rappel(&["plan", s, "--export", f, "--json"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let report: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");

    assert_eq!(crs_of(&dem), crs_of(f), "{fixture_name}");
    let read: serde_json::Value =
        serde_json::from_str(&gdal("ogr2ogr", &["-f", "GeoJSON", "/vsistdout/", f]))
            .expect("GDAL's GeoJSON");
    let (ncols, nrows, gt) = grid_of(&dem);
    let geo = rappel::scenario::Scenario::load(&scenario)
        .expect("scenario")
        .georeference
        .expect("georeference");
    let classes = report["classes"].as_array().expect("classes");
    let mut tethers = 0;
    for feature in read["features"].as_array().expect("features") {
        let g = &feature["geometry"];
        let vertices: Vec<&serde_json::Value> = match g["type"].as_str() {
            Some("LineString") => g["coordinates"].as_array().expect("line").iter().collect(),
            Some("Point") => vec![&g["coordinates"]],
            other => panic!("{fixture_name}: unexpected geometry {other:?}"),
        };
        let props = &feature["properties"];
        let planned = (props["layer"] == "tether").then(|| {
            let rank = props["class"].as_u64().expect("class rank");
            let c = classes
                .iter()
                .find(|c| c["rank"].as_u64() == Some(rank))
                .expect("class");
            c["points"].as_array().expect("points").clone()
        });
        if let Some(p) = &planned {
            assert_eq!(
                p.len(),
                vertices.len(),
                "{fixture_name}: tether vertex count"
            );
            tethers += 1;
        }
        for (i, v) in vertices.iter().enumerate() {
            let (x, y) = (v[0].as_f64().expect("x"), v[1].as_f64().expect("y"));
            let (col, row) = ((x - gt[0]) / gt[1], (y - gt[3]) / gt[5]);
            assert!(
                col >= 0.0 && row >= 0.0 && col < ncols as f64 && row < nrows as f64,
                "{fixture_name}: vertex ({x}, {y}) outside the DEM"
            );
            let Some(p) = &planned else { continue };
            // The cell GDAL's coordinates name; a vertex on a cell edge (obstacle corners lie on
            // the grid's lines) names both cells beside it, within EDGE_TOLERANCE cells.
            let sides = |v: f64| {
                let mut out = vec![v.floor()];
                if (v - v.round()).abs() < EDGE_TOLERANCE {
                    out.extend([v.round() - 1.0, v.round()]);
                }
                out
            };
            let q = Point2::new(p[i][0].as_f64().expect("x"), p[i][1].as_f64().expect("y"));
            let on_cell = sides(row).iter().any(|&r| {
                sides(col).iter().any(|&c| {
                    let corner = |dc: f64, dr: f64| {
                        let w = Point2::new(gt[0] + (c + dc) * gt[1], gt[3] + (r + dr) * gt[5]);
                        geo.frame.to_planning(&w)
                    };
                    let footprint = Polygon::new(vec![
                        corner(0.0, 1.0),
                        corner(1.0, 1.0),
                        corner(1.0, 0.0),
                        corner(0.0, 0.0),
                    ]);
                    footprint.locate(&q) != PointInPolygon::Outside
                })
            });
            assert!(
                on_cell,
                "{fixture_name}: tether vertex {i} at planning {q}, read at ({x}, {y}), is not on cell ({row}, {col})"
            );
        }
    }
    assert_eq!(
        tethers,
        classes.len(),
        "{fixture_name}: one tether per class"
    );
}

#[test]
fn plans_export_as_flatgeobuf_in_the_dems_crs() {
    for name in [
        "mars_equirectangular_crop",
        "earth_mt_st_helens_utm10n",
        "mars_hirise_dteec_010228_1490_crop",
    ] {
        check_plan_flatgeobuf(name);
    }
}
