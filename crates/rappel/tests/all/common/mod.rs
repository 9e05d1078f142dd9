//! Set-up shared by the facade's Alg. 5 / Alg. 6 integration tests: a scenario's BTM and planes,
//! the feasibility context over them, and the first classes of its SPT search.

use rappel::geometry::btm::Btm;
use rappel::mechanics::friction_cone::TetherFrictionCone;
use rappel::planners::feasibility::FeasibilityContext;
use rappel::planners::spt::{RankedShp, SearchOptions, SptPlanner};
use rappel::planners::terrain::PlaneSeries;
use rappel::scenario::Scenario;

/// What Alg. 5 and Alg. 6 read of one scenario, with its first classes.
pub struct Prepared {
    pub btm: Btm,
    pub terrain: PlaneSeries,
    pub clearance: f64,
    pub tether_length: Option<f64>,
    /// The first `k` classes of the search from the scenario's start to its goal.
    pub classes: Vec<RankedShp>,
}

impl Prepared {
    /// Builds the BTM and planes of `scenario` and runs the search for `k` classes.
    pub fn new(scenario: &Scenario, k: usize) -> Prepared {
        let btm = Btm::from_map(&scenario.map).expect("btm");
        let terrain =
            PlaneSeries::new(&scenario.terrain.planes, &TetherFrictionCone).expect("planes");
        let options = SearchOptions::default()
            .with_max_classes(Some(k))
            .expect("options");
        let classes = SptPlanner::new(&btm)
            .search(scenario.start, scenario.goal, &options)
            .expect("search")
            .run()
            .expect("classes")
            .classes;
        Prepared {
            btm,
            terrain,
            clearance: scenario.robot.clearance_m,
            tether_length: scenario.robot.tether_length_m,
            classes,
        }
    }

    /// The feasibility context over this scenario's BTM and planes.
    pub fn ctx(&self) -> FeasibilityContext<'_> {
        FeasibilityContext {
            btm: &self.btm,
            terrain: &self.terrain,
            clearance: self.clearance,
            tether_length: self.tether_length,
        }
    }
}
