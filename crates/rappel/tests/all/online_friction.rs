//! The online form of frictional planning (issue 12): PTFOs in an online session. Independent
//! references: the offline frictional planner (Alg. 7 with Alg. 8, 9 and 14, built from scratch)
//! on the same scenario and friction, and re-deciding the final SHP's anchors.

use rappel::geometry::btm::Btm;
use rappel::mechanics::friction::FrictionInterval;
use rappel::mechanics::friction_cone::TetherFrictionCone;
use rappel::mechanics::ptfo::PtfoClass;
use rappel::planners::frictional::FrictionModel;
use rappel::planners::frictional::anchor_check::{AnchorVerdict, decide_anchor_with};
use rappel::planners::frictional::search::{FrictionalQuery, plan_frictional};
use rappel::planners::online::simulate::Difference;
use rappel::planners::online::{OnlineOptions, OnlineSession, SimulationOptions};
use rappel::planners::spt::SearchOptions;
use rappel::planners::terrain::PlaneSeries;
use rappel::ptfo_spec::FrictionRange;
use rappel::scenario::Scenario;

fn fixture(name: &str) -> Scenario {
    Scenario::load(format!(
        "{}/../../fixtures/friction/{name}",
        env!("CARGO_MANIFEST_DIR")
    ))
    .expect("fixture")
}

fn model(s: &Scenario) -> FrictionModel {
    s.friction
        .as_ref()
        .expect("a friction section")
        .resolve(s.robot.mass_kg, &s.terrain.planes, s.map.obstacles.len())
        .expect("resolves")
        .model
}

fn terrain(s: &Scenario) -> PlaneSeries {
    PlaneSeries::new(&s.terrain.planes, &TetherFrictionCone).expect("planes")
}

/// Alg. 7 from scratch: the first feasible class's SHP after its slips (length, anchor points).
fn offline(s: &Scenario, m: &FrictionModel) -> (f64, Vec<(f64, f64)>) {
    let btm = Btm::from_map(&s.map).expect("btm");
    let options = SearchOptions::default();
    let t = terrain(s);
    let query = FrictionalQuery {
        terrain: &t,
        clearance: s.robot.clearance_m,
        start: s.start,
        goal: s.goal,
        options: &options,
        holding_limit: None,
        tether_length: None,
    };
    let plan = plan_frictional(&btm, &s.map, m, &query).expect("Alg. 7");
    let chosen = &plan.classes[plan.chosen.expect("a feasible class")];
    let taut = &chosen.check.taut;
    (
        taut.length,
        taut.anchors
            .iter()
            .map(|a| (a.point.x, a.point.y))
            .collect(),
    )
}

fn session(s: &Scenario) -> OnlineSession {
    let options = OnlineOptions {
        clearance: s.robot.clearance_m,
        ..OnlineOptions::default()
    };
    OnlineSession::new(&s.map, s.start, s.goal, terrain(s), options).expect("session")
}

fn online_shp(session: &OnlineSession) -> (f64, Vec<(f64, f64)>) {
    let taut = &session.class().expect("a class").shp.taut;
    (
        taut.length,
        taut.anchors
            .iter()
            .map(|a| (a.point.x, a.point.y))
            .collect(),
    )
}

fn assert_same(a: &(f64, Vec<(f64, f64)>), b: &(f64, Vec<(f64, f64)>)) {
    assert!((a.0 - b.0).abs() <= 1e-9 * b.0.max(1.0), "{a:?} vs {b:?}");
    assert_eq!(a.1, b.1);
}

/// No anchor of the session's SHP slides or is volatile (decided again, independently of the
/// settling loop).
fn all_anchors_hold(session: &OnlineSession) {
    let m = session.friction_model().expect("PTFOs");
    let taut = &session.class().expect("a class").shp.taut;
    for a in &taut.anchors {
        let d = decide_anchor_with(m, |id| session.initial_obstacle(id), taut, a).expect("decides");
        assert!(
            !matches!(
                d.verdict,
                AnchorVerdict::Friction(PtfoClass::Slides | PtfoClass::Volatile)
            ),
            "{d:?}"
        );
    }
}

