//! The BTM's invariants, checked exactly where they are combinatorial and with a named relative
//! tolerance where they compare floating-point areas. Property tests and `cargo xtask regress`
//! run this check after every build and every sequence of updates.

use super::Btm;
use crate::dcel::{FaceKind, HalfEdgeId, NONE};
use crate::predicates::{incircle, orient2d};
use nalgebra::Point2;
use serde::Serialize;

/// Relative tolerance when comparing the summed triangle areas with the map's free area: both
/// are floating-point sums of many terms (shoelace and per-triangle cross products), so they
/// agree to rounding error, about `n * eps` relative; 1e-9 leaves ample room for 10^6 triangles.
pub const AREA_REL_TOL: f64 = 1e-9;

/// Figures from a successful invariant check.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct InvariantReport {
    /// Map vertices n.
    pub vertices: usize,
    /// Holes h.
    pub holes: usize,
    /// Free triangles.
    pub triangles: usize,
    /// n + 2h - 2.
    pub expected_triangles: usize,
    /// Sum of free triangle areas.
    pub triangle_area: f64,
    /// Boundary area minus obstacle areas.
    pub free_area: f64,
    /// Map edges (each bordering exactly one triangle).
    pub map_edges: usize,
    /// Diagonals (each bordering exactly two triangles).
    pub diagonals: usize,
    /// The empty-circumcircle test held on every diagonal.
    pub constrained_delaunay: bool,
}

/// The first invariant found broken.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum InvariantViolation {
    /// The half-edge structure is inconsistent.
    #[error("broken structure: {0}")]
    Structure(String),
    /// Wrong number of triangles.
    #[error("{triangles} triangles, expected n + 2h - 2 = {expected}")]
    TriangleCount {
        /// Found.
        triangles: usize,
        /// Expected.
        expected: usize,
    },
    /// Areas disagree.
    #[error("triangle areas sum to {triangle_area}, free area is {free_area}")]
    Area {
        /// Sum of triangle areas.
        triangle_area: f64,
        /// Free-space area.
        free_area: f64,
    },
    /// A map edge is missing or borders the wrong faces.
    #[error("map edge ({}, {})-({}, {}): {problem}", from.x, from.y, to.x, to.y)]
    MapEdge {
        /// Start.
        from: Point2<f64>,
        /// End.
        to: Point2<f64>,
        /// What is wrong.
        problem: &'static str,
    },
    /// A diagonal fails the empty-circumcircle test.
    #[error("edge ({}, {})-({}, {}) is not locally Delaunay", from.x, from.y, to.x, to.y)]
    NotDelaunay {
        /// Start.
        from: Point2<f64>,
        /// End.
        to: Point2<f64>,
    },
}

