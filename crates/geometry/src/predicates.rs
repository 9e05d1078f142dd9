//! Exact geometric predicates: every topological decision in rappel (which side of a line a point
//! lies on, whether a point is inside a circumcircle, whether two segments meet) is made here, with
//! Shewchuk's adaptive-precision arithmetic (the `robust` crate). The answers are exact for all
//! finite `f64` inputs: no tolerance is involved, so degenerate cases (collinear points, cocircular
//! points, touching segments) are recognised as such rather than guessed.

use crate::expansion::Expansion;
use nalgebra::{Point2, Vector2};

/// The orientation of an ordered triple of points.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Orientation {
    /// The triple turns left (positive signed area).
    CounterClockwise,
    /// The triple turns right (negative signed area).
    Clockwise,
    /// The three points lie on one line.
    Collinear,
}

#[inline]
fn coord(p: &Point2<f64>) -> robust::Coord<f64> {
    robust::Coord { x: p.x, y: p.y }
}

/// Twice the signed area of triangle `abc`, with the exact sign: positive when `abc` turns left.
///
/// ```
/// use nalgebra::Point2;
/// use rappel_geometry::predicates::orient2d;
/// let (a, b) = (Point2::new(0.0, 0.0), Point2::new(1.0, 0.0));
/// assert!(orient2d(&a, &b, &Point2::new(0.5, 1.0)) > 0.0);
/// assert_eq!(orient2d(&a, &b, &Point2::new(0.5, 0.0)), 0.0);
/// ```
#[inline]
pub fn orient2d(a: &Point2<f64>, b: &Point2<f64>, c: &Point2<f64>) -> f64 {
    robust::orient2d(coord(a), coord(b), coord(c))
}

/// The exact orientation of the triple `abc`.
///
/// ```
/// use nalgebra::Point2;
/// use rappel_geometry::predicates::{orientation, Orientation};
/// let o = orientation(&Point2::new(0.0, 0.0), &Point2::new(1.0, 1.0), &Point2::new(2.0, 2.0));
/// assert_eq!(o, Orientation::Collinear);
/// ```
#[inline]
pub fn orientation(a: &Point2<f64>, b: &Point2<f64>, c: &Point2<f64>) -> Orientation {
    let d = orient2d(a, b, c);
    if d > 0.0 {
        Orientation::CounterClockwise
    } else if d < 0.0 {
        Orientation::Clockwise
    } else {
        Orientation::Collinear
    }
}

/// Positive when `d` lies strictly inside the circle through `a`, `b`, `c` (which must turn left),
/// zero when the four points are cocircular, negative outside. Exact sign.
///
/// ```
/// use nalgebra::Point2;
/// use rappel_geometry::predicates::incircle;
/// let (a, b, c) = (Point2::new(0.0, 0.0), Point2::new(2.0, 0.0), Point2::new(0.0, 2.0));
/// assert!(incircle(&a, &b, &c, &Point2::new(1.0, 1.0)) > 0.0);
/// assert_eq!(incircle(&a, &b, &c, &Point2::new(2.0, 2.0)), 0.0);
/// ```
#[inline]
pub fn incircle(a: &Point2<f64>, b: &Point2<f64>, c: &Point2<f64>, d: &Point2<f64>) -> f64 {
    robust::incircle(coord(a), coord(b), coord(c), coord(d))
}

/// How two closed segments meet.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SegmentContact {
    /// The segments share no point.
    Disjoint,
    /// They cross at one point interior to both.
    Crossing,
    /// They share at least one point, and that contact involves an endpoint of one of them or a
    /// collinear overlap.
    Touching,
}

/// `true` when `p`, known to be collinear with segment `ab`, lies on the closed segment.
#[inline]
fn on_collinear_segment(a: &Point2<f64>, b: &Point2<f64>, p: &Point2<f64>) -> bool {
    p.x >= a.x.min(b.x) && p.x <= a.x.max(b.x) && p.y >= a.y.min(b.y) && p.y <= a.y.max(b.y)
}

