//! H-signatures: agreement with the analytic angle sum and with eq. 2.3's product form evaluated
//! by quadrature, exact winding counts among 10,000 poles, the homology-versus-homotopy
//! caveat of thesis Fig. 2.4, and signatures read from sleeves through the cut index equal to
//! the winding form on random walks (crater strips, and a map built for ties: poles at the height
//! of obstacle vertices and of portal midpoints).

use crate::common;

use common::{p, random_walk, small_strip, steps};
use nalgebra::{Complex, Point2};
use proptest::prelude::*;
use rappel_geometry::btm::Btm;
use rappel_geometry::dcel::ObstacleId;
use rappel_geometry::map::Map;
use rappel_geometry::polygon::{PointInPolygon, Polygon};
use rappel_homotopy::crossing::CrossingSequence;
use rappel_homotopy::h_signature::{CutIndex, HSignature, Poles};
use rappel_homotopy::homotopy::is_contractible;
use rappel_homotopy::path::Path;
use rappel_homotopy::sleeve::Sleeve;
use std::f64::consts::{PI, TAU};

/// Tolerance for comparing two ways of computing the same angle sum (a few hundred terms of
/// `atan2`, each exact to an ulp).
const ANGLE_TOLERANCE: f64 = 1e-9;

/// Two square obstacles A = [2, 4] x [4, 6] and B = [6, 8] x [4, 6] in a 10 x 10 map.
fn two_squares() -> Btm {
    let sq = |x0: f64, y0: f64| {
        Polygon::new(vec![
            p(x0, y0),
            p(x0 + 2., y0),
            p(x0 + 2., y0 + 2.),
            p(x0, y0 + 2.),
        ])
    };
    let map = Map::new(
        Polygon::new(vec![p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)]),
        vec![sq(2., 4.), sq(6., 4.)],
    );
    Btm::from_map(&map).unwrap()
}

/// The angle `arg(z - zeta)` sweeps along a polyline, summed segment by segment (each segment
/// subtends less than pi): an independent evaluation of `theta`.
fn subtended(points: &[Point2<f64>], zeta: Point2<f64>) -> f64 {
    points
        .windows(2)
        .map(|w| {
            let (u, v) = (w[0] - zeta, w[1] - zeta);
            (u.x * v.y - u.y * v.x).atan2(u.dot(&v))
        })
        .sum()
}

#[test]
fn fig_2_4_commutator_loop_has_trivial_signature_but_is_not_contractible() {
    let btm = two_squares();
    let poles = Poles::new(&btm);
    // Basepoint (5, 2), between and below A and B. Loop around A counter-clockwise, then around B
    // counter-clockwise, then A clockwise, then B clockwise.
    let base = p(5., 2.);
    let around_a = [p(5., 3.), p(5., 7.), p(1., 7.), p(1., 3.), p(5., 3.)];
    let around_b = [p(5., 3.), p(9., 3.), p(9., 7.), p(5., 7.), p(5., 3.)];
    let rev = |v: &[Point2<f64>]| v.iter().rev().copied().collect::<Vec<_>>();
    let mut points = vec![base];
    for piece in [
        around_a.to_vec(),
        around_b.to_vec(),
        rev(&around_a),
        rev(&around_b),
    ] {
        points.extend(piece);
        points.push(base);
    }
    let commutator = Path::new(points).unwrap();
    let h = HSignature::of_path(&poles, &commutator);
    assert!(h.is_trivial());
    assert_eq!(h.winding(ObstacleId(0)), 0);
    let chi = CrossingSequence::reduced_of_path(&btm, &commutator).unwrap();
    assert!(!chi.is_empty());
    assert!(!is_contractible(&btm, &commutator).unwrap());
    // Each piece alone winds once.
    let mut a_loop = vec![base];
    a_loop.extend(around_a);
    a_loop.push(base);
    let ha = HSignature::of_path(&poles, &Path::new(a_loop).unwrap());
    assert_eq!(ha.windings(), &[(ObstacleId(0), 1)]);
}

