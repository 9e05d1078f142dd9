//! H-signatures (thesis §2.2.1, eqs. 2.2-2.3; the online paper's L-values, §II-B; Bhattacharya et
//! al.): the homology class of a path from complex analysis, computed in a per-obstacle winding
//! form that stays exact with any number of obstacles.
//!
//! # From the product form to windings
//! With one pole `zeta_j` inside each obstacle `j = 1..N` and `z = x + iy`, eqs. 2.2-2.3 define
//!
//! ```text
//! H(pi) = integral over pi of F(z) dz,   F(z) = f0(z) / ((z - zeta_1) (z - zeta_2) ... (z - zeta_N)).
//! ```
//!
//! By partial fractions (for `f0` analytic, the poles distinct),
//! `F(z) = sum_j c_j / (z - zeta_j) + E(z)` with residues
//! `c_j = f0(zeta_j) / prod_{k != j} (zeta_j - zeta_k)` and `E` entire, so
//!
//! ```text
//! H(pi) = sum_j c_j L_j(pi) + (integral of E, which depends on the endpoints only),
//! L_j(pi) = integral over pi of dz / (z - zeta_j) = ln|b - zeta_j| - ln|a - zeta_j| + i theta_j(pi)
//! ```
//!
//! for a path from `a` to `b`, where `theta_j` is the total change of `arg(z - zeta_j)` along the
//! path. Per segment the integral is analytic: `Log(q - zeta) - Log(p - zeta)` on the principal
//! branch (cut along the ray `zeta + t (-1, 0)`, `t > 0`), plus `2 pi i` each time the segment
//! crosses the cut downwards (counter-clockwise) and minus `2 pi i` upwards. Summed over a path
//! the principal logarithms telescope, leaving
//!
//! ```text
//! theta_j(pi) = Arg(b - zeta_j) - Arg(a - zeta_j) + 2 pi n_j(pi),   n_j in Z,
//! ```
//!
//! with `n_j` the signed count of cut crossings. For paths with the same endpoints everything but
//! the integers `n_j` is shared, so the vector `(n_1, .., n_N)` *is* the signature: two paths
//! have equal product-form signatures (for generic `f0`, whose residues admit no integer relation)
//! exactly when their winding vectors are equal. [`HSignature`] stores the endpoints and the
//! non-zero `n_j`, exactly, as integers; [`HSignature::product_form`] evaluates eq. 2.3 from them
//! for small `N`.
//!
//! Why not the product form itself: each residue divides by `N - 1` pole differences, products
//! like `100^9999` that overflow (or, for close poles, underflow) `f64` long before 10,000
//! obstacles, and a single complex number cannot keep apart thousands of independent
//! `2 pi i c_j n_j` terms in 53 bits. The winding form needs no arithmetic beyond exact
//! orientation signs and integer sums.
//!
//! Cut crossings use the half-open rule "a point is above the cut when `y >= zeta.y`" (the
//! symbolic perturbation that lifts the cut infinitesimally), consistent with `Arg = +pi` on the
//! cut itself; which side of the pole a crossing is on is an exact orientation sign. Poles are
//! sorted by `y`, so a segment only tests the poles in its `y` range: on a crater strip (long in
//! `y`) a segment meets a handful.
//!
//! # From the sleeve, in time proportional to the path ([`CutIndex`])
//! Homotopic paths with the same endpoints have the same windings, so a class's signature can be
//! read off any path in its sleeve instead of its SHP: the path from the start through one point
//! strictly inside each portal to the goal (at the height of the point before, clamped into the
//! portal's open height range, so that it climbs and drops as little as the sleeve allows). Each of its segments lies in one free
//! triangle, and a cut that meets a free triangle crosses it from side to side (the pole lies
//! strictly inside an obstacle, never in a free triangle), so inside that triangle the segment
//! crosses the cut exactly when its ends lie on opposite sides of the cut's line: a comparison of
//! `y` coordinates (exact also for a portal midpoint, by an error-free sum). [`CutIndex`] lists, once per
//! map, the cuts meeting each free triangle sorted by height, so the cuts a segment crosses in a
//! triangle are one range of its list found by two binary searches; [`HSignature::of_sleeve`]
//! then costs `O(n log m + c log c)` for a sleeve of `n` triangles meeting at most `m` cuts each
//! and `c` cut crossings (the signature's own size, before cancellation), not `O(poles in the
//! path's y band)`. The winding form over the SHP's polyline ([`HSignature::of_taut_path`]) is
//! its test oracle: both give identical signatures.
//!
//! # Homology, not homotopy (thesis Fig. 2.4)
//! The H-signature is a homology invariant. A loop that goes around obstacle A, then B, then A
//! backwards, then B backwards (the commutator `A B A^-1 B^-1`) winds zero times around each
//! obstacle, so its signature is trivial, yet it cannot be contracted: its reduced crossing
//! sequence is not empty. Equal signatures are necessary for homotopy, not sufficient; use
//! [`crate::homotopy`] to decide homotopy.

