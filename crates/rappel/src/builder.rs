//! Scenarios built in code: [`Scenario::builder`] takes typed values (points as `(x, y)` tuples,
//! `[x, y]` arrays or nalgebra points), fills every optional part with the documented default
//! of the scenario file format (`docs/scenario-format.md`), and [`ScenarioBuilder::build`]
//! validates the result exactly as a loaded file is validated, so a built scenario is one every
//! planner accepts.

use nalgebra::Point2;
use rappel_geometry::map::Map;
use rappel_geometry::polygon::Polygon;
use rappel_terrain::plane_series::TerrainPlane;

use crate::ptfo_spec::FrictionSpec;
use crate::scenario::{RobotModel, RobotParams, Scenario, ScenarioError, Terrain};

/// Anything that names a point of the planning frame: `(x, y)`, `[x, y]` or a `Point2<f64>`.
pub trait IntoPoint {
    /// The point.
    fn into_point(self) -> Point2<f64>;
}

impl IntoPoint for (f64, f64) {
    fn into_point(self) -> Point2<f64> {
        Point2::new(self.0, self.1)
    }
}

impl IntoPoint for [f64; 2] {
    fn into_point(self) -> Point2<f64> {
        Point2::new(self[0], self[1])
    }
}

impl IntoPoint for Point2<f64> {
    fn into_point(self) -> Point2<f64> {
        self
    }
}

fn ring<P: IntoPoint>(points: impl IntoIterator<Item = P>) -> Polygon {
    Polygon::new(points.into_iter().map(IntoPoint::into_point).collect())
}

/// A scenario under construction ([`Scenario::builder`]). The boundary, the start and the goal
/// are required; everything else has the scenario format's default (no obstacles, no terrain
/// planes, the point robot with a 0.5 m clearance and an unlimited tether, no friction section).
///
/// ```
/// use rappel::prelude::*;
/// let s = Scenario::builder()
///     .name("one rock")
///     .boundary([(0.0, 0.0), (10.0, 0.0), (10.0, 20.0), (0.0, 20.0)])
///     .obstacle([(4.0, 8.0), (6.0, 8.0), (5.0, 10.0)])
///     .start(5.0, 19.0)
///     .goal(5.0, 1.0)
///     .plane(20.0, 0.0, 45.0, 0.4)
///     .clearance(0.5)
///     .build()
///     .unwrap();
/// assert_eq!(s.map.obstacles.len(), 1);
/// // The same checks as a file: an obstacle crossing the boundary is refused.
/// let bad = Scenario::builder()
///     .boundary([(0.0, 0.0), (10.0, 0.0), (10.0, 20.0), (0.0, 20.0)])
///     .obstacle([(8.0, 8.0), (12.0, 8.0), (10.0, 10.0)])
///     .start(5.0, 19.0)
///     .goal(5.0, 1.0)
///     .build();
/// assert!(bad.is_err());
/// ```
#[derive(Debug, Clone, Default)]
pub struct ScenarioBuilder {
    name: String,
    description: String,
    boundary: Option<Polygon>,
    obstacles: Vec<Polygon>,
    start: Option<Point2<f64>>,
    goal: Option<Point2<f64>>,
    robot: RobotParams,
    planes: Vec<TerrainPlane>,
    friction: Option<FrictionSpec>,
}

impl Scenario {
    /// A builder of a scenario from typed values ([`ScenarioBuilder`]).
    pub fn builder() -> ScenarioBuilder {
        ScenarioBuilder::default()
    }
}

impl ScenarioBuilder {
    /// A short name (reports and pictures carry it).
    pub fn name(mut self, name: impl Into<String>) -> Self {
        self.name = name.into();
        self
    }

    /// Free text: where the scenario comes from.
    pub fn description(mut self, text: impl Into<String>) -> Self {
        self.description = text.into();
        self
    }

    /// The outer boundary of the planning region (either orientation), in the unfolded frame
    /// (x across the slope, y up the slope). Required.
    pub fn boundary<P: IntoPoint>(mut self, points: impl IntoIterator<Item = P>) -> Self {
        self.boundary = Some(ring(points));
        self
    }

    /// One more tether obstacle (a hole in the free space).
    pub fn obstacle<P: IntoPoint>(mut self, points: impl IntoIterator<Item = P>) -> Self {
        self.obstacles.push(ring(points));
        self
    }

    /// Many obstacles at once, e.g. from a detector.
    pub fn obstacles<P: IntoPoint, R: IntoIterator<Item = P>>(
        mut self,
        rings: impl IntoIterator<Item = R>,
    ) -> Self {
        self.obstacles.extend(rings.into_iter().map(ring));
        self
    }

    /// Where the tether is anchored and the descent starts. Required.
    pub fn start(mut self, x: f64, y: f64) -> Self {
        self.start = Some(Point2::new(x, y));
        self
    }

    /// The science target. Required.
    pub fn goal(mut self, x: f64, y: f64) -> Self {
        self.goal = Some(Point2::new(x, y));
        self
    }

    /// One more terrain plane below the previous ones: its band `[y_bottom, y_top]` down the fall
    /// line, its slope in degrees and its wheel-terrain friction coefficient.
    pub fn plane(mut self, y_top: f64, y_bottom: f64, slope_deg: f64, friction: f64) -> Self {
        self.planes
            .push(TerrainPlane::new(y_top, y_bottom, slope_deg, friction));
        self
    }

    /// The robot's parameters as a whole (default: [`RobotParams::default`]).
    pub fn robot(mut self, robot: RobotParams) -> Self {
        self.robot = robot;
        self
    }

    /// The robot model (point, Axel or a four-wheel rover).
    pub fn robot_model(mut self, model: RobotModel) -> Self {
        self.robot.model = model;
        self
    }

    /// Clearance kept around obstacles by the ascent and descent, m.
    pub fn clearance(mut self, metres: f64) -> Self {
        self.robot.clearance_m = metres;
        self
    }

    /// The tether's length, m (default: unlimited).
    pub fn tether_length(mut self, metres: f64) -> Self {
        self.robot.tether_length_m = Some(metres);
        self
    }

    /// The frictional-planning section (`docs/friction.md`).
    pub fn friction(mut self, spec: FrictionSpec) -> Self {
        self.friction = Some(spec);
        self
    }

    /// The scenario, validated as a loaded file is ([`Scenario::validate`]): a missing boundary,
    /// start or goal is [`ScenarioError::Incomplete`]; a defect is the error a file with it gets.
    pub fn build(self) -> Result<Scenario, ScenarioError> {
        let boundary = self.boundary.ok_or(ScenarioError::Incomplete {
            missing: "boundary",
        })?;
        let start = self
            .start
            .ok_or(ScenarioError::Incomplete { missing: "start" })?;
        let goal = self
            .goal
            .ok_or(ScenarioError::Incomplete { missing: "goal" })?;
        let scenario = Scenario {
            name: self.name,
            description: self.description,
            map: Map::new(boundary, self.obstacles),
            start,
            goal,
            robot: self.robot,
            terrain: Terrain {
                planes: self.planes,
            },
            friction: self.friction,
            georeference: None,
        };
        scenario.validate()?;
        Ok(scenario)
    }
}
