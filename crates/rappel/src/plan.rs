//! The Chapter-2 planner on a scenario (`rappel plan`; thesis §2.3.3-2.4, Algorithms 3-6): "show
//! me the ways down, shortest first, and tell me which ones I can climb back up".
//!
//! [`plan`] builds the scenario's BTM, lists its homotopy classes shortest first with the SPT A*
//! search ([`rappel_planners::spt`]), checks each class's ascent for feasibility with anchor
//! reachable sets ([`rappel_planners::feasibility`], Alg. 5) on the scenario's terrain planes, and
//! returns the first feasible class's ascent/descent path pair ([`rappel_planners::path_pair`],
//! Alg. 6), with the clearance `robot.clearance_m`. The robot enters through the
//! [`AnchorTraversability`] trait: a point robot with the thesis' tether friction cone (eq. 2.7),
//! Axel and the four-wheel rover with the cone their own stability QP allows (Paton §IV-C;
//! [`rappel_mechanics::wheeled_tether_cone`]).
//! [`PlanReport`] is plain data (serde); `rappel_render::plan::picture` draws it like thesis Figs. 2.31-2.44.

pub use crate::pair::PairReport;
use crate::report::deg;
use crate::scenario::{Scenario, ValidScenario};
use crate::tether::HSignatureReport;
use crate::verdict::{AnchorPassability, AscentVerdict, BlockedAnchor, PairFailure};
use nalgebra::Point2;
use rappel_geometry::btm::{Btm, BtmError};
use rappel_geometry::map::ValidMap;
use rappel_homotopy::funnel::Side;
use rappel_mechanics::anchor_traversability::{AnchorTraversability, TetherLimit};
use rappel_mechanics::friction_cone::TetherFrictionCone;
use rappel_mechanics::stability_qp::StabilityQp;
use rappel_mechanics::traversability::StabilitySettings;
use rappel_mechanics::wheeled_tether_cone::WheeledTetherCone;
#[cfg(doc)]
use rappel_planners::budget::ExpansionBudget;
use rappel_planners::feasibility::{FeasibilityContext, Passability, fill_reachable_areas};
use rappel_planners::path_pair::{ClassOutcome, PairPlan, plan_path_pair_each};
use rappel_planners::spt::{SearchError, SearchOptions, SearchStats, SptPlanner, Termination};
use rappel_planners::stop::{StopCondition, StopReason};
use rappel_planners::terrain::{PlaneSeries, TerrainError};
use serde::{Deserialize, Serialize};

/// Default number of classes listed.
pub const DEFAULT_CLASSES: usize = 5;

/// The most classes one plan may list. Every class costs a search, an Alg. 5 feasibility check
/// and a report entry with its SHP and reachable sets (a few kB of JSON); a thousand classes are
/// far more than anyone reads, and keep a run within seconds and megabytes, where an unbounded
/// request (`--classes 1000000000`) ran for minutes and printed half a gigabyte.
pub const MAX_CLASSES: usize = 1000;

/// Options of [`plan`].
#[derive(Debug, Clone, PartialEq)]
pub struct PlanOptions {
    /// How many classes to list (at least 1).
    pub classes: usize,
    /// List only classes at most this factor longer than the shortest (at least 1).
    pub max_length_factor: Option<f64>,
    /// List only simple classes (no tether winds around an obstacle; see `docs/planner.md`).
    pub simple_only: bool,
    /// When to stop the search ([`rappel_planners::stop`]): its funnel expansion budget
    /// (scaled to the map by default, [`ExpansionBudget::Auto`]), a time limit, cancel flags.
    /// The time limit counts from the start of the call (the map's triangulation included) and
    /// bounds the whole plan: the search of the classes and the frictional planning share it,
    /// unless the condition was [started](StopCondition::started) earlier. The report says which
    /// condition stopped the search ([`PlanOutcome::stop_reason`]).
    pub stop: StopCondition,
    /// Cut every anchor reachable set to free space and report its area
    /// ([`AnchorReport::reachable_area_m2`]): a polygon overlay per anchor of every class, for
    /// reports only (feasibility never needs it), so off by default.
    pub reachable_areas: bool,
}

