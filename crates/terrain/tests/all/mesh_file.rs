//! Mesh files (OBJ through tobj, STL through stl_io, PLY through ply-rs-bw) into the validated mesh: welded topology and
//! distances against closed forms, and each kind of bad file a typed error naming the file.

use nalgebra::Point3;
use rappel_terrain::mesh::{MeshError, TriMesh};
use rappel_terrain::mesh_file::{MeshFileError, read_mesh, read_obj, read_ply, read_stl};
use std::path::PathBuf;

fn temp(name: &str, contents: &[u8]) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rappel-mesh-file-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, contents).unwrap();
    p
}

/// A 2 x 2 square at z = 1 as one quad (triangulated by the reader) plus a triangle sharing
/// its edge x = 2, tilted up to z = 2 at x = 3: 5 distinct positions, 3 triangles.
const OBJ: &str = "o ground\nv 0 0 1\nv 2 0 1\nv 2 2 1\nv 0 2 1\nf 1 2 3 4\no ramp\nv 2 0 1\nv 3 1 2\nv 2 2 1\nf 5 6 7\n";

#[test]
fn obj_is_triangulated_and_welded() {
    let m = read_obj(&temp("g.obj", OBJ.as_bytes())).unwrap();
    assert_eq!(m.triangles().len(), 3);
    assert_eq!(
        m.vertices().len(),
        5,
        "the ramp's two shared corners are welded"
    );
    // Above the square's interior: the distance to z = 1.
    let d = m.signed_distance(&Point3::new(0.5, 1.0, 1.7));
    assert!((d - 0.7).abs() < 1e-12, "{d}");
    assert_eq!(
        read_mesh(&temp("G.OBJ", OBJ.as_bytes()))
            .unwrap()
            .triangles()
            .len(),
        3
    );
}

