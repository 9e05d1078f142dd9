//! Tether tracking (Kumar Alg. 1): the 2D consistency property against the homotopy crate's
//! shortest homotopic path (an independent subsystem: crossing sequences, sleeves and funnels) on
//! one plane and on a developable series of planes, and hand cases with known answers.

use nalgebra::Point2;
use proptest::prelude::*;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rappel_geometry::btm::Btm;
use rappel_geometry::map::Map;
use rappel_geometry::polygon::Polygon;
use rappel_homotopy::path::Path;
use rappel_homotopy::shp::shortest_homotopic_path;
use rappel_planners::tether_tracking::{AnchorKind, TetherTracker, TrackError};
use rappel_terrain::plane_series::TerrainPlane;
use rappel_terrain::plane_series_terrain::PlaneSeriesTerrain;
use rappel_terrain::surface::{Prism, Terrain};

const SIZE: f64 = 40.0;

fn p(x: f64, y: f64) -> Point2<f64> {
    Point2::new(x, y)
}

fn prisms(obstacles: &[Polygon]) -> Vec<Prism> {
    obstacles
        .iter()
        .map(|o| Prism {
            surface: 0,
            base: o.clone(),
            height: 1.0,
            friction: 0.4,
        })
        .collect()
}

/// One random triangle in each 10 m cell of a 40 m square (cells keep them disjoint).
fn random_obstacles(rng: &mut ChaCha8Rng) -> Vec<Polygon> {
    let mut out = Vec::new();
    for i in 0..4 {
        for j in 0..4 {
            if rng.random_range(0.0..1.0) < 0.3 {
                continue;
            }
            let (cx, cy) = (10.0 * i as f64 + 5.0, 10.0 * j as f64 + 5.0);
            let a0: f64 = rng.random_range(0.0..std::f64::consts::TAU);
            let pts = (0..3)
                .map(|k| {
                    let a = a0 + k as f64 * 2.1 + rng.random_range(-0.3..0.3);
                    let r = rng.random_range(1.5..3.5);
                    p(cx + r * a.cos(), cy + r * a.sin())
                })
                .collect();
            out.push(Polygon::new(pts).to_counter_clockwise());
        }
    }
    out
}

/// The series used for the developable case: a flat top, then steeper bands (crests).
fn series() -> Vec<TerrainPlane> {
    vec![
        TerrainPlane::new(SIZE, 20.0, 0.0, 0.4),
        TerrainPlane::new(20.0, 10.0, 35.0, 0.4),
        TerrainPlane::new(10.0, 0.0, 60.0, 0.4),
    ]
}

/// Tracks a random walk and compares the final tether with the SHP of the walk.
fn check_walk(seed: u64, planes: &[TerrainPlane], steps: usize) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let obstacles = random_obstacles(&mut rng);
    let terrain = PlaneSeriesTerrain::new(planes, (0.0, SIZE), prisms(&obstacles)).unwrap();
    let map = Map::new(Polygon::rectangle(0.0, 0.0, SIZE, SIZE), obstacles);
    let btm = Btm::from_map(&map).unwrap();
    // Base and start: cell corners are free of obstacles.
    let base = p(10.0, 30.0);
    let mut tracker = TetherTracker::new(&terrain, base, base).unwrap();
    let mut walk = vec![base];
    let mut tries = 0;
    while walk.len() < steps && tries < 20 * steps {
        tries += 1;
        let cur = *walk.last().unwrap();
        let a: f64 = rng.random_range(0.0..std::f64::consts::TAU);
        let r = rng.random_range(0.5..6.0);
        let q = p(cur.x + r * a.cos(), cur.y + r * a.sin());
        if !(q.x > 0.0 && q.x < SIZE && q.y > 0.0 && q.y < SIZE) {
            continue;
        }
        match tracker.step(q) {
            Ok(()) => walk.push(q),
            Err(TrackError::ThroughObstacle { .. }) => continue,
            Err(e) => panic!("seed {seed}: {e}"),
        }
    }
    let shp = shortest_homotopic_path(&btm, &Path::new(walk.clone()).unwrap()).unwrap();
    let config = tracker.configuration();
    let tracked: Vec<Point2<f64>> = config
        .iter()
        .filter(|a| !matches!(a.kind, AnchorKind::Ground { .. }))
        .map(|a| a.point)
        .collect();
    let expected = &shp.taut.points;
    let same = tracked.len() == expected.len()
        && tracked
            .iter()
            .zip(expected)
            .all(|(a, b)| (a - b).norm() <= 1e-9 * SIZE);
    assert!(
        same,
        "seed {seed}: tracked {tracked:?}\n SHP {expected:?}\n walk {walk:?}"
    );
    // Length in the frame equals the SHP's length (unfolding is isometric).
    let frame_len: f64 = tracked.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
    assert!((frame_len - shp.taut.length).abs() <= 1e-9 * shp.taut.length.max(1.0));
    assert!((tracker.length() - shp.taut.length).abs() <= 1e-9 * shp.taut.length.max(1.0));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// On one plane the tracked tether is the SHP of the robot's path (anchors and length).
    #[test]
    fn tracked_tether_is_the_shp_on_a_plane(seed in any::<u64>()) {
        check_walk(seed, &[TerrainPlane::new(SIZE, 0.0, 0.0, 0.4)], 60);
    }

    /// On a developable series of planes the same holds in the unfolded frame, ground anchors aside.
    #[test]
    fn tracked_tether_is_the_shp_on_a_plane_series(seed in any::<u64>()) {
        check_walk(seed, &series(), 60);
    }
}

