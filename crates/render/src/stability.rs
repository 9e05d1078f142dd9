//! The picture of `rappel stability` (Kumar Fig. 5): every assessed pose on the scenario's map,
//! stable poses coloured by their margin, unstable ones as rings.

use rappel::scenario::Scenario;
use rappel::stability::StabilityReport;
use rappel_geometry::polygon::Aabb;

use crate::style::scale_colour;
use crate::{Layer, Picture};

/// The picture of the map (cropped to `window`, map frame, when given): each stable pose a
/// disc sized to the grid step and coloured by its margin on the colour scale
/// ([`crate::style::SCALE_STOPS`], drawn in the panel from the smallest to the largest margin),
/// each unstable pose a thin ring of the same size; dots lie under the obstacles, so that
/// none hides one. Every dot's hover text gives its position, margin and tension.
pub fn picture(
    report: &StabilityReport,
    scenario: &Scenario,
    window: Option<&Aabb>,
    title: &str,
) -> String {
    let mut pic = Picture::of_map_in(&scenario.map, window);
    pic.map(&scenario.map);
    let margins = report.dots.iter().filter_map(|d| d.margin);
    let lo = margins.clone().fold(f64::INFINITY, f64::min);
    let hi = margins.fold(f64::NEG_INFINITY, f64::max);
    let r = 0.45 * report.grid_step_m;
    for d in &report.dots {
        let title = format!(
            "({:.2}, {:.2}) plane {}: {}{}",
            d.point.x,
            d.point.y,
            d.plane,
            match d.margin {
                Some(m) => format!("stable, margin {m:.3}"),
                None if d.stable => "stable".to_string(),
                None => "not stable".to_string(),
            },
            d.tether_tension_n
                .map_or(String::new(), |t| format!(", tension {t:.1} N"))
        );
        if d.stable {
            let t = match d.margin {
                Some(m) if hi > lo => (m - lo) / (hi - lo),
                _ => 1.0,
            };
            pic.disc(Layer::Stable, d.point, r, Some(&scale_colour(t)), &title);
        } else {
            pic.disc(Layer::Unstable, d.point, 0.8 * r, None, &title);
        }
    }
    if lo.is_finite() && hi.is_finite() {
        pic.set_colour_scale("stability margin", lo, hi);
    }
    pic.marker(Layer::Start, scenario.start);
    pic.finish(title)
}
