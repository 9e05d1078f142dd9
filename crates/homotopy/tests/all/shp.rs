//! Shortest homotopic paths: closed-form lengths around one convex obstacle, and the properties
//! of issue 3 on random maps and random free-space walks (shorter than the path, homotopic to it,
//! locally shortest, idempotent, reversible, equal H-signatures), plus the funnel-state
//! primitive reproducing the Funnel Algorithm.

use crate::common;

use common::{LENGTH_SLACK, p, random_walk, small_strip, square_map, steps};
use nalgebra::Point2;
use proptest::prelude::*;
use rappel_geometry::btm::Btm;
use rappel_geometry::map::Map;
use rappel_geometry::polygon::{Polygon, convex_hull};
use rappel_geometry::predicates::orient2d;
use rappel_homotopy::crossing::CrossingSequence;
use rappel_homotopy::funnel::{Side, TautPath};
use rappel_homotopy::funnel_state::{FunnelState, FunnelTree};
use rappel_homotopy::h_signature::{HSignature, Poles};
use rappel_homotopy::kite::KiteTable;
use rappel_homotopy::path::Path;
use rappel_homotopy::shp::{ShortestHomotopicPath, shortest_homotopic_path};
use rappel_homotopy::sleeve::{Sleeve, SleeveError};
use rappel_homotopy::{shortest_path_in_sleeve, sleeve};

fn shp(btm: &Btm, points: Vec<Point2<f64>>) -> ShortestHomotopicPath {
    shortest_homotopic_path(btm, &Path::new(points).unwrap()).unwrap()
}

/// The two ways from `s` to `g` around a convex obstacle, measured independently along the
/// boundary of the convex hull of `{s, g}` and the obstacle (counter-clockwise chain first).
fn hull_chains(s: Point2<f64>, g: Point2<f64>, obstacle: &[Point2<f64>]) -> (f64, f64) {
    let mut pts = obstacle.to_vec();
    pts.extend([s, g]);
    let hull = convex_hull(&pts).to_counter_clockwise().vertices;
    let n = hull.len();
    let i = hull.iter().position(|q| *q == s).unwrap();
    let mut ccw = 0.0;
    let mut k = i;
    while hull[k] != g {
        ccw += (hull[(k + 1) % n] - hull[k]).norm();
        k = (k + 1) % n;
    }
    let perimeter: f64 = (0..n).map(|k| (hull[(k + 1) % n] - hull[k]).norm()).sum();
    (ccw, perimeter - ccw)
}

fn hexagon_map() -> (Map, Btm, Vec<Point2<f64>>) {
    let hex: Vec<Point2<f64>> = (0..6)
        .map(|k| {
            let t = std::f64::consts::PI / 3.0 * k as f64 + 0.3;
            p(20.0 + 4.0 * t.cos(), 20.0 + 4.0 * t.sin())
        })
        .collect();
    let map = Map::new(
        Polygon::new(vec![p(0., 0.), p(40., 0.), p(40., 40.), p(0., 40.)]),
        vec![Polygon::new(hex.clone())],
    );
    let btm = Btm::from_map(&map).unwrap();
    (map, btm, hex)
}

#[test]
fn both_ways_around_a_convex_obstacle_have_closed_form_lengths() {
    let (_, btm, hex) = hexagon_map();
    let (s, g) = (p(21., 35.), p(18.5, 5.));
    let (ccw, cw) = hull_chains(s, g, &hex);
    // West of the obstacle going down is clockwise around the hull? No: s -> west -> g is
    // counter-clockwise (the hull interior stays on the left).
    let west = shp(&btm, vec![s, p(5., 20.), g]);
    let east = shp(&btm, vec![s, p(35., 20.), g]);
    assert!((west.taut.length - ccw).abs() < LENGTH_SLACK * ccw);
    assert!((east.taut.length - cw).abs() < LENGTH_SLACK * cw);
    assert!(west.taut.anchors.iter().all(|a| a.side == Side::Left));
    assert!(east.taut.anchors.iter().all(|a| a.side == Side::Right));
    // The turning angles add up to the change of direction.
    let dir = |a: Point2<f64>, b: Point2<f64>| (b.y - a.y).atan2(b.x - a.x);
    let pts = &west.taut.points;
    let total = dir(pts[pts.len() - 2], pts[pts.len() - 1]) - dir(pts[0], pts[1]);
    assert!((west.taut.total_turning() - total).abs() < 1e-12);
    // Winding once more around the obstacle adds exactly its perimeter.
    let perimeter: f64 = (0..6).map(|k| (hex[(k + 1) % 6] - hex[k]).norm()).sum();
    let wound = shp(
        &btm,
        vec![
            s,
            p(5., 20.),
            p(20., 5.),
            p(35., 20.),
            p(20., 35.),
            p(5., 20.),
            g,
        ],
    );
    assert!((wound.taut.length - (ccw + perimeter)).abs() < LENGTH_SLACK * ccw);
    assert_eq!(wound.taut.anchors.len(), west.taut.anchors.len() + 6);
}

