//! Quick timing of a BTM build on a generated crater strip (the criterion benchmark in
//! `benches/` is the reference; this is for a glance from the command line, and for profiling:
//! `btm_timing N REPEAT` builds the N-obstacle strip's BTM REPEAT times (at most 1000) and prints
//! the fastest build).

use rappel_geometry::btm::Btm;
use rappel_geometry::generate::{CraterStripOptions, crater_strip};
use std::time::Instant;

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(10_000);
    let g = match crater_strip(&CraterStripOptions::new(n, 1)) {
        Ok(g) => g,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(2);
        }
    };
    let repeat: usize = std::env::args()
        .nth(2)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1)
        .clamp(1, 1000);
    let mut build = std::time::Duration::MAX;
    let mut built = None;
    for _ in 0..repeat {
        let t = Instant::now();
        let btm = match Btm::from_map(&g.map) {
            Ok(b) => b,
            Err(e) => {
                eprintln!("error: {e}");
                std::process::exit(2);
            }
        };
        build = build.min(t.elapsed());
        built = Some(btm);
    }
    let Some(btm) = built else {
        return;
    };
    let t = Instant::now();
    let report = btm.check_invariants();
    println!(
        "{} vertices, build {:?}, check {:?}: {:?}",
        g.map.vertex_count(),
        build,
        t.elapsed(),
        report.map(|r| r.triangles)
    );
}
