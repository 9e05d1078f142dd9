//! Regions with holes and the free part of a polygon: `polygon ∩ boundary − obstacles`, the last
//! ingredient of an anchor reachable set (thesis Def. 2.1: the set lies in free space). Polygon
//! boolean operations are commodity work done by `i_overlay` through [`crate::overlay`] (which
//! snaps to its 64-bit integer grid spanning the input; the result is for reporting and drawing,
//! not for exact decisions).

use crate::overlay::{OverlayError, OverlayRule, overlay};
use crate::polygon::{Aabb, Polygon};
use nalgebra::Point2;
use serde::{Deserialize, Serialize};

/// A polygon with holes: an outer ring (counter-clockwise) and holes (clockwise).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Region {
    /// The outer ring.
    pub outer: Polygon,
    /// The holes.
    #[serde(default)]
    pub holes: Vec<Polygon>,
}

impl Region {
    /// Area: the outer ring's minus the holes'.
    pub fn area(&self) -> f64 {
        self.outer.area() - self.holes.iter().map(Polygon::area).sum::<f64>()
    }
}

fn contour(p: &Polygon) -> Vec<[f64; 2]> {
    p.vertices.iter().map(|v| [v.x, v.y]).collect()
}

fn ring(c: &[[f64; 2]]) -> Polygon {
    Polygon::new(c.iter().map(|p| Point2::new(p[0], p[1])).collect())
}

/// The part of `polygon` inside `boundary` and outside every obstacle, as regions with holes.
/// Obstacles whose bounding box misses the polygon's are skipped without being looked at.
///
/// ```
/// use nalgebra::Point2;
/// use rappel_geometry::polygon::Polygon;
/// use rappel_geometry::region::free_part;
/// let sq = |x: f64, y: f64, s: f64| Polygon::new(vec![
///     Point2::new(x, y), Point2::new(x + s, y), Point2::new(x + s, y + s), Point2::new(x, y + s)]);
/// let parts = free_part(&sq(0., 0., 10.), &sq(-5., -5., 100.), [&sq(4., 4., 2.)]);
/// let parts = parts.unwrap();
/// assert_eq!(parts.len(), 1);
/// assert_eq!(parts[0].holes.len(), 1);
/// assert!((parts[0].area() - 96.0).abs() < 1e-6);
/// ```
pub fn free_part<'a>(
    polygon: &Polygon,
    boundary: &Polygon,
    obstacles: impl IntoIterator<Item = &'a Polygon>,
) -> Result<Vec<Region>, OverlayError> {
    let bbox: Aabb = polygon.aabb();
    let inside = overlay(
        &vec![contour(polygon)],
        &vec![contour(boundary)],
        OverlayRule::Intersect,
    )?;
    let near: Vec<Vec<[f64; 2]>> = obstacles
        .into_iter()
        .filter(|o| o.aabb().intersects(&bbox))
        .map(contour)
        .collect();
    let shapes = if near.is_empty() {
        inside
    } else {
        let subject: Vec<Vec<[f64; 2]>> = inside.into_iter().flatten().collect();
        overlay(&subject, &near, OverlayRule::Difference)?
    };
    Ok(shapes
        .iter()
        .filter_map(|shape| {
            let (outer, holes) = shape.split_first()?;
            Some(Region {
                outer: ring(outer),
                holes: holes.iter().map(|h| ring(h)).collect(),
            })
        })
        .filter(|r| r.outer.len() >= 3)
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sq(x: f64, y: f64, s: f64) -> Polygon {
        Polygon::rectangle(x, y, s, s)
    }

    #[test]
    fn an_obstacle_across_the_polygon_splits_it() {
        // A 10 x 10 square cut by a wall obstacle from y = 4 to 6 spanning it: two 10 x 4 parts.
        let wall = Polygon::new(vec![
            Point2::new(-1., 4.),
            Point2::new(11., 4.),
            Point2::new(11., 6.),
            Point2::new(-1., 6.),
        ]);
        let parts = free_part(&sq(0., 0., 10.), &sq(-5., -5., 100.), [&wall]).unwrap();
        assert_eq!(parts.len(), 2);
        for p in &parts {
            assert!((p.area() - 40.0).abs() < 1e-6);
        }
    }

    #[test]
    fn the_boundary_clips_and_far_obstacles_are_ignored() {
        let parts = free_part(&sq(0., 0., 10.), &sq(5., -5., 100.), [&sq(50., 50., 1.)]).unwrap();
        assert_eq!(parts.len(), 1);
        assert!((parts[0].area() - 50.0).abs() < 1e-6);
        assert!(parts[0].holes.is_empty());
    }
}
