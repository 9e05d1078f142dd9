//! Anchor prediction (Paton Alg. 1) against geometry: the ledge lip of Paton's scene (closed-form
//! line), the wrap around the test-3 pole (closed-form tangent points and wrap length of a
//! cylinder), a cross-check with the planar tether tracker on a convex plane series, detachment,
//! and typed errors for bad input.

use nalgebra::{Point2, Point3, Vector3};
use rappel_planners::anchor_prediction::{
    AnchorError, AnchorHistory, EventKind, PredictParams, predict, predict_path,
};
use rappel_planners::tether_tracking::{AnchorKind, TetherTracker};
use rappel_terrain::mesh::TriMesh;
use rappel_terrain::paton_scene::PatonScene;
use rappel_terrain::plane_series::TerrainPlane;
use rappel_terrain::plane_series_terrain::PlaneSeriesTerrain;
use rappel_terrain::sdf::{Sdf, SdfParams};
use rappel_terrain::surface::{SignedDistance, Terrain};

/// The ledge's ground point and upward normal under `(x, y)` (closed form: the top for `x <= 0`,
/// the 55° slope beyond).
fn ledge_ground(scene: &PatonScene, x: f64, y: f64) -> (Point3<f64>, Vector3<f64>) {
    let a = scene.slope_deg.to_radians();
    if x <= 0.0 {
        (Point3::new(x, y, scene.height), Vector3::z())
    } else {
        (
            Point3::new(x, y, scene.height - x * a.tan()),
            Vector3::new(a.sin(), 0.0, a.cos()),
        )
    }
}

/// Tips `lift` above the ledge from `(x0, y0)` to `(x1, y1)` in `n` steps.
fn ledge_tips(scene: &PatonScene, a: (f64, f64), b: (f64, f64), n: usize) -> Vec<Point3<f64>> {
    (0..=n)
        .map(|k| {
            let s = k as f64 / n as f64;
            let (g, nrm) = ledge_ground(scene, a.0 + (b.0 - a.0) * s, a.1 + (b.1 - a.1) * s);
            g + nrm * 0.3
        })
        .collect()
}

fn assert_on_lip(scene: &PatonScene, p: &Point3<f64>, tol: f64) {
    // The lip: x = 0, z = height, |y| <= length / 2.
    assert!(
        p.x.abs() < tol && (p.z - scene.height).abs() < tol && p.y.abs() <= 0.5 * scene.length,
        "anchor {p:?} not on the lip line x = 0, z = {} (tol {tol})",
        scene.height
    );
}

#[test]
fn tether_pulled_over_the_ledge_lip_anchors_on_the_lip() {
    let scene = PatonScene::paper(false);
    let mesh = scene.mesh().unwrap();
    let root = AnchorHistory::new(scene.anchor_points()[0]).unwrap();
    let h = 0.02;
    for y_end in [0.0, 2.0, -3.0] {
        let tips = ledge_tips(&scene, (-1.0, 0.0), (1.4, y_end), 24);
        let out = predict_path(&mesh, &PredictParams::new(h), &root, &tips).unwrap();
        assert_eq!(out.history.len(), 2, "y_end {y_end}: {:?}", out.history);
        assert_eq!(out.events.len(), 1);
        assert_eq!(out.events[0].kind, EventKind::Attach);
        assert_on_lip(&scene, &out.history.last().point, 2.0 * h);
        // The anchor's gradient lies between the top's and the slope's normals (the lip's
        // normal cone): both components non-negative along x and z.
        let g = out.history.last().gradient;
        assert!(g.x >= -1e-6 && g.z >= -1e-6 && g.y.abs() < 1e-6, "{g:?}");
        // Before the lip the tether is free: the attach happens past the lip.
        assert!(out.events[0].tip.x > -0.5, "{:?}", out.events[0]);
    }
}

