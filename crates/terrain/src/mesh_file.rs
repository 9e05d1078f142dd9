//! Triangle meshes from files (issue 14): Wavefront OBJ through `tobj`, STL (ASCII or binary)
//! through `stl_io` and PLY (ASCII or binary, either byte order) through `ply-rs-bw`, into the
//! validated [`TriMesh`]. Polygons are triangulated by the reader (PLY faces: fanned from their
//! first vertex, exact for the convex faces mesh exporters write);
//! exactly equal positions are welded into one vertex (STL stores triangle soup; OBJ objects
//! repeat shared vertices), so edges shared by neighbouring faces are shared in the mesh and
//! [`TriMesh::new`]'s manifold checks apply. Materials, normals, colours and texture coordinates
//! (and a PLY file's elements other than `vertex` and `face`) are ignored. Every failure names the file; mesh defects keep the mesh's vertex or triangle index.

use std::collections::HashMap;
use std::io::BufReader;
use std::path::Path;

use nalgebra::Point3;

use crate::mesh::{MAX_TRIANGLES, MeshError, TriMesh};

/// Why a mesh file could not be turned into a mesh.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshFileError {
    /// The file was not read: not a regular file, or over the input size cap
    /// ([`crate::input`]; the message names the file).
    #[error("{0}")]
    Input(String),
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
        /// `OBJ`, `PLY` or `STL`.
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
    /// An extension other than `.obj`, `.ply` or `.stl`.
    #[error("{path}: unknown mesh format (use .obj, .ply or .stl)")]
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
    let cap = crate::input::max_input_bytes().map_err(|e| err(e.to_string()))?;
    crate::input::open_input(path, cap)
        .map(|(f, _)| f)
        .map_err(|e| MeshFileError::Input(e.to_string()))
}

/// Refuses a file whose triangle count, known before the mesh is built, is over
/// [`MAX_TRIANGLES`]: checked from the header (STL, PLY) or a streaming count (OBJ) before the
/// reader allocates for the data.
fn check_count(path: &Path, format: &'static str, triangles: u64) -> Result<(), MeshFileError> {
    if triangles > MAX_TRIANGLES as u64 {
        return Err(MeshFileError::Parse {
            path: path.display().to_string(),
            format,
            why: format!(
                "{triangles} triangles, more than the {MAX_TRIANGLES} a mesh may have; decimate or crop it"
            ),
        });
    }
    Ok(())
}

/// The triangles an OBJ file's faces make (a face of `n` vertices gives `n - 2`), counted by
/// streaming its lines (memory: one line).
fn obj_triangles(path: &Path) -> Result<u64, MeshFileError> {
    use std::io::BufRead;
    let mut r = BufReader::new(open(path)?);
    let (mut line, mut count) = (String::new(), 0u64);
    loop {
        line.clear();
        let n = r.read_line(&mut line).map_err(|e| MeshFileError::Read {
            path: path.display().to_string(),
            why: e.to_string(),
        })?;
        if n == 0 {
            return Ok(count);
        }
        let mut words = line.split_whitespace();
        if words.next() == Some("f") {
            count = count.saturating_add((words.count() as u64).saturating_sub(2));
        }
    }
}

