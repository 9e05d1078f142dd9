//! `rappel plan` on scenarios with PTFOs: the frictional report in text and JSON, the picture's
//! PTFO colours, exit 0 when a class is feasible with friction and 1 when none is.

use crate::common;

use common::*;

#[test]
fn solid_friction_anchor_is_its_own_waypoint() {
    let dir = temp_dir("friction-svg");
    let out = dir.join("plan.svg");
    let file = fixture("friction/capstan_holds.ron");
    let o = rappel(&[
        "plan",
        &file,
        "--json",
        "--svg",
        out.to_str().unwrap_or_default(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    let f = &v["friction"];
    assert_eq!(f["chosen"], 1);
    let class = &f["classes"][0];
    assert_eq!(class["anchors"][0]["verdict"], "solid");
    // The waypoint is the anchor itself (thesis §3.4.2).
    assert_eq!(class["waypoints"][0], class["anchors"][0]["point"]);
    let svg = std::fs::read_to_string(&out).expect("svg written");
    for needle in ["PTFO: solid", "sticking point"] {
        assert!(svg.contains(needle), "missing {needle}");
    }
}

#[test]
fn slips_are_reported_and_volatile_classes_exit_1() {
    let o = rappel(&["plan", &fixture("friction/slip_then_wrap.ron")]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(
        text.contains("slip       vertex (28.000, 50.000) of obstacle 0"),
        "{text}"
    );
    // Lower the pillar's friction until its wrap is volatile: no class is feasible with friction.
    let dir = temp_dir("friction-volatile");
    let src = std::fs::read_to_string(fixture("friction/capstan_holds.ron")).expect("fixture");
    let volatile = dir.join("volatile.ron");
    std::fs::write(
        &volatile,
        src.replace("lo: 1.0, hi: 1.1", "lo: 0.3, hi: 0.33"),
    )
    .expect("write");
    // The two simple classes turn once at a corner: volatile.
    let o = rappel(&[
        "plan",
        volatile.to_str().unwrap_or_default(),
        "--classes",
        "2",
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stdout(&o));
    assert!(stdout(&o).contains("volatile"), "{}", stdout(&o));
    // The third winds the tether once round the pillar, at five corners: judged by its total
    // wrap (e^(0.3 * 7.67) = 10 > T_max/T_min), it holds although no corner alone would.
    let o = rappel(&[
        "plan",
        volatile.to_str().unwrap_or_default(),
        "--classes",
        "3",
    ]);
    assert!(o.status.success(), "{}", stdout(&o));
    assert!(
        stdout(&o).contains("class 3 is the first feasible class with friction"),
        "{}",
        stdout(&o)
    );
    // A typo in the friction section is a located error, exit 2.
    let typo = dir.join("typo.ron");
    std::fs::write(
        &typo,
        src.replace(
            "radius: 7.0710678118654755",
            "radius: 7.0710678118654755, radios: 1.0",
        ),
    )
    .expect("write");
    let o = rappel(&["plan", typo.to_str().unwrap_or_default()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("radios"), "{}", stderr(&o));
    // `rappel validate` checks the friction section too.
    let bad = dir.join("bad-obstacle.ron");
    std::fs::write(&bad, src.replace("obstacle: 0", "obstacle: 7")).expect("write");
    let o = rappel(&["validate", bad.to_str().unwrap_or_default()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("obstacle 7"), "{}", stderr(&o));
}
