//! Results exported for other tools (issues 16, 34) as FlatGeobuf, GeoJSON or CSV, all through
//! one writer per format over [`Feature`]s: a plan (the chosen class's taut tether, anchors,
//! waypoints, ascent and descent, and every other class's tether: [`plan_features`]) and an
//! online run (the path travelled, the final ascent, one point per timeline event:
//! [`online_features`]).
//! For scenarios made from a DEM ([`rappel::georeference`]) coordinates are the DEM's own
//! `(east, north)`, so a plan lays over the DEM in a GIS; otherwise they are planning-frame
//! coordinates, and the file says so.
//!
//! FlatGeobuf (`.fgb`, the format that carries **any** CRS): one layer (`rappel_plan`,
//! `rappel_online`) of mixed `LineString` and `Point` features with columns `layer`, `class`,
//! and the points' properties (anchors' `index`, `psi_deg`, `obstacle`; events' `step`,
//! `change`, `case`, `decision`, `travelled_m`, `backtracked_m`); the CRS in the header: `EPSG` and its code, or the DEM's WKT, or a
//! `LOCAL_CS` naming the planning frame or "CRS unknown" ([`export_crs`]). GDAL and QGIS read it.
//!
//! GeoJSON: a `FeatureCollection` of the same features and properties. RFC 7946 means WGS 84
//! longitude/latitude; projected DEM coordinates are declared with the 2008 `crs` member when the
//! DEM names an EPSG code (QGIS and GDAL read it), and otherwise with a foreign member
//! `rappel_crs` holding the DEM's WKT (GDAL ignores it: use the FlatGeobuf export), and a
//! `rappel_note` saying so. CSV: one row per vertex, `layer,class,index,x,y,psi_deg,obstacle` and,
//! when georeferenced, `east,north`; `class` is the integer rank, anchors fill `psi_deg` and
//! `obstacle` (events' other properties are in the FlatGeobuf and GeoJSON exports).

use flatgeobuf::{ColumnType, FgbCrs, FgbWriter, FgbWriterOptions, GeometryType};
use geozero::{ColumnValue, GeomProcessor, GeozeroGeometry, PropertyProcessor};
use nalgebra::Point2;
use rappel::georeference::Georeference;
use rappel::plan::PlanReport;
use rappel::planners::online::SimulationReport;
use rappel_terrain::crs::{Crs, PLANNING_FRAME_NAME, UNKNOWN_CRS_NAME};
use serde_json::{Map as JsonMap, Value, json};
use std::fmt::Write;

/// An export format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ExportFormat {
    /// FlatGeobuf (`.fgb`): any CRS.
    FlatGeobuf,
    /// GeoJSON (`.geojson`).
    GeoJson,
    /// Comma-separated values (`.csv`).
    Csv,
}

impl ExportFormat {
    /// The format of an output path by its extension (`.fgb`, `.geojson` or `.csv`, any case).
    pub fn of_path(path: &std::path::Path) -> Option<ExportFormat> {
        match path.extension()?.to_str()?.to_ascii_lowercase().as_str() {
            "fgb" => Some(ExportFormat::FlatGeobuf),
            "geojson" => Some(ExportFormat::GeoJson),
            "csv" => Some(ExportFormat::Csv),
            _ => None,
        }
    }
}

/// Why an export could not be built.
#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    /// The FlatGeobuf writer failed.
    #[error("FlatGeobuf: {0}")]
    FlatGeobuf(String),
}

/// The CRS an export is written in: the DEM's (`EPSG:n` or its WKT), a local grid named
/// [`UNKNOWN_CRS_NAME`] when the DEM declared none, or the planning frame
/// ([`PLANNING_FRAME_NAME`]) for a scenario not made from a DEM.
pub fn export_crs(geo: Option<&Georeference>) -> Crs {
    match geo {
        None => Crs::local(PLANNING_FRAME_NAME),
        Some(g) => g
            .crs
            .as_deref()
            .and_then(Crs::parse)
            .unwrap_or_else(|| Crs::local(UNKNOWN_CRS_NAME)),
    }
}

/// What a feature is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Geometry {
    /// A polyline.
    Line,
    /// One point per entry.
    Points,
}

