//! Alg. 14 `UpdateWithSlipped` (thesis §3.5.5): when the tether slips over a PTFO vertex, clip
//! that vertex from the obstacle (remove the obstacle when fewer than three vertices are left),
//! update the BTM locally (remove the obstacle, insert the clipped ring: `Btm::remove_obstacle`,
//! `Btm::insert_obstacle`, thesis §3.5.2), trace the old SHP through the new BTM to get the new
//! sleeve and run the funnel in it.
//!
//! The old SHP stays in free space: the tether turns toward the obstacle at an anchor, so the
//! clipped vertex is convex and the clipped ring lies inside the old one. The thesis funnels only
//! between the two anchors around the slipped one and splices the ends back; we funnel the whole
//! traced sleeve (the thesis' stated alternative): the result is the same path, because every
//! sub-path of a shortest homotopic path is one, and the splice would need the same sleeve.
//!
//! The BTM is copied on the first slip only ([`SlipState`]): classes with no slipping anchor
//! share the search's BTM.

use super::{FrictionalError, original_index};
use nalgebra::Point2;
use rappel_geometry::btm::Btm;
use rappel_geometry::dcel::ObstacleId;
use rappel_geometry::map::Map;
use rappel_geometry::polygon::Polygon;
use rappel_homotopy::funnel::{Anchor, TautPath};
use rappel_homotopy::shp::shortest_homotopic_path;
use serde::{Deserialize, Serialize};

/// One slip: which vertex was clipped and how the SHP changed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct SlipEvent {
    /// The clipped vertex (the slipping friction anchor).
    #[schemars(with = "[f64; 2]")]
    pub vertex: Point2<f64>,
    /// The map obstacle index of its PTFO.
    pub obstacle: usize,
    /// `true` when the PTFO disappeared (fewer than three vertices left).
    pub obstacle_removed: bool,
    /// SHP length before and after, m.
    pub length_before_m: f64,
    /// SHP length after the slip, m.
    pub length_after_m: f64,
    /// Anchor points before the slip.
    #[schemars(with = "Vec<[f64; 2]>")]
    pub anchors_before: Vec<Point2<f64>>,
    /// Anchor points after the slip.
    #[schemars(with = "Vec<[f64; 2]>")]
    pub anchors_after: Vec<Point2<f64>>,
}

/// What is left of a PTFO when a vertex slips (Alg. 14 line 4).
#[derive(Debug, Clone, PartialEq)]
pub enum Clipped {
    /// The outline with the vertex clipped off.
    Outline(Polygon),
    /// Fewer than three distinct vertices, or no area, are left: the PTFO is removed.
    Removed,
}

/// Alg. 14 line 4: the PTFO `ring` with its vertex `vertex` clipped off; `None` when `vertex` is
/// not a vertex of `ring`. The frictional planner ([`SlipState::update_with_slipped`]) and the
/// online session (`crate::online`, as a map change) both clip through this one function.
///
/// ```
/// use nalgebra::Point2;
/// use rappel_geometry::polygon::Polygon;
/// use rappel_planners::frictional::slip::{clip_vertex, Clipped};
/// let p = |x, y| Point2::new(x, y);
/// let square = Polygon::new(vec![p(0., 0.), p(0., 1.), p(1., 1.), p(1., 0.)]);
/// assert!(matches!(clip_vertex(&square, &p(1., 1.)), Some(Clipped::Outline(t)) if t.len() == 3));
/// let triangle = Polygon::new(vec![p(0., 0.), p(0., 1.), p(1., 0.)]);
/// assert_eq!(clip_vertex(&triangle, &p(0., 0.)), Some(Clipped::Removed));
/// assert_eq!(clip_vertex(&triangle, &p(5., 5.)), None);
/// ```
pub fn clip_vertex(ring: &Polygon, vertex: &Point2<f64>) -> Option<Clipped> {
    let at = ring.vertices.iter().position(|v| v == vertex)?;
    let mut clipped = ring.vertices.clone();
    clipped.remove(at);
    let clipped = Polygon::new(clipped);
    Some(
        if clipped.distinct_vertex_count() >= 3 && !clipped.is_degenerate() {
            Clipped::Outline(clipped)
        } else {
            Clipped::Removed
        },
    )
}

