//! Regression cases of mesh traversability (issue 14, Paton §IV-V): Axel settled on Paton's ledge
//! scene (`fixtures/paton/ledge.ron`) against closed forms, and Fig. 8's shading: the test-1
//! anchor (4.9 m behind, 2.0 m above the start) makes the slope in front of the rover stable, the
//! test-2 anchor (8.2 m in front, 2.0 m above) makes the whole 55° slope unstable. A pose counts
//! as stable when the QP finds an equilibrium with the boom inline or in contact.

use super::{Case, workspace_root};
use rappel::settle::{load_ground, load_scene, settle_report};
use rappel::terrain::paton_scene::PatonScene;

const SUITE: &str = "paton";

/// Settles at `(x, y)` facing `+x` (down the slope); `Some(stable)` with an anchor.
fn stable_at(
    ground: &rappel::terrain::mesh::TriMesh,
    x: f64,
    y: f64,
    anchor: [f64; 3],
) -> Result<bool, String> {
    let (_, r) = settle_report(ground, x, y, 0.0, Some(anchor)).map_err(|e| e.to_string())?;
    Ok(r.stability.iter().any(|v| v.stable == Some(true)))
}

/// The suite.
pub fn suite() -> Result<Vec<Case>, String> {
    let path = workspace_root().join("fixtures/paton/ledge.ron");
    let ground = load_ground(&path).map_err(|e| e.to_string())?;
    let scene: PatonScene = load_scene(&path).map_err(|e| e.to_string())?;
    let mut cases = Vec::new();
    // Settling against closed forms: on the top (height 4 m, level) and mid-slope (pitch -55°,
    // height 4 - x tan 55°).
    let (_, top) = settle_report(&ground, -1.0, 0.0, 0.0, None).map_err(|e| e.to_string())?;
    cases.push(Case::new(
        SUITE,
        "settle on the ledge top: height, pitch",
        format!("{:.4} m, {:.3}°", top.origin[2], top.pitch_deg),
        "4.0000 m, 0.000° (the top plane)",
        (top.origin[2] - 4.0).abs() < 1e-3 && top.pitch_deg.abs() < 1e-3f64.to_degrees(),
    ));
    let x = 0.5 * scene.slope_foot_x();
    let want = 4.0 - x * scene.slope_deg.to_radians().tan();
    let (_, mid) = settle_report(&ground, x, 0.0, 0.0, None).map_err(|e| e.to_string())?;
    cases.push(Case::new(
        SUITE,
        "settle mid-slope facing down: height, pitch",
        format!("{:.4} m, {:.3}°", mid.origin[2], mid.pitch_deg),
        format!("{want:.4} m, -55.000° (4 - x tan 55°)"),
        (mid.origin[2] - want).abs() < 1e-3
            && (mid.pitch_deg + scene.slope_deg).abs() < 1e-3f64.to_degrees(),
    ));
    // Fig. 8 shading over the slope: 3 positions down the slope by `ys` across it.
    let anchors = scene.anchor_points();
    let down: Vec<f64> = [0.25, 0.5, 0.75]
        .iter()
        .map(|f| f * scene.slope_foot_x())
        .collect();
    let shade =
        |anchor: &rappel::nalgebra::Point3<f64>, ys: &[f64]| -> Result<(usize, usize), String> {
            let mut stable = 0;
            let mut n = 0;
            for &x in &down {
                for &y in ys {
                    n += 1;
                    if stable_at(&ground, x, y, [anchor.x, anchor.y, anchor.z])? {
                        stable += 1;
                    }
                }
            }
            Ok((stable, n))
        };
    let (s1, n1) = shade(&anchors[0], &[-1.0, 0.0, 1.0])?;
    cases.push(Case::new(
        SUITE,
        "Fig. 8 test 1 anchor: slope in front of the rover",
        format!("{s1}/{n1} stable"),
        format!("{n1}/{n1} stable (green)"),
        s1 == n1,
    ));
    let ys: Vec<f64> = (-4..=4).map(f64::from).collect();
    let (s2, n2) = shade(&anchors[1], &ys)?;
    cases.push(Case::new(
        SUITE,
        "Fig. 8 test 2 anchor: the whole 55° slope",
        format!("{s2}/{n2} stable"),
        format!("0/{n2} stable (red)"),
        s2 == 0,
    ));
    Ok(cases)
}