#[test]
fn lip_anchor_through_the_distance_field() {
    // A smaller ground margin and a root 0.5 m above the top keep the field small (a 1 m margin
    // around the scene); the ledge is the paper's.
    let scene = PatonScene {
        ground_margin: 1.0,
        ..PatonScene::paper(false)
    };
    let mesh = scene.mesh().unwrap();
    let h = 0.1;
    let field = Sdf::from_mesh(
        &mesh,
        &SdfParams {
            margin: 1.0,
            ..SdfParams::new(h)
        },
    )
    .unwrap();
    let root = AnchorHistory::new(Point3::new(-4.5, 0.0, scene.height + 0.5)).unwrap();
    let tips = ledge_tips(&scene, (-1.0, 0.0), (1.4, 1.0), 12);
    let out = predict_path(&field, &PredictParams::new(h), &root, &tips).unwrap();
    assert_eq!(out.history.len(), 2, "{:?}", out.history);
    // The field's own error (0.87 h) plus the sampling: within 2 h of the lip.
    assert_on_lip(&scene, &out.history.last().point, 2.0 * h);
}

#[test]
fn pulling_back_onto_the_top_detaches_where_the_tether_straightens() {
    let scene = PatonScene::paper(false);
    let mesh = scene.mesh().unwrap();
    let root = AnchorHistory::new(scene.anchor_points()[0]).unwrap();
    let h = 0.02;
    let down = ledge_tips(&scene, (-1.0, 0.0), (1.4, 0.0), 12);
    let over = predict_path(&mesh, &PredictParams::new(h), &root, &down).unwrap();
    assert_eq!(over.history.len(), 2);
    // A straight step back up would cut through the lip: refused.
    assert!(matches!(
        predict(
            &mesh,
            &PredictParams::new(h),
            &over.history,
            down.last().unwrap(),
            &down[0]
        ),
        Err(AnchorError::TipInGround {
            what: "the motion",
            ..
        })
    ));
    // Back up the same way: the lip is released on the way.
    let up: Vec<Point3<f64>> = down.iter().rev().copied().collect();
    let back = predict_path(&mesh, &PredictParams::new(h), &over.history, &up).unwrap();
    assert_eq!(back.history.len(), 1, "{:?}", back.history);
    assert_eq!(back.events.len(), 1, "{:?}", back.events);
    let ev = back.events[0];
    assert_eq!(ev.kind, EventKind::Detach);
    // Where it detaches, root, lip anchor and tip are collinear (the tether is straight).
    let (r, a) = (root.root().point, over.history.last().point);
    let u = (a - r).normalize();
    let off = (ev.tip - r) - u * (ev.tip - r).dot(&u);
    assert!(
        off.norm() < 1e-6,
        "detach tip {:?} is {} m off the line",
        ev.tip,
        off.norm()
    );
}

#[test]
fn tether_swept_around_the_pole_wraps_it_at_the_tangent_points() {
    let scene = PatonScene::paper(true);
    let mesh = scene.mesh().unwrap();
    let c = scene.pole_center().unwrap();
    let r = scene.pole.unwrap().radius;
    let z = scene.height + 2.0;
    let centre = Point3::new(c.x, c.y, z);
    // Root 4 m to the -y side of the pole; the tip circles it at 2 m from -30° to 200°
    // (counter-clockwise), the tether horizontal at 2 m above the ledge top.
    let (dr, rt) = (4.0, 2.0);
    let root_p = centre + Vector3::new(0.0, -dr, 0.0);
    let root = AnchorHistory::new(root_p).unwrap();
    let at =
        |deg: f64| centre + Vector3::new(deg.to_radians().cos(), deg.to_radians().sin(), 0.0) * rt;
    let tips: Vec<Point3<f64>> = (0..=46).map(|k| at(-30.0 + 5.0 * k as f64)).collect();
    let h = 0.03;
    let out = predict_path(&mesh, &PredictParams::new(h), &root, &tips).unwrap();
    let anchors = &out.history.anchors()[1..];
    assert!(anchors.len() >= 2, "{:?}", out.history);
    // Closed form: tangent point from the root (right side), from the tip (left of the far side).
    let t1 = -90.0 + (r / dr).acos().to_degrees();
    let t2 = 200.0 - (r / rt).acos().to_degrees();
    let angle = |p: &Point3<f64>| {
        let a = (p.y - centre.y).atan2(p.x - centre.x).to_degrees();
        if a < -100.0 { a + 360.0 } else { a }
    };
    // The 32-gon's sides are within 0.005 r of the circle; the contact is found h deep.
    for a in anchors {
        let rad = ((a.point.x - c.x).powi(2) + (a.point.y - c.y).powi(2)).sqrt();
        assert!(
            (rad - r).abs() < 0.01 * r + 1e-3,
            "anchor {:?} radius {rad}",
            a.point
        );
        assert!(
            (a.point.z - z).abs() < 1e-6,
            "anchor off the tether's plane: {:?}",
            a.point
        );
    }
    let first = angle(&anchors[0].point);
    assert!(
        (first - t1).abs() < 3.0,
        "first anchor at {first}°, tangent point {t1}°"
    );
    // Anchors go around counter-clockwise within [t1, t2].
    let angles: Vec<f64> = anchors.iter().map(|a| angle(&a.point)).collect();
    assert!(angles.windows(2).all(|w| w[1] > w[0]), "{angles:?}");
    assert!(*angles.last().unwrap() < t2 + 3.0, "{angles:?} past {t2}");
    // The free tether from the last anchor is tangent: its distance to the axis is r within
    // the contact depth.
    let tip = tips.last().unwrap();
    let last = anchors.last().unwrap().point;
    let u = (tip - last).normalize();
    let w = centre - last;
    let dist = (w - u * w.dot(&u)).norm();
    assert!(
        dist > r - h - 0.01 && dist < r + 0.01,
        "free tether {dist} m from the axis"
    );
    // Length against the closed-form wrap: two tangents plus the arc.
    let want = (dr * dr - r * r).sqrt() + r * (t2 - t1).to_radians() + (rt * rt - r * r).sqrt();
    let got = out.history.tether_length(tip);
    assert!(
        (got - want).abs() < 0.01 * want,
        "length {got} vs closed form {want}"
    );
}