/// The map as the slips of one class have left it: the search's BTM until the first slip, then a
/// private copy updated locally.
#[derive(Debug, Clone)]
pub struct SlipState<'a> {
    base: &'a Btm,
    map: &'a Map,
    owned: Option<Btm>,
    /// Current rings of obstacles changed by slips, by BTM obstacle id.
    rings: Vec<(ObstacleId, Option<Polygon>)>,
    /// `(new id, map obstacle index)` for re-inserted obstacles.
    renamed: Vec<(ObstacleId, usize)>,
}

impl<'a> SlipState<'a> {
    /// The state before any slip: `btm` must be `Btm::from_map(map)`.
    pub fn new(base: &'a Btm, map: &'a Map) -> Self {
        SlipState {
            base,
            map,
            owned: None,
            rings: Vec::new(),
            renamed: Vec::new(),
        }
    }

    /// The current BTM.
    pub fn btm(&self) -> &Btm {
        self.owned.as_ref().unwrap_or(self.base)
    }

    /// The map obstacle index of a current BTM obstacle.
    pub fn original(&self, id: ObstacleId) -> usize {
        original_index(&self.renamed, id)
    }

    /// The number of slips applied.
    pub fn slips(&self) -> usize {
        self.rings.iter().filter(|(_, r)| r.is_none()).count()
    }

    /// The current ring of a BTM obstacle.
    fn ring(&self, id: ObstacleId) -> Option<Polygon> {
        if let Some((_, r)) = self.rings.iter().rev().find(|(o, _)| *o == id) {
            return r.clone();
        }
        // Never changed: a map obstacle under its original id.
        self.map.obstacles.get(id.index()).cloned()
    }

    /// The map with every clip applied (for pictures and for rebuilding from scratch).
    pub fn current_map(&self) -> Map {
        let mut obstacles = Vec::new();
        for (i, o) in self.map.obstacles.iter().enumerate() {
            if !self.rings.iter().any(|(id, _)| id.index() == i) {
                obstacles.push(o.clone());
            }
        }
        // Re-inserted rings that are still current.
        for (id, ring) in &self.rings {
            let superseded = self.rings.iter().any(|(o, r)| o == id && r.is_none());
            if let Some(r) = ring
                && !superseded
            {
                obstacles.push(r.clone());
            }
        }
        Map::new(self.map.boundary.clone(), obstacles)
    }

    /// Alg. 14 for the friction anchor `anchor` of `taut`: clip, update, retrace. Returns the new
    /// SHP and the slip event.
    pub fn update_with_slipped(
        &mut self,
        taut: &TautPath,
        anchor: &Anchor,
    ) -> Result<(TautPath, SlipEvent), FrictionalError> {
        let id = anchor.obstacle.ok_or_else(|| {
            FrictionalError::Internal("a slipping anchor on the map boundary".into())
        })?;
        let obstacle = self.original(id);
        let ring = self
            .ring(id)
            .ok_or_else(|| FrictionalError::Internal(format!("obstacle {id} has no ring")))?;
        let clipped = clip_vertex(&ring, &anchor.point).ok_or_else(|| {
            FrictionalError::Internal(format!("anchor is not a vertex of obstacle {id}"))
        })?;
        if self.owned.is_none() {
            self.owned = Some(self.base.clone());
        }
        let btm = self.owned.as_mut().expect("just set");
        btm.remove_obstacle(id)?;
        self.rings.push((id, None));
        let removed = clipped == Clipped::Removed;
        if let Clipped::Outline(clipped) = clipped {
            let (new_id, _) = btm.insert_obstacle(&clipped)?;
            self.rings.push((new_id, Some(clipped)));
            self.renamed.push((new_id, obstacle));
        }
        let traced = shortest_homotopic_path(btm, &taut.to_path())?.taut;
        let points = |t: &TautPath| t.anchors.iter().map(|a| a.point).collect::<Vec<_>>();
        let event = SlipEvent {
            vertex: anchor.point,
            obstacle,
            obstacle_removed: removed,
            length_before_m: taut.length,
            length_after_m: traced.length,
            anchors_before: points(taut),
            anchors_after: points(&traced),
        };
        Ok((traced, event))
    }
}
