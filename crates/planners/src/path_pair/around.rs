//! The path around anchors at a clearance (thesis §2.4.3; [`super`] module docs): a polyline
//! through **nodes**, each a point the path passes through or an anchor it keeps on a given side
//! at a given radius, made of the tangents between consecutive nodes and, around each anchor, the
//! circumscribed polygon of the arc between its two tangent points.
//!
//! # Formulation
//! A node is `(P_i, rho_i)`: `rho_i > 0` keeps `P_i` on the path's left at distance `rho_i`,
//! `rho_i < 0` on its right, `rho_i = 0` passes through it. The tangent from node `i` to node `j`
//! is the line `{X : nu . (P - X) = rho}` for both nodes, `nu` the unit left normal of the travel
//! direction `t`: with `D = P_j - P_i`, `L = |D|` and `sin beta = (rho_i - rho_j) / L`,
//! `t = cos beta D/L + sin beta rot90(D/L)` and `nu = rot90(t)` (it exists while
//! `|rho_i - rho_j| < L`). It touches node `i` at `P_i - rho_i nu`.
//!
//! Around an anchor node the path turns from the incoming tangent to the outgoing one. The radial
//! directions of the two tangent points are `u = -sign(rho) nu`; the path sweeps from `u_in` to
//! `u_out` counterclockwise round an anchor on its left (clockwise on its right). A sweep of
//! `s >= 0` is replaced by `ceil(s / ARC_STEP)` edges of the arc's circumscribed polygon: its
//! vertices lie at `|rho| / cos(delta / 2)` from the anchor (`delta` the angle per edge) and its
//! edges, the tangents before and after included, touch the circle of radius `|rho|`, so every
//! point of the path keeps at least `|rho|` from the anchor. A negative sweep (the two tangents
//! cross before they reach the circle: the path turns away from the anchor) is replaced by the
//! tangents' crossing, at `|rho| / cos(phi / 2)` along the bisector of `u_in` and `u_out` (`phi`
//! their angle), which keeps `|rho|` too.
//!
//! The polygon's vertices belong to their anchor ([`Corner`] with an owner), so that a later push
//! ([`super::keep_clear`]) can move them radially; the pass-through nodes are fixed corners.

use super::corner::{Corner, MITRE_LIMIT};
use nalgebra::{Point2, Vector2};

/// Largest angle one edge of an arc's circumscribed polygon turns through: 22.5°, so that the
/// polygon's vertices lie within 2 % of the radius beyond the circle (`1 / cos(11.25°) - 1`).
pub const ARC_STEP: f64 = std::f64::consts::PI / 8.0;

/// One node of the path ([module docs](self)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Node {
    /// `P_i`.
    pub point: Point2<f64>,
    /// `rho_i`, m: positive keeps the node on the path's left, negative on its right, zero passes
    /// through it.
    pub rho: f64,
    /// The anchor `a_k` (`k` from 1) a node with a radius stands for; 0 for a pass-through node.
    pub k: usize,
}

impl Node {
    /// A node the path passes through.
    pub fn through(point: Point2<f64>) -> Node {
        Node {
            point,
            rho: 0.0,
            k: 0,
        }
    }
}

/// `v` turned a quarter counterclockwise.
fn rot90(v: &Vector2<f64>) -> Vector2<f64> {
    Vector2::new(-v.y, v.x)
}

/// The unit left normal `nu` of the tangent from `a` to `b` ([module docs](self)), or `None` when
/// it does not exist (`|rho_a - rho_b| >= L`, or coincident points).
fn tangent(a: &Node, b: &Node) -> Option<Vector2<f64>> {
    let d = b.point - a.point;
    let l = d.norm();
    if l.is_nan() || l <= 0.0 {
        return None;
    }
    let s = (a.rho - b.rho) / l;
    if s.is_nan() || s.abs() >= 1.0 {
        return None;
    }
    let dh = d / l;
    let t = dh * (1.0 - s * s).sqrt() + rot90(&dh) * s;
    Some(rot90(&t))
}

