//! Triangle meshes from files (issue 14): Wavefront OBJ through `tobj` and STL (ASCII or binary)
//! through `stl_io`, into the validated [`TriMesh`]. Polygons are triangulated by the reader;
//! exactly equal positions are welded into one vertex (STL stores triangle soup; OBJ objects
//! repeat shared vertices), so edges shared by neighbouring faces are shared in the mesh and
//! [`TriMesh::new`]'s manifold checks apply. Materials, normals and texture coordinates are
//! ignored. Every failure names the file; mesh defects keep the mesh's vertex or triangle index.

use std::collections::HashMap;
use std::io::BufReader;
use std::path::Path;

use nalgebra::Point3;

use crate::mesh::{MeshError, TriMesh};

/// Largest mesh file read, bytes (1 GiB: well over [`crate::mesh::MAX_TRIANGLES`] binary STL
/// triangles of 50 bytes); a larger file is refused before reading.
pub const MAX_MESH_FILE_BYTES: u64 = 1 << 30;

/// Why a mesh file could not be turned into a mesh.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshFileError {
    /// The file cannot be opened or read, or is too large.
    #[error("{path}: {why}")]
    Read {
        /// The file.
        path: String,
        /// What went wrong.
        why: String,
    },
    /// The reader refused the contents.
    #[error("{path}: not a readable {format} file: {why}")]
    Parse {
        /// The file.
        path: String,
        /// `OBJ` or `STL`.
        format: &'static str,
        /// The reader's message.
        why: String,
    },
    /// The contents are not a valid mesh (positioned by vertex or triangle index after welding).
    #[error("{path}: {source}")]
    Mesh {
        /// The file.
        path: String,
        /// The defect.
        source: MeshError,
    },
    /// An extension other than `.obj` or `.stl`.
    #[error("{path}: unknown mesh format (use .obj or .stl)")]
    Format {
        /// The file.
        path: String,
    },
}

/// Welds exactly equal positions (bitwise, after `-0.0 -> 0.0`) and builds the validated mesh.
fn weld(
    path: &Path,
    positions: impl Iterator<Item = [f64; 3]>,
    triangles: Vec<[usize; 3]>,
) -> Result<TriMesh, MeshFileError> {
    let mut index: HashMap<[u64; 3], usize> = HashMap::new();
    let mut vertices = Vec::new();
    let mut remap = Vec::new();
    for p in positions {
        let key = p.map(|c| (c + 0.0).to_bits());
        let k = *index.entry(key).or_insert_with(|| {
            vertices.push(Point3::from(p));
            vertices.len() - 1
        });
        remap.push(k);
    }
    let triangles = triangles
        .into_iter()
        .map(|t| t.map(|i| remap.get(i).copied().unwrap_or(usize::MAX)))
        .collect();
    TriMesh::new(vertices, triangles).map_err(|source| MeshFileError::Mesh {
        path: path.display().to_string(),
        source,
    })
}

fn open(path: &Path) -> Result<std::fs::File, MeshFileError> {
    let err = |why: String| MeshFileError::Read {
        path: path.display().to_string(),
        why,
    };
    let f = std::fs::File::open(path).map_err(|e| err(e.to_string()))?;
    let len = f.metadata().map_err(|e| err(e.to_string()))?.len();
    if len > MAX_MESH_FILE_BYTES {
        return Err(err(format!(
            "{len} bytes exceeds the mesh file limit of {MAX_MESH_FILE_BYTES}"
        )));
    }
    Ok(f)
}

/// A Wavefront OBJ file: every object's faces (triangulated) in one mesh.
pub fn read_obj(path: &Path) -> Result<TriMesh, MeshFileError> {
    let mut r = BufReader::new(open(path)?);
    let opts = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        ..Default::default()
    };
    let (models, _) = tobj::load_obj_buf(&mut r, &opts, |_| Err(tobj::LoadError::OpenFileFailed))
        .map_err(|e| MeshFileError::Parse {
        path: path.display().to_string(),
        format: "OBJ",
        why: e.to_string(),
    })?;
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    for m in &models {
        let base = positions.len();
        positions.extend(m.mesh.positions.chunks_exact(3).map(|c| [c[0], c[1], c[2]]));
        triangles.extend(
            m.mesh
                .indices
                .chunks_exact(3)
                .map(|t| [0, 1, 2].map(|k| base + t[k] as usize)),
        );
    }
    weld(path, positions.into_iter(), triangles)
}

/// An STL file (ASCII or binary).
pub fn read_stl(path: &Path) -> Result<TriMesh, MeshFileError> {
    let mut r = BufReader::new(open(path)?);
    let m = stl_io::read_stl(&mut r).map_err(|e| MeshFileError::Parse {
        path: path.display().to_string(),
        format: "STL",
        why: e.to_string(),
    })?;
    let triangles = m.faces.iter().map(|f| f.vertices).collect();
    weld(
        path,
        m.vertices.iter().map(|v| v.0.map(f64::from)),
        triangles,
    )
}

/// A mesh file by its extension (`.obj` or `.stl`, any case).
pub fn read_mesh(path: &Path) -> Result<TriMesh, MeshFileError> {
    match path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .as_deref()
    {
        Some("obj") => read_obj(path),
        Some("stl") => read_stl(path),
        _ => Err(MeshFileError::Format {
            path: path.display().to_string(),
        }),
    }
}
