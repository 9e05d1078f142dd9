//! Obstacle detection on slopes (issue 6, deliverable 4; thesis §2.1.2, §2.5.2 after
//! Abad-Manterola and Manduchi et al.), through the whole ingestion: a boulder of known footprint
//! becomes a tether obstacle with exactly that footprint, a pit goes to the robot-obstacle layer,
//! bumps below `H_min` and gentle mounds are not obstacles, steps taller than `H_max` need the
//! unsampled-face rule, non-convex clusters become their hulls, NODATA regions follow the policy,
//! and obstacles at the edge are carved out of the boundary.

use nalgebra::Point2;
use proptest::prelude::*;
use rappel_geometry::polygon::{Polygon, convex_hull};
use rappel_terrain::grid::{GridGeometry, HeightGrid};
use rappel_terrain::ingest::{IngestOptions, Ingested, UnknownPolicy, ingest};
use rappel_terrain::obstacle_detection::{CellClass, ObstacleOptions};
use rappel_terrain::slope::FallLine;
use rappel_terrain::synthetic::{self, ProfilePlane, plane_series_dem};
use std::ops::Range;

/// A 20 degree slope falling south-south-west, 60 x 50 cells of 1 m.
fn slope() -> HeightGrid {
    tilted(190.0, 20.0)
}

/// A plane of `slope_deg` falling towards `azimuth`, 60 x 50 cells of 1 m.
fn tilted(azimuth: f64, slope_deg: f64) -> HeightGrid {
    let g = GridGeometry::new(60, 50, 1.0, 1.0, 0.0, 60.0).unwrap();
    let fall = FallLine::from_azimuth(azimuth).unwrap();
    plane_series_dem(g, &fall, 500.0, &[ProfilePlane::new(1e3, slope_deg)]).unwrap()
}

/// `dem` with a box raised by `rise` (sunk when negative).
fn with_box(dem: &HeightGrid, rows: Range<usize>, cols: Range<usize>, rise: f64) -> HeightGrid {
    synthetic::with_box(dem, rows, cols, rise).unwrap()
}

fn run(dem: &HeightGrid, options: &IngestOptions) -> Ingested {
    let out = ingest(dem, options).unwrap();
    out.map.validate().unwrap();
    out
}

/// The footprint of the cells `rows x cols` in the planning frame of `out`.
fn footprint(out: &Ingested, rows: Range<usize>, cols: Range<usize>) -> Polygon {
    let g = out.grid;
    let pts: Vec<Point2<f64>> = rows
        .flat_map(|r| cols.clone().map(move |c| (r, c)))
        .flat_map(|(r, c)| g.cell_corners(r, c))
        .map(|w| out.frame.to_planning(&w))
        .collect();
    convex_hull(&pts)
}

/// Cells of class `class` lie in `rows x cols` and include its whole rim.
fn check_cells(out: &Ingested, class: CellClass, rows: Range<usize>, cols: Range<usize>) {
    let g = out.grid;
    for i in 0..g.len() {
        let (r, c) = g.row_col(i);
        let inside = rows.contains(&r) && cols.contains(&c);
        let rim = inside
            && (r == rows.start || r + 1 == rows.end || c == cols.start || c + 1 == cols.end);
        let is = out.detection.classes[i] == class;
        assert!(!is || inside, "({r}, {c}) is {class:?} outside");
        assert!(!rim || is, "rim cell ({r}, {c}) is not {class:?}");
    }
}

/// `a` and `b` are the same polygon (same vertex set, to rounding).
fn same_polygon(a: &Polygon, b: &Polygon) {
    assert_eq!(a.len(), b.len(), "{a:?} vs {b:?}");
    for p in &a.vertices {
        assert!(
            b.vertices.iter().any(|q| (p - q).norm() < 1e-9),
            "{p} not in {b:?}"
        );
    }
    assert!((a.area() - b.area()).abs() < 1e-9);
}

