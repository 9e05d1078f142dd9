//! LAS point clouds into height grids: a LAS 1.4 file with an OGC WKT record (the other CRS
//! form; the shipped fixture carries GeoTIFF keys) written with the `las` crate, read back and
//! gridded by both statistics against sums done by hand; bad cell sizes and empty clouds are
//! typed errors.

use nalgebra::Point3;
use rappel_terrain::grid::DemLimits;
use rappel_terrain::point_cloud::{PointCloudError, Statistic, grid_points, read_point_cloud};

/// A Mars equirectangular WKT (what a planetary lidar or a photogrammetric cloud might carry).
const MARS: &str = r#"PROJCS["Mars 2000 Equirectangular",GEOGCS["Mars 2000",DATUM["D_Mars_2000",SPHEROID["Mars_2000_IAU_IAG",3396190,169.894447223612]],PRIMEM["Reference_Meridian",0],UNIT["degree",0.0174532925199433]],PROJECTION["Equirectangular"],PARAMETER["standard_parallel_1",-30],PARAMETER["central_meridian",180],UNIT["metre",1]]"#;

/// Four points in two 1 m cells: (0.25, 0.25) at 1 and 3 m, (1.75, 0.75) at 5 and 6 m.
fn write_las(path: &std::path::Path) {
    let mut builder = las::Builder::from((1, 4));
    builder.transforms = las::Vector {
        x: las::Transform {
            scale: 0.001,
            offset: 0.0,
        },
        y: las::Transform {
            scale: 0.001,
            offset: 0.0,
        },
        z: las::Transform {
            scale: 0.001,
            offset: 0.0,
        },
    };
    let mut header = builder.into_header().expect("header");
    header
        .set_wkt_crs(MARS.as_bytes().to_vec())
        .expect("WKT record");
    let mut w = las::Writer::from_path(path, header).expect("writer");
    for (x, y, z) in [
        (0.25, 0.25, 1.0),
        (0.25, 0.25, 3.0),
        (1.75, 0.75, 5.0),
        (1.75, 0.75, 6.0),
    ] {
        w.write_point(las::Point {
            x,
            y,
            z,
            ..Default::default()
        })
        .expect("point");
    }
    w.close().expect("close");
}

#[test]
fn a_las_file_with_a_wkt_record_grids_by_max_and_mean() {
    let dir = std::env::temp_dir().join(format!("rappel-point-cloud-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let path = dir.join("four.las");
    write_las(&path);
    let max = read_point_cloud(&path, 1.0, Statistic::Max, &DemLimits::default()).expect("reads");
    assert_eq!(max.points, 4);
    let crs = max.crs.expect("the WKT record's CRS");
    assert!(
        crs.starts_with("PROJCS[\"Mars 2000 Equirectangular\""),
        "{crs}"
    );
    assert!(max.ignored.is_empty());
    let g = max.grid.geometry();
    assert_eq!((g.nrows, g.ncols), (1, 2));
    // The bounds are widened by half a millimetre (the records' scale).
    assert!((g.west - (0.25 - 0.0005)).abs() < 1e-9, "{}", g.west);
    assert_eq!(max.grid.height(0, 0), Some(3.0));
    assert_eq!(max.grid.height(0, 1), Some(6.0));
    let mean = read_point_cloud(&path, 1.0, Statistic::Mean, &DemLimits::default()).expect("reads");
    assert_eq!(mean.grid.height(0, 0), Some(2.0));
    assert_eq!(mean.grid.height(0, 1), Some(5.5));
}

#[test]
fn bad_cell_sizes_empty_clouds_and_strays_are_errors() {
    let (lo, hi) = (Point3::new(0.0, 0.0, 0.0), Point3::new(1.0, 1.0, 1.0));
    for cell in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let e = grid_points(&[lo], (lo, hi), cell, Statistic::Max, &DemLimits::default());
        assert!(matches!(e, Err(PointCloudError::Cell(_))), "{cell}");
    }
    let e = grid_points(&[], (lo, hi), 0.5, Statistic::Max, &DemLimits::default());
    assert!(e.unwrap_err().to_string().contains("no point"));
    let stray = Point3::new(2.0, 0.5, 0.0);
    let e = grid_points(
        &[stray],
        (lo, hi),
        0.5,
        Statistic::Max,
        &DemLimits::default(),
    );
    assert!(
        e.unwrap_err()
            .to_string()
            .contains("outside the header's bounds")
    );
    let tight = DemLimits::with_max_cells(3).expect("cap");
    let e = grid_points(&[lo], (lo, hi), 0.5, Statistic::Max, &tight);
    assert!(matches!(e, Err(PointCloudError::Grid(_))));
}
