//! scratch
use rappel_geometry::terrain::dem::read_dem;
use rappel_geometry::terrain::ingest::{IngestOptions, ingest};
use rappel_geometry::terrain::obstacle_detection::CellClass;

#[test]
fn scratch() {
    for f in [
        "mars_hirise_dteec_010228_1490_crop.asc",
        "mars_hirise_dteec_010228_1490_crop.tif",
        "earth_mt_st_helens_landslide_10m.asc",
    ] {
        let path = format!("{}/../../fixtures/terrain/{f}", env!("CARGO_MANIFEST_DIR"));
        let dem = read_dem(&path).unwrap();
        println!(
            "== {f}: {:?} unknown {}",
            dem.geometry(),
            dem.unknown_count()
        );
        for tol in [0.1, 0.25, 0.5, 1.0, 2.0] {
            let mut o = IngestOptions::default();
            o.planes.merge_tolerance_m = tol;
            let t = std::time::Instant::now();
            let out = match ingest(&dem, &o) {
                Ok(o) => o,
                Err(e) => {
                    use rappel_geometry::terrain::{
                        frame::PlanningFrame, plane_fit::fit_plane_series, slope::SlopeField,
                    };
                    let fl = SlopeField::horn(&dem).fall_line().unwrap();
                    let f0 = PlanningFrame::for_grid(dem.geometry(), &fl);
                    let fit = fit_plane_series(&dem, &f0, &o.planes).unwrap();
                    let bu: Vec<(f64, f64)> = fit
                        .planes
                        .iter()
                        .rev()
                        .map(|p| (p.s_bottom, p.slope_deg()))
                        .collect();
                    let f = f0.unfolded(&bu);
                    println!("ERR {e}\n fl {:?}\n pieces {:?}", fl, f.pieces);
                    for c in dem.geometry().corners() {
                        println!("corner {:?}", f0.horizontal(&c));
                    }
                    for (i, p) in f.footprint(dem.geometry()).iter().enumerate() {
                        println!("{i} {:?}", p);
                    }
                    let mut o2 = o;
                    o2.obstacles.min_cluster_cells = 1;
                    let mut o3 = o;
                    o3.fall_line_azimuth_deg = Some(fl.azimuth_deg());
                    // find hulls near the point
                    let det_out = ingest(
                        &dem,
                        &rappel_geometry::terrain::ingest::IngestOptions {
                            unknown: rappel_geometry::terrain::ingest::UnknownPolicy::Ignore,
                            ..o
                        },
                    );
                    println!("{:?}", det_out.err());
                    panic!()
                }
            };
            let el = t.elapsed();
            println!(
                "tol {tol}: fall az {:.1} mean slope {:.1}; {:?} convexity merges {} time {:?}",
                out.fall_line.azimuth_deg(),
                out.fall_line.mean_slope_deg,
                out.summary(),
                out.convexity_merges,
                el
            );
            for (p, fp) in out.planes.iter().zip(&out.plane_fits) {
                println!(
                    "   y {:.1}..{:.1} slope {:.2} incl {:.2} rms {:.2} n {}",
                    p.y_bottom,
                    p.y_top,
                    p.slope_deg,
                    fp.inclination_deg(),
                    fp.rms_residual_m,
                    fp.cell_count
                );
            }
        }
        let out = ingest(&dem, &IngestOptions::default()).unwrap();
        let d = &out.detection;
        println!(
            "classes: ground {} foot {} raised {} sunken {} unknown {} pairs {}",
            d.count(CellClass::Ground),
            d.count(CellClass::Foot),
            d.count(CellClass::Raised),
            d.count(CellClass::Sunken),
            d.count(CellClass::Unknown),
            d.compatible_pairs
        );
        println!(
            "tether clusters sizes {:?}",
            d.tether_clusters
                .iter()
                .map(|c| c.len())
                .collect::<Vec<_>>()
        );
        println!(
            "robot clusters sizes {:?}",
            d.robot_clusters.iter().map(|c| c.len()).collect::<Vec<_>>()
        );
        println!(
            "map boundary verts {} area {:.0} obstacles areas {:?}",
            out.map.boundary.len(),
            out.map.boundary.area(),
            out.map
                .obstacles
                .iter()
                .map(|o| (o.area() * 10.0).round() / 10.0)
                .collect::<Vec<_>>()
        );
        println!("start {:?} goal {:?}", out.start, out.goal);
        // ascii map of classes
        let g = out.grid;
        for r in (0..g.nrows).step_by(2) {
            let line: String = (0..g.ncols)
                .map(|c| match d.classes[g.index(r, c)] {
                    CellClass::Ground => '.',
                    CellClass::Foot => 'f',
                    CellClass::Raised => '#',
                    CellClass::Sunken => 'o',
                    CellClass::Unknown => '?',
                })
                .collect();
            println!("{line}");
        }
    }
}
