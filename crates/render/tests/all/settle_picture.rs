//! The axonometric picture of a settled pose (`rappel settle --svg`): the ground patch tiles the
//! square around the pose (plan areas summed here) on the mesh, two wheels, a body, a boom and a
//! tether, and the rendered pixels show the wheels' blue and the tether's red.

use rappel::mechanics::axel::AxelParams;
use rappel::settle::{load_ground, settle_report};
use rappel_render::settle::{PICTURE_PATCH_TRACKS, ground_patch, settled_pose_picture};

fn group<'a>(svg: &'a str, id: &str) -> &'a str {
    let open = format!("<g id=\"{id}\">");
    let i = svg.find(&open).unwrap_or_else(|| panic!("no group {id}")) + open.len();
    &svg[i..i + svg[i..].find("</g>").expect("group end")]
}

#[test]
fn a_settled_pose_is_drawn_with_its_ground_wheels_boom_and_tether() {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/paton/ledge.ron");
    let ground = load_ground(&path).expect("the ledge scene");
    let anchor = [-3.0, 0.0, 4.5];
    let (pose, _) = settle_report(&ground, -1.0, 0.0, 0.0, Some(anchor)).expect("settles");
    let params = AxelParams::default();
    let svg = settled_pose_picture(&ground, &pose, &params, Some(anchor), &[], "ledge");

    // The ground: the clipped pieces of the mesh over the square around the axle centre tile
    // it (the ledge is a height field): their plan areas sum to the square's, every corner lies
    // in the square and on the mesh.
    let pivot = pose.origin + pose.rotation * nalgebra::Vector3::z() * params.wheel_radius;
    let half = PICTURE_PATCH_TRACKS * params.track;
    let patch = ground_patch(&ground, pivot.xy(), half);
    let area: f64 = patch
        .iter()
        .map(|f| {
            let n = f.len();
            0.5 * (0..n)
                .map(|k| f[k].x * f[(k + 1) % n].y - f[(k + 1) % n].x * f[k].y)
                .sum::<f64>()
                .abs()
        })
        .sum();
    assert!(
        (area - 4.0 * half * half).abs() < 1e-9 * half * half,
        "{area}"
    );
    for p in patch.iter().flatten() {
        assert!(
            (p.x - pivot.x).abs() <= half * (1.0 + 1e-12)
                && (p.y - pivot.y).abs() <= half * (1.0 + 1e-12)
        );
        let d = ground.signed_distance(p);
        assert!(d.abs() < 1e-9, "{p}: {d}");
    }
    assert_eq!(
        group(&svg, "ground").matches("<polygon").count(),
        patch.len()
    );
    assert_eq!(group(&svg, "wheels").matches("<polygon").count(), 2);
    assert_eq!(
        group(&svg, "wheels").matches("class=\"contact\"").count(),
        2
    );
    assert_eq!(group(&svg, "boom").matches("<polyline").count(), 1);
    assert_eq!(group(&svg, "tether").matches("<polyline").count(), 1);

    // Rendered: the tether's red and the wheels' blue are visible.
    let tree = resvg::usvg::Tree::from_str(&svg, &resvg::usvg::Options::default()).expect("SVG");
    let size = tree.size().to_int_size();
    let mut pixmap = resvg::tiny_skia::Pixmap::new(size.width(), size.height()).expect("size");
    resvg::render(
        &tree,
        resvg::tiny_skia::Transform::default(),
        &mut pixmap.as_mut(),
    );
    let shows = |rgb: [u8; 3]| {
        pixmap.pixels().iter().any(|p| {
            let c = p.demultiply();
            [c.red(), c.green(), c.blue()]
                .iter()
                .zip(rgb)
                .all(|(a, b)| a.abs_diff(b) <= 3)
        })
    };
    assert!(shows([0xd6, 0x27, 0x28]), "the tether's red");
    assert!(shows([0x1f, 0x77, 0xb4]), "the wheels' blue");

    // Without an anchor: no boom, no tether.
    let bare = settled_pose_picture(&ground, &pose, &params, None, &[], "ledge");
    assert!(!bare.contains("<g id=\"tether\">") && !bare.contains("<g id=\"boom\">"));
}

