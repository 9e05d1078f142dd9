//! Coordinate reference systems of DEMs and of the rasters rappel writes (issue 34): the GeoTIFF
//! GeoKey directory in full (OGC GeoTIFF 1.1: the key directory tag 34735 with its double and
//! ASCII parameters, tags 34736 and 34737), its translation to OGC WKT 1 (the GDAL flavour that
//! GDAL, QGIS and ESRI `.prj` readers accept), and back from WKT to GeoKeys for writing.
//!
//! Pure Rust, no EPSG database (the default build needs only the Rust toolchain):
//! - a system with an EPSG code (`ProjectedCSTypeGeoKey` or, for a geographic model,
//!   `GeographicTypeGeoKey`) is kept as `EPSG:n`, the one identifier every GIS resolves with its
//!   own database; [`Crs::Epsg`];
//! - a user-defined projected system (planetary DTMs: a Mars or Moon equirectangular, polar
//!   stereographic, sinusoidal...) becomes a `PROJCS` with its `GEOGCS`, `DATUM`, `SPHEROID` (from
//!   the semi-axes or the inverse flattening), prime meridian, projection and parameters, from the
//!   projections in [`PROJECTIONS`]; a user-defined geographic system a `GEOGCS`;
//! - a projected model with no projection at all (an engineering or local grid, like the shipped
//!   HiRISE crop) becomes `LOCAL_CS[name, UNIT, AXIS east, AXIS north]`, as GDAL reads it;
//! - a GDAL-written citation `ESRI PE String = <WKT>` is that WKT.
//!
//! Anything else the keys declare (a projection not in the table, a non-degree angular unit, an
//! EPSG datum or ellipsoid code under a user-defined system that is not one of the few built in)
//! is a [`CrsError`] naming the key, not a silent guess. Fix: `gdalwarp -t_srs` to an EPSG code
//! or to a projection in the table.

use std::fmt;

/// `GeoKeyDirectoryTag`, `GeoDoubleParamsTag` and `GeoAsciiParamsTag`.
pub const GEO_KEY_DIRECTORY_TAG: u16 = 34735;
/// The double parameters' tag.
pub const GEO_DOUBLE_PARAMS_TAG: u16 = 34736;
/// The ASCII parameters' tag.
pub const GEO_ASCII_PARAMS_TAG: u16 = 34737;

/// GeoKey ids (OGC GeoTIFF 1.1, Annex B).
pub mod key {
    /// 1 projected, 2 geographic, 3 geocentric, 32767 user-defined.
    pub const MODEL_TYPE: u16 = 1024;
    /// 1 PixelIsArea, 2 PixelIsPoint.
    pub const RASTER_TYPE: u16 = 1025;
    /// Free text naming the system.
    pub const CITATION: u16 = 1026;
    /// EPSG geographic CRS code, or 32767.
    pub const GEOGRAPHIC_TYPE: u16 = 2048;
    /// Free text naming the geographic system (GDAL: `GCS Name = ..|Datum = ..|...`).
    pub const GEOG_CITATION: u16 = 2049;
    /// EPSG datum code, or 32767.
    pub const GEODETIC_DATUM: u16 = 2050;
    /// EPSG prime meridian code (8901 Greenwich).
    pub const PRIME_MERIDIAN: u16 = 2051;
    /// EPSG angular unit code (9102 degree).
    pub const ANGULAR_UNITS: u16 = 2054;
    /// EPSG ellipsoid code, or 32767.
    pub const ELLIPSOID: u16 = 2056;
    /// Semi-major axis, in the geographic linear unit (metres).
    pub const SEMI_MAJOR_AXIS: u16 = 2057;
    /// Semi-minor axis.
    pub const SEMI_MINOR_AXIS: u16 = 2058;
    /// Inverse flattening.
    pub const INV_FLATTENING: u16 = 2059;
    /// Prime meridian longitude, degrees.
    pub const PRIME_MERIDIAN_LONG: u16 = 2061;
    /// EPSG projected CRS code, or 32767.
    pub const PROJECTED_CS_TYPE: u16 = 3072;
    /// Free text naming the projected system.
    pub const PCS_CITATION: u16 = 3073;
    /// EPSG projection (conversion) code, or 32767.
    pub const PROJECTION: u16 = 3074;
    /// The coordinate transformation (projection method) code.
    pub const COORD_TRANS: u16 = 3075;
    /// EPSG linear unit code (9001 metre).
    pub const LINEAR_UNITS: u16 = 3076;
    /// First standard parallel, degrees.
    pub const STD_PARALLEL1: u16 = 3078;
    /// Second standard parallel.
    pub const STD_PARALLEL2: u16 = 3079;
    /// Longitude of the natural origin.
    pub const NAT_ORIGIN_LONG: u16 = 3080;
    /// Latitude of the natural origin.
    pub const NAT_ORIGIN_LAT: u16 = 3081;
    /// False easting.
    pub const FALSE_EASTING: u16 = 3082;
    /// False northing.
    pub const FALSE_NORTHING: u16 = 3083;
    /// Longitude of the false origin.
    pub const FALSE_ORIGIN_LONG: u16 = 3084;
    /// Latitude of the false origin.
    pub const FALSE_ORIGIN_LAT: u16 = 3085;
    /// Easting at the false origin.
    pub const FALSE_ORIGIN_EASTING: u16 = 3086;
    /// Northing at the false origin.
    pub const FALSE_ORIGIN_NORTHING: u16 = 3087;
    /// Longitude of the projection centre.
    pub const CENTER_LONG: u16 = 3088;
    /// Latitude of the projection centre.
    pub const CENTER_LAT: u16 = 3089;
    /// Scale factor at the natural origin.
    pub const SCALE_AT_NAT_ORIGIN: u16 = 3092;
    /// Longitude of the straight vertical pole (polar stereographic).
    pub const STRAIGHT_VERT_POLE_LONG: u16 = 3095;
}

/// The name of the local grid a result is written in when its DEM declared no CRS.
pub const UNKNOWN_CRS_NAME: &str = "DEM coordinates, CRS unknown (the DEM declared none)";

/// The name of the local grid of a result not made from a DEM: the planning frame.
pub const PLANNING_FRAME_NAME: &str =
    "rappel planning frame (x across the slope, y up the unfolded slope), metres";

