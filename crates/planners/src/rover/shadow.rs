//! Shadow sampling for the tethered rover: the sample-bias hook
//! ([`crate::sampler::StateSpace::sample_biased`]) of [`super::problem`].
//!
//! A state is *in the shadow* of the tether's root anchor when the straight segment from the
//! anchor to the rover's tether end is blocked by the terrain: the taut tether cannot reach such
//! a state without bending around a feature (a pole, a lip, a boulder), so its anchor history
//! must hold an extra anchor there. These are exactly the states that make the problem
//! non-Markovian (Paton §V-A: the pole wrap of test 3 starts with a motion into the narrow
//! strip behind the pole, which a uniform sampler rarely hits). Drawing a fraction of the
//! samples from the shadow is the tether's form of the visibility- and obstacle-based samplers
//! of the PRM literature (samples where the free space is hard to see into).
//!
//! The test is cheap and approximate (it only shapes a sampling distribution; every sample is
//! still checked by the validator): the ground height under `(x, y)` by a vertical ray cast on
//! the mesh's BVH, the tether end `2 r_w` above it (Axel's tether leaves `r_w` above the axle, which
//! stands `r_w` above level ground), and one ray cast from the
//! anchor towards it, stopped [`END_CLEARANCE`] short of it. A draw is uniform in the region
//! and heading, kept if shadowed; at most [`SHADOW_ATTEMPTS`] draws per call.

use std::sync::Arc;

use nalgebra::{Point3, Vector3};
use rand::RngExt;
use rand_chacha::ChaCha8Rng;

use rappel_mechanics::axel::AxelParams;
use rappel_terrain::parry_mesh::ParryMesh;

/// Uniform draws per shadow sample before the search gives up (returns `None`, and the planner
/// samples uniformly): the bound of the sampling loop. With the pole's shadow about 2 % of
/// Paton's sampled region (1.1 m² of 62 m²), 512 draws miss it with probability about
/// `0.982^512` = 1e-4; a band draw is kept with probability about 2.5 % (the band is about 7 %
/// of the region, and a point in it is kept for the fraction of shifts that block, about 0.35),
/// missed by all 512 with probability below `0.975^512` = 2e-6. A draw costs two ray casts on
/// the BVH (microseconds), against milliseconds per motion check.
pub const SHADOW_ATTEMPTS: usize = 512;

/// Half-width of the *silhouette band*, metres: a ground point is in the band when the sight
/// line to its tether end, shifted sideways (horizontally, perpendicular to it) by some amount
/// in `[-SILHOUETTE_BAND, SILHOUETTE_BAND]`, is blocked: the shadow widened by this much either
/// side, without gaps. The states beside a narrow shadow are the ones a motion into it starts
/// from (the pole's own shadow, 0.7 m wide, is mostly too close to the pole for Axel's body);
/// Axel's 1 m boom.
pub const SILHOUETTE_BAND: f64 = 1.0;

/// Fraction of the shadow samples drawn from the shadow itself (the *core*); the rest come
/// from the silhouette band. A state in the core can only be reached with an extra anchor, so
/// it is where a new anchor class starts; the band holds the states the motions into it start
/// from and end at (`docs/sampler.md`, "Diagnosing the shadow row's failing seeds": with the
/// core drawn only as one of three strips, a batch often held no valid state in it).
pub const SHADOW_CORE_FRACTION: f64 = 0.5;

/// How far short of the tether end the sight line stops, metres, so that the ground right under
/// the rover (e.g. a slope rising towards the anchor) does not count as a feature: a tenth of
/// Axel's 1 m boom.
pub const END_CLEARANCE: f64 = 0.1;

/// The shadow of one anchor on a mesh ground, over a rectangular region of ground points.
#[derive(Clone)]
pub struct TetherShadow {
    ground: Arc<ParryMesh>,
    anchor: Point3<f64>,
    lo: [f64; 2],
    hi: [f64; 2],
    z_top: f64,
    z_bottom: f64,
    end_height: f64,
    core_fraction: f64,
}

impl std::fmt::Debug for TetherShadow {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("TetherShadow")
            .field("anchor", &self.anchor)
            .field("lo", &self.lo)
            .field("hi", &self.hi)
            .finish()
    }
}

impl PartialEq for TetherShadow {
    fn eq(&self, o: &Self) -> bool {
        Arc::ptr_eq(&self.ground, &o.ground)
            && self.anchor == o.anchor
            && self.lo == o.lo
            && self.hi == o.hi
    }
}

impl TetherShadow {
    /// The shadow of `anchor` on `ground` (whose heights lie in `[z_bottom, z_top]`) over the
    /// ground points in the box `lo`-`hi`.
    pub fn new(
        ground: Arc<ParryMesh>,
        anchor: Point3<f64>,
        lo: [f64; 2],
        hi: [f64; 2],
        z_bottom: f64,
        z_top: f64,
    ) -> Self {
        TetherShadow {
            end_height: 2.0 * AxelParams::default().wheel_radius,
            ground,
            anchor,
            lo,
            hi,
            z_top,
            z_bottom,
            core_fraction: SHADOW_CORE_FRACTION,
        }
    }

