//! Regression suite `terrain`: each real elevation model in `fixtures/terrain/` goes DEM ->
//! scenario -> BTM; the counts (planes and their classes, obstacle clusters, tether and robot
//! obstacles, unknown regions) are compared with the golden file `fixtures/terrain/golden.json`,
//! and the ingested map must build a BTM whose invariants hold. The golden file is rewritten by
//! `cargo xtask gen-fixtures` after a deliberate change; a diff in review shows what moved.

use super::{Case, workspace_root};
use rappel::btm_summary::summarize_btm;
use rappel::dem::dem_scenario;
use rappel::geometry::terrain::ingest::{IngestOptions, IngestSummary};
use std::collections::BTreeMap;
use std::path::PathBuf;

const SUITE: &str = "terrain";

/// The real grids the suite ingests (file names under `fixtures/terrain/`).
pub const GRIDS: &[&str] = &[
    "mars_hirise_dteec_010228_1490_crop.asc",
    "mars_hirise_dteec_010228_1490_crop.tif",
    "earth_mt_st_helens_landslide_10m.asc",
];

fn golden_path() -> PathBuf {
    workspace_root()
        .join("fixtures")
        .join("terrain")
        .join("golden.json")
}

/// The summaries of every grid with default options, keyed by file name.
pub fn summaries() -> Result<BTreeMap<String, IngestSummary>, String> {
    let dir = workspace_root().join("fixtures").join("terrain");
    let mut out = BTreeMap::new();
    for g in GRIDS {
        let d = dem_scenario(&dir.join(g), &IngestOptions::default()).map_err(|e| e.to_string())?;
        out.insert((*g).to_string(), d.summary());
    }
    Ok(out)
}

/// Rewrites the golden file.
pub fn write_golden() -> Result<PathBuf, String> {
    let text = serde_json::to_string_pretty(&summaries()?).map_err(|e| e.to_string())? + "\n";
    let path = golden_path();
    rappel::io::write_atomically(&path, text.as_bytes())
        .map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(path)
}

/// Runs the suite.
pub fn suite() -> Result<Vec<Case>, String> {
    let text = std::fs::read_to_string(golden_path())
        .map_err(|e| format!("{}: {e}", golden_path().display()))?;
    let golden: BTreeMap<String, IngestSummary> =
        serde_json::from_str(&text).map_err(|e| format!("{}: {e}", golden_path().display()))?;
    let dir = workspace_root().join("fixtures").join("terrain");
    let mut cases = Vec::new();
    for g in GRIDS {
        let d = dem_scenario(&dir.join(g), &IngestOptions::default()).map_err(|e| e.to_string())?;
        let got = d.summary();
        let want = golden
            .get(*g)
            .ok_or_else(|| format!("{g}: missing from the golden file"))?;
        let rows: [(&str, usize, usize); 7] = [
            ("planes", got.planes, want.planes),
            (
                "tether-demand planes",
                got.tether_demand_planes,
                want.tether_demand_planes,
            ),
            (
                "tether obstacle clusters",
                got.tether_clusters,
                want.tether_clusters,
            ),
            (
                "tether obstacles in the map",
                got.tether_obstacles,
                want.tether_obstacles,
            ),
            ("robot obstacles", got.robot_obstacles, want.robot_obstacles),
            ("unknown regions", got.unknown_regions, want.unknown_regions),
            ("obstacle cells", got.obstacle_points, want.obstacle_points),
        ];
        for (what, measured, reference) in rows {
            cases.push(Case::new(
                SUITE,
                format!("{g}: {what}"),
                measured.to_string(),
                format!("{reference} (golden)"),
                measured == reference,
            ));
        }
        let (_, btm) = summarize_btm(&d.scenario.map).map_err(|e| format!("{g}: {e}"))?;
        cases.push(Case::new(
            SUITE,
            format!("{g}: BTM of the ingested map"),
            btm.invariant_violation
                .clone()
                .unwrap_or_else(|| format!("{} triangles, invariants hold", btm.triangles)),
            "invariants hold",
            btm.invariants_hold,
        ));
    }
    Ok(cases)
}