/// The GeoKey value meaning "user-defined" (no EPSG code).
pub const USER_DEFINED: u16 = 32767;
/// EPSG code of the degree as a GeoTIFF angular unit.
const DEGREE: u16 = 9102;
/// EPSG codes of the linear units read and written, with their size in metres.
const LINEAR_UNITS: [(u16, &str, f64); 3] = [
    (9001, "metre", 1.0),
    (9002, "foot", 0.3048),
    (9003, "US survey foot", 0.304_800_609_601_219_2),
];
/// Relative difference under which a WKT unit's size is taken as one of [`LINEAR_UNITS`] (or as
/// the degree): WKT writers print 10 to 17 significant digits.
const UNIT_SIZE_TOLERANCE: f64 = 1e-9;
/// The degree in radians, as WKT 1 writes it.
const DEGREE_RADIANS: &str = "0.0174532925199433";

/// One GeoKey's value.
#[derive(Debug, Clone, PartialEq)]
pub enum GeoKeyValue {
    /// A short stored in the directory itself (codes).
    Short(u16),
    /// Doubles from `GeoDoubleParams`.
    Double(Vec<f64>),
    /// Text from `GeoAsciiParams`, without its `|` terminator.
    Ascii(String),
}

/// A GeoTIFF's whole GeoKey directory, in file order.
///
/// ```
/// use rappel_terrain::crs::{GeoKeyDirectory, GeoKeyValue, key};
/// // GTModelType = projected, ProjectedCSType = 32611, a citation.
/// let dir = [1, 1, 0, 3, 1024, 0, 1, 1, 3072, 0, 1, 32611, 1026, 34737, 8, 0];
/// let keys = GeoKeyDirectory::parse(&dir, &[], "UTM 11N|").unwrap();
/// assert_eq!(keys.get(key::CITATION), Some(&GeoKeyValue::Ascii("UTM 11N".into())));
/// assert_eq!(keys.to_crs().unwrap().unwrap().to_string(), "EPSG:32611");
/// ```
#[derive(Debug, Clone, PartialEq, Default)]
pub struct GeoKeyDirectory {
    /// `(key id, value)`.
    pub keys: Vec<(u16, GeoKeyValue)>,
}

/// A coordinate reference system as rappel keeps it: an EPSG code or a WKT 1 definition.
/// Its text form (what scenarios store) is `EPSG:n` or the WKT; [`Crs::parse`] reads it back.
#[derive(Debug, Clone, PartialEq)]
pub enum Crs {
    /// An EPSG code.
    Epsg(u32),
    /// An OGC WKT (1) definition: `PROJCS`, `GEOGCS` or `LOCAL_CS`.
    Wkt(String),
}

/// Why GeoKeys could not be read or turned into a CRS (and back). Fix: reproject with `gdalwarp
/// -t_srs EPSG:n` (or to one of the projections in [`PROJECTIONS`]).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CrsError {
    /// The key directory is malformed.
    #[error("malformed GeoKey directory: {0}")]
    Malformed(String),
    /// A key whose value this reader does not honour.
    #[error("GeoKey {key} = {value} is not supported: {why}")]
    Unsupported {
        /// The key id.
        key: u16,
        /// Its value as found.
        value: String,
        /// What is supported.
        why: String,
    },
    /// A WKT text that is not WKT 1 or names something not in the tables.
    #[error("WKT not written as GeoKeys: {0}")]
    Wkt(String),
}

impl GeoKeyDirectory {
    /// Parses the three GeoTIFF tags: the directory (`[version, revision, minor, count]` then
    /// `count` entries `[key, location, count, value]`), the doubles and the ASCII text.
    pub fn parse(dir: &[u16], doubles: &[f64], ascii: &str) -> Result<GeoKeyDirectory, CrsError> {
        let Some(header) = dir.get(..4) else {
            return Err(CrsError::Malformed(format!(
                "{} shorts, fewer than the 4 of the header",
                dir.len()
            )));
        };
        let n = usize::from(header[3]);
        let entries = dir.get(4..).unwrap_or(&[]);
        if entries.len() < 4 * n {
            return Err(CrsError::Malformed(format!(
                "the header declares {n} keys, the tag holds {}",
                entries.len() / 4
            )));
        }
        let mut keys = Vec::with_capacity(n);
        for e in entries.chunks_exact(4).take(n) {
            let (id, location, count, value) = (e[0], e[1], usize::from(e[2]), usize::from(e[3]));
            let v = match location {
                0 => GeoKeyValue::Short(e[3]),
                GEO_DOUBLE_PARAMS_TAG => match doubles.get(value..value + count) {
                    Some(d) => GeoKeyValue::Double(d.to_vec()),
                    None => {
                        return Err(CrsError::Malformed(format!(
                            "key {id} points at doubles {value}..{} of {}",
                            value + count,
                            doubles.len()
                        )));
                    }
                },
                GEO_ASCII_PARAMS_TAG => {
                    // A count running past the text (a sloppy writer) is clamped to it.
                    let end = value.saturating_add(count).min(ascii.len());
                    let text = ascii.get(value.min(end)..end).unwrap_or("");
                    GeoKeyValue::Ascii(text.trim_end_matches(['|', '\0']).trim().to_string())
                }
                other => {
                    return Err(CrsError::Malformed(format!(
                        "key {id} stored in tag {other}, not in the GeoKey tags"
                    )));
                }
            };
            keys.push((id, v));
        }
        Ok(GeoKeyDirectory { keys })
    }

    /// The three tags' contents for writing: directory, doubles, ASCII (each text ends in `|`).
    pub fn encode(&self) -> (Vec<u16>, Vec<f64>, String) {
        let mut keys = self.keys.clone();
        keys.sort_by_key(|(id, _)| *id);
        let mut dir = vec![1, 1, 0, keys.len() as u16];
        let (mut doubles, mut ascii) = (Vec::new(), String::new());
        for (id, v) in &keys {
            match v {
                GeoKeyValue::Short(s) => dir.extend([*id, 0, 1, *s]),
                GeoKeyValue::Double(d) => {
                    dir.extend([
                        *id,
                        GEO_DOUBLE_PARAMS_TAG,
                        d.len() as u16,
                        doubles.len() as u16,
                    ]);
                    doubles.extend(d);
                }
                GeoKeyValue::Ascii(t) => {
                    // `|` inside a text is GDAL's separator of citation parts; kept as is.
                    dir.extend([
                        *id,
                        GEO_ASCII_PARAMS_TAG,
                        (t.len() + 1) as u16,
                        ascii.len() as u16,
                    ]);
                    ascii.push_str(t);
                    ascii.push('|');
                }
            }
        }
        (dir, doubles, ascii)
    }

    /// The value of key `id`.
    pub fn get(&self, id: u16) -> Option<&GeoKeyValue> {
        self.keys.iter().find(|(k, _)| *k == id).map(|(_, v)| v)
    }