fn square_terrain(planes: &[TerrainPlane]) -> PlaneSeriesTerrain {
    PlaneSeriesTerrain::new(
        planes,
        (0.0, 20.0),
        prisms(&[Polygon::rectangle(4.0, 4.0, 2.0, 2.0)]),
    )
    .unwrap()
}

fn flat() -> Vec<TerrainPlane> {
    vec![TerrainPlane::new(20.0, 0.0, 0.0, 0.4)]
}

#[test]
fn a_corner_passed_on_the_left_and_on_the_right() {
    let t = square_terrain(&flat());
    // West of the square: the tether from (5, 0) catches corner (4, 4), turning clockwise.
    let mut tr = TetherTracker::new(&t, p(5.0, 0.0), p(3.0, 2.0)).unwrap();
    tr.step(p(3.0, 10.0)).unwrap();
    let a = tr.obstacle_anchors();
    assert_eq!(a.len(), 1);
    assert_eq!(a[0].point, p(4.0, 4.0));
    assert!(matches!(
        a[0].kind,
        AnchorKind::Obstacle { left: false, .. }
    ));
    let want = 17f64.sqrt() + 37f64.sqrt();
    assert!((tr.length() - want).abs() < 1e-12);
    // East: corner (6, 4), counter-clockwise.
    let mut tr = TetherTracker::new(&t, p(5.0, 0.0), p(7.0, 2.0)).unwrap();
    tr.step(p(7.0, 10.0)).unwrap();
    let a = tr.obstacle_anchors();
    assert_eq!(a.len(), 1);
    assert_eq!(a[0].point, p(6.0, 4.0));
    assert!(matches!(a[0].kind, AnchorKind::Obstacle { left: true, .. }));
    // Going over the top: both upper-left corner and upper right are wound.
    tr.step(p(3.0, 10.0)).unwrap();
    tr.step(p(3.0, 2.0)).unwrap();
    let pts: Vec<_> = tr.obstacle_anchors().iter().map(|a| a.point).collect();
    assert_eq!(pts, vec![p(6.0, 4.0), p(6.0, 6.0), p(4.0, 6.0)]);
}

#[test]
fn a_detour_returning_leaves_no_anchor() {
    let t = square_terrain(&flat());
    let mut tr = TetherTracker::new(&t, p(5.0, 0.0), p(3.0, 2.0)).unwrap();
    tr.follow(&[p(3.0, 10.0), p(5.0, 12.0), p(3.0, 10.0), p(3.0, 2.0)])
        .unwrap();
    assert!(tr.obstacle_anchors().is_empty());
    assert!((tr.length() - 8f64.sqrt()).abs() < 1e-12);
}

