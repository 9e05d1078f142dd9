//! Regression suite `planner`: the Chapter-2 planner (thesis Alg. 3-6) on the plan fixtures, each
//! measured value beside an independently obtained reference: the first SHP against the brute-force
//! visibility-graph shortest path, SHP lengths and anchors against the closed forms the fixtures
//! were built from, feasibility verdicts against eq. 2.7 evaluated here from the slope and friction
//! (`asin(mu cot eta)`) and the anchors' coordinates, and the papers' stated outcomes (the online
//! paper's worked example has a feasible path, §IV; Garni's best SHP is straight, Fig. 2.31;
//! Golden Queen's wraps two small obstacles and is feasible at mu 0.4 on 45 degrees, Fig. 2.44).

use super::case::{Case, Kind, workspace_root};
use rappel::plan::{PlanOptions, PlanReport};
use rappel::planners::visibility_graph;
use rappel::scenario::Scenario;
use rappel::verdict::{AnchorPassability, AscentVerdict, Blocked, BlockedAnchor};

const SUITE: &str = "planner";
/// Relative tolerance of length comparisons with the oracle and the closed forms.
const LENGTH_TOLERANCE: f64 = 1e-9;
/// Tolerance of angle comparisons, degrees (the references are evaluated here in floating point).
const ANGLE_TOLERANCE: f64 = 1e-9;

/// Runs the suite.
pub fn suite() -> Result<Vec<Case>, String> {
    let mut cases = Vec::new();
    garni(&mut cases)?;
    golden_queen(&mut cases)?;
    shortest_infeasible(&mut cases)?;
    none_feasible(&mut cases)?;
    multi_plane(&mut cases)?;
    for (file, feasible) in [
        ("fixtures/thesis-fig-2-7.ron", None),
        ("fixtures/online-example.ron", Some(true)),
        ("fixtures/online-example-discovered.ron", Some(true)),
    ] {
        paper_case(file, feasible, &mut cases)?;
    }
    Ok(cases)
}

/// The friction cone of eq. 2.7, degrees, evaluated independently of the mechanics crate.
fn cone_deg(slope_deg: f64, mu: f64) -> f64 {
    (mu / slope_deg.to_radians().tan()).asin().to_degrees()
}

/// The angle of the segment `a -> b` from the fall line, degrees.
fn psi_deg(a: (f64, f64), b: (f64, f64)) -> f64 {
    (b.0 - a.0).abs().atan2(a.1 - b.1).to_degrees()
}

fn dist(a: (f64, f64), b: (f64, f64)) -> f64 {
    (b.0 - a.0).hypot(b.1 - a.1)
}

fn load(file: &str) -> Result<Scenario, String> {
    Scenario::load(workspace_root().join(file)).map_err(|e| e.to_string())
}

fn run(s: &Scenario, options: &PlanOptions) -> Result<PlanReport, String> {
    rappel::plan(s, options).map_err(|e| e.to_string())
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= LENGTH_TOLERANCE * b.abs().max(1.0)
}

fn length_case(
    cases: &mut Vec<Case>,
    kind: Kind,
    name: String,
    measured: f64,
    reference: f64,
    what: &str,
) {
    cases.push(Case::new(
        SUITE,
        kind,
        name,
        format!("{measured:.9} m"),
        format!("{reference:.9} m ({what})"),
        close(measured, reference),
    ));
}

/// The first class's length against the visibility-graph oracle.
fn oracle_case(
    file: &str,
    s: &Scenario,
    r: &PlanReport,
    cases: &mut Vec<Case>,
) -> Result<(), String> {
    let oracle = visibility_graph::shortest_path(&s.map, s.start, s.goal)
        .ok_or_else(|| format!("{file}: the oracle finds no path"))?;
    let first = r
        .classes
        .first()
        .ok_or_else(|| format!("{file}: no class"))?;
    length_case(
        cases,
        Kind::Oracle,
        format!("{file}: first SHP length"),
        first.length_m,
        oracle.length,
        "visibility graph + Dijkstra",
    );
    let ordered = r.classes.windows(2).all(|w| w[0].length_m <= w[1].length_m);
    cases.push(Case::property(
        SUITE,
        format!("{file}: {} classes non-decreasing", r.classes.len()),
        if ordered {
            "non-decreasing"
        } else {
            "out of order"
        },
        "non-decreasing (Alg. 3)",
        ordered,
    ));
    Ok(())
}

fn verdict_case(
    cases: &mut Vec<Case>,
    kind: Kind,
    name: String,
    measured: &str,
    reference: String,
    pass: bool,
) {
    cases.push(Case::new(SUITE, kind, name, measured, reference, pass));
}

