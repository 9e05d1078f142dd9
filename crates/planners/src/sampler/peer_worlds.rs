//! The obstacle worlds of the sampling-planner peer comparison (docs/sampler.md): the worlds
//! `benches/examples/sampler_peer.rs` writes for OMPL's BIT* to read, also used by the sampler's
//! own tests, so the planner is tested on exactly what it is compared on; and the generators of
//! the worlds nobody tuned on (random clutter in 2D and 3D, a narrow passage in 2D and 3D), drawn
//! from a seed.

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

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

/// The seeds of the generated peer worlds that `benches/examples/sampler_peer.rs` writes (fixed
/// once, before any run; nothing was tuned on them).
pub const GENERATED_SEED: u64 = 20261129;

/// Clearance every generated obstacle keeps from the start and the goal.
pub const CLEARANCE: f64 = 0.25;

/// Width of the generated narrow passages (2D: the gap in the wall; 3D: the side of the square
/// hole), 2 % and 5 % of the side of the square or cube.
pub const GAP_2D: f64 = 0.2;
/// See [`GAP_2D`].
pub const GAP_3D: f64 = 0.5;

/// Half-thickness of the generated walls, centred on `x = 5`.
const WALL_HALF: f64 = 0.25;

/// Distance from `p` to the obstacle (0 inside).
fn distance_to<const D: usize>(o: &Obstacle<D>, p: &[f64; D]) -> f64 {
    match o {
        Obstacle::Box { min, max } => (0..D)
            .map(|i| (min[i] - p[i]).max(p[i] - max[i]).max(0.0).powi(2))
            .sum::<f64>()
            .sqrt(),
        Obstacle::Sphere { centre, radius } => ((0..D)
            .map(|i| (p[i] - centre[i]).powi(2))
            .sum::<f64>()
            .sqrt()
            - radius)
            .max(0.0),
    }
}

/// One random obstacle in `[0, 10]^D`: with probability 1/2 a box with half-sides uniform in
/// `half`, else a ball with radius uniform in `radius`, centred uniformly in the square or cube.
fn random_obstacle<const D: usize>(
    rng: &mut ChaCha8Rng,
    half: (f64, f64),
    radius: (f64, f64),
) -> Obstacle<D> {
    let centre: [f64; D] = std::array::from_fn(|_| rng.random_range(0.0..10.0));
    if rng.random::<f64>() < 0.5 {
        let h: [f64; D] = std::array::from_fn(|_| rng.random_range(half.0..half.1));
        Obstacle::Box {
            min: std::array::from_fn(|i| centre[i] - h[i]),
            max: std::array::from_fn(|i| centre[i] + h[i]),
        }
    } else {
        Obstacle::Sphere {
            centre,
            radius: rng.random_range(radius.0..radius.1),
        }
    }
}

/// Adds `count` random obstacles that keep [`CLEARANCE`] from start and goal and that `keep`
/// accepts (redrawn otherwise, at most 1000 draws per obstacle).
fn scatter<const D: usize>(
    world: &mut ObstacleWorld<D>,
    rng: &mut ChaCha8Rng,
    count: usize,
    half: (f64, f64),
    radius: (f64, f64),
    keep: impl Fn(&Obstacle<D>) -> bool,
) {
    for _ in 0..count {
        for _ in 0..1000 {
            let o = random_obstacle(rng, half, radius);
            if distance_to(&o, &world.start) > CLEARANCE
                && distance_to(&o, &world.goal) > CLEARANCE
                && keep(&o)
            {
                world.obstacles.push(o);
                break;
            }
        }
    }
}

/// Whether obstacle `o` stays out of the slab `x in [4, 6]` around the generated walls.
fn off_the_wall<const D: usize>(o: &Obstacle<D>) -> bool {
    match o {
        Obstacle::Box { min, max } => max[0] < 4.0 || min[0] > 6.0,
        Obstacle::Sphere { centre, radius } => centre[0] + radius < 4.0 || centre[0] - radius > 6.0,
    }
}

/// A generated clutter world in `[0, 10]²` (a world the planners were not tuned on): 40 random
/// boxes (half-sides 0.2-0.8) and balls (radius 0.3-0.9), each with probability 1/2, keeping
/// [`CLEARANCE`] from the start `(0.5, 0.5)` and the goal `(9.5, 9.5)`; resolution 0.002. Not
/// every seed need have a solution (the planners' success counts say).
///
/// ```
/// use rappel_planners::sampler::peer_worlds::random_2d;
/// assert_eq!(random_2d(1), random_2d(1));
/// assert_ne!(random_2d(1), random_2d(2));
/// assert_eq!(random_2d(1).obstacles.len(), 40);
/// ```
pub fn random_2d(seed: u64) -> ObstacleWorld<2> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut w = ObstacleWorld {
        space: RealVectorSpace::new([0.0; 2], [10.0; 2]).expect("a non-empty box"),
        obstacles: Vec::new(),
        start: [0.5, 0.5],
        goal: [9.5, 9.5],
        resolution: 0.002,
    };
    scatter(&mut w, &mut rng, 40, (0.2, 0.8), (0.3, 0.9), |_| true);
    w
}

