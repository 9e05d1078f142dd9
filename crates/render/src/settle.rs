//! The picture of `rappel settle` (Paton Figs. 3-5): the settled rover drawn axonometrically on
//! the patch of ground around it, with its tether and boom.

use nalgebra::Point3;
use rappel_mechanics::axel::AxelParams;
use rappel_mechanics::settle::SettledPose;
use rappel_terrain::mesh::TriMesh;

/// Half-width of the square of ground drawn around a settled pose by [`settled_pose_picture`],
/// in multiples of the rover's track.
pub const PICTURE_PATCH_TRACKS: f64 = 2.5;
/// Most ground triangles [`ground_patch`] clips (the nearest to the centre first): bounds the
/// picture on a fine mesh.
pub const PICTURE_MAX_TRIANGLES: usize = 20_000;

/// The part of `ground` over the square of half-width `half` (plan view) centred on `centre`:
/// each triangle whose plan bounding box meets the square, clipped to it (Sutherland-Hodgman on
/// the square's four sides, heights interpolated along the clipped edges, so every point stays on
/// its triangle); at most [`PICTURE_MAX_TRIANGLES`] triangles, nearest first. On a height-field
/// mesh covering the square the pieces tile it.
///
/// ```
/// use rappel_render::settle::ground_patch;
/// use rappel::terrain::mesh::TriMesh;
/// use nalgebra::{Point2, Point3};
/// let ground = TriMesh::new(
///     vec![
///         Point3::new(-5.0, -5.0, 0.0),
///         Point3::new(5.0, -5.0, 1.0),
///         Point3::new(5.0, 5.0, 1.0),
///         Point3::new(-5.0, 5.0, 0.0),
///     ],
///     vec![[0, 1, 2], [0, 2, 3]],
/// )
/// .unwrap();
/// let patch = ground_patch(&ground, Point2::new(0.0, 0.0), 1.0);
/// assert_eq!(patch.len(), 2);
/// ```
pub fn ground_patch(
    ground: &TriMesh,
    centre: nalgebra::Point2<f64>,
    half: f64,
) -> Vec<Vec<Point3<f64>>> {
    let (lo, hi) = (centre.x - half, centre.x + half);
    let (blo, bhi) = (centre.y - half, centre.y + half);
    let vertices = ground.vertices();
    let mut near: Vec<(f64, [Point3<f64>; 3])> = ground
        .triangles()
        .iter()
        .map(|t| t.map(|i| vertices[i]))
        .filter(|t| {
            let (x0, x1) = (
                t.iter().map(|p| p.x).fold(f64::INFINITY, f64::min),
                t.iter().map(|p| p.x).fold(f64::NEG_INFINITY, f64::max),
            );
            let (y0, y1) = (
                t.iter().map(|p| p.y).fold(f64::INFINITY, f64::min),
                t.iter().map(|p| p.y).fold(f64::NEG_INFINITY, f64::max),
            );
            x1 >= lo && x0 <= hi && y1 >= blo && y0 <= bhi
        })
        .map(|t| {
            let c = (t[0].coords + t[1].coords + t[2].coords) / 3.0;
            ((c.xy() - centre.coords).norm(), t)
        })
        .collect();
    near.sort_by(|a, b| a.0.total_cmp(&b.0));
    near.truncate(PICTURE_MAX_TRIANGLES);
    // The square's sides as (axis, bound, keep below): x <= hi, x >= lo, y <= bhi, y >= blo.
    let sides = [
        (0usize, hi, true),
        (0, lo, false),
        (1, bhi, true),
        (1, blo, false),
    ];
    near.into_iter()
        .filter_map(|(_, t)| {
            let mut poly: Vec<Point3<f64>> = t.to_vec();
            for (axis, bound, below) in sides {
                let inside = |p: &Point3<f64>| {
                    if below {
                        p[axis] <= bound
                    } else {
                        p[axis] >= bound
                    }
                };
                let mut out = Vec::with_capacity(poly.len() + 1);
                for (k, p) in poly.iter().enumerate() {
                    let q = &poly[(k + 1) % poly.len()];
                    if inside(p) {
                        out.push(*p);
                    }
                    if inside(p) != inside(q) {
                        let s = (bound - p[axis]) / (q[axis] - p[axis]);
                        let mut m = p + (q - p) * s;
                        m[axis] = bound;
                        out.push(m);
                    }
                }
                poly = out;
                if poly.is_empty() {
                    return None;
                }
            }
            (poly.len() >= 3).then_some(poly)
        })
        .collect()
}

