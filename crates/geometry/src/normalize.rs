//! Map normalisation: turns the raw output of obstacle detection (overlapping, touching or
//! self-intersecting obstacle outlines, repeated vertices, obstacles at or beyond the map's edge)
//! into a valid [`Map`], and reports what it changed. Validation refuses such maps; this module is
//! the explicit, opt-in repair.
//!
//! Steps, in order:
//! 1. consecutive repeated vertices (and a closing copy of the first vertex) are removed;
//! 2. obstacles with fewer than three distinct vertices or zero area are dropped (reported);
//! 3. optionally every obstacle is replaced by its convex hull (as the thesis does, §2.1.2: the
//!    taut tether only ever touches convex vertices, so hulls change no shortest path's length
//!    class... but they do close concave pockets the tether could otherwise enter);
//! 4. obstacles that overlap, touch or nest are merged, repeatedly, until none do: by polygon
//!    union (holes of the union are filled: a pocket enclosed by obstacles is unreachable) or, in
//!    hull mode, by the hull of the union;
//! 5. obstacles that cross or touch the boundary are carved out of the free region (the boundary
//!    is replaced by the largest piece of boundary minus those obstacles), and obstacles outside
//!    the boundary are dropped.
//!
//! Polygon union and difference are commodity operations done by `i_overlay`, which snaps
//! coordinates to a 64-bit integer grid spanning the input: only obstacles that are merged or
//! carved pass through it; every other vertex keeps its exact input coordinates.

use crate::map::{EdgeContact, Map, MapError, RingId};
use crate::overlay::{OverlayRule, overlay};
use crate::polygon::{Polygon, convex_hull};
use nalgebra::Point2;
use serde::{Deserialize, Serialize};

/// What normalisation may do.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct NormalizeOptions {
    /// Replace every obstacle by its convex hull (thesis §2.1.2). Default: `false`.
    pub convex_hulls: bool,
    /// Carve obstacles that cross or touch the boundary out of the free region instead of
    /// refusing the map. Default: `true`.
    pub carve_boundary: bool,
}

impl Default for NormalizeOptions {
    fn default() -> Self {
        NormalizeOptions {
            convex_hulls: false,
            carve_boundary: true,
        }
    }
}

/// What normalisation changed, in terms of the input's obstacle indices.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct NormalizeReport {
    /// For each obstacle of the output map, the input obstacles it came from.
    pub sources: Vec<Vec<usize>>,
    /// Input obstacles dropped as degenerate (fewer than 3 distinct vertices or zero area).
    pub dropped_degenerate: Vec<usize>,
    /// Input obstacles dropped because they lie outside the boundary.
    pub dropped_outside: Vec<usize>,
    /// Input obstacles carved out of the boundary.
    pub carved_into_boundary: Vec<usize>,
}

impl NormalizeReport {
    /// Number of output obstacles made from more than one input obstacle.
    pub fn merged_count(&self) -> usize {
        self.sources.iter().filter(|s| s.len() > 1).count()
    }
}