/// A binary STL's triangle count from its header, checked against the file's size (84 bytes of
/// header and count, 50 bytes a triangle); `None` for an ASCII STL (it begins with `solid` and
/// its size is not the binary size of its count).
fn binary_stl_count(path: &Path) -> Result<Option<u64>, MeshFileError> {
    use std::io::Read;
    let mut f = open(path)?;
    let len = f
        .metadata()
        .map_err(|e| MeshFileError::Read {
            path: path.display().to_string(),
            why: e.to_string(),
        })?
        .len();
    let mut head = [0u8; 84];
    let parse = |why: String| MeshFileError::Parse {
        path: path.display().to_string(),
        format: "STL",
        why: one_line(&why),
    };
    if len < 84 {
        let mut start = Vec::new();
        let _ = f.read_to_end(&mut start);
        return if start.trim_ascii_start().starts_with(b"solid") {
            Ok(None)
        } else {
            Err(parse(format!(
                "{len} bytes: too short for a binary STL (84 bytes of header and count)"
            )))
        };
    }
    f.read_exact(&mut head).map_err(|e| parse(e.to_string()))?;
    let count = u64::from(u32::from_le_bytes([head[80], head[81], head[82], head[83]]));
    let expected = 84 + 50 * count;
    if head.trim_ascii_start().starts_with(b"solid") && expected != len {
        return Ok(None);
    }
    if expected != len {
        return Err(parse(format!(
            "the header says {count} triangles ({expected} bytes), but the file has {len} bytes (room for {} triangles)",
            (len - 84) / 50
        )));
    }
    Ok(Some(count))
}

/// The `face` count a PLY header declares (its lines up to `end_header`, at most
/// [`MAX_PLY_HEADER_BYTES`]); `None` when it declares none (the reader then refuses the file).
fn ply_faces(path: &Path) -> Result<Option<u64>, MeshFileError> {
    use std::io::{BufRead, Read};
    let mut r = BufReader::new(open(path)?);
    let (mut line, mut read) = (String::new(), 0usize);
    let mut faces = None;
    while read < MAX_PLY_HEADER_BYTES {
        line.clear();
        let mut bytes = Vec::new();
        let n = r
            .by_ref()
            .take(MAX_PLY_HEADER_BYTES as u64)
            .read_until(b'\n', &mut bytes)
            .map_err(|e| MeshFileError::Read {
                path: path.display().to_string(),
                why: e.to_string(),
            })?;
        if n == 0 {
            break;
        }
        read += n;
        line.push_str(&String::from_utf8_lossy(&bytes));
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.as_slice() {
            ["end_header"] => break,
            ["element", "face", n] => faces = n.parse::<u64>().ok(),
            _ => {}
        }
    }
    Ok(faces)
}

/// Most bytes of a PLY header read for its counts.
pub const MAX_PLY_HEADER_BYTES: usize = 1 << 16;

/// A Wavefront OBJ file: every object's faces (triangulated) in one mesh.
pub fn read_obj(path: &Path) -> Result<TriMesh, MeshFileError> {
    check_count(path, "OBJ", obj_triangles(path)?)?;
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
        why: one_line(&e.to_string()),
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
    if let Some(count) = binary_stl_count(path)? {
        check_count(path, "STL", count)?;
    }
    let mut r = BufReader::new(open(path)?);
    let m = stl_io::read_stl(&mut r).map_err(|e| MeshFileError::Parse {
        path: path.display().to_string(),
        format: "STL",
        why: one_line(&e.to_string()),
    })?;
    let triangles = m.faces.iter().map(|f| f.vertices).collect();
    weld(
        path,
        m.vertices.iter().map(|v| v.0.map(f64::from)),
        triangles,
    )
}

/// A third-party reader's message as one printable line: its first line, without control
/// characters, cut before any Debug dump of the reader's internals (`ParseError { ... }`) and
/// at [`MAX_READER_MESSAGE`] characters.
fn one_line(why: &str) -> String {
    let first = why.lines().next().unwrap_or("").trim();
    let first = first.split(" { ").next().unwrap_or(first);
    let clean: String = first.chars().filter(|c| !c.is_control()).collect();
    if clean.chars().count() > MAX_READER_MESSAGE {
        let cut: String = clean.chars().take(MAX_READER_MESSAGE).collect();
        format!("{cut}...")
    } else {
        clean
    }
}

/// The longest reader message kept, characters.
const MAX_READER_MESSAGE: usize = 200;