fn anchor_points(r: &PlanReport, class: usize) -> Vec<(f64, f64)> {
    r.classes[class]
        .anchors
        .iter()
        .map(|a| (a.point.x, a.point.y))
        .collect()
}

fn garni(cases: &mut Vec<Case>) -> Result<(), String> {
    let file = "fixtures/plan/garni-straight.ron";
    let s = load(file)?;
    let r = run(&s, &PlanOptions::default())?;
    oracle_case(file, &s, &r, cases)?;
    let straight = (s.goal - s.start).norm();
    length_case(
        cases,
        Kind::ClosedForm,
        format!("{file}: SHP length"),
        r.classes[0].length_m,
        straight,
        "straight line, Fig. 2.31",
    );
    cases.push(Case::closed_form(
        SUITE,
        format!("{file}: anchors of the best SHP"),
        r.classes[0].anchors.len().to_string(),
        "0 (straight line)",
        r.classes[0].anchors.is_empty(),
    ));
    let psi = psi_deg((s.start.x, s.start.y), (s.goal.x, s.goal.y));
    let cone = cone_deg(45.0, 0.4);
    verdict_case(
        cases,
        Kind::PaperVerdict,
        format!("{file}: class 1 ascent"),
        feasibility_word(r.classes[0].feasible),
        format!("feasible (psi {psi:.2}° < {cone:.2}°, Fig. 2.36)"),
        r.classes[0].feasible && psi < cone,
    );
    // Fig. 2.37: the same map and path with mu 0.3 ("even with a smaller friction coefficient,
    // this path is feasible too"): the cone narrows to asin(0.3 cot 45°).
    let mut low = s.clone();
    for p in &mut low.terrain.planes {
        p.friction = 0.3;
    }
    let r = run(&low, &PlanOptions::default())?;
    let cone = cone_deg(45.0, 0.3);
    verdict_case(
        cases,
        Kind::PaperVerdict,
        format!("{file} at mu 0.3: class 1 ascent"),
        feasibility_word(r.classes[0].feasible),
        format!("feasible (psi {psi:.2}° < {cone:.2}°, Fig. 2.37)"),
        r.classes[0].feasible && psi < cone,
    );
    Ok(())
}

fn golden_queen(cases: &mut Vec<Case>) -> Result<(), String> {
    let file = "fixtures/plan/golden-queen-two-anchors.ron";
    let s = load(file)?;
    let r = run(&s, &PlanOptions::default())?;
    oracle_case(file, &s, &r, cases)?;
    let (st, a1, a2, g) = ((50.0, 200.0), (52.0, 130.0), (48.0, 60.0), (50.0, 0.0));
    length_case(
        cases,
        Kind::ClosedForm,
        format!("{file}: SHP length"),
        r.classes[0].length_m,
        dist(st, a1) + dist(a1, a2) + dist(a2, g),
        "closed form via (52, 130), (48, 60)",
    );
    let anchors = anchor_points(&r, 0);
    cases.push(Case::closed_form(
        SUITE,
        format!("{file}: anchors of the best SHP"),
        format!("{anchors:?}"),
        "[(52.0, 130.0), (48.0, 60.0)] (2 anchors, Fig. 2.44)",
        anchors == vec![a1, a2],
    ));
    let cone = cone_deg(45.0, 0.4);
    let worst = [psi_deg(st, a1), psi_deg(a1, a2), psi_deg(a2, g)]
        .into_iter()
        .fold(0.0, f64::max);
    verdict_case(
        cases,
        Kind::PaperVerdict,
        format!("{file}: class 1 ascent"),
        feasibility_word(r.classes[0].feasible),
        format!("feasible (largest psi {worst:.2}° < {cone:.2}°, Fig. 2.44)"),
        r.classes[0].feasible && worst < cone,
    );
    pair_case(file, &r, 1, s.robot.clearance_m, cases);
    Ok(())
}

/// The chosen pair: its class, and its clearance against the scenario's.
fn pair_case(file: &str, r: &PlanReport, rank: usize, clearance: f64, cases: &mut Vec<Case>) {
    let chosen = r.outcome.chosen.as_ref().map(|p| p.rank);
    cases.push(Case::property(
        SUITE,
        format!("{file}: chosen class"),
        chosen.map_or("none".into(), |k| k.to_string()),
        format!("{rank} (shortest feasible)"),
        chosen == Some(rank),
    ));
    let d = r
        .outcome
        .chosen
        .as_ref()
        .and_then(|p| p.min_anchor_distance_m)
        .unwrap_or(0.0);
    cases.push(Case::property(
        SUITE,
        format!("{file}: pair clearance from anchors"),
        format!("{d:.6} m"),
        format!(">= {clearance} m (robot.clearance_m)"),
        d >= clearance * (1.0 - 1e-9),
    ));
}