#[test]
fn a_ground_anchor_appears_and_slides_at_a_crest_and_none_at_a_valley() {
    // Flat above y = 10, 30 degrees below: a crest.
    let crest = [
        TerrainPlane::new(20.0, 10.0, 0.0, 0.4),
        TerrainPlane::new(10.0, 0.0, 30.0, 0.5),
    ];
    let t = PlaneSeriesTerrain::new(&crest, (0.0, 20.0), vec![]).unwrap();
    let mut tr = TetherTracker::new(&t, p(5.0, 15.0), p(5.0, 12.0)).unwrap();
    assert_eq!(tr.configuration().len(), 2);
    tr.step(p(5.0, 5.0)).unwrap();
    let c = tr.configuration();
    assert_eq!(c.len(), 3);
    assert!(matches!(c[1].kind, AnchorKind::Ground { edge: 0 }));
    assert_eq!(c[1].point, p(5.0, 10.0));
    // Straight down the fall line the tether bends by the slope change, 30 degrees, with the
    // smaller friction of the two planes.
    let w = tr.windings();
    assert_eq!(w.len(), 1);
    assert!((w[0].1 - 30f64.to_radians()).abs() < 1e-12);
    assert_eq!(w[0].0, 0.4);
    // The anchor slides along the edge: the frame line from (5, 15) to (1, 5) crosses y = 10 at 3.
    tr.step(p(1.0, 5.0)).unwrap();
    let c = tr.configuration();
    assert!((c[1].point - p(3.0, 10.0)).norm() < 1e-12);
    // Back up onto the flat: the ground anchor is gone.
    tr.step(p(1.0, 12.0)).unwrap();
    assert_eq!(tr.configuration().len(), 2);

    // 30 degrees above y = 10, flat below: a valley, no ground anchor.
    let valley = [
        TerrainPlane::new(20.0, 10.0, 30.0, 0.4),
        TerrainPlane::new(10.0, 0.0, 0.0, 0.4),
    ];
    let t = PlaneSeriesTerrain::new(&valley, (0.0, 20.0), vec![]).unwrap();
    let mut tr = TetherTracker::new(&t, p(5.0, 15.0), p(5.0, 12.0)).unwrap();
    tr.step(p(5.0, 5.0)).unwrap();
    assert_eq!(tr.configuration().len(), 2);
    assert!(tr.windings().is_empty());
}

#[test]
fn winding_twice_around_an_obstacle_matches_the_shp() {
    let obstacles = [Polygon::rectangle(4.0, 4.0, 2.0, 2.0)];
    let t = PlaneSeriesTerrain::new(&flat(), (0.0, 20.0), prisms(&obstacles)).unwrap();
    let base = p(5.0, 1.0);
    let ring = [p(8.0, 2.0), p(8.0, 8.0), p(2.0, 8.0), p(2.0, 2.0)];
    let mut walk = vec![base];
    for _ in 0..2 {
        walk.extend(ring);
    }
    walk.push(p(5.0, 2.0));
    let mut tr = TetherTracker::new(&t, base, base).unwrap();
    tr.follow(&walk).unwrap();
    let btm = Btm::from_map(&Map::new(
        Polygon::rectangle(0.0, 0.0, 20.0, 20.0),
        obstacles.to_vec(),
    ))
    .unwrap();
    let shp = shortest_homotopic_path(&btm, &Path::new(walk).unwrap()).unwrap();
    let tracked: Vec<_> = tr.configuration().iter().map(|a| a.point).collect();
    assert_eq!(tracked, shp.taut.points);
    assert_eq!(tr.obstacle_anchors().len(), 8);
    // Two full turns: the turning angles add up to 4 pi minus the open ends' deficit.
    let total: f64 = tr.windings().iter().map(|w| w.1).sum();
    let shp_total: f64 = shp.taut.anchors.iter().map(|a| a.turning_angle).sum();
    assert!((total - shp_total).abs() < 1e-9);
    assert!(total > 3.0 * std::f64::consts::PI);
}