    fn short(&self, id: u16) -> Option<u16> {
        match self.get(id) {
            Some(GeoKeyValue::Short(s)) => Some(*s),
            _ => None,
        }
    }

    fn double(&self, id: u16) -> Option<f64> {
        match self.get(id) {
            Some(GeoKeyValue::Double(d)) => d.first().copied(),
            _ => None,
        }
    }

    fn text(&self, id: u16) -> Option<&str> {
        match self.get(id) {
            Some(GeoKeyValue::Ascii(t)) if !t.is_empty() => Some(t),
            _ => None,
        }
    }

    /// The keys present that the CRS read from them ([`GeoKeyDirectory::to_crs`]) does not use,
    /// one message each naming the key, its value and why it is not used (nothing is ignored
    /// silently; `rappel dem` prints them as warnings):
    /// - vertical CRS keys (4096-4099): heights are used as stored, in metres; the vertical
    ///   datum and unit are not kept;
    /// - projection parameters (3078-3095) the projection read does not take, or any of them
    ///   when the system is an EPSG code, an ESRI WKT citation or a local grid;
    /// - a linear unit other than the metre: the CRS keeps it, but cell sizes and heights are
    ///   taken as metres.
    ///
    /// ```
    /// use rappel_terrain::crs::GeoKeyDirectory;
    /// // Projected EPSG:32611 with VerticalCSTypeGeoKey = 5773 (EGM96 height).
    /// let dir = [1, 1, 0, 3, 1024, 0, 1, 1, 3072, 0, 1, 32611, 4096, 0, 1, 5773];
    /// let keys = GeoKeyDirectory::parse(&dir, &[], "").unwrap();
    /// let ignored = keys.ignored_keys();
    /// assert_eq!(ignored.len(), 1);
    /// assert!(ignored[0].starts_with("GeoKey VerticalCSTypeGeoKey (4096) = 5773 ignored"), "{}", ignored[0]);
    /// ```
    pub fn ignored_keys(&self) -> Vec<String> {
        let code = |id| self.short(id).filter(|&c| c != 0 && c != USER_DEFINED);
        let esri = [key::CITATION, key::PCS_CITATION].iter().any(|&id| {
            self.text(id)
                .is_some_and(|t| t.starts_with("ESRI PE String = "))
        });
        let projected_by_keys = !esri
            && code(key::PROJECTED_CS_TYPE).is_none()
            && self.short(key::MODEL_TYPE) == Some(1);
        let taken: &[(&str, u16, f64)] = match self
            .short(key::COORD_TRANS)
            .and_then(|ct| PROJECTIONS.iter().find(|p| p.coord_trans == ct))
        {
            Some(p) if projected_by_keys => p.params,
            _ => &[],
        };
        let mut out = Vec::new();
        // One pass over the directory's keys (at most u16::MAX entries, its count field).
        for (id, value) in &self.keys {
            let why = match *id {
                4096..=4099 => {
                    "a vertical CRS key: heights are used as stored, taken as metres; the vertical datum and unit are not kept"
                }
                3078..=3095 if !taken.iter().any(|(_, k, _)| k == id) => {
                    "a projection parameter the CRS read from these keys does not take (its EPSG code or its projection defines the system)"
                }
                key::LINEAR_UNITS if self.short(key::LINEAR_UNITS) != Some(9001) => {
                    "the CRS keeps this unit, but rappel takes cell sizes and heights as metres: convert the DEM to metres (gdalwarp -t_srs with +units=m, gdal_calc for heights)"
                }
                _ => continue,
            };
            let value = match value {
                GeoKeyValue::Short(v) => v.to_string(),
                GeoKeyValue::Double(d) => d.iter().map(|v| num(*v)).collect::<Vec<_>>().join(", "),
                GeoKeyValue::Ascii(t) => format!("\"{t}\""),
            };
            out.push(format!(
                "GeoKey {} ({id}) = {value} ignored: {why}",
                key_name(*id)
            ));
        }
        out
    }

    /// `true` when `GTRasterTypeGeoKey` says `RasterPixelIsPoint`.
    pub fn pixel_is_point(&self) -> bool {
        self.short(key::RASTER_TYPE) == Some(2)
    }

    /// The CRS the keys declare (module docs); `None` when they declare none (no model type, no
    /// code, no citation).
    pub fn to_crs(&self) -> Result<Option<Crs>, CrsError> {
        let code = |id| self.short(id).filter(|&c| c != 0 && c != USER_DEFINED);
        for id in [key::CITATION, key::PCS_CITATION] {
            if let Some(wkt) = self
                .text(id)
                .and_then(|t| t.strip_prefix("ESRI PE String = "))
            {
                return Ok(Some(Crs::Wkt(wkt.trim().to_string())));
            }
        }
        let model = self.short(key::MODEL_TYPE);
        if let Some(c) = code(key::PROJECTED_CS_TYPE) {
            return Ok(Some(Crs::Epsg(u32::from(c))));
        }
        if model != Some(1)
            && let Some(c) = code(key::GEOGRAPHIC_TYPE)
        {
            return Ok(Some(Crs::Epsg(u32::from(c))));
        }
        let name = self
            .text(key::CITATION)
            .or_else(|| self.text(key::PCS_CITATION));
        if model == Some(1)
            && self.short(key::COORD_TRANS).is_none()
            && let Some(c) = code(key::PROJECTION)
        {
            // An EPSG conversion code without its parameters: no database here to expand it,
            // and reading the grid as local would drop a real projection.
            return Err(CrsError::Unsupported {
                key: key::PROJECTION,
                value: c.to_string(),
                why: "an EPSG projection code without ProjCoordTransGeoKey and its parameters;                       give the projected CRS an EPSG code or write the projection's parameters"
                    .into(),
            });
        }
        match model {
            Some(1) if self.short(key::COORD_TRANS).is_some() => {
                Ok(Some(Crs::Wkt(self.projcs_wkt(name.unwrap_or("unnamed"))?)))
            }
            Some(1) | Some(USER_DEFINED) => Ok(Some(Crs::Wkt(self.local_cs_wkt(name)?))),
            Some(2) => Ok(Some(Crs::Wkt(self.geogcs_wkt()?))),
            Some(other) => Err(CrsError::Unsupported {
                key: key::MODEL_TYPE,
                value: other.to_string(),
                why: "only projected (1), geographic (2) and user-defined (32767) models are read"
                    .into(),
            }),
            None => Ok(name.map(|n| Crs::Wkt(local_cs(n, &linear_unit(9001, 1.0))))),
        }
    }

