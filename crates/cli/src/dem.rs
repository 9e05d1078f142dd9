//! `rappel dem FILE.(asc|tif|obj|ply|stl|las|laz) --out SCENARIO [--cell M] [--statistic max|mean]
//! [--crs CRS] [--grid-out OUT.tif]
//! [--hmin M] [--hmax M] [--theta-max DEG] [--friction MU] [--max-cells N]
//! [--ptfo-friction LO[,HI]] [--geotiff OUT.tif] [--svg OUT] [--convexity-svg OUT]
//! [--sticking-svg OUT] [--phi-svg OUT] [--hill-svg OUT] [--html OUT]`: turns a digital
//! elevation model, or a terrain mesh or lidar point cloud gridded to one (`--cell`), into a
//! planning scenario
//! (planes, tether obstacles, optionally PTFOs, start and goal) and optionally draws it over a
//! hillshade. `--geotiff` writes the obstacle mask and the PTFO labels in the DEM's grid and
//! CRS ([`rappel_render::raster_export::dem_geotiff`]). The CRS recorded is printed (and is the
//! report's `crs`); GeoKeys read but not used are printed as warnings.

use crate::gis_out::GeoTiffOut;
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
    /// The elevation model: ESRI ASCII grid (.asc) or single-band GeoTIFF (.tif, .tiff); or a
    /// terrain mesh (.obj, .ply, .stl; x east, y north, z up) or a lidar point cloud (.las,
    /// .laz), gridded with --cell.
    file: PathBuf,
    /// Output scenario (.ron or .json).
    #[arg(long)]
    out: PathBuf,
    /// A mesh's or point cloud's grid: cell size, m. A mesh's cell takes the highest surface at
    /// its centre, a point cloud's the --statistic of its points; cells without are unknown.
    /// Required for a mesh or a point cloud.
    #[arg(long, value_parser = crate::numbers::finite, value_name = "M", allow_negative_numbers = true)]
    cell: Option<f64>,
    /// How a point cloud's cell height is made from its points: `max` (the highest, default)
    /// or `mean`.
    #[arg(long, value_name = "max|mean")]
    statistic: Option<String>,
    /// The CRS of a mesh, or of a point cloud whose file declares none: `EPSG:N`, a WKT text, or
    /// a .prj file holding one (without it results are in a local grid and say so).
    #[arg(long, value_name = "CRS")]
    crs: Option<String>,
    /// Where a mesh's or point cloud's height grid is written as a GeoTIFF (the scenario's DEM;
    /// default: the scenario's path with `.dem.tif`).
    #[arg(long, value_name = "OUT.tif")]
    grid_out: Option<PathBuf>,
    /// Also write the detection as a GeoTIFF in the DEM's grid and CRS: band 1 the obstacle
    /// mask (0 ground, 1 an obstacle's foot, 2 raised: tether obstacle, 3 sunken: robot
    /// obstacle), band 2 the PTFO labels (k on the cells of PTFO k, 0 elsewhere; no value
    /// without --ptfo-friction); -9999 where heights are unknown.
    #[arg(long, value_name = "OUT.tif")]
    geotiff: Option<PathBuf>,
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

/// What `rappel dem` reads, by extension.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Input {
    /// An elevation model (`.asc`, `.tif`; the DEM readers judge anything else).
    Dem,
    /// A mesh `rappel settle` reads (`.obj`, `.ply`, `.stl`).
    Mesh,
    /// A lidar point cloud (`.las`, `.laz`).
    PointCloud,
}

impl Input {
    fn of(path: &Path) -> Input {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("obj" | "ply" | "stl") => Input::Mesh,
            Some("las" | "laz") => Input::PointCloud,
            _ => Input::Dem,
        }
    }
}

/// The `--crs` text: `EPSG:N`, a WKT 1 text, or a `.prj` file holding one.
fn crs_arg(text: &str) -> Result<String, CliError> {
    let t = text.trim();
    let bad = |why: &str| CliError(format!("--crs {t}: {why}"));
    let t = if t.to_ascii_lowercase().ends_with(".prj") {
        let body =
            rappel::terrain::input::read_text(Path::new(t)).map_err(|e| bad(&e.to_string()))?;
        body.trim().to_string()
    } else {
        t.to_string()
    };
    if t.get(..5).is_some_and(|p| p.eq_ignore_ascii_case("EPSG:")) {
        return match t[5..].trim().parse::<u32>() {
            Ok(n) if n > 0 => Ok(format!("EPSG:{n}")),
            _ => Err(bad("the EPSG code is not a positive integer")),
        };
    }
    let root = t.split('[').next().unwrap_or_default().trim();
    if !t.ends_with(']') || !["PROJCS", "GEOGCS", "LOCAL_CS"].contains(&root) {
        return Err(bad(
            "not EPSG:N, a WKT 1 PROJCS/GEOGCS/LOCAL_CS text or a .prj file holding one",
        ));
    }
    Ok(t)
}

/// The scenario's path with `.dem.tif` in place of its extension.
fn default_grid_out(out: &Path) -> PathBuf {
    out.with_extension("dem.tif")
}

