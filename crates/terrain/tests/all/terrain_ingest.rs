//! DEM to scenario ingredients (issue 6, deliverable 5; thesis §2.1.3, §2.5.1-2.5.5): the real
//! Mars and Earth grids give sane scenarios (counts printed with `--nocapture`), the map covers
//! the unfolded footprint, planes tile it and are classified by friction, the result is
//! deterministic, and every bad input is a typed error.

use nalgebra::Point2;
use rappel_geometry::map::MapError;
use rappel_terrain::dem::read_dem;
use rappel_terrain::grid::{GridGeometry, HeightGrid};
use rappel_terrain::ingest::{IngestError, IngestOptions, Ingested, ingest};
use rappel_terrain::obstacle_detection::{ObstacleError, ObstacleOptions};
use rappel_terrain::plane_class::PlaneClass;
use rappel_terrain::plane_fit::{PlaneFitError, PlaneFitOptions};
use rappel_terrain::plane_series::validate_planes;
use rappel_terrain::slope::{FallLine, SlopeError};
use rappel_terrain::synthetic::{ProfilePlane, plane_series_dem, textured_wall};

fn fixture(name: &str) -> HeightGrid {
    read_dem(format!(
        "{}/../../fixtures/terrain/{name}",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap()
}

/// Downhill azimuth of the mean gradient estimated independently of Horn's method: the mean
/// forward difference over every pair of neighbouring known cells, east-west and north-south.
fn mean_difference_azimuth(dem: &HeightGrid) -> f64 {
    let g = dem.geometry();
    let (mut gx, mut nx, mut gy, mut ny) = (0.0, 0.0, 0.0, 0.0);
    for r in 0..g.nrows {
        for c in 0..g.ncols {
            let Some(z) = dem.height(r, c) else { continue };
            if let Some(e) = dem.height(r, c + 1) {
                gx += (e - z) / g.cell_x;
                nx += 1.0;
            }
            if let Some(s) = dem.height(r + 1, c) {
                gy += (z - s) / g.cell_y;
                ny += 1.0;
            }
        }
    }
    (-gx / nx).atan2(-gy / ny).to_degrees().rem_euclid(360.0)
}

/// Properties every scenario must have.
fn check_scenario(out: &Ingested, mu: f64) {
    out.map.validate().unwrap();
    validate_planes(&out.planes).unwrap();
    assert_eq!(out.planes.len(), out.plane_fits.len());
    assert_eq!(out.planes.len(), out.plane_classes.len());
    // Convex: going down, no plane is shallower than the one above (signed fall-line gradient).
    for w in out.plane_fits.windows(2) {
        assert!(w[1].fall_line_gradient >= w[0].fall_line_gradient);
    }
    for (p, class) in out.planes.iter().zip(&out.plane_classes) {
        assert_eq!(p.friction, mu);
        let free = mu >= p.slope_deg.to_radians().tan();
        assert_eq!(*class == PlaneClass::TetherFree, free);
    }
    // The planes tile the unfolded footprint of the grid from its top to its bottom, so they cover
    // the map (whose boundary may have been carved).
    let fp = rappel_geometry::polygon::Polygon::new(out.frame.footprint(&out.grid)).aabb();
    assert!((out.planes[0].y_top - fp.max.y).abs() < 1e-6);
    assert!((out.planes.last().unwrap().y_bottom - fp.min.y).abs() < 1e-6);
    let b = out.map.aabb();
    assert!(b.max.y <= fp.max.y + 1e-9 && b.min.y >= fp.min.y - 1e-9);
    // Start near the top, goal near the bottom, both free and clear of robot obstacles.
    let h = b.max.y - b.min.y;
    assert!(out.start.y > b.min.y + 0.5 * h, "start {}", out.start);
    assert!(out.goal.y < b.min.y + 0.5 * h, "goal {}", out.goal);
    for p in [out.start, out.goal] {
        out.map.validate_point("endpoint", &p).unwrap();
        assert!(
            out.robot_obstacles
                .iter()
                .all(|o| o.locate(&p) == rappel_geometry::polygon::PointInPolygon::Outside)
        );
    }
    // The rasters cover the grid.
    for r in [&out.slope_deg, &out.aspect_deg, &out.hillshade] {
        assert_eq!(r.values.len(), out.grid.len());
    }
    // Plane edges drawn over the grid lie on the plane breaks.
    for (e, p) in out
        .plane_edges_world()
        .iter()
        .zip(out.plane_fits.iter().skip(1))
    {
        for w in e {
            assert!((out.frame.horizontal(w).1 - p.s_top).abs() < 1e-6);
        }
    }
}

fn describe(name: &str, out: &Ingested) {
    println!(
        "{name}: fall line {:.1} deg, mean slope {:.1} deg; {:?}",
        out.fall_line.azimuth_deg(),
        out.fall_line.mean_slope_deg,
        out.summary()
    );
    for (p, f) in out.planes.iter().zip(&out.plane_fits) {
        println!(
            "  y {:7.1} .. {:7.1}  slope {:5.2} deg  rms {:5.2} m  {:?}",
            p.y_bottom,
            p.y_top,
            p.slope_deg,
            f.rms_residual_m,
            classify(p.slope_deg)
        );
    }
}

fn classify(slope_deg: f64) -> PlaneClass {
    rappel_terrain::plane_class::classify_plane(slope_deg, 0.4)
}

#[test]
fn mars_hirise_patch() {
    let dem = fixture("mars_hirise_dteec_010228_1490_crop.asc");
    let out = ingest(&dem, &IngestOptions::default()).unwrap();
    describe("Mars HiRISE 1 m", &out);
    check_scenario(&out, 0.4);
    let d = (out.fall_line.azimuth_deg() - mean_difference_azimuth(&dem) + 540.0).rem_euclid(360.0)
        - 180.0;
    assert!(d.abs() < 1.0, "{d}");
    // README: median slope about 22 degrees, steepest about 60.
    let mut s: Vec<f64> = out.slope_deg.values.clone();
    s.sort_by(f64::total_cmp);
    assert!(
        (s[s.len() / 2] - 22.0).abs() < 2.5,
        "median {}",
        s[s.len() / 2]
    );
    assert!(
        (s[s.len() - 1] - 60.0).abs() < 6.0,
        "max {}",
        s[s.len() - 1]
    );
    // A steep patch of 8,400 cells: a few dozen small obstacles of each kind, no unknown terrain,
    // a series of a few planes, tether-free at the top and tether-demand at the bottom.
    let sum = out.summary();
    assert!((2..=8).contains(&sum.planes), "{sum:?}");
    assert!((10..=80).contains(&sum.tether_obstacles), "{sum:?}");
    assert!((10..=80).contains(&sum.robot_obstacles), "{sum:?}");
    assert_eq!(sum.unknown_regions, 0);
    assert_eq!(out.plane_classes[0], PlaneClass::TetherFree);
    assert_eq!(*out.plane_classes.last().unwrap(), PlaneClass::TetherDemand);
    let obstacle_area: f64 = out.map.obstacles.iter().map(|o| o.area()).sum();
    assert!(obstacle_area < 0.05 * out.map.boundary.area());
    // The GeoTIFF copy gives the same scenario (heights agree to float32).
    let tif = ingest(
        &fixture("mars_hirise_dteec_010228_1490_crop.tif"),
        &IngestOptions::default(),
    )
    .unwrap();
    assert_eq!(tif.summary(), sum);
}

#[test]
fn earth_landslide_slope() {
    let dem = fixture("earth_mt_st_helens_landslide_10m.asc");
    let out = ingest(&dem, &IngestOptions::default()).unwrap();
    describe("Earth Mt St Helens 10 m", &out);
    check_scenario(&out, 0.4);
    let d = (out.fall_line.azimuth_deg() - mean_difference_azimuth(&dem) + 540.0).rem_euclid(360.0)
        - 180.0;
    assert!(d.abs() < 1.0, "{d}");
    let sum = out.summary();
    // The NODATA column is one unknown region, on the edge: carved out of the boundary.
    assert_eq!(sum.unknown_regions, 1);
    assert!(!out.normalize_report.carved_into_boundary.is_empty());
    assert!((2..=8).contains(&sum.planes), "{sum:?}");
    assert!(sum.tether_obstacles <= 40, "{sum:?}");
    // At 10 m a pair 3.1 m apart cannot exist: every compatible pair is a step between
    // neighbours, found by the unsampled-face rule alone.
    let strict = IngestOptions {
        obstacles: ObstacleOptions {
            bridge_unsampled_faces: false,
            ..Default::default()
        },
        ..Default::default()
    };
    let none = ingest(&dem, &strict).unwrap();
    assert_eq!(none.detection.compatible_pairs, 0);
    assert!(out.detection.compatible_pairs > 0);
    // Parameters scaled to the grid (ten times the thesis' values) find the landslide's scarps.
    let scaled = IngestOptions {
        obstacles: ObstacleOptions {
            h_min_m: 2.0,
            h_max_m: 20.0,
            ..Default::default()
        },
        ..Default::default()
    };
    let scarps = ingest(&dem, &scaled).unwrap();
    describe("Earth, H_min 2 m, H_max 20 m", &scarps);
    check_scenario(&scarps, 0.4);
}

#[test]
fn map_is_the_unfolded_sampled_footprint() {
    // One 30 degree plane falling south: the map is the rectangle through the outer cell
    // centres, stretched along the fall line by 1 / cos 30.
    let g = GridGeometry::new(41, 21, 2.0, 2.0, 100.0, 100.0).unwrap();
    let south = FallLine::from_azimuth(180.0).unwrap();
    let dem = plane_series_dem(g, &south, 50.0, &[ProfilePlane::new(1e3, 30.0)]).unwrap();
    let out = ingest(&dem, &IngestOptions::default()).unwrap();
    check_scenario(&out, 0.4);
    let want = 40.0 * 80.0 / 30f64.to_radians().cos();
    assert!((out.map.boundary.area() - want).abs() < 1e-6);
    let b = out.map.aabb();
    assert!(b.min.x.abs() < 1e-9 && b.min.y.abs() < 1e-9);
    // The transform round-trips and puts each cell centre where the grid says.
    let p = g.cell_center(7, 3);
    let (r, c) = out.planning_to_grid(&out.frame.to_planning(&p));
    assert!((r - 7.5).abs() < 1e-9 && (c - 3.5).abs() < 1e-9);
}

#[test]
fn planes_are_classified_by_friction() {
    let g = GridGeometry::new(81, 30, 1.0, 1.0, 0.0, 81.0).unwrap();
    let south = FallLine::from_azimuth(180.0).unwrap();
    let planes = [ProfilePlane::new(40.0, 15.0), ProfilePlane::new(40.0, 35.0)];
    let dem = plane_series_dem(g, &south, 900.0, &planes).unwrap();
    for (mu, want) in [
        (0.4, [PlaneClass::TetherFree, PlaneClass::TetherDemand]),
        (0.8, [PlaneClass::TetherFree; 2]),
        (0.1, [PlaneClass::TetherDemand; 2]),
    ] {
        let out = ingest(
            &dem,
            &IngestOptions {
                friction: mu,
                ..Default::default()
            },
        )
        .unwrap();
        check_scenario(&out, mu);
        assert_eq!(out.plane_classes, want);
    }
}

#[test]
fn ingestion_is_deterministic() {
    let dem = fixture("mars_hirise_dteec_010228_1490_crop.asc");
    let a = ingest(&dem, &IngestOptions::default()).unwrap();
    let b = ingest(&dem, &IngestOptions::default()).unwrap();
    assert_eq!(a, b);
}

#[test]
fn large_textured_wall() {
    // The benchmark's input, smaller: a Mars-textured convex wall off the grid axes.
    let mars = fixture("mars_hirise_dteec_010228_1490_crop.asc");
    let dem = textured_wall(&mars, 250, 200).unwrap();
    let out = ingest(&dem, &IngestOptions::default()).unwrap();
    describe("textured wall 250 x 200", &out);
    check_scenario(&out, 0.4);
    assert!((out.fall_line.azimuth_deg() - 200.0).abs() < 5.0);
}

#[test]
fn bad_inputs_are_typed_errors() {
    let dem = fixture("mars_hirise_dteec_010228_1490_crop.asc");
    let with = |o: IngestOptions| ingest(&dem, &o);
    assert_eq!(
        with(IngestOptions {
            friction: -0.1,
            ..Default::default()
        })
        .unwrap_err(),
        IngestError::BadFriction(-0.1)
    );
    assert!(matches!(
        with(IngestOptions {
            obstacles: ObstacleOptions {
                h_max_m: 0.1,
                ..Default::default()
            },
            ..Default::default()
        }),
        Err(IngestError::Obstacles(ObstacleError::BadParameter {
            name: "H_max",
            ..
        }))
    ));
    assert!(matches!(
        with(IngestOptions {
            planes: PlaneFitOptions {
                merge_tolerance_m: -1.0,
                ..Default::default()
            },
            ..Default::default()
        }),
        Err(IngestError::PlaneFit(PlaneFitError::BadTolerance(_)))
    ));
    assert!(matches!(
        with(IngestOptions {
            fall_line_azimuth_deg: Some(f64::INFINITY),
            ..Default::default()
        }),
        Err(IngestError::Slope(SlopeError::BadAzimuth { .. }))
    ));
    // A start inside an obstacle is refused; a free one is kept as given.
    let out = with(IngestOptions::default()).unwrap();
    let inside = out.map.obstacles[0]
        .vertices
        .iter()
        .fold(Point2::origin(), |a, v| {
            a + v.coords / out.map.obstacles[0].len() as f64
        });
    assert!(matches!(
        with(IngestOptions {
            start: Some(inside),
            ..Default::default()
        }),
        Err(IngestError::Map(MapError::PointNotFree {
            what: "start",
            ..
        }))
    ));
    let given = Point2::new(out.start.x + 1.0, out.start.y - 1.0);
    let kept = with(IngestOptions {
        start: Some(given),
        goal: Some(out.goal),
        ..Default::default()
    })
    .unwrap();
    assert_eq!((kept.start, kept.goal), (given, out.goal));

    // Flat ground has no fall line unless one is given.
    let g = GridGeometry::new(20, 20, 1.0, 1.0, 0.0, 20.0).unwrap();
    let flat = HeightGrid::from_fn(g, |_, _, _| Some(3.0)).unwrap();
    assert!(matches!(
        ingest(&flat, &IngestOptions::default()),
        Err(IngestError::Slope(SlopeError::NoFallLine { .. }))
    ));
    let out = ingest(
        &flat,
        &IngestOptions {
            fall_line_azimuth_deg: Some(90.0),
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(out.planes.len(), 1);
    assert_eq!(out.plane_classes[0], PlaneClass::TetherFree);
    // A grid of unknown cells, and a one-row grid, cannot be ingested.
    let unknown = HeightGrid::from_fn(g, |_, _, _| None).unwrap();
    assert!(matches!(
        ingest(&unknown, &IngestOptions::default()),
        Err(IngestError::Slope(SlopeError::NoKnownSlope))
    ));
    let row = GridGeometry::new(1, 30, 1.0, 1.0, 0.0, 1.0).unwrap();
    let line = HeightGrid::from_fn(row, |_, c, _| Some(c as f64)).unwrap();
    assert!(ingest(&line, &IngestOptions::default()).is_err());
}
