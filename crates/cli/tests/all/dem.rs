//! `rappel dem` at its edges: an output path equal to the input is refused before anything is
//! written, and a spiked grid is refused as implausible relief with exit code 2 and no output.

use crate::common;

use common::*;

#[test]
fn dem_refuses_to_overwrite_its_input() {
    let dir = temp_dir("dem-same");
    let input = dir.join("x.asc");
    let original =
        std::fs::read(fixture("terrain/mars_hirise_dteec_010228_1490_crop.asc")).expect("fixture");
    std::fs::write(&input, &original).expect("copy");
    let inp = input.to_str().unwrap_or_default();
    let out = dir.join("s.ron");
    let o = out.to_str().unwrap_or_default();
    check_error(
        &["dem", inp, "--out", o, "--svg", inp],
        "would overwrite the input file",
    );
    check_error(
        &["dem", inp, "--out", inp],
        "would overwrite the input file",
    );
    // The same file through another spelling of the path.
    let dotted = dir.join(".").join("x.asc");
    check_error(
        &[
            "dem",
            inp,
            "--out",
            o,
            "--svg",
            dotted.to_str().unwrap_or_default(),
        ],
        "would overwrite the input file",
    );
    assert_eq!(std::fs::read(&input).expect("input"), original);
    assert!(!out.exists());
}

#[test]
fn a_spiked_grid_is_implausible_relief_and_nothing_is_written() {
    let dir = temp_dir("dem-spike");
    let mut text = String::from(
        "ncols 12\nnrows 10\nxllcorner 0\nyllcorner 0\ncellsize 1\nNODATA_value -9999\n",
    );
    for r in 0..10 {
        let row: Vec<String> = (0..12)
            .map(|c| {
                if (r, c) == (3, 4) {
                    "1e12".to_string()
                } else {
                    format!("{}", r as f64 * 0.5)
                }
            })
            .collect();
        text.push_str(&row.join(" "));
        text.push('\n');
    }
    let input = dir.join("spike.asc");
    std::fs::write(&input, text).expect("write");
    let out = dir.join("s.ron");
    check_error(
        &[
            "dem",
            input.to_str().unwrap_or_default(),
            "--out",
            out.to_str().unwrap_or_default(),
        ],
        "implausible relief",
    );
    assert!(!out.exists());
}

#[test]
fn dem_work_cap_is_named_and_can_be_raised() {
    let dir = temp_dir("dem-cap");
    let input = fixture("terrain/mars_hirise_dteec_010228_1490_crop.asc");
    let inp = input.as_str();
    let out = dir.join("s.ron");
    let o = out.to_str().unwrap_or_default();
    // The grid has 120 x 70 = 8,400 cells.
    check_error(
        &["dem", inp, "--out", o, "--max-cells", "8399"],
        "more than the work cap of 8399 cells; raise it with --max-cells",
    );
    assert!(!out.exists());
    check_error(
        &["dem", inp, "--out", o, "--max-cells", "0"],
        "--max-cells: a work cap of 0 cells is outside 1 ..= 134217728",
    );
    let run = rappel(&["dem", inp, "--out", o, "--max-cells", "8400"]);
    assert_eq!(run.status.code(), Some(0), "{}", stderr(&run));
    assert!(out.exists());
}