use crate::funnel::TautPath;
use crate::path::Path;
use crate::sleeve::Sleeve;
use nalgebra::{Complex, Point2};
use rappel_geometry::btm::Btm;
use rappel_geometry::dcel::{FaceKind, HalfEdgeId, ObstacleId, TriangleId};
use rappel_geometry::predicates::orient2d;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// One representative point (pole `zeta_j`) strictly inside each obstacle.
#[derive(Debug, Clone, PartialEq)]
pub struct Poles {
    /// Pole per obstacle id (`None` for ids without an obstacle).
    by_obstacle: Vec<Option<Point2<f64>>>,
    /// Poles sorted by `y`, for range queries.
    sorted: Vec<(Point2<f64>, ObstacleId)>,
}

impl Poles {
    /// A pole inside each obstacle of `btm`: the centroid of the largest triangle of the
    /// obstacle's triangulation whose centroid is verified (exactly) to lie strictly inside it.
    pub fn new(btm: &Btm) -> Poles {
        let d = btm.dcel();
        let mut best: Vec<Option<(f64, Point2<f64>)>> = Vec::new();
        for t in (0..d.triangle_capacity() as u32).map(TriangleId) {
            let FaceKind::Obstacle(o) = d.face_kind(t) else {
                continue;
            };
            let [a, b, c] = d.triangle_points(t);
            let area = orient2d(&a, &b, &c).abs();
            let centroid = Point2::new((a.x + b.x + c.x) / 3.0, (a.y + b.y + c.y) / 3.0);
            let inside = [(a, b), (b, c), (c, a)]
                .iter()
                .all(|(u, v)| orient2d(u, v, &centroid) * orient2d(&a, &b, &c) > 0.0);
            if !inside {
                continue;
            }
            if best.len() <= o.index() {
                best.resize(o.index() + 1, None);
            }
            if best[o.index()].is_none_or(|(area0, _)| area > area0) {
                best[o.index()] = Some((area, centroid));
            }
        }
        Poles::from_points(
            best.iter()
                .enumerate()
                .filter_map(|(i, b)| b.map(|(_, p)| (ObstacleId(i as u32), p))),
        )
    }

    /// Poles from explicit points (one per obstacle id; later duplicates win).
    pub fn from_points(points: impl IntoIterator<Item = (ObstacleId, Point2<f64>)>) -> Poles {
        let mut by_obstacle: Vec<Option<Point2<f64>>> = Vec::new();
        for (o, p) in points {
            if by_obstacle.len() <= o.index() {
                by_obstacle.resize(o.index() + 1, None);
            }
            by_obstacle[o.index()] = Some(p);
        }
        let mut sorted: Vec<(Point2<f64>, ObstacleId)> = by_obstacle
            .iter()
            .enumerate()
            .filter_map(|(i, p)| p.map(|p| (p, ObstacleId(i as u32))))
            .collect();
        sorted.sort_by(|a, b| a.0.y.total_cmp(&b.0.y).then(a.1.cmp(&b.1)));
        Poles {
            by_obstacle,
            sorted,
        }
    }

    /// The pole of obstacle `o`.
    pub fn pole(&self, o: ObstacleId) -> Option<Point2<f64>> {
        self.by_obstacle.get(o.index()).copied().flatten()
    }

    /// Number of poles.
    pub fn len(&self) -> usize {
        self.sorted.len()
    }

    /// `true` when there are no obstacles.
    pub fn is_empty(&self) -> bool {
        self.sorted.is_empty()
    }

