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
//! The other exports go the same way: `rappel dem --geotiff` (obstacle mask and PTFO labels:
//! the DEM's CRS and grid, counts equal to the report's, every labelled cell's centre inside its
//! PTFO's outline), `settle-map --geotiff` on a DEM (the DEM's CRS, inside its footprint, every
//! pose's verdict and margin in the cell GDAL's geotransform puts its ground point in) and on a
//! Paton scene (its named local frame), `online --export .fgb` (the DEM's CRS, the path
//! travelled where the report's path maps), a mesh rasterised by `rappel dem --cell --crs` (a
//! plane with a hole: every covered cell on the plane, the hole no value), and the warning for
//! a vertical CRS GDAL writes.
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

/// A fresh directory named after `tag` for a test that needs GDAL, or `None` (after saying why)
/// when GDAL is absent and not required.
fn gdal_dir(tag: &str) -> Option<std::path::PathBuf> {
    gdal_available().then(|| temp_dir(tag))
}

/// Runs a GDAL tool and returns its standard output.
fn gdal(tool: &str, args: &[&str]) -> String {
    let o = Command::new(tool).args(args).output().expect("GDAL runs");
    assert!(o.status.success(), "{tool} {args:?}: {}", stderr(&o));
    stdout(&o)
}

/// Runs rappel, which must exit 0 and say `says` on stderr (the CRS an export wrote, a
/// warning); its output.
fn rappel_saying(args: &[&str], says: &str) -> std::process::Output {
    let o = rappel(args);
    assert_eq!(o.status.code(), Some(0), "{args:?}: {}", stderr(&o));
    assert!(stderr(&o).contains(says), "{args:?}: {}", stderr(&o));
    o
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
    let Some(dir) = gdal_dir(&format!("gdal-{fixture_name}")) else {
        return;
    };
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
    let Some(dir) = gdal_dir("gdal-ortho") else {
        return;
    };
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

/// The features GDAL reads from the vector file at `path` (through `ogr2ogr -f GeoJSON`): each
/// one's properties and vertices `(x, y)`, every vertex checked to lie inside the DEM's grid
/// `(ncols, nrows, geotransform)`; `what` names the case in failures.
fn features_inside(
    path: &str,
    (ncols, nrows, gt): (usize, usize, [f64; 6]),
    what: &str,
) -> Vec<(serde_json::Value, Vec<(f64, f64)>)> {
    let read: serde_json::Value =
        serde_json::from_str(&gdal("ogr2ogr", &["-f", "GeoJSON", "/vsistdout/", path]))
            .expect("GDAL's GeoJSON");
    let xy = |v: &serde_json::Value| (v[0].as_f64().expect("x"), v[1].as_f64().expect("y"));
    read["features"]
        .as_array()
        .expect("features")
        .iter()
        .map(|feature| {
            let g = &feature["geometry"];
            let vertices: Vec<(f64, f64)> = match g["type"].as_str() {
                Some("LineString") => g["coordinates"]
                    .as_array()
                    .expect("line")
                    .iter()
                    .map(xy)
                    .collect(),
                Some("Point") => vec![xy(&g["coordinates"])],
                other => panic!("{what}: unexpected geometry {other:?}"),
            };
            for &(x, y) in &vertices {
                let (col, row) = ((x - gt[0]) / gt[1], (y - gt[3]) / gt[5]);
                assert!(
                    col >= 0.0 && row >= 0.0 && col < ncols as f64 && row < nrows as f64,
                    "{what}: vertex ({x}, {y}) outside the DEM"
                );
            }
            (feature["properties"].clone(), vertices)
        })
        .collect()
}

/// How close to a grid line, in cells, a vertex read back counts as on it: the export's
/// coordinates and GDAL's decimal text round in the last digits (1e-9 of a cell is a micrometre
/// on a 1 m grid, far below any planning decision).
const EDGE_TOLERANCE: f64 = 1e-9;

/// DEM -> scenario -> plan -> FlatGeobuf -> GDAL, for one fixture (module docs).
fn check_plan_flatgeobuf(fixture_name: &str) {
    use rappel::geometry::polygon::{PointInPolygon, Polygon};
    use rappel::nalgebra::Point2;
    let Some(dir) = gdal_dir(&format!("gdal-plan-{fixture_name}")) else {
        return;
    };
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
    let (ncols, nrows, gt) = grid_of(&dem);
    let geo = rappel::scenario::Scenario::load(&scenario)
        .expect("scenario")
        .georeference
        .expect("georeference");
    let classes = report["classes"].as_array().expect("classes");
    let mut tethers = 0;
    for (props, vertices) in features_inside(f, (ncols, nrows, gt), fixture_name) {
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
        for (i, &(x, y)) in vertices.iter().enumerate() {
            let (col, row) = ((x - gt[0]) / gt[1], (y - gt[3]) / gt[5]);
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

/// GDAL's nodata value of band 1 of a raster, when it declares one.
fn nodata_of(path: &str) -> Option<f64> {
    let v: serde_json::Value =
        serde_json::from_str(&gdal("gdalinfo", &["-json", path])).expect("gdalinfo JSON");
    v["bands"][0]["noDataValue"].as_f64()
}

/// `rappel dem --ptfo-friction --geotiff` -> GDAL, for one fixture: the DEM's CRS and grid; the
/// obstacle mask's obstacle cells number the report's `obstacle_points`, its no-value cells are
/// exactly the DEM's; each PTFO label `k` marks as many cells as the report's `cells[k - 1]`,
/// each of them with its centre (GDAL's geotransform, mapped into the planning frame) inside
/// PTFO `k`'s outline in the scenario written. Returns the number of PTFOs.
fn check_dem_geotiff(fixture_name: &str, expected_crs: &str) -> usize {
    use rappel::geometry::polygon::PointInPolygon;
    use rappel::nalgebra::Point2;
    let dir = temp_dir(&format!("gdal-dem-{fixture_name}"));
    let dem = fixture(&format!("terrain/{fixture_name}.tif"));
    let scenario = dir.join("s.ron");
    let s = scenario.to_str().unwrap_or_default();
    let tif = dir.join("detection.tif");
    let t = tif.to_str().unwrap_or_default();
    let o = rappel_saying(
        &[
            "dem",
            &dem,
            "--out",
            s,
            "--ptfo-friction",
            "0.4,0.6",
            "--geotiff",
            t,
            "--json",
        ],
        &format!("CRS {expected_crs}"),
    );
    let report: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    assert_eq!(report["crs"], expected_crs, "{fixture_name}");
    assert_eq!(crs_of(&dem), crs_of(t), "{fixture_name}");
    let (ncols, nrows, gt) = grid_of(&dem);
    assert_eq!(grid_of(t), (ncols, nrows, gt), "{fixture_name}");

    let heights = band_of(&dem, 1, &dir);
    let dem_nodata = nodata_of(&dem);
    let (mask, labels) = (band_of(t, 1, &dir), band_of(t, 2, &dir));
    let obstacle_points = mask.iter().filter(|v| [1.0, 2.0, 3.0].contains(*v)).count();
    assert_eq!(
        obstacle_points as u64,
        report["counts"]["obstacle_points"].as_u64().expect("count"),
        "{fixture_name}"
    );
    for (i, (m, h)) in mask.iter().zip(&heights).enumerate() {
        let unknown = h.is_nan() || dem_nodata.is_some_and(|n| f64::from(*h) == n);
        assert_eq!(*m == -9999.0, unknown, "{fixture_name}: cell {i}");
        assert!(
            unknown || [0.0, 1.0, 2.0, 3.0].contains(m),
            "{fixture_name}: cell {i} has mask {m}"
        );
    }
    let sc = rappel::scenario::Scenario::load(&scenario).expect("scenario");
    let geo = sc.georeference.as_ref().expect("georeference");
    let cells: Vec<u64> = report["ptfos"]["cells"]
        .as_array()
        .expect("cells per PTFO")
        .iter()
        .map(|c| c.as_u64().expect("count"))
        .collect();
    assert_eq!(
        cells.len() as u64,
        report["ptfos"]["ptfos"].as_u64().expect("ptfos")
    );
    let ptfos = sc.friction.as_ref().map_or(&[][..], |f| &f.ptfos[..]);
    assert_eq!(ptfos.len(), cells.len(), "{fixture_name}");
    for (k, expected) in cells.iter().enumerate() {
        let label = (k + 1) as f32;
        let marked: Vec<usize> = (0..labels.len()).filter(|&i| labels[i] == label).collect();
        assert_eq!(
            marked.len() as u64,
            *expected,
            "{fixture_name}: PTFO {}",
            k + 1
        );
        let hull = &sc.map.obstacles[ptfos[k].obstacle];
        for i in marked {
            let (r, c) = ((i / ncols) as f64, (i % ncols) as f64);
            let w = Point2::new(gt[0] + (c + 0.5) * gt[1], gt[3] + (r + 0.5) * gt[5]);
            let p = geo.frame.to_planning(&w);
            assert_eq!(
                hull.locate(&p),
                PointInPolygon::Inside,
                "{fixture_name}: cell {i} labelled {label} lies outside PTFO {label}'s outline"
            );
        }
    }
    // Cells not in a PTFO: 0 where heights are known.
    assert!(
        labels
            .iter()
            .all(|v| *v == -9999.0 || *v == 0.0 || (*v >= 1.0 && *v <= cells.len() as f32)),
        "{fixture_name}: labels out of range"
    );
    cells.len()
}

#[test]
fn dem_obstacle_mask_and_ptfo_labels_read_back_in_gdal() {
    if !gdal_available() {
        return;
    }
    let ptfos = check_dem_geotiff(
        "mars_equirectangular_crop",
        "PROJCS \"Mars 2000 Equirectangular, clon 180, lat_ts -30\"",
    ) + check_dem_geotiff("earth_mt_st_helens_utm10n", "EPSG:32610")
        + check_dem_geotiff("mars_hirise_dteec_010228_1490_crop", "LOCAL_CS \"unnamed\"");
    assert!(
        ptfos > 0,
        "no fixture has a PTFO: the labels are not checked"
    );
}

/// `rappel settle-map` on an elevation model with `--geotiff` -> GDAL: the DEM's CRS, the
/// raster inside the DEM's footprint, one cell per pose, each cell's verdict and margin those of
/// the JSON report's pose whose ground point GDAL's geotransform puts in it.
#[test]
fn settle_map_on_a_dem_reads_back_in_gdal() {
    let Some(dir) = gdal_dir("gdal-settle-map") else {
        return;
    };
    let dem = fixture("terrain/earth_mt_st_helens_utm10n.tif");
    let (ncols, nrows, gt) = grid_of(&dem);
    // A 5 x 5 map of 10 m around the DEM's centre, the root anchor 40 m up the grid's north.
    let (cx, cy) = (
        gt[0] + 0.5 * ncols as f64 * gt[1],
        gt[3] + 0.5 * nrows as f64 * gt[5],
    );
    let range = |c: f64| format!("{},{}", c - 20.0, c + 20.0);
    let heights = band_of(&dem, 1, &dir);
    let at = |x: f64, y: f64| {
        let (c, r) = ((x - gt[0]) / gt[1], (y - gt[3]) / gt[5]);
        f64::from(heights[r as usize * ncols + c as usize])
    };
    let root = format!("{},{},{}", cx, cy + 40.0, at(cx, cy + 40.0) + 1.0);
    let tif = dir.join("settle.tif");
    let t = tif.to_str().unwrap_or_default();
    let o = rappel_saying(
        &[
            "settle-map",
            &dem,
            "--x",
            &range(cx),
            "--y",
            &range(cy),
            "--step",
            "10",
            "--start",
            &format!("{cx},{cy}"),
            "--root",
            &root,
            "--yaw",
            "-90",
            "--geotiff",
            t,
            "--json",
        ],
        "CRS EPSG:32610",
    );
    assert_eq!(crs_of(&dem), crs_of(t));
    let report: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    let (nx, ny, sgt) = grid_of(t);
    assert_eq!(
        (nx as u64, ny as u64),
        (
            report["nx"].as_u64().expect("nx"),
            report["ny"].as_u64().expect("ny")
        )
    );
    // Inside the DEM's footprint.
    let (west, north) = (sgt[0], sgt[3]);
    let (east, south) = (west + nx as f64 * sgt[1], north + ny as f64 * sgt[5]);
    let (dw, dn) = (gt[0], gt[3]);
    let (de, ds) = (dw + ncols as f64 * gt[1], dn + nrows as f64 * gt[5]);
    assert!(west >= dw && east <= de && south >= ds && north <= dn);
    let (verdict, margin) = (band_of(t, 1, &dir), band_of(t, 2, &dir));
    let mut assessed = 0;
    for cell in report["cells"].as_array().expect("cells") {
        let (x, y) = (
            cell["ground"][0].as_f64().expect("x"),
            cell["ground"][1].as_f64().expect("y"),
        );
        let (c, r) = ((x - sgt[0]) / sgt[1], (y - sgt[3]) / sgt[5]);
        let i = r.floor() as usize * nx + c.floor() as usize;
        let (v, m) = match cell["pose"].as_object() {
            None => (-9999.0, -9999.0),
            Some(p) if p["stable"] == true => (1.0, p["margin"].as_f64().expect("margin") as f32),
            Some(_) => (0.0, -9999.0),
        };
        assessed += usize::from(v != -9999.0);
        assert_eq!((verdict[i], margin[i]), (v, m), "pose at ({x}, {y})");
    }
    assert!(assessed > 0, "no pose settled: the values are not checked");
}

/// A settle-map over a Paton scene (no CRS) is written in the scene's local frame, named so.
#[test]
fn settle_map_on_a_scene_is_written_in_its_local_frame() {
    let Some(dir) = gdal_dir("gdal-settle-map-scene") else {
        return;
    };
    let tif = dir.join("scene.tif");
    let t = tif.to_str().unwrap_or_default();
    rappel_saying(
        &[
            "settle-map",
            &fixture("paton/ledge.ron"),
            "--test",
            "1",
            "--step",
            "1",
            "--geotiff",
            t,
        ],
        "CRS LOCAL_CS \"rappel Paton scene frame",
    );
    let wkt = gdal("gdalsrsinfo", &["-o", "wkt1", t]);
    assert!(wkt.contains("Paton scene frame"), "{wkt}");
}

/// `rappel online --export .fgb` on a scenario made from the Mars equirectangular DEM, the truth
/// without the prior's obstacles (all phantoms): GDAL reads the DEM's CRS, every vertex inside the DEM,
/// the path travelled vertex for vertex where the report's planning-frame path maps, and one
/// event point per timeline event.
#[test]
fn online_run_exports_as_flatgeobuf_in_the_dems_crs() {
    let Some(dir) = gdal_dir("gdal-online") else {
        return;
    };
    let dem = fixture("terrain/mars_equirectangular_crop.tif");
    let prior = dir.join("prior.ron");
    let p = prior.to_str().unwrap_or_default();
    let o = rappel(&["dem", &dem, "--out", p]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let mut truth = rappel::scenario::Scenario::load(&prior).expect("prior");
    assert!(!truth.map.obstacles.is_empty());
    // Every obstacle a phantom: those the robot passes are sensed, so the timeline has events.
    truth.map.obstacles.clear();
    let truth_path = dir.join("truth.ron");
    truth.save(&truth_path).expect("truth written");
    let fgb = dir.join("online.fgb");
    let f = fgb.to_str().unwrap_or_default();
    let o = rappel(&[
        "online",
        p,
        "--truth",
        truth_path.to_str().unwrap_or_default(),
        "--export",
        f,
        "--json",
    ]);
    assert!(matches!(o.status.code(), Some(0 | 1)), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("CRS PROJCS \"Mars 2000 Equirectangular"),
        "{}",
        stderr(&o)
    );
    let report: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    assert_eq!(crs_of(&dem), crs_of(f));
    let dem_grid = grid_of(&dem);
    let geo = rappel::scenario::Scenario::load(&prior)
        .expect("prior")
        .georeference
        .expect("georeference");
    let travelled = report["travelled"].as_array().expect("travelled");
    let (mut events, mut lines) = (0, 0);
    for (props, vertices) in features_inside(f, dem_grid, "online") {
        match props["layer"].as_str() {
            Some("event") => {
                events += 1;
                // Enum names as plain text: the decision's tag, not a JSON object.
                let decision = props["decision"].as_str().unwrap_or_default();
                assert!(
                    !decision.is_empty()
                        && decision.chars().all(|c| c.is_ascii_lowercase() || c == '_'),
                    "event decision {decision:?}"
                );
            }
            Some("travelled") => {
                lines += 1;
                assert_eq!(vertices.len(), travelled.len());
                for (&(x, y), t) in vertices.iter().zip(travelled) {
                    let w = geo.to_world(&rappel::nalgebra::Point2::new(
                        t[0].as_f64().expect("x"),
                        t[1].as_f64().expect("y"),
                    ));
                    let d = (x - w.x).hypot(y - w.y);
                    assert!(
                        d <= 1e-6 * dem_grid.2[1].abs(),
                        "travelled vertex {d} m off"
                    );
                }
            }
            _ => {}
        }
    }
    assert_eq!(lines, 1, "one path travelled");
    let timeline = report["timeline"].as_array().expect("timeline");
    assert!(
        !timeline.is_empty(),
        "no event: the event points are not checked"
    );
    assert_eq!(events, timeline.len());
}

/// A mesh into `rappel dem`: a tilted plane (z = 0.6 y + 0.1 x) over 30 m x 50 m with a square
/// hole, written as OBJ in UTM 10N coordinates, rasterised at 2 m with `--crs EPSG:32610`. GDAL
/// reads the height grid written: the CRS is EPSG:32610, every cell whose centre the mesh
/// covers holds the plane's height there (the closed form, to float32), the hole's cells and
/// nothing else are no value.
#[test]
fn mesh_into_dem_reads_back_in_gdal() {
    let Some(dir) = gdal_dir("gdal-mesh-dem") else {
        return;
    };
    let (x0, y0) = (562_000.0, 5_121_000.0);
    let plane = |x: f64, y: f64| 0.6 * (y - y0) + 0.1 * (x - x0) + 1000.0;
    // Vertices every 5 m (7 x 11), two triangles per square; the square (2..3, 4..5) is a hole.
    let mut obj = String::new();
    for j in 0..11 {
        for i in 0..7 {
            let (x, y) = (x0 + 5.0 * f64::from(i), y0 + 5.0 * f64::from(j));
            obj.push_str(&format!("v {x} {y} {}\n", plane(x, y)));
        }
    }
    let id = |i: usize, j: usize| j * 7 + i + 1;
    for j in 0..10 {
        for i in 0..6 {
            if (i, j) == (2, 4) {
                continue;
            }
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            obj.push_str(&format!("f {a} {b} {c}\nf {a} {c} {d}\n"));
        }
    }
    let mesh = dir.join("plane.obj");
    std::fs::write(&mesh, obj).expect("OBJ written");
    let grid = dir.join("plane_grid.tif");
    let g = grid.to_str().unwrap_or_default();
    let scenario = dir.join("s.ron");
    let o = rappel(&[
        "dem",
        mesh.to_str().unwrap_or_default(),
        "--cell",
        "2",
        "--crs",
        "EPSG:32610",
        "--grid-out",
        g,
        "--out",
        scenario.to_str().unwrap_or_default(),
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let report: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    assert_eq!(report["crs"], "EPSG:32610");
    assert!(crs_of(g).contains("+proj=utm+zone=10"), "{}", crs_of(g));
    let (ncols, nrows, gt) = grid_of(g);
    assert_eq!((ncols, nrows), (15, 25));
    assert_eq!((gt[0], gt[1], gt[3], gt[5]), (x0, 2.0, y0 + 50.0, -2.0));
    let heights = band_of(g, 1, &dir);
    for r in 0..nrows {
        for c in 0..ncols {
            let (x, y) = (
                gt[0] + (c as f64 + 0.5) * gt[1],
                gt[3] + (r as f64 + 0.5) * gt[5],
            );
            // Strictly inside: a centre on the hole's edge lies on the triangles beside it.
            let in_hole = x > x0 + 10.0 && x < x0 + 15.0 && y > y0 + 20.0 && y < y0 + 25.0;
            let h = heights[r * ncols + c];
            if in_hole {
                assert_eq!(h, -9999.0, "cell ({r}, {c}) in the hole");
            } else {
                assert!(
                    (f64::from(h) - plane(x, y)).abs() <= 1e-3,
                    "cell ({r}, {c}): {h} against the plane's {}",
                    plane(x, y)
                );
            }
        }
    }
    // The scenario's DEM is the grid written: a stability raster lands in its CRS.
    let sc = rappel::scenario::Scenario::load(&scenario).expect("scenario");
    assert_eq!(sc.georeference.expect("georeference").dem, "plane_grid.tif");
}

/// A GeoTIFF with a vertical CRS (GDAL writes `EPSG:32610+5703`, UTM 10N with NAVD88 heights,
/// as VerticalCSTypeGeoKey): `rappel dem` warns that the key is not used, naming it.
#[test]
fn vertical_crs_keys_are_warned_about() {
    let Some(dir) = gdal_dir("gdal-vertical") else {
        return;
    };
    let tif = dir.join("compound.tif");
    let t = tif.to_str().unwrap_or_default();
    gdal(
        "gdal_translate",
        &[
            "-q",
            "-a_srs",
            "EPSG:32610+5703",
            &fixture("terrain/earth_mt_st_helens_utm10n.tif"),
            t,
        ],
    );
    let scenario = dir.join("s.ron");
    let o = rappel_saying(
        &["dem", t, "--out", scenario.to_str().unwrap_or_default()],
        "GeoKey VerticalCSTypeGeoKey (4096) = 5703 ignored",
    );
    assert!(stderr(&o).starts_with("warning: "), "{}", stderr(&o));
    assert!(
        stdout(&o).contains("crs                EPSG:32610"),
        "{}",
        stdout(&o)
    );
}

/// The lidar fixture into `rappel dem` (`fixtures/lidar/boulder_slope_utm10n.laz`, written by
/// `crates/terrain/examples/lidar_fixture.rs`: a 0.7 m/m slope from 1,000 m at (562,000 E,
/// 5,121,000 N), a 1.2 m boulder at (+10, +15), no returns in the shadow box (+9..+11,
/// +16.5..+19.5)), gridded at 1 m with the max statistic. GDAL reads the grid written: CRS
/// EPSG:32610 (from the LAS GeoTIFF-key records), and against the generator's closed forms:
/// a cell away from the boulder and the shadow holds a height between the slope's at its south
/// and north edges (the max of its points), the boulder's cell stands a metre above the slope,
/// cells inside the shadow have no value.
#[test]
fn lidar_point_cloud_into_dem_reads_back_in_gdal() {
    if !gdal_available() {
        return;
    }
    let (x0, y0) = (562_000.0, 5_121_000.0);
    let slope = |y: f64| 1000.0 + 0.7 * (y - y0);
    let dir = temp_dir("gdal-lidar");
    let grid = dir.join("scan_grid.tif");
    let g = grid.to_str().unwrap_or_default();
    let o = rappel(&[
        "dem",
        &fixture("lidar/boulder_slope_utm10n.laz"),
        "--cell",
        "1",
        "--grid-out",
        g,
        "--out",
        dir.join("s.ron").to_str().unwrap_or_default(),
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let report: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    assert_eq!(report["crs"], "EPSG:32610");
    assert!(crs_of(g).contains("+proj=utm+zone=10"), "{}", crs_of(g));
    let (ncols, nrows, gt) = grid_of(g);
    let heights = band_of(g, 1, &dir);
    let (mut flat, mut holes) = (0, 0);
    // Tolerance: millimetre records, float32 at 1,000 m (6e-5 m).
    let tol = 2e-3;
    for r in 0..nrows {
        for c in 0..ncols {
            let (w, n) = (gt[0] + c as f64 * gt[1], gt[3] + r as f64 * gt[5]);
            let (e, s) = (w + gt[1], n + gt[5]);
            let h = f64::from(heights[r * ncols + c]);
            let edge = r + 1 == nrows || c + 1 == ncols;
            let near = |(ax, ay, bx, by): (f64, f64, f64, f64)| {
                e > x0 + ax && w < x0 + bx && n > y0 + ay && s < y0 + by
            };
            let inside_shadow = w >= x0 + 9.0 && e <= x0 + 11.0 && s >= y0 + 16.5 && n <= y0 + 19.5;
            if inside_shadow {
                assert_eq!(h, -9999.0, "cell ({r}, {c}) in the scanner's shadow");
                holes += 1;
            } else if !near((8.5, 13.5, 11.5, 19.5)) && !edge {
                assert!(
                    h >= slope(s) - tol && h <= slope(n) + tol,
                    "cell ({r}, {c}): {h} outside the slope's {} .. {}",
                    slope(s),
                    slope(n)
                );
                flat += 1;
            }
            if (w..e).contains(&(x0 + 10.0)) && (s..n).contains(&(y0 + 15.0)) {
                assert!(h >= slope(s) + 1.0, "the boulder's cell: {h}");
            }
        }
    }
    assert!(flat > 400 && holes >= 2, "{flat} flat cells, {holes} holes");
}