/// A named set of planning-frame points with their properties.
#[derive(Debug, Clone, PartialEq)]
pub struct Feature {
    /// `tether`, `anchor`, `waypoint`, `ascent`, `descent`, `start`, `goal`; `travelled`,
    /// `event` (online runs).
    pub layer: &'static str,
    /// The class's rank (1 = shortest), when it belongs to one.
    pub class: Option<usize>,
    /// Line or points.
    pub geometry: Geometry,
    /// The points, planning frame.
    pub points: Vec<Point2<f64>>,
    /// Extra properties per point (points features only; may be empty).
    pub properties: Vec<JsonMap<String, Value>>,
}

fn line(layer: &'static str, class: Option<usize>, points: &[Point2<f64>]) -> Feature {
    Feature {
        layer,
        class,
        geometry: Geometry::Line,
        points: points.to_vec(),
        properties: Vec::new(),
    }
}

/// The features of a plan: every class's tether, the chosen class's anchors and waypoints, the
/// chosen pair's ascent and descent, the start and the goal.
///
/// ```
/// use rappel_render::export::{plan_features, Geometry};
/// use rappel::plan::{plan, PlanOptions};
/// use rappel::scenario::Scenario;
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/thesis-fig-2-7.ron");
/// let report = plan(&Scenario::load(path).unwrap(), &PlanOptions::default()).unwrap();
/// let f = plan_features(&report);
/// assert!(f.iter().any(|f| f.layer == "descent" && f.geometry == Geometry::Line));
/// assert_eq!(f.iter().filter(|f| f.layer == "tether").count(), report.classes.len());
/// ```
pub fn plan_features(report: &PlanReport) -> Vec<Feature> {
    let mut out: Vec<Feature> = report
        .classes
        .iter()
        .map(|c| line("tether", Some(c.rank), &c.points))
        .collect();
    if let Some(pair) = &report.outcome.chosen {
        if let Some(c) = report.classes.iter().find(|c| c.rank == pair.rank) {
            out.push(Feature {
                layer: "anchor",
                class: Some(c.rank),
                geometry: Geometry::Points,
                points: c.anchors.iter().map(|a| a.point).collect(),
                properties: c
                    .anchors
                    .iter()
                    .map(|a| {
                        let mut m = JsonMap::new();
                        m.insert("index".into(), json!(a.index));
                        m.insert("psi_deg".into(), json!(a.psi_deg));
                        m.insert("obstacle".into(), json!(a.obstacle));
                        m
                    })
                    .collect(),
            });
            out.push(Feature {
                layer: "waypoint",
                class: Some(c.rank),
                geometry: Geometry::Points,
                points: c.waypoints.clone(),
                properties: Vec::new(),
            });
        }
        out.push(line("ascent", Some(pair.rank), &pair.ascent));
        out.push(line("descent", Some(pair.rank), &pair.descent));
    }
    out.extend(end_points(report.setting.start, report.setting.goal));
    out
}

/// The features of an online run (`rappel online`): the path travelled, the final selected
/// ascent (goal to start, when a class was selected), one point per timeline event where the
/// robot was (properties `step`, `change`, `case`, `decision`, `travelled_m`,
/// `backtracked_m`), and the start and the goal.
///
/// ```
/// use rappel::planners::online::SimulationOptions;
/// use rappel::scenario::Scenario;
/// use rappel_render::export::online_features;
/// let prior = Scenario::from_ron_str(r#"(
///     map: (boundary: [(0.0, 0.0), (20.0, 0.0), (20.0, 40.0), (0.0, 40.0)], obstacles: []),
///     start: (10.0, 38.0), goal: (10.0, 2.0))"#).unwrap();
/// let mut truth = prior.clone();
/// truth.map.obstacles.push(rappel::geometry::polygon::Polygon::rectangle(9.0, 20.0, 2.0, 1.0));
/// let run = rappel::online::run(&prior, &truth, &SimulationOptions::default(), &mut |_, _| {}).unwrap();
/// let f = online_features(&run.report, prior.start, prior.goal);
/// assert_eq!(f.iter().filter(|f| f.layer == "event").map(|f| f.points.len()).sum::<usize>(), run.report.timeline.len());
/// ```
pub fn online_features(
    report: &SimulationReport,
    start: Point2<f64>,
    goal: Point2<f64>,
) -> Vec<Feature> {
    // An enum as its name: a plain string, or the tag of an internally tagged object
    // (`{"decision": "switched", "backtrack_m": ..}` is `switched`), else its JSON text.
    let text = |v: serde_json::Result<Value>, tag: &str| match v {
        Ok(Value::String(s)) => json!(s),
        Ok(Value::Object(o)) if o.get(tag).is_some_and(Value::is_string) => o[tag].clone(),
        Ok(other) => json!(other.to_string()),
        Err(_) => Value::Null,
    };
    let mut out = vec![line("travelled", None, &report.travelled)];
    if !report.ascent.is_empty() {
        out.push(line("ascent", None, &report.ascent));
    }
    out.push(Feature {
        layer: "event",
        class: None,
        geometry: Geometry::Points,
        points: report.timeline.iter().map(|e| e.robot).collect(),
        properties: report
            .timeline
            .iter()
            .map(|e| {
                let mut m = JsonMap::new();
                m.insert("step".into(), json!(e.step));
                m.insert(
                    "change".into(),
                    text(serde_json::to_value(&e.outcome.change), "change"),
                );
                m.insert("case".into(), json!(e.outcome.case.describe()));
                m.insert(
                    "decision".into(),
                    text(serde_json::to_value(&e.outcome.decision), "decision"),
                );
                m.insert("travelled_m".into(), json!(e.travelled_m));
                m.insert("backtracked_m".into(), json!(e.backtracked_m));
                m
            })
            .collect(),
    });
    out.extend(end_points(start, goal));
    out
}

