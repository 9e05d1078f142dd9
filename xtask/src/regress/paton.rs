//! Regression cases of mesh traversability (issue 14, Paton §IV-V): Axel settled on Paton's ledge
//! scene (`fixtures/paton/ledge.ron`) against closed forms, and Fig. 8's shading: the test-1
//! anchor (4.9 m behind, 2.0 m above the start) makes the slope in front of the rover stable, the
//! test-2 anchor (8.2 m in front, 2.0 m above) makes the whole 55° slope unstable. Each pose is
//! reached by a drive from the start with its anchor history predicted (Paton Alg. 1), and the
//! QP uses the last predicted anchor; a pose counts as stable when the QP finds an equilibrium
//! with the boom inline or in contact. Test 3: the tether swept around the pole against the
//! closed-form wrap of a cylinder.

use super::case::{Case, Kind, workspace_root};
use rappel::nalgebra::{Point3, Vector3};
use rappel::planners::anchor_prediction::{AnchorHistory, PredictParams, predict_path};
use rappel::planners::rover::stability_map::{
    MapSpec, PREDICT_RESOLUTION, PoseStability, drive_and_check, stability_map,
};
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
    cases.push(Case::closed_form(
        SUITE,
        "settle on the ledge top: height, pitch",
        format!("{:.4} m, {:.3}°", top.origin[2], top.pitch_deg),
        "4.0000 m, 0.000° (the top plane)",
        (top.origin[2] - 4.0).abs() < 1e-3 && top.pitch_deg.abs() < 1e-3f64.to_degrees(),
    ));
    let x = 0.5 * scene.slope_foot_x();
    let want = 4.0 - x * scene.slope_deg.to_radians().tan();
    let (_, mid) = settle_report(&ground, x, 0.0, 0.0, None).map_err(|e| e.to_string())?;
    cases.push(Case::closed_form(
        SUITE,
        "settle mid-slope facing down: height, pitch",
        format!("{:.4} m, {:.3}°", mid.origin[2], mid.pitch_deg),
        format!("{want:.4} m, -55.000° (4 - x tan 55°)"),
        (mid.origin[2] - want).abs() < 1e-3
            && (mid.pitch_deg + scene.slope_deg).abs() < 1e-3f64.to_degrees(),
    ));
    // The same two poses settled through the sparse distance field at 5 cm (`terrain::sparse_sdf`,
    // propagated to its default 1 m): on the top and mid-slope every corner the wheels read lies
    // on one plane within T, so the trilinear field is exact there and the closed forms hold to
    // 1e-3.
    let mut sp = rappel::terrain::sparse_sdf::SparseSdfParams::new(0.05);
    sp.margin = 2.0;
    let field = rappel::terrain::sparse_sdf::SparseSdf::from_mesh(&ground, &sp)
        .map_err(|e| e.to_string())?;
    let z_top = ground.bounds().1.z + 1.0;
    let on_field =
        |x: f64| rappel::planners::rover::stability_map::settle_from(&field, z_top, x, 0.0, 0.0);
    let (ft, fm) = (on_field(-1.0)?, on_field(x)?);
    cases.push(Case::closed_form(
        SUITE,
        "settle through the sparse 5 cm field: top and mid-slope height, pitch",
        format!(
            "{:.4} m, {:.3}°; {:.4} m, {:.3}° ({} blocks)",
            ft.origin.z,
            ft.pitch().to_degrees(),
            fm.origin.z,
            fm.pitch().to_degrees(),
            field.block_count()
        ),
        format!("4.0000 m, 0.000°; {want:.4} m, -55.000° (closed forms, 1e-3)"),
        (ft.origin.z - 4.0).abs() < 1e-3
            && ft.pitch().abs() < 1e-3
            && (fm.origin.z - want).abs() < 1e-3
            && (fm.pitch() + scene.slope_deg.to_radians()).abs() < 1e-3,
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
    cases.push(Case::closed_form(
        SUITE,
        "Fig. 8 test 1: predicted anchor on the lip (x = 0, z = 4) for slope poses",
        format!("{lip1}/{n1} with one anchor on the lip"),
        format!("{n1}/{n1} (the tether from 4.9 m behind bends over the lip)"),
        lip1 == n1,
    ));
    cases.push(Case::paper_verdict(
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
    cases.push(Case::closed_form(
        SUITE,
        "Fig. 8 test 2: no anchor attaches (tether in the air in front)",
        format!("{free2}/{n2} with the root as last anchor"),
        format!("{n2}/{n2}"),
        free2 == n2,
    ));
    cases.push(Case::paper_verdict(
        SUITE,
        "Fig. 8 test 2 anchor (predicted): the whole 55° slope",
        format!("{s2}/{n2} stable"),
        format!("0/{n2} stable (red)"),
        s2 == 0,
    ));
    // The boom swept against the mesh just past the lip (Paton §IV-A, in contact): a straight
    // descent from the test-1 start on the centre line, every 5 cm from the lip to 0.7 m past
    // it. Where the footprint lies wholly on the slope (pitch -55°) and the lip is within the
    // boom's reach, the boom's shaft rests on the lip at the closed-form elevation
    // -atan(r_w / s) below the slope (s the distance along the slope from the lip).
    let axel = rappel::mechanics::axel::AxelParams::default();
    let slope = scene.slope_deg.to_radians();
    let (mut on_slope, mut on_lip_ok, mut stable_past, mut past) = (0, 0, 0, 0);
    let mut unstable_at = Vec::new();
    for k in 0..=14 {
        let x = 0.05 * k as f64;
        let p = drive(&ground, &scene, x, 0.0, &anchors[0])?;
        past += 1;
        if p.stable {
            stable_past += 1;
        } else {
            unstable_at.push(format!("{x:.2}"));
        }
        let pose = rappel::planners::rover::stability_map::settle(&ground, x, 0.0, 0.0)?;
        let s = pose.origin.x / slope.cos();
        if (pose.pitch() + slope).abs() < 1e-6 && s.hypot(axel.wheel_radius) < axel.boom_length {
            on_slope += 1;
            let last = p.anchors.last().copied().unwrap_or_default();
            let a = Point3::new(last[0], last[1], last[2]);
            let (_, c) = rappel::mechanics::boom_contact::place_boom_in_contact(
                &pose,
                &axel,
                &ground,
                rappel::settle::SCENE_FRICTION,
                (&a, None),
            )
            .map_err(|e| e.to_string())?;
            let want = -(axel.wheel_radius / s).atan();
            if c.point.x.abs() < 1e-6
                && (c.point.z - scene.height).abs() < 1e-6
                && (c.elevation - want).abs() < 1e-6
            {
                on_lip_ok += 1;
            }
        }
    }
    cases.push(Case::closed_form(
        SUITE,
        "boom in contact past the lip: shaft on the lip at -atan(r_w / s)",
        format!("{on_lip_ok}/{on_slope} poses on the slope within the boom's reach"),
        format!("{on_slope}/{on_slope} (closed form, 1e-6), at least 3"),
        on_slope >= 3 && on_lip_ok == on_slope,
    ));
    cases.push(Case::paper_verdict(
        SUITE,
        "test-1 straight descent over the lip (x 0 to 0.7 m, 5 cm): stable poses",
        format!(
            "{stable_past}/{past} stable{}",
            if unstable_at.is_empty() {
                String::new()
            } else {
                format!(", unstable at x = {}", unstable_at.join(", "))
            }
        ),
        format!("{past}/{past} (Paton's test-1 paths drive over the lip: Table I 100/100)"),
        stable_past == past,
    ));
    // The map: 0.5 m cells, the slope cells past the lip.
    let spec = MapSpec::fig8(&scene);
    let foot = scene.slope_foot_x();
    let map = |root: &Point3<f64>| -> Result<(usize, usize), String> {
        let h = AnchorHistory::new(*root).map_err(|e| e.to_string())?;
        let m = stability_map(&ground, &h, &spec).map_err(|e| e.to_string())?;
        let cells: Vec<_> = m
            .cells
            .iter()
            .filter(|c| c.ground[0] > 0.0 && c.ground[0] < foot - 0.3)
            .collect();
        let stable = cells
            .iter()
            .filter(|c| c.pose.as_ref().is_some_and(|p| p.stable))
            .count();
        Ok((stable, cells.len()))
    };
    let (m1, k1) = map(&anchors[0])?;
    let (m2, k2) = map(&anchors[1])?;
    cases.push(Case::paper_verdict(
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
    cases.push(Case::closed_form(
        SUITE,
        "test 3 pole: tether swept 230° around the pole, length",
        format!("{got:.3} m, {} anchors", wrap.history.len() - 1),
        format!("{want:.3} m (tangents + arc of a 0.3 m cylinder), within 1%"),
        (got - want).abs() < 0.01 * want && wrap.history.len() > 2,
    ));
    cases.push(mesh_tether_cone()?);
    cases.extend(table_one()?);
    Ok(cases)
}

/// The wheels' friction on a mesh (the scene's `SCENE_FRICTION`, Paton §IV-A/C): the four-wheel
/// rover settled on a 45° plane given as a triangle mesh, facing away from its anchor, the
/// tether parallel to the slope at `psi` from the fall line and unlimited. The wheels must cancel
/// the cross-tether part of gravity, so it holds iff `psi <= asin(mu cot eta)` (eq. 2.7): checked
/// 4° either side of the boundary, which a 30 % change of the friction moves by 11-14°.
fn mesh_tether_cone() -> Result<Case, String> {
    use rappel::planners::rover::ground::{DistanceSource, GroundDistances};
    use rappel::planners::rover::verdict::SCENE_FRICTION;
    use rappel::terrain::mesh::TriMesh;
    let eta = 45f64.to_radians();
    let (w, t) = (60.0, eta.tan());
    let ground = TriMesh::new(
        vec![
            Point3::new(-w, -w, -w * t),
            Point3::new(w, -w, -w * t),
            Point3::new(w, w, w * t),
            Point3::new(-w, w, w * t),
        ],
        vec![[0, 1, 2], [0, 2, 3]],
    )
    .map_err(|e| e.to_string())?;
    let d = GroundDistances::new(&ground, DistanceSource::Exact).map_err(|e| e.to_string())?;
    let boundary = (SCENE_FRICTION / eta.tan()).asin();
    let normal = Vector3::new(0.0, -eta.sin(), eta.cos());
    let verdict = |psi: f64| -> Result<Option<bool>, String> {
        // Up the slope at psi from the fall line, in the plane; the rover faces the other way.
        let along = Vector3::new(psi.sin(), psi.cos() * eta.cos(), psi.cos() * eta.sin());
        let exit = rappel::mechanics::four_wheel::FourWheelParams::default()
            .tether_exit
            .z;
        let anchor = Point3::origin() + along * 40.0 + normal * exit;
        let yaw = (-along.y).atan2(-along.x).to_degrees();
        let (_, r) = rappel::settle::four_wheel_report_with(
            &d,
            0.0,
            0.0,
            yaw,
            Some([anchor.x, anchor.y, anchor.z]),
        )
        .map_err(|e| e.to_string())?;
        Ok(r.stability.first().and_then(|v| v.stable))
    };
    let margin = 4f64.to_radians();
    let (below, above) = (verdict(boundary - margin)?, verdict(boundary + margin)?);
    Ok(Case::closed_form(
        SUITE,
        "four-wheel rover on a 45° mesh plane, tether 4° inside / outside the cone: stable",
        format!("{below:?} / {above:?}"),
        format!(
            "Some(true) / Some(false): asin(mu cot eta) = {:.2}° with the scene's mu {SCENE_FRICTION} (eq. 2.7)",
            boundary.to_degrees()
        ),
        below == Some(true) && above == Some(false),
    ))
}

/// Seeds of Table I's test `test` (`shadow`: our shadow-sampling row): Paton's 100 behind
/// `--full`; in CI 20 for test 1 (tens of milliseconds a seed to the first solution), 10 for
/// test 2 (all 750 iterations, about a second a seed), 10 for test 3 with Paton's uniform
/// sampling (up to 750 iterations) and [`CI_SHADOW_TEST_3_SEEDS`] for test 3 with shadow
/// sampling, so a found fraction is measured rather than one seed's luck, while the rows stay
/// well under a minute on 2 cores.
fn table_seeds(test: u32, shadow: bool) -> Vec<u64> {
    let ci = match (test, shadow) {
        (1, _) => 20,
        (2, _) => 10,
        (_, false) => 10,
        (_, true) => CI_SHADOW_TEST_3_SEEDS,
    };
    (0..if super::case::full() { 100 } else { ci }).collect()
}

/// CI seeds of the shadow-sampling test-3 row. The row passes only if every seed finds the
/// wrap (`>= 0.99 n`), so a planner that finds it on 89 % of seeds (the rate before the core
/// of the shadow was sampled, `docs/sampler.md`) passes 30 independent seeds with probability
/// `0.89^30` = 3 %: CI fails it with probability 97 %. A seed stops at its first solution
/// (about 250 iterations, under a second of CPU), so the row costs about 15-25 s wall on 2 idle
/// cores (rayon across seeds).
const CI_SHADOW_TEST_3_SEEDS: u64 = 30;

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
    use rappel::navigate::{
        PATON_ITERATIONS, RoverProblem, SHADOW_SAMPLE_FRACTION, navigate_seeds,
    };
    use rappel::planners::sampler::Termination;
    let term = if super::case::full() {
        Termination::iterations(PATON_ITERATIONS)
    } else {
        Termination::iterations(PATON_ITERATIONS).or_cost_at_most(f64::MAX)
    };
    // (test, pole, root anchor, shadow sampling, reference). The first three rows are Paton's
    // set-up with his uniform sampling; the last two are ours (shadow sampling,
    // `rappel::planners::rover::shadow`) against the goal, and that no path is reported unsafe.
    let tests: [(u32, bool, usize, bool, &str); 5] = [
        (1, false, 0, false, "paper 100/0, 0.29 s (0.05), 1 (0) it"),
        (2, false, 1, false, "paper 0/0"),
        (
            3,
            true,
            1,
            false,
            "paper 84/0 of 100, 12.8 s (10.3), 188 (141) it",
        ),
        (
            2,
            false,
            1,
            true,
            "0/0 (no path exists: the bias must not make one unsafe)",
        ),
        (
            3,
            true,
            1,
            true,
            "issue goal: >= 99% found (CI: every seed), mean first solution < 1 s, 0 unsafe",
        ),
    ];
    let mut cases = Vec::new();
    for (test, pole, anchor, shadow, reference) in tests {
        let scene = PatonScene::paper(pole);
        let seeds = table_seeds(test, shadow);
        let n = seeds.len();
        // The faithful model only (the held variant is `rappel navigate --held`).
        {
            let mut problem = RoverProblem::paton(&scene, anchor)?;
            if shadow {
                problem.shadow_sample_fraction = SHADOW_SAMPLE_FRACTION;
            }
            let began = std::time::Instant::now();
            let runs = navigate_seeds(
                &problem,
                &seeds,
                term,
                &rappel::planners::stop::StopCondition::none(),
            )?;
            let wall = began.elapsed().as_secs_f64();
            let found: Vec<_> = runs.iter().filter(|r| r.found).collect();
            let unsafe_ = runs.iter().filter(|r| r.unsafe_reason.is_some()).count();
            let times: Vec<f64> = found.iter().filter_map(|r| r.first_solution_s).collect();
            let its: Vec<f64> = found
                .iter()
                .filter_map(|r| r.first_solution_iteration.map(|i| i as f64))
                .collect();
            let checks: Vec<f64> = found
                .iter()
                .filter_map(|r| r.first_solution_motions_checked.map(|i| i as f64))
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
            let mean_time = times.iter().sum::<f64>() / times.len().max(1) as f64;
            let pass = match (test, shadow) {
                (1, _) => found.len() == n && shaped == n && unsafe_ == 0,
                (2, _) => found.is_empty() && unsafe_ == 0,
                (_, false) => {
                    found.len() as f64 >= 0.84 * n as f64 && shaped == found.len() && unsafe_ == 0
                }
                (_, true) => {
                    found.len() as f64 >= 0.99 * n as f64
                        && shaped == found.len()
                        && unsafe_ == 0
                        && !times.is_empty()
                        && mean_time < 1.0
                }
            };
            let name = if shadow {
                format!(
                    "Table I test {test}, shadow sampling (ours): found stable / unstable, first solution"
                )
            } else {
                format!("Table I test {test}: found stable / unstable, first solution")
            };
            let shadow_note = if shadow {
                let k: u64 = runs.iter().map(|r| r.shadow_samples).sum();
                format!(", {k} shadow samples")
            } else {
                String::new()
            };
            // Paton's uniform rows are his Table I numbers; the shadow rows are ours: test 2's
            // against his verdict that no path exists, test 3's against our own goal.
            let kind = match (test, shadow) {
                (_, false) => Kind::PaperNumber,
                (2, true) => Kind::PaperVerdict,
                _ => Kind::Property,
            };
            let row = Case::new(
                SUITE,
                kind,
                name,
                format!(
                    "{}/{} of {n} ({shaped} with the expected anchors), {:.1} s wall; {} s, {} it ({} motions checked){shadow_note}",
                    found.len(),
                    unsafe_,
                    wall,
                    mean_sd(&times, 2),
                    mean_sd(&its, 0),
                    mean_sd(&checks, 0)
                ),
                reference,
                pass,
            );
            // The known difference of test 3 with Paton's sampling: its band (see
            // `TEST_3_UNIFORM_BAND`), every found path wrapping the pole and none unsafe.
            let row = if (test, shadow) == (3, false) {
                let (lo, hi) = TEST_3_UNIFORM_BAND;
                let share = found.len() as f64 / n as f64;
                row.differs_within(
                    format!(
                        "{:.0}-{:.0} % of seeds found, all wrapping the pole, 0 unsafe",
                        100.0 * lo,
                        100.0 * hi
                    ),
                    share >= lo && share <= hi && shaped == found.len() && unsafe_ == 0,
                )
            } else {
                row
            };
            cases.push(row);
        }
    }
    Ok(cases)
}

/// The band of Table I test 3 with Paton's uniform sampling (a known difference): the share of
/// seeds on which the pole wrap is found within 750 iterations. Measured 5 of the 10 CI seeds and
/// 56 of 100 with `--full`, 55 of 100 after the OMPL-faithful ABIT* search, 61 of 100 with the
/// yaw-aware cost estimates, 64 of 100 with OMPL's neighbour count `k` (`docs/sampler.md`; the
/// same 5 of the 10 CI seeds; paper 84 of 100);
/// the band holds them all and fails if the share drops below 30 % or rises above 70 % without
/// reaching the paper's 84 %.
const TEST_3_UNIFORM_BAND: (f64, f64) = (0.30, 0.70);
