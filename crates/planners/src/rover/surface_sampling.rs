//! Ground points drawn uniformly over the *area* of a mesh's upward-facing surface, for the rover
//! sampler's uniform samples (Paton 2020 §III: "states on the surface manifold are sampled by
//! perturbing a randomly selected R^3 grid point in the reconstructed 3D voxel space"; the
//! voxels of a reconstructed surface are spread evenly over its area, so a slope of inclination
//! `θ` holds `1 / cos θ` times the samples of flat ground with the same footprint).
//!
//! A [`SurfaceSampler`] clips the upward-facing triangles (normal's `z` above zero) to the
//! sampled box's footprint, fans each clipped polygon into triangles (they stay in the face's
//! plane), draws one of them with probability proportional to its 3D area and a point uniformly
//! in it: uniform over the area inside the box, with no rejection. Vertical faces (walls, a
//! pole's side) have no footprint: no ground point stands for them, and Axel cannot settle on
//! them. The sampler returns ground points `(x, y)`; the state space settles them as before (from
//! above, onto the topmost surface), so on a scene without overhangs each point is settled onto
//! the face it was drawn on.

use nalgebra::Point3;
use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use rappel_terrain::mesh::TriMesh;

/// Uniform sampling over the area of a mesh's upward-facing surface within a box (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceSampler {
    /// The upward-facing triangles clipped to the box, as triangles in their faces' planes.
    triangles: Vec<[Point3<f64>; 3]>,
    /// Running sums of their areas (the last is the total).
    cumulative: Vec<f64>,
}

impl SurfaceSampler {
    /// The sampler of `mesh`'s upward-facing surface over the box `lo..hi` (ground `x`, `y`), or
    /// `None` when no upward-facing surface of positive area lies in the box. Linear in the
    /// mesh's triangles.
    ///
    /// ```
    /// use rappel_planners::rover::surface_sampling::SurfaceSampler;
    /// use rappel_terrain::paton_scene::PatonScene;
    /// let mesh = PatonScene::paper(false).mesh().unwrap();
    /// let s = SurfaceSampler::new(&mesh, [-4.5, -3.0], [5.0, 3.0]).unwrap();
    /// // The slope holds more area than its footprint.
    /// assert!(s.area() > 9.5 * 6.0);
    /// ```
    pub fn new(mesh: &TriMesh, lo: [f64; 2], hi: [f64; 2]) -> Option<SurfaceSampler> {
        let v = mesh.vertices();
        let mut triangles = Vec::new();
        let mut cumulative = Vec::new();
        let mut total = 0.0;
        for t in mesh.triangles() {
            let [a, b, c] = t.map(|i| v[i]);
            if (b - a).cross(&(c - a)).z <= 0.0 {
                continue;
            }
            let clipped = clip_to_box(vec![a, b, c], lo, hi);
            for i in 2..clipped.len() {
                let (p, q, r) = (clipped[0], clipped[i - 1], clipped[i]);
                let area = 0.5 * (q - p).cross(&(r - p)).norm();
                if area > 0.0 {
                    total += area;
                    triangles.push([p, q, r]);
                    cumulative.push(total);
                }
            }
        }
        (total > 0.0).then_some(SurfaceSampler {
            triangles,
            cumulative,
        })
    }

    /// The upward-facing surface's area inside the box, square metres.
    pub fn area(&self) -> f64 {
        self.cumulative.last().copied().unwrap_or(0.0)
    }

    /// A ground point `(x, y)` in the box, uniform over the surface's area there.
    pub fn sample(&self, rng: &mut ChaCha8Rng) -> (f64, f64) {
        let r = rng.random_range(0.0..self.area());
        let i = self
            .cumulative
            .partition_point(|&c| c <= r)
            .min(self.triangles.len() - 1);
        let [a, b, c] = self.triangles[i];
        // A uniform point of the triangle: fold the unit square's upper half onto it.
        let (mut s, mut t) = (rng.random::<f64>(), rng.random::<f64>());
        if s + t > 1.0 {
            (s, t) = (1.0 - s, 1.0 - t);
        }
        let p = a + (b - a) * s + (c - a) * t;
        (p.x, p.y)
    }
}

/// The part of the convex polygon `poly` (3D points, one plane) whose footprint lies in the box
/// `lo..hi` (Sutherland-Hodgman against the box's four sides, interpolating along the polygon's
/// edges, so the points stay in its plane).
fn clip_to_box(mut poly: Vec<Point3<f64>>, lo: [f64; 2], hi: [f64; 2]) -> Vec<Point3<f64>> {
    // Each side: the coordinate, its bound, and whether points must lie above it.
    for (k, bound, above) in [
        (0, lo[0], true),
        (0, hi[0], false),
        (1, lo[1], true),
        (1, hi[1], false),
    ] {
        let inside = |p: &Point3<f64>| if above { p[k] >= bound } else { p[k] <= bound };
        let mut out = Vec::with_capacity(poly.len() + 1);
        for i in 0..poly.len() {
            let (p, q) = (poly[i], poly[(i + 1) % poly.len()]);
            if inside(&p) {
                out.push(p);
            }
            if inside(&p) != inside(&q) {
                let t = (bound - p[k]) / (q[k] - p[k]);
                out.push(p + (q - p) * t);
            }
        }
        poly = out;
        if poly.len() < 3 {
            return Vec::new();
        }
    }
    poly
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rappel_terrain::paton_scene::PatonScene;

    /// On the paper's ledge the slope's share of the samples is its share of the area, not of the
    /// footprint: `1 / cos 55°` times its footprint share, against the closed form.
    #[test]
    fn the_slope_holds_its_share_of_the_area() {
        let scene = PatonScene::paper(false);
        let mesh = scene.mesh().unwrap();
        let foot = scene.slope_foot_x();
        let (lo, hi) = ([-scene.width + 0.5, -3.0], [foot + 3.0, 3.0]);
        let s = SurfaceSampler::new(&mesh, lo, hi).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let n = 200_000;
        let on_slope = (0..n)
            .filter(|_| {
                let (x, y) = s.sample(&mut rng);
                assert!((lo[0]..=hi[0]).contains(&x) && (lo[1]..=hi[1]).contains(&y));
                x > 0.0 && x < foot
            })
            .count() as f64
            / n as f64;
        // Footprint lengths along x: ledge top (lo.x to 0), slope (0 to foot), ground (3 m).
        let stretch = 1.0 / scene.slope_deg.to_radians().cos();
        let (top, slope, ground) = (-lo[0], foot, 3.0);
        let expected = slope * stretch / (top + slope * stretch + ground);
        let footprint_share = slope / (top + slope + ground);
        assert!(
            (on_slope - expected).abs() < 0.005,
            "slope share {on_slope}, area share {expected}, footprint share {footprint_share}"
        );
        assert!(expected > footprint_share + 0.05);
    }

    /// A box that no upward-facing triangle meets has no sampler.
    #[test]
    fn a_box_off_the_surface_has_no_sampler() {
        let mesh = PatonScene::paper(false).mesh().unwrap();
        assert!(SurfaceSampler::new(&mesh, [1e3, 1e3], [1e3 + 1.0, 1e3 + 1.0]).is_none());
    }
}