#[test]
fn bad_steps_are_positioned_errors() {
    let t = square_terrain(&flat());
    let mut tr = TetherTracker::new(&t, p(5.0, 0.0), p(3.0, 2.0)).unwrap();
    assert!(matches!(
        tr.step(p(7.0, 5.0)),
        Err(TrackError::ThroughObstacle { obstacle: 0, .. })
    ));
    assert!(matches!(
        tr.step(p(30.0, 5.0)),
        Err(TrackError::OffTerrain { .. })
    ));
    assert!(matches!(
        tr.step(p(f64::NAN, 5.0)),
        Err(TrackError::NonFinite { .. })
    ));
    assert!(matches!(
        tr.step(p(5.0, 5.0)),
        Err(TrackError::ThroughObstacle { .. })
    ));
    // A failed step leaves the tracker where it was.
    assert_eq!(tr.robot(), p(3.0, 2.0));
    assert_eq!(t.surface_count(), 1);
}

// Exact attach and release (issue 29 §4): steps through obstacle corners, along obstacle sides and
// within an ulp of a corner, checked against the homotopy crate's SHP of the walked path (crossing
// sequences, sleeves and the funnel: exact, and independent of the tracker's incremental updates).

/// The walk `base -> walk[0] -> ...` tracked on a flat map with `obstacles`, against the SHP of the
/// same walk: the same points (repeated and straight-through points dropped on both sides; anchors
/// are obstacle corners, so they compare exactly) and the same length.
fn check_against_shp(obstacles: &[Polygon], size: f64, base: Point2<f64>, walk: &[Point2<f64>]) {
    let planes = [TerrainPlane::new(size, 0.0, 0.0, 0.4)];
    let terrain = PlaneSeriesTerrain::new(&planes, (0.0, size), prisms(obstacles)).unwrap();
    let mut tracker = TetherTracker::new(&terrain, base, base).unwrap();
    tracker.follow(walk).unwrap();
    let map = Map::new(Polygon::rectangle(0.0, 0.0, size, size), obstacles.to_vec());
    let btm = Btm::from_map(&map).unwrap();
    let full: Vec<Point2<f64>> = std::iter::once(base).chain(walk.iter().copied()).collect();
    let shp = shortest_homotopic_path(&btm, &Path::new(full.clone()).unwrap()).unwrap();
    let tracked = taut_points(tracker.configuration().iter().map(|a| a.point));
    let expected = taut_points(shp.taut.points.iter().copied());
    assert_eq!(
        tracked, expected,
        "tracked tether differs from the SHP of the walk {full:?} (obstacles {obstacles:?})"
    );
    assert!((tracker.length() - shp.taut.length).abs() <= 1e-9 * shp.taut.length.max(1.0));
}

/// A polyline without repeated points and without points passed straight through (exact: a point
/// on the closed segment between its neighbours). A point where the line doubles back stays.
fn taut_points(points: impl Iterator<Item = Point2<f64>>) -> Vec<Point2<f64>> {
    let mut out: Vec<Point2<f64>> = Vec::new();
    for q in points {
        if out.last() == Some(&q) {
            continue;
        }
        while out.len() >= 2 {
            let (a, b) = (out[out.len() - 2], out[out.len() - 1]);
            if rappel_geometry::predicates::point_on_segment(&a, &q, &b) {
                out.pop();
            } else {
                break;
            }
        }
        out.push(q);
    }
    out
}

/// The square `[4, 6]^2` of the hand cases above, as a polygon list.
fn square() -> Vec<Polygon> {
    vec![Polygon::rectangle(4.0, 4.0, 2.0, 2.0)]
}

#[test]
fn a_step_along_an_obstacle_side_and_through_the_anchor_releases_it() {
    // Wrapped clockwise at (4, 4), the robot walks down the square's west side, through the
    // anchor, to (4, 0): the tether is straight again.
    let walk = [p(3.0, 2.0), p(3.0, 10.0), p(4.0, 8.0), p(4.0, 0.0)];
    check_against_shp(&square(), 20.0, p(5.0, 0.0), &walk);
    let t = square_terrain(&flat());
    let mut tr = TetherTracker::new(&t, p(5.0, 0.0), p(3.0, 2.0)).unwrap();
    tr.follow(&walk[1..]).unwrap();
    assert!(tr.obstacle_anchors().is_empty());
    assert_eq!(tr.length(), 1.0);
}

