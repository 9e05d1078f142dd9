//! Builds the sparse distance field of Paton's ledge scene `REPS` times at resolution `H`
//! (propagated to the default `D`, margin 2 m as in the `sdf` bench; `truncated` as a third
//! argument for `D = T`) and prints each build's wall time: a driver for CPU-time
//! (`/usr/bin/time -v`), thread-count (`RAYON_NUM_THREADS`) and instruction-count
//! (`valgrind --tool=callgrind`) measurements of the build alone.
//!
//! `cargo run --release -p rappel-benches --example sdf_build -- 0.05 3`

use rappel_terrain::paton_scene::PatonScene;
use rappel_terrain::sparse_sdf::{SparseSdf, SparseSdfParams};
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let h: f64 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(0.05);
    let reps: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(1);
    let truncated = args.get(3).is_some_and(|s| s == "truncated");
    let m = PatonScene::paper(false)
        .mesh()
        .expect("the paper's scene meshes");
    let mut p = if truncated {
        SparseSdfParams::truncated(h)
    } else {
        SparseSdfParams::new(h)
    };
    p.margin = 2.0;
    for _ in 0..reps {
        let t = Instant::now();
        let f = SparseSdf::from_mesh(&m, &p).expect("fits");
        println!(
            "h {h} {}: {} blocks, {:.3} s",
            if truncated { "truncated" } else { "propagated" },
            f.block_count(),
            t.elapsed().as_secs_f64()
        );
    }
}
