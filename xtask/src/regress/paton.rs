//! Regression cases of mesh traversability (issue 14, Paton §IV-V): Axel settled on Paton's ledge
//! scene (`fixtures/paton/ledge.ron`) against closed forms, and Fig. 8's shading: the test-1
//! anchor (4.9 m behind, 2.0 m above the start) makes the slope in front of the rover stable, the
//! test-2 anchor (8.2 m in front, 2.0 m above) makes the whole 55° slope unstable. Each pose is
//! reached by a drive from the start with its anchor history predicted (Paton Alg. 1), and the
//! QP uses the last predicted anchor; a pose counts as stable when the QP finds an equilibrium
//! with the boom inline or in contact. Test 3: the tether swept around the pole against the
//! closed-form wrap of a cylinder.

use super::{Case, workspace_root};
use rappel::mesh_stability::{
    MapSpec, PREDICT_RESOLUTION, PoseStability, drive_and_check, stability_map,
};
use rappel::nalgebra::{Point3, Vector3};
use rappel::planners::anchor_prediction::{AnchorHistory, PredictParams, predict_path};
use rappel::settle::{load_ground, load_scene, settle_report};
use rappel::terrain::paton_scene::PatonScene;

const SUITE: &str = "paton";

/// Drives Axel from the scene's start straight to `(x, y)` facing `+x` (down the slope) under
/// the root anchor `root`, predicting the anchor history on the way (Paton Alg. 1); the settled
/// pose's stability with the tether from the last predicted anchor.
fn drive(
    ground: &rappel::terrain::mesh::TriMesh,
    scene: &PatonScene,
    x: f64,
    y: f64,
    root: &Point3<f64>,
) -> Result<PoseStability, String> {
    let s = scene.start();
    let root = AnchorHistory::new(*root).map_err(|e| e.to_string())?;
    drive_and_check(ground, &root, [s.x, s.y], [x, y], 0.0).map_err(|e| e.to_string())
}