impl Default for PlanOptions {
    /// [`DEFAULT_CLASSES`] classes, no length bound, every class, the automatic budget alone
    /// ([`StopCondition::none`]).
    fn default() -> Self {
        PlanOptions {
            classes: DEFAULT_CLASSES,
            max_length_factor: None,
            simple_only: false,
            stop: StopCondition::none(),
            reachable_areas: false,
        }
    }
}

/// Why a plan could not be made (a scenario that has no feasible class is not an error: the
/// report says why).
#[derive(Debug, thiserror::Error)]
pub enum PlanError {
    /// The map does not triangulate.
    #[error(transparent)]
    Btm(#[from] BtmError),
    /// The terrain planes are unusable.
    #[error("terrain: {0}")]
    Terrain(#[from] TerrainError),
    /// The search refused its input or options.
    #[error(transparent)]
    Search(#[from] SearchError),
    /// The robot's parameters do not make a valid model.
    #[error("robot: {0}")]
    Robot(String),
    /// More classes were asked for than [`MAX_CLASSES`].
    #[error("{asked} classes asked for; at most {MAX_CLASSES} can be listed")]
    TooManyClasses {
        /// The number asked for.
        asked: usize,
    },
    /// The scenario's `friction` section is unusable, or frictional planning failed.
    #[error("{0}")]
    Friction(String),
}

/// One terrain plane in a report.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct PlaneReport {
    /// Index, 0 at the top.
    pub index: usize,
    /// Band top, m.
    pub y_top_m: f64,
    /// Band bottom, m.
    pub y_bottom_m: f64,
    /// Slope, degrees.
    pub slope_deg: f64,
    /// Wheel friction.
    pub friction: f64,
    /// `true` when the robot needs the tether to hold on it.
    pub tether_demand: bool,
    /// The friction cone's half-angle, degrees (`None` when tether-free).
    pub max_tether_angle_deg: Option<f64>,
}

/// One anchor of a class in a report.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct AnchorReport {
    /// `j`, from 1 at the start's end of the tether.
    pub index: usize,
    /// The map vertex.
    pub vertex: u32,
    /// Its obstacle (`None` on the map boundary).
    pub obstacle: Option<u32>,
    /// Its position.
    #[schemars(with = "[f64; 2]")]
    pub point: Point2<f64>,
    /// The side of the tether the obstacle lies on.
    pub side: Side,
    /// The plane holding it.
    pub plane: Option<usize>,
    /// `psi_j`, degrees from the fall line.
    pub psi_deg: f64,
    /// `theta_max_j`, degrees (`None`: tether-free).
    pub theta_max_deg: Option<f64>,
    /// `theta_max_{j-1}`, degrees (`None`: tether-free).
    pub previous_theta_max_deg: Option<f64>,
    /// Passed, impassable (and why) or not reached; `Display` gives `passable`,
    /// `impassable: <why>` or `not reached`.
    pub passability: AnchorPassability,
    /// Its waypoint on the visibility edge, when passable.
    #[schemars(with = "Option<[f64; 2]>")]
    pub waypoint: Option<Point2<f64>>,
    /// Area of its anchor reachable set `C_j` cut to free space, m² (`None` when it was not
    /// asked for, [`PlanOptions::reachable_areas`], or the overlay refused its input).
    pub reachable_area_m2: Option<f64>,
}

/// One homotopy class in a report.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct ClassReport {
    /// 1 for the shortest.
    pub rank: usize,
    /// SHP length, m.
    pub length_m: f64,
    /// Simple (no tether winds around an obstacle).
    pub simple: bool,
    /// The SHP polyline.
    #[schemars(with = "Vec<[f64; 2]>")]
    pub points: Vec<Point2<f64>>,
    /// Its anchors.
    pub anchors: Vec<AnchorReport>,
    /// Length of its reduced crossing sequence.
    pub reduced_crossings: usize,
    /// Its H-signature.
    pub h_signature: HSignatureReport,
    /// Angle of the last tether segment at the goal, degrees from the fall line.
    pub goal_psi_deg: f64,
    /// Ascent feasible (thesis Def. 2.4).
    pub feasible: bool,
    /// Feasible, or the first impassable anchor and why; `Display` gives the sentence.
    pub verdict: AscentVerdict,
    /// Waypoints in ascent order.
    #[schemars(with = "Vec<[f64; 2]>")]
    pub waypoints: Vec<Point2<f64>>,
    /// Why a feasible class got no path pair, if it did not.
    pub pair_failure: Option<PairFailure>,
}

