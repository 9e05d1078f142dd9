//! Small exact-geometry helpers shared by the tracer, the funnel and the funnel states. Every
//! decision is an exact [`orient2d`] sign or an exact coordinate comparison; nothing here
//! constructs a new point.

use nalgebra::Point2;
use rappel_geometry::dcel::{Dcel, HalfEdgeId, TriangleId, VertexId};
use rappel_geometry::predicates::orient2d;

/// Where a point of a closed triangle sits in it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum InTriangle {
    /// Strictly inside.
    Interior,
    /// On the relative interior of this half-edge of the triangle.
    Edge(HalfEdgeId),
    /// On this corner.
    Vertex(VertexId),
    /// Strictly outside the closed triangle.
    Outside,
}

/// Where `p` sits relative to the closed triangle `t` (exact).
pub(crate) fn classify(d: &Dcel, t: TriangleId, p: &Point2<f64>) -> InTriangle {
    let hs = t.half_edges();
    let mut zeros = [None; 3];
    let mut count = 0;
    for (i, h) in hs.iter().enumerate() {
        let o = orient2d(&d.point(d.origin(*h)), &d.point(d.destination(*h)), p);
        if o < 0.0 {
            return InTriangle::Outside;
        }
        if o == 0.0 {
            zeros[count] = Some(i);
            count += 1;
        }
    }
    match count {
        0 => InTriangle::Interior,
        1 => InTriangle::Edge(hs[zeros[0].unwrap_or(0)]),
        _ => {
            // On two edge lines: the corner they share. Edge i ends where edge i + 1 starts.
            let (i, j) = (zeros[0].unwrap_or(0), zeros[1].unwrap_or(1));
            let corner = if (i + 1) % 3 == j { j } else { i };
            InTriangle::Vertex(d.origin(hs[corner]))
        }
    }
}

/// `true` when `p` lies in the closed triangle `t` (exact).
#[inline]
pub(crate) fn in_closed_triangle(d: &Dcel, t: TriangleId, p: &Point2<f64>) -> bool {
    t.half_edges()
        .iter()
        .all(|h| orient2d(&d.point(d.origin(*h)), &d.point(d.destination(*h)), p) >= 0.0)
}

/// `true` when `v`, known to be collinear with `p` and `q` (`p != q`), lies strictly ahead of `p`
/// in the direction of `q`. Exact: along a line that is not vertical, the x coordinate is monotone,
/// and the sign of a floating-point difference is always exact.
#[inline]
pub(crate) fn ahead(p: &Point2<f64>, q: &Point2<f64>, v: &Point2<f64>) -> bool {
    if q.x != p.x {
        (v.x > p.x) == (q.x > p.x) && v.x != p.x
    } else {
        (v.y > p.y) == (q.y > p.y) && v.y != p.y
    }
}

/// `true` when the direction from `w` towards `q` lies in the closed cone of the free triangle of
/// the out-edge `h` (`w = origin(h)`) at its corner `w`. Triangle angles are below pi, so the cone
/// is the intersection of two closed half-planes.
#[inline]
pub(crate) fn cone_contains(d: &Dcel, h: HalfEdgeId, q: &Point2<f64>) -> bool {
    let w = d.point(d.origin(h));
    let x = d.point(d.destination(h));
    let y = d.point(d.origin(h.prev()));
    orient2d(&w, &x, q) >= 0.0 && orient2d(&w, &y, q) <= 0.0
}

/// The funnel's sector test (thesis §2.3.1, Fig. 2.14): `true` when `v` lies strictly to the left
/// of the ray `from -> to` extending a chain edge. A left chain keeps its vertex `to` as the
/// predecessor of `v` exactly when this holds; collinear points fall through, so the taut path
/// never keeps a vertex it passes straight through.
#[inline]
pub(crate) fn strictly_left(from: &Point2<f64>, to: &Point2<f64>, v: &Point2<f64>) -> bool {
    orient2d(from, to, v) > 0.0
}

/// Mirror of [`strictly_left`].
#[inline]
pub(crate) fn strictly_right(from: &Point2<f64>, to: &Point2<f64>, v: &Point2<f64>) -> bool {
    orient2d(from, to, v) < 0.0
}

/// `true` when both coordinates are finite.
#[inline]
pub(crate) fn is_finite(p: &Point2<f64>) -> bool {
    p.x.is_finite() && p.y.is_finite()
}