#[test]
fn a_step_through_the_anchor_corner_releases_it() {
    // The step (3.5, 8) -> (4.25, 2) passes exactly through the anchor (4, 4) on a supporting
    // line of the square, crossing the release ray there: the wrap is released, as it is for the
    // same step moved off the corner.
    let walk = [p(3.0, 2.0), p(3.0, 10.0), p(3.5, 8.0), p(4.25, 2.0)];
    check_against_shp(&square(), 20.0, p(5.0, 0.0), &walk);
    let walk = [
        p(3.0, 2.0),
        p(3.0, 10.0),
        p(3.5, 8.0),
        p(4.25, 2.0),
        p(9.0, 1.0),
    ];
    check_against_shp(&square(), 20.0, p(5.0, 0.0), &walk);
}

#[test]
fn a_step_along_an_obstacle_side_wraps_both_its_corners_in_turn() {
    // The robot walks east along the top side of the square [-1, 1] x [8, 10] (shifted into the
    // map): the tether from the base below catches the bottom-left corner, then the top-left one
    // where the robot passes it, and runs along the side to the robot.
    let obstacles = vec![Polygon::rectangle(9.0, 8.0, 2.0, 2.0)];
    check_against_shp(
        &obstacles,
        20.0,
        p(10.0, 0.0),
        &[p(5.0, 10.0), p(15.0, 10.0)],
    );
    // Back west along the side: both corners are released.
    check_against_shp(
        &obstacles,
        20.0,
        p(10.0, 0.0),
        &[p(5.0, 10.0), p(15.0, 10.0), p(5.0, 10.0)],
    );
}

#[test]
fn a_robot_stopping_on_a_corner_and_leaving_round_it_wraps_it() {
    // The robot stops exactly on the top-left corner of the square, then walks round it east.
    check_against_shp(
        &square(),
        20.0,
        p(2.0, 1.0),
        &[p(2.0, 6.0), p(4.0, 6.0), p(5.0, 8.0)],
    );
    // Stopping on the anchor itself, then leaving on either side of its release ray.
    for q in [
        p(2.0, 9.0),
        p(3.0, 10.0),
        p(3.0, 2.0),
        p(4.0, 0.0),
        p(1.0, 4.0),
    ] {
        check_against_shp(
            &square(),
            20.0,
            p(5.0, 0.0),
            &[p(3.0, 2.0), p(3.0, 10.0), p(4.0, 4.0), q],
        );
    }
}

/// The walk of the hand case above whose last step passes through the anchor (4, 4), rotated by
/// `turn` about (10, 10) and moved to the centre of a 40 m map and with that last step moved off the corner by `offset` (outwards, away
/// from the square), as the rounded coordinates give it: `(square, base, walk)`.
fn near_corner_case(turn: f64, offset: f64) -> (Polygon, Point2<f64>, Vec<Point2<f64>>) {
    let (c, s) = (turn.cos(), turn.sin());
    let r = |x: f64, y: f64| {
        p(
            20.0 + c * (x - 10.0) - s * (y - 10.0),
            20.0 + s * (x - 10.0) + c * (y - 10.0),
        )
    };
    let o = offset / 2f64.sqrt();
    let square = Polygon::new(vec![r(4.0, 4.0), r(6.0, 4.0), r(6.0, 6.0), r(4.0, 6.0)]);
    let walk = vec![
        r(3.0, 2.0),
        r(3.0, 10.0),
        r(3.5 - o, 8.0 - o),
        r(4.25 - o, 2.0 - o),
    ];
    (square, r(5.0, 0.0), walk)
}

#[test]
fn a_step_passing_within_an_ulp_of_the_anchor_releases_it_exactly_when_it_should() {
    // Issue 29 §4: a step passing 1e-15 outside the top anchor corner, across its release ray.
    // The rounded intersection with the release ray can land behind the corner; the exact
    // decision releases the wrap (and the SHP of the walk agrees), whatever the rounding.
    let mut rng = ChaCha8Rng::seed_from_u64(29);
    let mut checked = 0;
    for _ in 0..400 {
        let turn = rng.random_range(0.0..std::f64::consts::TAU);
        let offset = rng.random_range(-2e-15..2e-15);
        let (square, base, walk) = near_corner_case(turn, offset);
        let planes = [TerrainPlane::new(SIZE, 0.0, 0.0, 0.4)];
        let terrain =
            PlaneSeriesTerrain::new(&planes, (0.0, SIZE), prisms(std::slice::from_ref(&square)))
                .unwrap();
        let mut tr = TetherTracker::new(&terrain, base, base).unwrap();
        // Rounding may put the step through the square's interior: refused, not tracked.
        if tr.follow(&walk).is_err() {
            continue;
        }
        check_against_shp(&[square], SIZE, base, &walk);
        checked += 1;
    }
    assert!(checked > 100, "{checked} cases checked");
}

