//! Regression suite `terrain`: each real elevation model in `fixtures/terrain/` goes DEM ->
//! scenario -> BTM -> plan; the counts (planes and their classes, obstacle clusters, tether and
//! robot obstacles, unknown regions) and the plan (classes found, feasible classes, the chosen
//! class, the shortest SHP's length to the millimetre) are compared with the golden file
//! `fixtures/terrain/golden.json`, and the ingested map must build a BTM whose invariants hold. The golden file is rewritten by
//! `cargo xtask gen-fixtures` after a deliberate change; a diff in review shows what moved.
//! Those golden rows are drift checks; the suite's reproductions are the synthetic DEMs of known
//! geometry in [`super::terrain_synthetic`].

use super::case::{Case, workspace_root};
use rappel::btm_summary::summarize_btm;
use rappel::dem::dem_scenario;
use rappel::plan::{PlanOptions, plan};
use rappel::scenario::Scenario;
use rappel::terrain::ingest::{IngestOptions, IngestSummary};
use serde::{Deserialize, Serialize};
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

/// What the pipeline produces for one grid with default options.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Golden {
    /// Ingestion counts.
    pub ingest: IngestSummary,
    /// Homotopy classes the planner listed (default options).
    pub classes: usize,
    /// How many of them are feasible.
    pub feasible_classes: usize,
    /// Rank of the class the planner chose, if any.
    pub chosen_rank: Option<usize>,
    /// Length of the shortest SHP, millimetres.
    pub shortest_mm: i64,
}

/// Runs the pipeline on one grid; also returns the scenario for further checks.
fn run_pipeline(grid: &str) -> Result<(Golden, Scenario), String> {
    let dir = workspace_root().join("fixtures").join("terrain");
    let d = dem_scenario(&dir.join(grid), &IngestOptions::default()).map_err(|e| e.to_string())?;
    let report =
        plan(&d.scenario, &PlanOptions::default()).map_err(|e| format!("{grid}: plan: {e}"))?;
    let golden = Golden {
        ingest: d.summary(),
        classes: report.classes.len(),
        feasible_classes: report.classes.iter().filter(|c| c.feasible).count(),
        chosen_rank: report.outcome.chosen.as_ref().map(|c| c.rank),
        shortest_mm: report
            .classes
            .first()
            .map(|c| (c.length_m * 1000.0).round() as i64)
            .unwrap_or(-1),
    };
    Ok((golden, d.scenario))
}

/// The pipeline's results for every grid, keyed by file name.
pub fn summaries() -> Result<BTreeMap<String, Golden>, String> {
    let mut out = BTreeMap::new();
    for g in GRIDS {
        out.insert((*g).to_string(), run_pipeline(g)?.0);
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
    let golden: BTreeMap<String, Golden> =
        serde_json::from_str(&text).map_err(|e| format!("{}: {e}", golden_path().display()))?;
    let mut cases = Vec::new();
    for g in GRIDS {
        let (got, scenario) = run_pipeline(g)?;
        let want = golden
            .get(*g)
            .ok_or_else(|| format!("{g}: missing from the golden file"))?;
        let (gi, wi) = (&got.ingest, &want.ingest);
        let rows: [(&str, String, String); 11] = [
            ("planes", gi.planes.to_string(), wi.planes.to_string()),
            (
                "tether-demand planes",
                gi.tether_demand_planes.to_string(),
                wi.tether_demand_planes.to_string(),
            ),
            (
                "tether obstacle clusters",
                gi.tether_clusters.to_string(),
                wi.tether_clusters.to_string(),
            ),
            (
                "tether obstacles in the map",
                gi.tether_obstacles.to_string(),
                wi.tether_obstacles.to_string(),
            ),
            (
                "robot obstacles",
                gi.robot_obstacles.to_string(),
                wi.robot_obstacles.to_string(),
            ),
            (
                "unknown regions",
                gi.unknown_regions.to_string(),
                wi.unknown_regions.to_string(),
            ),
            (
                "obstacle cells",
                gi.obstacle_points.to_string(),
                wi.obstacle_points.to_string(),
            ),
            (
                "plan: classes found",
                got.classes.to_string(),
                want.classes.to_string(),
            ),
            (
                "plan: feasible classes",
                got.feasible_classes.to_string(),
                want.feasible_classes.to_string(),
            ),
            (
                "plan: chosen class",
                format!("{:?}", got.chosen_rank),
                format!("{:?}", want.chosen_rank),
            ),
            (
                "plan: shortest SHP, mm",
                got.shortest_mm.to_string(),
                want.shortest_mm.to_string(),
            ),
        ];
        for (what, measured, reference) in rows {
            let pass = measured == reference;
            cases.push(Case::drift(
                SUITE,
                format!("{g}: {what}"),
                measured,
                format!("{reference} (golden file written by rappel itself)"),
                pass,
            ));
        }
        let (_, btm) = summarize_btm(scenario.validate().map_err(|e| format!("{g}: {e}"))?.map())
            .map_err(|e| format!("{g}: {e}"))?;
        cases.push(Case::property(
            SUITE,
            format!("{g}: BTM of the ingested map"),
            btm.invariant_violation
                .clone()
                .unwrap_or_else(|| format!("{} triangles, invariants hold", btm.triangles)),
            "invariants hold",
            btm.invariants_hold,
        ));
    }
    cases.extend(super::terrain_synthetic::cases()?);
    Ok(cases)
}