/// Normalises `map` as described in the module docs; the result passes [`Map::validate`].
///
/// Errors: non-finite coordinates, or a boundary that is itself unusable (these cannot be
/// repaired without guessing).
///
/// ```
/// use nalgebra::Point2;
/// use rappel_geometry::map::Map;
/// use rappel_geometry::normalize::{normalize, NormalizeOptions};
/// use rappel_geometry::polygon::Polygon;
/// let sq = |x: f64, y: f64, s: f64| Polygon::new(vec![
///     Point2::new(x, y), Point2::new(x + s, y), Point2::new(x + s, y + s), Point2::new(x, y + s)]);
/// let map = Map::new(sq(0., 0., 100.), vec![sq(10., 10., 5.), sq(12., 12., 5.), sq(50., 50., 5.)]);
/// assert!(map.validate().is_err());
/// let (fixed, report) = normalize(&map, &NormalizeOptions::default()).unwrap();
/// fixed.validate().unwrap();
/// assert_eq!(fixed.obstacles.len(), 2);
/// assert_eq!(report.merged_count(), 1);
/// ```
pub fn normalize(
    map: &Map,
    options: &NormalizeOptions,
) -> Result<(Map, NormalizeReport), MapError> {
    let mut report = NormalizeReport::default();
    let boundary = clean_ring(&map.boundary);
    // The boundary must be usable on its own.
    Map::new(boundary.clone(), Vec::new()).validate()?;

    // Steps 1-3, per obstacle.
    let mut obstacles: Vec<(Polygon, Vec<usize>)> = Vec::new();
    for (i, o) in map.obstacles.iter().enumerate() {
        if let Some((vertex, p)) = o
            .vertices
            .iter()
            .enumerate()
            .find(|(_, p)| !(p.x.is_finite() && p.y.is_finite()))
        {
            return Err(MapError::NonFinite {
                ring: RingId::Obstacle(i),
                vertex,
                x: p.x,
                y: p.y,
            });
        }
        let mut ring = clean_ring(o);
        if ring.distinct_vertex_count() < 3 || ring.is_degenerate() {
            report.dropped_degenerate.push(i);
            continue;
        }
        if options.convex_hulls {
            ring = convex_hull(&ring.vertices);
        }
        obstacles.push((ring.to_counter_clockwise(), vec![i]));
    }

    // Step 4: merge until no two obstacles (or an obstacle with itself) meet.
    loop {
        let candidate = Map::new(
            boundary.clone(),
            obstacles.iter().map(|(p, _)| p.clone()).collect(),
        );
        let contacts = candidate.edge_contacts();
        let broken = self_intersecting_obstacles(&contacts, obstacles.len());
        let groups = contact_groups(&candidate, &contacts);
        if groups.iter().all(|g| g.len() == 1 && !broken[g[0]]) {
            break;
        }
        let mut next = Vec::with_capacity(groups.len());
        for group in groups {
            let needs_repair = group.len() > 1 || broken[group[0]];
            if !needs_repair {
                next.push(obstacles[group[0]].clone());
                continue;
            }
            let mut sources: Vec<usize> =
                group.iter().flat_map(|&k| obstacles[k].1.clone()).collect();
            sources.sort_unstable();
            let rings: Vec<&Polygon> = group.iter().map(|&k| &obstacles[k].0).collect();
            let merged = if options.convex_hulls {
                let pts: Vec<Point2<f64>> = rings
                    .iter()
                    .flat_map(|r| r.vertices.iter().copied())
                    .collect();
                vec![convex_hull(&pts)]
            } else {
                let pieces = union_outlines(&rings)?;
                // A union whose outlines still meet (a pinch point, like the middle of a bow tie)
                // cannot be drawn as separate simple rings: take the hull instead, which also
                // guarantees that every round makes progress.
                if pieces_are_simple_and_apart(&pieces) {
                    pieces
                } else {
                    let pts: Vec<Point2<f64>> = rings
                        .iter()
                        .flat_map(|r| r.vertices.iter().copied())
                        .collect();
                    vec![convex_hull(&pts)]
                }
            };
            for m in merged {
                if m.distinct_vertex_count() >= 3 && !m.is_degenerate() {
                    next.push((m, sources.clone()));
                }
            }
        }
        obstacles = next;
    }

    // Step 5: the boundary.
    let mut boundary = boundary;
    let contacts: Vec<MapError> = Map::new(
        boundary.clone(),
        obstacles.iter().map(|(p, _)| p.clone()).collect(),
    )
    .edge_contacts()
    .into_iter()
    .map(|(_, e)| e)
    .filter(|e| matches!(e, MapError::ObstacleCrossesBoundary { .. }))
    .collect();
    let mut touching: Vec<usize> = contacts
        .iter()
        .filter_map(|e| match e {
            MapError::ObstacleCrossesBoundary { obstacle, .. } => Some(*obstacle),
            _ => None,
        })
        .collect();
    touching.sort_unstable();
    touching.dedup();
    if let Some(first) = contacts.into_iter().next() {
        if !options.carve_boundary {
            return Err(first);
        }
        let cut: Vec<&Polygon> = touching.iter().map(|&k| &obstacles[k].0).collect();
        boundary = carve(&boundary, &cut)?.ok_or(MapError::ZeroArea {
            ring: RingId::Boundary,
            at: boundary.vertices[0],
        })?;
        for &k in &touching {
            report
                .carved_into_boundary
                .extend(obstacles[k].1.iter().copied());
        }
        let mut keep = vec![true; obstacles.len()];
        for &k in &touching {
            keep[k] = false;
        }
        obstacles = obstacles
            .into_iter()
            .zip(keep)
            .filter(|(_, k)| *k)
            .map(|(o, _)| o)
            .collect();
    }
    let mut kept = Vec::new();
    for (o, sources) in obstacles {
        if boundary.locate(&o.vertices[0]) == crate::polygon::PointInPolygon::Inside {
            kept.push((o, sources));
        } else {
            report.dropped_outside.extend(sources);
        }
    }
    report.carved_into_boundary.sort_unstable();
    report.dropped_outside.sort_unstable();
    report.sources = kept.iter().map(|(_, s)| s.clone()).collect();
    let out = Map::new(boundary, kept.into_iter().map(|(o, _)| o).collect());
    out.validate()?;
    Ok((out, report))
}