/// A random map on a 1/64 grid: up to four obstacles (rectangles and triangles with integer
/// corners, one in each 8 m cell of a 16 m square, clear of the cells' borders), so that steps
/// between grid points pass exactly through corners and along sides.
fn dyadic_obstacles(rng: &mut ChaCha8Rng) -> Vec<Polygon> {
    let mut out = Vec::new();
    for (i, j) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
        if rng.random_range(0.0..1.0) < 0.2 {
            continue;
        }
        let (cx, cy) = (8.0 * i as f64, 8.0 * j as f64);
        let coord = |r: &mut ChaCha8Rng, c: f64| c + r.random_range(1..=7) as f64;
        let poly = if rng.random_range(0.0..1.0) < 0.5 {
            let (x0, x1) = (coord(rng, cx), coord(rng, cx));
            let (y0, y1) = (coord(rng, cy), coord(rng, cy));
            if x0 == x1 || y0 == y1 {
                continue;
            }
            Polygon::rectangle(x0.min(x1), y0.min(y1), (x1 - x0).abs(), (y1 - y0).abs())
        } else {
            let pts: Vec<_> = (0..3).map(|_| p(coord(rng, cx), coord(rng, cy))).collect();
            if rappel_geometry::predicates::orient2d(&pts[0], &pts[1], &pts[2]) == 0.0 {
                continue;
            }
            Polygon::new(pts).to_counter_clockwise()
        };
        out.push(poly);
    }
    out
}

/// A random walk on the 1/64 grid from the map's centre: mostly integer points (through corners
/// and along sides), some obstacle corners themselves, some repeated points, some off the integer
/// grid; steps the tracker refuses (through an obstacle) are skipped. Checked against the SHP.
fn check_dyadic_walk(seed: u64, steps: usize) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let obstacles = dyadic_obstacles(&mut rng);
    let corners: Vec<Point2<f64>> = obstacles.iter().flat_map(|o| o.vertices.clone()).collect();
    let planes = [TerrainPlane::new(16.0, 0.0, 0.0, 0.4)];
    let terrain = PlaneSeriesTerrain::new(&planes, (0.0, 16.0), prisms(&obstacles)).unwrap();
    let base = p(8.0, 8.0);
    let mut tracker = TetherTracker::new(&terrain, base, base).unwrap();
    let mut walk = Vec::new();
    let mut tries = 0;
    while walk.len() < steps && tries < 20 * steps {
        tries += 1;
        let cur = *walk.last().unwrap_or(&base);
        let roll = rng.random_range(0.0..1.0);
        let q = if roll < 0.1 {
            cur
        } else if roll < 0.3 && !corners.is_empty() {
            corners[rng.random_range(0..corners.len())]
        } else if roll < 0.85 {
            p(
                rng.random_range(1..=15) as f64,
                rng.random_range(1..=15) as f64,
            )
        } else {
            let g = |r: &mut ChaCha8Rng| r.random_range(64..=15 * 64) as f64 / 64.0;
            p(g(&mut rng), g(&mut rng))
        };
        match tracker.step(q) {
            Ok(()) => walk.push(q),
            Err(TrackError::ThroughObstacle { .. }) => continue,
            Err(e) => panic!("seed {seed}: {e}"),
        }
        // Every prefix: the first step that goes wrong is the one reported.
        check_against_shp(&obstacles, 16.0, base, &walk);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// On a 1/64 grid, with steps through corners, along sides and onto corners, and repeated
    /// points, the tracked tether is the SHP of the walk.
    #[test]
    fn tracked_tether_is_the_shp_on_a_dyadic_grid(seed in any::<u64>()) {
        check_dyadic_walk(seed, 40);
    }
}