    /// `UNIT[..]` of the projected linear unit (metre when absent).
    fn linear_unit_wkt(&self) -> Result<String, CrsError> {
        let code = self.short(key::LINEAR_UNITS).unwrap_or(9001);
        match LINEAR_UNITS.iter().find(|(c, _, _)| *c == code) {
            Some(&(c, _, size)) => Ok(linear_unit(c, size)),
            None => Err(CrsError::Unsupported {
                key: key::LINEAR_UNITS,
                value: code.to_string(),
                why: "linear units must be metre (9001), foot (9002) or US survey foot (9003)"
                    .into(),
            }),
        }
    }

    fn local_cs_wkt(&self, name: Option<&str>) -> Result<String, CrsError> {
        Ok(local_cs(
            name.unwrap_or("unnamed"),
            &self.linear_unit_wkt()?,
        ))
    }

    /// The `GEOGCS[..]` the geographic keys define.
    fn geogcs_wkt(&self) -> Result<String, CrsError> {
        if let Some(c) = self.short(key::ANGULAR_UNITS)
            && c != DEGREE
        {
            return Err(CrsError::Unsupported {
                key: key::ANGULAR_UNITS,
                value: c.to_string(),
                why: "angular units must be degrees (9102)".into(),
            });
        }
        if let Some(c) = self
            .short(key::GEOGRAPHIC_TYPE)
            .filter(|&c| c != USER_DEFINED)
        {
            return match KNOWN_GEOGCS.iter().find(|g| g.code == c) {
                Some(g) => Ok(g.wkt()),
                None => Err(CrsError::Unsupported {
                    key: key::GEOGRAPHIC_TYPE,
                    value: c.to_string(),
                    why: "under a user-defined projection only WGS 84 (4326), NAD83 (4269) and \
                          NAD27 (4267) are built in"
                        .into(),
                }),
            };
        }
        // GDAL's citation: `GCS Name = a|Datum = b|Ellipsoid = c|Primem = d|` ('|' already split).
        let citation = self.text(key::GEOG_CITATION).unwrap_or("");
        let part = |label: &str| {
            citation
                .split('|')
                .find_map(|p| p.trim().strip_prefix(label))
                .map(|s| s.trim().to_string())
        };
        let gcs_name = part("GCS Name = ").unwrap_or_else(|| {
            if citation.is_empty() || citation.contains(" = ") {
                "unnamed".into()
            } else {
                citation.to_string()
            }
        });
        let ellipsoid = match self.short(key::ELLIPSOID).filter(|&c| c != USER_DEFINED) {
            Some(c) => match KNOWN_GEOGCS.iter().find(|g| g.ellipsoid_code == c) {
                Some(g) => (g.ellipsoid.to_string(), g.a, g.inv_f),
                None => {
                    return Err(CrsError::Unsupported {
                        key: key::ELLIPSOID,
                        value: c.to_string(),
                        why: "EPSG ellipsoids 7030, 7019 and 7008 are built in; give others by \
                              their semi-axes"
                            .into(),
                    });
                }
            },
            None => {
                let Some(a) = self.double(key::SEMI_MAJOR_AXIS) else {
                    return Err(CrsError::Unsupported {
                        key: key::SEMI_MAJOR_AXIS,
                        value: "absent".into(),
                        why: "a user-defined ellipsoid needs its semi-major axis".into(),
                    });
                };
                let inv_f = match (
                    self.double(key::INV_FLATTENING),
                    self.double(key::SEMI_MINOR_AXIS),
                ) {
                    (Some(f), _) => f,
                    (None, Some(b)) if b < a => a / (a - b),
                    _ => 0.0,
                };
                let name = part("Ellipsoid = ").unwrap_or_else(|| "unnamed".into());
                (name, a, inv_f)
            }
        };
        let datum = match self
            .short(key::GEODETIC_DATUM)
            .filter(|&c| c != USER_DEFINED)
        {
            Some(c) => match KNOWN_GEOGCS.iter().find(|g| g.datum_code == c) {
                Some(g) => g.datum.to_string(),
                None => {
                    return Err(CrsError::Unsupported {
                        key: key::GEODETIC_DATUM,
                        value: c.to_string(),
                        why: "EPSG datums 6326, 6269 and 6267 are built in".into(),
                    });
                }
            },
            None => part("Datum = ").unwrap_or_else(|| "unnamed".into()),
        };
        let pm_long = self.double(key::PRIME_MERIDIAN_LONG).unwrap_or(0.0);
        let pm_name = part("Primem = ").unwrap_or_else(|| {
            if pm_long == 0.0 {
                "Greenwich".into()
            } else {
                "unnamed".into()
            }
        });
        Ok(format!(
            "GEOGCS[{},DATUM[{},SPHEROID[{},{},{}]],PRIMEM[{},{}],UNIT[\"degree\",{DEGREE_RADIANS}]]",
            quote(&gcs_name),
            quote(&datum),
            quote(&ellipsoid.0),
            num(ellipsoid.1),
            num(ellipsoid.2),
            quote(&pm_name),
            num(pm_long)
        ))
    }

    /// The `PROJCS[..]` of a user-defined projection.
    fn projcs_wkt(&self, name: &str) -> Result<String, CrsError> {
        let Some(ct) = self.short(key::COORD_TRANS) else {
            return Err(CrsError::Unsupported {
                key: key::COORD_TRANS,
                value: "absent".into(),
                why: "a user-defined projected system needs its projection".into(),
            });
        };
        let Some(p) = PROJECTIONS.iter().find(|p| p.coord_trans == ct) else {
            return Err(CrsError::Unsupported {
                key: key::COORD_TRANS,
                value: ct.to_string(),
                why: format!(
                    "projections read: {}",
                    PROJECTIONS
                        .iter()
                        .map(|p| format!("{} ({})", p.wkt_name, p.coord_trans))
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            });
        };
        let mut params = String::new();
        for &(param, geo_key, default) in p.params {
            let v = self.double(geo_key).unwrap_or(default);
            params.push_str(&format!(",PARAMETER[{},{}]", quote(param), num(v)));
        }
        Ok(format!(
            "PROJCS[{},{},PROJECTION[{}]{params},{},AXIS[\"Easting\",EAST],AXIS[\"Northing\",NORTH]]",
            quote(name),
            self.geogcs_wkt()?,
            quote(p.wkt_name),
            self.linear_unit_wkt()?
        ))
    }
}

/// The GeoTIFF 1.1 name of the keys [`GeoKeyDirectory::ignored_keys`] reports.
fn key_name(id: u16) -> &'static str {
    match id {
        3076 => "ProjLinearUnitsGeoKey",
        3078 => "ProjStdParallel1GeoKey",
        3079 => "ProjStdParallel2GeoKey",
        3080 => "ProjNatOriginLongGeoKey",
        3081 => "ProjNatOriginLatGeoKey",
        3082 => "ProjFalseEastingGeoKey",
        3083 => "ProjFalseNorthingGeoKey",
        3084 => "ProjFalseOriginLongGeoKey",
        3085 => "ProjFalseOriginLatGeoKey",
        3086 => "ProjFalseOriginEastingGeoKey",
        3087 => "ProjFalseOriginNorthingGeoKey",
        3088 => "ProjCenterLongGeoKey",
        3089 => "ProjCenterLatGeoKey",
        3090 => "ProjCenterEastingGeoKey",
        3091 => "ProjCenterNorthingGeoKey",
        3092 => "ProjScaleAtNatOriginGeoKey",
        3093 => "ProjScaleAtCenterGeoKey",
        3094 => "ProjAzimuthAngleGeoKey",
        3095 => "ProjStraightVertPoleLongGeoKey",
        4096 => "VerticalCSTypeGeoKey",
        4097 => "VerticalCitationGeoKey",
        4098 => "VerticalDatumGeoKey",
        4099 => "VerticalUnitsGeoKey",
        _ => "GeoKey",
    }
}

