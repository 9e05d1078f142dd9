//! The plan report's typed reasons (`rappel::verdict`) say what the planner said: on every
//! class of the plan fixtures and of a crater strip, the verdict's and each anchor's `Display`
//! is the planner's own sentence (`FeasibilityReport::describe`, `Impassability::describe`), the
//! pair failure is the planner's, and the JSON carries the kind and its data.

use rappel::plan::{PlanOptions, plan_detailed};
use rappel::planners::feasibility::Passability;
use rappel::scenario::Scenario;
use rappel::verdict::{AnchorPassability, AscentVerdict};

fn check(s: &Scenario) -> (usize, usize) {
    let options = PlanOptions {
        classes: 8,
        ..Default::default()
    };
    let plan = plan_detailed(&s.validate().expect("valid"), &options).expect("plan");
    let (mut blocked, mut anchors) = (0, 0);
    assert_eq!(plan.report.classes.len(), plan.outcome.classes.len());
    for (r, c) in plan.report.classes.iter().zip(&plan.outcome.classes) {
        let f = &c.feasibility;
        assert_eq!(
            r.verdict.to_string(),
            f.describe(),
            "{}: class {}",
            s.name,
            r.rank
        );
        assert_eq!(r.verdict.is_feasible(), f.feasible());
        blocked += usize::from(matches!(r.verdict, AscentVerdict::Blocked { .. }));
        assert_eq!(r.pair_failure, c.pair_failure);
        for (a, x) in r.anchors.iter().zip(&f.anchors) {
            let said = match x.passability {
                Passability::Passable { .. } => "passable".to_string(),
                Passability::Impassable(why) => format!("impassable: {}", why.describe()),
                Passability::NotReached => "not reached".to_string(),
            };
            assert_eq!(a.passability.to_string(), said);
            anchors += usize::from(!matches!(a.passability, AnchorPassability::Passable));
        }
        let json: serde_json::Value = serde_json::to_value(r).expect("json");
        let kind = if r.verdict.is_feasible() {
            "feasible"
        } else {
            "blocked"
        };
        assert_eq!(json["verdict"]["kind"], kind);
    }
    (blocked, anchors)
}

#[test]
fn typed_reasons_say_what_the_planner_said() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/plan");
    let (mut blocked, mut anchors) = (0, 0);
    for name in [
        "none-feasible",
        "shortest-infeasible",
        "multi-plane",
        "golden-queen-two-anchors",
    ] {
        let s = Scenario::load(dir.join(format!("{name}.ron"))).expect("fixture");
        let (b, a) = check(&s);
        blocked += b;
        anchors += a;
    }
    let strip = rappel::generated::crater_strip_scenario(300, 2, 200.0).expect("strip");
    let (b, a) = check(&strip);
    // The fixtures are chosen for their blocked classes: the check saw some.
    assert!(
        blocked + b > 3 && anchors + a > 3,
        "{blocked}+{b} blocked, {anchors}+{a}"
    );
}
