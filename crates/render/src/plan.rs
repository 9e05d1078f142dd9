//! The picture of `rappel plan` (thesis Figs. 2.31-2.44 and, with friction, 3.17-3.20): the
//! BTM, the shown class's sleeve, taut tether and anchors, friction cones, visibility edges,
//! waypoints, the ascent/descent pair, infeasible classes with their blocking anchors, and PTFOs
//! coloured by their verdict.

use nalgebra::Point2;
use rappel::friction_plan::FrictionReport;
use rappel::plan::Plan;
use rappel::scenario::Scenario;
use rappel::verdict::AnchorHold;
use rappel_geometry::polygon::Aabb;
use rappel_mechanics::anchor_traversability::TetherLimit;
use rappel_terrain::frame::PlanningFrame;
use rappel_terrain::grid::Raster;

use crate::style::CONE_DRAW_FACTOR;
use crate::{Layer, Picture};

/// The picture of a plan (thesis Figs. 2.31-2.44), cropped to `window` (map frame; `--window`)
/// when given: BTM, the sleeve and SHP of the chosen class (the shortest when none is feasible),
/// its anchors, friction cones of the tether-demand planes, visibility edges, waypoints, the
/// ascent and descent paths, start and goal; every infeasible class drawn as a thin red tether
/// tagged with its rank and its blocking anchor (or the goal) marked with the reason as hover
/// text; the frictional outcome when the scenario has one.
pub fn picture(plan: &Plan, scenario: &Scenario, window: Option<&Aabb>) -> String {
    picture_over(plan, scenario, window, None)
}

/// [`picture`] over a hillshade of the ground (a scenario made from a DEM:
/// [`crate::dem::scenario_hillshade`]) and its planning frame.
pub fn picture_over(
    plan: &Plan,
    scenario: &Scenario,
    window: Option<&Aabb>,
    ground: Option<(&Raster, &PlanningFrame)>,
) -> String {
    let mut pic = Picture::of_map_in(&scenario.map, window);
    if let Some((shade, frame)) = ground {
        crate::dem::draw_hillshade(&mut pic, shade, frame);
        let o = frame.to_world(&scenario.start);
        pic.set_north(frame.to_planning(&(o + nalgebra::Vector2::new(0.0, 1.0))) - scenario.start);
    }
    let shown = plan
        .outcome
        .pair
        .as_ref()
        .and_then(|p| plan.outcome.classes.iter().find(|c| c.class.rank == p.rank))
        .or_else(|| plan.outcome.classes.first());
    if let Some(c) = shown {
        pic.sleeve(&plan.btm, &c.class.shp.sleeve);
    }
    pic.btm(&plan.btm);
    pic.map(&scenario.map);
    if let Some(c) = shown {
        let taut = &c.class.shp.taut;
        let corners: Vec<Point2<f64>> = std::iter::once(taut.start())
            .chain(taut.anchors.iter().map(|a| a.point))
            .chain(std::iter::once(taut.goal()))
            .collect();
        for set in &c.feasibility.reachable_sets {
            let reach = CONE_DRAW_FACTOR * (corners[set.anchor + 1] - set.apex).norm();
            for (poly, limit) in &set.pieces {
                if let TetherLimit::Cone { max_angle } = limit {
                    pic.friction_cone(&set.apex, *max_angle, reach, &poly.vertices);
                }
            }
        }
        for a in &c.feasibility.anchors {
            if let Some([p, q]) = a.visibility_edge {
                pic.polyline(Layer::Visibility, &[p, q]);
            }
        }
        if let Some(pair) = &plan.outcome.pair {
            pic.polyline(Layer::Descent, &pair.descent);
            pic.polyline(Layer::Ascent, &pair.ascent);
        }
        pic.taut_path(taut);
        for w in &c.feasibility.waypoints {
            pic.marker(Layer::Waypoint, *w);
        }
    }
    for c in &plan.outcome.classes {
        let Some(b) = &c.feasibility.blockage else {
            continue;
        };
        let taut = &c.class.shp.taut;
        pic.set_tag(Some(format!("class {} (infeasible)", c.class.rank)));
        pic.polyline(Layer::InfeasibleShp, &taut.points);
        let at = match b.anchor {
            Some(j) => c.feasibility.anchors.get(j - 1).map(|a| a.anchor.point),
            None => Some(taut.goal()),
        };
        if let Some(p) = at {
            let what = b
                .anchor
                .map_or("the goal".to_string(), |j| format!("anchor {j}"));
            pic.titled_marker(
                Layer::Blocking,
                p,
                &format!(
                    "class {}: {what} blocks the ascent: {}",
                    c.class.rank,
                    b.reason.describe()
                ),
            );
        }
        pic.set_tag(None);
    }
    if let Some(f) = &plan.report.outcome.friction {
        draw_friction(&mut pic, scenario, f);
    }
    pic.start_goal(scenario.start, scenario.goal);
    let title = match &plan.outcome.pair {
        Some(p) => format!("{}: class {} (ascent/descent pair)", scenario.name, p.rank),
        None => format!("{}: no feasible class", scenario.name),
    };
    pic.finish(&title)
}

/// Draws the frictional outcome onto `pic`: PTFOs coloured by their verdict in the shown class
/// (solid, slides, volatile; untouched PTFOs outlined), the clipped vertices, the final SHP, its
/// sticking points (solid friction anchors), the waypoints and the ascent/descent pair.
pub fn draw_friction(pic: &mut Picture, scenario: &Scenario, report: &FrictionReport) {
    let shown = report
        .chosen
        .and_then(|r| report.classes.iter().find(|c| c.rank == r))
        .or_else(|| report.classes.first());
    for &o in &report.ptfos {
        let verdict = shown.and_then(|c| {
            c.anchors
                .iter()
                .find(|a| a.obstacle == Some(o))
                .map(|a| a.verdict)
                .or_else(|| {
                    c.slips
                        .iter()
                        .any(|s| s.obstacle == o)
                        .then_some(AnchorHold::Slides)
                })
        });
        let layer = match verdict {
            Some(AnchorHold::Solid) => Layer::PtfoSolid,
            Some(AnchorHold::Volatile) => Layer::PtfoVolatile,
            Some(_) => Layer::PtfoSlides,
            None => Layer::Ptfo,
        };
        if let Some(poly) = scenario.map.obstacles.get(o) {
            pic.polygon(layer, &poly.vertices);
        }
    }
    if let Some(c) = shown {
        if let Some(pair) = &c.pair {
            pic.polyline(Layer::Descent, &pair.descent);
            pic.polyline(Layer::Ascent, &pair.ascent);
        }
        pic.polyline(Layer::Shp, &c.points);
        for s in &c.slips {
            pic.marker(Layer::Slip, s.vertex);
        }
        for a in &c.anchors {
            let layer = if a.verdict == AnchorHold::Geometric {
                Layer::Anchor
            } else {
                Layer::Sticking
            };
            pic.marker(layer, a.point);
        }
        for w in &c.waypoints {
            pic.marker(Layer::Waypoint, *w);
        }
    }
}