/// A projection method: its GeoTIFF `ProjCoordTransGeoKey` code, its WKT 1 name (and ESRI
/// aliases read from `.prj` files), and its WKT parameters with the GeoKey holding each and the
/// value when the key is absent.
#[derive(Debug)]
pub struct Projection {
    /// `ProjCoordTransGeoKey` value.
    pub coord_trans: u16,
    /// WKT 1 `PROJECTION` name (GDAL's).
    pub wkt_name: &'static str,
    /// Other names for it (ESRI).
    pub aliases: &'static [&'static str],
    /// `(WKT parameter, GeoKey, default)`.
    pub params: &'static [(&'static str, u16, f64)],
}

/// The projections read and written: those planetary DTMs (HiRISE, CTX, LOLA) and field DEMs
/// use. The GeoKey of each parameter follows GDAL's GeoTIFF writer.
pub const PROJECTIONS: &[Projection] = &[
    Projection {
        coord_trans: 17,
        wkt_name: "Equirectangular",
        aliases: &["Equidistant_Cylindrical", "Plate_Carree"],
        params: &[
            ("latitude_of_origin", key::CENTER_LAT, 0.0),
            ("central_meridian", key::CENTER_LONG, 0.0),
            ("standard_parallel_1", key::STD_PARALLEL1, 0.0),
            ("false_easting", key::FALSE_EASTING, 0.0),
            ("false_northing", key::FALSE_NORTHING, 0.0),
        ],
    },
    Projection {
        coord_trans: 15,
        wkt_name: "Polar_Stereographic",
        aliases: &[],
        params: &[
            ("latitude_of_origin", key::NAT_ORIGIN_LAT, 90.0),
            ("central_meridian", key::STRAIGHT_VERT_POLE_LONG, 0.0),
            ("scale_factor", key::SCALE_AT_NAT_ORIGIN, 1.0),
            ("false_easting", key::FALSE_EASTING, 0.0),
            ("false_northing", key::FALSE_NORTHING, 0.0),
        ],
    },
    Projection {
        coord_trans: 1,
        wkt_name: "Transverse_Mercator",
        aliases: &[],
        params: &[
            ("latitude_of_origin", key::NAT_ORIGIN_LAT, 0.0),
            ("central_meridian", key::NAT_ORIGIN_LONG, 0.0),
            ("scale_factor", key::SCALE_AT_NAT_ORIGIN, 1.0),
            ("false_easting", key::FALSE_EASTING, 0.0),
            ("false_northing", key::FALSE_NORTHING, 0.0),
        ],
    },
    Projection {
        coord_trans: 24,
        wkt_name: "Sinusoidal",
        aliases: &[],
        params: &[
            ("longitude_of_center", key::CENTER_LONG, 0.0),
            ("false_easting", key::FALSE_EASTING, 0.0),
            ("false_northing", key::FALSE_NORTHING, 0.0),
        ],
    },
    Projection {
        coord_trans: 8,
        wkt_name: "Lambert_Conformal_Conic_2SP",
        aliases: &["Lambert_Conformal_Conic"],
        params: &[
            ("standard_parallel_1", key::STD_PARALLEL1, 0.0),
            ("standard_parallel_2", key::STD_PARALLEL2, 0.0),
            ("latitude_of_origin", key::FALSE_ORIGIN_LAT, 0.0),
            ("central_meridian", key::FALSE_ORIGIN_LONG, 0.0),
            ("false_easting", key::FALSE_ORIGIN_EASTING, 0.0),
            ("false_northing", key::FALSE_ORIGIN_NORTHING, 0.0),
        ],
    },
    Projection {
        coord_trans: 10,
        wkt_name: "Lambert_Azimuthal_Equal_Area",
        aliases: &[],
        params: &[
            ("latitude_of_center", key::CENTER_LAT, 0.0),
            ("longitude_of_center", key::CENTER_LONG, 0.0),
            ("false_easting", key::FALSE_EASTING, 0.0),
            ("false_northing", key::FALSE_NORTHING, 0.0),
        ],
    },
];

/// A geographic system built in by EPSG code (for user-defined projections over it).
struct KnownGeogcs {
    code: u16,
    name: &'static str,
    datum_code: u16,
    datum: &'static str,
    ellipsoid_code: u16,
    ellipsoid: &'static str,
    a: f64,
    inv_f: f64,
}

impl KnownGeogcs {
    fn wkt(&self) -> String {
        format!(
            "GEOGCS[{},DATUM[{},SPHEROID[{},{},{}]],PRIMEM[\"Greenwich\",0],UNIT[\"degree\",{DEGREE_RADIANS}],AUTHORITY[\"EPSG\",\"{}\"]]",
            quote(self.name),
            quote(self.datum),
            quote(self.ellipsoid),
            num(self.a),
            num(self.inv_f),
            self.code
        )
    }
}