    /// The same shadow drawing a fraction `f` (clamped to `[0, 1]`; NaN counts as 0) of its
    /// samples from the core instead of [`SHADOW_CORE_FRACTION`] (for experiments,
    /// `examples/navigate_diag.rs`).
    pub fn with_core_fraction(mut self, f: f64) -> Self {
        self.core_fraction = if f.is_nan() { 0.0 } else { f.clamp(0.0, 1.0) };
        self
    }

    /// The tether end over ground point `(x, y)` (`2 r_w` above the first ground hit from
    /// above), or `None` where no ground lies under it.
    pub fn tether_end(&self, x: f64, y: f64) -> Option<Point3<f64>> {
        let from = Point3::new(x, y, self.z_top + 1.0);
        let t = self
            .ground
            .cast_ray(&from, &-Vector3::z(), self.z_top - self.z_bottom + 2.0)?;
        Some(Point3::new(x, y, from.z - t + self.end_height))
    }

    /// Whether the sight line from the anchor to `end` is blocked by the ground before it
    /// comes within [`END_CLEARANCE`] of `end`.
    fn blocked(&self, end: &Point3<f64>) -> bool {
        let d = end - self.anchor;
        let len = d.norm();
        len > END_CLEARANCE
            && self
                .ground
                .cast_ray(&self.anchor, &(d / len), len - END_CLEARANCE)
                .is_some()
    }

    /// Whether ground point `(x, y)` is in the anchor's shadow: the sight line to its tether
    /// end is blocked (module doc).
    pub fn shadowed(&self, x: f64, y: f64) -> bool {
        self.tether_end(x, y).is_some_and(|e| self.blocked(&e))
    }

    /// Whether the sight line to the tether end over `(x, y)`, shifted sideways by `shift`
    /// metres (horizontally, perpendicular to the sight line), is blocked.
    pub fn shifted_shadowed(&self, x: f64, y: f64, shift: f64) -> bool {
        let Some(end) = self.tether_end(x, y) else {
            return false;
        };
        let d = end - self.anchor;
        let Some(side) = Vector3::new(-d.y, d.x, 0.0).try_normalize(0.0) else {
            return self.blocked(&end);
        };
        self.blocked(&(end + side * shift))
    }

    /// Whether ground point `(x, y)` is in the silhouette band: some sideways shift of its
    /// sight line within `[-SILHOUETTE_BAND, SILHOUETTE_BAND]` is blocked, checked at the
    /// shifts `j * SILHOUETTE_BAND / 8`, `j = -8..=8` (exact for shadows wider than an eighth of
    /// the band, 0.125 m; the pole's is 0.7 m). For tests and pictures; [`TetherShadow::sample`]
    /// draws the shift instead.
    pub fn near_shadow(&self, x: f64, y: f64) -> bool {
        (-8..=8).any(|j| self.shifted_shadowed(x, y, SILHOUETTE_BAND * f64::from(j) / 8.0))
    }

