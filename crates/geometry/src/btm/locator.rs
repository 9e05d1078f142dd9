//! The coarse index of a BTM's vertices ([`Locator`]) that starts a point-location walk
//! ([`super::locate`]) for a cold query: the live vertices bucketed by a grid of about four
//! vertices per cell. Held by the [`super::Btm`] it indexes; knows nothing of the BTM itself.

use crate::dcel::{Dcel, NONE};
use crate::spatial_grid::SpatialGrid;
use nalgebra::Point2;

/// Coarse index for cold queries: the live vertices bucketed by a grid of about four vertices
/// per cell.
#[derive(Debug, Clone)]
pub(crate) struct Locator {
    /// Cells of about four vertices each, holding indices into `alive`.
    grid: SpatialGrid,
    /// The vertices live when the index was built.
    alive: Vec<u32>,
}

impl Locator {
    pub(crate) fn new(dcel: &Dcel) -> Self {
        let alive: Vec<u32> = (dcel.scaffold..dcel.points.len() as u32)
            .filter(|&v| dcel.vertex_edge[v as usize] != NONE)
            .collect();
        let bounds =
            crate::polygon::Aabb::of_points(alive.iter().map(|&v| &dcel.points[v as usize]));
        // About four vertices per cell, every live vertex in the cell holding it (ids are
        // indices into `alive`, mapped back below): a short walk from any of them.
        let boxes: Vec<crate::polygon::Aabb> = alive
            .iter()
            .map(|&v| {
                let p = dcel.points[v as usize];
                crate::polygon::Aabb { min: p, max: p }
            })
            .collect();
        let grid = SpatialGrid::packed(bounds, alive.len() / 4 + 1, &boxes);
        Locator { grid, alive }
    }

    /// A live triangle near `p` to start a walk from.
    pub(crate) fn hint(&self, dcel: &Dcel, p: &Point2<f64>) -> Option<u32> {
        // Rings widen until one holds a live vertex or the grid is exhausted: at most
        // max(cols, rows) rings.
        for ring in 0.. {
            let found = self.grid.find_in_ring(p, ring, |i| {
                let e = dcel.vertex_edge[self.alive[i as usize] as usize];
                (e != NONE).then_some(e / 3)
            })?;
            if found.is_some() {
                return found;
            }
        }
        None
    }
}
