//! Regression cases of tether tracking and two robots on one tether (Kumar Alg. 1, Problem 1,
//! Fig. 5): Kumar's environment (S0 flat with two obstacles, S1 55 deg, S2 65 deg, S3 flat;
//! m1 = m2 = 35 kg, mu = 0.4), three Robot-1 paths whose tracked windings give `T_2max` near the
//! paper's 200 / 300 / 500 N, and Robot 2's stability grids on S1 and S2 compared with Fig. 5.
//!
//! References come from outside the code under test: the paper's numbers and verdicts, and the
//! homotopy crate's shortest homotopic path (an independent oracle for the tracked tether). Where
//! our faithful model disagrees with the paper, the row says DIFFERS with the reason; those rows
//! are listed, with their reasons, in the runner's [`super::KNOWN_DIFFERENCES`].
//!
//! The geometry the paper does not give numerically is chosen here: surfaces 16 m wide
//! (`x` in `[-8, 8]`), S0 14 m deep, S1 and S2 8 m long, S3 4 m; obstacle O1 the square
//! `[-4, -2] x [22, 24]`, O2 the square `[2, 4] x [19, 21]` (frame metres, `y` up the fall line);
//! Robot 2 starts at `(3, 17)` on S0, Robot 1 at `(5, 18)`; Robot 1's paths (below) wind the
//! tether as the paper describes. `F_0 = 0`: Robot 1 holds with its wheels' friction only, so
//! `T_1 <= mu m1 g = 137.3 N` (eq. 1).

use super::case::Case;
use rappel::geometry::btm::Btm;
use rappel::geometry::map::Map;
use rappel::geometry::polygon::Polygon;
use rappel::homotopy::path::Path;
use rappel::homotopy::shp::shortest_homotopic_path;
use rappel::mechanics::four_wheel::FourWheelRover;
use rappel::mechanics::robot::{RobotModel, STANDARD_GRAVITY};
use rappel::mechanics::tension_limit::HoldingRobot;
use rappel::nalgebra::Point2;
use rappel::planners::tether_tracking::TetherTracker;
use rappel::planners::tether_tracking::two_robots::{TwoRobots, WaypointReport};
use rappel::terrain::kumar::{kumar_obstacles, kumar_scene};
use rappel::terrain::plane_series_terrain::PlaneSeriesTerrain;

const SUITE: &str = "tracking";

fn p(x: f64, y: f64) -> Point2<f64> {
    Point2::new(x, y)
}

fn kumar_terrain() -> Result<PlaneSeriesTerrain, String> {
    kumar_scene().map_err(|e| e.to_string())
}

const ROBOT2_START: (f64, f64) = (3.0, 17.0);

/// The three scenarios: name, the paper's `T_2max`, Robot 1's path.
fn scenarios() -> Vec<(&'static str, f64, Vec<Point2<f64>>)> {
    vec![
        // Partly around O2's right side.
        ("5a", 200.0, vec![p(5.0, 18.0), p(5.0, 23.0), p(3.0, 23.0)]),
        // Around O2's right side, then over O1's top.
        (
            "5b",
            300.0,
            vec![
                p(5.0, 18.0),
                p(5.0, 23.0),
                p(0.0, 25.0),
                p(-5.0, 25.0),
                p(-5.5, 24.0),
            ],
        ),
        // Nearly a full turn around O2.
        (
            "5c",
            500.0,
            vec![p(5.0, 18.0), p(5.0, 23.0), p(1.0, 23.0), p(1.0, 18.5)],
        ),
    ]
}

/// Robot 2's grid on a surface band `(y_bottom, y_top)`: 1 m steps, half a metre in from the
/// edges, `x` in `[-7, 7]`.
fn grid(y_bottom: f64, y_top: f64) -> Vec<Point2<f64>> {
    let mut out = Vec::new();
    let mut y = y_bottom + 0.5;
    while y < y_top {
        for i in -7..=7 {
            out.push(p(i as f64, y));
        }
        y += 1.0;
    }
    out
}

struct Counts {
    red: usize,
    green: usize,
    yellow: usize,
    /// Stable poses (green or yellow) left of the centre line (`x < 0`), on it, and right of it.
    stable_by_side: [usize; 3],
}

/// Robot 2 walks straight from its start to each grid pose; red unstable, green stable with the
/// obstacle windings alone, yellow stable only with the ground anchors' gain (Kumar's yellow).
fn classify(
    two: &TwoRobots<'_, PlaneSeriesTerrain>,
    path1: &[Point2<f64>],
    poses: &[Point2<f64>],
) -> Result<Counts, String> {
    let mut c = Counts {
        red: 0,
        green: 0,
        yellow: 0,
        stable_by_side: [0; 3],
    };
    let start = p(ROBOT2_START.0, ROBOT2_START.1);
    for q in poses {
        let reports = two
            .run(path1, &[start, p(q.x, 16.0), *q])
            .map_err(|e| e.to_string())?;
        let r: &WaypointReport = reports.last().ok_or("no report")?;
        if r.stable {
            let side = if q.x < 0.0 {
                0
            } else if q.x == 0.0 {
                1
            } else {
                2
            };
            c.stable_by_side[side] += 1;
        }
        if !r.stable {
            c.red += 1;
        } else if r
            .required_tension_n
            .is_some_and(|t| t > r.t2max_obstacles_n && r.ground_anchored)
        {
            c.yellow += 1;
        } else {
            c.green += 1;
        }
    }
    Ok(c)
}

