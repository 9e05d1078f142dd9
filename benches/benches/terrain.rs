//! Terrain ingestion benchmarks (issue 6): DEM to scenario ingredients for a 1,000 x 1,000 grid,
//! target under 1 s. The grid is synthesised from the real Mars HiRISE patch in
//! `fixtures/terrain/`: its roughness (heights minus their plane) mirror-tiled over a convex
//! three-plane crater wall whose fall line is off the grid axes
//! ([`rappel_terrain::synthetic::textured_wall`]). Besides the whole pipeline, its
//! stages are timed alone: Horn slopes, the plane series, obstacle detection.

use criterion::{Criterion, criterion_group, criterion_main};
use rappel_terrain::dem::read_dem;
use rappel_terrain::frame::PlanningFrame;
use rappel_terrain::grid::HeightGrid;
use rappel_terrain::ingest::{IngestOptions, ingest};
use rappel_terrain::obstacle_detection::{ObstacleOptions, ReferencePlane, detect_obstacles};
use rappel_terrain::plane_fit::{PlaneFitOptions, fit_plane_series};
use rappel_terrain::slope::SlopeField;
use rappel_terrain::synthetic::textured_wall;
use std::hint::black_box;

/// The real Mars patch the texture comes from.
const MARS: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../fixtures/terrain/mars_hirise_dteec_010228_1490_crop.asc"
);

fn wall() -> HeightGrid {
    let mars = read_dem(MARS).expect("the Mars fixture reads");
    textured_wall(&mars, 1000, 1000).expect("the texture has a plane")
}

fn terrain(c: &mut Criterion) {
    let dem = wall();
    let options = IngestOptions::default();
    let out = ingest(&dem, &options).expect("the synthetic wall ingests");
    eprintln!("1000 x 1000 textured wall: {:?}", out.summary());

    let mut g = c.benchmark_group("terrain_1000x1000");
    g.sample_size(10);
    g.bench_function("ingest", |b| {
        b.iter(|| ingest(black_box(&dem), &options).expect("ingests"))
    });
    g.bench_function("horn_slope", |b| {
        b.iter(|| SlopeField::horn(black_box(&dem)))
    });
    let fall = SlopeField::horn(&dem).fall_line().expect("a fall line");
    let frame = PlanningFrame::for_grid(dem.geometry(), &fall);
    g.bench_function("plane_series", |b| {
        b.iter(|| fit_plane_series(black_box(&dem), &frame, &PlaneFitOptions::default()))
    });
    let geometry = *dem.geometry();
    let plane = out.plane_fits[out.plane_fits.len() / 2];
    let gradient =
        out.frame.uphill * plane.fall_line_gradient + out.frame.across * plane.cross_gradient;
    let reference = |r: usize, c: usize| {
        let (t, s) = out.frame.horizontal(&geometry.cell_center(r, c));
        ReferencePlane {
            gradient,
            height: plane.height(t, s),
        }
    };
    g.bench_function("obstacle_detection", |b| {
        b.iter(|| detect_obstacles(black_box(&dem), reference, &ObstacleOptions::default()))
    });
    g.finish();
}

criterion_group!(benches, terrain);
criterion_main!(benches);
