//! Crossing sequences: the symbolic perturbation rules for paths through vertices, along edges and
//! with endpoints on the skeleton, reduction, and path validation against free space.

use crate::common;

use common::{p, random_walk, segment_clear, small_strip, square_map, steps};
use nalgebra::Point2;
use proptest::prelude::*;
use rappel_geometry::btm::{Btm, Location};
use rappel_geometry::dcel::ObstacleId;
use rappel_homotopy::crossing::{CrossingSequence, Tracer};
use rappel_homotopy::homotopy::{HomotopyError, LoopPrefix, are_homotopic, is_contractible};
use rappel_homotopy::path::{Blocker, Path, PathError};

fn path(points: &[(f64, f64)]) -> Path {
    Path::new(points.iter().map(|&(x, y)| p(x, y)).collect()).expect("valid path")
}

fn homotopic(btm: &Btm, a: &[(f64, f64)], b: &[(f64, f64)]) -> bool {
    are_homotopic(btm, &path(a), &path(b)).expect("valid paths")
}

#[test]
fn grazing_an_obstacle_corner_is_homotopic_to_passing_beside_it() {
    let (_, btm) = square_map();
    // The line x + y = 8 touches the square [4, 6]^2 only at its corner (4, 4).
    let grazing = [(2., 6.), (6., 2.)];
    assert!(homotopic(&btm, &grazing, &[(2., 6.), (3.9, 3.9), (6., 2.)]));
    assert!(!homotopic(
        &btm,
        &grazing,
        &[(2., 6.), (2., 9.), (9., 9.), (6., 2.)]
    ));
}

#[test]
fn running_along_an_obstacle_edge_is_homotopic_to_passing_below_it() {
    let (_, btm) = square_map();
    let along = [(3., 4.), (7., 4.)];
    assert!(homotopic(&btm, &along, &[(3., 4.), (5., 3.), (7., 4.)]));
    assert!(!homotopic(
        &btm,
        &along,
        &[(3., 4.), (3., 7.), (7., 7.), (7., 4.)]
    ));
}

#[test]
fn turning_at_an_obstacle_vertex_wraps_it_on_the_free_side() {
    let (_, btm) = square_map();
    // Down the west side, turning at both west corners.
    let wrapped = [(5., 9.), (4., 6.), (4., 4.), (5., 1.)];
    assert!(homotopic(&btm, &wrapped, &[(5., 9.), (1., 5.), (5., 1.)]));
    assert!(!homotopic(&btm, &wrapped, &[(5., 9.), (9., 5.), (5., 1.)]));
}

#[test]
fn start_and_end_at_an_obstacle_vertex_are_canonical() {
    let (_, btm) = square_map();
    // Leaving the corner (4, 4) in different directions and meeting again: homotopic.
    let a = [(4., 4.), (1., 1.), (8., 1.)];
    let b = [(4., 4.), (4., 2.), (8., 1.)];
    let c = [(4., 4.), (3., 5.), (2., 2.), (8., 1.)];
    assert!(homotopic(&btm, &a, &b));
    assert!(homotopic(&btm, &a, &c));
    // Around the obstacle the other way: not homotopic.
    let d = [(4., 4.), (3., 8.), (8., 8.), (8., 1.)];
    assert!(!homotopic(&btm, &a, &d));
    // The same at the end.
    let rev = |x: &[(f64, f64)]| x.iter().rev().copied().collect::<Vec<_>>();
    assert!(homotopic(&btm, &rev(&a), &rev(&c)));
    assert!(!homotopic(&btm, &rev(&a), &rev(&d)));
}

#[test]
fn endpoints_on_a_diagonal_are_canonical() {
    let (_, btm) = square_map();
    let d = btm.dcel();
    // A diagonal whose midpoint is exactly on it (integer coordinates with even sums).
    let (h, m) = btm
        .triangles()
        .flat_map(|t| t.half_edges())
        .filter(|&h| d.twin(h).is_some())
        .find_map(|h| {
            let (a, b) = (d.point(d.origin(h)), d.point(d.destination(h)));
            let m = Point2::new((a.x + b.x) / 2.0, (a.y + b.y) / 2.0);
            matches!(btm.locate(&m), Location::Edge(_)).then_some((h, m))
        })
        .expect("a diagonal with an exact midpoint");
    // Points just off the diagonal on both sides, inside the two triangles.
    let side = |t| {
        let [a, b, c] = d.triangle_points(t);
        Point2::new((a.x + b.x + c.x) / 3.0, (a.y + b.y + c.y) / 3.0)
    };
    let (l, r) = (
        side(h.triangle()),
        side(d.twin(h).expect("diagonal").triangle()),
    );
    let via_l = Path::new(vec![m, l, r]).unwrap();
    let direct = Path::new(vec![m, r]).unwrap();
    assert!(are_homotopic(&btm, &via_l, &direct).unwrap());
    let back_l = Path::new(vec![l, m]).unwrap();
    let back_r = Path::new(vec![l, r, m]).unwrap();
    assert!(are_homotopic(&btm, &back_l, &back_r).unwrap());
    // A loop from the midpoint into both triangles is contractible.
    let lp = Path::new(vec![m, l, m, r, m]).unwrap();
    assert!(is_contractible(&btm, &lp).unwrap());
}

