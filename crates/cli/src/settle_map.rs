//! `rappel settle-map GROUND [--x MIN,MAX] [--y MIN,MAX] [--step M] [--yaw DEG] [--start X,Y]
//! (--root X,Y,Z | --test N) [--robot axel|four-wheel] [--field RES] [--time-limit SECONDS]
//! [--svg OUT] [--html OUT] [--json]`: a stability map of settled poses on 3D ground like Paton's Fig. 8, of Axel or of the
//! rigid four-wheel rover. Every grid cell is settled, its anchor history is predicted from the
//! start outward (Paton Alg. 1, [`rappel::planners::rover::stability_map`]) along the robot's tether end and the
//! stability QP is solved with the tether from the last predicted anchor (Axel: boom inline or in
//! contact; the four-wheel rover: the tether fixed to its body).
//! `--field RES`: settling and anchor prediction read the sparse distance field at `RES` metres
//! instead of parry's exact distances (Paton's use of the field, [`crate::field_arg`]).
//! `--time-limit SECONDS` bounds the whole map (the distance field's build included) and Ctrl-C
//! stops it ([`crate::stop`]): the map is then partial, the cells not computed are failed with
//! "not computed: the map stopped at ...", the report's `stopped_by` names the condition, the
//! picture shows what was computed, and the exit code is 1.
//! `--geotiff OUT.tif` writes the verdicts and margins in the map's own grid (one cell per pose,
//! centred on its ground point), in the DEM's CRS when the ground is an elevation model, else in
//! the scene's or mesh's local frame, named so ([`rappel_render::raster_export::settle_map_geotiff`]).
//! Exit 0 when the whole map was computed, 1 when it was stopped; bad input exits 2.

use crate::field_arg::FieldArg;
use crate::gis_out::GeoTiffOut;
use crate::output::{Answer, CliError, PictureArgs, print_report, refuse_clashing_outputs};
use rappel::nalgebra::Point3;
use rappel::planners::anchor_prediction::AnchorHistory;
use rappel::planners::rover::stability_map::{
    AxelMap, FourWheelMap, MapSpec, UNITS_PER_CELL, stability_map_observed,
};
use rappel::settle::SettleRobot;
use rappel::settle::{load_ground, load_scene};
use rappel_render::settle_map::map_svg;
use std::path::PathBuf;

/// Arguments of `rappel settle-map`.
#[derive(clap::Args)]
pub struct Args {
    /// The ground: a Paton scene (.ron, fixtures/paton/) or an elevation model (.asc, .tif).
    file: PathBuf,
    /// Map extent along x, `MIN,MAX` metres (default for a scene: the ledge top to 1 m past the
    /// slope's foot).
    #[arg(long, value_name = "MIN,MAX", allow_hyphen_values = true)]
    x: Option<String>,
    /// Map extent along y, `MIN,MAX` metres (default for a scene: the ledge's length).
    #[arg(long, value_name = "MIN,MAX", allow_hyphen_values = true)]
    y: Option<String>,
    /// Grid spacing, metres. The map holds at most 1,000,000 cells; each costs about 0.06 ms of
    /// one core (settling, anchor prediction, the stability QP), so a 1,000 x 1,000 map takes
    /// about half a minute on two cores (a bar shows the progress on a terminal; --time-limit
    /// bounds the run and keeps a partial map).
    #[arg(long, value_parser = crate::numbers::finite, default_value_t = 0.25, allow_negative_numbers = true)]
    step: f64,
    /// Heading of every pose: degrees counter-clockwise from +x (default: down a scene's slope).
    #[arg(
        long,
        value_parser = crate::numbers::finite,
        value_name = "DEG",
        allow_negative_numbers = true,
        default_value_t = 0.0
    )]
    yaw: f64,
    /// The start's ground point `X,Y` (default: the scene's start).
    #[arg(long, value_name = "X,Y", allow_hyphen_values = true)]
    start: Option<String>,
    /// The root anchor `X,Y,Z` (world).
    #[arg(
        long,
        value_name = "X,Y,Z",
        allow_hyphen_values = true,
        conflicts_with = "test"
    )]
    root: Option<String>,
    /// The root anchor of a scene's test N (1: behind the start, 2: in front).
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    test: Option<usize>,
    /// The robot: `axel` (both boom configurations, the boom pivot as the tether end of anchor
    /// prediction) or `four-wheel` (the rigid rover, its tether exit on the body as the tether
    /// end, one verdict without a boom).
    #[arg(long, value_name = "NAME", default_value = "axel")]
    robot: String,
    #[command(flatten)]
    field: FieldArg,
    #[command(flatten)]
    picture: PictureArgs,
    /// The time limit of the whole map (Ctrl-C stops it too): a partial map is reported.
    #[command(flatten)]
    time_limit: crate::stop::TimeLimitArg,
    /// Print the map as JSON.
    #[arg(long)]
    json: bool,
    /// Also write the map as a GeoTIFF, one cell per pose centred on its ground point: band 1
    /// the verdict (1 stable, 0 not), band 2 the best margin of a stable pose, -9999 where no
    /// pose was assessed; in the DEM's CRS for an elevation model, else in the ground's local
    /// frame (named so in the file).
    #[arg(long, value_name = "OUT.tif")]
    geotiff: Option<PathBuf>,
}

