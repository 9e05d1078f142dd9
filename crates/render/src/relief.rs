//! Relief of 3D ground seen from above: a mesh's triangles shaded by their slope towards a light
//! from the north-west (hillshade), and the ground's overall downhill direction for the panel's
//! fall-line arrow. Used under the pictures of mesh scenes (`navigate`, `settle-map`).

use nalgebra::{Point2, Vector2, Vector3};
use rappel_geometry::polygon::Aabb;
use rappel_terrain::mesh::TriMesh;

use crate::{Layer, Picture};

/// Most triangles shaded in one picture; a larger mesh is drawn without relief (the picture
/// stays small enough to open).
pub const MAX_RELIEF_TRIANGLES: usize = 20_000;

/// Steepest triangle counted as ground by [`fall_line`], degrees: steeper faces are walls.
pub const MAX_GROUND_SLOPE_DEG: f64 = 80.0;

/// The direction of the light, from the north-west, 45° above the horizon (map frame: y north).
fn light() -> Vector3<f64> {
    Vector3::new(-1.0, 1.0, std::f64::consts::SQRT_2).normalize()
}

/// The grey of a surface with unit normal `n` under the light: flat ground mid-light, slopes
/// facing the light brighter, slopes facing away darker, as `#rrggbb`.
pub fn shade(n: &Vector3<f64>) -> String {
    let lit = n.dot(&light()).max(0.0);
    let g = (60.0 + 190.0 * lit).round().clamp(0.0, 255.0) as u8;
    format!("#{g:02x}{g:02x}{g:02x}")
}

/// The mean downhill direction of `mesh` seen from above: the area-weighted mean of the
/// horizontal parts of its ground triangles' normals (a surface with normal `n` descends along
/// `(n.x, n.y)`). Ground triangles face up, at most [`MAX_GROUND_SLOPE_DEG`] from level: a
/// closed mesh's underside and its walls (a box's end faces) would otherwise cancel the slope.
/// `None` when the ground is flat on the whole (within 1e-6 of its area).
///
/// ```
/// use nalgebra::Point3;
/// use rappel_terrain::mesh::TriMesh;
/// // z = -x: downhill is +x.
/// let m = TriMesh::new(
///     vec![Point3::new(0.0, 0.0, 0.0), Point3::new(1.0, 0.0, -1.0), Point3::new(0.0, 1.0, 0.0)],
///     vec![[0, 1, 2]],
/// ).unwrap();
/// let f = rappel_render::relief::fall_line(&m).unwrap();
/// assert!((f.x - 1.0).abs() < 1e-12 && f.y.abs() < 1e-12);
/// ```
pub fn fall_line(mesh: &TriMesh) -> Option<Vector2<f64>> {
    let v = mesh.vertices();
    let (mut sum, mut area) = (Vector2::zeros(), 0.0);
    let min_cos = MAX_GROUND_SLOPE_DEG.to_radians().cos();
    // Upward faces first; a mesh wound the other way round (all its ground facing down) is read
    // with its normals flipped.
    for sign in [1.0, -1.0] {
        for t in mesh.triangles() {
            let n = sign * (v[t[1]] - v[t[0]]).cross(&(v[t[2]] - v[t[0]]));
            if n.z > min_cos * n.norm() {
                sum += Vector2::new(n.x, n.y);
                area += n.norm();
            }
        }
        if area > 0.0 {
            break;
        }
    }
    (sum.norm() > 1e-6 * area).then(|| sum / sum.norm())
}

/// Shades the triangles of `mesh` that meet `within` (at most [`MAX_RELIEF_TRIANGLES`]; none
/// when more meet it) on [`Layer::Terrain`], under everything else. Returns whether it drew.
pub fn draw_relief(pic: &mut Picture, mesh: &TriMesh, within: &Aabb) -> bool {
    let v = mesh.vertices();
    let inside: Vec<&[usize; 3]> = mesh
        .triangles()
        .iter()
        .filter(|t| {
            let xs = t.map(|i| v[i].x);
            let ys = t.map(|i| v[i].y);
            xs.iter().copied().fold(f64::INFINITY, f64::min) <= within.max.x
                && xs.iter().copied().fold(f64::NEG_INFINITY, f64::max) >= within.min.x
                && ys.iter().copied().fold(f64::INFINITY, f64::min) <= within.max.y
                && ys.iter().copied().fold(f64::NEG_INFINITY, f64::max) >= within.min.y
        })
        .collect();
    if inside.len() > MAX_RELIEF_TRIANGLES {
        return false;
    }
    for t in inside {
        let mut n = (v[t[1]] - v[t[0]]).cross(&(v[t[2]] - v[t[0]]));
        if n.z < 0.0 {
            n = -n;
        }
        let Some(n) = n.try_normalize(0.0) else {
            continue;
        };
        let pts = t.map(|i| Point2::new(v[i].x, v[i].y));
        pic.shaded_polygon(Layer::Terrain, &pts, &shade(&n));
    }
    true
}
