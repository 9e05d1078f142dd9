//! `rappel dem FILE.(asc|tif) --out SCENARIO [--hmin M] [--hmax M] [--theta-max DEG] [--friction MU]
//! [--max-cells N] [--svg OUT]`: turns a digital elevation model into a planning scenario (planes, tether
//! obstacles, start and goal) and optionally draws it over a hillshade.

use crate::output::{CliError, print_json, refuse_clashing_outputs, write_file};
use rappel::dem::{dem_picture, dem_scenario_with};
use rappel::scenario::Format;
use rappel::terrain::dem::DemLimits;
use rappel::terrain::ingest::IngestOptions;
use std::path::{Path, PathBuf};

/// Arguments of `rappel dem`.
#[derive(clap::Args)]
pub struct Args {
    /// The elevation model: ESRI ASCII grid (.asc) or single-band GeoTIFF (.tif, .tiff).
    file: PathBuf,
    /// Output scenario (.ron or .json).
    #[arg(long)]
    out: PathBuf,
    /// H_min: smallest height difference that makes an obstacle, m.
    #[arg(long, value_name = "M")]
    hmin: Option<f64>,
    /// H_max: largest height difference between two cells of one obstacle, m.
    #[arg(long, value_name = "M")]
    hmax: Option<f64>,
    /// theta_max: slope above which two cells belong to one obstacle, degrees.
    #[arg(long, value_name = "DEG")]
    theta_max: Option<f64>,
    /// Wheel-terrain friction mu used to classify planes.
    #[arg(long, value_name = "MU")]
    friction: Option<f64>,
    /// Work cap: refuse grids of more cells than this before reading their heights (default
    /// 16,777,216 = 2^24; at most 134,217,728 = 2^27). Ingestion takes about a second per million
    /// cells.
    #[arg(long, value_name = "N")]
    max_cells: Option<usize>,
    /// Print the ingestion summary as JSON.
    #[arg(long)]
    json: bool,
    /// Draw the hillshade with planes and obstacles to this SVG file.
    #[arg(long, value_name = "OUT")]
    svg: Option<PathBuf>,
}

/// Runs `rappel dem`.
pub fn run(args: &Args) -> Result<(), CliError> {
    let mut outputs: Vec<(&str, &Path)> = vec![("--out", args.out.as_path())];
    if let Some(svg) = &args.svg {
        outputs.push(("--svg", svg.as_path()));
    }
    refuse_clashing_outputs(&outputs, &[&args.file])?;
    if Format::of_path(&args.out).is_none() {
        return Err(CliError(format!(
            "{}: unknown scenario format; use a .ron or .json file",
            args.out.display()
        )));
    }
    let mut options = IngestOptions::default();
    if let Some(v) = args.hmin {
        options.obstacles.h_min_m = v;
    }
    if let Some(v) = args.hmax {
        options.obstacles.h_max_m = v;
    }
    if let Some(v) = args.theta_max {
        options.obstacles.theta_max_deg = v;
    }
    if let Some(v) = args.friction {
        options.friction = v;
    }
    let limits = match args.max_cells {
        None => DemLimits::default(),
        Some(n) => {
            DemLimits::with_max_cells(n).map_err(|e| CliError(format!("--max-cells: {e}")))?
        }
    };
    let d = dem_scenario_with(&args.file, &options, &limits)?;
    d.scenario.validate().map_err(|e| {
        CliError(format!(
            "{}: the ingested scenario is invalid: {e}",
            args.file.display()
        ))
    })?;
    if let Some(out) = &args.svg {
        write_file(
            out,
            &dem_picture(&d, &format!("rappel dem {}", args.file.display())),
        )?;
    }
    d.scenario.save(&args.out)?;
    let s = d.summary();
    if args.json {
        return print_json(&s);
    }
    crate::outln!("dem                {}", args.file.display());
    crate::outln!("scenario           {}", args.out.display());
    crate::outln!(
        "fall line          azimuth {:.1} deg",
        d.ingested.frame.fall_line_azimuth_deg()
    );
    for (i, (p, class)) in d
        .scenario
        .terrain
        .planes
        .iter()
        .zip(&d.ingested.plane_classes)
        .enumerate()
    {
        crate::outln!(
            "plane {i}            {:.2} deg, y {:.1} .. {:.1} m, {:?}",
            p.slope_deg,
            p.y_bottom,
            p.y_top,
            class
        );
    }
    crate::outln!(
        "tether obstacles   {} (from {} clusters)",
        s.tether_obstacles,
        s.tether_clusters
    );
    crate::outln!("robot obstacles    {}", s.robot_obstacles);
    crate::outln!("unknown regions    {}", s.unknown_regions);
    crate::outln!(
        "start              ({:.2}, {:.2})",
        d.scenario.start.x,
        d.scenario.start.y
    );
    crate::outln!(
        "goal               ({:.2}, {:.2})",
        d.scenario.goal.x,
        d.scenario.goal.y
    );
    Ok(())
}