#[test]
fn loops_around_an_obstacle_are_not_contractible_even_through_vertices() {
    let (_, btm) = square_map();
    let around = path(&[(4., 4.), (6., 4.), (6., 6.), (4., 6.), (4., 4.)]);
    assert!(!is_contractible(&btm, &around).unwrap());
    let beside = path(&[(6., 4.), (9., 4.), (9., 6.), (6., 6.), (6., 4.)]);
    assert!(is_contractible(&btm, &beside).unwrap());
    // Twice around reduces to twice the once-around word.
    let once = CrossingSequence::reduced_of_path(
        &btm,
        &path(&[(2., 2.), (8., 2.), (8., 8.), (2., 8.), (2., 2.)]),
    )
    .unwrap();
    let twice = CrossingSequence::reduced_of_path(
        &btm,
        &path(&[
            (2., 2.),
            (8., 2.),
            (8., 8.),
            (2., 8.),
            (2., 2.),
            (8., 2.),
            (8., 8.),
            (2., 8.),
            (2., 2.),
        ]),
    )
    .unwrap();
    assert!(!once.is_empty());
    assert_eq!(
        twice.crossings(),
        [once.crossings(), once.crossings()].concat()
    );
}

#[test]
fn reduction_cancels_back_and_forth() {
    let (_, btm) = square_map();
    let there_and_back = path(&[(1., 1.), (9., 1.), (9., 3.), (1., 1.)]);
    let raw = CrossingSequence::of_path(&btm, &there_and_back).unwrap();
    assert!(!raw.is_empty());
    assert!(!raw.is_reduced(&btm));
    let reduced = raw.reduced(&btm);
    assert!(reduced.is_empty() && reduced.is_reduced(&btm));
    // Reversal maps the raw sequence to twins in reverse order.
    let rev = CrossingSequence::of_path(&btm, &there_and_back.reversed()).unwrap();
    assert_eq!(rev.reduced(&btm), raw.reversed(&btm).reduced(&btm));
}

#[test]
fn bad_paths_are_typed_errors_naming_the_place() {
    let (_, btm) = square_map();
    assert_eq!(Path::new(vec![]), Err(PathError::Empty));
    assert!(matches!(
        Path::new(vec![p(1., 1.), p(f64::NAN, 2.)]),
        Err(PathError::NonFinite { index: 1, .. })
    ));
    // Segment 1 goes through the obstacle.
    let e = path(&[(1., 1.), (1., 5.), (9., 5.)])
        .validate(&btm)
        .unwrap_err();
    assert!(matches!(
        e,
        PathError::LeavesFreeSpace {
            segment: 1,
            blocker: Blocker::Obstacle(ObstacleId(0)),
            ..
        }
    ));
    assert!(e.to_string().contains("segment 1"));
    // Turning into the obstacle at its corner.
    let e = path(&[(2., 2.), (4., 4.), (5., 5.)])
        .validate(&btm)
        .unwrap_err();
    assert!(matches!(
        e,
        PathError::LeavesFreeSpace {
            segment: 1,
            near,
            ..
        } if near == p(4., 4.)
    ));
    // Leaving the map.
    assert!(matches!(
        path(&[(1., 1.), (-1., 1.)]).validate(&btm),
        Err(PathError::LeavesFreeSpace {
            segment: 0,
            blocker: Blocker::Boundary,
            ..
        })
    ));
    // Starting inside the obstacle or outside the map.
    assert!(matches!(
        path(&[(5., 5.), (1., 1.)]).validate(&btm),
        Err(PathError::PointNotFree {
            index: 0,
            blocker: Blocker::Obstacle(_),
            ..
        })
    ));
    assert!(matches!(
        path(&[(11., 5.)]).validate(&btm),
        Err(PathError::PointNotFree {
            blocker: Blocker::Boundary,
            ..
        })
    ));
    // Homotopy needs shared endpoints and loops must be closed.
    assert!(matches!(
        are_homotopic(
            &btm,
            &path(&[(1., 1.), (2., 2.)]),
            &path(&[(1., 1.), (2., 3.)])
        ),
        Err(HomotopyError::EndpointsDiffer { .. })
    ));
    assert!(matches!(
        is_contractible(&btm, &path(&[(1., 1.), (2., 2.)])),
        Err(HomotopyError::NotClosed { .. })
    ));
    // The second path is the bad one.
    assert!(matches!(
        are_homotopic(
            &btm,
            &path(&[(1., 5.), (1., 1.), (9., 5.)]),
            &path(&[(1., 5.), (9., 5.)])
        ),
        Err(HomotopyError::NthPath { path: 2, .. })
    ));
}

