//! `rappel dem FILE.(asc|tif) --out SCENARIO [--hmin M] [--hmax M] [--theta-max DEG] [--friction MU]
//! [--max-cells N] [--ptfo-friction LO[,HI]] [--svg OUT] [--convexity-svg OUT] [--sticking-svg OUT]
//! [--phi-svg OUT] [--hill-svg OUT] [--html OUT]`: turns a digital elevation model into a
//! planning scenario (planes, tether obstacles, optionally PTFOs, start and goal) and optionally
//! draws it over a hillshade.

use crate::output::{CliError, PictureArgs, print_report, refuse_clashing_outputs, write_file};
use rappel::dem::dem_scenario_with;
use rappel::dem_ptfo::{PtfoLabelOptions, label_ptfos};
use rappel::ptfo_spec::FrictionRange;
use rappel::scenario::Format;
use rappel::sticking_profile::sticking_profile;
use rappel::terrain::grid::DemLimits;
use rappel::terrain::ingest::IngestOptions;
use rappel_render::dem::{convexity_picture, dem_picture, hill_view, phi_chart, sticking_picture};
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
    #[arg(long, value_parser = crate::numbers::finite, value_name = "M", allow_negative_numbers = true)]
    hmin: Option<f64>,
    /// H_max: largest height difference between two cells of one obstacle, m.
    #[arg(long, value_parser = crate::numbers::finite, value_name = "M", allow_negative_numbers = true)]
    hmax: Option<f64>,
    /// theta_max: slope above which two cells belong to one obstacle, degrees.
    #[arg(long, value_parser = crate::numbers::finite, value_name = "DEG", allow_negative_numbers = true)]
    theta_max: Option<f64>,
    /// Wheel-terrain friction mu used to classify planes.
    #[arg(long, value_parser = crate::numbers::finite, value_name = "MU", allow_negative_numbers = true)]
    friction: Option<f64>,
    /// Work cap: refuse grids of more cells than this before reading their heights (default
    /// 16,777,216 = 2^24; at most 134,217,728 = 2^27). Ingestion takes about half a second and
    /// 55 MB per million cells.
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    max_cells: Option<usize>,
    /// Label convex patches as potential tether friction obstacles (thesis §3.4) with this
    /// tether-terrain friction: one coefficient, or a range `LO,HI`. Off when not given.
    #[arg(long, value_name = "LO[,HI]")]
    ptfo_friction: Option<String>,
    /// Flatness tolerance of the convexity test (PTFOs and --convexity-svg), 1/m (default 0.1
    /// over the cell size: a radius under ten cells).
    #[arg(long, value_parser = crate::numbers::finite, value_name = "K", allow_negative_numbers = true)]
    ptfo_curvature: Option<f64>,
    /// Fewest cells of a PTFO patch (default 4).
    #[arg(
        long,
        value_name = "N",
        requires = "ptfo_friction",
        allow_negative_numbers = true
    )]
    ptfo_min_cells: Option<usize>,
    /// Also label saddle cells convex along the fall line as PTFO cells (docs/friction.md).
    #[arg(long, requires = "ptfo_friction")]
    ptfo_saddles: bool,
    /// Draw the convexity map (thesis Figs. 3.11-3.12: convex, concave, saddle cells, saddles'
    /// convex directions) under the PTFO convexity tolerance to this SVG file.
    #[arg(long, value_name = "OUT")]
    convexity_svg: Option<PathBuf>,
    /// Draw where the planned tether may stick along its length (thesis Fig. 3.13; the shortest
    /// class `rappel plan` finds on the scenario, friction from --ptfo-friction's lower value).
    #[arg(long, value_name = "OUT", requires = "ptfo_friction")]
    sticking_svg: Option<PathBuf>,
    /// Chart |φ| along that tether against the friction bound (thesis Fig. 3.15).
    #[arg(long, value_name = "OUT", requires = "ptfo_friction")]
    phi_svg: Option<PathBuf>,
    /// Draw that tether draped over the DEM in 3D with its curve normals (red) and the surface
    /// normals (green) (thesis Fig. 3.14; an axonometric view at true vertical scale).
    #[arg(long, value_name = "OUT", requires = "ptfo_friction")]
    hill_svg: Option<PathBuf>,
    /// Print the ingestion summary as JSON.
    #[arg(long)]
    json: bool,
    /// The picture: the hillshade with planes and obstacles.
    #[command(flatten)]
    picture: PictureArgs,
}

/// `LO` or `LO,HI`: finite numbers ([`crate::numbers::numbers`]) forming a friction interval
/// (non-negative, `LO <= HI`: [`rappel::mechanics::friction::FrictionInterval::new`]).
fn friction_range(text: &str) -> Result<FrictionRange, CliError> {
    let count = text.split(',').count();
    if count > 2 {
        return Err(CliError(format!(
            "--ptfo-friction {text}: give LO or LO,HI (found {count} numbers)"
        )));
    }
    let v = crate::numbers::numbers("--ptfo-friction", text, count)?;
    let (lo, hi) = (v[0], v[count - 1]);
    rappel::mechanics::friction::FrictionInterval::new(lo, hi)
        .map_err(|e| CliError(format!("--ptfo-friction {text}: {e}")))?;
    Ok(FrictionRange { lo, hi })
}