/// `true` when `p` lies on the closed segment `ab` (exact).
///
/// ```
/// use nalgebra::Point2;
/// use rappel_geometry::predicates::point_on_segment;
/// let (a, b) = (Point2::new(0.0, 0.0), Point2::new(0.3, 0.3));
/// assert!(point_on_segment(&a, &b, &Point2::new(0.1, 0.1)));
/// assert!(!point_on_segment(&a, &b, &Point2::new(0.4, 0.4)));
/// ```
#[inline]
pub fn point_on_segment(a: &Point2<f64>, b: &Point2<f64>, p: &Point2<f64>) -> bool {
    orient2d(a, b, p) == 0.0 && on_collinear_segment(a, b, p)
}

/// Classifies how the closed segments `ab` and `cd` meet (exact).
///
/// ```
/// use nalgebra::Point2;
/// use rappel_geometry::predicates::{segment_contact, SegmentContact};
/// let p = |x, y| Point2::new(x, y);
/// assert_eq!(segment_contact(&p(0., 0.), &p(2., 2.), &p(0., 2.), &p(2., 0.)), SegmentContact::Crossing);
/// assert_eq!(segment_contact(&p(0., 0.), &p(2., 2.), &p(1., 1.), &p(2., 0.)), SegmentContact::Touching);
/// assert_eq!(segment_contact(&p(0., 0.), &p(1., 0.), &p(2., 0.), &p(3., 0.)), SegmentContact::Disjoint);
/// ```
pub fn segment_contact(
    a: &Point2<f64>,
    b: &Point2<f64>,
    c: &Point2<f64>,
    d: &Point2<f64>,
) -> SegmentContact {
    // Cheap bounding-box rejection first: exact, since it only compares coordinates.
    if a.x.max(b.x) < c.x.min(d.x)
        || c.x.max(d.x) < a.x.min(b.x)
        || a.y.max(b.y) < c.y.min(d.y)
        || c.y.max(d.y) < a.y.min(b.y)
    {
        return SegmentContact::Disjoint;
    }
    let o1 = orient2d(a, b, c);
    let o2 = orient2d(a, b, d);
    let o3 = orient2d(c, d, a);
    let o4 = orient2d(c, d, b);
    if ((o1 > 0.0 && o2 < 0.0) || (o1 < 0.0 && o2 > 0.0))
        && ((o3 > 0.0 && o4 < 0.0) || (o3 < 0.0 && o4 > 0.0))
    {
        return SegmentContact::Crossing;
    }
    let touches = (o1 == 0.0 && on_collinear_segment(a, b, c))
        || (o2 == 0.0 && on_collinear_segment(a, b, d))
        || (o3 == 0.0 && on_collinear_segment(c, d, a))
        || (o4 == 0.0 && on_collinear_segment(c, d, b));
    if touches {
        SegmentContact::Touching
    } else {
        SegmentContact::Disjoint
    }
}

/// Relative error bound of the floating-point filters of [`ray_side`] and [`ray_side_at_height`],
/// in units of the sum of the magnitudes of their terms: a few roundings deep, each at most
/// `EPSILON / 2`; this bound leaves a wide margin. Below it the exact expansion decides.
const RAY_FILTER: f64 = 16.0 * f64::EPSILON;

/// The exact sign (-1, 0 or 1) of `e × (x - a)`: positive when `x` lies left of the line through
/// `a` along the direction `e`, zero on it. The direction is taken as given (its components are
/// the inputs), so a wedge given by the directions of its edges decides membership exactly.
///
/// ```
/// use nalgebra::{Point2, Vector2};
/// use rappel_geometry::predicates::ray_side;
/// let (a, e) = (Point2::new(1.0, 1.0), Vector2::new(0.5, -1.0));
/// assert_eq!(ray_side(&a, &e, &Point2::new(1.5, 0.0)), 0.0);
/// assert_eq!(ray_side(&a, &e, &Point2::new(1.5f64.next_down(), 0.0)), -1.0);
/// assert_eq!(ray_side(&a, &e, &Point2::new(1.5f64.next_up(), 0.0)), 1.0);
/// ```
pub fn ray_side(a: &Point2<f64>, e: &Vector2<f64>, x: &Point2<f64>) -> f64 {
    let (dx, dy) = (x.x - a.x, x.y - a.y);
    let (l, r) = (e.x * dy, e.y * dx);
    let v = l - r;
    if v.abs() > RAY_FILTER * (l.abs() + r.abs()) {
        return v.signum();
    }
    Expansion::diff(x.y, a.y)
        .scale(e.x)
        .add(&Expansion::diff(x.x, a.x).scale(e.y).neg())
        .sign()
}

