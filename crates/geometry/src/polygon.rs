//! Simple polygons (rings) in the planar map frame: area, exact orientation, exact point-in-polygon,
//! bounding boxes and convex hulls. A ring lists its vertices once each, without repeating the first
//! at the end; either orientation is accepted on input.

use crate::predicates::{orient2d, point_on_segment};
use nalgebra::Point2;
use serde::{Deserialize, Serialize};

/// A closed polygonal ring: the outer boundary of a map or an obstacle.
///
/// ```
/// use nalgebra::Point2;
/// use rappel_geometry::polygon::Polygon;
/// let square = Polygon::new(vec![
///     Point2::new(0.0, 0.0), Point2::new(2.0, 0.0), Point2::new(2.0, 2.0), Point2::new(0.0, 2.0),
/// ]);
/// assert_eq!(square.area(), 4.0);
/// assert!(square.is_counter_clockwise());
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct Polygon {
    /// The vertices in order, first not repeated at the end.
    pub vertices: Vec<Point2<f64>>,
}

/// Where a point lies with respect to a ring.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PointInPolygon {
    /// Strictly inside.
    Inside,
    /// On an edge or a vertex.
    OnBoundary,
    /// Strictly outside.
    Outside,
}

/// An axis-aligned bounding box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    /// Lower-left corner.
    pub min: Point2<f64>,
    /// Upper-right corner.
    pub max: Point2<f64>,
}

impl Aabb {
    /// The smallest box holding every point (an inverted empty box for no points).
    pub fn of_points<'a>(points: impl IntoIterator<Item = &'a Point2<f64>>) -> Self {
        let mut b = Aabb {
            min: Point2::new(f64::INFINITY, f64::INFINITY),
            max: Point2::new(f64::NEG_INFINITY, f64::NEG_INFINITY),
        };
        for p in points {
            b.min.x = b.min.x.min(p.x);
            b.min.y = b.min.y.min(p.y);
            b.max.x = b.max.x.max(p.x);
            b.max.y = b.max.y.max(p.y);
        }
        b
    }

    /// `true` when the closed boxes share a point.
    pub fn intersects(&self, other: &Aabb) -> bool {
        self.min.x <= other.max.x
            && other.min.x <= self.max.x
            && self.min.y <= other.max.y
            && other.min.y <= self.max.y
    }

    /// `true` when the closed box holds `p`.
    pub fn contains(&self, p: &Point2<f64>) -> bool {
        p.x >= self.min.x && p.x <= self.max.x && p.y >= self.min.y && p.y <= self.max.y
    }

    /// Width and height.
    pub fn size(&self) -> (f64, f64) {
        (self.max.x - self.min.x, self.max.y - self.min.y)
    }
}

impl Polygon {
    /// A ring from its vertices.
    pub fn new(vertices: Vec<Point2<f64>>) -> Self {
        Polygon { vertices }
    }

    /// The axis-aligned rectangle with lower-left corner `(x, y)`, `width` and `height`,
    /// counter-clockwise.
    ///
    /// ```
    /// use rappel_geometry::polygon::Polygon;
    /// assert_eq!(Polygon::rectangle(1.0, 2.0, 3.0, 4.0).area(), 12.0);
    /// ```
    pub fn rectangle(x: f64, y: f64, width: f64, height: f64) -> Polygon {
        Polygon::new(vec![
            Point2::new(x, y),
            Point2::new(x + width, y),
            Point2::new(x + width, y + height),
            Point2::new(x, y + height),
        ])
    }

    /// Number of vertices.
    pub fn len(&self) -> usize {
        self.vertices.len()
    }

    /// `true` for a ring with no vertices.
    pub fn is_empty(&self) -> bool {
        self.vertices.is_empty()
    }