/// The predicted anchor lies on the lip (`x = 0`, `z = height`, closed form) within two sampling
/// resolutions.
fn on_lip(scene: &PatonScene, a: &[f64; 3]) -> bool {
    a[0].abs() < 2.0 * PREDICT_RESOLUTION && (a[2] - scene.height).abs() < 2.0 * PREDICT_RESOLUTION
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
    // Each pose: (stable, anchors in its history, last anchor on the lip).
    let shade = |anchor: &Point3<f64>, ys: &[f64]| -> Result<Vec<(bool, usize, bool)>, String> {
        let mut out = Vec::new();
        for &x in &down {
            for &y in ys {
                let p = drive(&ground, &scene, x, y, anchor)?;
                let last = p.anchors.last().copied().unwrap_or_default();
                out.push((p.stable, p.anchors.len(), on_lip(&scene, &last)));
            }
        }
        Ok(out)
    };
    let one = shade(&anchors[0], &[-1.0, 0.0, 1.0])?;
    let n1 = one.len();
    let s1 = one.iter().filter(|p| p.0).count();
    let lip1 = one.iter().filter(|p| p.1 == 2 && p.2).count();
    cases.push(Case::new(
        SUITE,
        "Fig. 8 test 1: predicted anchor on the lip (x = 0, z = 4) for slope poses",
        format!("{lip1}/{n1} with one anchor on the lip"),
        format!("{n1}/{n1} (the tether from 4.9 m behind bends over the lip)"),
        lip1 == n1,
    ));
    cases.push(Case::new(
        SUITE,
        "Fig. 8 test 1 anchor (predicted): slope in front of the rover",
        format!("{s1}/{n1} stable"),
        format!("{n1}/{n1} stable (green)"),
        s1 == n1,
    ));
    let ys: Vec<f64> = (-4..=4).map(f64::from).collect();
    let two = shade(&anchors[1], &ys)?;
    let n2 = two.len();
    let s2 = two.iter().filter(|p| p.0).count();
    let free2 = two.iter().filter(|p| p.1 == 1).count();
    cases.push(Case::new(
        SUITE,
        "Fig. 8 test 2: no anchor attaches (tether in the air in front)",
        format!("{free2}/{n2} with the root as last anchor"),
        format!("{n2}/{n2}"),
        free2 == n2,
    ));
    cases.push(Case::new(
        SUITE,
        "Fig. 8 test 2 anchor (predicted): the whole 55° slope",
        format!("{s2}/{n2} stable"),
        format!("0/{n2} stable (red)"),
        s2 == 0,
    ));
    // The map: 0.5 m cells, slope cells beyond the boom's reach from the lip (1 m).
    let s = scene.start();
    let spec = MapSpec {
        x: (-2.0, 2.5),
        y: (-2.0, 2.0),
        step: 0.5,
        yaw_deg: 0.0,
        start: [s.x, s.y],
    };
    let foot = scene.slope_foot_x();
    let map = |root: &Point3<f64>| -> Result<(usize, usize), String> {
        let h = AnchorHistory::new(*root).map_err(|e| e.to_string())?;
        let m = stability_map(&ground, &h, &spec).map_err(|e| e.to_string())?;
        let cells: Vec<_> = m
            .cells
            .iter()
            .filter(|c| c.ground[0] > 0.7 && c.ground[0] < foot - 0.3)
            .collect();
        let stable = cells
            .iter()
            .filter(|c| c.pose.as_ref().is_some_and(|p| p.stable))
            .count();
        Ok((stable, cells.len()))
    };
    let (m1, k1) = map(&anchors[0])?;
    let (m2, k2) = map(&anchors[1])?;
    cases.push(Case::new(
        SUITE,
        "Fig. 8 map (0.5 m): slope cells stable, test 1 / test 2 root",
        format!("{m1}/{k1}, {m2}/{k2}"),
        format!("{k1}/{k1}, 0/{k2} (green / red)"),
        k1 > 0 && m1 == k1 && m2 == 0,
    ));
    // Test 3: a tether swept around the pole wraps it; its length against the closed form of a
    // cylinder (two tangents and the arc), the tether horizontal 2 m above the top.
    let pole = PatonScene::paper(true);
    let pm = pole.mesh().map_err(|e| e.to_string())?;
    let (c, r) = (
        pole.pole_center().ok_or("no pole")?,
        pole.pole.ok_or("no pole")?.radius,
    );
    let centre = Point3::new(c.x, c.y, pole.height + 2.0);
    let (dr, rt) = (4.0, 2.0);
    let root =
        AnchorHistory::new(centre - Vector3::new(0.0, dr, 0.0)).map_err(|e| e.to_string())?;
    let tips: Vec<Point3<f64>> = (0..=46)
        .map(|k| {
            let a = (-30.0 + 5.0 * k as f64).to_radians();
            centre + Vector3::new(a.cos(), a.sin(), 0.0) * rt
        })
        .collect();
    let wrap =
        predict_path(&pm, &PredictParams::new(0.03), &root, &tips).map_err(|e| e.to_string())?;
    let t1 = -90.0 + (r / dr).acos().to_degrees();
    let t2 = 200.0 - (r / rt).acos().to_degrees();
    let want = (dr * dr - r * r).sqrt() + r * (t2 - t1).to_radians() + (rt * rt - r * r).sqrt();
    let got = wrap.history.tether_length(tips.last().ok_or("no tips")?);
    cases.push(Case::new(
        SUITE,
        "test 3 pole: tether swept 230° around the pole, length",
        format!("{got:.3} m, {} anchors", wrap.history.len() - 1),
        format!("{want:.3} m (tangents + arc of a 0.3 m cylinder), within 1%"),
        (got - want).abs() < 0.01 * want && wrap.history.len() > 2,
    ));
    cases.extend(table_one()?);
    Ok(cases)
}

/// Seeds of Table I's test `test`: Paton's 100 behind `--full`; in CI 3 for test 1 (under a
/// second a seed to the first solution), 2 for test 2 (all 750 iterations, about 5 s a seed)
/// and 1 for test 3 (its first solution after 571 iterations, about 5 s), which keeps the
/// rows well under a minute on 2 cores.
fn table_seeds(test: u32) -> Vec<u64> {
    let ci = match test {
        1 => 3,
        2 => 2,
        _ => 1,
    };
    (0..if super::full() { 100 } else { ci }).collect()
}