#[test]
fn dem_labels_ptfos_that_the_frictional_planner_then_judges() {
    let dir = temp_dir("dem-ptfo");
    let input = fixture("terrain/mars_hirise_dteec_010228_1490_crop.asc");
    let out = dir.join("s.ron");
    let o = out.to_str().unwrap_or_default();
    check_error(
        &["dem", &input, "--out", o, "--ptfo-friction", "0.4,x"],
        "--ptfo-friction 0.4,x: number 2 (`x`) is not a number",
    );
    check_error(
        &["dem", &input, "--out", o, "--ptfo-friction", "NaN"],
        "--ptfo-friction NaN: number 1 (`NaN`) is not a finite number",
    );
    check_error(
        &["dem", &input, "--out", o, "--ptfo-friction", "0.1,0.2,0.3"],
        "--ptfo-friction 0.1,0.2,0.3: give LO or LO,HI (found 3 numbers)",
    );
    check_error(
        &["dem", &input, "--out", o, "--ptfo-friction", "0.6,0.4"],
        "--ptfo-friction 0.6,0.4: friction interval [0.6, 0.4] is empty",
    );
    check_error(
        &[
            "dem",
            &input,
            "--out",
            o,
            "--ptfo-friction",
            "0.5",
            "--ptfo-curvature=-1",
        ],
        "the curvature tolerance -1 must be positive and finite",
    );
    assert!(!out.exists());
    let convexity = dir.join("convexity.svg");
    let c = convexity.to_str().unwrap_or_default();
    let (sticking, phi) = (dir.join("sticking.svg"), dir.join("phi.svg"));
    let run = rappel(&[
        "dem",
        &input,
        "--out",
        o,
        "--ptfo-friction",
        "0.4,0.6",
        "--convexity-svg",
        c,
        "--sticking-svg",
        sticking.to_str().unwrap_or_default(),
        "--phi-svg",
        phi.to_str().unwrap_or_default(),
    ]);
    assert_eq!(run.status.code(), Some(0), "{}", stderr(&run));
    let text = stdout(&run);
    let line = text
        .lines()
        .find(|l| l.starts_with("PTFOs"))
        .expect("a PTFO line");
    let count: usize = line
        .split_whitespace()
        .nth(1)
        .and_then(|n| n.parse().ok())
        .expect("a count");
    assert!(count > 0, "{line}");
    let scenario = std::fs::read_to_string(&out).expect("scenario");
    assert_eq!(scenario.matches("HeightField").count(), count);
    let svg = std::fs::read_to_string(&convexity).expect("convexity picture");
    for layer in ["convex", "concave", "saddle", "saddle's convex direction"] {
        assert!(svg.contains(layer), "{layer}");
    }
    let svg = std::fs::read_to_string(&sticking).expect("sticking picture");
    assert!(svg.contains("tether may stick") && svg.contains("tether slips"));
    let svg = std::fs::read_to_string(&phi).expect("phi chart");
    assert!(svg.contains("atan"));
    // Without a friction the profile cannot be drawn: clap refuses, exit 2.
    let run = rappel(&["dem", &input, "--out", o, "--phi-svg", "x.svg"]);
    assert_eq!(run.status.code(), Some(2));
    // The frictional planner judges them: a clean answer, never an error.
    let plan = rappel(&["plan", o]);
    assert!(
        matches!(plan.status.code(), Some(0 | 1)),
        "{}",
        stderr(&plan)
    );
    assert!(stdout(&plan).contains("friction     PTFOs on obstacles"));
}