    /// All poles with their obstacles, sorted by `y`.
    pub fn iter(&self) -> impl Iterator<Item = (ObstacleId, Point2<f64>)> + '_ {
        self.sorted.iter().map(|(p, o)| (*o, *p))
    }

    /// The number of pole tests the winding form ([`HSignature::of_path`]) makes for the
    /// polyline through `points`: the poles in each segment's `y` band, summed. Two binary
    /// searches per segment.
    pub fn band_work(&self, points: &[Point2<f64>]) -> usize {
        points
            .windows(2)
            .map(|w| self.in_band(&w[0], &w[1]).len())
            .sum()
    }

    /// The poles whose cut a segment from `a` to `b` might cross: `min y < zeta.y <= max y`.
    fn in_band(&self, a: &Point2<f64>, b: &Point2<f64>) -> &[(Point2<f64>, ObstacleId)] {
        let (lo, hi) = (a.y.min(b.y), a.y.max(b.y));
        let from = self.sorted.partition_point(|(p, _)| p.y <= lo);
        let to = self.sorted.partition_point(|(p, _)| p.y <= hi);
        &self.sorted[from..to.max(from)]
    }
}

/// The H-signature of a path in winding form: its endpoints and, per obstacle, the signed number
/// of times it crosses the obstacle's branch cut (module docs). Equal signatures of paths with
/// the same endpoints mean equal homology classes.
///
/// ```
/// use nalgebra::Point2;
/// use rappel_geometry::{btm::Btm, map::Map, polygon::Polygon};
/// use rappel_homotopy::{h_signature::{HSignature, Poles}, path::Path};
/// let p = |x, y| Point2::new(x, y);
/// let map = Map::new(
///     Polygon::new(vec![p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)]),
///     vec![Polygon::new(vec![p(4., 4.), p(6., 4.), p(6., 6.), p(4., 6.)])],
/// );
/// let btm = Btm::from_map(&map).unwrap();
/// let poles = Poles::new(&btm);
/// let west = Path::new(vec![p(5., 9.), p(1., 5.), p(5., 1.)]).unwrap();
/// let east = Path::new(vec![p(5., 9.), p(9., 5.), p(5., 1.)]).unwrap();
/// let (hw, he) = (HSignature::of_path(&poles, &west), HSignature::of_path(&poles, &east));
/// assert_ne!(hw, he);
/// // The two ways around differ by one full turn: theta_west - theta_east = 2 pi.
/// let o = rappel_geometry::dcel::ObstacleId(0);
/// let turn = hw.angle(&poles, o).unwrap() - he.angle(&poles, o).unwrap();
/// assert!((turn - 2.0 * std::f64::consts::PI).abs() < 1e-12);
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HSignature {
    start: Point2<f64>,
    end: Point2<f64>,
    /// Non-zero winding counts `n_j`, sorted by obstacle id.
    windings: Vec<(ObstacleId, i64)>,
}

impl HSignature {
    /// The signature of the trivial path at `start`; extend it with [`HSignature::push`].
    pub fn new(start: Point2<f64>) -> HSignature {
        HSignature {
            start,
            end: start,
            windings: Vec::new(),
        }
    }

    /// The signature of a path.
    pub fn of_path(poles: &Poles, path: &Path) -> HSignature {
        HSignature::of_polyline(poles, path.points(), &mut Vec::new()).0
    }

    /// The signature of a taut path's polyline, without copying it into a [`Path`] first.
    pub fn of_taut_path(poles: &Poles, taut: &TautPath) -> HSignature {
        HSignature::of_polyline(poles, &taut.points, &mut Vec::new()).0
    }

    /// [`HSignature::of_taut_path`] with a caller's buffer for the cut crossings (cleared
    /// first; left holding them), so that a planner answering many queries allocates only the
    /// signature itself; also returns the pole tests it made ([`Poles::band_work`] of the
    /// path's points, counted on the way instead of by a second pass of binary searches).
    ///
    /// ```
    /// use nalgebra::Point2;
    /// use rappel_geometry::{btm::Btm, map::Map, polygon::Polygon};
    /// use rappel_homotopy::{h_signature::{HSignature, Poles}, path::Path, shp::shortest_homotopic_path};
    /// let p = |x, y| Point2::new(x, y);
    /// let map = Map::new(
    ///     Polygon::new(vec![p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)]),
    ///     vec![Polygon::new(vec![p(4., 4.), p(6., 4.), p(6., 6.), p(4., 6.)])],
    /// );
    /// let btm = Btm::from_map(&map).unwrap();
    /// let poles = Poles::new(&btm);
    /// let west = Path::new(vec![p(5., 9.), p(1., 5.), p(5., 1.)]).unwrap();
    /// let taut = shortest_homotopic_path(&btm, &west).unwrap().taut;
    /// let mut buffer = Vec::new();
    /// let (h, tests) = HSignature::of_taut_path_reusing(&poles, &taut, &mut buffer);
    /// assert_eq!(h, HSignature::of_taut_path(&poles, &taut));
    /// assert_eq!(tests, poles.band_work(&taut.points));
    /// ```
    pub fn of_taut_path_reusing(
        poles: &Poles,
        taut: &TautPath,
        crossings: &mut Vec<u64>,
    ) -> (HSignature, usize) {
        HSignature::of_polyline(poles, &taut.points, crossings)
    }

