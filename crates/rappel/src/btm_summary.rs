//! The summary of a BTM build that `rappel btm` prints and `--json` emits: sizes, the checked
//! invariants (including whether the triangulation is constrained Delaunay) and the build time.

use rappel_geometry::btm::{Btm, BtmError};
use rappel_geometry::map::ValidMap;
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// What `rappel btm` reports.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct BtmSummary {
    /// Map vertices.
    pub vertices: usize,
    /// Holes (obstacles).
    pub holes: usize,
    /// Free triangles.
    pub triangles: usize,
    /// n + 2h - 2.
    pub expected_triangles: usize,
    /// Every invariant of `Btm::check_invariants` held (count, area, map edges, Delaunay).
    pub invariants_hold: bool,
    /// The first broken invariant, if any.
    pub invariant_violation: Option<String>,
    /// The empty-circumcircle test, checked exactly on every diagonal.
    pub constrained_delaunay: bool,
    /// Free-space area, m².
    pub free_area_m2: f64,
    /// Wall-clock time of the build (triangulation and labelling; the map was validated before,
    /// by the caller that holds its `ValidMap` proof), whole microseconds.
    pub build_us: u64,
}

crate::report::report!(BtmSummary, "btm");

/// Builds the BTM of the validated `map`, timing the build, and checks it.
///
/// ```
/// use nalgebra::Point2;
/// use rappel::btm_summary::summarize_btm;
/// use rappel::geometry::{map::Map, polygon::Polygon};
/// let p = |x, y| Point2::new(x, y);
/// let map = Map::new(Polygon::new(vec![p(0., 0.), p(4., 0.), p(4., 4.), p(0., 4.)]), vec![]);
/// let (_, s) = summarize_btm(map.validate().unwrap()).unwrap();
/// assert!(s.constrained_delaunay && s.invariants_hold);
/// assert_eq!(s.triangles, 2);
/// ```
pub fn summarize_btm(map: ValidMap<'_>) -> Result<(Btm, BtmSummary), BtmError> {
    let t = Instant::now();
    let btm = Btm::build(map)?;
    let build_us = crate::report::micros(t.elapsed());
    let check = btm.check_invariants();
    let vertices = btm.vertex_count();
    let holes = btm.hole_count();
    let summary = BtmSummary {
        vertices,
        holes,
        triangles: btm.triangle_count(),
        expected_triangles: vertices + 2 * holes - 2,
        invariants_hold: check.is_ok(),
        invariant_violation: check.as_ref().err().map(ToString::to_string),
        constrained_delaunay: btm.is_constrained_delaunay(),
        free_area_m2: map.free_area(),
        build_us,
    };
    Ok((btm, summary))
}
