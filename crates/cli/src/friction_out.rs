//! Text output of the frictional part of `rappel plan` (thesis Alg. 7): tensions, per class each
//! anchor's kind and verdict, the slips, the ascent sweep at friction anchors and the capstan along
//! the tether.

use rappel::friction_plan::FrictionReport;

fn pt(p: &rappel::nalgebra::Point2<f64>) -> String {
    format!("({:.3}, {:.3})", p.x, p.y)
}

/// Prints the frictional report.
pub fn print_friction(f: &FrictionReport) {
    let t = &f.tensions;
    crate::output::outln!(
        "friction     PTFOs on obstacles {:?}; T_min {:.1} N, T_max {:.1} N, T_d {:.1} N, eps {:.1} N",
        f.ptfos,
        t.t_min_n,
        t.t_max_n,
        t.t_d_n,
        t.epsilon_n
    );
    for n in &f.notes {
        crate::output::outln!("  derived    {n}");
    }
    for c in &f.classes {
        crate::output::outln!(
            "f-class {:<3}  length {:.3} m (searched {:.3} m), {} anchors, {} slip(s): {}",
            c.rank,
            c.length_m,
            c.searched_length_m,
            c.anchors.len(),
            c.slips.len(),
            c.verdict
        );
        for s in &c.slips {
            crate::output::outln!(
                "  slip       vertex {} of obstacle {}{}: length {:.3} -> {:.3} m, anchors {} -> {}",
                pt(&s.vertex),
                s.obstacle,
                if s.obstacle_removed {
                    " (obstacle removed)"
                } else {
                    ""
                },
                s.length_before_m,
                s.length_after_m,
                s.anchors_before.len(),
                s.anchors_after.len()
            );
        }
        for a in &c.anchors {
            let on = a
                .obstacle
                .map_or_else(|| "boundary".to_string(), |o| format!("obstacle {o}"));
            crate::output::outln!(
                "  anchor     {} {on}: {}, turn {:.1}°, int omega ds {:.3}{}",
                pt(&a.point),
                a.verdict,
                a.turn_deg,
                a.omega_integral_hold,
                a.no_contact
                    .as_ref()
                    .map_or_else(String::new, |w| format!(" (no contact: {w})"))
            );
        }
        for s in &c.sweeps {
            crate::output::outln!(
                "  sweep      a{}: holds for turns >= {:.2}° (SHP turn {:.2}°), early release {}",
                s.index,
                s.release_turn.to_degrees(),
                s.turn.to_degrees(),
                if s.release_safe { "safe" } else { "unsafe" }
            );
        }
        if let Some(h) = &c.holding {
            crate::output::outln!(
                "  capstan    total exponent {:.3}: a_0 holds {:.1} N when the robot pulls T_max{}",
                h.total_exponent,
                h.holding_force_at_start_n,
                h.tension_limit_n.map_or_else(String::new, |l| format!(
                    "; robot-side limit {l:.1} N (Kumar eq. 2)"
                ))
            );
        }
        if !c.waypoints.is_empty() {
            let list: Vec<String> = c.waypoints.iter().map(pt).collect();
            crate::output::outln!("  waypoints  {}", list.join(" "));
        }
        if let Some(p) = &c.pair {
            crate::output::outln!(
                "  pair       ascent {:.2} m, descent {:.2} m{}, {}",
                p.ascent_length_m,
                p.descent_length_m,
                if p.descent_is_reversed_ascent {
                    " (the ascent reversed)"
                } else {
                    ""
                },
                p.min_anchor_distance_m.map_or_else(
                    || "no anchor kept clear".to_string(),
                    |d| format!("{d:.3} m from the nearest anchor kept clear")
                )
            );
        }
    }
    crate::output::outln!("f-verdict    {}", f.verdict);
}
