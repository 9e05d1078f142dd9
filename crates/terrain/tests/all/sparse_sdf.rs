//! The sparse distance field against independent exact distances: the parry BVH's on Paton's
//! ledge scenes, closed forms on a closed box and a tilted plane. Truncated fields (`D = T`):
//! each test fails if the proven bound `|f - clamp(d, -T, T)| <= (sqrt 3 / 2) h + T 2^-24` is
//! violated anywhere it samples, or if a sign beyond the bound is wrong. Propagated fields
//! (`D > T`): grid values must never lie below the exact distance (they are distances to real
//! surface points) and at most the empirical `PROPAGATION_EXCESS_VOXELS * h` above it, in the
//! band and far out; interpolated queries within `error_bound`. Typed errors for bad parameters
//! and caps.

use nalgebra::{Point3, Vector3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rappel_terrain::mesh::TriMesh;
use rappel_terrain::parry_mesh::ParryMesh;
use rappel_terrain::paton_scene::PatonScene;
use rappel_terrain::sdf::SdfError;
use rappel_terrain::sparse_sdf::{DEFAULT_MAX_FAR_PAIRS, SparseSdf, SparseSdfParams};
use rappel_terrain::surface::SignedDistance;

/// Samples `n` points from `sample`, checks the bound against `exact`; returns how many lay
/// within `T` of the surface and how many beyond.
fn check_bound(
    f: &SparseSdf,
    n: usize,
    mut sample: impl FnMut() -> Point3<f64>,
    exact: impl Fn(&Point3<f64>) -> f64,
) -> (usize, usize) {
    let t = f.max_distance();
    let bound = f.error_bound();
    let (mut near, mut far) = (0, 0);
    for _ in 0..n {
        let q = sample();
        let d = exact(&q);
        let got = f.distance(&q).expect("inside the box");
        assert!(
            (got - d.clamp(-t, t)).abs() <= bound + 1e-9,
            "at {q}: field {got}, exact {d} (T {t}, bound {bound})"
        );
        if d.abs() > bound {
            assert_eq!(got.signum(), d.signum(), "sign at {q}: {got} vs {d}");
        }
        if d.abs() < t { near += 1 } else { far += 1 }
    }
    (near, far)
}

/// One of Paton's ledge scenes (`pole`: test 3's) with parry's exact distances and the field of
/// `params`; also the ledge's top height and the lowest height sampled (with the pole, above the
/// ledge's top only: the pole's open bottom end is sunk into the ledge, where the exact sign is a
/// convention).
fn ledge_case(pole: bool, params: &SparseSdfParams) -> (ParryMesh, SparseSdf, f64, f64) {
    let scene = PatonScene::paper(pole);
    let m = scene.mesh().expect("the paper's scene meshes");
    let exact = ParryMesh::new(&m).expect("parry takes it");
    let f = SparseSdf::from_mesh(&m, params).expect("fits");
    let top = scene.height;
    let zmin = if pole { top + 0.05 } else { f.bounds().0.z };
    (exact, f, top, zmin)
}

/// A point near the ledge (x in -6 .. 4, y in -6 .. 6 m) at a height in `zmin .. zmax`.
fn near_ledge(rng: &mut ChaCha8Rng, zmin: f64, zmax: f64) -> Point3<f64> {
    Point3::new(
        rng.random_range(-6.0..4.0),
        rng.random_range(-6.0..6.0),
        rng.random_range(zmin..zmax),
    )
}

#[test]
fn ledge_scenes_within_the_bound_of_the_bvh_distance() {
    for pole in [false, true] {
        let (exact, f, top, zmin) = ledge_case(pole, &SparseSdfParams::truncated(0.1));
        let (lo, hi) = f.bounds();
        let mut rng = ChaCha8Rng::seed_from_u64(14);
        // Uniform over the box's interior (7 m inside the open ground's edge), and near the
        // ledge.
        let (near, far) = check_bound(
            &f,
            1500,
            || {
                if rng.random_bool(0.5) {
                    Point3::new(
                        rng.random_range(lo.x + 7.0..hi.x - 7.0),
                        rng.random_range(lo.y + 7.0..hi.y - 7.0),
                        rng.random_range(zmin..hi.z),
                    )
                } else {
                    near_ledge(&mut rng, zmin, (top + 1.0).min(hi.z))
                }
            },
            |q| exact.signed_distance(q).expect("finite"),
        );
        assert!(
            near > 50 && far > 300,
            "pole {pole}: {near} near, {far} far"
        );
    }
}

/// A closed box of half-sizes `e` about `c`, outward triangles.
fn closed_box(c: Point3<f64>, e: Vector3<f64>) -> TriMesh {
    let v: Vec<Point3<f64>> = (0..8)
        .map(|i| {
            let s = |b: usize| if i >> b & 1 == 1 { 1.0 } else { -1.0 };
            c + Vector3::new(s(0) * e.x, s(1) * e.y, s(2) * e.z)
        })
        .collect();
    let quads = [
        [0, 2, 3, 1], // z-
        [4, 5, 7, 6], // z+
        [0, 1, 5, 4], // y-
        [2, 6, 7, 3], // y+
        [0, 4, 6, 2], // x-
        [1, 3, 7, 5], // x+
    ];
    let t = quads
        .iter()
        .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
        .collect();
    TriMesh::new(v, t).expect("a closed box")
}

#[test]
fn closed_box_against_its_closed_form() {
    let (c, e) = (Point3::new(0.13, -0.21, 0.37), Vector3::new(1.0, 0.7, 0.5));
    let m = closed_box(c, e);
    // Check the mesh's orientation with the exact distance at the centre: inside is negative.
    assert!(m.signed_distance(&c) < -0.4);
    let mut p = SparseSdfParams::truncated(0.05);
    p.truncation = 0.2;
    p.max_distance = 0.2;
    p.margin = 0.6;
    let f = SparseSdf::from_mesh(&m, &p).expect("fits");
    let closed_form = |q: &Point3<f64>| {
        let a = (q - c).abs() - e;
        let out = a.sup(&Vector3::zeros()).norm();
        let inside = a.x.max(a.y).max(a.z).min(0.0);
        out + inside
    };
    let (lo, hi) = f.bounds();
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let (near, far) = check_bound(
        &f,
        3000,
        || {
            Point3::new(
                rng.random_range(lo.x..hi.x),
                rng.random_range(lo.y..hi.y),
                rng.random_range(lo.z..hi.z),
            )
        },
        closed_form,
    );
    assert!(near > 300 && far > 1000, "{near} near, {far} far");
    // Deep inside (0.3 m from every face, beyond T): the flood carried the inside sign.
    assert_eq!(f.distance(&c), Some(-f.truncation()));
    assert!(f.distance(&Point3::new(50.0, 0.0, 0.0)).is_none());
}

#[test]
fn tilted_plane_distance_and_gradient() {
    // z = 0.3 x - 0.2 y + 1 over [-10, 10]^2 (two triangles; z from -4 to 6).
    let z = |x: f64, y: f64| 0.3 * x - 0.2 * y + 1.0;
    let v = [(-10.0, -10.0), (10.0, -10.0), (10.0, 10.0), (-10.0, 10.0)]
        .map(|(x, y)| Point3::new(x, y, z(x, y)))
        .to_vec();
    let m = TriMesh::new(v, vec![[0, 1, 2], [0, 2, 3]]).expect("a plane");
    let n = Vector3::new(-0.3, 0.2, 1.0).normalize();
    let closed_form = |q: &Point3<f64>| (q - Point3::new(0.0, 0.0, 1.0)).dot(&n);
    let f = SparseSdf::from_mesh(&m, &SparseSdfParams::truncated(0.1)).expect("fits");
    let mut rng = ChaCha8Rng::seed_from_u64(99);
    let (near, far) = check_bound(
        &f,
        2000,
        || {
            let (x, y) = (rng.random_range(-8.0..8.0), rng.random_range(-8.0..8.0));
            Point3::new(x, y, z(x, y) + rng.random_range(-1.0..1.0))
        },
        closed_form,
    );
    assert!(near > 200 && far > 800, "{near} near, {far} far");
    // Within T - 2 h every corner is exact and the distance linear: the interpolant is exact
    // and its gradient the normal (to f32 rounding over h).
    for k in 0..50 {
        let (x, y) = (-5.0 + 0.21 * k as f64, 4.0 - 0.17 * k as f64);
        let q = Point3::new(x, y, z(x, y)) + n * (0.004 * k as f64 - 0.1);
        let (d, g) = f.distance_and_gradient(&q).expect("inside");
        assert!((d - closed_form(&q)).abs() < 1e-6, "{d} at {q}");
        assert!((g - n).norm() < 1e-5, "{g} vs {n}");
    }
    // Far above: T and no gradient.
    let (d, g) = f
        .distance_and_gradient(&Point3::new(0.0, 0.0, 2.5))
        .expect("inside");
    assert_eq!(d, f.truncation());
    assert_eq!(g, Vector3::zeros());
}

#[test]
fn bad_parameters_and_caps_are_typed_errors() {
    let m = PatonScene::paper(false).mesh().expect("meshes");
    for h in [0.0, -0.1, f64::NAN, f64::INFINITY] {
        let mut p = SparseSdfParams::new(0.1);
        p.resolution = h;
        assert!(
            matches!(
                SparseSdf::from_mesh(&m, &p),
                Err(SdfError::BadParameter {
                    name: "resolution",
                    ..
                })
            ),
            "resolution {h}"
        );
    }
    let mut p = SparseSdfParams::new(0.1);
    p.truncation = 0.15;
    assert!(matches!(
        SparseSdf::from_mesh(&m, &p),
        Err(SdfError::BadParameter {
            name: "truncation",
            ..
        })
    ));
    let mut p = SparseSdfParams::new(0.1);
    p.margin = f64::NAN;
    assert!(matches!(
        SparseSdf::from_mesh(&m, &p),
        Err(SdfError::BadParameter { name: "margin", .. })
    ));
    let mut p = SparseSdfParams::new(0.1);
    p.max_blocks = 0;
    assert!(matches!(
        SparseSdf::from_mesh(&m, &p),
        Err(SdfError::BadParameter {
            name: "max_blocks",
            ..
        })
    ));
    // A micrometre grid over a 40 m scene: refused before allocating anything.
    let mut p = SparseSdfParams::new(1e-6);
    p.truncation = 0.4;
    assert!(matches!(
        SparseSdf::from_mesh(&m, &p),
        Err(SdfError::TooManyBlockCells { .. })
    ));
    let mut p = SparseSdfParams::new(0.1);
    p.max_blocks = 100;
    match SparseSdf::from_mesh(&m, &p) {
        Err(SdfError::TooManyBlocks { blocks, cap: 100 }) => assert!(blocks > 100),
        other => panic!("expected TooManyBlocks, got {other:?}"),
    }
    let mut p = SparseSdfParams::new(0.1);
    p.max_distance = 0.3;
    assert!(matches!(
        SparseSdf::from_mesh(&m, &p),
        Err(SdfError::BadParameter {
            name: "max_distance",
            ..
        })
    ));
    // The wavefront's blocks count against the cap: room for the band but not for D = 1 m.
    let band = SparseSdf::from_mesh(&m, &SparseSdfParams::truncated(0.1)).expect("fits");
    let mut p = SparseSdfParams::new(0.1);
    p.max_blocks = band.block_count() * 3 / 2;
    match SparseSdf::from_mesh(&m, &p) {
        Err(SdfError::TooManyBlocks { blocks, cap }) => assert!(blocks > cap),
        other => panic!("expected TooManyBlocks, got {other:?}"),
    }
    // A resolution far coarser than the scene is valid: one block or a few, bound still holds.
    let f = SparseSdf::from_mesh(&m, &SparseSdfParams::new(100.0)).expect("coarse");
    assert!(f.block_count() >= 1);
}

/// Checks grid point `q` of a propagated field against the exact distance `d`: the sign, never
/// below `min(|d|, D)` (up to `f32` rounding), at most `excess_bound` above it. Returns whether
/// `q` lay beyond the exact band (`T < |d| <= D`).
fn check_grid_point(f: &SparseSdf, q: &Point3<f64>, d: f64) -> bool {
    let got = f.distance(q).expect("inside the box");
    let dm = f.max_distance();
    let rounding = 4e-6 * (1.0 + q.coords.norm());
    let excess = got.abs() - d.abs().min(dm);
    assert!(
        excess >= -rounding && excess <= f.excess_bound() + rounding,
        "at {q}: field {got}, exact {d} (D {dm}, excess {excess}, bound {})",
        f.excess_bound()
    );
    if d.abs() > rounding {
        assert_eq!(got.signum(), d.signum(), "sign at {q}: {got} vs {d}");
    }
    d.abs() > f.truncation() && d.abs() <= dm
}

/// [`SparseSdfParams::new`] at `h`, far mode's pair budget `far_pairs` (`0`: the band and the
/// wavefront only, the path a fine mesh takes).
fn propagated(h: f64, far_pairs: usize) -> SparseSdfParams {
    let mut p = SparseSdfParams::new(h);
    p.max_far_pairs = far_pairs;
    p
}

#[test]
fn propagated_field_on_the_ledge_scenes_against_the_bvh() {
    // Both paths: far mode (the default on this 18-triangle mesh; with the pole some blocks
    // still go to the wavefront) and the wavefront alone.
    for (pole, far_pairs) in [
        (false, DEFAULT_MAX_FAR_PAIRS),
        (true, DEFAULT_MAX_FAR_PAIRS),
        (false, 0),
        (true, 0),
    ] {
        let h = 0.1;
        let (exact, f, top, zmin) = ledge_case(pole, &propagated(h, far_pairs));
        assert!(f.max_distance() > f.truncation());
        let (lo, hi) = f.bounds();
        let n = (hi - lo) / h;
        let mut rng = ChaCha8Rng::seed_from_u64(1414);
        // Grid points: uniform over the interior (7 m inside the open ground's edge) and near
        // the ledge; with the pole above the ledge's top only (its open bottom end is sunk).
        let (mut band, mut far) = (0, 0);
        for k in 0..3000 {
            let (x0, x1, y0, y1) = if k % 2 == 0 {
                (lo.x + 7.0, hi.x - 7.0, lo.y + 7.0, hi.y - 7.0)
            } else {
                (-6.0, 4.0, -6.0, 6.0)
            };
            // Grid indices of the sampled ranges (heights up to 1.5 m above the top).
            let idx = |a: f64, b: f64, lo: f64, n: f64| {
                let i0 = ((a - lo) / h).ceil().max(0.0) as i64;
                let i1 = ((b - lo) / h).floor().min(n.round()) as i64;
                (i0, i1)
            };
            let (i0, i1) = idx(x0, x1, lo.x, n.x);
            let (j0, j1) = idx(y0, y1, lo.y, n.y);
            let (k0, k1) = idx(zmin, top + 1.5, lo.z, n.z);
            let q = lo
                + Vector3::new(
                    rng.random_range(i0..=i1) as f64,
                    rng.random_range(j0..=j1) as f64,
                    rng.random_range(k0..=k1) as f64,
                ) * h;
            let d = exact.signed_distance(&q).expect("finite");
            if check_grid_point(&f, &q, d) {
                far += 1;
            } else if d.abs() <= f.truncation() {
                band += 1;
            }
        }
        assert!(
            band > 100 && far > 300,
            "pole {pole}: {band} band, {far} far"
        );
        // Interpolated queries, including the far ones: within the documented bound.
        let (near, beyond) = check_bound(
            &f,
            1500,
            || near_ledge(&mut rng, zmin, (top + 1.5).min(hi.z)),
            |q| exact.signed_distance(q).expect("finite"),
        );
        assert!(
            near > 100 && beyond > 20,
            "pole {pole}: {near} near, {beyond} beyond"
        );
    }
}

#[test]
fn propagated_field_against_closed_forms() {
    for far_pairs in [DEFAULT_MAX_FAR_PAIRS, 0] {
        closed_box_and_tilted_plane(far_pairs);
    }
}

/// [`propagated_field_against_closed_forms`] with far mode's pair budget `far_pairs`.
fn closed_box_and_tilted_plane(far_pairs: usize) {
    // A closed box 2 x 1.4 x 1 m: its centre lies 0.5 m deep, beyond T = 0.2 m; far mode's
    // exact values or the wavefront must carry the exact -0.5 there (the truncated field reads
    // -T).
    let (c, e) = (Point3::new(0.13, -0.21, 0.37), Vector3::new(1.0, 0.7, 0.5));
    let m = closed_box(c, e);
    let h = 0.05;
    let mut p = propagated(h, far_pairs);
    p.truncation = 0.2;
    let f = SparseSdf::from_mesh(&m, &p).expect("fits");
    assert_eq!(f.max_distance(), 1.0);
    let closed_form = |q: &Point3<f64>| {
        let a = (q - c).abs() - e;
        a.sup(&Vector3::zeros()).norm() + a.x.max(a.y).max(a.z).min(0.0)
    };
    let (lo, hi) = f.bounds();
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut far = 0;
    for _ in 0..4000 {
        let g = (hi - lo) / h;
        let q = lo
            + Vector3::new(
                rng.random_range(0..=g.x.round() as i64) as f64,
                rng.random_range(0..=g.y.round() as i64) as f64,
                rng.random_range(0..=g.z.round() as i64) as f64,
            ) * h;
        far += usize::from(check_grid_point(&f, &q, closed_form(&q)));
    }
    assert!(far > 1000, "{far} far");
    let centre = f.distance(&c).expect("inside");
    assert!((centre + 0.5).abs() <= f.error_bound(), "centre {centre}");
    // A tilted plane: 0.3-1.0 m above and below, far beyond T, within the bound.
    let z = |x: f64, y: f64| 0.3 * x - 0.2 * y + 1.0;
    let v = [(-10.0, -10.0), (10.0, -10.0), (10.0, 10.0), (-10.0, 10.0)]
        .map(|(x, y)| Point3::new(x, y, z(x, y)))
        .to_vec();
    let m = TriMesh::new(v, vec![[0, 1, 2], [0, 2, 3]]).expect("a plane");
    let n = Vector3::new(-0.3, 0.2, 1.0).normalize();
    let plane = |q: &Point3<f64>| (q - Point3::new(0.0, 0.0, 1.0)).dot(&n);
    let f = SparseSdf::from_mesh(&m, &propagated(0.1, far_pairs)).expect("fits");
    let (near, far) = check_bound(
        &f,
        2000,
        || {
            let (x, y) = (rng.random_range(-8.0..8.0), rng.random_range(-8.0..8.0));
            let s = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
            Point3::new(x, y, z(x, y)) + n * (s * rng.random_range(0.3..1.0))
        },
        plane,
    );
    assert!(near > 1000 && far < 2000, "{near} near, {far} far");
}

/// The field is the same whatever the thread count: built in a 1-thread and a 3-thread rayon
/// pool, every stored value (and the block layout) is bit-identical (`SparseSdf: PartialEq`
/// compares the index and the `f32` values, which hold no NaN). Fails if the parallel wavefront's
/// rounds, the band or the floods depend on how rayon splits the work.
#[test]
fn same_field_whatever_the_thread_count() {
    let build = |threads: usize, pole: bool, params: &SparseSdfParams| {
        let m = PatonScene::paper(pole).mesh().expect("meshes");
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a pool")
            .install(|| SparseSdf::from_mesh(&m, params).expect("fits"))
    };
    // Far mode (default), and the wavefront alone (pair budget 0).
    for (pole, h, far_pairs) in [
        (false, 0.1, DEFAULT_MAX_FAR_PAIRS),
        (true, 0.1, DEFAULT_MAX_FAR_PAIRS),
        (false, 0.2, DEFAULT_MAX_FAR_PAIRS),
        (false, 0.1, 0),
        (true, 0.1, 0),
    ] {
        let p = propagated(h, far_pairs);
        let one = build(1, pole, &p);
        let three = build(3, pole, &p);
        assert!(one.block_count() > 0);
        assert_eq!(one.block_count(), three.block_count(), "pole {pole}, h {h}");
        assert!(one == three, "pole {pole}, h {h}: stored values differ");
    }
}

/// Far mode on Paton's ledge (18 triangles: every block's complete candidate list is short):
/// every sampled grid point out to `D` holds the exact signed distance (parry's) up to `f32`
/// rounding, far beyond `T` too, where the wavefront's values may lie up to `excess_bound`
/// above it. The wavefront-only field (pair budget 0) is a different field (so the budget
/// switches the path) that never reads below far mode's values and at most `excess_bound`
/// above them. Fails if a complete block misses a point's closest triangle, if the face-region
/// shortcut gives a wrong distance or sign, or if the two paths disagree beyond the bound.
#[test]
fn far_mode_is_exact_on_the_ledge_and_agrees_with_the_wavefront() {
    let h = 0.1;
    let (exact, far, top, zmin) = ledge_case(false, &propagated(h, DEFAULT_MAX_FAR_PAIRS));
    let (_, wave, _, _) = ledge_case(false, &propagated(h, 0));
    assert!(far != wave, "the pair budget must switch the path");
    let (lo, hi) = far.bounds();
    let n = (hi - lo) / h;
    let dm = far.max_distance();
    let mut rng = ChaCha8Rng::seed_from_u64(2611);
    let mut beyond = 0;
    for _ in 0..6000 {
        let q = lo
            + Vector3::new(
                rng.random_range(0..=n.x.round() as i64) as f64,
                rng.random_range(0..=n.y.round() as i64) as f64,
                rng.random_range(0..=((top + 1.5 - lo.z) / h).floor().min(n.z) as i64) as f64,
            ) * h;
        // Inside the open ground's edge (beyond it the sign is a convention).
        if q.x < lo.x + 3.0 || q.x > hi.x - 3.0 || q.y < lo.y + 3.0 || q.y > hi.y - 3.0 {
            continue;
        }
        if q.z < zmin {
            continue;
        }
        let d = exact.signed_distance(&q).expect("finite");
        let rounding = 4e-6 * (1.0 + q.coords.norm());
        let got = far.distance(&q).expect("inside");
        assert!(
            (got - d.clamp(-dm, dm)).abs() <= rounding,
            "far mode at {q}: {got}, exact {d}"
        );
        let w = wave.distance(&q).expect("inside");
        let excess = w.abs() - got.abs();
        assert!(
            excess >= -rounding && excess <= wave.excess_bound() + rounding,
            "wavefront at {q}: {w}, far mode {got}"
        );
        if d.abs() > rounding {
            assert_eq!(w.signum(), got.signum(), "sign at {q}: {w} vs {got}");
        }
        beyond += usize::from(d.abs() > far.truncation() && d.abs() < dm);
    }
    assert!(beyond > 500, "{beyond} grid points between T and D");
}

/// Two closed boxes 300 m apart on each axis at 5 cm: a dense block index over the box would
/// need about 757^3 = 434 M cells, over the old cap of 2^25 (computed below from the grid, so the
/// test fails if the scene stops exceeding it); the two-level index builds it. Fails if the
/// field's grid values near either box (in the band and propagated out to `D`) leave
/// `[|d|, |d| + excess_bound]` against the closed form or take the wrong sign, if the air
/// between the boxes reads other than `+D`, or if interpolated queries
/// near the boxes leave `error_bound`.
#[test]
fn far_apart_boxes_exceed_the_old_dense_cap() {
    let e = Vector3::new(0.5, 0.4, 0.3);
    let centres = [Point3::new(0.0, 0.0, 0.0), Point3::new(300.0, 300.0, 300.0)];
    let (a, b) = (closed_box(centres[0], e), closed_box(centres[1], e));
    let nv = a.vertices().len();
    let mut v = a.vertices().to_vec();
    v.extend_from_slice(b.vertices());
    let mut t = a.triangles().to_vec();
    t.extend(b.triangles().iter().map(|tr| tr.map(|i| i + nv)));
    let m = TriMesh::new(v, t).expect("two closed boxes");
    let h = 0.05;
    let p = SparseSdfParams::new(h);
    let f = SparseSdf::from_mesh(&m, &p).expect("fits in the two-level index");
    let (lo, hi) = f.bounds();
    let dense_cells: f64 = (0..3)
        .map(|k| (((hi[k] - lo[k]) / h).round() + 1.0) / 8.0)
        .map(f64::ceil)
        .product();
    assert!(dense_cells > (1u64 << 25) as f64, "{dense_cells} cells");
    let closed_form = |q: &Point3<f64>| {
        centres
            .iter()
            .map(|c| {
                let a = (q - c).abs() - e;
                a.sup(&Vector3::zeros()).norm() + a.x.max(a.y).max(a.z).min(0.0)
            })
            .fold(f64::INFINITY, f64::min)
    };
    let mut rng = ChaCha8Rng::seed_from_u64(14);
    let mut far = 0;
    for k in 0..4000 {
        let c = centres[k % 2];
        // Grid points within 1.25 m of a box's centre on each axis (the box holds 1.3 m).
        let q = lo + ((c - lo) / h).map(|x| x.round() + rng.random_range(-25..=25) as f64) * h;
        far += usize::from(check_grid_point(&f, &q, closed_form(&q)));
    }
    assert!(far > 800, "{far} far");
    let dm = f.max_distance();
    assert_eq!(f.distance(&Point3::new(150.0, 150.0, 150.0)), Some(dm));
    assert_eq!(f.distance(&Point3::new(10.0, 290.0, 5.0)), Some(dm));
    let (near, _) = check_bound(
        &f,
        2000,
        || {
            let c = centres[usize::from(rng.random_bool(0.5))];
            c + Vector3::new(
                rng.random_range(-1.25..1.25),
                rng.random_range(-1.25..1.25),
                rng.random_range(-1.25..1.25),
            )
        },
        closed_form,
    );
    assert!(near > 200, "{near} near");
}
