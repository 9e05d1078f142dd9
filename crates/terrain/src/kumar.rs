//! Kumar §IV's environment as a plane series (Kumar Fig. 5): S0 flat (14 m deep) with two square
//! prism obstacles, S1 55 deg and S2 65 deg (8 m each), S3 flat (4 m), 16 m wide, mu = 0.4.
//! The paper gives slopes and friction only; the extents and obstacle squares are ours (see
//! docs/mechanics.md). Frame: `x` across in `[-8, 8]`, `y` up the fall line, S0 above `y = 16`.

use crate::plane_series::TerrainPlane;
use crate::plane_series_terrain::{PlaneSeriesTerrain, PlaneSeriesTerrainError};
use crate::surface::Prism;
use rappel_geometry::polygon::Polygon;

/// The obstacles' bases: O1 `[-4, -2] x [22, 24]`, O2 `[2, 4] x [19, 21]`.
pub fn kumar_obstacles() -> Vec<Polygon> {
    vec![
        Polygon::rectangle(-4.0, 22.0, 2.0, 2.0),
        Polygon::rectangle(2.0, 19.0, 2.0, 2.0),
    ]
}

/// The environment, obstacles 1 m tall with tether friction 0.4.
///
/// ```
/// use rappel_terrain::kumar::kumar_scene;
/// use rappel_terrain::surface::Terrain;
/// let t = kumar_scene().unwrap();
/// assert_eq!((t.surface_count(), t.obstacles().len()), (4, 2));
/// ```
pub fn kumar_scene() -> Result<PlaneSeriesTerrain, PlaneSeriesTerrainError> {
    let planes = [
        TerrainPlane::new(30.0, 16.0, 0.0, 0.4),
        TerrainPlane::new(16.0, 8.0, 55.0, 0.4),
        TerrainPlane::new(8.0, 0.0, 65.0, 0.4),
        TerrainPlane::new(0.0, -4.0, 0.0, 0.4),
    ];
    let prisms = kumar_obstacles()
        .into_iter()
        .map(|base| Prism {
            surface: 0,
            base,
            height: 1.0,
            friction: 0.4,
        })
        .collect();
    PlaneSeriesTerrain::new(&planes, (-8.0, 8.0), prisms)
}