/// Removes consecutive repeated vertices, including a closing copy of the first.
fn clean_ring(ring: &Polygon) -> Polygon {
    let mut v: Vec<Point2<f64>> = Vec::with_capacity(ring.len());
    for p in &ring.vertices {
        if v.last() != Some(p) {
            v.push(*p);
        }
    }
    while v.len() > 1 && v.first() == v.last() {
        v.pop();
    }
    Polygon::new(v)
}

/// For each obstacle, whether one of `contacts` (from [`Map::edge_contacts`]) says it meets
/// itself.
fn self_intersecting_obstacles(contacts: &[EdgeContact], n: usize) -> Vec<bool> {
    let mut broken = vec![false; n];
    for (_, e) in contacts {
        if let MapError::SelfIntersecting {
            ring: RingId::Obstacle(j),
            ..
        } = e
            && *j < n
        {
            broken[*j] = true;
        }
    }
    broken
}

/// Groups of obstacle indices that meet (edges touching or crossing per `contacts`, or nested),
/// transitively, by union-find; each group sorted, groups ordered by their first member.
pub(crate) fn contact_groups(map: &Map, contacts: &[EdgeContact]) -> Vec<Vec<usize>> {
    let n = map.obstacles.len();
    let mut parent: Vec<usize> = (0..n).collect();
    fn find(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let mut join = |a: usize, b: usize| {
        let (ra, rb) = (find(&mut parent, a), find(&mut parent, b));
        if ra != rb {
            parent[ra.max(rb)] = ra.min(rb);
        }
    };
    for (_, e) in contacts {
        if let MapError::ObstaclesOverlap { first, second, .. }
        | MapError::ObstaclesTouch { first, second, .. } = e
        {
            join(*first, *second);
        }
    }
    for (i, j, _) in map.nested_obstacles() {
        join(i, j);
    }
    let mut groups: Vec<Vec<usize>> = vec![Vec::new(); n];
    for i in 0..n {
        let r = find(&mut parent, i);
        groups[r].push(i);
    }
    groups.into_iter().filter(|g| !g.is_empty()).collect()
}

fn to_contour(p: &Polygon) -> Vec<[f64; 2]> {
    p.vertices.iter().map(|v| [v.x, v.y]).collect()
}

fn from_contour(c: &[[f64; 2]]) -> Polygon {
    clean_ring(&Polygon::new(
        c.iter().map(|p| Point2::new(p[0], p[1])).collect(),
    ))
}

/// The outer outlines of the union of `rings` (holes of the union dropped: filled).
fn union_outlines(rings: &[&Polygon]) -> Result<Vec<Polygon>, MapError> {
    let subject: Vec<Vec<[f64; 2]>> = rings.iter().map(|r| to_contour(r)).collect();
    let empty: Vec<Vec<[f64; 2]>> = Vec::new();
    let shapes = overlay(&subject, &empty, OverlayRule::Subject)?;
    Ok(shapes
        .iter()
        .filter_map(|shape| shape.first())
        .map(|c| from_contour(c))
        .collect())
}

/// `true` when `pieces` are simple rings of positive area that pairwise share no point.
fn pieces_are_simple_and_apart(pieces: &[Polygon]) -> bool {
    if pieces
        .iter()
        .any(|p| p.distinct_vertex_count() < 3 || p.is_degenerate())
    {
        return false;
    }
    Map::framing(pieces.to_vec()).validate().is_ok()
}

/// The largest piece of `boundary` minus `cut`, or `None` when nothing is left.
fn carve(boundary: &Polygon, cut: &[&Polygon]) -> Result<Option<Polygon>, MapError> {
    let subject = vec![to_contour(boundary)];
    let clip: Vec<Vec<[f64; 2]>> = cut.iter().map(|r| to_contour(r)).collect();
    let shapes = overlay(&subject, &clip, OverlayRule::Difference)?;
    Ok(shapes
        .iter()
        .filter_map(|shape| shape.first())
        .map(|c| from_contour(c))
        .filter(|p| p.distinct_vertex_count() >= 3 && !p.is_degenerate())
        .max_by(|a, b| a.area().total_cmp(&b.area())))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sq(x: f64, y: f64, s: f64) -> Polygon {
        Polygon::rectangle(x, y, s, s)
    }

    #[test]
    fn union_keeps_concave_outline_and_area() {
        let map = Map::new(sq(0., 0., 100.), vec![sq(10., 10., 10.), sq(15., 15., 10.)]);
        let (fixed, report) = normalize(&map, &NormalizeOptions::default()).unwrap();
        assert_eq!(fixed.obstacles.len(), 1);
        assert_eq!(report.sources, vec![vec![0, 1]]);
        assert!((fixed.obstacles[0].area() - 175.0).abs() < 1e-6);
        assert!(!fixed.obstacles[0].is_convex());
    }

    #[test]
    fn hull_mode_merges_transitively() {
        // a touches b; the hull of a+b then overlaps c, which touched neither.
        let c = Polygon::new(vec![
            Point2::new(19., 24.),
            Point2::new(21., 24.),
            Point2::new(20., 26.),
        ]);
        let map = Map::new(
            sq(0., 0., 100.),
            vec![sq(10., 10., 10.), sq(20., 20., 10.), c],
        );
        let opts = NormalizeOptions {
            convex_hulls: true,
            ..Default::default()
        };
        let (fixed, report) = normalize(&map, &opts).unwrap();
        assert_eq!(fixed.obstacles.len(), 1);
        assert_eq!(report.sources, vec![vec![0, 1, 2]]);
        assert!(fixed.obstacles[0].is_convex());
    }

    #[test]
    fn boundary_obstacles_are_carved_and_outside_ones_dropped() {
        let map = Map::new(
            sq(0., 0., 100.),
            vec![sq(95., 40., 10.), sq(200., 200., 3.), sq(50., 50., 2.)],
        );
        let (fixed, report) = normalize(&map, &NormalizeOptions::default()).unwrap();
        assert_eq!(report.carved_into_boundary, vec![0]);
        assert_eq!(report.dropped_outside, vec![1]);
        assert_eq!(fixed.obstacles.len(), 1);
        assert!((fixed.boundary.area() - (10000.0 - 50.0)).abs() < 1e-6);
        let strict = NormalizeOptions {
            carve_boundary: false,
            ..Default::default()
        };
        assert!(matches!(
            normalize(&map, &strict),
            Err(MapError::ObstacleCrossesBoundary { .. })
        ));
    }

    #[test]
    fn self_intersecting_obstacle_is_repaired_and_degenerate_dropped() {
        let bowtie = Polygon::new(vec![
            Point2::new(10., 10.),
            Point2::new(20., 20.),
            Point2::new(20., 10.),
            Point2::new(10., 20.),
        ]);
        let line = Polygon::new(vec![
            Point2::new(30., 30.),
            Point2::new(31., 31.),
            Point2::new(32., 32.),
        ]);
        let map = Map::new(sq(0., 0., 100.), vec![bowtie, line]);
        let (fixed, report) = normalize(&map, &NormalizeOptions::default()).unwrap();
        assert_eq!(report.dropped_degenerate, vec![1]);
        // The bow tie's union is two triangles pinched at (15, 15): no simple outline exists, so
        // the hull (the 10 x 10 square) replaces it.
        fixed.validate().unwrap();
        assert_eq!(fixed.obstacles.len(), 1);
        assert!((fixed.obstacles[0].area() - 100.0).abs() < 1e-9);
    }
}