/// `mean (sd)` of `v`, or `-` when empty.
fn mean_sd(v: &[f64], digits: usize) -> String {
    if v.is_empty() {
        return "-".into();
    }
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    let sd = (v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / n).sqrt();
    format!("{m:.digits$} ({sd:.digits$})")
}

/// Paton's Table I (§VI-A): tests 1-3 on the procedural ledge scenes, each seed planned for
/// Paton's 750 iterations (in CI stopped at the first solution, which decides "found"); every
/// reported path re-validated independently (`RoverProblem::revalidate`) before it counts.
/// The faithful model (`RoverProblem::held_within_boom_reach` off).
fn table_one() -> Result<Vec<Case>, String> {
    use rappel::navigate::{PATON_ITERATIONS, RoverProblem, navigate_seeds};
    use rappel::planners::sampler::Termination;
    let term = if super::full() {
        Termination::iterations(PATON_ITERATIONS)
    } else {
        Termination::iterations(PATON_ITERATIONS).or_cost_at_most(f64::MAX)
    };
    let tests: [(u32, bool, usize, &str); 3] = [
        (1, false, 0, "100/0, 0.29 s (0.05), 1 (0) it"),
        (2, false, 1, "0/0"),
        (3, true, 1, "84/0 of 100, 12.8 s (10.3), 188 (141) it"),
    ];
    let mut cases = Vec::new();
    for (test, pole, anchor, paper) in tests {
        let scene = PatonScene::paper(pole);
        let seeds = table_seeds(test);
        let n = seeds.len();
        // The faithful model only (the held variant is `rappel navigate --held`).
        {
            let problem = RoverProblem::paton(&scene, anchor)?;
            let began = std::time::Instant::now();
            let runs = navigate_seeds(&problem, &seeds, term)?;
            let wall = began.elapsed().as_secs_f64();
            let found: Vec<_> = runs.iter().filter(|r| r.found).collect();
            let unsafe_ = runs.iter().filter(|r| r.unsafe_reason.is_some()).count();
            let times: Vec<f64> = found.iter().filter_map(|r| r.first_solution_s).collect();
            let its: Vec<f64> = found
                .iter()
                .filter_map(|r| r.first_solution_iteration.map(|i| i as f64))
                .collect();
            // The shape of the found paths, from their re-predicted anchor histories.
            let shape_ok = |a: &[[f64; 3]]| match test {
                // One intermediate anchor, on the lip (x = 0, z = 4).
                1 => a.len() == 2 && on_lip(&scene, &a[1]),
                // Wraps the pole: an anchor on the pole's surface above the top.
                3 => {
                    let (c, r) = (
                        scene.pole_center().unwrap_or(Point3::origin()),
                        scene.pole.map_or(0.0, |p| p.radius),
                    );
                    a[1..].iter().any(|p| {
                        (p[0] - c.x).hypot(p[1] - c.y) < r + 2.0 * PREDICT_RESOLUTION
                            && p[2] > scene.height
                    })
                }
                _ => false,
            };
            let shaped = found.iter().filter(|r| shape_ok(&r.anchors)).count();
            let pass = match test {
                1 => found.len() == n && shaped == n && unsafe_ == 0,
                2 => found.is_empty() && unsafe_ == 0,
                _ => found.len() as f64 >= 0.84 * n as f64 && shaped == found.len() && unsafe_ == 0,
            };
            cases.push(Case::new(
                SUITE,
                format!("Table I test {test}: found stable / unstable, first solution"),
                format!(
                    "{}/{} of {n} ({shaped} with the expected anchors), {:.1} s wall; {} s, {} it",
                    found.len(),
                    unsafe_,
                    wall,
                    mean_sd(&times, 2),
                    mean_sd(&its, 0)
                ),
                format!("paper {paper}"),
                pass,
            ));
        }
    }
    Ok(cases)
}