    /// The polyline through `points` (a taut path's or a path's, never empty: an empty slice
    /// gives the trivial signature at the origin). The crossings of all segments are collected
    /// first and summed per obstacle once, by one sort: `O(c log c)` for `c` cut crossings (a
    /// long path down a strip crosses the cuts of half its obstacles), where adding them one by
    /// one into the sorted list would shift it on every new obstacle. Also returns the pole
    /// tests made ([`Poles::band_work`]).
    fn of_polyline(
        poles: &Poles,
        points: &[Point2<f64>],
        crossings: &mut Vec<u64>,
    ) -> (HSignature, usize) {
        let Some((first, rest)) = points.split_first() else {
            return (HSignature::new(Point2::origin()), 0);
        };
        crossings.clear();
        let mut a = *first;
        let mut tests = 0;
        for q in rest {
            tests += cut_crossings(poles, &a, q, |o, delta| crossings.push(pack(o, delta > 0)));
            a = *q;
        }
        (HSignature::from_packed(*first, a, crossings), tests)
    }

    /// The signature of the class whose sleeve is `sleeve`, for a path from `start` (in the
    /// sleeve's first triangle) to `goal` (in its last), read from the cuts `index` lists for the
    /// sleeve's triangles (module docs, "From the sleeve"): equal to the winding form of every
    /// path from `start` to `goal` whose reduced crossing sequence is the sleeve's portals (its
    /// SHP's, for instance). `index` must have been built for the sleeve's BTM.
    pub fn of_sleeve(
        btm: &Btm,
        index: &CutIndex,
        start: Point2<f64>,
        goal: Point2<f64>,
        sleeve: &Sleeve,
    ) -> HSignature {
        HSignature::of_sleeve_reusing(btm, index, start, goal, sleeve, &mut Vec::new())
    }

    /// [`HSignature::of_sleeve`] with a caller's buffer for the cut crossings (cleared first;
    /// left holding them), as [`HSignature::of_taut_path_reusing`].
    pub fn of_sleeve_reusing(
        btm: &Btm,
        index: &CutIndex,
        start: Point2<f64>,
        goal: Point2<f64>,
        sleeve: &Sleeve,
        crossings: &mut Vec<u64>,
    ) -> HSignature {
        crossings.clear();
        let d = btm.dcel();
        let ends = |h: HalfEdgeId| {
            let (u, v) = (d.point(d.origin(h)), d.point(d.destination(h)));
            (u.y, v.y)
        };
        let mut entry = Side::Point(start.y);
        let portals = sleeve.portals();
        for (i, &t) in sleeve.triangles().iter().enumerate() {
            let exit = match portals.get(i) {
                Some(&h) => entry.onto(ends(h)),
                None => Side::Point(goal.y),
            };
            // The triangle's cuts are sorted by height: those at or below the entry's height
            // come first, so the crossed ones are one range between the two partition points.
            let cuts = index.cuts(t);
            let at_entry = cuts.partition_point(|&r| entry.at_or_above(index.height(r)));
            let at_exit = cuts.partition_point(|&r| exit.at_or_above(index.height(r)));
            // Downwards (entry above) is +1, upwards -1: the direction bit of `pack`.
            let (range, down) = if at_entry > at_exit {
                (at_exit..at_entry, true)
            } else {
                (at_entry..at_exit, false)
            };
            crossings.extend(cuts[range].iter().map(|&r| pack(index.obstacle(r), down)));
            entry = exit;
        }
        HSignature::from_packed(start, goal, crossings)
    }

    /// The signature from its endpoints and its cut crossings packed by [`pack`], in any order:
    /// one sort of machine words, summed per obstacle, zero sums dropped.
    fn from_packed(start: Point2<f64>, end: Point2<f64>, crossings: &mut [u64]) -> HSignature {
        crossings.sort_unstable();
        let mut windings: Vec<(ObstacleId, i64)> = Vec::with_capacity(crossings.len());
        for &c in crossings.iter() {
            let (o, delta) = (ObstacleId((c >> 1) as u32), if c & 1 == 1 { 1 } else { -1 });
            match windings.last_mut() {
                Some((last, n)) if *last == o => *n += delta,
                _ => windings.push((o, delta)),
            }
        }
        windings.retain(|&(_, n)| n != 0);
        HSignature {
            start,
            end,
            windings,
        }
    }