#[test]
fn angles_match_the_segment_by_segment_sum() {
    let btm = two_squares();
    let poles = Poles::new(&btm);
    // A path that winds around A twice and B once, clockwise.
    let pts = vec![
        p(5., 9.),
        p(1., 9.),
        p(1., 1.),
        p(5., 1.),
        p(5., 9.),
        p(1., 9.),
        p(1., 1.),
        p(9., 1.),
        p(9., 9.),
        p(5., 8.),
    ];
    let h = HSignature::of_path(&poles, &Path::new(pts.clone()).unwrap());
    for (o, zeta) in poles.iter() {
        let expected = subtended(&pts, zeta);
        let got = h.angle(&poles, o).unwrap();
        assert!(
            (got - expected).abs() < ANGLE_TOLERANCE,
            "{o}: {got} vs {expected}"
        );
    }
    assert_eq!(h.winding(ObstacleId(0)), 2);
    assert_eq!(h.winding(ObstacleId(1)), 1);
    assert_eq!(h.reversed().winding(ObstacleId(0)), -2);
    assert_eq!(h.reversed().reversed(), h);
    assert_eq!(h.reversed().reversed().digest(), h.digest());
    assert_ne!(h.reversed().digest(), h.digest());
}

#[test]
fn product_form_equals_quadrature_of_eq_2_3() {
    // Three poles; f0 = 1 (numerator degree below N, so F is exactly the sum of its partial
    // fractions). Composite Simpson along each segment, far from the poles.
    let poles = Poles::from_points([
        (ObstacleId(0), p(3., 5.)),
        (ObstacleId(1), p(7., 5.)),
        (ObstacleId(2), p(5., 2.)),
    ]);
    let zetas: Vec<Complex<f64>> = poles.iter().map(|(_, z)| Complex::new(z.x, z.y)).collect();
    let f = |z: Complex<f64>| {
        Complex::new(1.0, 0.0) / zetas.iter().map(|zj| z - zj).product::<Complex<f64>>()
    };
    let pts = vec![
        p(5., 9.),
        p(1., 9.),
        p(1., 1.),
        p(9., 0.5),
        p(9., 8.),
        p(5., 7.),
    ];
    let mut quad = Complex::new(0.0, 0.0);
    let m = 4000;
    for w in pts.windows(2) {
        let (a, b) = (Complex::new(w[0].x, w[0].y), Complex::new(w[1].x, w[1].y));
        let dz = (b - a) / m as f64;
        let mut s = f(a) + f(b);
        for k in 1..m {
            s += f(a + dz * k as f64) * if k % 2 == 1 { 4.0 } else { 2.0 };
        }
        quad += s * dz / 3.0;
    }
    let h = HSignature::of_path(&poles, &Path::new(pts).unwrap());
    let closed = h.product_form(&poles, |_| Complex::new(1.0, 0.0));
    assert!((closed - quad).norm() < 1e-8, "{closed} vs {quad}");
}

#[test]
fn windings_are_exact_among_ten_thousand_poles() {
    // 10,000 poles on a jittered grid; a star-shaped loop; every pole inside winds exactly once
    // (the loop is counter-clockwise), every pole outside zero times.
    let mut state = 0x2545_F491_4F6C_DD1Du64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let poles = Poles::from_points((0..10_000u32).map(|i| {
        let (gx, gy) = ((i % 100) as f64, (i / 100) as f64);
        (
            ObstacleId(i),
            p(gx + 0.1 + 0.8 * next(), gy + 0.1 + 0.8 * next()),
        )
    }));
    let n = 200;
    let ring: Vec<Point2<f64>> = (0..n)
        .map(|k| {
            let t = TAU * k as f64 / n as f64;
            let r = 20.0 + 25.0 * next();
            p(50.0 + r * t.cos(), 50.0 + r * t.sin())
        })
        .collect();
    let mut closed = ring.clone();
    closed.push(ring[0]);
    let h = HSignature::of_path(&poles, &Path::new(closed).unwrap());
    let polygon = Polygon::new(ring);
    let mut inside = 0;
    for (o, zeta) in poles.iter() {
        let expected = match polygon.locate(&zeta) {
            PointInPolygon::Inside => 1,
            PointInPolygon::Outside => 0,
            PointInPolygon::OnBoundary => continue,
        };
        inside += expected;
        assert_eq!(h.winding(o), expected, "pole {o} at {zeta:?}");
    }
    assert!(inside > 1000);
    assert_eq!(h.windings().len(), inside as usize);
    // And the loop's angle around a pole inside is exactly one turn.
    let (o, _) = h.windings()[0];
    assert!((h.angle(&poles, o).unwrap() - 2.0 * PI).abs() < ANGLE_TOLERANCE);
}

