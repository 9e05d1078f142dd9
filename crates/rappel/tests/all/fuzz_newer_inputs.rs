//! The fuzz harness of the newer inputs (issue 30), as `fuzz_inputs` fuzzes the scenario reader:
//! Paton scenes, OBJ / ASCII PLY / binary STL meshes, tracking terrains and their paths, query
//! pairs files and the online truth map are fed truncated, byte-flipped, number-spliced
//! (`1e308`, `NaN`, `-0.0`, ...) and inserted-garbage versions of real fixtures. Every outcome
//! must be clean: no panic, a typed error whose message names the file and is one printable line
//! without huge numbers or `-0` (`fuzz_inputs::check_message`), or a valid input that the
//! command's next step (settling, tracking, answering, an online run) handles without a panic.
//! Seeded and bounded (48 cases per property, a few seconds in a debug build); set
//! `PROPTEST_CASES` to run longer.

use crate::fuzz_inputs::{Mutation, apply, check_message, mutation, temp_dir};
use proptest::prelude::*;
use std::path::{Path, PathBuf};

/// A fixture's text.
fn fixture(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures")
        .join(name);
    std::fs::read_to_string(path).expect("fixture")
}

/// `bytes` written to a fresh file `name` in a directory of this property.
fn write(tag: &str, name: &str, bytes: &[u8]) -> PathBuf {
    let file = temp_dir(tag).join(name);
    std::fs::write(&file, bytes).expect("write");
    file
}

/// A refusal must name the file and read as one clean line.
fn refused(file: &Path, e: &dyn std::fmt::Display) -> Result<(), TestCaseError> {
    let text = e.to_string();
    check_message(&text)?;
    prop_assert!(
        text.contains(&file.display().to_string()),
        "the error names the file: {text}"
    );
    Ok(())
}

/// Byte mutations for binary files (no numbers to splice).
fn byte_mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        any::<usize>().prop_map(Mutation::Truncate),
        (any::<usize>(), any::<u8>()).prop_map(|(i, b)| Mutation::Flip(i, b)),
    ]
}

/// A small binary STL of the ledge scene's first triangles.
fn stl_bytes() -> Vec<u8> {
    let mesh = rappel::terrain::paton_scene::PatonScene::paper(false)
        .mesh()
        .expect("scene");
    let mut b = vec![0u8; 80];
    b.extend((mesh.triangles().len() as u32).to_le_bytes());
    for t in mesh.triangles() {
        b.extend([0f32; 3].iter().flat_map(|v| v.to_le_bytes()));
        for &i in t {
            let p = mesh.vertices()[i];
            for c in [p.x, p.y, p.z] {
                b.extend((c as f32).to_le_bytes());
            }
        }
        b.extend([0u8; 2]);
    }
    b
}

/// A mesh file read (or refused) cleanly; a mesh read is settled on without a panic.
fn check_mesh(file: &Path) -> Result<(), TestCaseError> {
    match rappel::terrain::mesh_file::read_mesh(file) {
        Ok(mesh) => {
            let (lo, hi) = mesh.bounds();
            let (x, y) = (0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y));
            if let Err(e) = rappel::settle::settle_report(&mesh, x, y, 0.0, None) {
                check_message(&e.to_string())?;
            }
            Ok(())
        }
        Err(e) => refused(file, &e),
    }
}