#[test]
fn boulder_is_a_tether_obstacle_with_its_footprint() {
    // 1.6 m tall (vertically): 1.5 m across the plane, every face steeper than 40 degrees.
    let dem = with_box(&slope(), 20..24, 15..19, 1.6);
    let out = run(&dem, &IngestOptions::default());
    assert_eq!(out.map.obstacles.len(), 1, "{:?}", out.summary());
    same_polygon(&out.map.obstacles[0], &footprint(&out, 20..24, 15..19));
    assert!(out.robot_obstacles.is_empty());
    // Raised cells: the boulder's whole rim, and nothing outside the boulder (the ground at its
    // foot is an obstacle point but level with the ground).
    check_cells(&out, CellClass::Raised, 20..24, 15..19);
    assert!(out.detection.count(CellClass::Foot) > 0);
    assert_eq!(out.detection.count(CellClass::Sunken), 0);
    // Start and goal avoid it.
    for p in [out.start, out.goal] {
        out.map.validate_point("endpoint", &p).unwrap();
    }
}

#[test]
fn large_flat_topped_boulder_keeps_its_foot_on_the_ground() {
    // Its flat top (not obstacle points) must not be taken for ground around it, or the ground at
    // its foot would seem sunken.
    let dem = with_box(&slope(), 15..27, 12..24, 1.8);
    let out = run(&dem, &IngestOptions::default());
    assert_eq!(out.map.obstacles.len(), 1);
    same_polygon(&out.map.obstacles[0], &footprint(&out, 15..27, 12..24));
    assert_eq!(out.detection.count(CellClass::Sunken), 0);
    assert!(out.robot_obstacles.is_empty());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// Any boulder of 1.6-2 m across the plane, on any slope up to 25 degrees falling any way, is
    /// one tether obstacle with exactly its footprint; a pit of the same shape is one robot
    /// obstacle with its footprint.
    #[test]
    fn any_boulder_or_pit_keeps_its_footprint(
        azimuth in 0.0f64..360.0,
        slope_deg in 8.0f64..25.0,
        r0 in 5usize..40,
        c0 in 5usize..30,
        h in 3usize..12,
        w in 3usize..12,
        rise in 1.8f64..2.0,
    ) {
        let (rows, cols) = (r0..(r0 + h).min(55), c0..(c0 + w).min(45));
        let plane = tilted(azimuth, slope_deg);
        let out = run(&with_box(&plane, rows.clone(), cols.clone(), rise), &IngestOptions::default());
        prop_assert_eq!(out.map.obstacles.len(), 1);
        same_polygon(&out.map.obstacles[0], &footprint(&out, rows.clone(), cols.clone()));
        check_cells(&out, CellClass::Raised, rows.clone(), cols.clone());
        prop_assert!(out.robot_obstacles.is_empty());
        let out = run(&with_box(&plane, rows.clone(), cols.clone(), -rise), &IngestOptions::default());
        prop_assert!(out.map.obstacles.is_empty());
        prop_assert_eq!(out.robot_obstacles.len(), 1);
        same_polygon(&out.robot_obstacles[0], &footprint(&out, rows.clone(), cols.clone()));
        check_cells(&out, CellClass::Sunken, rows, cols);
    }
}

#[test]
fn pit_goes_to_the_robot_obstacle_layer() {
    let dem = with_box(&slope(), 30..34, 20..24, -1.6);
    let out = run(&dem, &IngestOptions::default());
    assert!(out.map.obstacles.is_empty(), "the tether passes over a pit");
    assert_eq!(out.robot_obstacles.len(), 1);
    same_polygon(&out.robot_obstacles[0], &footprint(&out, 30..34, 20..24));
    check_cells(&out, CellClass::Sunken, 30..34, 20..24);
    assert_eq!(out.detection.count(CellClass::Raised), 0);
}

#[test]
fn small_bumps_and_gentle_mounds_are_not_obstacles() {
    // Below H_min across the plane (0.15 m vertical).
    let bump = with_box(&slope(), 20..24, 15..19, 0.15);
    let out = run(&bump, &IngestOptions::default());
    assert_eq!(out.detection.count(CellClass::Raised), 0);
    assert!(out.map.obstacles.is_empty());
    // A 1.5 m mound whose sides are gentle (a cosine bump of 12 m radius).
    let mound = slope()
        .map(|r, c, h| {
            let d = ((r as f64 - 30.0).powi(2) + (c as f64 - 25.0).powi(2)).sqrt();
            h.map(|h| {
                h + if d < 12.0 {
                    0.75 * (1.0 + (d / 12.0 * std::f64::consts::PI).cos())
                } else {
                    0.0
                }
            })
        })
        .unwrap();
    let out = run(&mound, &IngestOptions::default());
    assert_eq!(out.detection.compatible_pairs, 0);
    assert!(out.map.obstacles.is_empty() && out.robot_obstacles.is_empty());
}

