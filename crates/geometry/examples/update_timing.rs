//! Quick timing of local updates on the generated 10,000-obstacle strip (the criterion benchmark
//! in `benches/` is the reference; this is for profiling from the command line).

use rappel_geometry::btm::Btm;
use rappel_geometry::generate::{CraterStripOptions, crater_strip};
use std::time::Instant;

fn main() {
    let Ok(generated) = crater_strip(&CraterStripOptions::new(10_000, 1)) else {
        return;
    };
    let mut map = generated.map;
    let obstacle = map.obstacles.remove(5_000);
    let Ok(mut btm) = Btm::from_map(&map) else {
        return;
    };
    let rounds = 200;
    let (mut ins, mut rem) = (0.0, 0.0);
    for _ in 0..rounds {
        let t = Instant::now();
        let Ok((id, _)) = btm.insert_obstacle(&obstacle) else {
            return;
        };
        ins += t.elapsed().as_secs_f64();
        let t = Instant::now();
        if btm.remove_obstacle(id).is_err() {
            return;
        }
        rem += t.elapsed().as_secs_f64();
    }
    println!(
        "insert {:.1} us, remove {:.1} us",
        ins / rounds as f64 * 1e6,
        rem / rounds as f64 * 1e6
    );
}