    /// A ground point and heading `(x, y, yaw)`: with probability [`SHADOW_CORE_FRACTION`]
    /// (or the fraction set by [`TetherShadow::with_core_fraction`])
    /// uniform over the shadow, else from the silhouette band (a point and a sideways shift in
    /// `[-SILHOUETTE_BAND, SILHOUETTE_BAND]` drawn uniformly, kept when the shifted sight line
    /// is blocked: a density proportional to the measure of blocking shifts, a solid band with
    /// no gaps), within [`SHADOW_ATTEMPTS`] draws from `rng`; `None` if every draw was lit.
    pub fn sample(&self, rng: &mut ChaCha8Rng) -> Option<(f64, f64, f64)> {
        let core = rng.random::<f64>() < self.core_fraction;
        for _ in 0..SHADOW_ATTEMPTS {
            let x = rng.random_range(self.lo[0]..self.hi[0]);
            let y = rng.random_range(self.lo[1]..self.hi[1]);
            let hit = if core {
                self.shadowed(x, y)
            } else {
                let shift = rng.random_range(-SILHOUETTE_BAND..=SILHOUETTE_BAND);
                self.shifted_shadowed(x, y, shift)
            };
            if hit {
                let yaw = rng.random_range(-std::f64::consts::PI..std::f64::consts::PI);
                return Some((x, y, yaw));
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rappel_terrain::paton_scene::PatonScene;

    fn shadow(pole: bool, anchor: usize) -> TetherShadow {
        let scene = PatonScene::paper(pole);
        let ground = scene.mesh().unwrap();
        let (lo, hi) = ground.bounds();
        let fast = Arc::new(ParryMesh::new(&ground).unwrap());
        let root = scene.anchor_points()[anchor];
        TetherShadow::new(fast, root, [-4.5, -3.0], [5.8, 3.0], lo.z, hi.z)
    }

    #[test]
    fn the_pole_casts_its_shadow_and_the_lip_hides_the_slope() {
        // Test 3: root (7.2, 0, 6), pole axis (-2.5, 0), radius 0.3 (a 32-gon, inscribed
        // 0.2986), 10 m tall. By similar triangles the shadow at x = -4 reaches
        // |y| < 0.3 (7.2 + 4) / (7.2 + 2.5) = 0.346; the band (shifts up to 1 m) covers
        // |y| < 1.346 without gaps.
        let s = shadow(true, 1);
        let end = s.tether_end(-4.0, 0.0).unwrap();
        let r_w = AxelParams::default().wheel_radius;
        assert!((end.z - (4.0 + 2.0 * r_w)).abs() < 1e-9, "{end:?}");
        assert!(s.shadowed(-4.0, 0.0) && s.shadowed(-4.0, 0.25) && s.shadowed(-4.0, -0.25));
        assert!(!s.shadowed(-4.0, 0.45) && !s.shadowed(-4.0, 1.0));
        for y in [0.0, 1.0, -1.0, 0.7, -1.3, 0.5, -0.5] {
            assert!(s.near_shadow(-4.0, y), "{y}");
        }
        for y in [1.45, -1.45, 1.6, -2.5] {
            assert!(!s.near_shadow(-4.0, y), "{y}");
        }
        // In front of the pole the ledge top, the slope and the ground are all in sight.
        for (x, y) in [(-1.0, 0.0), (-2.0, 0.0), (1.5, 0.0), (4.8, 0.0)] {
            assert!(!s.near_shadow(x, y), "{x} {y}");
        }
        // Test 2 (no pole): nothing on the ledge top is hidden from the same root; every draw
        // misses, so the planner falls back to uniform samples.
        let two = shadow(false, 1);
        assert!(!two.near_shadow(-4.0, 0.0) && !two.near_shadow(-1.0, 1.0));
        let mut rng = <ChaCha8Rng as rand::SeedableRng>::seed_from_u64(3);
        assert!(two.sample(&mut rng).is_none());
        // Test 1: root (-5.9, 0, 6) behind the start. The sight line to the tether end on the
        // slope at x = 1.5 (ground 4 - 1.5 tan 55 = 1.858, end 2.558) crosses x = 0 at
        // z = 6 - 3.442 * 5.9 / 7.4 = 3.26, below the lip (4): hidden. The ledge top is seen.
        let one = shadow(false, 0);
        assert!(one.shadowed(1.5, 0.0) && !one.shadowed(-1.0, 0.0));
        // Draws are deterministic and inside the support.
        let three = shadow(true, 1);
        let draw = |seed| {
            let mut rng = <ChaCha8Rng as rand::SeedableRng>::seed_from_u64(seed);
            (0..20)
                .map(|_| three.sample(&mut rng).unwrap())
                .collect::<Vec<_>>()
        };
        let a = draw(5);
        assert_eq!(a, draw(5));
        assert!(a.iter().all(|&(x, y, _)| three.near_shadow(x, y)));
    }

    #[test]
    fn half_the_samples_come_from_the_core_and_the_band_has_no_gaps() {
        // 400 draws on test 3. Expected share in the pole's shadow: the core half plus the band
        // draws that land in it (shadow 0.7 m of the band's 2.7 m width at x = -4, about a
        // quarter): about 0.63. The former support (shadow and two 1 m shifted copies) had no
        // point with 0.4 < |y| < 0.6 at x < -3.5; the band puts about 15 % of its draws there.
        let three = shadow(true, 1);
        let mut rng = <ChaCha8Rng as rand::SeedableRng>::seed_from_u64(11);
        let draws: Vec<_> = (0..400).map(|_| three.sample(&mut rng).unwrap()).collect();
        let core = draws
            .iter()
            .filter(|&&(x, y, _)| three.shadowed(x, y))
            .count();
        let gap = draws
            .iter()
            .filter(|&&(x, y, _)| x < -3.5 && y.abs() > 0.4 && y.abs() < 0.6)
            .count();
        assert!((200..=310).contains(&core), "{core}");
        assert!(gap >= 12, "{gap}");
        // Nothing in front of the pole: a point with x > -2.2 sees the root past the pole even
        // with its sight line shifted 1 m sideways (the band reaches beside the pole).
        let front = draws.iter().find(|&&(x, _, _)| x > -2.2);
        assert!(front.is_none(), "{front:?}");
        // Core only: every draw in the shadow (a miss of all 512 draws has probability 1e-4).
        let only = shadow(true, 1).with_core_fraction(1.0);
        assert!((0..50).all(|_| {
            let (x, y, _) = only.sample(&mut rng).unwrap();
            only.shadowed(x, y)
        }));
    }
}