#[test]
fn batch_and_incremental_signatures_agree_on_a_winding_zigzag() {
    // 2,000 poles on a jittered grid and a zigzag that sweeps back and forth across their cuts,
    // crossing many twice in opposite directions (the sums cancel) and some once: the signature
    // of the whole polyline (crossings summed by one sort) equals the one grown segment by segment,
    // and every pole's angle equals the independently subtended one.
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let poles = Poles::from_points((0..2_000u32).map(|i| {
        let (gx, gy) = ((i % 40) as f64, (i / 40) as f64);
        (
            ObstacleId(i),
            p(gx + 0.1 + 0.8 * next(), gy + 0.1 + 0.8 * next()),
        )
    }));
    let pts: Vec<Point2<f64>> = (0..60)
        .map(|k| {
            p(
                40.0 * next(),
                50.0 * next() + if k % 2 == 0 { 0.0 } else { 0.5 },
            )
        })
        .collect();
    let batch = HSignature::of_path(&poles, &Path::new(pts.clone()).unwrap());
    let mut grown = HSignature::new(pts[0]);
    for q in &pts[1..] {
        grown.push(&poles, *q);
    }
    assert_eq!(batch, grown);
    assert!(batch.windings().len() > 100, "{}", batch.windings().len());
    assert!(batch.windings().windows(2).all(|w| w[0].0 < w[1].0));
    assert!(batch.windings().iter().all(|&(_, n)| n != 0));
    for (o, zeta) in poles.iter() {
        let expected = subtended(&pts, zeta);
        let got = batch.angle(&poles, o).unwrap();
        assert!(
            (got - expected).abs() < ANGLE_TOLERANCE,
            "{o}: {got} vs {expected}"
        );
    }
}

#[test]
fn poles_lie_inside_their_obstacles() {
    let (g, btm) = common::small_strip(8, 3);
    let poles = Poles::new(&btm);
    assert_eq!(poles.len(), g.map.obstacles.len());
    for (o, zeta) in poles.iter() {
        assert_eq!(
            btm.locate(&zeta),
            rappel_geometry::btm::Location::Obstacle(o)
        );
    }
}

/// A 20 x 20 map built for ties: right triangles `(x0, y0), (x0 + 3, y0), (x0, y0 + 3)` whose
/// poles (their centroids, exactly `(x0 + 1, y0 + 1)`) lie at the height of no vertex of their
/// own but at the exact midpoint height of the diagonals from the squares `[6, 7] x [y0, y0 + 2]`
/// and `[12, 13] x [y0, y0 + 2]` (corners at `y0` and `y0 + 2`) to the triangles' corners.
fn tie_map() -> (Map, Btm) {
    let mut obstacles = Vec::new();
    for y0 in [2.0, 8.0, 14.0] {
        for x0 in [2.0, 8.0, 14.0] {
            obstacles.push(Polygon::new(vec![
                p(x0, y0),
                p(x0 + 3., y0),
                p(x0, y0 + 3.),
            ]));
        }
        for x0 in [6.0, 12.0] {
            obstacles.push(Polygon::new(vec![
                p(x0, y0),
                p(x0 + 1., y0),
                p(x0 + 1., y0 + 2.),
                p(x0, y0 + 2.),
            ]));
        }
    }
    let map = Map::new(
        Polygon::new(vec![p(0., 0.), p(20., 0.), p(20., 20.), p(0., 20.)]),
        obstacles,
    );
    let btm = Btm::from_map(&map).unwrap();
    (map, btm)
}

/// The signature read from the path's sleeve equals the winding form of the path itself.
fn sleeve_agrees(btm: &Btm, poles: &Poles, index: &CutIndex, points: Vec<Point2<f64>>) {
    let path = Path::new(points).unwrap();
    let chi = CrossingSequence::reduced_of_path(btm, &path).unwrap();
    let sleeve = Sleeve::from_crossing_sequence(btm, &chi).unwrap();
    let from_sleeve = HSignature::of_sleeve(btm, index, path.start(), path.end(), &sleeve);
    assert_eq!(from_sleeve, HSignature::of_path(poles, &path), "{path:?}");
}