    /// Extends the path by a segment from its current end to `q`. A segment through a pole
    /// (impossible for paths in free space) counts no crossing for it.
    pub fn push(&mut self, poles: &Poles, q: Point2<f64>) {
        let a = self.end;
        cut_crossings(poles, &a, &q, |o, delta| self.add(o, delta));
        self.end = q;
    }

    fn add(&mut self, o: ObstacleId, delta: i64) {
        match self.windings.binary_search_by_key(&o, |(id, _)| *id) {
            Ok(i) => {
                self.windings[i].1 += delta;
                if self.windings[i].1 == 0 {
                    self.windings.remove(i);
                }
            }
            Err(i) => self.windings.insert(i, (o, delta)),
        }
    }

    /// The path's start.
    pub fn start(&self) -> Point2<f64> {
        self.start
    }

    /// The path's end.
    pub fn end(&self) -> Point2<f64> {
        self.end
    }

    /// The non-zero winding counts `n_j`, sorted by obstacle id.
    pub fn windings(&self) -> &[(ObstacleId, i64)] {
        &self.windings
    }

    /// The winding count `n_j` of one obstacle (zero for most).
    pub fn winding(&self, o: ObstacleId) -> i64 {
        self.windings
            .binary_search_by_key(&o, |(id, _)| *id)
            .map_or(0, |i| self.windings[i].1)
    }

    /// `true` when every winding count is zero. For a loop this means it is null-homologous
    /// (winds zero times around every obstacle); it may still not be contractible (module docs).
    pub fn is_trivial(&self) -> bool {
        self.windings.is_empty()
    }

    /// The total change of `arg(z - zeta_o)` along the path, `theta_o`, in radians.
    pub fn angle(&self, poles: &Poles, o: ObstacleId) -> Option<f64> {
        let zeta = poles.pole(o)?;
        let arg = |p: &Point2<f64>| (p.y - zeta.y).atan2(p.x - zeta.x);
        Some(arg(&self.end) - arg(&self.start) + 2.0 * PI * self.winding(o) as f64)
    }

    /// `L_o = integral of dz / (z - zeta_o)` along the path (module docs).
    pub fn integral(&self, poles: &Poles, o: ObstacleId) -> Option<Complex<f64>> {
        let zeta = poles.pole(o)?;
        let theta = self.angle(poles, o)?;
        let re = (self.end - zeta).norm().ln() - (self.start - zeta).norm().ln();
        Some(Complex::new(re, theta))
    }

    /// Eq. 2.3's H-signature `sum_j c_j L_j` for the analytic numerator `f0` (the entire part of
    /// the partial fractions is omitted: it is the same for all paths with these endpoints).
    /// `O(N^2)` and, as the module docs explain, numerically meaningless beyond a few dozen
    /// obstacles: for illustration and tests; compare signatures with `==`.
    pub fn product_form(
        &self,
        poles: &Poles,
        f0: impl Fn(Complex<f64>) -> Complex<f64>,
    ) -> Complex<f64> {
        let zs: Vec<(ObstacleId, Complex<f64>)> = poles
            .iter()
            .map(|(o, p)| (o, Complex::new(p.x, p.y)))
            .collect();
        zs.iter()
            .map(|&(o, zj)| {
                let denominator: Complex<f64> = zs
                    .iter()
                    .filter(|(k, _)| *k != o)
                    .map(|&(_, zk)| zj - zk)
                    .product();
                let l = self.integral(poles, o).unwrap_or_default();
                f0(zj) / denominator * l
            })
            .sum()
    }

    /// A 64-bit digest of the signature (FNV-1a over the endpoints' bits and the winding
    /// counts), the same on every platform: a short label for printing and bucketing classes.
    /// Equal signatures have equal digests; compare signatures with `==` to decide equality.
    pub fn digest(&self) -> u64 {
        const OFFSET: u64 = 0xcbf2_9ce4_8422_2325;
        const PRIME: u64 = 0x0000_0100_0000_01b3;
        let words = [self.start.x, self.start.y, self.end.x, self.end.y]
            .into_iter()
            .map(f64::to_bits)
            .chain(
                self.windings
                    .iter()
                    .flat_map(|&(o, n)| [u64::from(o.0), n as u64]),
            );
        words.fold(OFFSET, |h, w| {
            w.to_le_bytes()
                .iter()
                .fold(h, |h, b| (h ^ u64::from(*b)).wrapping_mul(PRIME))
        })
    }