/// The start and the goal as point features.
fn end_points(start: Point2<f64>, goal: Point2<f64>) -> [Feature; 2] {
    [("start", start), ("goal", goal)].map(|(layer, p)| Feature {
        layer,
        class: None,
        geometry: Geometry::Points,
        points: vec![p],
        properties: Vec::new(),
    })
}

/// `[x, y]` of a planning-frame point in the output's coordinates.
fn coords(p: &Point2<f64>, geo: Option<&Georeference>) -> [f64; 2] {
    let w = geo.map_or(*p, |g| g.to_world(p));
    [w.x, w.y]
}

/// The features as a GeoJSON `FeatureCollection` (module docs).
pub fn geojson(features: &[Feature], geo: Option<&Georeference>) -> String {
    let mut list = Vec::new();
    for f in features {
        let mut props = JsonMap::new();
        props.insert("layer".into(), json!(f.layer));
        props.insert("class".into(), json!(f.class));
        match f.geometry {
            Geometry::Line => {
                let c: Vec<[f64; 2]> = f.points.iter().map(|p| coords(p, geo)).collect();
                list.push(json!({
                    "type": "Feature",
                    "geometry": {"type": "LineString", "coordinates": c},
                    "properties": Value::Object(props),
                }));
            }
            Geometry::Points => {
                for (i, p) in f.points.iter().enumerate() {
                    let mut props = props.clone();
                    if let Some(extra) = f.properties.get(i) {
                        props.extend(extra.clone());
                    }
                    list.push(json!({
                        "type": "Feature",
                        "geometry": {"type": "Point", "coordinates": coords(p, geo)},
                        "properties": Value::Object(props),
                    }));
                }
            }
        }
    }
    let mut top = JsonMap::new();
    top.insert("type".into(), json!("FeatureCollection"));
    match geo {
        Some(g) => {
            top.insert(
                "rappel_frame".into(),
                json!("DEM coordinates (east, north)"),
            );
            top.insert("rappel_dem".into(), json!(g.dem));
            match g.crs.as_deref() {
                Some(c) if c.starts_with("EPSG:") => {
                    let code = &c["EPSG:".len()..];
                    top.insert(
                        "crs".into(),
                        json!({"type": "name", "properties": {"name": format!("urn:ogc:def:crs:EPSG::{code}")}}),
                    );
                }
                Some(c) => {
                    top.insert("rappel_crs".into(), json!(c));
                    top.insert(
                        "rappel_note".into(),
                        json!("GeoJSON (RFC 7946) readers assume WGS 84 longitude/latitude and ignore rappel_crs; these are DEM coordinates in the CRS above: use the .fgb export, which carries it"),
                    );
                }
                None => {
                    top.insert(
                        "rappel_crs".into(),
                        json!("unknown: the DEM declares none; set the layer's CRS to the DEM's"),
                    );
                }
            }
        }
        None => {
            top.insert(
                "rappel_frame".into(),
                json!("planning frame (x across the slope, y up the unfolded slope), metres"),
            );
        }
    }
    top.insert("features".into(), Value::Array(list));
    serde_json::to_string_pretty(&Value::Object(top)).unwrap_or_default() + "\n"
}