/// Reads the input: a DEM as it is, or a mesh or point cloud gridded to `--cell` and written as
/// a GeoTIFF (`--grid-out`) that becomes the scenario's DEM.
fn read_input(
    args: &Args,
    options: &IngestOptions,
    limits: &DemLimits,
    grid_out: Option<&GeoTiffOut>,
) -> Result<rappel::dem::DemScenario, CliError> {
    let input = Input::of(&args.file);
    if input != Input::PointCloud && args.statistic.is_some() {
        return Err(CliError(format!(
            "--statistic: {} is not a point cloud (.las, .laz)",
            args.file.display()
        )));
    }
    let (Some(grid_out), false) = (grid_out, input == Input::Dem) else {
        for (flag, given) in [
            ("--cell", args.cell.is_some()),
            ("--crs", args.crs.is_some()),
        ] {
            if given {
                return Err(CliError(format!(
                    "{flag}: {} is an elevation model, read in its own grid and CRS; {flag} is for meshes (.obj, .ply, .stl) and point clouds (.las, .laz)",
                    args.file.display()
                )));
            }
        }
        return Ok(dem_scenario_with(&args.file, options, limits)?);
    };
    let Some(cell) = args.cell else {
        return Err(CliError(format!(
            "{}: a mesh or point cloud is gridded to heights: give the cell size with --cell M",
            args.file.display()
        )));
    };
    let crs = args.crs.as_deref().map(crs_arg).transpose()?;
    let d = match input {
        Input::PointCloud => {
            let text = args.statistic.as_deref().unwrap_or("max");
            let statistic = rappel::terrain::point_cloud::Statistic::parse(text)
                .ok_or_else(|| CliError(format!("--statistic {text}: use max or mean")))?;
            rappel::dem::point_cloud_dem_scenario(&args.file, cell, statistic, crs, options, limits)
        }
        _ => rappel::dem::mesh_dem_scenario(&args.file, cell, crs, options, limits),
    }
    .map_err(|e| CliError(e.to_string()))?;
    let crs = d
        .scenario
        .georeference
        .as_ref()
        .and_then(|g| g.crs.as_deref())
        .and_then(rappel::terrain::crs::Crs::parse);
    let g = d.grid.geometry();
    let heights: Vec<f32> = d.grid.heights().iter().map(|&h| h as f32).collect();
    let image = rappel::terrain::geotiff_writer::geotiff_image(
        g,
        &[&heights],
        rappel_render::raster_export::NODATA,
        crs.as_ref(),
    )
    .map_err(|e| CliError(format!("{}: {e}", grid_out.context())))?;
    grid_out.write(
        &image,
        &format!(
            "the height grid, {} x {} cells of {cell} m (float32)",
            g.ncols, g.nrows
        ),
    )?;
    Ok(d)
}

/// Runs `rappel dem`.
pub fn run(args: &Args) -> Result<(), CliError> {
    let geotiff = args
        .geotiff
        .as_ref()
        .map(|p| GeoTiffOut::new("--geotiff", p));
    let grid_out = (Input::of(&args.file) != Input::Dem).then(|| {
        let p = args
            .grid_out
            .clone()
            .unwrap_or_else(|| default_grid_out(&args.out));
        GeoTiffOut::new("--grid-out", &p)
    });
    if args.grid_out.is_some() && grid_out.is_none() {
        return Err(CliError(format!(
            "--grid-out: {} is an elevation model already; --grid-out is for meshes and point clouds",
            args.file.display()
        )));
    }
    let mut outputs: Vec<(&str, &Path)> = vec![("--out", args.out.as_path())];
    for g in geotiff.iter().chain(grid_out.iter()) {
        outputs.extend(g.outputs());
    }
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
    let d = read_input(args, &options, &limits, grid_out.as_ref());
    progress.finish();
    let mut d = d?;
    for w in &d.warnings {
        eprintln!("warning: {w}");
    }
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
    if let Some(out) = &geotiff {
        let image = rappel_render::raster_export::dem_geotiff(&d, labels.is_some())
            .map_err(|e| CliError(format!("{}: {e}", out.context())))?;
        out.write(
            &image,
            "obstacle mask (band 1) and PTFO labels (band 2) in the DEM's grid",
        )?;
    }
    // The DEM path relative to the scenario file, so the two can be read from anywhere; a
    // mesh's or point cloud's DEM is the height grid written from it.
    let dem_file = match (&grid_out, &args.grid_out) {
        (None, _) => args.file.clone(),
        (Some(_), Some(p)) => p.clone(),
        (Some(_), None) => default_grid_out(&args.out),
    };
    if let Some(g) = &mut d.scenario.georeference {
        g.dem = rappel::georeference::dem_relative_to(&dem_file, &args.out);
    }
    d.scenario.save(&args.out)?;
    let s = d.summary();
    if args.json {
        return print_report(&d.report(&args.file, &args.out, labels));
    }
    crate::output::outln!("dem                {}", args.file.display());
    crate::output::outln!("scenario           {}", args.out.display());
    crate::output::outln!("crs                {}", d.crs_written());
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