#[test]
fn crest_anchors_agree_with_the_planar_tracker() {
    // A flat top, then 35° and 60° bands: two crests (Kumar's concave changes).
    let planes = vec![
        TerrainPlane::new(40.0, 20.0, 0.0, 0.4),
        TerrainPlane::new(20.0, 10.0, 35.0, 0.4),
        TerrainPlane::new(10.0, 0.0, 60.0, 0.4),
    ];
    let terrain = PlaneSeriesTerrain::new(&planes, (0.0, 40.0), Vec::new()).unwrap();
    let base = Point2::new(10.0, 30.0);
    let h = 0.05;
    for x_end in [4.0, 10.0, 22.0, 36.0] {
        // Radial: the tracker's ground anchors stay where the tether first touched.
        let end = Point2::new(x_end, 2.0);
        let frame: Vec<Point2<f64>> = (0..=80)
            .map(|k| base + (end - base) * (k as f64 / 80.0))
            .collect();
        let mut tracker = TetherTracker::new(&terrain, base, base).unwrap();
        tracker.follow(&frame).unwrap();
        let want: Vec<Point3<f64>> = tracker
            .configuration()
            .iter()
            .filter(|a| matches!(a.kind, AnchorKind::Ground { .. }))
            .map(|a| a.world)
            .collect();
        let tips: Vec<Point3<f64>> = frame.iter().map(|p| terrain.world(p).unwrap()).collect();
        let root = AnchorHistory::new(tips[0]).unwrap();
        let got = predict_path(&terrain, &PredictParams::new(h), &root, &tips).unwrap();
        let got: Vec<Point3<f64>> = got.history.anchors()[1..].iter().map(|a| a.point).collect();
        assert_eq!(
            got.len(),
            want.len(),
            "x_end {x_end}: {got:?} vs tracker {want:?}"
        );
        assert_eq!(want.len(), 2);
        for (g, w) in got.iter().zip(&want) {
            assert!(
                (g - w).norm() < 2.0 * h,
                "x_end {x_end}: {g:?} vs tracker {w:?}"
            );
        }
    }
}