    /// The edges as `(from, to)` pairs, closing the ring.
    pub fn edges(&self) -> impl Iterator<Item = (&Point2<f64>, &Point2<f64>)> + '_ {
        let n = self.vertices.len();
        (0..n).map(move |i| (&self.vertices[i], &self.vertices[(i + 1) % n]))
    }

    /// Signed area by the shoelace formula (positive counter-clockwise). Floating point: use
    /// [`Polygon::is_counter_clockwise`] or [`Polygon::is_degenerate`] for decisions.
    pub fn signed_area(&self) -> f64 {
        let n = self.vertices.len();
        if n < 3 {
            return 0.0;
        }
        // Shifting to the first vertex keeps the products small and the sum accurate.
        let o = self.vertices[0];
        let mut twice = 0.0;
        for i in 1..n - 1 {
            let a = self.vertices[i] - o;
            let b = self.vertices[i + 1] - o;
            twice += a.x * b.y - a.y * b.x;
        }
        twice / 2.0
    }

    /// Unsigned area.
    pub fn area(&self) -> f64 {
        self.signed_area().abs()
    }

    /// Index of the lexicographically smallest vertex (lowest x, then lowest y): a convex vertex of
    /// any simple ring, so its turn gives the ring's orientation exactly.
    fn extreme_vertex(&self) -> Option<usize> {
        (0..self.vertices.len()).min_by(|&i, &j| {
            let (a, b) = (self.vertices[i], self.vertices[j]);
            a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y))
        })
    }

    /// The exact turn at the extreme vertex, skipping neighbours equal to it: positive for a
    /// counter-clockwise simple ring, zero when every vertex is collinear.
    fn orientation_sign(&self) -> f64 {
        let n = self.vertices.len();
        let Some(k) = self.extreme_vertex() else {
            return 0.0;
        };
        let v = self.vertices[k];
        let prev = (1..n)
            .map(|s| self.vertices[(k + n - s) % n])
            .find(|p| *p != v);
        let next = (1..n).map(|s| self.vertices[(k + s) % n]).find(|p| *p != v);
        match (prev, next) {
            (Some(p), Some(q)) => {
                let turn = orient2d(&p, &v, &q);
                if turn != 0.0 {
                    return turn;
                }
                // The extreme vertex may sit on a straight run: fall back to any non-collinear
                // triple, whose sign the shoelace sum then settles.
                if self.is_degenerate() {
                    0.0
                } else {
                    self.signed_area()
                }
            }
            _ => 0.0,
        }
    }

    /// `true` when the ring runs counter-clockwise (exact for simple rings).
    pub fn is_counter_clockwise(&self) -> bool {
        self.orientation_sign() > 0.0
    }

    /// `true` when all vertices lie on one line (zero area), decided exactly.
    pub fn is_degenerate(&self) -> bool {
        let v = &self.vertices;
        let Some(first) = v.first() else { return true };
        let Some(second) = v.iter().find(|p| *p != first) else {
            return true;
        };
        v.iter().all(|p| orient2d(first, second, p) == 0.0)
    }

    /// Number of distinct vertices.
    pub fn distinct_vertex_count(&self) -> usize {
        let mut sorted: Vec<(u64, u64)> = self
            .vertices
            .iter()
            .map(|p| (p.x.to_bits(), p.y.to_bits()))
            .collect();
        sorted.sort_unstable();
        sorted.dedup();
        sorted.len()
    }

    /// Reverses the ring's orientation in place.
    pub fn reverse(&mut self) {
        self.vertices.reverse();
    }

    /// The same ring, counter-clockwise.
    pub fn to_counter_clockwise(&self) -> Polygon {
        let mut r = self.clone();
        if !r.is_counter_clockwise() {
            r.reverse();
        }
        r
    }

    /// The bounding box.
    pub fn aabb(&self) -> Aabb {
        Aabb::of_points(&self.vertices)
    }

    /// Exact point-in-polygon test (crossing number with exact orientation; boundary detected).
    ///
    /// ```
    /// use nalgebra::Point2;
    /// use rappel_geometry::polygon::{Polygon, PointInPolygon};
    /// let tri = Polygon::new(vec![Point2::new(0.0, 0.0), Point2::new(4.0, 0.0), Point2::new(0.0, 4.0)]);
    /// assert_eq!(tri.locate(&Point2::new(1.0, 1.0)), PointInPolygon::Inside);
    /// assert_eq!(tri.locate(&Point2::new(2.0, 2.0)), PointInPolygon::OnBoundary);
    /// assert_eq!(tri.locate(&Point2::new(3.0, 3.0)), PointInPolygon::Outside);
    /// ```
    pub fn locate(&self, p: &Point2<f64>) -> PointInPolygon {
        let mut inside = false;
        for (a, b) in self.edges() {
            if point_on_segment(a, b, p) {
                return PointInPolygon::OnBoundary;
            }
            // Half-open rule on y: count an edge when it straddles the horizontal line through p.
            if (a.y > p.y) != (b.y > p.y) {
                let o = orient2d(a, b, p);
                // Upward edge: p left of it means the ray to +x crosses it; downward: right.
                if (b.y > a.y && o > 0.0) || (b.y < a.y && o < 0.0) {
                    inside = !inside;
                }
            }
        }
        if inside {
            PointInPolygon::Inside
        } else {
            PointInPolygon::Outside
        }
    }

    /// The convex hull of the ring's vertices (see [`convex_hull`]).
    pub fn convex_hull(&self) -> Polygon {
        convex_hull(&self.vertices)
    }

    /// `true` when the ring is convex (every turn in one direction or straight), exact.
    pub fn is_convex(&self) -> bool {
        let n = self.vertices.len();
        let (mut pos, mut neg) = (false, false);
        for i in 0..n {
            let o = orient2d(
                &self.vertices[i],
                &self.vertices[(i + 1) % n],
                &self.vertices[(i + 2) % n],
            );
            pos |= o > 0.0;
            neg |= o < 0.0;
        }
        !(pos && neg)
    }
}

