//! The planner judges each scenario's own robot through the traversability trait: a rigid
//! four-wheel rover's QP-derived cone equals the point robot's closed-form cone (eq. 2.7), and
//! Axel (whose wheels also resist moments) gets a cone at least as wide, on the same fixture.

use rappel::plan::{PlanOptions, plan};
use rappel::scenario::{RobotModel, Scenario};

fn cone_deg(model: RobotModel) -> (f64, bool) {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../fixtures/plan/golden-queen-two-anchors.ron"
    );
    let mut s = Scenario::load(path).expect("fixture loads");
    s.robot.model = model;
    let r = plan(&s, &PlanOptions::default()).expect("plans");
    let cone = r.setting.planes[0]
        .max_tether_angle_deg
        .expect("45 degrees at mu 0.4 needs the tether");
    (cone, r.outcome.chosen.is_some())
}

#[test]
fn wheeled_models_plan_with_their_own_cones() {
    let (point, point_ok) = cone_deg(RobotModel::Point);
    let (four, four_ok) = cone_deg(RobotModel::FourWheel);
    let (axel, axel_ok) = cone_deg(RobotModel::Axel);
    let closed_form = (0.4f64 / 45f64.to_radians().tan()).asin().to_degrees();
    assert!(
        (point - closed_form).abs() < 1e-9,
        "{point} vs {closed_form}"
    );
    assert!((four - closed_form).abs() < 0.02, "{four} vs {closed_form}");
    assert!(axel >= four - 0.02, "{axel} < {four}");
    assert!(point_ok && four_ok && axel_ok);
}
