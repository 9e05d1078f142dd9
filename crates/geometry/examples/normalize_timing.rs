//! Quick timing of map normalisation on thousands of overlapping obstacle outlines, as obstacle
//! detection produces them (for profiling; correctness is covered by the tests).

use nalgebra::Point2;
use rappel_geometry::map::Map;
use rappel_geometry::normalize::{NormalizeOptions, normalize};
use rappel_geometry::polygon::Polygon;
use std::time::Instant;

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(3000);
    // A deterministic scatter of small squares, many overlapping.
    let mut obstacles = Vec::with_capacity(n);
    for i in 0..n {
        let x = 5.0 + (i as f64 * 0.618_033_988_75).fract() * 490.0;
        let y = 5.0 + (i as f64 * 0.754_877_666_25).fract() * 490.0;
        let s = 1.0 + (i % 7) as f64 * 0.8;
        obstacles.push(Polygon::new(vec![
            Point2::new(x, y),
            Point2::new(x + s, y),
            Point2::new(x + s, y + s),
            Point2::new(x, y + s),
        ]));
    }
    let boundary = Polygon::new(vec![
        Point2::new(0.0, 0.0),
        Point2::new(500.0, 0.0),
        Point2::new(500.0, 500.0),
        Point2::new(0.0, 500.0),
    ]);
    let map = Map::new(boundary, obstacles);
    for hulls in [true, false] {
        let t = Instant::now();
        match normalize(
            &map,
            &NormalizeOptions {
                convex_hulls: hulls,
                carve_boundary: true,
            },
        ) {
            Ok((m, r)) => println!(
                "hulls {hulls}: {} -> {} obstacles ({} merged) in {:?}",
                n,
                m.obstacles.len(),
                r.merged_count(),
                t.elapsed()
            ),
            Err(e) => println!("error: {e}"),
        }
    }
}