    /// The signature of the reversed path.
    pub fn reversed(&self) -> HSignature {
        HSignature {
            start: self.end,
            end: self.start,
            windings: self.windings.iter().map(|&(o, n)| (o, -n)).collect(),
        }
    }
}

/// Calls `crossed(obstacle, delta)` for every pole whose branch cut the segment from `a` to `q`
/// crosses (module docs): `+1` downwards (counter-clockwise about the pole), `-1` upwards.
/// Returns the number of poles tested (those in the segment's `y` band).
fn cut_crossings(
    poles: &Poles,
    a: &Point2<f64>,
    q: &Point2<f64>,
    mut crossed: impl FnMut(ObstacleId, i64),
) -> usize {
    let band = poles.in_band(a, q);
    for (zeta, o) in band {
        let (a_above, q_above) = (a.y >= zeta.y, q.y >= zeta.y);
        if a_above == q_above {
            continue;
        }
        let turn = orient2d(a, q, zeta);
        if a_above && turn > 0.0 {
            crossed(*o, 1);
        } else if q_above && turn < 0.0 {
            crossed(*o, -1);
        }
    }
    band.len()
}

/// Where a point of the sleeve path lies, as far as the cuts' lines care: its `y`, or the exact
/// midpoint of a portal given by its endpoints' `y`.
#[derive(Clone, Copy)]
enum Side {
    Point(f64),
    Midpoint((f64, f64)),
}

impl Side {
    /// The sleeve path's point on the next portal, whose ends have heights `(u, v)`: strictly
    /// inside the portal, at a height as close to this point's as possible, so that the path
    /// climbs and drops no more than its sleeve forces it to (every cut it crosses and crosses
    /// back is work, not signature). Any point strictly inside a portal gives the same signature
    /// (module docs); the height is the previous one clamped to the portal's open range (the
    /// first float inside at an end), the portal's height when it is level, and its exact
    /// midpoint when no float lies strictly between its ends.
    #[inline]
    fn onto(self, (u, v): (f64, f64)) -> Side {
        let (lo, hi) = if u <= v { (u, v) } else { (v, u) };
        if lo == hi {
            return Side::Point(lo);
        }
        let (first, last) = (lo.next_up(), hi.next_down());
        if first > last {
            return Side::Midpoint((u, v));
        }
        let y = match self {
            Side::Point(y) => y,
            // A midpoint lies strictly inside its own portal: start from either end's side.
            Side::Midpoint((a, _)) => a,
        };
        Side::Point(y.clamp(first, last))
    }

    /// `true` when the point is at or above the line `y = cut` (the half-open rule of the module
    /// docs). For a midpoint `(u + v) / 2 >= cut` is decided exactly: the rounded sum `s` of `u`
    /// and `v` is on the same side of `2 cut` as the exact sum whenever they differ (rounding to
    /// nearest is monotone and `2 cut` is a float), and when `s = 2 cut` the sign of the sum's
    /// rounding error (Knuth's two-sum, exact) decides. Coordinates lie in the map's domain
    /// ([`rappel_geometry::domain`]), so nothing overflows.
    #[inline]
    fn at_or_above(self, cut: f64) -> bool {
        match self {
            Side::Point(y) => y >= cut,
            Side::Midpoint((u, v)) => {
                let s = u + v;
                let twice = 2.0 * cut;
                if s != twice {
                    return s > twice;
                }
                let bv = s - u;
                let av = s - bv;
                (u - av) + (v - bv) >= 0.0
            }
        }
    }
}

/// One cut crossing as a machine word: the obstacle id above a direction bit (1 downwards,
/// counter-clockwise about the pole, `+1`; 0 upwards, `-1`), so that sorting the words groups
/// the crossings by obstacle in increasing id.
#[inline]
fn pack(o: ObstacleId, down: bool) -> u64 {
    (u64::from(o.0) << 1) | u64::from(down)
}

