//! The coarse index of a BTM's vertices ([`Locator`]) that starts a point-location walk
//! ([`super::locate`]) for a cold query: the live vertices bucketed by a grid of about four
//! vertices per cell. Held by the [`super::Btm`] it indexes; knows nothing of the BTM itself.

use crate::dcel::{Dcel, NONE};
use crate::spatial_grid::SpatialGrid;
use nalgebra::Point2;

/// Coarse index for cold queries: the live vertices bucketed by a grid of about four vertices
/// per cell, by vertex id.
///
/// Built with [`SpatialGrid::pack_points`] straight from the DCEL's point array: no list of the
/// live vertices and no box per vertex (on a 1,000,000-obstacle strip those were 36 bytes per
/// vertex, about 200 MB at the build's peak, and 4 bytes per vertex kept).
#[derive(Debug, Clone)]
pub(crate) struct Locator {
    /// Cells of about four live vertices each, holding vertex ids.
    grid: SpatialGrid,
}

impl Locator {
    pub(crate) fn new(dcel: &Dcel) -> Self {
        let live = |v: usize| v >= dcel.scaffold as usize && dcel.vertex_edge[v] != NONE;
        let points = &dcel.points;
        let live_points = (0..points.len()).filter(|&v| live(v)).map(|v| &points[v]);
        let bounds = crate::polygon::Aabb::of_points(live_points.clone());
        let count = live_points.count();
        let grid = SpatialGrid::new(bounds, count / 4 + 1).pack_points(points, live);
        Locator { grid }
    }

    /// A live triangle near `p` to start a walk from.
    pub(crate) fn hint(&self, dcel: &Dcel, p: &Point2<f64>) -> Option<u32> {
        // Rings widen until one holds a live vertex or the grid is exhausted: at most
        // max(cols, rows) rings.
        for ring in 0.. {
            let found = self.grid.find_in_ring(p, ring, |v| {
                let e = dcel.vertex_edge[v as usize];
                (e != NONE).then_some(e / 3)
            })?;
            if found.is_some() {
                return found;
            }
        }
        None
    }
}