#[test]
fn ascii_and_binary_stl_read_the_same_tetrahedron() {
    let v = [
        [0.0f32, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    // Outward-oriented faces of the tetrahedron.
    let faces = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
    let tris: Vec<stl_io::Triangle> = faces
        .iter()
        .map(|f| stl_io::Triangle {
            normal: stl_io::Normal::new([0.0, 0.0, 0.0]),
            vertices: f.map(|i| stl_io::Vertex::new(v[i])),
        })
        .collect();
    let mut bin = Vec::new();
    stl_io::write_stl(&mut bin, tris.iter()).unwrap();
    let mut ascii = String::from("solid t\n");
    for f in faces {
        ascii += "facet normal 0 0 0\nouter loop\n";
        for i in f {
            ascii += &format!("vertex {} {} {}\n", v[i][0], v[i][1], v[i][2]);
        }
        ascii += "endloop\nendfacet\n";
    }
    ascii += "endsolid t\n";
    for p in [temp("t.stl", &bin), temp("ta.stl", ascii.as_bytes())] {
        assert_is_the_unit_tetrahedron(&read_stl(&p).unwrap(), &p);
    }
}

/// `m` is the closed tetrahedron (0,0,0), (1,0,0), (0,1,0), (0,0,1) read from `p`: four vertices,
/// four faces, and signed distances from the closed forms.
fn assert_is_the_unit_tetrahedron(m: &TriMesh, p: &std::path::Path) {
    assert_eq!((m.vertices().len(), m.triangles().len()), (4, 4), "{p:?}");
    // Inside, 0.1 from the face z = 0 (the nearest): -0.1 (closed tetrahedron).
    let d = m.signed_distance(&Point3::new(0.2, 0.2, 0.1));
    assert!((d + 0.1).abs() < 1e-6, "{p:?}: {d}");
    // Outside below the base.
    let d = m.signed_distance(&Point3::new(0.2, 0.2, -0.5));
    assert!((d - 0.5).abs() < 1e-6, "{p:?}: {d}");
}

#[test]
fn bad_mesh_files_are_typed_errors_naming_the_file() {
    // A NaN coordinate: positioned at the welded vertex.
    let p = temp("nan.obj", b"v 0 0 0\nv 1 0 NaN\nv 0 1 0\nf 1 2 3\n");
    match read_obj(&p) {
        Err(MeshFileError::Mesh {
            path,
            source:
                MeshError::NonFiniteVertex {
                    vertex: 1,
                    axis: 'z',
                    ..
                },
        }) => {
            assert!(path.ends_with("nan.obj"))
        }
        Err(MeshFileError::Parse { path, .. }) => assert!(path.ends_with("nan.obj")),
        other => panic!("{other:?}"),
    }
    // Three triangles on one edge: not a 2-manifold.
    let p = temp(
        "fan.obj",
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n",
    );
    assert!(
        matches!(read_obj(&p), Err(MeshFileError::Mesh { .. })),
        "{:?}",
        read_obj(&p)
    );
    // A face naming a missing vertex.
    let p = temp("oob.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
    assert!(read_obj(&p).is_err());
    // Degenerate (collinear) triangle.
    let p = temp("flat.obj", b"v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
    assert!(matches!(
        read_obj(&p),
        Err(MeshFileError::Mesh {
            source: MeshError::DegenerateTriangle { .. },
            ..
        })
    ));
    // Empty.
    let p = temp("empty.obj", b"# nothing\n");
    assert!(matches!(
        read_obj(&p),
        Err(MeshFileError::Mesh {
            source: MeshError::Empty { .. },
            ..
        })
    ));
    // Garbage STL.
    let p = temp("junk.stl", b"this is not an stl file at all");
    assert!(matches!(
        read_stl(&p),
        Err(MeshFileError::Parse { format: "STL", .. })
    ));
    assert!(matches!(
        read_mesh(&temp("x.off", b"OFF\n")),
        Err(MeshFileError::Format { .. })
    ));
    let missing = read_mesh(std::path::Path::new("/nonexistent/ground.obj")).unwrap_err();
    assert!(matches!(missing, MeshFileError::Input(_)));
    assert!(
        missing.to_string().contains("/nonexistent/ground.obj"),
        "{missing}"
    );
}

/// Counts a file declares are checked before its data is read (issue 30): a binary STL whose
/// header disagrees with its size either way is refused naming both numbers, and a PLY header
/// declaring more faces than a mesh may have is refused before the parser allocates for them.
#[test]
fn declared_counts_are_checked_before_the_data() {
    // One triangle's worth of data (134 bytes) under headers saying 3 and 0 triangles.
    let stl = |count: u32, triangles: usize| {
        let mut b = vec![0u8; 80];
        b.extend(count.to_le_bytes());
        b.extend(std::iter::repeat_n(0u8, 50 * triangles));
        b
    };
    for (count, triangles) in [(3, 1), (0, 1), (1, 2)] {
        let e = read_stl(&temp("count.stl", &stl(count, triangles))).unwrap_err();
        let text = e.to_string();
        assert!(
            text.contains(&format!("the header says {count} triangles"))
                && text.contains(&format!("{} bytes", 84 + 50 * triangles)),
            "{text}"
        );
    }
    let huge = "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\nelement face 9000000\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    let e = read_ply(&temp("huge.ply", huge.as_bytes())).unwrap_err();
    assert!(
        matches!(e, MeshFileError::Parse { format: "PLY", .. })
            && e.to_string()
                .contains("9000000 triangles, more than the 4000000"),
        "{e}"
    );
}

/// The OBJ test's ground as an ASCII PLY: the square as one quad (fanned by the reader) and the
/// ramp triangle, whose two shared corners are listed again (welded).
const PLY_ASCII: &str = "ply\nformat ascii 1.0\ncomment ground\nelement vertex 7\nproperty double x\nproperty double y\nproperty double z\nproperty uchar red\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 1 9\n2 0 1 9\n2 2 1 9\n0 2 1 9\n2 0 1 9\n3 1 2 9\n2 2 1 9\n4 0 1 2 3\n3 4 5 6\n";

#[test]
fn ascii_ply_is_fanned_and_welded() {
    for name in ["g.ply", "G.PLY"] {
        let m = read_mesh(&temp(name, PLY_ASCII.as_bytes())).unwrap();
        assert_eq!((m.vertices().len(), m.triangles().len()), (5, 3), "{name}");
        // Above the square's interior: the distance to z = 1; above the ramp's far corner.
        let d = m.signed_distance(&Point3::new(0.5, 1.0, 1.7));
        assert!((d - 0.7).abs() < 1e-12, "{d}");
        let d = m.signed_distance(&Point3::new(3.0, 1.0, 2.5));
        assert!((d - 0.5).abs() < 1e-12, "{d}");
    }
}

/// The STL test's tetrahedron as a binary PLY in the given byte order, `float` coordinates and
/// `uchar`-counted `int` index lists, written byte by byte here (not by the reader's crate).
fn binary_tetrahedron(big_endian: bool) -> Vec<u8> {
    let v = [
        [0.0f32, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let faces = [[0i32, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
    let order = if big_endian { "big" } else { "little" };
    let mut b = format!(
        "ply\nformat binary_{order}_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n"
    )
    .into_bytes();
    for p in v {
        for c in p {
            b.extend(if big_endian {
                c.to_be_bytes()
            } else {
                c.to_le_bytes()
            });
        }
    }
    for f in faces {
        b.push(3);
        for i in f {
            b.extend(if big_endian {
                i.to_be_bytes()
            } else {
                i.to_le_bytes()
            });
        }
    }
    b
}

#[test]
fn binary_ply_in_both_byte_orders_reads_the_tetrahedron() {
    for big in [false, true] {
        let p = temp(&format!("t{big}.ply"), &binary_tetrahedron(big));
        assert_is_the_unit_tetrahedron(&read_ply(&p).unwrap(), &p);
    }
}

#[test]
fn bad_ply_files_are_typed_errors_naming_the_file_and_the_place() {
    let header = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
    let faces =
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n";
    let parse_error =
        |name: &str, text: String, needle: &str| match read_ply(&temp(name, text.as_bytes())) {
            Err(e @ MeshFileError::Parse { .. }) => {
                let msg = e.to_string();
                assert!(msg.contains(name) && msg.contains(needle), "{msg}");
            }
            other => panic!("{name}: {other:?}"),
        };
    // No face element at all.
    parse_error(
        "noface.ply",
        format!("{header}end_header\n0 0 0\n1 0 0\n0 1 0\n"),
        "no `face` element",
    );
    // A face of two vertices; a negative index.
    parse_error(
        "two.ply",
        format!("{header}{faces}2 0 1\n"),
        "face 0: 2 vertices",
    );
    parse_error("neg.ply", format!("{header}{faces}3 0 1 -1\n"), "face 0");
    // A vertex without z.
    parse_error(
        "noz.ply",
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0\n1 0\n0 1\n3 0 1 2\n".into(),
        "vertex 0: no numeric `z`",
    );
    // Not a PLY file; a binary file cut short.
    parse_error("junk.ply", "solid nothing\n".into(), "PLY");
    let mut cut = binary_tetrahedron(false);
    cut.truncate(cut.len() - 7);
    parse_error("empty.ply", String::new(), "PLY");
    match read_ply(&temp("cut2.ply", &cut)) {
        Err(MeshFileError::Parse { path, .. }) => assert!(path.ends_with("cut2.ply")),
        other => panic!("{other:?}"),
    }
    // An index past the vertices: refused by the mesh, positioned by triangle.
    match read_ply(&temp(
        "oob.ply",
        format!("{header}{faces}3 0 1 7\n").as_bytes(),
    )) {
        Err(MeshFileError::Mesh { path, .. }) => assert!(path.ends_with("oob.ply")),
        other => panic!("{other:?}"),
    }
}