/// The exact sign of `e × (p - a)` for the point `p` of the segment `q -> w` at height `y`
/// (`q.y != w.y`; `p = q + s (w - q)` with `s = (y - q.y) / (w.y - q.y)`), as [`ray_side`] would
/// give for `p` computed without rounding: where a move crosses a band edge, against a wedge edge.
///
/// ```
/// use nalgebra::{Point2, Vector2};
/// use rappel_geometry::predicates::ray_side_at_height;
/// let (a, e) = (Point2::new(0.0, 0.0), Vector2::new(0.0, -1.0));
/// // The segment (-1, 1) -> (1, -3) crosses y = -1 at x = 0, on the ray.
/// let (q, w) = (Point2::new(-1.0, 1.0), Point2::new(1.0, -3.0));
/// assert_eq!(ray_side_at_height(&a, &e, &q, &w, -1.0), 0.0);
/// assert_eq!(ray_side_at_height(&a, &e, &q, &w, -1.5), 1.0);
/// ```
pub fn ray_side_at_height(
    a: &Point2<f64>,
    e: &Vector2<f64>,
    q: &Point2<f64>,
    w: &Point2<f64>,
    y: f64,
) -> f64 {
    // e × (p - a) = (c1 dy + (y - q.y) c2) / dy with c1 = e × (q - a), c2 = e × (w - q).
    let dy = w.y - q.y;
    let below = y - q.y;
    let (c1l, c1r) = (e.x * (q.y - a.y), e.y * (q.x - a.x));
    let (c2l, c2r) = (e.x * dy, e.y * (w.x - q.x));
    let (t1, t2) = ((c1l - c1r) * dy, below * (c2l - c2r));
    let v = t1 + t2;
    let scale = (c1l.abs() + c1r.abs()) * dy.abs() + below.abs() * (c2l.abs() + c2r.abs());
    let num = if v.abs() > RAY_FILTER * scale {
        v.signum()
    } else {
        let dy = Expansion::diff(w.y, q.y);
        let c1 = Expansion::diff(q.y, a.y)
            .scale(e.x)
            .add(&Expansion::diff(q.x, a.x).scale(e.y).neg());
        let c2 = dy
            .scale(e.x)
            .add(&Expansion::diff(w.x, q.x).scale(e.y).neg());
        c1.mul(&dy).add(&Expansion::diff(y, q.y).mul(&c2)).sign()
    };
    if dy > 0.0 {
        num
    } else if dy < 0.0 {
        -num
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: f64, y: f64) -> Point2<f64> {
        Point2::new(x, y)
    }

    #[test]
    fn orientation_is_exact_for_nearly_collinear_points() {
        // A classic failure of naive floating point: points within an ulp of a line.
        let a = p(0.5, 0.5);
        let b = p(12.0, 12.0);
        let c = p(24.0, 24.0);
        assert_eq!(orientation(&a, &b, &c), Orientation::Collinear);
        let c2 = p(24.0, f64::from_bits(24.0f64.to_bits() + 1));
        assert_eq!(orientation(&a, &b, &c2), Orientation::CounterClockwise);
    }

    #[test]
    fn collinear_overlap_is_touching() {
        assert_eq!(
            segment_contact(&p(0., 0.), &p(2., 0.), &p(1., 0.), &p(3., 0.)),
            SegmentContact::Touching
        );
    }

    #[test]
    fn incircle_sign_flips_with_cocircular_boundary() {
        let (a, b, c) = (p(1., 0.), p(0., 1.), p(-1., 0.));
        assert_eq!(incircle(&a, &b, &c, &p(0., -1.)), 0.0);
        assert!(incircle(&a, &b, &c, &p(0., -0.999)) > 0.0);
        assert!(incircle(&a, &b, &c, &p(0., -1.001)) < 0.0);
    }
}