#[test]
fn the_session_clips_a_slipping_ptfo_as_alg_7_does() {
    let s = fixture("slip_then_wrap.ron");
    let m = model(&s);
    let mut session = session(&s);
    let before = online_shp(&session);
    let outcomes = session.set_friction(m.clone()).expect("settles");
    assert!(!outcomes.is_empty(), "the fixture's PTFO vertex slips");
    assert!(
        outcomes.iter().all(|o| o.reason.contains("slips")),
        "{outcomes:?}"
    );
    let after = online_shp(&session);
    assert!(after.0 < before.0);
    assert_same(&after, &offline(&s, &m));
}

#[test]
fn a_ptfo_reclassified_during_the_descent_slips_and_the_plan_follows() {
    let s = fixture("capstan_holds.ron");
    let m = model(&s);
    let mut session = session(&s);
    assert!(
        session.set_friction(m.clone()).expect("settles").is_empty(),
        "it holds"
    );
    assert_same(&online_shp(&session), &offline(&s, &m));
    session.advance(2.0);
    // A new estimate: the pillar is nearly frictionless.
    let low = FrictionInterval::new(0.01, 0.01).expect("interval");
    let outcomes = session.reclassify_ptfo(0, low).expect("reclassified");
    assert!(!outcomes.is_empty());
    assert!(
        outcomes.iter().all(|o| o.reason.contains("slips")),
        "{outcomes:?}"
    );
    // The same scenario with that friction, planned offline from scratch.
    let mut lowered = s.clone();
    lowered.friction.as_mut().expect("friction").ptfos[0].friction =
        FrictionRange { lo: 0.01, hi: 0.01 };
    let reference = offline(&lowered, &model(&lowered));
    assert_same(&online_shp(&session), &reference);
    all_anchors_hold(&session);
    // Reclassifying what is not a PTFO is a typed error.
    assert!(session.reclassify_ptfo(7, low).is_err());
}

#[test]
fn a_simulated_descent_senses_a_weaker_ptfo_and_reaches_the_goal() {
    let prior = fixture("capstan_holds.ron");
    let mut truth = prior.clone();
    truth.friction.as_mut().expect("friction").ptfos[0].friction =
        FrictionRange { lo: 0.01, hi: 0.01 };
    let run = rappel::online::run(
        &prior,
        &truth,
        &SimulationOptions::default(),
        &mut |_, _| {},
    )
    .expect("runs");
    assert!(run.report.ending.reached(), "{:?}", run.report.ending);
    assert!(run.report.homotopic);
    assert!(
        run.report
            .timeline
            .iter()
            .any(|e| e.difference == Difference::Friction { prior: 0 }),
        "{:?}",
        run.report.timeline
    );
    // Only one side with PTFOs is refused, naming it.
    let mut bare = prior.clone();
    bare.friction = None;
    let err = rappel::online::run(&prior, &bare, &SimulationOptions::default(), &mut |_, _| {})
        .expect_err("refused");
    assert!(err.to_string().contains("only the prior scenario"), "{err}");
}

/// Alg. 10 (offline): a solid friction anchor is its own waypoint, reached along the tether, and
/// Alg. 5's clearance does not apply to it.
#[test]
fn a_solid_friction_anchor_is_passed_at_the_anchor_itself() {
    use rappel::planners::feasibility::Passability;
    let s = fixture("capstan_holds.ron");
    let m = model(&s);
    let btm = Btm::from_map(&s.map).expect("btm");
    let options = SearchOptions::default();
    let t = terrain(&s);
    // A clearance far larger than the pillar: no geometric waypoint could keep it.
    let query = FrictionalQuery {
        terrain: &t,
        clearance: 50.0,
        start: s.start,
        goal: s.goal,
        options: &options,
        holding_limit: None,
        tether_length: None,
    };
    let plan = plan_frictional(&btm, &s.map, &m, &query).expect("Alg. 7");
    let chosen = &plan.classes[plan.chosen.expect("feasible with a solid friction anchor")];
    let f = chosen.feasibility.as_ref().expect("checked");
    for (k, d) in chosen.check.anchors.iter().enumerate() {
        if d.verdict == AnchorVerdict::Friction(PtfoClass::Solid) {
            match f.base.anchors[k].passability {
                Passability::Passable { waypoint, via } => {
                    assert_eq!(waypoint, d.anchor.point);
                    assert!(via.is_none());
                }
                ref other => panic!("solid anchor {k}: {other:?}"),
            }
        }
    }
    assert!(
        chosen
            .check
            .anchors
            .iter()
            .any(|d| d.verdict == AnchorVerdict::Friction(PtfoClass::Solid))
    );
}