/// The path through `nodes` ([module docs](self)) as corners: the first and last nodes and every
/// pass-through node fixed, each anchor node replaced by its arc's polygon vertices (or the
/// tangents' crossing), owned by its anchor. `None` when a tangent does not exist or a crossing
/// lies beyond [`MITRE_LIMIT`] radii. At most `ceil(pi / ARC_STEP) = 8` corners per anchor node.
pub(super) fn around(nodes: &[Node]) -> Option<Vec<Corner>> {
    let normals: Vec<Vector2<f64>> = nodes
        .windows(2)
        .map(|w| tangent(&w[0], &w[1]))
        .collect::<Option<_>>()?;
    let mut out = Vec::with_capacity(nodes.len() + 4);
    for (i, node) in nodes.iter().enumerate() {
        let interior = i > 0 && i + 1 < nodes.len();
        if !interior || node.rho == 0.0 {
            out.push(Corner::fixed(node.point));
            continue;
        }
        let sign = node.rho.signum();
        let r = node.rho.abs();
        let u_in = -normals[i - 1] * sign;
        let u_out = -normals[i] * sign;
        let delta = u_in.perp(&u_out).atan2(u_in.dot(&u_out));
        let sweep = sign * delta;
        if sweep >= 0.0 {
            let pieces = (sweep / ARC_STEP).ceil().max(1.0);
            let step = sweep / pieces;
            let m = r / (step / 2.0).cos();
            let theta_in = u_in.y.atan2(u_in.x);
            for j in 0..pieces as usize {
                let theta = theta_in + sign * (j as f64 + 0.5) * step;
                out.push(Corner {
                    base: node.point,
                    owner: Some((node.k, Vector2::new(theta.cos(), theta.sin()), m)),
                });
            }
        } else {
            let bisector = u_in + u_out;
            let half = delta.abs() / 2.0;
            let m = r / half.cos();
            if !(bisector.norm() > 0.0 && m <= MITRE_LIMIT * r) {
                return None;
            }
            out.push(Corner {
                base: node.point,
                owner: Some((node.k, bisector.normalize(), m)),
            });
        }
    }
    Some(out)
}

/// The smallest `m >= 0` for which the line through `p` and `a + m n` (`n` a unit vector) passes at
/// least `c` from `a`, or `None` when no `m` does (`p` lies within `c` of the line through `a`
/// along `n`).
///
/// With `u = p - a`, the distance is `m |u x n| / |m n - u|`; setting it to `c` gives
/// `m^2 ((u x n)^2 - c^2) + 2 c^2 (u . n) m - c^2 |u|^2 = 0`, whose leading coefficient is positive
/// and constant term negative exactly when a solution exists: one positive root, taken in the
/// cancellation-free form. The distance grows from `m = 0` up to a peak and then falls towards
/// `|u x n| > c`, so every `m` beyond the root keeps the line at least `c` away, and so does the
/// segment `p -> a + m n`, which lies on it.
///
/// ```
/// use nalgebra::{Point2, Vector2};
/// use rappel_planners::path_pair::offset_for_clearance;
/// let a = Point2::new(0.0, 0.0);
/// // From 2 m along the x axis to a corner up the y axis, 1 m from the anchor: the corner at
/// // 2 / sqrt(3) (the segment's line is tangent to the unit circle).
/// let m = offset_for_clearance(&a, &Point2::new(2.0, 0.0), &Vector2::new(0.0, 1.0), 1.0).unwrap();
/// assert!((m - 2.0 / 3f64.sqrt()).abs() < 1e-12);
/// assert!(offset_for_clearance(&a, &Point2::new(0.5, 0.0), &Vector2::new(0.0, 1.0), 1.0).is_none());
/// ```
pub fn offset_for_clearance(
    a: &Point2<f64>,
    p: &Point2<f64>,
    n: &Vector2<f64>,
    c: f64,
) -> Option<f64> {
    let u = p - a;
    let cross = u.perp(n);
    let qa = cross * cross - c * c;
    if qa.is_nan() || qa <= 0.0 {
        return None;
    }
    let qb = 2.0 * c * c * u.dot(n);
    let qc = -c * c * u.norm_squared();
    let root = (qb * qb - 4.0 * qa * qc).sqrt();
    let m = if qb >= 0.0 {
        -2.0 * qc / (qb + root)
    } else {
        (root - qb) / (2.0 * qa)
    };
    (m.is_finite() && m >= 0.0).then_some(m)
}