/// The convex hull of a point set, counter-clockwise, without collinear points (Andrew's monotone
/// chain with exact orientation). Fewer than three non-collinear points give the extreme points.
///
/// ```
/// use nalgebra::Point2;
/// use rappel_geometry::polygon::convex_hull;
/// let pts = [(0.0, 0.0), (2.0, 0.0), (1.0, 1.0), (2.0, 2.0), (0.0, 2.0), (1.0, 0.0)]
///     .map(|(x, y)| Point2::new(x, y));
/// assert_eq!(convex_hull(&pts).len(), 4);
/// ```
pub fn convex_hull(points: &[Point2<f64>]) -> Polygon {
    let mut pts: Vec<Point2<f64>> = points.to_vec();
    pts.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    pts.dedup();
    if pts.len() < 3 {
        return Polygon::new(pts);
    }
    let mut hull: Vec<Point2<f64>> = Vec::with_capacity(2 * pts.len());
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &Point2<f64>>> = if pass == 0 {
            Box::new(pts.iter())
        } else {
            Box::new(pts.iter().rev())
        };
        for p in iter {
            while hull.len() >= start + 2
                && orient2d(&hull[hull.len() - 2], &hull[hull.len() - 1], p) <= 0.0
            {
                hull.pop();
            }
            hull.push(*p);
        }
        hull.pop();
    }
    Polygon::new(hull)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ring(pts: &[(f64, f64)]) -> Polygon {
        Polygon::new(pts.iter().map(|&(x, y)| Point2::new(x, y)).collect())
    }

    #[test]
    fn orientation_of_clockwise_ring() {
        let r = ring(&[(0., 0.), (0., 1.), (1., 1.), (1., 0.)]);
        assert!(!r.is_counter_clockwise());
        assert!(r.to_counter_clockwise().is_counter_clockwise());
        assert_eq!(r.signed_area(), -1.0);
    }

    #[test]
    fn orientation_with_straight_run_at_extreme_vertex() {
        // The lexicographic minimum (0,0) has collinear neighbours (0,1) and (0,-1)... not possible
        // for the minimum, but (0,0) between (0,-1) and (0,1) makes x-min vertices collinear.
        let r = ring(&[(0., -1.), (2., 0.), (0., 1.), (0., 0.)]);
        assert!(r.is_counter_clockwise());
    }

    #[test]
    fn degenerate_rings() {
        assert!(ring(&[(0., 0.), (1., 1.), (2., 2.)]).is_degenerate());
        assert!(!ring(&[(0., 0.), (1., 1.), (2., 2.1)]).is_degenerate());
        assert_eq!(
            ring(&[(0., 0.), (0., 0.), (1., 0.)]).distinct_vertex_count(),
            2
        );
    }

    #[test]
    fn point_in_concave_polygon() {
        let u = ring(&[
            (0., 0.),
            (3., 0.),
            (3., 3.),
            (2., 3.),
            (2., 1.),
            (1., 1.),
            (1., 3.),
            (0., 3.),
        ]);
        assert_eq!(u.locate(&Point2::new(1.5, 2.0)), PointInPolygon::Outside);
        assert_eq!(u.locate(&Point2::new(0.5, 2.0)), PointInPolygon::Inside);
        assert_eq!(u.locate(&Point2::new(1.5, 1.0)), PointInPolygon::OnBoundary);
        // A ray through a vertex at the same height must not double count.
        assert_eq!(u.locate(&Point2::new(-1.0, 3.0)), PointInPolygon::Outside);
        assert_eq!(u.locate(&Point2::new(2.5, 1.0)), PointInPolygon::Inside);
    }

    #[test]
    fn hull_drops_collinear_points() {
        let h = convex_hull(&ring(&[(0., 0.), (1., 0.), (2., 0.), (2., 2.), (0., 2.)]).vertices);
        assert_eq!(h.len(), 4);
        assert!(h.is_counter_clockwise());
        assert!(h.is_convex());
    }
}
