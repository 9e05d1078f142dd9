//! Seeded random maps for the planner tests: a star-shaped (often non-convex) boundary around a
//! disc of star-shaped obstacles, some non-convex, placed by rejection so that they never touch.

#![allow(dead_code)]

use nalgebra::Point2;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rappel_geometry::map::Map;
use rappel_geometry::polygon::Polygon;

/// A random valid map with a start and a goal in free space, from `seed`.
pub struct RandomMap {
    pub map: Map,
    pub start: Point2<f64>,
    pub goal: Point2<f64>,
}

fn star(rng: &mut ChaCha8Rng, c: Point2<f64>, r: f64, sides: usize, dent: f64) -> Polygon {
    // Evenly spread angles with jitter: every gap is below pi, so the star is simple.
    let step = std::f64::consts::TAU / sides as f64;
    let offset = rng.random_range(0.0..step);
    let angles: Vec<f64> = (0..sides)
        .map(|i| offset + (i as f64 + rng.random_range(-0.3..0.3)) * step)
        .collect();
    Polygon::new(
        angles
            .iter()
            .map(|a| {
                let rr = r * rng.random_range(dent..=1.0);
                Point2::new(c.x + rr * a.cos(), c.y + rr * a.sin())
            })
            .collect(),
    )
}

/// A random map; `None` when the draw happens to be invalid (rare).
pub fn random_map(seed: u64, obstacles: usize) -> Option<RandomMap> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let big = 20.0;
    let boundary = star(&mut rng, Point2::new(0.0, 0.0), big, 14, 0.8);
    let mut discs: Vec<(Point2<f64>, f64)> = Vec::new();
    let mut holes = Vec::new();
    let mut tries = 0;
    while holes.len() < obstacles && tries < 2_000 {
        tries += 1;
        let r = rng.random_range(1.0..3.5);
        let c = Point2::new(rng.random_range(-12.0..12.0), rng.random_range(-12.0..12.0));
        if c.coords.norm() + r > 0.7 * big
            || discs.iter().any(|(d, s)| (d - c).norm() < r + s + 0.3)
        {
            continue;
        }
        let sides = rng.random_range(3..=7usize);
        let dent = if rng.random_range(0.0..1.0) < 0.3 {
            0.35
        } else {
            0.75
        };
        discs.push((c, r));
        holes.push(star(&mut rng, c, r, sides, dent));
    }
    let map = Map::new(boundary, holes);
    map.validate().ok()?;
    let free_point = |rng: &mut ChaCha8Rng| {
        for _ in 0..1_000 {
            let p = Point2::new(rng.random_range(-16.0..16.0), rng.random_range(-16.0..16.0));
            if map.validate_point("point", &p).is_ok() {
                return Some(p);
            }
        }
        None
    };
    let start = free_point(&mut rng)?;
    let mut goal = free_point(&mut rng)?;
    // Now and then a goal on an obstacle vertex: the taut tether ends on a map vertex.
    if seed % 7 == 3 && !map.obstacles.is_empty() {
        goal = map.obstacles[0].vertices[0];
    }
    Some(RandomMap { map, start, goal })
}

/// The square map of the homotopy crate's examples with one obstacle `[x0, x1] x [y0, y1]`.
pub fn one_box(x0: f64, x1: f64, y0: f64, y1: f64) -> Map {
    let p = |x, y| Point2::new(x, y);
    Map::new(
        Polygon::new(vec![p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)]),
        vec![Polygon::new(vec![
            p(x0, y0),
            p(x1, y0),
            p(x1, y1),
            p(x0, y1),
        ])],
    )
}