#[test]
fn bad_input_is_a_typed_error() {
    let scene = PatonScene::paper(false);
    let mesh: TriMesh = scene.mesh().unwrap();
    let root = AnchorHistory::new(scene.anchor_points()[0]).unwrap();
    let p = PredictParams::new(0.05);
    let ok = Point3::new(-1.0, 0.0, 4.3);
    let nan = Point3::new(f64::NAN, 0.0, 4.3);
    assert!(matches!(
        predict(&mesh, &p, &root, &nan, &ok),
        Err(AnchorError::NonFinite {
            what: "the start tip"
        })
    ));
    assert!(matches!(
        predict(&mesh, &p, &root, &ok, &nan),
        Err(AnchorError::NonFinite {
            what: "the end tip"
        })
    ));
    assert!(AnchorHistory::new(Point3::new(0.0, f64::INFINITY, 0.0)).is_err());
    // Inside the ledge, 1 m under the top.
    let inside = Point3::new(-2.0, 0.0, 3.0);
    match predict(&mesh, &p, &root, &ok, &inside) {
        Err(AnchorError::TipInGround { depth, .. }) => assert!((depth - 1.0).abs() < 1e-9),
        other => panic!("{other:?}"),
    }
    for bad in [0.0, -1.0, f64::NAN] {
        assert!(matches!(
            predict(&mesh, &PredictParams::new(bad), &root, &ok, &ok),
            Err(AnchorError::BadParameter { .. })
        ));
    }
    let tight = PredictParams {
        max_samples: 50,
        ..PredictParams::new(0.01)
    };
    let far = Point3::new(1.0, 0.0, 4.0 - 55f64.to_radians().tan() + 0.3);
    assert!(matches!(
        predict(&mesh, &tight, &root, &ok, &far),
        Err(AnchorError::SampleBudget { limit: 50 })
    ));
    // Off a planar terrain's surfaces the analytic distance has no answer.
    let planes = vec![TerrainPlane::new(10.0, 0.0, 0.0, 0.4)];
    let t = PlaneSeriesTerrain::new(&planes, (0.0, 10.0), Vec::new()).unwrap();
    let r = AnchorHistory::new(Point3::new(5.0, 5.0, 0.0)).unwrap();
    let off = Point3::new(50.0, 5.0, 0.0);
    assert!(t.signed_distance(&off).is_none());
    assert!(matches!(
        predict(&t, &p, &r, &Point3::new(5.0, 6.0, 0.0), &off),
        Err(AnchorError::NoDistance { .. })
    ));
}

/// A ground that counts its distance queries.
struct Counted<'a> {
    mesh: &'a TriMesh,
    queries: std::cell::Cell<usize>,
}

impl SignedDistance for Counted<'_> {
    fn signed_distance(&self, q: &Point3<f64>) -> Option<f64> {
        self.queries.set(self.queries.get() + 1);
        SignedDistance::signed_distance(self.mesh, q)
    }
    fn distance_gradient(&self, q: &Point3<f64>) -> Option<Vector3<f64>> {
        SignedDistance::distance_gradient(self.mesh, q)
    }
}

#[test]
fn clear_ball_skipping_finds_the_same_anchors_with_fewer_queries() {
    // The pole wrap and the lip bend of Paton's scenes, on the exact mesh: with skipping
    // (`PredictParams::exact`) every event and anchor is bit-identical to the plain sampling,
    // and the tether in open air needs far fewer distance queries.
    let pole = PatonScene::paper(true);
    let mesh = pole.mesh().unwrap();
    let c = pole.pole_center().unwrap();
    let centre = Point3::new(c.x, c.y, pole.height + 2.0);
    let root = AnchorHistory::new(centre + Vector3::new(0.0, -4.0, 0.0)).unwrap();
    let tips: Vec<Point3<f64>> = (0..=46)
        .map(|k| {
            let a = (-30.0 + 5.0 * k as f64).to_radians();
            centre + Vector3::new(a.cos(), a.sin(), 0.0) * 2.0
        })
        .collect();
    let ledge = PatonScene::paper(false);
    let ledge_mesh = ledge.mesh().unwrap();
    let lip_root = AnchorHistory::new(ledge.anchor_points()[0]).unwrap();
    let lip_tips = ledge_tips(&ledge, (-1.0, 0.0), (1.4, 2.0), 24);
    for (m, root, tips, h) in [
        (&mesh, &root, &tips, 0.03),
        (&ledge_mesh, &lip_root, &lip_tips, 0.02),
    ] {
        let run = |params: PredictParams| {
            let g = Counted {
                mesh: m,
                queries: std::cell::Cell::new(0),
            };
            let out = predict_path(&g, &params, root, tips).unwrap();
            (out, g.queries.get())
        };
        let (plain, n_plain) = run(PredictParams::new(h));
        let (skip, n_skip) = run(PredictParams::exact(h));
        assert!(plain.history.len() >= 2, "{:?}", plain.history);
        assert_eq!(plain, skip);
        assert!(
            2 * n_skip < n_plain,
            "{n_skip} queries with skipping, {n_plain} without"
        );
    }
}