/// For every free triangle of a BTM, the branch cuts (module docs) that meet it: the poles `zeta`
/// with `min y < zeta.y <= max y` over the triangle's corners whose cut (the ray from `zeta`
/// towards `-x`, lowered infinitesimally by the half-open rule) passes through the triangle, as
/// ranks into the poles sorted by height, so each triangle's list is sorted by height too. Built
/// once per map, it lets [`HSignature::of_sleeve`] read a class's signature from its sleeve.
///
/// The build examines, for each free triangle, the poles in its `y` range (found by galloping
/// from the previous triangle's range: triangles are numbered in a spatially coherent order);
/// on a map long in `x` (cuts crossing many triangles) the index could grow to `O(poles x
/// triangles)`, so the build stops once it has examined [`CutIndex::MAX_WORK_PER_TRIANGLE`] poles
/// per free triangle, and the map has no index: signatures are then computed in winding form.
#[derive(Debug, Clone, PartialEq)]
pub struct CutIndex {
    /// `(zeta.y, obstacle)` of every pole, sorted by height (then id).
    poles: Vec<(f64, ObstacleId)>,
    /// `first[t] .. first[t + 1]` is triangle `t`'s range in `cuts` (triangle capacity + 1).
    first: Vec<u32>,
    /// Ranks into `poles` of the cuts meeting each triangle, grouped by triangle, ascending.
    cuts: Vec<u32>,
}

impl CutIndex {
    /// Most poles examined per free triangle, on average over the map, before the build gives up
    /// (the crater strips need about 5 to 10).
    pub const MAX_WORK_PER_TRIANGLE: usize = 64;

    /// The index of `btm`'s free triangles for `poles`, or `None` when the map is too
    /// unfavourable (the work bound above) or a pole lies in a closed free triangle (poles from
    /// [`Poles::new`] never do; [`Poles::from_points`] may place one there).
    pub fn new(btm: &Btm, poles: &Poles) -> Option<CutIndex> {
        let d = btm.dcel();
        let capacity = d.triangle_capacity();
        let free = btm.triangles().count();
        let budget = free
            .saturating_mul(Self::MAX_WORK_PER_TRIANGLE)
            .min(u32::MAX as usize);
        let sorted = &poles.sorted;
        let mut work = 0usize;
        let mut first = Vec::with_capacity(capacity + 1);
        let mut cuts = Vec::new();
        let (mut from, mut to) = (0, 0);
        for t in (0..capacity as u32).map(TriangleId) {
            first.push(cuts.len() as u32);
            if d.face_kind(t) != FaceKind::Free {
                continue;
            }
            let corners = d.triangle_points(t);
            let lo = corners.iter().map(|p| p.y).fold(f64::INFINITY, f64::min);
            let hi = corners
                .iter()
                .map(|p| p.y)
                .fold(f64::NEG_INFINITY, f64::max);
            from = gallop(sorted, from, |(p, _)| p.y <= lo);
            to = gallop(sorted, to, |(p, _)| p.y <= hi);
            for (rank, (zeta, _)) in sorted.iter().enumerate().take(to).skip(from) {
                work += 1;
                if work > budget {
                    return None;
                }
                if cut_meets(&corners, zeta)? {
                    cuts.push(rank as u32);
                }
            }
        }
        first.push(cuts.len() as u32);
        cuts.shrink_to_fit();
        Some(CutIndex {
            poles: sorted.iter().map(|(p, o)| (p.y, *o)).collect(),
            first,
            cuts,
        })
    }

    /// The cuts meeting triangle `t`, as ranks ([`CutIndex::height`], [`CutIndex::obstacle`]),
    /// ascending in height (empty for ids beyond the BTM's capacity when built).
    pub fn cuts(&self, t: TriangleId) -> &[u32] {
        match (self.first.get(t.index()), self.first.get(t.index() + 1)) {
            (Some(&a), Some(&b)) => &self.cuts[a as usize..b as usize],
            _ => &[],
        }
    }

    /// The height `zeta.y` of the cut of rank `r`.
    #[inline]
    pub fn height(&self, r: u32) -> f64 {
        self.poles[r as usize].0
    }

    /// The obstacle of the cut of rank `r`.
    #[inline]
    pub fn obstacle(&self, r: u32) -> ObstacleId {
        self.poles[r as usize].1
    }

    /// Number of (triangle, cut) pairs listed.
    pub fn len(&self) -> usize {
        self.cuts.len()
    }

    /// `true` when no cut meets any free triangle.
    pub fn is_empty(&self) -> bool {
        self.cuts.is_empty()
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        self.poles.capacity() * std::mem::size_of::<(f64, ObstacleId)>()
            + self.first.capacity() * 4
            + self.cuts.capacity() * 4
    }
}