#[test]
fn the_tie_map_has_poles_at_vertex_and_midpoint_heights() {
    let (_, btm) = tie_map();
    let poles = Poles::new(&btm);
    assert_eq!(poles.len(), 15);
    let d = btm.dcel();
    let pole_heights: Vec<f64> = poles.iter().map(|(_, z)| z.y).collect();
    // Some diagonal's exact midpoint lies at a pole's height (the ties the index must decide).
    let tie = btm.triangles().flat_map(|t| t.half_edges()).any(|h| {
        d.twin(h).is_some() && {
            let (u, v) = (d.point(d.origin(h)), d.point(d.destination(h)));
            u.y != v.y && pole_heights.contains(&(0.5 * (u.y + v.y)))
        }
    });
    assert!(tie);
    assert!(poles.iter().any(|(_, z)| z.y == 3.0));
}

#[test]
fn the_index_refuses_poles_in_free_space_and_maps_long_across_the_cuts() {
    // A pole placed in a free triangle: no chord side, no index.
    let (_, btm) = tie_map();
    let poles = Poles::from_points([(ObstacleId(0), p(1.0, 1.0))]);
    assert_eq!(CutIndex::new(&btm, &poles), None);
    // 300 obstacles in one row along x: every cut crosses the whole row, so the index would hold
    // O(poles x triangles) entries; the build gives up and signatures stay in winding form.
    let row: Vec<Polygon> = (0..300)
        .map(|i| {
            let x = 2.0 + 3.0 * f64::from(i);
            Polygon::new(vec![p(x, 4.0), p(x + 1.0, 4.0), p(x + 1.0, 6.0), p(x, 6.0)])
        })
        .collect();
    let map = Map::new(
        Polygon::new(vec![p(0., 0.), p(903., 0.), p(903., 10.), p(0., 10.)]),
        row,
    );
    let btm = Btm::from_map(&map).unwrap();
    assert_eq!(CutIndex::new(&btm, &Poles::new(&btm)), None);
    // The tie map itself is indexed.
    let (_, btm) = tie_map();
    let index = CutIndex::new(&btm, &Poles::new(&btm)).expect("a small map is indexed");
    assert!(!index.is_empty());
}

#[test]
fn sleeve_signatures_equal_the_winding_form_around_and_through_ties() {
    // Hand-made: once around the middle triangle (pole (9, 9)) counter-clockwise, through the
    // vertex heights of the ties, and the straight segment beside it.
    let (_, btm) = tie_map();
    let poles = Poles::new(&btm);
    let index = CutIndex::new(&btm, &poles).unwrap();
    let around = vec![
        p(7.5, 7.5),
        p(11.5, 7.5),
        p(11.5, 11.5),
        p(7.5, 11.5),
        p(7.5, 7.5),
        p(11.5, 7.5),
    ];
    sleeve_agrees(&btm, &poles, &index, around.clone());
    let h = HSignature::of_path(&poles, &Path::new(around).unwrap());
    assert!(!h.is_trivial());
    sleeve_agrees(&btm, &poles, &index, vec![p(1., 1.), p(1., 19.)]);
    sleeve_agrees(&btm, &poles, &index, vec![p(5.5, 19.), p(5.5, 1.)]);
    sleeve_agrees(
        &btm,
        &poles,
        &index,
        vec![p(5.5, 1.), p(5.5, 6.5), p(11.5, 6.5), p(11.5, 3.)],
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    /// Random walks (through obstacle vertices and along edges, winding around obstacles) on
    /// seeded crater strips: the signature read from the walk's sleeve is the walk's own.
    #[test]
    fn sleeve_signatures_equal_the_winding_form_on_strips(
        seed in 0u64..10_000,
        n in 1usize..12,
        walk in steps(40),
    ) {
        let (g, btm) = small_strip(n, seed);
        let poles = Poles::new(&btm);
        let index = CutIndex::new(&btm, &poles).expect("strips are indexed");
        sleeve_agrees(&btm, &poles, &index, random_walk(&g.map, g.start, &walk));
    }

    /// The same on the tie map, walks snapping to vertices at the poles' heights.
    #[test]
    fn sleeve_signatures_equal_the_winding_form_on_ties(
        from in 0usize..4,
        walk in steps(60),
    ) {
        let (map, btm) = tie_map();
        let poles = Poles::new(&btm);
        let index = CutIndex::new(&btm, &poles).unwrap();
        let start = [p(1., 1.), p(5., 3.), p(11., 9.), p(19., 15.)][from];
        sleeve_agrees(&btm, &poles, &index, random_walk(&map, start, &walk));
    }
}