const KNOWN_GEOGCS: [KnownGeogcs; 3] = [
    KnownGeogcs {
        code: 4326,
        name: "WGS 84",
        datum_code: 6326,
        datum: "WGS_1984",
        ellipsoid_code: 7030,
        ellipsoid: "WGS 84",
        a: 6_378_137.0,
        inv_f: 298.257_223_563,
    },
    KnownGeogcs {
        code: 4269,
        name: "NAD83",
        datum_code: 6269,
        datum: "North_American_Datum_1983",
        ellipsoid_code: 7019,
        ellipsoid: "GRS 1980",
        a: 6_378_137.0,
        inv_f: 298.257_222_101,
    },
    KnownGeogcs {
        code: 4267,
        name: "NAD27",
        datum_code: 6267,
        datum: "North_American_Datum_1927",
        ellipsoid_code: 7008,
        ellipsoid: "Clarke 1866",
        a: 6_378_206.4,
        inv_f: 294.978_698_213_898,
    },
];

/// A WKT string literal.
fn quote(s: &str) -> String {
    format!("\"{}\"", s.replace('"', "\"\""))
}

/// A number as WKT writes it: shortest round-trip decimal, no `-0`.
fn num(v: f64) -> String {
    if v == 0.0 { "0".into() } else { format!("{v}") }
}

fn linear_unit(code: u16, size: f64) -> String {
    let name = LINEAR_UNITS
        .iter()
        .find(|(c, _, _)| *c == code)
        .map_or("unknown", |(_, n, _)| *n);
    format!(
        "UNIT[{},{},AUTHORITY[\"EPSG\",\"{code}\"]]",
        quote(name),
        num(size)
    )
}

fn local_cs(name: &str, unit: &str) -> String {
    format!(
        "LOCAL_CS[{},{unit},AXIS[\"Easting\",EAST],AXIS[\"Northing\",NORTH]]",
        quote(name)
    )
}

impl fmt::Display for Crs {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Crs::Epsg(c) => write!(f, "EPSG:{c}"),
            Crs::Wkt(w) => f.write_str(w),
        }
    }
}

/// The first EPSG code and the last of the geographic 2D systems by EPSG's numbering (4326
/// WGS 84, 4269 NAD83...); other codes are written as projected systems.
const EPSG_GEOGRAPHIC_2D: std::ops::RangeInclusive<u32> = 4001..=4999;

impl Crs {
    /// A local engineering grid in metres named `name` ([`UNKNOWN_CRS_NAME`],
    /// [`PLANNING_FRAME_NAME`]): what results without a CRS are written in, and say so.
    ///
    /// ```
    /// use rappel_terrain::crs::{Crs, UNKNOWN_CRS_NAME};
    /// assert!(Crs::local(UNKNOWN_CRS_NAME).to_string().starts_with("LOCAL_CS[\"DEM coordinates"));
    /// ```
    pub fn local(name: &str) -> Crs {
        Crs::Wkt(local_cs(name, &linear_unit(9001, 1.0)))
    }

    /// Reads the text form: `EPSG:n` (any case), else WKT (a WKT 1 whose root carries
    /// `AUTHORITY["EPSG","n"]` is that code); a text that is neither (a bare name) is a local
    /// grid of that name ([`Crs::local`]). `None` for an empty text.
    ///
    /// ```
    /// use rappel_terrain::crs::Crs;
    /// assert_eq!(Crs::parse("epsg:32610"), Some(Crs::Epsg(32610)));
    /// let wkt = r#"PROJCS["WGS 84 / UTM zone 10N",GEOGCS["WGS 84"],AUTHORITY["EPSG","32610"]]"#;
    /// assert_eq!(Crs::parse(wkt), Some(Crs::Epsg(32610)));
    /// assert!(matches!(Crs::parse(r#"LOCAL_CS["site"]"#), Some(Crs::Wkt(_))));
    /// assert_eq!(Crs::parse("Equirectangular MARS").unwrap().describe(), "LOCAL_CS \"Equirectangular MARS\"");
    /// ```
    pub fn parse(text: &str) -> Option<Crs> {
        let t = text.trim();
        if t.is_empty() {
            return None;
        }
        if let Some(code) = t
            .get(..5)
            .filter(|p| p.eq_ignore_ascii_case("EPSG:"))
            .and_then(|_| t[5..].trim().parse::<u32>().ok())
        {
            return Some(Crs::Epsg(code));
        }
        match wkt::parse(t) {
            Ok(node) => match node.authority_epsg() {
                Some(code) => Some(Crs::Epsg(code)),
                None => Some(Crs::Wkt(t.to_string())),
            },
            // A bare name (scenarios written before issue 34 kept only a GeoTIFF citation): all
            // that is known is the name, so a local grid of that name.
            Err(_) => Some(Crs::local(t)),
        }
    }

    /// The GeoKeys that declare this CRS in a GeoTIFF (`RasterPixelIsArea`). An EPSG code in
    /// 4001..=4999 is written as a geographic system, any other as a projected one. A WKT is
    /// written from its `PROJCS` (projections of [`PROJECTIONS`], ESRI names too), `GEOGCS` or
    /// `LOCAL_CS`; anything else is a [`CrsError::Wkt`] (the caller then writes the WKT beside).
    ///
    /// ```
    /// use rappel_terrain::crs::{Crs, key, GeoKeyValue};
    /// let mars = r#"PROJCS["Mars eqc",GEOGCS["Mars 2000",DATUM["D_Mars_2000",SPHEROID["Mars_2000_IAU_IAG",3396190,169.894447223612]],PRIMEM["Reference_Meridian",0],UNIT["degree",0.0174532925199433]],PROJECTION["Equirectangular"],PARAMETER["standard_parallel_1",-30],PARAMETER["central_meridian",180],UNIT["metre",1]]"#;
    /// let keys = Crs::parse(mars).unwrap().to_geokeys().unwrap();
    /// assert_eq!(keys.get(key::COORD_TRANS), Some(&GeoKeyValue::Short(17)));
    /// // And back: the same system.
    /// let back = keys.to_crs().unwrap().unwrap().to_string();
    /// assert!(back.contains("PARAMETER[\"standard_parallel_1\",-30]"), "{back}");
    /// ```
    pub fn to_geokeys(&self) -> Result<GeoKeyDirectory, CrsError> {
        let mut keys = vec![(key::RASTER_TYPE, GeoKeyValue::Short(1))];
        let short = |id, v| (id, GeoKeyValue::Short(v));
        match self {
            Crs::Epsg(code) => {
                let c = u16::try_from(*code)
                    .ok()
                    .filter(|&c| c != USER_DEFINED)
                    .ok_or_else(|| {
                        CrsError::Wkt(format!("EPSG:{code} does not fit a GeoKey (1..32766)"))
                    })?;
                if EPSG_GEOGRAPHIC_2D.contains(code) {
                    keys.extend([short(key::MODEL_TYPE, 2), short(key::GEOGRAPHIC_TYPE, c)]);
                } else {
                    keys.extend([short(key::MODEL_TYPE, 1), short(key::PROJECTED_CS_TYPE, c)]);
                }
            }
            Crs::Wkt(text) => {
                let root = wkt::parse(text).map_err(CrsError::Wkt)?;
                match root.name.to_ascii_uppercase().as_str() {
                    "PROJCS" => {
                        keys.push(short(key::MODEL_TYPE, 1));
                        keys.extend(projcs_keys(&root)?);
                    }
                    "GEOGCS" => {
                        keys.push(short(key::MODEL_TYPE, 2));
                        keys.extend(geogcs_keys(&root)?);
                    }
                    "LOCAL_CS" => {
                        keys.push(short(key::MODEL_TYPE, 1));
                        keys.push((key::CITATION, GeoKeyValue::Ascii(root.label())));
                        keys.push(short(key::LINEAR_UNITS, linear_unit_code(&root)?));
                    }
                    other => {
                        return Err(CrsError::Wkt(format!(
                            "root `{other}`: only WKT 1 PROJCS, GEOGCS and LOCAL_CS are written as GeoKeys"
                        )));
                    }
                }
            }
        }
        Ok(GeoKeyDirectory { keys })
    }