/// The CRS of a settle-map's ground (`--geotiff`): an elevation model's own (or a local grid
/// saying it declared none; its unused GeoKeys printed as warnings), else the local frame of a
/// Paton scene or a mesh file.
fn ground_crs(file: &std::path::Path) -> Result<rappel::terrain::crs::Crs, CliError> {
    use rappel::terrain::crs::{Crs, UNKNOWN_CRS_NAME};
    let ext = file
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    Ok(match ext.as_deref() {
        Some("asc" | "tif" | "tiff") => {
            let c = rappel::terrain::dem::read_dem_crs(file)
                .map_err(|e| CliError(format!("--geotiff: {e}")))?;
            for w in &c.ignored {
                eprintln!("warning: {}: {w}", file.display());
            }
            c.crs
                .as_deref()
                .and_then(Crs::parse)
                .unwrap_or_else(|| Crs::local(UNKNOWN_CRS_NAME))
        }
        Some("ron") => Crs::local(rappel_render::raster_export::SCENE_FRAME_NAME),
        _ => Crs::local(rappel_render::raster_export::MESH_FRAME_NAME),
    })
}

/// Runs `rappel settle-map`.
pub fn run(args: &Args) -> Result<Answer, CliError> {
    let robot = crate::settle::robot(&args.robot)?;
    let stop = crate::stop::condition(
        rappel::planners::budget::ExpansionBudget::Auto,
        &args.time_limit,
    )?;
    let geotiff = args
        .geotiff
        .as_ref()
        .map(|p| GeoTiffOut::new("--geotiff", p));
    let mut outputs = args.picture.outputs();
    if let Some(g) = &geotiff {
        outputs.extend(g.outputs());
    }
    refuse_clashing_outputs(&outputs, &[&args.file])?;
    let crs = geotiff
        .as_ref()
        .map(|_| ground_crs(&args.file))
        .transpose()?;
    let ground = load_ground(&args.file).map_err(|e| CliError(e.to_string()))?;
    let is_scene = args
        .file
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("ron"));
    let scene = if is_scene {
        Some(load_scene(&args.file).map_err(|e| CliError(e.to_string()))?)
    } else {
        None
    };
    let need = |flag: &str| CliError(format!("{flag} is required for an elevation model"));
    let pair = |flag: &str,
                v: &Option<String>,
                dflt: Option<(f64, f64)>|
     -> Result<(f64, f64), CliError> {
        match v {
            Some(t) => {
                let v = crate::numbers::numbers(flag, t, 2)?;
                Ok((v[0], v[1]))
            }
            None => dflt.ok_or_else(|| need(flag)),
        }
    };
    let x = pair(
        "--x",
        &args.x,
        scene.as_ref().map(|s| (-s.width, s.slope_foot_x() + 1.0)),
    )?;
    let y = pair(
        "--y",
        &args.y,
        scene.as_ref().map(|s| (-0.5 * s.length, 0.5 * s.length)),
    )?;
    let start = pair(
        "--start",
        &args.start,
        scene.as_ref().map(|s| (s.start().x, s.start().y)),
    )?;
    let root = match (&args.root, args.test, &scene) {
        (Some(t), _, _) => {
            let v = crate::numbers::numbers("--root", t, 3)?;
            Point3::new(v[0], v[1], v[2])
        }
        (None, Some(n), Some(s)) => {
            let a = s.anchor_points();
            *n.checked_sub(1).and_then(|k| a.get(k)).ok_or_else(|| {
                CliError(format!("--test {n}: the scene has tests 1 to {}", a.len()))
            })?
        }
        (None, Some(_), None) => {
            return Err(CliError(
                "--test needs a Paton scene (.ron); give --root".into(),
            ));
        }
        (None, None, _) => {
            return Err(CliError(
                "give the root anchor: --root X,Y,Z or --test N".into(),
            ));
        }
    };
    let root = AnchorHistory::new(root).map_err(|e| CliError(e.to_string()))?;
    let spec = MapSpec {
        x,
        y,
        step: args.step,
        yaw_deg: args.yaw,
        start: [start.0, start.1],
    };
    // Thousands of settled poses take seconds: say so on a terminal.
    let stop = stop.started();
    // A bar over the work units (each cell settled, given its anchors, checked).
    let (fx, fy) = spec.size();
    let units = (UNITS_PER_CELL as f64 * fx * fy).min(u64::MAX as f64) as u64;
    let progress = crate::progress::Progress::with(units, "settle-map", Default::default());
    let tick = || progress.inc(1);
    let map = args.field.distances(&ground).and_then(|d| {
        match robot {
            SettleRobot::Axel => {
                stability_map_observed(&AxelMap, &ground, &d, &root, &spec, &stop, &tick)
            }
            SettleRobot::FourWheel => {
                stability_map_observed(&FourWheelMap, &ground, &d, &root, &spec, &stop, &tick)
            }
        }
        .map_err(|e| CliError(e.to_string()))
    });
    progress.finish();
    let map = map?;
    crate::stop::say(map.stopped_by);
    if args.picture.wanted() {
        args.picture
            .write(&map_svg(&map, &ground), "rappel settle-map")?;
    }
    if let (Some(out), Some(crs)) = (&geotiff, &crs) {
        let image = rappel_render::raster_export::settle_map_geotiff(&map, crs)
            .map_err(|e| CliError(format!("{}: {e}", out.context())))?;
        out.write(
            &image,
            &format!(
                "verdict and margin, {} x {} poses of {} m",
                map.nx, map.ny, spec.step
            ),
        )?;
    }
    if args.json {
        print_report(&map)?;
    } else {
        crate::output::outln!(
            "stability map {} x {} cells of {} m: {} stable, {} unstable, {} not settled or unreached",
            map.nx,
            map.ny,
            spec.step,
            map.stable,
            map.unstable,
            map.failed
        );
        let best = map
            .cells
            .iter()
            .filter_map(|c| c.pose.as_ref())
            .map(|p| p.margin)
            .fold(0.0f64, f64::max);
        crate::output::outln!("best margin  {best:.3}");
        if let Some(r) = map.stopped_by {
            crate::output::outln!("stopped      the map stopped at {r}: a partial map");
        }
    }
    Ok(if map.stopped_by.is_some() {
        Answer::No
    } else {
        Answer::Yes
    })
}