#[test]
fn a_refused_step_leaves_the_tracer_unchanged() {
    let (_, btm) = square_map();
    let mut t = Tracer::new(&btm, p(1., 5.)).unwrap();
    t.push(p(1., 1.)).unwrap();
    let (tri, crossings) = (t.triangle(), t.crossings().to_vec());
    assert!(t.push(p(9., 9.)).is_err());
    assert_eq!((t.triangle(), t.crossings()), (tri, crossings.as_slice()));
    assert_eq!(t.point(), p(1., 1.));
    assert_eq!(t.segment_count(), 1);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// The tracer's free-space verdict on random segments agrees with an independent brute-force
    /// test against every map edge, and the crossing sequence is a chain of adjacent triangles
    /// from the start point's triangle to the end point's.
    #[test]
    fn validation_agrees_with_brute_force(
        seed in 0u64..1000,
        n in 2usize..8,
        segments in prop::collection::vec((0.0..std::f64::consts::TAU, 1.0..30.0f64), 1..20),
    ) {
        let (g, btm) = small_strip(n, seed);
        let d = btm.dcel();
        let mut tracer = Tracer::new(&btm, g.start).unwrap();
        for (angle, len) in segments {
            let a = tracer.point();
            let b = Point2::new(a.x + len * angle.cos(), a.y + len * angle.sin());
            let before = tracer.crossings().len();
            let ok = tracer.push(b).is_ok();
            prop_assert_eq!(ok, segment_clear(&g.map, &a, &b), "segment {:?} -> {:?}", a, b);
            if ok {
                // Every crossing leaves the triangle the previous one entered.
                let mut t = if before == 0 { None } else { d.twin(tracer.crossings()[before - 1]) };
                for &h in &tracer.crossings()[before..] {
                    if let Some(g) = t {
                        prop_assert_eq!(h.triangle(), g.triangle());
                    }
                    t = d.twin(h);
                    prop_assert!(t.is_some());
                }
                let here = btm.locate(&b);
                prop_assert_eq!(here, Location::Triangle(tracer.triangle()));
            }
        }
    }

    /// A loop's prefix traced once answers every closing as the whole loop's contractibility
    /// test does: loops made of two random walks from the strip's start (one out, the other
    /// back; walks snap to obstacle vertices, so the degenerate cases occur), split at every
    /// point, plus a closing straight back to the start (often through an obstacle: the same
    /// error on both sides).
    #[test]
    fn a_traced_loop_prefix_closes_as_the_whole_loop(
        seed in 0u64..1000,
        n in 2usize..8,
        out in steps(10),
        back in steps(10),
    ) {
        let (g, btm) = small_strip(n, seed);
        let mut points = random_walk(&g.map, g.start, &out);
        let mut home = random_walk(&g.map, g.start, &back);
        let last = *points.last().expect("non-empty");
        let mut skip = 0;
        if !segment_clear(&g.map, &last, home.last().expect("non-empty")) {
            // The walks' ends do not see each other: back the way it came (contractible).
            home = points.clone();
            skip = 1;
        }
        home.reverse();
        points.extend(home.into_iter().skip(skip));
        if points.len() < 2 {
            points.push(g.start);
        }
        for split in 1..points.len() {
            let mut prefix = LoopPrefix::new(&btm, &points[..split]).expect("walks stay free");
            let whole = Path::new(points.clone()).expect("finite");
            let expected = is_contractible(&btm, &whole).expect("walks stay free");
            prop_assert_eq!(prefix.closes_contractibly(&points[split..]), Ok(expected));
            // Straight back from the split point.
            let mut short = points[..split].to_vec();
            short.push(g.start);
            let short_whole = Path::new(short).expect("finite");
            prop_assert_eq!(
                prefix.closes_contractibly(&[g.start]).ok(),
                is_contractible(&btm, &short_whole).ok()
            );
        }
    }
}