    /// A one-line human description: `EPSG:n` or the WKT root's kind and name.
    ///
    /// ```
    /// use rappel_terrain::crs::Crs;
    /// assert_eq!(Crs::Epsg(4326).describe(), "EPSG:4326");
    /// assert_eq!(Crs::parse(r#"LOCAL_CS["site",UNIT["metre",1]]"#).unwrap().describe(), "LOCAL_CS \"site\"");
    /// ```
    pub fn describe(&self) -> String {
        match self {
            Crs::Epsg(c) => format!("EPSG:{c}"),
            Crs::Wkt(w) => match wkt::parse(w) {
                Ok(n) => format!("{} \"{}\"", n.name, n.label()),
                Err(_) => "WKT (unparsed)".into(),
            },
        }
    }
}

/// The EPSG linear unit code of a node's `UNIT` child (metre when absent).
fn linear_unit_code(node: &wkt::Node) -> Result<u16, CrsError> {
    let Some(unit) = node.child("UNIT") else {
        return Ok(9001);
    };
    let size = unit.number(1).unwrap_or(1.0);
    LINEAR_UNITS
        .iter()
        .find(|(_, _, s)| ((size - s) / s).abs() < UNIT_SIZE_TOLERANCE)
        .map(|(c, _, _)| *c)
        .ok_or_else(|| CrsError::Wkt(format!("linear unit of {size} m is not metre or foot")))
}

/// The geographic keys of a `GEOGCS` node (user-defined, or its EPSG authority code).
fn geogcs_keys(g: &wkt::Node) -> Result<Vec<(u16, GeoKeyValue)>, CrsError> {
    let short = |id, v| (id, GeoKeyValue::Short(v));
    if let Some(code) = g.authority_epsg().and_then(|c| u16::try_from(c).ok()) {
        return Ok(vec![short(key::GEOGRAPHIC_TYPE, code)]);
    }
    let datum = g
        .child("DATUM")
        .ok_or_else(|| CrsError::Wkt("GEOGCS without DATUM".into()))?;
    let sph = datum
        .child("SPHEROID")
        .ok_or_else(|| CrsError::Wkt("DATUM without SPHEROID".into()))?;
    let (a, inv_f) = match (sph.number(1), sph.number(2)) {
        (Some(a), Some(f)) if a > 0.0 && f >= 0.0 => (a, f),
        _ => return Err(CrsError::Wkt("SPHEROID needs a > 0 and 1/f >= 0".into())),
    };
    if let Some(u) = g.child("UNIT") {
        let size = u.number(1).unwrap_or(0.0);
        let deg = std::f64::consts::PI / 180.0;
        if ((size - deg) / deg).abs() > UNIT_SIZE_TOLERANCE {
            return Err(CrsError::Wkt(format!(
                "angular unit of {size} rad is not the degree"
            )));
        }
    }
    let pm = g.child("PRIMEM");
    let pm_long = pm.and_then(|p| p.number(1)).unwrap_or(0.0);
    let b = if inv_f == 0.0 { a } else { a - a / inv_f };
    let mut citation = format!(
        "GCS Name = {}|Datum = {}|Ellipsoid = {}",
        g.label(),
        datum.label(),
        sph.label()
    );
    if let Some(p) = pm {
        citation.push_str(&format!("|Primem = {}", p.label()));
    }
    let mut keys = vec![
        short(key::GEOGRAPHIC_TYPE, USER_DEFINED),
        (key::GEOG_CITATION, GeoKeyValue::Ascii(citation)),
        short(key::GEODETIC_DATUM, USER_DEFINED),
        short(key::ANGULAR_UNITS, DEGREE),
        short(key::ELLIPSOID, USER_DEFINED),
        (key::SEMI_MAJOR_AXIS, GeoKeyValue::Double(vec![a])),
    ];
    if inv_f == 0.0 {
        keys.push((key::SEMI_MINOR_AXIS, GeoKeyValue::Double(vec![b])));
    } else {
        keys.push((key::INV_FLATTENING, GeoKeyValue::Double(vec![inv_f])));
    }
    if pm_long != 0.0 {
        keys.push((key::PRIME_MERIDIAN_LONG, GeoKeyValue::Double(vec![pm_long])));
    }
    Ok(keys)
}

/// The projected keys of a `PROJCS` node.
fn projcs_keys(p: &wkt::Node) -> Result<Vec<(u16, GeoKeyValue)>, CrsError> {
    let short = |id, v| (id, GeoKeyValue::Short(v));
    if let Some(code) = p.authority_epsg().and_then(|c| u16::try_from(c).ok()) {
        return Ok(vec![short(key::PROJECTED_CS_TYPE, code)]);
    }
    let g = p
        .child("GEOGCS")
        .ok_or_else(|| CrsError::Wkt("PROJCS without GEOGCS".into()))?;
    let method = p
        .child("PROJECTION")
        .map(|n| n.label())
        .ok_or_else(|| CrsError::Wkt("PROJCS without PROJECTION".into()))?;
    let proj = PROJECTIONS
        .iter()
        .find(|q| {
            q.wkt_name.eq_ignore_ascii_case(&method)
                || q.aliases.iter().any(|a| a.eq_ignore_ascii_case(&method))
        })
        .ok_or_else(|| CrsError::Wkt(format!("projection `{method}` is not in the table")))?;
    let mut keys = vec![
        short(key::PROJECTED_CS_TYPE, USER_DEFINED),
        (key::CITATION, GeoKeyValue::Ascii(p.label())),
        short(key::PROJECTION, USER_DEFINED),
        short(key::COORD_TRANS, proj.coord_trans),
        short(key::LINEAR_UNITS, linear_unit_code(p)?),
    ];
    // Parameter names compare without case (ESRI writes `Central_Meridian`...); an absent one
    // takes the table's default, as GDAL does.
    for &(param, geo_key, default) in proj.params {
        let v = p
            .children("PARAMETER")
            .find(|n| n.label().eq_ignore_ascii_case(param))
            .and_then(|n| n.number(1))
            .unwrap_or(default);
        keys.push((geo_key, GeoKeyValue::Double(vec![v])));
    }
    keys.extend(geogcs_keys(g)?);
    Ok(keys)
}