fn shortest_infeasible(cases: &mut Vec<Case>) -> Result<(), String> {
    let file = "fixtures/plan/shortest-infeasible.ron";
    let s = load(file)?;
    let r = run(&s, &PlanOptions::default())?;
    oracle_case(file, &s, &r, cases)?;
    let (st, g) = ((50.0, 100.0), (50.0, 0.0));
    let (w1, w2, e1) = ((40.0, 85.0), (45.0, 40.0), (65.0, 40.0));
    length_case(
        cases,
        Kind::ClosedForm,
        format!("{file}: class 1 length"),
        r.classes[0].length_m,
        dist(st, w1) + dist(w1, w2) + dist(w2, g),
        "west of the triangle",
    );
    length_case(
        cases,
        Kind::ClosedForm,
        format!("{file}: class 2 length"),
        r.classes[1].length_m,
        dist(st, e1) + dist(e1, g),
        "east of the triangle",
    );
    let cone = cone_deg(45.0, 0.4);
    let psi = psi_deg(st, w1);
    let a = &r.classes[0].anchors[0];
    verdict_case(
        cases,
        Kind::ClosedForm,
        format!("{file}: class 1 first impassable anchor"),
        &format!(
            "anchor {} psi {:.9}°: {}",
            a.index, a.psi_deg, r.classes[0].verdict
        ),
        format!("anchor 1, psi {psi:.9}° >= {cone:.2}°: no visibility edge"),
        !r.classes[0].feasible
            && matches!(
                a.passability,
                AnchorPassability::Impassable {
                    reason: Blocked::NoVisibilityEdge { .. }
                }
            )
            && (a.psi_deg - psi).abs() < ANGLE_TOLERANCE,
    );
    let worst = psi_deg(st, e1).max(psi_deg(e1, g));
    verdict_case(
        cases,
        Kind::ClosedForm,
        format!("{file}: class 2 ascent"),
        feasibility_word(r.classes[1].feasible),
        format!("feasible (largest psi {worst:.2}° < {cone:.2}°)"),
        r.classes[1].feasible && worst < cone,
    );
    pair_case(file, &r, 2, s.robot.clearance_m, cases);
    Ok(())
}

fn none_feasible(cases: &mut Vec<Case>) -> Result<(), String> {
    let file = "fixtures/plan/none-feasible.ron";
    let s = load(file)?;
    let options = PlanOptions {
        simple_only: true,
        ..PlanOptions::default()
    };
    let r = run(&s, &options)?;
    oracle_case(file, &s, &r, cases)?;
    cases.push(Case::closed_form(
        SUITE,
        format!("{file}: simple classes"),
        format!("{} ({:?})", r.classes.len(), r.outcome.termination),
        "2 (west and east of the bar; search exhausted)",
        r.classes.len() == 2
            && r.outcome.termination == rappel::planners::spt::Termination::Exhausted,
    ));
    let cone = cone_deg(60.0, 0.3);
    let (st, g) = ((50.0, 100.0), (25.0, 5.0));
    let west = psi_deg(st, (25.0, 55.0));
    let east_goal = psi_deg((75.0, 45.0), g);
    let c1 = &r.classes[0];
    verdict_case(
        cases,
        Kind::ClosedForm,
        format!("{file}: class 1 (west) verdict"),
        &c1.verdict.to_string(),
        format!("anchor 1 has no visibility edge: psi {west:.2}° >= {cone:.2}°"),
        !c1.feasible
            && matches!(
                c1.verdict,
                AscentVerdict::Blocked {
                    anchor: Some(BlockedAnchor { index: 1, .. }),
                    ..
                }
            )
            && (c1.anchors[0].psi_deg - west).abs() < ANGLE_TOLERANCE,
    );
    let c2 = r.classes.get(1).ok_or("none-feasible: no second class")?;
    verdict_case(
        cases,
        Kind::ClosedForm,
        format!("{file}: class 2 (east) verdict"),
        &c2.verdict.to_string(),
        format!("cannot hold at the goal: psi {east_goal:.2}° >= {cone:.2}°"),
        !c2.feasible && (c2.goal_psi_deg - east_goal).abs() < ANGLE_TOLERANCE,
    );
    cases.push(Case::closed_form(
        SUITE,
        format!("{file}: chosen pair"),
        r.outcome
            .chosen
            .as_ref()
            .map_or("none".into(), |p| format!("class {}", p.rank)),
        "none: no class is feasible",
        r.outcome.chosen.is_none() && r.outcome.verdict.starts_with("no feasible class"),
    ));
    Ok(())
}