/// A scenario made by `rappel dem` records its DEM relative to itself, so a plan's picture run
/// from another working directory, after both files moved together, still has its hillshade.
#[test]
fn a_dem_scenario_finds_its_dem_from_any_working_directory() {
    let dir = temp_dir("dem-relative");
    std::fs::create_dir_all(dir.join("site/dems")).expect("dirs");
    let dem = dir.join("site/dems/mars.asc");
    std::fs::copy(
        fixture("terrain/mars_hirise_dteec_010228_1490_crop.asc"),
        &dem,
    )
    .expect("copy");
    let out = dir.join("site/plans/mars.ron");
    std::fs::create_dir_all(out.parent().unwrap()).expect("dirs");
    let o = rappel(&["dem", dem.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&out).expect("scenario");
    assert!(text.contains("\"../dems/mars.asc\""), "{text}");
    // Move the site elsewhere and plan from an unrelated working directory.
    let moved = dir.join("moved");
    std::fs::rename(dir.join("site"), &moved).expect("move");
    let svg = dir.join("plan.svg");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_rappel"))
        .current_dir(std::env::temp_dir())
        .args([
            "plan",
            moved.join("plans/mars.ron").to_str().unwrap(),
            "--classes",
            "1",
            "--svg",
            svg.to_str().unwrap(),
        ])
        .output()
        .expect("runs");
    assert!(o.status.code().is_some_and(|c| c <= 1), "{}", stderr(&o));
    assert!(!stderr(&o).contains("no hillshade"), "{}", stderr(&o));
    let picture = std::fs::read_to_string(&svg).expect("svg");
    assert!(picture.contains("hillshade"), "the plan has no hillshade");
}

/// Negative numbers reach the option that takes them (issue 30): `--hmin -1` is refused by the
/// obstacle detector naming H_min, and `--seed -1` by the parser naming `--seed`, not as an
/// unknown argument.
#[test]
fn negative_option_values_are_judged_by_their_option() {
    let out = temp_dir("dem-negative").join("x.ron");
    let dem = fixture("terrain/mars_hirise_dteec_010228_1490_crop.asc");
    check_error(
        &["dem", &dem, "--out", out.to_str().unwrap(), "--hmin", "-1"],
        "H_min = -1 must be positive",
    );
    check_error(
        &[
            "gen-map",
            "--obstacles",
            "10",
            "--seed",
            "-1",
            "--out",
            out.to_str().unwrap(),
        ],
        "invalid value '-1' for '--seed",
    );
    assert!(!out.exists());
}

/// Meshes and point clouds into `rappel dem`: their options are refused where they do not
/// apply, and required where they do, each with one located error and exit code 2; a bad mesh
/// is the mesh reader's error.
#[test]
fn mesh_and_point_cloud_options_are_checked() {
    let dir = temp_dir("dem-gridded");
    let out = dir.join("s.ron");
    let o = out.to_str().unwrap_or_default();
    let tif = fixture("terrain/earth_mt_st_helens_utm10n.tif");
    let laz = fixture("lidar/boulder_slope_utm10n.laz");
    let obj = dir.join("ramp.obj");
    std::fs::write(
        &obj,
        "v 0 0 0\nv 40 0 0\nv 40 60 48\nv 0 60 48\nf 1 2 3\nf 1 3 4\n",
    )
    .expect("OBJ");
    let obj = obj.to_str().unwrap_or_default();
    check_error(&["dem", &tif, "--out", o, "--cell", "1"], "--cell: ");
    check_error(&["dem", &tif, "--out", o, "--crs", "EPSG:4326"], "--crs: ");
    check_error(
        &["dem", &tif, "--out", o, "--grid-out", "g.tif"],
        "--grid-out: ",
    );
    check_error(
        &["dem", obj, "--out", o],
        "give the cell size with --cell M",
    );
    check_error(
        &["dem", obj, "--out", o, "--cell", "1", "--crs", "EPSG:north"],
        "the EPSG code is not a positive integer",
    );
    check_error(
        &["dem", obj, "--out", o, "--cell", "1", "--crs", "Mars"],
        "not EPSG:N, a WKT 1",
    );
    check_error(&["dem", obj, "--out", o, "--cell", "0"], "cell size 0");
    check_error(
        &["dem", obj, "--out", o, "--cell", "1", "--statistic", "max"],
        "is not a point cloud",
    );
    check_error(
        &[
            "dem",
            &laz,
            "--out",
            o,
            "--cell",
            "1",
            "--statistic",
            "median",
        ],
        "--statistic median: use max or mean",
    );
    check_error(
        &["dem", &laz, "--out", o, "--cell", "1", "--crs", "EPSG:4326"],
        "declares its CRS (EPSG:32610)",
    );
    check_error(
        &[
            "dem",
            &fixture("hostile/mesh-non-manifold.obj"),
            "--out",
            o,
            "--cell",
            "1",
        ],
        "mesh-non-manifold.obj",
    );
    assert!(!out.exists(), "no scenario written on bad input");
    // A mesh with its CRS: the grid written beside the scenario by default.
    let ok = rappel(&["dem", obj, "--out", o, "--cell", "2", "--crs", "EPSG:32610"]);
    assert_eq!(ok.status.code(), Some(0), "{}", stderr(&ok));
    assert!(dir.join("s.dem.tif").exists());
    assert!(
        stdout(&ok).contains("crs                EPSG:32610"),
        "{}",
        stdout(&ok)
    );
}

/// `rappel validate` knows lidar point clouds by their extension and checks them with `rappel
/// dem`'s reader: the point count against the count in the file's own header (the legacy
/// "number of point records", a little-endian `u32` at byte 107 of every LAS 1.0-1.4 header,
/// uncompressed in a LAZ file too) and the CRS its records give; a file that is not LAS, and a
/// truncated one, are errors naming the kind checked, with exit 2.
#[test]
fn validate_checks_point_clouds_with_the_dem_reader() {
    let laz = fixture("lidar/boulder_slope_utm10n.laz");
    let bytes = std::fs::read(&laz).expect("fixture");
    assert_eq!(&bytes[..4], b"LASF");
    let count = u32::from_le_bytes([bytes[107], bytes[108], bytes[109], bytes[110]]);
    let o = rappel(&["validate", &laz]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        out.contains(&format!(
            "valid point-cloud: {count} points, CRS EPSG:32610"
        )),
        "{out}"
    );
    let dir = temp_dir("validate-lidar");
    let not_las = dir.join("scan.las");
    std::fs::write(&not_las, "x y z\n1 2 3\n").expect("write");
    check_error(
        &["validate", not_las.to_str().unwrap_or_default()],
        "(checked as a point-cloud file)",
    );
    let truncated = dir.join("cut.laz");
    std::fs::write(&truncated, &bytes[..bytes.len().min(600)]).expect("write");
    check_error(
        &["validate", truncated.to_str().unwrap_or_default()],
        "(checked as a point-cloud file)",
    );
}