/// A generated clutter world in `[0, 10]³`: 60 random boxes (half-sides 0.3-1.2) and balls
/// (radius 0.4-1.3) from `(0.5, 0.5, 0.5)` to `(9.5, 9.5, 9.5)`, as [`random_2d`].
pub fn random_3d(seed: u64) -> ObstacleWorld<3> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut w = ObstacleWorld {
        space: RealVectorSpace::new([0.0; 3], [10.0; 3]).expect("a non-empty box"),
        obstacles: Vec::new(),
        start: [0.5; 3],
        goal: [9.5; 3],
        resolution: 0.002,
    };
    scatter(&mut w, &mut rng, 60, (0.3, 1.2), (0.4, 1.3), |_| true);
    w
}

/// A generated narrow-passage world in `[0, 10]²`: a wall `x in [4.75, 5.25]` across the whole
/// square but for a gap of width [`GAP_2D`] centred at a height uniform in `[1.5, 8.5]`; start
/// `(1, u)` and goal `(9, v)` with `u, v` uniform in `[1, 9]`; 12 random obstacles as in
/// [`random_2d`] that keep out of the slab `x in [4, 6]` (so the gap stays open). Returns the
/// world and the gap's centre.
pub fn narrow_2d(seed: u64) -> (ObstacleWorld<2>, [f64; 2]) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let g = rng.random_range(1.5..8.5);
    let (x0, x1) = (5.0 - WALL_HALF, 5.0 + WALL_HALF);
    let mut w = ObstacleWorld {
        space: RealVectorSpace::new([0.0; 2], [10.0; 2]).expect("a non-empty box"),
        obstacles: vec![
            Obstacle::Box {
                min: [x0, 0.0],
                max: [x1, g - GAP_2D / 2.0],
            },
            Obstacle::Box {
                min: [x0, g + GAP_2D / 2.0],
                max: [x1, 10.0],
            },
        ],
        start: [1.0, rng.random_range(1.0..9.0)],
        goal: [9.0, rng.random_range(1.0..9.0)],
        resolution: 0.002,
    };
    scatter(&mut w, &mut rng, 12, (0.2, 0.8), (0.3, 0.9), off_the_wall);
    (w, [5.0, g])
}

/// A generated narrow-passage world in `[0, 10]³`: a wall `x in [4.75, 5.25]` filling the cube's
/// cross-section but for a square hole of side [`GAP_3D`] centred at `(y, z)` uniform in
/// `[2, 8]²`; start `(1, u)`, goal `(9, v)` with `u, v` uniform in `[1, 9]²`; 20 random obstacles
/// as in [`random_3d`] that keep out of the slab `x in [4, 6]`. Returns the world and the hole's
/// centre.
pub fn narrow_3d(seed: u64) -> (ObstacleWorld<3>, [f64; 3]) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (gy, gz) = (rng.random_range(2.0..8.0), rng.random_range(2.0..8.0));
    let (x0, x1) = (5.0 - WALL_HALF, 5.0 + WALL_HALF);
    let h = GAP_3D / 2.0;
    let mut w = ObstacleWorld {
        space: RealVectorSpace::new([0.0; 3], [10.0; 3]).expect("a non-empty box"),
        obstacles: vec![
            // Below and above the hole (full width in y), then left and right of it.
            Obstacle::Box {
                min: [x0, 0.0, 0.0],
                max: [x1, 10.0, gz - h],
            },
            Obstacle::Box {
                min: [x0, 0.0, gz + h],
                max: [x1, 10.0, 10.0],
            },
            Obstacle::Box {
                min: [x0, 0.0, gz - h],
                max: [x1, gy - h, gz + h],
            },
            Obstacle::Box {
                min: [x0, gy + h, gz - h],
                max: [x1, 10.0, gz + h],
            },
        ],
        start: [1.0, rng.random_range(1.0..9.0), rng.random_range(1.0..9.0)],
        goal: [9.0, rng.random_range(1.0..9.0), rng.random_range(1.0..9.0)],
        resolution: 0.002,
    };
    scatter(&mut w, &mut rng, 20, (0.3, 1.2), (0.4, 1.3), off_the_wall);
    (w, [5.0, gy, gz])
}