/// What a plan's report says before its classes: the scenario, the model and the planes.
/// Shared (serde-flattened, so the JSON is one flat object) by [`PlanReport`] and the streamed
/// summary [`PlanSummary`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct PlanSetting {
    /// The scenario's name.
    pub scenario: String,
    /// Start.
    #[schemars(with = "[f64; 2]")]
    pub start: Point2<f64>,
    /// Goal.
    #[schemars(with = "[f64; 2]")]
    pub goal: Point2<f64>,
    /// The traversability model.
    pub traversability: String,
    /// Clearance around anchors, m.
    pub clearance_m: f64,
    /// The planes (empty: flat, tether-free ground).
    pub planes: Vec<PlaneReport>,
}

/// What a plan's report says after its classes: the chosen pair, the verdict, the search's end
/// and counters, warnings and the frictional plan. Shared (serde-flattened) by [`PlanReport`] and
/// [`PlanSummary`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct PlanOutcome {
    /// The chosen pair (the shortest feasible class with a valid pair).
    pub chosen: Option<PairReport>,
    /// One line: which class was chosen, or why none was.
    pub verdict: String,
    /// Why the search stopped.
    #[serde(with = "rappel_planners::search_report::termination_serde")]
    #[schemars(with = "rappel_planners::search_report::TerminationName")]
    pub termination: Termination,
    /// Which condition of the stop condition ([`PlanOptions::stop`]) stopped the search: the
    /// expansion budget with its limit, the time limit, a cancel request (`null` when the search
    /// ended by its own rules: the classes asked for, the length factor, no class left).
    #[serde(default)]
    pub stop_reason: Option<StopReason>,
    /// The search's counters.
    pub stats: SearchStats,
    /// Warnings (concave plane edges, approximated robot models).
    pub warnings: Vec<String>,
    /// Frictional planning (Alg. 7), when the scenario has PTFOs.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<crate::friction_plan::FrictionReport>,
}

/// What `rappel plan` reports: its [`PlanSetting`], the classes and its [`PlanOutcome`], in one
/// flat JSON object.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct PlanReport {
    /// Scenario, model and planes.
    #[serde(flatten)]
    pub setting: PlanSetting,
    /// The classes, shortest first.
    pub classes: Vec<ClassReport>,
    /// Chosen pair, verdict, search counters, warnings, frictional plan.
    #[serde(flatten)]
    pub outcome: PlanOutcome,
}

crate::report::report!(PlanReport, "plan");

/// A plan with what its picture needs.
#[derive(Debug, Clone)]
pub struct Plan {
    /// The report.
    pub report: PlanReport,
    /// The BTM of the scenario's map.
    pub btm: Btm,
    /// The planner's full outcome (sleeves, reachable sets, pairs).
    pub outcome: PairPlan,
    /// The frictional planner's outcome, when the scenario has PTFOs.
    pub friction: Option<rappel_planners::frictional::search::FrictionalPlan>,
}