#[test]
fn straight_when_nothing_is_in_the_way() {
    let (_, btm) = square_map();
    let s = shp(&btm, vec![p(1., 9.), p(3., 2.), p(1.5, 8.), p(2., 1.)]);
    assert_eq!(s.taut.points, vec![p(1., 9.), p(2., 1.)]);
    assert!(s.taut.anchors.is_empty());
    // A trivial path.
    let t = shp(&btm, vec![p(1., 1.)]);
    assert_eq!(t.taut.points, vec![p(1., 1.)]);
    assert_eq!(t.taut.length, 0.0);
}

#[test]
fn sleeve_queries_check_their_endpoints() {
    let (_, btm) = square_map();
    let s = shp(&btm, vec![p(5., 9.), p(1., 5.), p(5., 1.)]);
    assert!(matches!(
        shortest_path_in_sleeve(&btm, &s.sleeve, p(5., 1.), p(5., 9.)),
        Err(SleeveError::PointNotInTriangle { which: "start", .. })
    ));
    assert!(matches!(
        shortest_path_in_sleeve(&btm, &s.sleeve, p(5., 9.), p(f64::INFINITY, 1.)),
        Err(SleeveError::NonFinite { which: "goal", .. })
    ));
    // Any two points of the end triangles: the path stays in the class.
    let rev = s.sleeve.reversed(&btm);
    let back = shortest_path_in_sleeve(&btm, &rev, p(5., 1.), p(5., 9.)).unwrap();
    let mut pts = back.points.clone();
    pts.reverse();
    assert_eq!(pts, s.taut.points);
    // A portal list that is not a chain.
    let portals = s.sleeve.portals();
    if portals.len() >= 2 {
        assert!(matches!(
            Sleeve::from_portals(&btm, s.sleeve.start_triangle(), portals[1..].to_vec()),
            Err(sleeve::SleeveError::NotAChain { index: 0, .. })
        ));
    }
}

/// The SHP by advancing a funnel state portal by portal (Alg. 2's primitive).
fn funnel_state_path(btm: &Btm, sleeve: &Sleeve, s: Point2<f64>, g: Point2<f64>) -> TautPath {
    let mut tree = FunnelTree::new(s);
    let portals = sleeve.portals();
    let node = match portals.first() {
        None => {
            let root = tree.root();
            tree.extend(root, g, None)
        }
        Some(&first) => {
            let mut f = FunnelState::through(&mut tree, btm, first).unwrap();
            for &h in &portals[1..] {
                f = f.advance(&mut tree, btm, h).unwrap();
            }
            f.reach(&mut tree, g)
        }
    };
    tree.taut_path(btm, node)
}

