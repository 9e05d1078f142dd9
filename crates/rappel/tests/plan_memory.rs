//! What a streamed plan holds (issue 10, "K classes in bounded memory"): `plan_summary` keeps
//! nothing of a class once its callback has seen it, so the memory resident when class `k` is
//! handed over does not include the classes before it. Measured as the process's resident set
//! (`VmRSS` of `/proc/self/status`; the workspace forbids `unsafe`, so no counting allocator) on
//! a star whose classes wind round it more and more: class `k` has about `k / 2` windings, so
//! the anchors grow linearly with `k` and their sum quadratically. This binary holds one test,
//! so nothing else runs meanwhile.
//!
//! How it fails: if the streamed plan kept every class's report (as `plan_streamed` does) or its
//! geometry (as `plan_detailed` does), the resident set at the last class would exceed that at
//! the first by at least the earlier classes' anchor reports (one `AnchorReport` per anchor),
//! and the bound is half of that; the same measurement on `plan_streamed` checks that it does
//! see retained reports.

use rappel::generated::star_scenario;
use rappel::plan::{AnchorReport, ClassReport, PlanOptions, plan_streamed, plan_summary};

/// The resident set, bytes (`None` where `/proc/self/status` is not there).
fn resident() -> Option<usize> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    let kb: usize = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// Star vertices (half of them on its hull: the anchors of one winding) and classes: windings
/// up to about `CLASSES / 2`.
const VERTICES: usize = 400;
const CLASSES: usize = 100;

/// Per class handed over: (anchors, bytes resident in the callback).
fn live_per_class(run: impl FnOnce(&mut dyn FnMut(&ClassReport))) -> Vec<(usize, usize)> {
    let mut seen = Vec::new();
    run(&mut |c: &ClassReport| seen.push((c.anchors.len(), resident().unwrap_or(0))));
    seen
}

/// The bytes the reports of the classes before the last would hold: one `AnchorReport` per
/// anchor (their strings and the classes' points not counted, so a lower bound).
fn earlier_reports_bytes(seen: &[(usize, usize)]) -> usize {
    let anchors: usize = seen[..seen.len() - 1].iter().map(|&(n, _)| n).sum();
    anchors * std::mem::size_of::<AnchorReport>()
}

/// Growth of the resident bytes from the first class's callback to the last's.
fn growth(seen: &[(usize, usize)]) -> isize {
    seen[seen.len() - 1].1 as isize - seen[0].1 as isize
}

#[test]
fn a_streamed_plan_holds_no_earlier_class() {
    if resident().is_none() {
        eprintln!("no /proc/self/status: the resident set cannot be read here");
        return;
    }
    let s = star_scenario(VERTICES).expect("star");
    let valid = s.validate().expect("valid");
    let options = PlanOptions {
        classes: CLASSES,
        ..Default::default()
    };
    let streamed = live_per_class(|f| {
        let summary = plan_summary(&valid, &options, f).expect("plan");
        assert_eq!(summary.class_count, CLASSES);
    });
    assert_eq!(streamed.len(), CLASSES);
    let (first, last) = (streamed[0].0, streamed[CLASSES - 1].0);
    assert!(
        last > 10 * first,
        "the classes must grow (windings): {first} then {last} anchors"
    );
    let earlier = earlier_reports_bytes(&streamed);
    let grew = growth(&streamed);
    eprintln!(
        "plan_summary: {} anchors in all, the last class {last}; the resident set grew by {grew} bytes from the first class to the last; the earlier classes' anchor reports alone are {earlier} bytes",
        streamed.iter().map(|&(n, _)| n).sum::<usize>()
    );
    assert!(
        grew < (earlier / 2) as isize,
        "the streamed plan's resident set grew by {grew} bytes over the classes; half the earlier classes' reports is {}",
        earlier / 2
    );
    // The same measurement sees retained reports.
    let kept = live_per_class(|f| {
        let report = plan_streamed(&valid, &options, f).expect("plan");
        assert_eq!(report.classes.len(), CLASSES);
    });
    let kept_growth = growth(&kept);
    eprintln!("plan_streamed (reports kept): grew by {kept_growth}");
    assert!(
        kept_growth >= (earlier_reports_bytes(&kept) / 2) as isize,
        "keeping the reports grew the resident set by only {kept_growth} bytes"
    );
}