/// Plans `scenario` (module docs), validating its map first (once: the BTM is built from the
/// proof, [`rappel_geometry::map::ValidMap`]).
///
/// ```
/// use rappel::plan::PlanOptions;
/// use rappel::scenario::Scenario;
/// let s = Scenario::from_ron_str(r#"(
///     map: (boundary: [(0.0, 0.0), (40.0, 0.0), (40.0, 100.0), (0.0, 100.0)],
///           obstacles: [[(18.0, 50.0), (22.0, 50.0), (22.0, 54.0), (18.0, 54.0)]]),
///     start: (21.0, 95.0), goal: (20.0, 5.0),
///     terrain: (planes: [(y_top: 100.0, y_bottom: 0.0, slope_deg: 45.0, friction: 0.4)]))"#).unwrap();
/// let report = rappel::plan(&s, &PlanOptions { classes: 3, ..Default::default() }).unwrap();
/// assert_eq!(report.classes.len(), 3);
/// assert!(report.classes[0].length_m <= report.classes[1].length_m);
/// let pair = report.outcome.chosen.expect("the shortest class is feasible");
/// assert_eq!(pair.rank, 1);
/// ```
pub fn plan(scenario: &Scenario, options: &PlanOptions) -> Result<PlanReport, PlanError> {
    let map = scenario.map.validate().map_err(BtmError::from)?;
    let core = plan_core(scenario, map, options, Keep::Reports, &mut |_| {})?;
    Ok(core.report())
}

/// Plans the validated `scenario` and keeps the BTM and the planner's outcome for pictures.
pub fn plan_detailed(
    scenario: &ValidScenario<'_>,
    options: &PlanOptions,
) -> Result<Plan, PlanError> {
    plan_detailed_each(scenario, options, &mut |_| {})
}

/// [`plan_detailed`], handing each class's report to `on_class` as soon as the class is decided
/// (for progress; the classes' geometry is kept, unlike [`plan_streamed`]).
pub fn plan_detailed_each(
    scenario: &ValidScenario<'_>,
    options: &PlanOptions,
    on_class: &mut dyn FnMut(&ClassReport),
) -> Result<Plan, PlanError> {
    Ok(plan_core(scenario, scenario.map(), options, Keep::Outcomes, on_class)?.plan())
}

/// Plans the validated `scenario` handing each class's report to `on_class` as soon as the class
/// is decided (searched, checked by Alg. 5, its pair built if it is the first feasible one),
/// shortest first, and drops the class's geometry (sleeve, funnel, anchor reachable sets) right
/// after; the class reports are kept for the returned report, which is the one [`plan`] returns
/// (the same classes, in the same order). [`plan_summary`] keeps no class at all.
///
/// ```
/// use rappel::plan::{plan, plan_streamed, PlanOptions};
/// use rappel::scenario::Scenario;
/// let s = Scenario::from_ron_str(r#"(
///     map: (boundary: [(0.0, 0.0), (40.0, 0.0), (40.0, 100.0), (0.0, 100.0)],
///           obstacles: [[(18.0, 50.0), (22.0, 50.0), (22.0, 54.0), (18.0, 54.0)]]),
///     start: (21.0, 95.0), goal: (20.0, 5.0),
///     terrain: (planes: [(y_top: 100.0, y_bottom: 0.0, slope_deg: 45.0, friction: 0.4)]))"#).unwrap();
/// let options = PlanOptions { classes: 3, ..Default::default() };
/// let mut seen = Vec::new();
/// let streamed = plan_streamed(&s.validate().unwrap(), &options, &mut |c| seen.push(c.rank)).unwrap();
/// assert_eq!(seen, vec![1, 2, 3]);
/// assert_eq!(streamed, plan(&s, &options).unwrap());
/// ```
pub fn plan_streamed(
    scenario: &ValidScenario<'_>,
    options: &PlanOptions,
    on_class: &mut dyn FnMut(&ClassReport),
) -> Result<PlanReport, PlanError> {
    Ok(plan_core(scenario, scenario.map(), options, Keep::Reports, on_class)?.report())
}