/// The boom is drawn in the configuration that holds, and labelled: on the top with an anchor
/// far above and behind, inline toward it (the boom's tip on the line from the pivot to the
/// anchor, one boom length out); 0.4 m past the lip with the anchor low behind it, the inline
/// boom would pass through the ledge, so it is drawn swept down to its ground contact
/// (the tip where `boom_contact` puts it, not on the line to the anchor).
#[test]
fn the_boom_is_drawn_in_the_configuration_that_holds() {
    use nalgebra::{Point3, Vector3};
    use rappel::mechanics::boom_contact::{place_boom_in_contact, place_boom_inline};
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/paton/ledge.ron");
    let ground = load_ground(&path).expect("the ledge scene");
    let params = AxelParams::default();
    // The boom's direction in the picture: its polyline's (SVG y down) against the projection
    // of `tip - pivot` (uniform scale): the cosine between them.
    let boom_dir = |svg: &str| -> (f64, f64) {
        let g = group(svg, "boom");
        let i = g.find("points=\"").expect("boom points") + 8;
        let pts: Vec<f64> = g[i..i + g[i..].find('"').unwrap()]
            .split([' ', ','])
            .map(|v| v.parse().unwrap())
            .collect();
        (pts[2] - pts[0], pts[1] - pts[3])
    };
    let cosine = |svg: &str, pivot: Point3<f64>, tip: Point3<f64>| {
        let (p, q) = (
            rappel_render::axonometric::Axonometric::project(&pivot),
            rappel_render::axonometric::Axonometric::project(&tip),
        );
        let (a, b) = (boom_dir(svg), (q.x - p.x, q.y - p.y));
        (a.0 * b.0 + a.1 * b.1) / (a.0.hypot(a.1) * b.0.hypot(b.1))
    };
    // Inline on the top.
    let anchor = [-6.0, 0.0, 10.0];
    let (pose, _) = settle_report(&ground, -2.0, 0.0, 0.0, Some(anchor)).expect("settles");
    let a = Point3::from(anchor);
    assert!(place_boom_inline(&pose, &params, &ground, 0.6, (&a, None)).is_ok());
    let svg = settled_pose_picture(&ground, &pose, &params, Some(anchor), &[], "top");
    assert!(svg.contains("boom inline toward the anchor") && !svg.contains("in contact with"));
    let pivot = pose.origin + pose.rotation * Vector3::z() * params.wheel_radius;
    let tip = pivot + (a - pivot).normalize() * params.boom_length;
    assert!(cosine(&svg, pivot, tip) > 1.0 - 1e-6);
    // In contact past the lip, the anchor low behind the lip (the line to it cuts the ledge).
    let anchor = [-6.0, 0.0, 4.5];
    let a = Point3::from(anchor);
    let (pose, _) = settle_report(&ground, 0.4, 0.0, 0.0, Some(anchor)).expect("settles");
    assert!(place_boom_inline(&pose, &params, &ground, 0.6, (&a, None)).is_err());
    let (_, c) = place_boom_in_contact(&pose, &params, &ground, 0.6, (&a, None)).expect("rests");
    let svg = settled_pose_picture(&ground, &pose, &params, Some(anchor), &[], "lip");
    assert!(svg.contains("boom in contact with the ground") && !svg.contains("inline toward"));
    let pivot = pose.origin + pose.rotation * Vector3::z() * params.wheel_radius;
    let inline_tip = pivot + (a - pivot).normalize() * params.boom_length;
    assert!(cosine(&svg, pivot, c.tip) > 1.0 - 1e-6);
    assert!(cosine(&svg, pivot, inline_tip) < 0.99);
}