/// The features as CSV, one row per vertex (module docs).
pub fn csv(features: &[Feature], geo: Option<&Georeference>) -> String {
    let mut out = String::from("layer,class,index,x,y,psi_deg,obstacle");
    if geo.is_some() {
        out.push_str(",east,north");
    }
    out.push('\n');
    let text = |v: Option<&Value>| match v {
        Some(Value::Null) | None => String::new(),
        Some(v) => v.to_string(),
    };
    for f in features {
        let class = f.class.map(|c| c.to_string()).unwrap_or_default();
        for (i, p) in f.points.iter().enumerate() {
            let props = f.properties.get(i);
            let index = props
                .and_then(|m| m.get("index"))
                .map_or(i.to_string(), |v| text(Some(v)));
            let _ = write!(
                out,
                "{},{class},{index},{},{},{},{}",
                f.layer,
                p.x,
                p.y,
                text(props.and_then(|m| m.get("psi_deg"))),
                text(props.and_then(|m| m.get("obstacle")))
            );
            if let Some(g) = geo {
                let w = g.to_world(p);
                let _ = write!(out, ",{},{}", w.x, w.y);
            }
            out.push('\n');
        }
    }
    out
}

/// One exported geometry in output coordinates, for the FlatGeobuf writer.
enum FgbGeometry {
    Line(Vec<[f64; 2]>),
    Point([f64; 2]),
}

impl GeozeroGeometry for FgbGeometry {
    fn process_geom<P: GeomProcessor>(&self, p: &mut P) -> geozero::error::Result<()> {
        match self {
            FgbGeometry::Line(pts) => {
                p.linestring_begin(true, pts.len(), 0)?;
                for (i, c) in pts.iter().enumerate() {
                    p.xy(c[0], c[1], i)?;
                }
                p.linestring_end(true, 0)
            }
            FgbGeometry::Point(c) => {
                p.point_begin(0)?;
                p.xy(c[0], c[1], 0)?;
                p.point_end(0)
            }
        }
    }
}

/// The FlatGeobuf columns: `layer`, `class`, then the points' extra properties (anchors'
/// `index`, `psi_deg`, `obstacle`), typed by their first non-null value.
fn fgb_columns(features: &[Feature]) -> Vec<(String, ColumnType)> {
    let mut cols = vec![
        ("layer".to_string(), ColumnType::String),
        ("class".to_string(), ColumnType::Long),
    ];
    for m in features.iter().flat_map(|f| &f.properties) {
        for (k, v) in m {
            let t = match v {
                Value::Bool(_) => ColumnType::Bool,
                Value::Number(n) if n.is_i64() || n.is_u64() => ColumnType::Long,
                Value::Number(_) => ColumnType::Double,
                Value::String(_) => ColumnType::String,
                _ => continue,
            };
            if !cols.iter().any(|(c, _)| c == k) {
                cols.push((k.clone(), t));
            }
        }
    }
    cols
}

/// A property's value in its column's type; `None` for null or a value of another type.
fn fgb_value(v: &Value, t: ColumnType) -> Option<ColumnValue<'_>> {
    match (t, v) {
        (ColumnType::Bool, Value::Bool(b)) => Some(ColumnValue::Bool(*b)),
        (ColumnType::Long, Value::Number(n)) => n.as_i64().map(ColumnValue::Long),
        (ColumnType::Double, Value::Number(n)) => n.as_f64().map(ColumnValue::Double),
        (ColumnType::String, Value::String(s)) => Some(ColumnValue::String(s)),
        _ => None,
    }
}