/// [`plan_streamed`] keeping nothing of a class once `on_class` has seen it: neither its
/// geometry nor its report, only their count. The memory held is one class's (its geometry and
/// report) plus the search's, whatever K; the summary is the one of [`plan`]'s report
/// (`PlanSummary::from` of it). This is `rappel plan` without `--json`, `--export` or a picture.
///
/// ```
/// use rappel::plan::{plan, plan_summary, PlanOptions};
/// use rappel::plan_stream::PlanSummary;
/// let s = rappel::generated::star_scenario(40).unwrap();
/// let options = PlanOptions { classes: 4, ..Default::default() };
/// let mut anchors = Vec::new();
/// let valid = s.validate().unwrap();
/// let summary = plan_summary(&valid, &options, &mut |c| anchors.push(c.anchors.len())).unwrap();
/// assert_eq!(summary.class_count, 4);
/// assert!(anchors[2] > anchors[0]); // the third class winds once more round the star
/// assert_eq!(summary, PlanSummary::from(&plan(&s, &options).unwrap()));
/// ```
pub fn plan_summary(
    scenario: &ValidScenario<'_>,
    options: &PlanOptions,
    on_class: &mut dyn FnMut(&ClassReport),
) -> Result<PlanSummary, PlanError> {
    let core = plan_core(scenario, scenario.map(), options, Keep::Nothing, on_class)?;
    Ok(PlanSummary {
        setting: core.setting,
        class_count: core.class_count,
        outcome: core.outcome,
    })
}

/// What [`plan_core`] keeps of each class once `on_class` has seen its report.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Keep {
    /// Its report and its whole outcome (sleeve, funnel, reachable sets): for pictures.
    Outcomes,
    /// Its report only.
    Reports,
    /// Nothing (the count).
    Nothing,
}

/// What [`plan_core`] made.
struct Core {
    setting: PlanSetting,
    classes: Vec<ClassReport>,
    class_count: usize,
    outcome: PlanOutcome,
    btm: Btm,
    pair_plan: PairPlan,
    friction: Option<rappel_planners::frictional::search::FrictionalPlan>,
}

impl Core {
    fn report(self) -> PlanReport {
        PlanReport {
            setting: self.setting,
            classes: self.classes,
            outcome: self.outcome,
        }
    }

    fn plan(self) -> Plan {
        Plan {
            report: PlanReport {
                setting: self.setting,
                classes: self.classes,
                outcome: self.outcome,
            },
            btm: self.btm,
            outcome: self.pair_plan,
            friction: self.friction,
        }
    }
}

/// The planner behind every entry point: `map` is `scenario.map`'s proof; `keep` says what stays
/// of each class after `on_class`.
fn plan_core(
    scenario: &Scenario,
    map: ValidMap<'_>,
    options: &PlanOptions,
    keep: Keep,
    on_class: &mut dyn FnMut(&ClassReport),
) -> Result<Core, PlanError> {
    if options.classes > MAX_CLASSES {
        return Err(PlanError::TooManyClasses {
            asked: options.classes,
        });
    }
    // One clock for the whole plan (triangulation, search, frictional planning).
    let stop = options.stop.started();
    let btm = Btm::build(map)?;
    // The point robot uses the thesis' friction cone (eq. 2.7); a wheeled robot the cone its own
    // stability QP allows (Paton §IV-C), through the same trait.
    let wheeled = crate::robot::wheeled_model(&scenario.robot).map_err(PlanError::Robot)?;
    let qp = StabilityQp::new(StabilitySettings::default());
    let wheeled_cone = wheeled
        .as_deref()
        .map(|robot| WheeledTetherCone::new(robot, &qp));
    let model: &dyn AnchorTraversability = match &wheeled_cone {
        Some(cone) => cone,
        None => &TetherFrictionCone,
    };
    let terrain = PlaneSeries::new(&scenario.terrain.planes, model)?;
    let search = SearchOptions::default()
        .with_max_classes(Some(options.classes))?
        .with_max_length_factor(options.max_length_factor)?
        .with_stop(stop)?
        .with_simple_only(options.simple_only);
    let ctx = FeasibilityContext {
        btm: &btm,
        terrain: &terrain,
        clearance: scenario.robot.clearance_m,
        tether_length: scenario.robot.tether_length_m,
    };
    let planner = SptPlanner::new(&btm);
    let (mut kept, mut reports) = (Vec::new(), Vec::new());
    let (mut class_count, mut first_failure) = (0, None);
    let mut pair_plan = plan_path_pair_each(
        &planner,
        scenario.start,
        scenario.goal,
        &search,
        &ctx,
        false,
        &mut |mut c| {
            if options.reachable_areas {
                fill_reachable_areas(&ctx, &mut c.feasibility);
            }
            let r = class_report(&c, options.reachable_areas);
            on_class(&r);
            class_count += 1;
            if first_failure.is_none() {
                first_failure = Some(
                    r.pair_failure
                        .as_ref()
                        .map_or_else(|| r.verdict.to_string(), ToString::to_string),
                );
            }
            if keep != Keep::Nothing {
                reports.push(r);
            }
            if keep == Keep::Outcomes {
                kept.push(c);
            }
        },
    )?;
    pair_plan.classes = kept;
    let setting = setting_of(scenario, model, &terrain);
    let mut outcome = outcome_of(&terrain, &pair_plan, class_count, first_failure);
    let mut friction = None;
    if let Some(spec) = &scenario.friction {
        let resolved = spec
            .resolve(
                scenario.robot.mass_kg,
                &scenario.terrain.planes,
                scenario.map.obstacles.len(),
            )
            .map_err(PlanError::Friction)?;
        let (r, p) =
            crate::friction_plan::plan_friction(scenario, &resolved, &btm, &terrain, &search)
                .map_err(|e| PlanError::Friction(format!("frictional planning: {e}")))?;
        outcome.friction = Some(r);
        friction = Some(p);
    }
    Ok(Core {
        setting,
        classes: reports,
        class_count,
        outcome,
        btm,
        pair_plan,
        friction,
    })
}

