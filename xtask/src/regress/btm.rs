//! Regression suite `btm`: the BTM invariants (triangle count n + 2h - 2, area, map edges,
//! constrained Delaunay) on every scenario fixture and on the generated 10,000-obstacle map; the
//! generated fixtures match their seeds; and a long sequence of local updates on the big map keeps
//! the invariants and the ids of untouched triangles.

use super::case::{Case, workspace_root};
use crate::fixtures::{GENERATED, generated_path};
use rappel::btm_summary::summarize_btm;
use rappel::geometry::btm::Btm;
use rappel::geometry::dcel::{TriangleId, VertexId};
use rappel::scenario::Scenario;
use std::path::{Path, PathBuf};

const SUITE: &str = "btm";

/// Runs the suite.
pub fn suite() -> Result<Vec<Case>, String> {
    let mut cases = Vec::new();
    let root = workspace_root();
    let mut files = scenario_files(&root.join("fixtures"));
    files.sort();
    for file in files {
        let name = file
            .strip_prefix(&root)
            .unwrap_or(&file)
            .display()
            .to_string();
        // Read here, validated once in `invariant_cases` (its proof goes to the BTM build).
        let scenario = Scenario::read(&file).map_err(|e| e.to_string())?;
        invariant_cases(&name, &scenario, &mut cases)?;
    }
    for &(n, seed) in GENERATED {
        let fresh =
            rappel::generated::crater_strip_scenario(n, seed, 200.0).map_err(|e| e.to_string())?;
        let path = generated_path(n);
        let committed = Scenario::load(&path).map_err(|e| e.to_string())?;
        cases.push(Case::drift(
            SUITE,
            format!("generated {n} obstacles, seed {seed}: committed fixture matches"),
            if committed == fresh {
                "identical"
            } else {
                "differs"
            },
            "identical (run cargo xtask gen-fixtures)",
            committed == fresh,
        ));
    }
    let big =
        rappel::generated::crater_strip_scenario(10_000, 1, 200.0).map_err(|e| e.to_string())?;
    update_cases(&big, &mut cases)?;
    Ok(cases)
}

fn scenario_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let Ok(entries) = std::fs::read_dir(dir) else {
        return out;
    };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            // fixtures/terrain holds elevation models and golden counts, fixtures/tracking track
            // scenarios and paths (rappel track), fixtures/paths path files (rappel shp,
            // homotopic), fixtures/queries pairs files (rappel query), fixtures/paton Paton's mesh
            // scenes (rappel settle), fixtures/hostile inputs built to be refused
            // (crates/cli/tests/all/hostile.rs): not planning scenarios.
            const NOT_SCENARIOS: [&str; 6] = [
                "terrain", "tracking", "paths", "paton", "queries", "hostile",
            ];
            if p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| NOT_SCENARIOS.contains(&n))
            {
                continue;
            }
            out.extend(scenario_files(&p));
        } else if rappel::scenario::Format::of_path(&p).is_some() {
            out.push(p);
        }
    }
    out
}

fn invariant_cases(name: &str, s: &Scenario, cases: &mut Vec<Case>) -> Result<(), String> {
    let (_, summary) = summarize_btm(s.validate().map_err(|e| format!("{name}: {e}"))?.map())
        .map_err(|e| format!("{name}: {e}"))?;
    // n and h counted from the input map, not from the BTM under test.
    let (n, h) = (s.map.vertex_count(), s.map.obstacles.len());
    let expected = n + 2 * h - 2;
    cases.push(Case::closed_form(
        SUITE,
        format!("{name}: triangles"),
        summary.triangles.to_string(),
        format!("n + 2h - 2 = {n} + 2*{h} - 2 = {expected} (counted from the map)"),
        summary.triangles == expected,
    ));
    cases.push(Case::property(
        SUITE,
        format!("{name}: invariants (area, map edges, Delaunay)"),
        summary
            .invariant_violation
            .clone()
            .unwrap_or_else(|| "all hold".into()),
        "all hold",
        summary.invariants_hold && summary.constrained_delaunay,
    ));
    Ok(())
}

/// Removes 200 obstacles from the big map one by one, then puts them back, checking the
/// invariants every 20 updates and at the end, and that unreported triangles never change.
fn update_cases(s: &Scenario, cases: &mut Vec<Case>) -> Result<(), String> {
    let mut btm = Btm::from_map(&s.map).map_err(|e| e.to_string())?;
    let original = btm.triangle_count();
    let ids: Vec<_> = btm.obstacle_ids().step_by(50).take(200).collect();
    let mut removed = Vec::new();
    let mut unreported_changes = 0usize;
    let mut broken = None;
    let mut step = 0;
    let check = |btm: &Btm, step: usize, broken: &mut Option<String>| {
        if broken.is_none()
            && step.is_multiple_of(20)
            && let Err(e) = btm.check_invariants()
        {
            *broken = Some(format!("after update {step}: {e}"));
        }
    };
    let snapshot = |btm: &Btm| -> Vec<_> {
        btm.triangles()
            .map(|t| (t, btm.dcel().triangle_vertices(t)))
            .collect()
    };
    for id in ids {
        let poly = btm.obstacle_polygon(id).ok_or("missing obstacle")?;
        let before = snapshot(&btm);
        let report = btm.remove_obstacle(id).map_err(|e| e.to_string())?;
        unreported_changes += unreported(&btm, &before, &report.removed);
        removed.push(poly);
        step += 1;
        check(&btm, step, &mut broken);
    }
    for poly in removed {
        let before = snapshot(&btm);
        let (_, report) = btm.insert_obstacle(&poly).map_err(|e| e.to_string())?;
        unreported_changes += unreported(&btm, &before, &report.removed);
        step += 1;
        check(&btm, step, &mut broken);
    }
    let final_check = btm.check_invariants();
    cases.push(Case::property(
        SUITE,
        "10,000 obstacles: 200 removals + 200 insertions, invariants",
        broken
            .clone()
            .or(final_check.as_ref().err().map(ToString::to_string))
            .unwrap_or_else(|| "all hold".into()),
        "all hold",
        broken.is_none() && final_check.is_ok(),
    ));
    cases.push(Case::property(
        SUITE,
        "10,000 obstacles: triangles changed without being reported",
        unreported_changes.to_string(),
        "0",
        unreported_changes == 0,
    ));
    cases.push(Case::property(
        SUITE,
        "10,000 obstacles: triangle count after the round trip",
        btm.triangle_count().to_string(),
        format!("{original} (before)"),
        btm.triangle_count() == original,
    ));
    Ok(())
}

/// Triangles of `before` that are not reported removed yet are gone or changed in `btm`.
fn unreported(btm: &Btm, before: &[(TriangleId, [VertexId; 3])], removed: &[TriangleId]) -> usize {
    before
        .iter()
        .filter(|(t, v)| {
            let intact = btm.is_free_triangle(*t) && btm.dcel().triangle_vertices(*t) == *v;
            !removed.contains(t) && !intact
        })
        .count()
}
