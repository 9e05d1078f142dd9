//! `rappel online` on a truth equal to its prior follows `rappel plan`'s pair (issue 29 §5): on
//! every bundled online fixture the session's initial class, descent and ascent are the pair
//! `rappel::plan` chooses (Alg. 6) with the same class budget, and a run over a truth equal to
//! the prior travels exactly that descent.

use nalgebra::Point2;
use rappel::mechanics::friction_cone::TetherFrictionCone;
use rappel::plan::PlanOptions;
use rappel::planners::feasibility::distance_to_segment;
use rappel::planners::online::{
    DEFAULT_ONLINE_CLASSES, OnlineOptions, OnlineSession, SimulationOptions,
};
use rappel::planners::terrain::PlaneSeries;
use rappel::scenario::Scenario;

fn fixtures() -> Vec<std::path::PathBuf> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures");
    let mut out: Vec<_> = std::fs::read_dir(&root)
        .unwrap()
        .chain(std::fs::read_dir(root.join("online")).unwrap())
        .map(|e| e.unwrap().path())
        .filter(|p| {
            let name = p.file_name().unwrap().to_string_lossy().to_string();
            name.ends_with(".ron")
                && (p.parent().unwrap().ends_with("online") || name.starts_with("online"))
        })
        .collect();
    out.sort();
    out
}

/// `travelled` runs along `descent`: the descent's corners in order, every other point on the
/// descent segment between them.
fn runs_along(travelled: &[Point2<f64>], descent: &[Point2<f64>]) -> bool {
    let mut k = 0;
    for q in travelled {
        while k + 1 < descent.len() && *q != descent[k] {
            if distance_to_segment(q, &descent[k], &descent[k + 1]) <= 1e-9 {
                break;
            }
            k += 1;
        }
        if k + 1 >= descent.len() && *q != descent[descent.len() - 1] {
            return false;
        }
    }
    travelled.last() == descent.last() && descent.iter().all(|c| travelled.contains(c))
}

#[test]
fn online_on_its_prior_follows_plans_pair_on_every_fixture() {
    let mut compared = 0;
    for path in fixtures() {
        let what = path.display().to_string();
        let s = Scenario::load(&path).unwrap_or_else(|e| panic!("{what}: {e}"));
        let plan = rappel::plan(
            &s,
            &PlanOptions {
                classes: DEFAULT_ONLINE_CLASSES,
                ..PlanOptions::default()
            },
        )
        .unwrap_or_else(|e| panic!("{what}: {e}"));
        let terrain = PlaneSeries::new(&s.terrain.planes, &TetherFrictionCone).unwrap();
        let options = OnlineOptions {
            clearance: s.robot.clearance_m,
            tether_length: s.robot.tether_length_m,
            ..OnlineOptions::default()
        };
        let session = OnlineSession::new(&s.map, s.start, s.goal, terrain, options).unwrap();
        let Some(chosen) = &plan.outcome.chosen else {
            assert!(
                session.class().is_none() || session.clearance_shortfall().is_some(),
                "{what}: the session has a pair plan did not find"
            );
            continue;
        };
        let c = session.class().expect("a class");
        assert_eq!(c.descent, chosen.descent, "{what}: another descent");
        assert_eq!(c.ascent, chosen.ascent, "{what}: another ascent");
        assert_eq!(session.route(), &chosen.descent[..], "{what}: route");
        assert_eq!(session.clearance_shortfall(), None, "{what}");
        // Without PTFOs, a run over a truth equal to the prior travels that very descent.
        if s.friction.is_none() {
            let run = rappel::online::run(&s, &s, &SimulationOptions::default(), &mut |_, _| {})
                .unwrap_or_else(|e| panic!("{what}: {e}"));
            assert!(run.report.ending.reached(), "{what}");
            assert!(run.report.timeline.is_empty(), "{what}");
            assert_eq!(run.report.initial_clearance_shortfall, None, "{what}");
            assert!(
                runs_along(&run.report.travelled, &chosen.descent),
                "{what}: travelled {:?}, plan's descent {:?}",
                run.report.travelled,
                chosen.descent
            );
            assert_eq!(run.report.ascent, chosen.ascent, "{what}");
        }
        compared += 1;
    }
    assert!(compared >= 8, "only {compared} fixtures compared");
}