/// Dyadic walks that went wrong while the exact decisions were written (a corner on the step
/// with its obstacle beyond it, a robot leaving a corner it stands on away from its obstacle).
#[test]
fn dyadic_walks_that_went_wrong() {
    for seed in [213305290714261695, 0, 1, 2, 3] {
        check_dyadic_walk(seed, 40);
    }
}

/// Kumar's two robots on `terrain` (his scene): Robot 1 holding with `μ` 0.4 and 35 kg, Robot 2
/// the default four-wheel rover `rover`, tracked with `model`.
fn kumar_two_robots<'a>(
    terrain: &'a PlaneSeriesTerrain,
    rover: &'a rappel_mechanics::four_wheel::FourWheelRover,
    model: rappel_planners::tether_tracking::two_robots::TrackModel,
) -> rappel_planners::tether_tracking::two_robots::TwoRobots<'a, PlaneSeriesTerrain> {
    use rappel_mechanics::robot::{RobotModel, STANDARD_GRAVITY};
    rappel_planners::tether_tracking::two_robots::TwoRobots {
        terrain,
        holding: rappel_mechanics::tension_limit::HoldingRobot {
            max_pull: 0.0,
            friction: 0.4,
            mass: 35.0,
        },
        gravity: STANDARD_GRAVITY,
        robot2: rover as &dyn RobotModel,
        tether_height: rover.params().tether_exit.z,
        model,
    }
}

/// Kumar's text against rappel's model on Kumar's scene (Fig. 5a: Robot 1 partly round O2;
/// Robot 2's last anchor O2's corner (4, 19)), Robot 2 at (2, 10.5) on S1, 5.5 m below the crest,
/// `θ = atan(2 / 8.5)` off its anchor's line in the unfolding. Independent closed forms: with
/// ground anchors at valleys no anchor lies on this convex hillside, so the tether is the straight
/// 3D line from the corner (the literal reading: "no changes are made") and `T_2max =
/// μ m_1 g exp(0.4 (φ_(4,21) + φ_(4,19)))` with the angles of that polyline; Kumar's free body
/// with eq. 3c needs `G cos θ - μN` (`G sin θ <= μN`).
#[test]
fn kumars_reading_valley_anchors_and_free_body_against_rappels_model() {
    use nalgebra::Vector3;
    use rappel_mechanics::four_wheel::FourWheelRover;
    use rappel_mechanics::robot::STANDARD_GRAVITY;
    use rappel_planners::tether_tracking::GroundAnchorEdges;
    use rappel_planners::tether_tracking::two_robots::{Robot2Contact, TrackModel};
    let terrain = rappel_terrain::kumar::kumar_scene().unwrap();
    let rover = FourWheelRover::default();
    let two = |model| kumar_two_robots(&terrain, &rover, model);
    let path1 = [p(5.0, 18.0), p(5.0, 23.0), p(3.0, 23.0)];
    let path2 = [p(3.0, 17.0), p(2.0, 16.0), p(2.0, 10.5)];
    let at = |model| two(model).run(&path1, &path2).unwrap().pop().unwrap();
    let crests = at(TrackModel::default());
    let valleys = at(TrackModel {
        ground_anchors: GroundAnchorEdges::Valleys,
        ..TrackModel::default()
    });
    let kumar = at(TrackModel::kumar());
    let n = kumar.configuration.len();
    assert_eq!(kumar.configuration[n - 2].point, p(4.0, 19.0));
    // Crests: the S0/S1 crest is a ground anchor that adds capstan gain; valleys: none.
    assert!(crests.ground_anchored && crests.t2max_n > crests.t2max_obstacles_n * 1.01);
    assert!(!valleys.ground_anchored && !kumar.ground_anchored);
    assert_eq!(valleys.t2max_n, valleys.t2max_obstacles_n);
    // T2max of the straight 3D tether (4, 21) -> (4, 19) -> Robot 2, folded by hand: S1 falls
    // at 55 degrees from the crest y = 16.
    let eta = 55f64.to_radians();
    let d = 16.0 - 10.5;
    let robot = Vector3::new(2.0, 16.0 - d * eta.cos(), -d * eta.sin());
    let angle = |u: Vector3<f64>, v: Vector3<f64>| (u.dot(&v) / (u.norm() * v.norm())).acos();
    let phi = angle(Vector3::new(1.0, -2.0, 0.0), Vector3::new(0.0, -2.0, 0.0))
        + angle(
            Vector3::new(0.0, -2.0, 0.0),
            robot - Vector3::new(4.0, 19.0, 0.0),
        );
    let t1 = 0.4 * 35.0 * STANDARD_GRAVITY;
    let t2max = t1 * (0.4 * phi).exp();
    assert!(
        (kumar.t2max_n - t2max).abs() < 1e-9 * t2max,
        "{} vs {t2max}",
        kumar.t2max_n
    );
    // Kumar's free body: the closed form of eq. 3c, below the limit here.
    let w = 35.0 * STANDARD_GRAVITY;
    let theta = (2.0f64 / 8.5).atan();
    let (g, mu_n) = (w * eta.sin(), 0.4 * w * eta.cos());
    assert!(g * theta.sin() <= mu_n);
    let want = g * theta.cos() - mu_n;
    assert!(want < t2max);
    assert!(
        kumar.stable,
        "Kumar's free body holds at {want} N <= {t2max} N"
    );
    let t = kumar.required_tension_n.unwrap();
    assert!((t - want).abs() < 1e-6 * w, "{t} vs {want}");
    // The wheeled rover in the same tether needs more, or is refused.
    assert!(!valleys.stable || valleys.required_tension_n.unwrap() > want);
    // The free body alone (crest anchors kept) holds too, with the crest's gain in the limit.
    let body = at(TrackModel {
        robot2: Robot2Contact::Body,
        ..TrackModel::default()
    });
    assert!(body.stable && body.ground_anchored);
}

