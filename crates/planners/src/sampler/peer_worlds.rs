//! The obstacle worlds of the sampling-planner peer comparison (docs/sampler.md): the worlds
//! `benches/examples/sampler_peer.rs` writes for OMPL's BIT* to read, also used by the sampler's
//! own tests, so the planner is tested on exactly what it is compared on.

use super::obstacle_world::{Obstacle, ObstacleWorld};
use super::real_vector::RealVectorSpace;

/// The 2D world: two walls forming a detour from `(1, 1)` to `(9, 9)` in the square `[0, 10]²`,
/// with a small box in the corridor between them; motion-check resolution 0.002.
///
/// ```
/// use rappel_planners::sampler::MotionValidator;
/// use rappel_planners::sampler::peer_worlds::boxes_2d;
/// let w = boxes_2d();
/// assert_eq!(w.obstacles.len(), 3);
/// assert!(w.state_valid(&w.start) && w.state_valid(&w.goal));
/// ```
pub fn boxes_2d() -> ObstacleWorld<2> {
    ObstacleWorld {
        space: RealVectorSpace::new([0.0, 0.0], [10.0, 10.0]).expect("a non-empty box"),
        obstacles: vec![
            Obstacle::Box {
                min: [3.0, 0.0],
                max: [4.0, 7.0],
            },
            Obstacle::Box {
                min: [6.0, 3.0],
                max: [7.0, 10.0],
            },
            Obstacle::Box {
                min: [4.8, 5.0],
                max: [5.2, 5.4],
            },
        ],
        start: [1.0, 1.0],
        goal: [9.0, 9.0],
        resolution: 0.002,
    }
}

/// The 3D world: two slabs and a block in the cube `[0, 10]³`, from `(1, 1, 5)` to `(9, 9, 5)`;
/// motion-check resolution 0.002.
///
/// ```
/// use rappel_planners::sampler::MotionValidator;
/// use rappel_planners::sampler::peer_worlds::boxes_3d;
/// let w = boxes_3d();
/// assert!(w.state_valid(&w.start) && w.state_valid(&w.goal));
/// ```
pub fn boxes_3d() -> ObstacleWorld<3> {
    ObstacleWorld {
        space: RealVectorSpace::new([0.0; 3], [10.0; 3]).expect("a non-empty box"),
        obstacles: vec![
            Obstacle::Box {
                min: [4.0, 0.0, 0.0],
                max: [5.0, 8.0, 10.0],
            },
            Obstacle::Box {
                min: [7.0, 2.0, 0.0],
                max: [8.0, 10.0, 7.0],
            },
            Obstacle::Box {
                min: [1.0, 4.0, 4.0],
                max: [3.0, 6.0, 6.0],
            },
        ],
        start: [1.0, 1.0, 5.0],
        goal: [9.0, 9.0, 5.0],
        resolution: 0.002,
    }
}