fn degrees(limit: TetherLimit) -> Option<f64> {
    limit.max_angle().map(deg)
}

/// The report of one class (`areas`: its reachable areas were computed).
fn class_report(c: &ClassOutcome, areas: bool) -> ClassReport {
    let f = &c.feasibility;
    let taut = &c.class.shp.taut;
    let h = &c.class.h_signature;
    ClassReport {
        rank: c.class.rank,
        length_m: taut.length,
        simple: c.class.simple,
        points: taut.points.clone(),
        anchors: f
            .anchors
            .iter()
            .map(|a| AnchorReport {
                index: a.index,
                vertex: a.anchor.vertex.0,
                obstacle: a.anchor.obstacle.map(|o| o.0),
                point: a.anchor.point,
                side: a.anchor.side,
                plane: a.plane,
                psi_deg: deg(a.psi),
                theta_max_deg: degrees(a.limit),
                previous_theta_max_deg: degrees(a.previous_limit),
                passability: a.passability.into(),
                waypoint: match a.passability {
                    Passability::Passable { waypoint, .. } => Some(waypoint),
                    _ => None,
                },
                reachable_area_m2: f
                    .reachable_sets
                    .iter()
                    .find(|set| areas && set.anchor == a.index && set.free_pieces_error.is_none())
                    .map(|set| set.free_pieces.iter().map(|(r, _)| r.area()).sum()),
            })
            .collect(),
        reduced_crossings: c.class.shp.crossings.len(),
        h_signature: HSignatureReport {
            digest: format!("{:016x}", h.digest()),
            windings: h.windings().iter().map(|&(o, n)| (o.0, n)).collect(),
        },
        goal_psi_deg: deg(f.goal_psi),
        feasible: f.feasible(),
        verdict: match &f.blockage {
            None => AscentVerdict::Feasible,
            Some(b) => AscentVerdict::Blocked {
                anchor: b.anchor.map(|j| {
                    let a = &f.anchors[j - 1].anchor;
                    BlockedAnchor {
                        index: j,
                        vertex: a.vertex.index(),
                        obstacle: a.obstacle.map(|o| o.index()),
                    }
                }),
                reason: b.reason.into(),
            },
        },
        waypoints: f.waypoints.clone(),
        pair_failure: c.pair_failure.clone(),
    }
}

