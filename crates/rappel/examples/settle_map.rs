//! A stability map of Paton's ledge like his Fig. 8: Axel driven from the start under the root
//! anchor, the anchor history carried along (`cargo run -p rappel --example settle_map`).
use rappel::planners::anchor_prediction::AnchorHistory;
use rappel::prelude::*;
use rappel::settle_map::stability_map;
use rappel::terrain::paton_scene::PatonScene;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let scene = PatonScene::paper(false);
    let ground = scene.mesh()?;
    let root = AnchorHistory::new(scene.anchor_points()[0])?;
    let mut spec = MapSpec::fig8(&scene);
    spec.step = 1.0;
    let map = stability_map(&ground, &root, &spec)?;
    println!("{} stable, {} unstable cells", map.stable, map.unstable);
    Ok(())
}