/// A minimal WKT 1 reader: `NAME[arg, ...]` trees of quoted strings, numbers, bare words and
/// nodes (`(..)` brackets too).
mod wkt {
    /// One argument.
    #[derive(Debug, Clone, PartialEq)]
    pub enum Arg {
        Str(String),
        Num(f64),
        Word(String),
        Node(Node),
    }

    /// `NAME[args]`.
    #[derive(Debug, Clone, PartialEq)]
    pub struct Node {
        pub name: String,
        pub args: Vec<Arg>,
    }

    /// The deepest nesting accepted (WKT 1 nests 5 levels; a hostile text cannot recurse deeper).
    const MAX_DEPTH: usize = 32;

    impl Node {
        /// The first argument as text (the node's name in WKT terms).
        pub fn label(&self) -> String {
            match self.args.first() {
                Some(Arg::Str(s)) | Some(Arg::Word(s)) => s.clone(),
                _ => String::new(),
            }
        }
        /// Argument `i` as a number.
        pub fn number(&self, i: usize) -> Option<f64> {
            match self.args.get(i) {
                Some(Arg::Num(v)) => Some(*v),
                _ => None,
            }
        }
        pub fn children<'a>(&'a self, name: &'a str) -> impl Iterator<Item = &'a Node> + 'a {
            self.args.iter().filter_map(move |a| match a {
                Arg::Node(n) if n.name.eq_ignore_ascii_case(name) => Some(n),
                _ => None,
            })
        }
        pub fn child<'a>(&'a self, name: &'a str) -> Option<&'a Node> {
            self.children(name).next()
        }
        /// The code of a direct `AUTHORITY["EPSG","n"]` child.
        pub fn authority_epsg(&self) -> Option<u32> {
            let a = self.child("AUTHORITY")?;
            if !a.label().eq_ignore_ascii_case("EPSG") {
                return None;
            }
            match a.args.get(1)? {
                Arg::Str(s) | Arg::Word(s) => s.trim().parse().ok(),
                Arg::Num(v) if v.fract() == 0.0 && *v > 0.0 => Some(*v as u32),
                _ => None,
            }
        }
    }

    /// Parses one WKT node; the whole text must be consumed.
    pub fn parse(text: &str) -> Result<Node, String> {
        let b = text.as_bytes();
        let mut i = 0;
        let node = node(b, &mut i, 0)?;
        skip_ws(b, &mut i);
        if i != b.len() {
            return Err(format!("text after the WKT's end at byte {i}"));
        }
        Ok(node)
    }

    fn skip_ws(b: &[u8], i: &mut usize) {
        while *i < b.len() && b[*i].is_ascii_whitespace() {
            *i += 1;
        }
    }

    fn word(b: &[u8], i: &mut usize) -> String {
        let start = *i;
        while *i < b.len()
            && (b[*i].is_ascii_alphanumeric() || matches!(b[*i], b'_' | b'.' | b'-' | b'+'))
        {
            *i += 1;
        }
        String::from_utf8_lossy(&b[start..*i]).into_owned()
    }

    fn node(b: &[u8], i: &mut usize, depth: usize) -> Result<Node, String> {
        if depth > MAX_DEPTH {
            return Err(format!("nested deeper than {MAX_DEPTH} levels"));
        }
        skip_ws(b, i);
        let name = word(b, i);
        if name.is_empty() || !name.as_bytes()[0].is_ascii_alphabetic() {
            return Err(format!("a keyword expected at byte {i}"));
        }
        skip_ws(b, i);
        let close = match b.get(*i) {
            Some(b'[') => b']',
            Some(b'(') => b')',
            _ => return Err(format!("`[` expected after {name} at byte {i}")),
        };
        *i += 1;
        let mut args = Vec::new();
        loop {
            skip_ws(b, i);
            match b.get(*i) {
                Some(&c) if c == close && args.is_empty() => {
                    *i += 1;
                    return Ok(Node { name, args });
                }
                Some(b'"') => {
                    *i += 1;
                    let mut s = Vec::new();
                    loop {
                        match b.get(*i) {
                            Some(b'"') if b.get(*i + 1) == Some(&b'"') => {
                                s.push(b'"');
                                *i += 2;
                            }
                            Some(b'"') => {
                                *i += 1;
                                break;
                            }
                            Some(&c) => {
                                s.push(c);
                                *i += 1;
                            }
                            None => return Err("unterminated string".into()),
                        }
                    }
                    args.push(Arg::Str(String::from_utf8_lossy(&s).into_owned()));
                }
                Some(c) if c.is_ascii_digit() || matches!(c, b'-' | b'+' | b'.') => {
                    let w = word(b, i);
                    let v = w
                        .parse::<f64>()
                        .map_err(|_| format!("`{w}` is not a number (byte {i})"))?;
                    args.push(Arg::Num(v));
                }
                Some(c) if c.is_ascii_alphabetic() => {
                    let save = *i;
                    let w = word(b, i);
                    skip_ws(b, i);
                    if matches!(b.get(*i), Some(b'[') | Some(b'(')) {
                        *i = save;
                        args.push(Arg::Node(node(b, i, depth + 1)?));
                    } else {
                        args.push(Arg::Word(w));
                    }
                }
                _ => return Err(format!("unexpected input at byte {i}")),
            }
            skip_ws(b, i);
            match b.get(*i) {
                Some(b',') => *i += 1,
                Some(&c) if c == close => {
                    *i += 1;
                    return Ok(Node { name, args });
                }
                _ => return Err(format!("`,` or `{}` expected at byte {i}", close as char)),
            }
        }
    }
}