/// The report's [`PlanSetting`].
fn setting_of(
    scenario: &Scenario,
    model: &dyn AnchorTraversability,
    terrain: &PlaneSeries,
) -> PlanSetting {
    let planes = terrain
        .planes()
        .iter()
        .zip(terrain.limits())
        .enumerate()
        .map(|(index, (p, l))| PlaneReport {
            index,
            y_top_m: p.y_top,
            y_bottom_m: p.y_bottom,
            slope_deg: p.slope_deg,
            friction: p.friction,
            tether_demand: l.is_tether_demand(),
            max_tether_angle_deg: degrees(*l),
        })
        .collect();
    PlanSetting {
        scenario: scenario.name.clone(),
        start: scenario.start,
        goal: scenario.goal,
        traversability: model.name().to_string(),
        clearance_m: scenario.robot.clearance_m,
        planes,
    }
}

/// The report's [`PlanOutcome`] (without the frictional plan): `class_count` classes were found,
/// and `first_failure` is the first one's pair failure or verdict.
///
/// The verdict names the condition that stopped the search, if one did ("the search stopped at
/// the time limit of 0.1 s", "... at a cancel request", "... at the automatic budget of N
/// expansions; raise --max-expansions"): after the chosen class's lengths, before "no class
/// found" (which then does not mean that start and goal are disconnected), or in the parenthesis
/// of "no feasible class among the N found".
fn outcome_of(
    terrain: &PlaneSeries,
    pair_plan: &PairPlan,
    class_count: usize,
    first_failure: Option<String>,
) -> PlanOutcome {
    let chosen = pair_plan.pair.as_ref().map(PairReport::from);
    let stopped = pair_plan
        .stop_reason
        .map(|r| format!("the search stopped at {r}"));
    let verdict = match (&chosen, first_failure) {
        (Some(p), _) => {
            let mut v = format!(
                "class {} is the shortest feasible class: ascent {:.2} m, descent {:.2} m",
                p.rank, p.ascent_length_m, p.descent_length_m
            );
            if let Some(r) = pair_plan.stop_reason {
                v.push_str(&format!(
                    "; after {class_count} classes the search stopped at {r}"
                ));
            }
            v
        }
        (None, None) => match &stopped {
            Some(s) => format!(
                "no class found before {s} (this does not mean start and goal are disconnected)"
            ),
            None => format!("no class found: {}", pair_plan.termination.describe()),
        },
        (None, Some(first)) => format!(
            "no feasible class among the {class_count} found ({}); class 1: {first}",
            stopped.unwrap_or_else(|| pair_plan.termination.describe().to_string())
        ),
    };
    let mut warnings = Vec::new();
    for k in terrain.concave_edges() {
        warnings.push(format!(
            "planes {k} and {} form a concave edge (the lower plane is shallower): the taut tether may lift off the ground there, which the Chapter-2 model does not cover",
            k + 1
        ));
    }
    if terrain.planes().is_empty() {
        warnings.push(
            "no terrain planes: planned as flat, tether-free ground (thesis §2.2.4)".to_string(),
        );
    }
    PlanOutcome {
        chosen,
        verdict,
        termination: pair_plan.termination,
        stop_reason: pair_plan.stop_reason,
        stats: pair_plan.stats,
        warnings,
        friction: None,
    }
}

/// A plan's report without its classes: the last line of a complete stream.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct PlanSummary {
    /// Scenario, model and planes.
    #[serde(flatten)]
    pub setting: PlanSetting,
    /// How many `class` lines came before (the classes found).
    pub class_count: usize,
    /// Chosen pair, verdict, search counters, warnings, frictional plan.
    #[serde(flatten)]
    pub outcome: PlanOutcome,
}

impl From<&PlanReport> for PlanSummary {
    fn from(r: &PlanReport) -> Self {
        PlanSummary {
            setting: r.setting.clone(),
            class_count: r.classes.len(),
            outcome: r.outcome.clone(),
        }
    }
}