/// Figs. 3.13 and 3.15 for the shortest class of the ingested scenario (before PTFOs are added).
fn draw_sticking(args: &Args, d: &rappel::dem::DemScenario) -> Result<(), CliError> {
    let mu = friction_range(args.ptfo_friction.as_deref().unwrap_or_default())?.lo;
    let report =
        rappel::plan::plan(&d.scenario, &rappel::plan::PlanOptions::default()).map_err(|e| {
            CliError(format!(
                "{}: planning the tether to draw: {e}",
                args.file.display()
            ))
        })?;
    let Some(class) = report.classes.first() else {
        return Err(CliError(format!(
            "{}: no class to draw the sticking profile of",
            args.file.display()
        )));
    };
    let samples = sticking_profile(
        d,
        &class.points,
        mu,
        STICKING_STEP_CELLS * d.grid.geometry().cell_x.min(d.grid.geometry().cell_y),
    );
    let stick = samples.iter().filter(|s| s.may_stick).count();
    let title = format!(
        "where the shortest tether may stick ({stick} of {} samples, mu {mu})",
        samples.len()
    );
    if let Some(out) = &args.sticking_svg {
        write_file(out, &sticking_picture(d, &class.points, &samples, &title))?;
    }
    if let Some(out) = &args.phi_svg {
        write_file(out, &phi_chart(&samples, mu, &title))?;
    }
    if let Some(out) = &args.hill_svg {
        let title = format!("{title}; tether normals red, surface normals green");
        let Some(svg) = hill_view(d, &samples, &title) else {
            return Err(CliError(format!(
                "{}: the shortest tether has no sample on known heights to draw in 3D",
                args.file.display()
            )));
        };
        write_file(out, &svg)?;
    }
    Ok(())
}

/// The sticking profile samples the tether every half cell.
const STICKING_STEP_CELLS: f64 = 0.5;

/// Runs `rappel dem`.
pub fn run(args: &Args) -> Result<(), CliError> {
    let mut outputs: Vec<(&str, &Path)> = vec![("--out", args.out.as_path())];
    outputs.extend(args.picture.outputs());
    for (flag, out) in [
        ("--convexity-svg", &args.convexity_svg),
        ("--sticking-svg", &args.sticking_svg),
        ("--phi-svg", &args.phi_svg),
        ("--hill-svg", &args.hill_svg),
    ] {
        if let Some(p) = out {
            outputs.push((flag, p.as_path()));
        }
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
    // Reading and ingesting a large grid takes seconds: say so on a terminal.
    let progress = crate::progress::Progress::spinner("dem");
    progress.message("reading and ingesting");
    let mut d = dem_scenario_with(&args.file, &options, &limits)?;
    progress.finish();
    if args.sticking_svg.is_some() || args.phi_svg.is_some() || args.hill_svg.is_some() {
        draw_sticking(args, &d)?;
    }
    let labels = match &args.ptfo_friction {
        None => None,
        Some(text) => {
            let mut opts = PtfoLabelOptions::with_friction(friction_range(text)?);
            if let Some(k) = args.ptfo_curvature {
                opts.min_curvature = Some(k);
            }
            opts.saddles = args.ptfo_saddles;
            if let Some(n) = args.ptfo_min_cells {
                opts.min_cells = n;
            }
            Some(label_ptfos(&mut d, &opts).map_err(|e| CliError(e.to_string()))?)
        }
    };
    d.scenario.validate().map_err(|e| {
        CliError(format!(
            "{}: the ingested scenario is invalid: {e}",
            args.file.display()
        ))
    })?;
    if args.picture.wanted() {
        let title = format!("rappel dem {}", args.file.display());
        args.picture.write(&dem_picture(&d, &title), &title)?;
    }
    if let Some(out) = &args.convexity_svg {
        let title = format!("convexity of {}", args.file.display());
        write_file(out, &convexity_picture(&d, args.ptfo_curvature, &title))?;
    }
    // The DEM path relative to the scenario file, so the two can be read from anywhere.
    if let Some(g) = &mut d.scenario.georeference {
        g.dem = rappel::georeference::dem_relative_to(&args.file, &args.out);
    }
    d.scenario.save(&args.out)?;
    let s = d.summary();
    if args.json {
        return print_report(&d.report(&args.file, &args.out, labels));
    }
    crate::output::outln!("dem                {}", args.file.display());
    crate::output::outln!("scenario           {}", args.out.display());
    crate::output::outln!(
        "fall line          azimuth {:.1} deg",
        d.ingested.frame.fall_line_azimuth_deg()
    );
    for (i, (p, class)) in d.classified_planes().enumerate() {
        crate::output::outln!(
            "plane {i}            {:.2} deg, y {:.1} .. {:.1} m, {}",
            p.slope_deg,
            p.y_bottom,
            p.y_top,
            class.label()
        );
    }
    crate::output::outln!(
        "tether obstacles   {} (from {} clusters)",
        s.tether_obstacles,
        s.tether_clusters
    );
    crate::output::outln!("robot obstacles    {}", s.robot_obstacles);
    match &labels {
        None => {
            crate::output::outln!(
                "PTFOs              not labelled (give --ptfo-friction to label them)"
            )
        }
        Some(l) => {
            crate::output::outln!(
                "PTFOs              {} (from {} convex patches of {} convex cells{})",
                l.ptfos,
                l.patches,
                l.convex_cells,
                if args.ptfo_saddles {
                    format!(
                        " and {} saddle cells convex along the fall line",
                        l.saddle_cells
                    )
                } else {
                    String::new()
                }
            );
            for why in &l.dropped {
                crate::output::outln!("  dropped          {why}");
            }
        }
    }
    crate::output::outln!("unknown regions    {}", s.unknown_regions);
    crate::output::outln!(
        "start              ({:.2}, {:.2})",
        d.scenario.start.x,
        d.scenario.start.y
    );
    crate::output::outln!(
        "goal               ({:.2}, {:.2})",
        d.scenario.goal.x,
        d.scenario.goal.y
    );
    Ok(())
}