/// The partition point of `sorted` for the monotone predicate `below` (true on a prefix),
/// found by galloping from the previous answer `hint`: `O(log k)` for an answer `k` places away.
fn gallop<T>(sorted: &[T], hint: usize, below: impl Fn(&T) -> bool) -> usize {
    let hint = hint.min(sorted.len());
    if hint < sorted.len() && below(&sorted[hint]) {
        // Forwards: the answer is beyond `hint`.
        let mut step = 1;
        let mut lo = hint + 1;
        while lo + step <= sorted.len() && below(&sorted[lo + step - 1]) {
            lo += step;
            step *= 2;
        }
        let hi = (lo + step).min(sorted.len());
        lo + sorted[lo..hi].partition_point(below)
    } else {
        // Backwards: the answer is at or before `hint`.
        let mut step = 1;
        let mut hi = hint;
        while hi >= step && !below(&sorted[hi - step]) {
            hi -= step;
            step *= 2;
        }
        let lo = hi.saturating_sub(step);
        lo + sorted[lo..hi].partition_point(below)
    }
}

/// Whether the cut of `zeta` meets the counter-clockwise triangle `corners`, given `min y <
/// zeta.y <= max y` (so the line `y = zeta.y`, lowered infinitesimally, crosses its interior):
/// the line's chord through the triangle ends on the two edges whose ends lie on opposite sides
/// of the line, and lies wholly on one side of `zeta` unless `zeta` is in the closed triangle.
/// On each of the two edges, directed upwards, `zeta` lies to the right exactly when that end
/// of the chord is to its left. Both ends on the left: the cut meets the triangle; both on the
/// right: it does not. `None` when they disagree or `zeta` lies on one of the edges (it is then
/// in the closed triangle: no side).
fn cut_meets(corners: &[Point2<f64>; 3], zeta: &Point2<f64>) -> Option<bool> {
    let mut sides = [None, None];
    let mut found = 0;
    for i in 0..3 {
        let (u, v) = (corners[i], corners[(i + 1) % 3]);
        let (u_above, v_above) = (u.y >= zeta.y, v.y >= zeta.y);
        if u_above == v_above {
            continue;
        }
        let (below, above) = if v_above { (u, v) } else { (v, u) };
        let turn = orient2d(&below, &above, zeta);
        if turn == 0.0 || found == 2 {
            return None;
        }
        sides[found] = Some(turn < 0.0);
        found += 1;
    }
    match sides {
        [Some(a), Some(b)] if a == b => Some(a),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::{Side, gallop};

    #[test]
    fn portal_points_lie_strictly_inside_and_midpoints_are_decided_exactly() {
        // Clamped strictly inside the open height range.
        let Side::Point(y) = Side::Point(5.0).onto((1.0, 2.0)) else {
            panic!("a float lies inside");
        };
        assert!(1.0 < y && y < 2.0 && y == 2.0f64.next_down());
        let Side::Point(y) = Side::Point(1.5).onto((2.0, 1.0)) else {
            panic!("a float lies inside");
        };
        assert_eq!(y, 1.5);
        // A level portal keeps its height.
        assert!(matches!(
            Side::Point(0.0).onto((3.0, 3.0)),
            Side::Point(3.0)
        ));
        // Ends one ulp apart: no float strictly between, so the exact midpoint 1 + 2^-53, whose
        // rounded doubled sum is exactly 2 (the tie the error-free sum decides).
        let (u, v) = (1.0f64, 1.0f64.next_up());
        let mid = Side::Point(0.0).onto((u, v));
        assert!(matches!(mid, Side::Midpoint(_)));
        assert!(mid.at_or_above(1.0));
        assert!(!mid.at_or_above(v));
        assert!(mid.at_or_above(0.5));
        assert!(!mid.at_or_above(1.5));
        assert!(Side::Point(1.0).at_or_above(1.0));
    }

    #[test]
    fn galloping_finds_the_partition_point_from_any_hint() {
        // Sorted values with repeats; every threshold and every hint, against `partition_point`.
        let sorted: Vec<u32> = (0..40u32).map(|i| i / 3).collect();
        for threshold in 0..16 {
            let expected = sorted.partition_point(|&x| x <= threshold);
            for hint in 0..=sorted.len() + 2 {
                assert_eq!(
                    gallop(&sorted, hint, |&x| x <= threshold),
                    expected,
                    "threshold {threshold}, hint {hint}"
                );
            }
        }
        assert_eq!(gallop(&[] as &[u32], 3, |&x| x < 1), 0);
    }
}
