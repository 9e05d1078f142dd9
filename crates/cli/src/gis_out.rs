//! GIS outputs (issue 34), each saying on stderr what it wrote and in which CRS: the GeoTIFF
//! results of `stability`, `dem` and `settle-map` (`--geotiff OUT.tif`: the file, GDAL's
//! `OUT.tif.aux.xml` sidecar when the CRS needs one, a stale sidecar from an earlier export
//! removed since GDAL would read it before the keys just written), and the vector exports of
//! `plan` and `online` (`--export OUT.fgb|.geojson|.csv`).

use crate::output::{CliError, write_bytes, write_file};
use rappel::terrain::geotiff_writer::GeoTiffImage;
use rappel_render::export::ExportFormat;
use std::path::{Path, PathBuf};

/// A `--geotiff` output and its sidecar's path.
pub struct GeoTiffOut {
    /// The option that named it (`--geotiff`).
    flag: &'static str,
    /// The flag as the sidecar's name in messages.
    aux_flag: String,
    /// `OUT.tif`.
    path: PathBuf,
    /// `OUT.tif.aux.xml`.
    aux: PathBuf,
}

impl GeoTiffOut {
    /// The output `path` given to option `flag`.
    pub fn new(flag: &'static str, path: &Path) -> GeoTiffOut {
        let mut aux = path.as_os_str().to_os_string();
        aux.push(".aux.xml");
        GeoTiffOut {
            flag,
            aux_flag: format!("{flag}'s .aux.xml"),
            path: path.to_path_buf(),
            aux: PathBuf::from(aux),
        }
    }

    /// The two files it may write, for [`crate::output::refuse_clashing_outputs`].
    pub fn outputs(&self) -> [(&str, &Path); 2] {
        [
            (self.flag, self.path.as_path()),
            (self.aux_flag.as_str(), self.aux.as_path()),
        ]
    }

    /// Writes `image` (and its sidecar, or removes a stale one) and says on stderr
    /// `wrote OUT.tif: WHAT, CRS ...`.
    pub fn write(&self, image: &GeoTiffImage, what: &str) -> Result<(), CliError> {
        write_bytes(&self.path, &image.bytes)?;
        match &image.aux_xml {
            Some(xml) => write_file(&self.aux, xml)?,
            None if self.aux.exists() => std::fs::remove_file(&self.aux).map_err(|e| {
                CliError(format!(
                    "{}: cannot remove the stale sidecar: {e}",
                    self.aux.display()
                ))
            })?,
            None => {}
        }
        eprintln!(
            "wrote {}: {what}, CRS {}{}",
            self.path.display(),
            image.crs_written,
            if image.aux_xml.is_some() {
                " (WKT in the .aux.xml beside it)"
            } else {
                ""
            }
        );
        Ok(())
    }

    /// `--geotiff OUT.tif: ` before a message.
    pub fn context(&self) -> String {
        format!("{} {}", self.flag, self.path.display())
    }
}

/// The format of `--export OUT` by its extension (`.fgb`, `.geojson` or `.csv`).
pub fn export_format(out: &Path) -> Result<ExportFormat, CliError> {
    ExportFormat::of_path(out).ok_or_else(|| {
        CliError(format!(
            "--export {}: unknown format; use a .fgb, .geojson or .csv file",
            out.display()
        ))
    })
}

/// Writes a vector export's bytes to `out` and says on stderr `wrote OUT: WHAT, CRS ...`
/// ([`rappel_render::export::crs_note`]: the planning frame or "CRS unknown" named when there
/// is no CRS).
pub fn write_export(
    out: &Path,
    bytes: &[u8],
    geo: Option<&rappel::georeference::Georeference>,
    format: ExportFormat,
    what: &str,
) -> Result<(), CliError> {
    write_bytes(out, bytes)?;
    eprintln!(
        "wrote {}: {what}, CRS {}",
        out.display(),
        rappel_render::export::crs_note(geo, format)
    );
    Ok(())
}