/// Text of an OBJ and an ASCII PLY of one square of ground.
const OBJ: &str = "v 0 0 0\nv 10 0 0\nv 10 10 1\nv 0 10 1\nf 1 2 3\nf 1 3 4\n";
const PLY: &str = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n10 0 0\n10 10 1\n0 10 1\n3 0 1 2\n3 0 2 3\n";

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 48,
        rng_seed: proptest::test_runner::RngSeed::Fixed(30),
        ..ProptestConfig::default()
    })]

    #[test]
    fn mutated_paton_scenes_load_and_settle_cleanly(m in mutation()) {
        let file = write("scene", "s.ron", &apply(&fixture("paton/ledge-pole.ron"), &m));
        match rappel::settle::load_scene(&file) {
            Ok(scene) => match scene.mesh() {
                Ok(mesh) => {
                    let s = scene.start();
                    if let Err(e) = rappel::settle::settle_report(&mesh, s.x, s.y, 0.0, None) {
                        check_message(&e.to_string())?;
                    }
                }
                Err(e) => check_message(&e.to_string())?,
            },
            Err(e) => refused(&file, &e)?,
        }
    }

    #[test]
    fn mutated_obj_meshes_read_cleanly(m in mutation()) {
        check_mesh(&write("obj", "m.obj", &apply(OBJ, &m)))?;
    }

    #[test]
    fn mutated_ply_meshes_read_cleanly(m in mutation()) {
        check_mesh(&write("ply", "m.ply", &apply(PLY, &m)))?;
    }

    #[test]
    fn mutated_binary_stl_meshes_read_cleanly(m in byte_mutation()) {
        let mut b = stl_bytes();
        match m {
            Mutation::Truncate(i) => b.truncate(i % (b.len() + 1)),
            Mutation::Flip(i, x) => {
                let i = i % b.len();
                b[i] ^= x | 1;
            }
            _ => unreachable!("byte mutations only"),
        }
        check_mesh(&write("stl", "m.stl", &b))?;
    }

    #[test]
    fn mutated_tracking_terrains_and_paths_run_cleanly(m in mutation(), which in 0..3usize) {
        let terrain = fixture("tracking/kumar.json");
        let robot1 = fixture("tracking/robot1-partial.json");
        let robot2 = fixture("tracking/robot2-descent.json");
        let texts = [&terrain, &robot1, &robot2].map(|t| t.as_bytes().to_vec());
        let mut files = ["t.json", "r1.json", "r2.json"]
            .iter()
            .zip(&texts)
            .map(|(name, bytes)| write("track", name, bytes))
            .collect::<Vec<_>>();
        let source = [&terrain, &robot1, &robot2][which];
        files[which] = write("track", ["t2.json", "r1b.json", "r2b.json"][which], &apply(source, &m));
        let loaded = rappel::track::load_terrain(&files[0]).and_then(|t| {
            Ok((t, rappel::track::load_path(&files[1])?, rappel::track::load_path(&files[2])?))
        });
        match loaded {
            Ok(((scenario, terrain), p1, p2)) => {
                if let Err(e) = rappel::track::track(&scenario, &terrain, &p1, &p2) {
                    check_message(&e.to_string())?;
                }
            }
            Err(e) => refused(&files[which], &e)?,
        }
    }

    #[test]
    fn mutated_pairs_files_are_answered_cleanly(m in mutation()) {
        let file = write("pairs", "p.json", &apply(&fixture("queries/fig-2-7-pairs.json"), &m));
        match rappel::query::load_pairs(&file) {
            Ok(pairs) => {
                let map_path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/thesis-fig-2-7.ron");
                let map = rappel::query::read_map(&map_path).expect("map");
                let valid = map.validate().expect("valid map");
                let answers = rappel::query::answer(valid, &pairs, &rappel::query::QueryOptions::default());
                match answers {
                    Ok(answers) => {
                        for a in &answers {
                            if let Some(e) = &a.error {
                                check_message(e)?;
                            }
                        }
                    }
                    Err(e) => check_message(&e.to_string())?,
                }
            }
            Err(e) => refused(&file, &e)?,
        }
    }

    #[test]
    fn mutated_online_truths_run_cleanly(m in mutation()) {
        let prior_path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/online-example.ron");
        let prior = rappel::scenario::Scenario::load(&prior_path).expect("prior");
        let file = write("online", "truth.ron", &apply(&fixture("online-example-discovered.ron"), &m));
        match rappel::scenario::Scenario::load(&file) {
            Ok(truth) => {
                let options = rappel::planners::online::simulate::SimulationOptions::default();
                if let Err(e) = rappel::online::run(&prior, &truth, &options, &mut |_, _| {}) {
                    check_message(&e.to_string())?;
                }
            }
            Err(e) => refused(&file, &e)?,
        }
    }
}