/// The suite.
pub fn suite() -> Result<Vec<Case>, String> {
    let terrain = kumar_terrain()?;
    let rover = FourWheelRover::default();
    let holding = HoldingRobot {
        max_pull: 0.0,
        friction: 0.4,
        mass: 35.0,
    };
    let two = TwoRobots {
        terrain: &terrain,
        holding,
        gravity: STANDARD_GRAVITY,
        robot2: &rover as &dyn RobotModel,
        tether_height: rover.params().tether_exit.z,
    };
    let map = Map::new(
        Polygon::rectangle(-8.0, -4.0, 16.0, 34.0),
        kumar_obstacles(),
    );
    let btm = Btm::from_map(&map).map_err(|e| e.to_string())?;
    let start2 = p(ROBOT2_START.0, ROBOT2_START.1);
    let mut cases = Vec::new();
    let s1 = grid(8.0, 16.0);
    let s2 = grid(0.0, 8.0);
    for (name, paper, path1) in scenarios() {
        // The tracked tether of Robot 1's path equals the SHP of that path from Robot 2's start.
        let mut tr = TetherTracker::new(&terrain, start2, path1[0]).map_err(|e| e.to_string())?;
        tr.follow(&path1[1..]).map_err(|e| e.to_string())?;
        let mut walk = vec![start2];
        walk.extend(&path1);
        let shp = shortest_homotopic_path(&btm, &Path::new(walk).map_err(|e| e.to_string())?)
            .map_err(|e| e.to_string())?;
        let anchors = tr.obstacle_anchors().len();
        let len = tr.length();
        cases.push(Case::oracle(
            SUITE,
            format!("Kumar Fig. {name}: Robot 1's tracked tether vs the SHP (homotopy crate)"),
            format!("{anchors} anchors, {len:.6} m"),
            format!(
                "{} anchors, {:.6} m (rel. 1e-9)",
                shp.taut.anchors.len(),
                shp.taut.length
            ),
            anchors == shp.taut.anchors.len()
                && (len - shp.taut.length).abs() <= 1e-9 * shp.taut.length,
        ));
        let at_start = two.run(&path1, &[start2]).map_err(|e| e.to_string())?;
        let t2 = at_start[0].t2max_n;
        cases.push(Case::paper_number(
            SUITE,
            format!("Kumar Fig. {name}: T2max from Robot 1's windings (eq. 2), Robot 2 at start"),
            format!(
                "{t2:.1} N (winding {:.1} deg)",
                at_start[0].total_winding.to_degrees()
            ),
            format!("{paper:.0} N +- 10% (paper)"),
            (t2 - paper).abs() <= 0.1 * paper,
        ));
        let c1 = classify(&two, &path1, &s1)?;
        let c2 = classify(&two, &path1, &s2)?;
        // The paper's verdicts: 5a nothing stable; 5b stable on S1's right part, S2 unstable;
        // 5c stable on S2.
        let expect: [(&str, &Counts, bool); 2] = match name {
            "5a" => [("S1", &c1, false), ("S2", &c2, false)],
            "5b" => [("S1", &c1, true), ("S2", &c2, false)],
            _ => [("S1", &c1, true), ("S2", &c2, true)],
        };
        for (surface, c, paper_stable) in expect {
            let stable = c.green + c.yellow > 0;
            let paper = if paper_stable {
                "some stable"
            } else {
                "none stable"
            };
            let row = Case::paper_verdict(
                SUITE,
                format!("Kumar Fig. {name}, Robot 2 on {surface}: red / green / yellow"),
                format!(
                    "{} / {} / {} of {}",
                    c.red,
                    c.green,
                    c.yellow,
                    c.red + c.green + c.yellow
                ),
                format!("paper: {paper}"),
                stable == paper_stable,
            );
            // Fig. 5b's S1, in the paper's words: "Robot 2 is stable at the right section of the
            // surface S1" (Kumar §IV): stable poses there, none on the left half.
            if (name, surface) == ("5b", "S1") {
                let [left, centre, right] = c.stable_by_side;
                cases.push(Case::paper_verdict(
                    SUITE,
                    "Kumar Fig. 5b, Robot 2 on S1: where the stable poses are",
                    format!("{left} left of centre, {centre} on it, {right} right"),
                    "paper: stable on the right section of S1 (none left of centre, some right)",
                    left == 0 && right > 0,
                ));
            }
            cases.push(match band(name, surface) {
                Some(b) => {
                    let holds = b.green.contains(&c.green) && b.yellow.contains(&c.yellow);
                    row.differs_within(
                        format!("green {:?}, yellow {:?} of 120", b.green, b.yellow),
                        holds,
                    )
                }
                None => row,
            });
        }
    }
    Ok(cases)
}

/// The band a known difference of Fig. 5 is expected in: green and yellow counts of Robot 2's
/// 120 poses.
struct FigBand {
    green: std::ops::RangeInclusive<usize>,
    yellow: std::ops::RangeInclusive<usize>,
}

/// The bands of the known differences (`super::KNOWN_DIFFERENCES`), around the measured counts
/// (5a S1: 0 green, 35 yellow; 5a S2: 0 green, 28 yellow; 5b S2: 20 green, 28 yellow): green
/// stays at the paper's 0 on 5a (with the depicted 200 N alone nothing holds) and the poses the
/// crests' capstan gain holds stay within about a third of their count; a row outside its band
/// (more or fewer) fails until the list is updated.
fn band(fig: &str, surface: &str) -> Option<FigBand> {
    match (fig, surface) {
        ("5a", "S1") => Some(FigBand {
            green: 0..=0,
            yellow: 24..=46,
        }),
        ("5a", "S2") => Some(FigBand {
            green: 0..=0,
            yellow: 19..=37,
        }),
        ("5b", "S2") => Some(FigBand {
            green: 14..=26,
            yellow: 19..=37,
        }),
        _ => None,
    }
}