impl Btm {
    /// Checks every invariant listed in the module docs.
    ///
    /// ```
    /// use nalgebra::Point2;
    /// use rappel_geometry::btm::Btm;
    /// use rappel_geometry::{map::Map, polygon::Polygon};
    /// let p = |x, y| Point2::new(x, y);
    /// let map = Map::new(Polygon::new(vec![p(0., 0.), p(9., 0.), p(9., 9.), p(0., 9.)]), vec![]);
    /// let report = Btm::from_map(&map).unwrap().check_invariants().unwrap();
    /// assert_eq!((report.triangles, report.expected_triangles), (2, 2));
    /// ```
    pub fn check_invariants(&self) -> Result<InvariantReport, InvariantViolation> {
        let d = &self.dcel;
        let structure = |m: String| Err(InvariantViolation::Structure(m));
        let mut triangles = 0;
        let mut triangle_area = 0.0;
        let mut map_edges = 0;
        let mut diagonals = 0;
        for t in 0..d.face.len() as u32 {
            let kind = d.face[t as usize];
            if kind == FaceKind::Dead {
                continue;
            }
            let [a, b, c] = [0, 1, 2].map(|i| d.origin[(3 * t + i) as usize]);
            if orient2d(d.pt(a), d.pt(b), d.pt(c)) <= 0.0 {
                return structure(format!("triangle {t} is not counter-clockwise"));
            }
            for i in 0..3 {
                let h = 3 * t + i;
                let g = d.twin[h as usize];
                if g == NONE {
                    if kind == FaceKind::Free {
                        return structure(format!("free half-edge {h} has no twin"));
                    }
                    continue;
                }
                if d.twin[g as usize] != h
                    || d.origin[g as usize] != d.dest(h)
                    || d.dest(g) != d.origin[h as usize]
                {
                    return structure(format!("half-edges {h} and {g} are not proper twins"));
                }
                if d.face[(g / 3) as usize] == FaceKind::Dead {
                    return structure(format!("half-edge {h} is twinned into a retired triangle"));
                }
                if d.constrained[h as usize] != d.constrained[g as usize] {
                    return structure(format!(
                        "half-edges {h} and {g} disagree on being a map edge"
                    ));
                }
            }
            if kind != FaceKind::Free {
                continue;
            }
            triangles += 1;
            triangle_area += orient2d(d.pt(a), d.pt(b), d.pt(c)) / 2.0;
            for v in [a, b, c] {
                if !d.is_map_vertex(crate::dcel::VertexId(v)) {
                    return structure(format!("free triangle {t} uses non-map vertex {v}"));
                }
            }
            for i in 0..3 {
                let h = 3 * t + i;
                let across = d.face[(d.twin[h as usize] / 3) as usize];
                let (from, to) = (*d.pt(d.origin[h as usize]), *d.pt(d.dest(h)));
                if d.constrained[h as usize] {
                    map_edges += 1;
                    if across == FaceKind::Free {
                        return Err(InvariantViolation::MapEdge {
                            from,
                            to,
                            problem: "borders two free triangles",
                        });
                    }
                    let ring = d.ring[d.origin[h as usize] as usize];
                    if ring.is_none_or(|r| r.next != d.dest(h)) {
                        return Err(InvariantViolation::MapEdge {
                            from,
                            to,
                            problem: "is marked but is not an edge of any ring",
                        });
                    }
                } else {
                    if across != FaceKind::Free {
                        return Err(InvariantViolation::MapEdge {
                            from,
                            to,
                            problem: "separates free space from a hole but is not marked",
                        });
                    }
                    if h < d.twin[h as usize] {
                        diagonals += 1;
                    }
                }
            }
        }
        // Every ring edge must exist with free space on its left.
        let mut ring_edges = 0;
        for v in self.vertices() {
            let Some(link) = d.ring[v.index()] else {
                continue;
            };
            ring_edges += 1;
            let (from, to) = (d.points[v.index()], d.points[link.next as usize]);
            match d.find_edge(v.0, link.next) {
                Some(h)
                    if d.constrained[h as usize] && d.face[(h / 3) as usize] == FaceKind::Free => {}
                Some(_) => {
                    return Err(InvariantViolation::MapEdge {
                        from,
                        to,
                        problem: "does not border free space on its left",
                    });
                }
                None => {
                    return Err(InvariantViolation::MapEdge {
                        from,
                        to,
                        problem: "is missing from the triangulation",
                    });
                }
            }
        }
        if ring_edges != map_edges {
            return structure(format!(
                "{ring_edges} ring edges but {map_edges} marked map edges"
            ));
        }
        let n = self.vertex_count();
        let h = self.hole_count();
        let expected = n + 2 * h - 2;
        if triangles != expected {
            return Err(InvariantViolation::TriangleCount {
                triangles,
                expected,
            });
        }
        let free_area = self.map().free_area();
        if (triangle_area - free_area).abs() > AREA_REL_TOL * free_area.abs().max(f64::MIN_POSITIVE)
        {
            return Err(InvariantViolation::Area {
                triangle_area,
                free_area,
            });
        }
        if let Some((from, to)) = self.first_non_delaunay_edge() {
            return Err(InvariantViolation::NotDelaunay { from, to });
        }
        Ok(InvariantReport {
            vertices: n,
            holes: h,
            triangles,
            expected_triangles: expected,
            triangle_area,
            free_area,
            map_edges,
            diagonals,
            constrained_delaunay: true,
        })
    }

    /// The first diagonal between free triangles whose opposite vertex lies strictly inside the
    /// circumcircle of the triangle on the other side.
    pub(crate) fn first_non_delaunay_edge(&self) -> Option<(Point2<f64>, Point2<f64>)> {
        let d = &self.dcel;
        for h in 0..d.origin.len() as u32 {
            if d.face[(h / 3) as usize] != FaceKind::Free || d.constrained[h as usize] {
                continue;
            }
            let g = d.twin[h as usize];
            if g == NONE || g < h || d.face[(g / 3) as usize] != FaceKind::Free {
                continue;
            }
            let (a, b, c) = (d.origin[h as usize], d.dest(h), d.apex(h));
            let x = d.origin[HalfEdgeId(g).prev().index()];
            if incircle(d.pt(a), d.pt(b), d.pt(c), d.pt(x)) > 0.0 {
                return Some((*d.pt(a), *d.pt(b)));
            }
        }
        None
    }
}