/// A PLY file (ASCII, binary little or big endian): the `vertex` element's numeric `x`, `y`, `z`
/// and the `face` element's `vertex_indices` (or `vertex_index`) lists, each face fanned into
/// triangles from its first vertex. A missing element or property, a face of fewer than three
/// vertices or a negative index is a [`MeshFileError::Parse`] naming the face or vertex; an index
/// past the vertices is refused by the mesh with its triangle.
pub fn read_ply(path: &Path) -> Result<TriMesh, MeshFileError> {
    use ply_rs_bw::parser::Parser;
    use ply_rs_bw::ply::{DefaultElement, Property};
    let parse = |why: String| MeshFileError::Parse {
        path: path.display().to_string(),
        format: "PLY",
        why: one_line(&why),
    };
    if let Some(faces) = ply_faces(path)? {
        check_count(path, "PLY", faces)?;
    }
    let mut f = open(path)?;
    let ply = Parser::<DefaultElement>::new()
        .read_ply(&mut f)
        .map_err(|e| parse(e.to_string()))?;
    let scalar = |p: &Property| -> Option<f64> {
        Some(match *p {
            Property::Char(v) => v.into(),
            Property::UChar(v) => v.into(),
            Property::Short(v) => v.into(),
            Property::UShort(v) => v.into(),
            Property::Int(v) => v.into(),
            Property::UInt(v) => v.into(),
            Property::Float(v) => v.into(),
            Property::Double(v) => v,
            _ => return None,
        })
    };
    fn indices<T: Copy + TryInto<usize>>(list: &[T]) -> Option<Vec<usize>> {
        list.iter().map(|&i| i.try_into().ok()).collect()
    }
    let index_list = |p: &Property| -> Option<Vec<usize>> {
        match p {
            Property::ListChar(l) => indices(l),
            Property::ListUChar(l) => indices(l),
            Property::ListShort(l) => indices(l),
            Property::ListUShort(l) => indices(l),
            Property::ListInt(l) => indices(l),
            Property::ListUInt(l) => indices(l),
            _ => None,
        }
    };
    let vertices = ply
        .payload
        .get("vertex")
        .ok_or_else(|| parse("no `vertex` element".into()))?;
    let mut positions = Vec::with_capacity(vertices.len());
    for (i, v) in vertices.iter().enumerate() {
        let mut c = [0.0; 3];
        for (k, name) in ["x", "y", "z"].into_iter().enumerate() {
            c[k] = v
                .get(name)
                .and_then(scalar)
                .ok_or_else(|| parse(format!("vertex {i}: no numeric `{name}` property")))?;
        }
        positions.push(c);
    }
    let faces = ply
        .payload
        .get("face")
        .ok_or_else(|| parse("no `face` element".into()))?;
    // Each face of n vertices gives n - 2 triangles: bounded by the file's size.
    let mut triangles = Vec::with_capacity(faces.len());
    for (i, face) in faces.iter().enumerate() {
        let list = face
            .get("vertex_indices")
            .or_else(|| face.get("vertex_index"))
            .ok_or_else(|| parse(format!("face {i}: no `vertex_indices` list")))?;
        let idx = index_list(list).ok_or_else(|| {
            parse(format!(
                "face {i}: `vertex_indices` is not a list of non-negative integers"
            ))
        })?;
        if idx.len() < 3 {
            return Err(parse(format!(
                "face {i}: {} vertices, a face needs at least 3",
                idx.len()
            )));
        }
        triangles.extend((1..idx.len() - 1).map(|k| [idx[0], idx[k], idx[k + 1]]));
    }
    weld(path, positions.into_iter(), triangles)
}

/// A mesh file by its extension (`.obj`, `.ply` or `.stl`, any case).
pub fn read_mesh(path: &Path) -> Result<TriMesh, MeshFileError> {
    match path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .as_deref()
    {
        Some("obj") => read_obj(path),
        Some("ply") => read_ply(path),
        Some("stl") => read_stl(path),
        _ => Err(MeshFileError::Format {
            path: path.display().to_string(),
        }),
    }
}