fn multi_plane(cases: &mut Vec<Case>) -> Result<(), String> {
    let file = "fixtures/plan/multi-plane.ron";
    let s = load(file)?;
    let r = run(&s, &PlanOptions::default())?;
    oracle_case(file, &s, &r, cases)?;
    let (upper, lower) = (cone_deg(30.0, 0.4), cone_deg(50.0, 0.4));
    let (st, a1, a2) = ((50.0, 115.0), (35.0, 90.0), (45.0, 40.0));
    let c1 = &r.classes[0];
    let anchors = anchor_points(&r, 0);
    cases.push(Case::closed_form(
        SUITE,
        format!("{file}: anchors of the best SHP"),
        format!("{anchors:?}"),
        "[(35.0, 90.0), (45.0, 40.0)]",
        anchors == vec![a1, a2],
    ));
    for (k, (a, cone, plane, psi)) in [
        (&c1.anchors[0], upper, 0, psi_deg(st, a1)),
        (&c1.anchors[1], lower, 1, psi_deg(a1, a2)),
    ]
    .into_iter()
    .enumerate()
    {
        let theta = a.theta_max_deg.unwrap_or(f64::NAN);
        verdict_case(
            cases,
            Kind::ClosedForm,
            format!("{file}: anchor {} (plane {plane})", k + 1),
            &format!(
                "plane {:?}, theta_max {theta:.9}°, psi {:.4}°, {}",
                a.plane, a.psi_deg, a.passability
            ),
            format!("theta_max asin(0.4 cot eta) = {cone:.9}°, psi {psi:.4}°: passable"),
            a.plane == Some(plane)
                && (theta - cone).abs() < ANGLE_TOLERANCE
                && a.passability == AnchorPassability::Passable,
        );
    }
    // Measured from the report: anchor 1's psi and the lower plane's cone as the planner computed
    // them, against the closed forms; the anchor passes because it lies on the upper plane.
    let psi1 = psi_deg(st, a1);
    let measured_psi = c1.anchors[0].psi_deg;
    let measured_lower = r
        .setting
        .planes
        .get(1)
        .and_then(|p| p.max_tether_angle_deg)
        .unwrap_or(f64::NAN);
    cases.push(Case::closed_form(
        SUITE,
        format!("{file}: anchor 1 against the lower plane's cone"),
        format!(
            "psi {measured_psi:.4}° vs lower cone {measured_lower:.4}°, plane {:?}, {}",
            c1.anchors[0].plane, c1.anchors[0].passability
        ),
        format!(
            "psi {psi1:.4}° > asin(0.4 cot 50°) = {lower:.4}°: passable only on the upper plane"
        ),
        (measured_psi - psi1).abs() < ANGLE_TOLERANCE
            && (measured_lower - lower).abs() < ANGLE_TOLERANCE
            && measured_psi > measured_lower
            && measured_psi < upper
            && c1.anchors[0].plane == Some(0)
            && c1.anchors[0].passability == AnchorPassability::Passable,
    ));
    pair_case(file, &r, 1, s.robot.clearance_m, cases);
    Ok(())
}

fn paper_case(file: &str, feasible: Option<bool>, cases: &mut Vec<Case>) -> Result<(), String> {
    let s = load(file)?;
    let r = run(&s, &PlanOptions::default())?;
    oracle_case(file, &s, &r, cases)?;
    let distinct = r.classes.iter().enumerate().all(|(i, c)| {
        r.classes[..i]
            .iter()
            .all(|d| d.h_signature != c.h_signature || d.points != c.points)
    });
    cases.push(Case::property(
        SUITE,
        format!("{file}: classes distinct"),
        if distinct { "distinct" } else { "repeated" },
        "distinct homotopy classes",
        distinct,
    ));
    if let Some(expected) = feasible {
        let found = r.outcome.chosen.is_some();
        cases.push(Case::paper_verdict(
            SUITE,
            format!("{file}: a feasible ascent/descent pair"),
            r.outcome.verdict.clone(),
            "a feasible path exists (online paper §IV)",
            found == expected,
        ));
    }
    Ok(())
}

/// The word a verdict row prints for a feasibility result.
fn feasibility_word(feasible: bool) -> &'static str {
    if feasible { "feasible" } else { "infeasible" }
}