/// Each robot is blamed for its own input, by the tracker's typed subject: on Kumar's scene
/// (O2 the square [2, 4] x [19, 21]), Robot 2's start off the terrain is Robot 2's, Robot 1's start
/// inside O2 and an initial tether through O2 are Robot 1's, and Robot 2's step through O2 is its
/// step 0; each message names the point as the user gave it.
#[test]
fn two_robots_blame_the_robot_whose_input_is_refused() {
    use rappel_mechanics::four_wheel::FourWheelRover;
    use rappel_planners::tether_tracking::TrackSubject;
    use rappel_planners::tether_tracking::two_robots::{TrackModel, TwoRobotError};
    let terrain = rappel_terrain::kumar::kumar_scene().unwrap();
    let rover = FourWheelRover::default();
    let two = kumar_two_robots(&terrain, &rover, TrackModel::default());
    let blame = |path1: &[Point2<f64>], path2: &[Point2<f64>]| match two.run(path1, path2) {
        Err(e @ TwoRobotError::Track { .. }) => {
            let TwoRobotError::Track { robot, source } = &e else {
                unreachable!()
            };
            (*robot, source.what(), e.to_string())
        }
        other => panic!("expected a tracking error, got {other:?}"),
    };
    let path1 = [p(5.0, 18.0), p(5.0, 23.0), p(3.0, 23.0)];
    let (robot, what, text) = blame(&path1, &[p(20.0, 10.0)]);
    assert_eq!((robot, what), (2, Some(TrackSubject::Named("the start"))));
    assert!(text.starts_with("robot 2: the start (20, 10)"), "{text}");
    let (robot, what, _) = blame(&[p(3.0, 20.0)], &[p(3.0, 17.0)]);
    assert_eq!((robot, what), (1, Some(TrackSubject::Named("the start"))));
    let (robot, what, text) = blame(&[p(3.0, 23.0)], &[p(3.0, 17.0)]);
    assert_eq!(
        (robot, what),
        (
            1,
            Some(TrackSubject::Named("the tether from Robot 2's start"))
        )
    );
    assert!(text.contains("passes through obstacle 1"), "{text}");
    let (robot, what, text) = blame(&path1, &[p(3.0, 17.0), p(3.0, 22.0)]);
    assert_eq!((robot, what), (2, Some(TrackSubject::Step(0))));
    assert_eq!(text, "robot 2: step 0 passes through obstacle 1");
}
