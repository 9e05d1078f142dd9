//! Reading a digital elevation model (thesis §2.5.1) from a file: [`read_dem`] picks the reader
//! by the file's extension, an ESRI ASCII grid ([`crate::esri_ascii`]) or a GeoTIFF
//! ([`crate::geotiff`]), and [`dem_crs`] reads the file's coordinate reference system. The grid
//! they return, its conventions and its limits are in [`crate::grid`].

use std::path::{Path, PathBuf};

use crate::esri_ascii::{EsriAsciiError, parse_esri_ascii_with};
use crate::geotiff::{GeoTiffError, decode_geotiff_with};
use crate::grid::{DemLimits, HeightGrid};

/// Why a DEM file could not be read; every variant names the file.
#[derive(Debug, thiserror::Error)]
pub enum DemError {
    /// The file was not read: not a regular file, over the input size cap, not text
    /// ([`crate::input`]).
    #[error(transparent)]
    Input(#[from] crate::input::InputError),
    /// The file could not be opened or read.
    #[error("{}: cannot read the file: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The system error.
        source: std::io::Error,
    },
    /// The extension is not one of `.asc`, `.tif`, `.tiff`. Fix: rename the file or convert it.
    #[error("{}: unknown DEM format; expected an ESRI ASCII grid (.asc) or a GeoTIFF (.tif, .tiff)", path.display())]
    UnknownFormat {
        /// The file.
        path: PathBuf,
    },
    /// A malformed ESRI ASCII grid (the source names the line).
    #[error("{}: {source}", path.display())]
    EsriAscii {
        /// The file.
        path: PathBuf,
        /// What is wrong and where.
        source: EsriAsciiError,
    },
    /// A malformed or unsupported GeoTIFF.
    #[error("{}: {source}", path.display())]
    GeoTiff {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        source: GeoTiffError,
    },
}

/// Reads a DEM, choosing the reader by extension (case-insensitive): `.asc` for an ESRI ASCII grid
/// ([`crate::esri_ascii`]), `.tif` / `.tiff` for a single-band GeoTIFF
/// ([`crate::geotiff`]).
///
/// ```
/// use rappel_terrain::dem::read_dem;
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/terrain/mars_hirise_dteec_010228_1490_crop.asc");
/// let dem = read_dem(path).unwrap();
/// assert_eq!((dem.geometry().nrows, dem.geometry().ncols), (120, 70));
/// assert!(read_dem("terrain.png").is_err());
/// ```
pub fn read_dem(path: impl AsRef<Path>) -> Result<HeightGrid, DemError> {
    read_dem_with(path, &DemLimits::default())
}

/// Longest `.prj` file read beside an ESRI ASCII grid, bytes (a WKT definition is a few kB).
const MAX_PRJ_BYTES: u64 = 64 * 1024;

/// The coordinate reference system of the DEM at `path`, when its file says: a GeoTIFF's GeoKeys
/// ([`crate::geotiff::geotiff_crs`]: `EPSG:n` or the WKT of a user-defined system), or for an
/// ESRI ASCII grid the WKT of the `.prj` file beside it (same stem). `None` when neither says.
///
/// ```
/// use rappel_terrain::dem::dem_crs;
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/terrain/mars_hirise_dteec_010228_1490_crop.asc");
/// assert_eq!(dem_crs(path.as_ref()).unwrap(), None);
/// ```
pub fn dem_crs(path: &Path) -> Result<Option<String>, DemError> {
    read_dem_crs(path).map(|c| c.crs)
}

/// A DEM's coordinate reference system and the GeoKeys its file holds that the CRS does not use.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct DemCrs {
    /// `EPSG:n` or a WKT; `None` when the file declares none.
    pub crs: Option<String>,
    /// One message per GeoKey present and not used
    /// ([`crate::crs::GeoKeyDirectory::ignored_keys`]); empty for an ESRI ASCII grid.
    pub ignored: Vec<String>,
}

/// [`dem_crs`] with the GeoKeys present that it does not use (vertical CRS keys, projection
/// parameters the system does not take, a linear unit other than the metre), so a caller can
/// say so.
///
/// ```
/// use rappel_terrain::dem::read_dem_crs;
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/terrain/earth_mt_st_helens_utm10n.tif");
/// let c = read_dem_crs(path.as_ref()).unwrap();
/// assert_eq!(c.crs.as_deref(), Some("EPSG:32610"));
/// assert!(c.ignored.is_empty());
/// ```
pub fn read_dem_crs(path: &Path) -> Result<DemCrs, DemError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("tif") | Some("tiff") => {
            let (file, _) = crate::input::open_input(path, crate::input::max_input_bytes()?)?;
            crate::geotiff::geotiff_crs_and_ignored(std::io::BufReader::new(file))
                .map(|(c, ignored)| DemCrs {
                    crs: c.map(|c| c.to_string()),
                    ignored,
                })
                .map_err(|source| DemError::GeoTiff {
                    path: path.to_path_buf(),
                    source,
                })
        }
        Some("asc") => {
            let prj = path.with_extension("prj");
            if !prj.exists() {
                return Ok(DemCrs::default());
            }
            let (file, _) = crate::input::open_input(&prj, crate::input::max_input_bytes()?)?;
            let mut text = String::new();
            std::io::Read::read_to_string(&mut std::io::Read::take(file, MAX_PRJ_BYTES), &mut text)
                .map_err(|source| DemError::Io { path: prj, source })?;
            let text = text.trim();
            Ok(DemCrs {
                crs: (!text.is_empty()).then(|| text.to_string()),
                ignored: Vec::new(),
            })
        }
        _ => Err(DemError::UnknownFormat {
            path: path.to_path_buf(),
        }),
    }
}

/// [`read_dem`] under explicit [`DemLimits`].
///
/// ```
/// use rappel_terrain::dem::read_dem_with;
/// use rappel_terrain::grid::DemLimits;
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/terrain/mars_hirise_dteec_010228_1490_crop.tif");
/// // 120 x 70 cells: over a cap of 8,000, within one of 8,400.
/// assert!(read_dem_with(path, &DemLimits::with_max_cells(8_000).unwrap()).is_err());
/// assert!(read_dem_with(path, &DemLimits::with_max_cells(8_400).unwrap()).is_ok());
/// ```
pub fn read_dem_with(path: impl AsRef<Path>, limits: &DemLimits) -> Result<HeightGrid, DemError> {
    let path = path.as_ref();
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let is_tiff = match ext.as_deref() {
        Some("asc") => false,
        Some("tif") | Some("tiff") => true,
        _ => {
            return Err(DemError::UnknownFormat {
                path: path.to_path_buf(),
            });
        }
    };
    let bytes = crate::input::read_input(path, crate::input::max_input_bytes()?)?;
    if is_tiff {
        decode_geotiff_with(std::io::Cursor::new(bytes), limits).map_err(|source| {
            DemError::GeoTiff {
                path: path.to_path_buf(),
                source,
            }
        })
    } else {
        parse_esri_ascii_with(&bytes, limits).map_err(|source| DemError::EsriAscii {
            path: path.to_path_buf(),
            source,
        })
    }
}