/// An axonometric SVG of Axel `params` settled at `pose` on `ground` ([`crate::axonometric`]):
/// the ground within [`PICTURE_PATCH_TRACKS`] tracks of the axle ([`ground_patch`]), shaded by
/// slope and drawn back to front; the axle (body) between the two wheels, each wheel a rim of the wheel radius in its
/// plane with its settled contact marked; and, with the tether's last `anchor`, the boom in the
/// configuration that holds, labelled in its `data-boom` attribute: **inline** toward the anchor
/// (`boom inline toward the anchor`) when the inline boom clears the ground, else swept down to
/// its ground contact (`boom in contact with the ground`), and the tether from the boom's tip to
/// the anchor. The placement is geometry alone; the title adds the stability QP's verdict of
/// the drawn configuration from `verdicts` (the settle report's, [`rappel::settle::BoomVerdict`]:
/// `stable, margin 0.123`, `unstable`, or why it was not checked), so a boom drawn in place is
/// never read as a stable one.
///
/// ```
/// use rappel::settle::settle_report;
/// use rappel_render::settle::settled_pose_picture;
/// use rappel::mechanics::axel::AxelParams;
/// use rappel::terrain::mesh::TriMesh;
/// use nalgebra::Point3;
/// let ground = TriMesh::new(
///     vec![
///         Point3::new(-5.0, -5.0, 0.0),
///         Point3::new(5.0, -5.0, 0.0),
///         Point3::new(5.0, 5.0, 0.0),
///         Point3::new(-5.0, 5.0, 0.0),
///     ],
///     vec![[0, 1, 2], [0, 2, 3]],
/// )
/// .unwrap();
/// let (pose, _) = settle_report(&ground, 0.0, 0.0, 0.0, None).unwrap();
/// let svg = settled_pose_picture(
///     &ground,
///     &pose,
///     &AxelParams::default(),
///     Some([-4.0, 0.0, 2.0]),
///     &[],
///     "flat",
/// );
/// assert!(svg.contains("<g id=\"wheels\">") && svg.contains("<g id=\"tether\">"));
/// ```
pub fn settled_pose_picture(
    ground: &TriMesh,
    pose: &SettledPose,
    params: &AxelParams,
    anchor: Option<[f64; 3]>,
    verdicts: &[rappel::settle::BoomVerdict],
    title: &str,
) -> String {
    use crate::axonometric::Axonometric;
    use nalgebra::Vector3;
    let pivot = rappel::planners::rover::stability_map::tether_end(pose, params);
    let mut faces: Vec<(f64, Vec<Point3<f64>>, f64)> =
        ground_patch(ground, pivot.xy(), PICTURE_PATCH_TRACKS * params.track)
            .into_iter()
            .map(|f| {
                let n = (f[1] - f[0]).cross(&(f[2] - f[0]));
                let cos_slope = (n.z.abs() / n.norm().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
                let c = f.iter().fold(Vector3::zeros(), |a, p| a + p.coords) / f.len() as f64;
                (Axonometric::depth(&Point3::from(c)), f, cos_slope)
            })
            .collect();
    faces.sort_by(|a, b| b.0.total_cmp(&a.0));
    let mut view = Axonometric::default();
    view.group("ground");
    for (_, f, cos_slope) in &faces {
        view.shaded_polygon(f, *cos_slope);
    }
    let frame = |v: Vector3<f64>| pose.rotation * v;
    let half = 0.5 * params.track;
    let hubs = [-half, half].map(|y| pivot + frame(Vector3::new(0.0, y, 0.0)));
    view.group("body");
    view.polyline(&hubs, "stroke=\"#1f77b4\" stroke-width=\"5\"");
    view.group("wheels");
    for hub in &hubs {
        let rim: Vec<Point3<f64>> = (0..RIM_POINTS)
            .map(|k| {
                let t = std::f64::consts::TAU * k as f64 / RIM_POINTS as f64;
                hub + frame(Vector3::new(t.cos(), 0.0, t.sin()) * params.wheel_radius)
            })
            .collect();
        view.polygon(
            &rim,
            "fill=\"#1f77b4\" fill-opacity=\"0.35\" stroke=\"#1f77b4\" stroke-width=\"2\"",
        );
    }
    for c in &pose.contacts {
        view.polyline(
            &[*c, *c + frame(Vector3::z()) * 0.25 * params.wheel_radius],
            "class=\"contact\" stroke=\"#ff7f0e\" stroke-width=\"3\"",
        );
    }
    if let Some(anchor) = anchor.map(Point3::from) {
        // The configuration that holds: inline toward the anchor when the inline boom clears the
        // ground, else swept down to its contact (Paton §IV-A; `boom_contact`).
        let inline = rappel_mechanics::boom_contact::place_boom_inline(
            pose,
            params,
            ground,
            rappel::settle::SCENE_FRICTION,
            (&anchor, None),
        );
        let contact = rappel_mechanics::boom_contact::place_boom_in_contact(
            pose,
            params,
            ground,
            rappel::settle::SCENE_FRICTION,
            (&anchor, None),
        );
        let (tip, label, boom) = match (inline, contact) {
            (Ok(placed), _) => (
                placed.tether.map_or(pivot, |t| t.exit),
                "boom inline toward the anchor",
                "inline",
            ),
            (Err(_), Ok((_, c))) => (c.tip, "boom in contact with the ground", "in-contact"),
            (Err(_), Err(_)) => (pivot, "no boom configuration can be placed", ""),
        };
        let qp = match verdicts.iter().find(|v| v.boom == boom) {
            Some(v) => match (v.stable, &v.error) {
                (Some(true), _) => format!(", stable (QP margin {:.3})", v.margin),
                (Some(false), _) => ", unstable (QP)".to_string(),
                (None, Some(e)) => format!(", not checked: {e}"),
                (None, None) => String::new(),
            },
            None => String::new(),
        };
        view.group("boom");
        view.polyline(
            &[pivot, tip],
            &format!("stroke=\"#333\" stroke-width=\"3\" data-boom=\"{label}\""),
        );
        view.group("tether");
        view.polyline(&[tip, anchor], "stroke=\"#d62728\" stroke-width=\"2\"");
        return view.render(&format!("{title}: {label}{qp}"));
    }
    view.render(title)
}

/// Points on each drawn wheel rim.
const RIM_POINTS: usize = 32;