/// Every interior vertex is an obstacle vertex the tether turns around, with the obstacle's
/// corner inside the turn (checked against the obstacle polygon with exact predicates).
fn assert_locally_shortest(btm: &Btm, taut: &TautPath) -> Result<(), TestCaseError> {
    let pts = &taut.points;
    prop_assert_eq!(taut.anchors.len(), pts.len().saturating_sub(2));
    for (i, anchor) in taut.anchors.iter().enumerate() {
        let (a, v, c) = (pts[i], pts[i + 1], pts[i + 2]);
        prop_assert_eq!(anchor.point, v);
        let o = anchor
            .obstacle
            .ok_or_else(|| TestCaseError::fail("anchor on the boundary"))?;
        let ring = btm.obstacle_vertices(o).unwrap();
        let k = ring.iter().position(|&w| w == anchor.vertex).unwrap();
        let n = ring.len();
        let d = btm.dcel();
        let turn = orient2d(&a, &v, &c);
        prop_assert!(turn != 0.0);
        prop_assert_eq!(
            anchor.side,
            if turn > 0.0 { Side::Left } else { Side::Right }
        );
        prop_assert!(anchor.turning_angle > 0.0 && anchor.turning_angle < std::f64::consts::PI);
        for w in [ring[(k + 1) % n], ring[(k + n - 1) % n]] {
            let w = d.point(w);
            let (oc, oa) = (orient2d(&v, &c, &w), orient2d(&v, &a, &w));
            match anchor.side {
                Side::Left => prop_assert!(oc >= 0.0 && oa <= 0.0),
                Side::Right => prop_assert!(oc <= 0.0 && oa >= 0.0),
            }
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// The properties of issue 3, item 8, on random crater strips and random walks that pass
    /// through obstacle vertices and along obstacle edges.
    #[test]
    fn shp_properties(seed in 0u64..10_000, n in 1usize..9, walk in steps(40)) {
        let (g, btm) = small_strip(n, seed);
        let points = random_walk(&g.map, g.start, &walk);
        let path = Path::new(points).unwrap();
        let s = shortest_homotopic_path(&btm, &path).unwrap();
        let taut = &s.taut;
        prop_assert_eq!(taut.start(), path.start());
        prop_assert_eq!(taut.goal(), path.end());

        // No longer than the path.
        prop_assert!(taut.length <= path.length() * (1.0 + LENGTH_SLACK));

        // Homotopic to it: equal reduced crossing sequences.
        let chi_path = CrossingSequence::reduced_of_path(&btm, &path).unwrap();
        let taut_path = taut.to_path();
        let chi_taut = CrossingSequence::reduced_of_path(&btm, &taut_path).unwrap();
        prop_assert_eq!(&chi_path, &chi_taut);
        prop_assert_eq!(&chi_path, &s.crossings);

        // Locally shortest.
        assert_locally_shortest(&btm, taut)?;

        // Equal reduced sequences, equal H-signatures.
        let poles = Poles::new(&btm);
        prop_assert_eq!(HSignature::of_path(&poles, &path), HSignature::of_path(&poles, &taut_path));

        // The SHP of the SHP is itself.
        let again = shortest_homotopic_path(&btm, &taut_path).unwrap();
        prop_assert_eq!(&again.taut.points, &taut.points);

        // Reversing the path reverses the SHP.
        let back = shortest_homotopic_path(&btm, &path.reversed()).unwrap();
        let mut reversed = taut.points.clone();
        reversed.reverse();
        prop_assert_eq!(&back.taut.points, &reversed);
        prop_assert!((back.taut.length - taut.length).abs() <= LENGTH_SLACK * taut.length);

        // Funnel states advanced along the sleeve reproduce the Funnel Algorithm.
        let via_states = funnel_state_path(&btm, &s.sleeve, path.start(), path.end());
        prop_assert_eq!(&via_states.points, &taut.points);
        prop_assert_eq!(&via_states.anchors, &taut.anchors);
    }

    /// Splitting funnels down random branches of the universal cover: the jump-pointer
    /// predecessor search agrees with a linear scan of the chains, and every funnel's apex is an
    /// ancestor of both tips.
    #[test]
    fn funnel_splits_agree_with_linear_scan(
        seed in 0u64..10_000,
        n in 1usize..9,
        choices in prop::collection::vec(any::<bool>(), 1..200),
    ) {
        let (g, btm) = small_strip(n, seed);
        let rappel_geometry::btm::Location::Triangle(t) = btm.locate(&g.start) else {
            return Err(TestCaseError::reject("start on the skeleton"));
        };
        let mut tree = FunnelTree::new(g.start);
        let mut f = FunnelState::initial(&mut tree, &btm, t).unwrap()[0];
        let kites = KiteTable::new(&btm);
        for go_left in choices {
            let d = btm.dcel();
            // The tips lie on the mouth's ends (the search's key reads them from the tree).
            prop_assert_eq!(tree.point(f.right()), d.point(d.origin(f.mouth())));
            prop_assert_eq!(tree.point(f.left()), d.point(d.destination(f.mouth())));
            let v = d.origin(d.twin(f.mouth()).unwrap().prev());
            let expected = linear_predecessor(&tree, &f, &d.point(v));
            // The split read from the kite table is the split read from the DCEL.
            let mut copy = tree.clone();
            let across = f.split_across(&mut copy, &kites.get(f.mouth())).unwrap();
            let split = f.split(&mut tree, &btm).unwrap();
            prop_assert_eq!(across, split);
            prop_assert_eq!(copy.node(across.node), tree.node(split.node));
            prop_assert_eq!(split.predecessor, expected);
            prop_assert_eq!(split.vertex, v);
            let node = tree.node(split.node);
            let pred = tree.node(split.predecessor);
            prop_assert!((node.length - pred.length - (node.point - pred.point).norm()).abs() < 1e-9);
            let next = match (split.left, split.right, go_left) {
                (Some(l), _, true) | (Some(l), None, false) => l,
                (_, Some(r), _) => r,
                (None, None, _) => break,
            };
            for tip in [next.left(), next.right()] {
                prop_assert!(tree.path(tip).contains(&next.apex()));
            }
            f = next;
        }
    }
}

/// The predecessor by scanning each chain from its tip, one node at a time.
fn linear_predecessor(
    tree: &FunnelTree,
    f: &FunnelState,
    v: &Point2<f64>,
) -> rappel_homotopy::funnel_state::NodeId {
    for (tip, sign) in [(f.left(), 1.0), (f.right(), -1.0)] {
        let mut x = tip;
        while x != f.apex() {
            let n = tree.node(x);
            let parent = n.parent().unwrap();
            if sign * orient2d(&tree.node(parent).point, &n.point, v) > 0.0 {
                return x;
            }
            x = parent;
        }
    }
    f.apex()
}

#[test]
fn a_reflex_corner_of_the_map_boundary_is_an_anchor_without_obstacle() {
    // An L-shaped map: the way from the east arm to the north arm wraps the reflex corner (4, 4).
    let map = Map::new(
        Polygon::new(vec![
            p(0., 0.),
            p(10., 0.),
            p(10., 4.),
            p(4., 4.),
            p(4., 10.),
            p(0., 10.),
        ]),
        vec![],
    );
    let btm = Btm::from_map(&map).unwrap();
    let s = shp(&btm, vec![p(8., 2.), p(2., 2.), p(2., 8.)]);
    assert_eq!(s.taut.points, vec![p(8., 2.), p(4., 4.), p(2., 8.)]);
    let a = s.taut.anchors[0];
    assert_eq!((a.obstacle, a.side), (None, Side::Right));
    let expected = (p(4., 4.) - p(8., 2.)).norm() + (p(2., 8.) - p(4., 4.)).norm();
    assert!((s.taut.length - expected).abs() < LENGTH_SLACK * expected);
}

#[test]
fn a_path_into_a_pocket_of_a_non_convex_obstacle_pulls_out_of_it() {
    // A U-shaped obstacle opening upwards; the path dips into the pocket and out again.
    let u = Polygon::new(vec![
        p(3., 3.),
        p(7., 3.),
        p(7., 7.),
        p(6., 7.),
        p(6., 4.),
        p(4., 4.),
        p(4., 7.),
        p(3., 7.),
    ]);
    let map = Map::new(
        Polygon::new(vec![p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)]),
        vec![u],
    );
    let btm = Btm::from_map(&map).unwrap();
    let s = shp(
        &btm,
        vec![p(2., 9.), p(5., 8.), p(5., 5.), p(5.5, 8.), p(8., 9.)],
    );
    assert_eq!(s.taut.points, vec![p(2., 9.), p(8., 9.)]);
    // Into the pocket and down around the outside: wraps the two lower corners.
    let around = shp(
        &btm,
        vec![
            p(5., 5.),
            p(5., 8.),
            p(8., 8.),
            p(8., 2.),
            p(2., 2.),
            p(2., 5.),
        ],
    );
    assert_eq!(around.taut.anchors.len(), 4);
    assert!(around.taut.anchors.iter().all(|a| a.side == Side::Right));
}
