//! Plans exported for other tools (issue 16): the chosen class's taut tether, anchors, waypoints,
//! ascent and descent, and every other class's tether, as GeoJSON or CSV. For scenarios made from
//! a DEM ([`rappel::georeference`]) coordinates are the DEM's own `(east, north)`, so a plan lays
//! over the DEM in a GIS; otherwise they are planning-frame coordinates, and the file says so.
//!
//! GeoJSON: a `FeatureCollection` of `LineString` and `Point` features with `layer` and `class`
//! properties (anchors also `index`, `psi_deg`, `obstacle`). RFC 7946 assumes WGS 84
//! longitude/latitude; projected DEM coordinates are declared with the 2008 `crs` member when the
//! DEM names an EPSG code (QGIS and GDAL read it), and otherwise with a foreign member
//! `rappel_crs` holding the DEM's WKT or citation (set the layer's CRS by hand). CSV: one row per
//! vertex, `layer,class,index,x,y` and, when georeferenced, `east,north`.

use nalgebra::Point2;
use rappel::georeference::Georeference;
use rappel::plan::PlanReport;
use serde_json::{Map as JsonMap, Value, json};
use std::fmt::Write;

/// An export format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ExportFormat {
    /// GeoJSON (`.geojson`).
    GeoJson,
    /// Comma-separated values (`.csv`).
    Csv,
}

impl ExportFormat {
    /// The format of an output path by its extension (`.geojson` or `.csv`, any case).
    pub fn of_path(path: &std::path::Path) -> Option<ExportFormat> {
        match path.extension()?.to_str()?.to_ascii_lowercase().as_str() {
            "geojson" => Some(ExportFormat::GeoJson),
            "csv" => Some(ExportFormat::Csv),
            _ => None,
        }
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
    /// `tether`, `anchor`, `waypoint`, `ascent`, `descent`, `start`, `goal`.
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
    for (layer, p) in [
        ("start", report.setting.start),
        ("goal", report.setting.goal),
    ] {
        out.push(Feature {
            layer,
            class: None,
            geometry: Geometry::Points,
            points: vec![p],
            properties: Vec::new(),
        });
    }
    out
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
    let mut out = String::from("layer,class,index,x,y");
    if geo.is_some() {
        out.push_str(",east,north");
    }
    out.push('\n');
    for f in features {
        let class = f.class.map(|c| c.to_string()).unwrap_or_default();
        for (i, p) in f.points.iter().enumerate() {
            let _ = write!(out, "{},{class},{i},{},{}", f.layer, p.x, p.y);
            if let Some(g) = geo {
                let w = g.to_world(p);
                let _ = write!(out, ",{},{}", w.x, w.y);
            }
            out.push('\n');
        }
    }
    out
}

/// The plan in `format` (see [`plan_features`]).
pub fn export_plan(
    report: &PlanReport,
    geo: Option<&Georeference>,
    format: ExportFormat,
) -> String {
    let f = plan_features(report);
    match format {
        ExportFormat::GeoJson => geojson(&f, geo),
        ExportFormat::Csv => csv(&f, geo),
    }
}