#[test]
fn steps_taller_than_h_max_need_the_unsampled_face_rule() {
    let dem = with_box(&slope(), 20..25, 15..21, 4.0);
    let out = run(&dem, &IngestOptions::default());
    assert_eq!(out.map.obstacles.len(), 1);
    same_polygon(&out.map.obstacles[0], &footprint(&out, 20..25, 15..21));
    let strict = IngestOptions {
        obstacles: ObstacleOptions {
            bridge_unsampled_faces: false,
            ..Default::default()
        },
        ..Default::default()
    };
    let out = run(&dem, &strict);
    assert_eq!(
        out.detection.compatible_pairs, 0,
        "no pair within the truncated cone"
    );
    assert!(out.map.obstacles.is_empty());
}

#[test]
fn non_convex_cluster_becomes_its_hull_and_neighbours_stay_apart() {
    // An L-shaped boulder, and a second boulder two cells away from it.
    let l = with_box(
        &with_box(&slope(), 10..20, 10..13, 1.6),
        17..20,
        10..20,
        1.6,
    );
    let dem = with_box(&l, 10..14, 22..26, 1.6);
    let out = run(&dem, &IngestOptions::default());
    assert_eq!(out.map.obstacles.len(), 2, "{:?}", out.summary());
    let hull_l = footprint(&out, 10..20, 10..13);
    let hull_l = convex_hull(&[hull_l.vertices, footprint(&out, 17..20, 10..20).vertices].concat());
    let mut found: Vec<&Polygon> = out.map.obstacles.iter().collect();
    found.sort_by(|a, b| b.area().total_cmp(&a.area()));
    same_polygon(found[0], &hull_l);
    assert!(found[0].is_convex());
    same_polygon(found[1], &footprint(&out, 10..14, 22..26));
}

#[test]
fn overlapping_hulls_are_merged() {
    // Two L-shaped boulders whose hulls overlap though their cells are apart.
    let a = with_box(
        &with_box(&slope(), 10..20, 10..12, 1.6),
        18..20,
        10..20,
        1.6,
    );
    let dem = with_box(&with_box(&a, 10..12, 14..24, 1.6), 10..17, 22..24, 1.6);
    let out = run(&dem, &IngestOptions::default());
    assert_eq!(out.detection.tether_clusters.len(), 2);
    assert_eq!(out.map.obstacles.len(), 1);
    assert_eq!(out.normalize_report.merged_count(), 1);
}

#[test]
fn unknown_regions_follow_the_policy() {
    let dem = slope()
        .map(|r, c, h| {
            if (40..44).contains(&r) && (5..9).contains(&c) {
                None
            } else {
                h
            }
        })
        .unwrap();
    let hole = |out: &Ingested| footprint(out, 40..44, 5..9);
    let with = |unknown| {
        run(
            &dem,
            &IngestOptions {
                unknown,
                ..Default::default()
            },
        )
    };
    let tether = with(UnknownPolicy::TetherObstacle);
    assert_eq!(tether.map.obstacles.len(), 1);
    same_polygon(&tether.map.obstacles[0], &hole(&tether));
    let robot = with(UnknownPolicy::RobotObstacle);
    assert!(robot.map.obstacles.is_empty());
    same_polygon(&robot.robot_obstacles[0], &hole(&robot));
    let ignore = with(UnknownPolicy::Ignore);
    assert!(ignore.map.obstacles.is_empty() && ignore.robot_obstacles.is_empty());
    for out in [&tether, &robot, &ignore] {
        assert_eq!(out.unknown_regions.len(), 1);
        assert_eq!(out.detection.count(CellClass::Unknown), 16);
    }
}

#[test]
fn obstacles_at_the_edge_are_carved_out_of_the_boundary() {
    let plain = run(&slope(), &IngestOptions::default());
    let dem = with_box(&slope(), 25..30, 0..3, 1.6);
    let out = run(&dem, &IngestOptions::default());
    assert!(out.map.obstacles.is_empty());
    assert_eq!(out.normalize_report.carved_into_boundary, vec![0]);
    assert!(out.map.boundary.area() < plain.map.boundary.area() - 5.0);
}
