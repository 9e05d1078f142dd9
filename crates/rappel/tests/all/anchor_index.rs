//! Alg. 5 and Alg. 6 with the anchor grid (`Evaluation::Indexed`, what the planners use) against
//! the direct form (`Evaluation::Direct`: every anchor scanned by every query, every cell of a
//! visibility line evaluated on its own), issue 10: identical feasibility reports (verdicts,
//! reachable parts, waypoints, routes) and identical path pairs or pair failures, class by class,
//! on seeded random crater strips, a long star obstacle, the committed strips and the Mars
//! patch. The reference is the direct form, which looks at every anchor and needs no index.

use crate::common;

use common::Prepared;
use rappel::dem::dem_scenario;
use rappel::planners::feasibility::{Evaluation, check_feasibility_evaluated};
use rappel::planners::path_pair::{AnchorClearance, PairInput, path_pair_evaluated};
use rappel::scenario::Scenario;
use rappel::terrain::ingest::IngestOptions;

/// What one comparison covered, so that a test can insist it was not vacuous.
#[derive(Debug, Default)]
struct Covered {
    classes: usize,
    anchors_examined: usize,
    pairs: usize,
}

/// Compares both evaluations on the first `k` classes of `scenario`.
fn compare(scenario: &Scenario, k: usize) -> Covered {
    let prepared = Prepared::new(scenario, k);
    let (ctx, classes) = (prepared.ctx(), &prepared.classes);
    let mut covered = Covered::default();
    for class in classes {
        let taut = &class.shp.taut;
        let none = |_: usize| false;
        let indexed = check_feasibility_evaluated(&ctx, taut, &none, Evaluation::Indexed);
        let direct = check_feasibility_evaluated(&ctx, taut, &none, Evaluation::Direct);
        assert_eq!(
            indexed, direct,
            "{}: class {} feasibility differs",
            scenario.name, class.rank
        );
        covered.classes += 1;
        covered.anchors_examined += direct
            .anchors
            .iter()
            .filter(|a| a.visibility_edge.is_some())
            .count();
        if direct.feasible() {
            let keep = vec![AnchorClearance::Keep; taut.anchors.len()];
            let input = PairInput {
                rank: class.rank,
                taut,
                crossings: &class.shp.crossings,
                route: &direct.route,
                anchors: &keep,
            };
            assert_eq!(
                path_pair_evaluated(&ctx, input, Evaluation::Indexed),
                path_pair_evaluated(&ctx, input, Evaluation::Direct),
                "{}: class {} path pair differs",
                scenario.name,
                class.rank
            );
            covered.pairs += 1;
        }
    }
    covered
}

fn fixture(name: &str) -> Scenario {
    let path = format!("{}/../../fixtures/{name}", env!("CARGO_MANIFEST_DIR"));
    Scenario::load(path).expect("fixture")
}

#[test]
fn seeded_strips_give_identical_reports() {
    let mut total = Covered::default();
    for seed in 1..=6 {
        let s = rappel::generated::crater_strip_scenario(60, seed, 60.0).expect("strip");
        let c = compare(&s, 4);
        total.classes += c.classes;
        total.anchors_examined += c.anchors_examined;
        total.pairs += c.pairs;
    }
    assert!(
        total.anchors_examined >= 20 && total.pairs >= 3,
        "{total:?}"
    );
}

#[test]
fn a_long_star_gives_identical_reports() {
    // 2,000 vertices: the class round the star wraps a hundred anchors, the next classes wind
    // round it again (a thousand more), so every query meets a crowd of anchors.
    let c = compare(&rappel::generated::star_scenario(2_000).expect("star"), 3);
    assert!(c.anchors_examined >= 100 && c.pairs >= 1, "{c:?}");
}

#[test]
fn the_committed_strips_give_identical_reports() {
    for (name, k) in [
        ("generated/crater-strip-100.ron", 5),
        ("generated/crater-strip-1000.ron", 3),
    ] {
        let c = compare(&fixture(name), k);
        assert!(c.anchors_examined >= 1, "{name}: {c:?}");
    }
}

#[test]
fn the_mars_patch_gives_identical_reports() {
    for file in [
        "mars_hirise_dteec_010228_1490_crop.asc",
        "mars_hirise_dteec_010228_1490_crop.tif",
    ] {
        let path = format!(
            "{}/../../fixtures/terrain/{file}",
            env!("CARGO_MANIFEST_DIR")
        );
        let d = dem_scenario(path.as_ref(), &IngestOptions::default()).expect("dem");
        let c = compare(&d.scenario, 10);
        assert!(c.pairs >= 1 && c.anchors_examined >= 5, "{file}: {c:?}");
    }
}