/// The features as a FlatGeobuf file in [`export_crs`] (module docs), one layer named `layer`
/// described by `about`.
pub fn flatgeobuf(
    features: &[Feature],
    geo: Option<&Georeference>,
    layer: &str,
    about: &str,
) -> Result<Vec<u8>, ExportError> {
    fn err(e: impl std::fmt::Display) -> ExportError {
        ExportError::FlatGeobuf(e.to_string())
    }
    let crs = export_crs(geo);
    let (wkt, code, org) = match &crs {
        Crs::Epsg(c) => (None, i32::try_from(*c).unwrap_or(0), Some("EPSG")),
        Crs::Wkt(w) => (Some(w.as_str()), 0, None),
    };
    let description = crs.describe();
    let options = FgbWriterOptions {
        write_index: false,
        // One layer of mixed lines and points: no type detection, no promotion to multi types.
        detect_type: false,
        promote_to_multi: false,
        crs: FgbCrs {
            org,
            code,
            wkt,
            name: Some(&description),
            ..Default::default()
        },
        description: Some(about),
        ..Default::default()
    };
    let mut fgb =
        FgbWriter::create_with_options(layer, GeometryType::Unknown, options).map_err(err)?;
    let columns = fgb_columns(features);
    for (name, t) in &columns {
        fgb.add_column(name, *t, |_, c| c.nullable = true);
    }
    let mut add = |geom: FgbGeometry, f: &Feature, extra: Option<&JsonMap<String, Value>>| {
        fgb.add_feature_geom(geom, |w| {
            let _ = w.property(0, "layer", &ColumnValue::String(f.layer));
            if let Some(c) = f.class {
                let _ = w.property(1, "class", &ColumnValue::Long(c as i64));
            }
            for (i, (name, t)) in columns.iter().enumerate().skip(2) {
                if let Some(v) = extra
                    .and_then(|m| m.get(name))
                    .and_then(|v| fgb_value(v, *t))
                {
                    let _ = w.property(i, name, &v);
                }
            }
        })
        .map_err(err)
    };
    for f in features {
        match f.geometry {
            Geometry::Line => {
                let pts = f.points.iter().map(|p| coords(p, geo)).collect();
                add(FgbGeometry::Line(pts), f, None)?;
            }
            Geometry::Points => {
                for (i, p) in f.points.iter().enumerate() {
                    add(FgbGeometry::Point(coords(p, geo)), f, f.properties.get(i))?;
                }
            }
        }
    }
    let mut out = Vec::new();
    fgb.write(&mut out).map_err(err)?;
    Ok(out)
}

/// The plan in `format` (see [`plan_features`]), as the file's bytes.
pub fn export_plan(
    report: &PlanReport,
    geo: Option<&Georeference>,
    format: ExportFormat,
) -> Result<Vec<u8>, ExportError> {
    export_features(
        &plan_features(report),
        geo,
        format,
        "rappel_plan",
        "rappel plan: tethers, anchors, waypoints, ascent, descent, start, goal",
    )
}

/// An online run in `format` (see [`online_features`]; `start` and `goal` are the scenario's),
/// as the file's bytes.
pub fn export_online(
    report: &SimulationReport,
    start: Point2<f64>,
    goal: Point2<f64>,
    geo: Option<&Georeference>,
    format: ExportFormat,
) -> Result<Vec<u8>, ExportError> {
    export_features(
        &online_features(report, start, goal),
        geo,
        format,
        "rappel_online",
        "rappel online: path travelled, final ascent, timeline events, start, goal",
    )
}

/// Features in `format` as the file's bytes (`layer` and `description` name the FlatGeobuf
/// layer).
pub fn export_features(
    features: &[Feature],
    geo: Option<&Georeference>,
    format: ExportFormat,
    layer: &str,
    description: &str,
) -> Result<Vec<u8>, ExportError> {
    Ok(match format {
        ExportFormat::FlatGeobuf => flatgeobuf(features, geo, layer, description)?,
        ExportFormat::GeoJson => geojson(features, geo).into_bytes(),
        ExportFormat::Csv => csv(features, geo).into_bytes(),
    })
}

/// The one line an export says about its CRS: the CRS written ([`export_crs`], described), and
/// for GeoJSON whether readers see it (only an EPSG code, in the 2008 `crs` member).
///
/// ```
/// use rappel_render::export::{ExportFormat, crs_note};
/// assert!(crs_note(None, ExportFormat::FlatGeobuf).starts_with("LOCAL_CS \"rappel planning frame"));
/// assert!(crs_note(None, ExportFormat::Csv).ends_with("(x, y columns; CSV carries no CRS)"));
/// assert!(crs_note(None, ExportFormat::GeoJson).contains("rappel_frame"));
/// ```
pub fn crs_note(geo: Option<&Georeference>, format: ExportFormat) -> String {
    let crs = export_crs(geo);
    let described = crs.describe();
    match (format, geo, &crs) {
        (ExportFormat::GeoJson, None, _) => {
            format!("{described} (GeoJSON: named in rappel_frame; readers will assume WGS 84)")
        }
        (ExportFormat::GeoJson, Some(_), Crs::Wkt(_)) => format!(
            "{described} (GeoJSON readers assume WGS 84: the WKT is in rappel_crs; use .fgb to carry it)"
        ),
        (ExportFormat::Csv, Some(_), _) => {
            format!("{described} (east, north columns; CSV carries no CRS)")
        }
        (ExportFormat::Csv, None, _) => {
            format!("{described} (x, y columns; CSV carries no CRS)")
        }
        _ => described,
    }
}
