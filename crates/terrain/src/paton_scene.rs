//! Paton et al. 2020's simulation scenes (§V, Fig. 8) as procedural triangle meshes: flat
//! ground with a `10 x 5 x 4` m ledge whose one side is a 55° slope, optionally a tall pole in
//! the middle of the ledge (test 3), and the start pose and root anchors of tests 1-3.
//!
//! The paper gives the ledge's three dimensions, the slope angle and the anchors relative to the
//! start; the rest is assumed here (and in `docs/mesh.md`):
//! - the world frame: `x` is the descent direction (the rover faces `+x`), `z` up, the ground at
//!   `z = 0`;
//! - the ledge's top is `length` (10 m, along `y`, the lip) by `width` (5 m, along `x`, from
//!   `x = -width` to the lip at `x = 0`) at `z = height` (4 m); the slope runs from the lip down to
//!   the ground at `x = height / tan(slope)` (2.80 m at 55°), outside that footprint (the anchor
//!   4.9 m behind the start then lies over the ledge, as Fig. 8 shows); the other three sides are
//!   vertical;
//! - the start is `start_back` (1 m) behind the lip on the ledge's centre line, facing `+x`;
//! - "above" for the anchors is above the start's ground point;
//! - the pole is a vertical 32-gon tube of radius `pole.radius` (0.3 m) and height `pole.height`
//!   (10 m) at the ledge top's centre, its open foot sunk `POLE_SINK` into the ledge (a separate
//!   mesh component, so the top face needs no hole);
//! - the ground is a rectangle `ground_margin` (15 m) beyond the ledge on every side.

use nalgebra::{Point3, Vector3};
use serde::{Deserialize, Serialize};

use crate::mesh::{MeshError, TriMesh};
use rappel_geometry::compact::Compact;

/// How far the pole's open foot is sunk below the ledge top, metres (only points deeper than
/// this inside the ledge may get the pole's inside/outside sign wrong; nothing queries there).
pub const POLE_SINK: f64 = 0.5;

/// Sides of the pole's polygon: a 32-gon's sides lie within `r (1 - cos(pi / 32)) = 0.0048 r` of
/// the circle.
pub const POLE_SIDES: usize = 32;

/// The pole of test 3.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Pole {
    /// Radius, metres.
    pub radius: f64,
    /// Height above the ledge top, metres.
    pub height: f64,
}

/// One of Paton's scenes, as read from `fixtures/paton/*.ron`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PatonScene {
    /// The ledge's length along the lip (`y`), metres (paper: 10).
    pub length: f64,
    /// Its depth behind the lip (`x`), metres (paper: 5).
    pub width: f64,
    /// Its height, metres (paper: 4).
    pub height: f64,
    /// The slope's inclination, degrees (paper: 55).
    pub slope_deg: f64,
    /// Ground beyond the ledge on every side, metres.
    pub ground_margin: f64,
    /// The start's distance behind the lip, metres.
    pub start_back: f64,
    /// The root anchors, relative to the start's ground point: `(forward, up)` metres (paper:
    /// test 1 `(-4.9, 2.0)`, tests 2-3 `(8.2, 2.0)`).
    pub anchors: Vec<(f64, f64)>,
    /// The pole of test 3, if any.
    pub pole: Option<Pole>,
}

/// Why a scene is refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SceneError {
    /// A dimension out of its domain.
    #[error("scene field {field} = {}: {why}", Compact(*.value))]
    Field {
        /// The field.
        field: &'static str,
        /// Its value.
        value: f64,
        /// The domain.
        why: &'static str,
    },
    /// A root anchor inside the ledge or below the ground: a tether cannot be tied there.
    #[error(
        "scene field anchors[{index}] = ({}, {}): the anchor point ({}, {}, {}) is {:.3} m inside the ground; an anchor must lie on or above the surface",
        Compact(*.forward), Compact(*.up), Compact(point[0]), Compact(point[1]), Compact(point[2]), depth
    )]
    AnchorBelowGround {
        /// Its index in `anchors`.
        index: usize,
        /// Its `forward` offset.
        forward: f64,
        /// Its `up` offset.
        up: f64,
        /// The anchor in the world, metres.
        point: [f64; 3],
        /// How deep inside the ground it lies, metres (the distance to the surface).
        depth: f64,
    },
    /// The mesh failed validation (a bug in the generator if the fields passed).
    #[error("scene mesh: {0}")]
    Mesh(#[from] MeshError),
}

impl PatonScene {
    /// The paper's scene: 10 x 5 x 4 m, 55°, the anchors of tests 1 and 2, with or without the
    /// pole of test 3.
    pub fn paper(pole: bool) -> Self {
        PatonScene {
            length: 10.0,
            width: 5.0,
            height: 4.0,
            slope_deg: 55.0,
            ground_margin: 15.0,
            start_back: 1.0,
            anchors: vec![(-4.9, 2.0), (8.2, 2.0)],
            pole: pole.then_some(Pole {
                radius: 0.3,
                height: 10.0,
            }),
        }
    }

    fn check(&self) -> Result<(), SceneError> {
        let pos = |field, value: f64| {
            if value > 0.0 && value.is_finite() && value < 1e4 {
                Ok(())
            } else {
                Err(SceneError::Field {
                    field,
                    value,
                    why: "must be positive, finite and below 10 km",
                })
            }
        };
        pos("length", self.length)?;
        pos("width", self.width)?;
        pos("height", self.height)?;
        pos("ground_margin", self.ground_margin)?;
        pos("start_back", self.start_back)?;
        if !(self.slope_deg > 1.0 && self.slope_deg < 89.0) {
            return Err(SceneError::Field {
                field: "slope_deg",
                value: self.slope_deg,
                why: "must be in (1, 89) degrees",
            });
        }
        if self.start_back >= self.width {
            return Err(SceneError::Field {
                field: "start_back",
                value: self.start_back,
                why: "must be less than the ledge's width",
            });
        }
        for &(f, u) in &self.anchors {
            for value in [f, u] {
                if !(value.is_finite() && value.abs() < 1e4) {
                    return Err(SceneError::Field {
                        field: "anchors",
                        value,
                        why: "an offset must be finite and within 10 km of the start",
                    });
                }
            }
        }
        if let Some(p) = self.pole {
            pos("pole.radius", p.radius)?;
            pos("pole.height", p.height)?;
            if 2.0 * p.radius >= self.width.min(self.length) {
                return Err(SceneError::Field {
                    field: "pole.radius",
                    value: p.radius,
                    why: "the pole must fit on the ledge top",
                });
            }
        }
        Ok(())
    }

    /// Where the slope meets the ground, `x` metres.
    pub fn slope_foot_x(&self) -> f64 {
        self.height / self.slope_deg.to_radians().tan()
    }

    /// The start's ground point (on the ledge top, facing `+x`).
    pub fn start(&self) -> Point3<f64> {
        Point3::new(-self.start_back, 0.0, self.height)
    }

    /// The root anchors in the world.
    pub fn anchor_points(&self) -> Vec<Point3<f64>> {
        self.anchors
            .iter()
            .map(|&(f, u)| self.start() + Vector3::new(f, 0.0, u))
            .collect()
    }

    /// The pole's axis foot on the ledge top, if there is a pole.
    pub fn pole_center(&self) -> Option<Point3<f64>> {
        self.pole
            .map(|_| Point3::new(-0.5 * self.width, 0.0, self.height))
    }

    /// The scene as a validated triangle mesh (ground with the ledge's footprint cut out, the
    /// ledge's top, slope and three walls, and the pole).
    ///
    /// ```
    /// use rappel_terrain::paton_scene::PatonScene;
    /// let m = PatonScene::paper(false).mesh().unwrap();
    /// assert_eq!(m.triangles().len(), 18);
    /// ```
    pub fn mesh(&self) -> Result<TriMesh, SceneError> {
        self.check()?;
        let (hw, w, h, g) = (
            0.5 * self.length,
            self.width,
            self.height,
            self.ground_margin,
        );
        let xf = self.slope_foot_x();
        let p = Point3::new;
        let mut v = vec![
            // Outer ground corners O0..O3 (0..4), counter-clockwise from above.
            p(-w - g, -hw - g, 0.0),
            p(xf + g, -hw - g, 0.0),
            p(xf + g, hw + g, 0.0),
            p(-w - g, hw + g, 0.0),
            // Footprint corners F0..F3 (4..8).
            p(-w, -hw, 0.0),
            p(xf, -hw, 0.0),
            p(xf, hw, 0.0),
            p(-w, hw, 0.0),
            // Top corners T0..T3 (8..12).
            p(-w, -hw, h),
            p(0.0, -hw, h),
            p(0.0, hw, h),
            p(-w, hw, h),
        ];
        let mut t = Vec::new();
        for i in 0..4 {
            let (o0, o1, f0, f1) = (i, (i + 1) % 4, 4 + i, 4 + (i + 1) % 4);
            t.push([o0, o1, f1]);
            t.push([o0, f1, f0]);
        }
        t.extend([
            [8, 9, 10],
            [8, 10, 11], // top
            [9, 5, 6],
            [9, 6, 10], // slope
            [4, 8, 11],
            [4, 11, 7], // back wall
            [4, 5, 9],
            [4, 9, 8], // side y = -hw
            [7, 11, 10],
            [7, 10, 6], // side y = +hw
        ]);
        if let (Some(pole), Some(c)) = (self.pole, self.pole_center()) {
            let base = v.len();
            let n = POLE_SIDES;
            for k in 0..n {
                let a = std::f64::consts::TAU * k as f64 / n as f64;
                let (s, co) = a.sin_cos();
                v.push(p(
                    c.x + pole.radius * co,
                    c.y + pole.radius * s,
                    h - POLE_SINK,
                ));
                v.push(p(
                    c.x + pole.radius * co,
                    c.y + pole.radius * s,
                    h + pole.height,
                ));
            }
            let cap = v.len();
            v.push(p(c.x, c.y, h + pole.height));
            for k in 0..n {
                let (b0, p0) = (base + 2 * k, base + 2 * k + 1);
                let (b1, p1) = (base + 2 * ((k + 1) % n), base + 2 * ((k + 1) % n) + 1);
                t.push([b0, b1, p1]);
                t.push([b0, p1, p0]);
                t.push([cap, p0, p1]);
            }
        }
        let mesh = TriMesh::new(v, t)?;
        for (index, (&(forward, up), point)) in
            self.anchors.iter().zip(self.anchor_points()).enumerate()
        {
            let d = mesh.signed_distance(&point);
            if d < 0.0 {
                return Err(SceneError::AnchorBelowGround {
                    index,
                    forward,
                    up,
                    point: [point.x, point.y, point.z],
                    depth: -d,
                });
            }
        }
        Ok(mesh)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn faces_point_to_the_air_and_distances_are_geometric() {
        let s = PatonScene::paper(true);
        let m = s.mesh().unwrap();
        // Closed forms: above the top, in front of the slope (along its normal), beside the pole.
        let top = Point3::new(-4.0, 3.0, 4.7);
        assert!((m.signed_distance(&top) - 0.7).abs() < 1e-12);
        let a = 55f64.to_radians();
        let n = Vector3::new(a.sin(), 0.0, a.cos());
        let on_slope = Point3::new(1.0, 1.0, 4.0 - a.tan());
        assert!((m.signed_distance(&(on_slope + n * 0.5)) - 0.5).abs() < 1e-12);
        assert!((m.signed_distance(&(on_slope - n * 0.5)) + 0.5).abs() < 1e-12);
        // 0.5 m beside the pole's axis at mid height: 0.2 m from a 0.3 m pole (32-gon: within
        // 0.0048 r of the circle).
        let c = s.pole_center().unwrap();
        let d = m.signed_distance(&(c + Vector3::new(0.5, 0.0, 3.0)));
        assert!((d - 0.2).abs() < 0.0048 * 0.3 + 1e-12, "{d}");
        let inside = m.signed_distance(&(c + Vector3::new(0.1, 0.0, 3.0)));
        assert!(inside < 0.0);
        // Inside the ledge, below the ground.
        assert!(m.signed_distance(&Point3::new(-2.0, -3.0, 2.0)) < 0.0);
        assert!(m.signed_distance(&Point3::new(10.0, 0.0, -0.3)) < 0.0);
        assert_eq!(s.slope_foot_x(), 4.0 / a.tan());
        let anchors = s.anchor_points();
        assert!((anchors[0] - Point3::new(-5.9, 0.0, 6.0)).norm() < 1e-12);
        assert!((anchors[1] - Point3::new(7.2, 0.0, 6.0)).norm() < 1e-12);
    }

    #[test]
    fn anchors_inside_the_ledge_or_under_the_ground_are_refused() {
        // 2 m below the ledge top at the start: 2 m inside the ledge (the top is the nearest
        // face).
        let mut s = PatonScene::paper(false);
        s.anchors = vec![(-4.9, 2.0), (-1.0, -2.0)];
        match s.mesh() {
            Err(SceneError::AnchorBelowGround { index, depth, .. }) => {
                assert_eq!(index, 1);
                assert!((depth - 2.0).abs() < 1e-12, "{depth}");
            }
            other => panic!("{other:?}"),
        }
        // In front of the slope's foot, 1 m under the flat ground.
        s.anchors = vec![(10.0, -5.0)];
        let e = s.mesh().unwrap_err().to_string();
        assert!(
            e.contains("anchors[0] = (10, -5)") && e.contains("1.000 m inside"),
            "{e}"
        );
        // On the surface is allowed (the lip's corner, 0 m).
        s.anchors = vec![(1.0, 0.0)];
        assert!(s.mesh().is_ok());
    }

    #[test]
    fn fixtures_are_the_paper_scenes() {
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/paton/");
        for (file, pole) in [("ledge.ron", false), ("ledge-pole.ron", true)] {
            let text = std::fs::read_to_string(format!("{dir}{file}")).unwrap();
            let s: PatonScene = ron::from_str(&text).unwrap();
            assert_eq!(s, PatonScene::paper(pole), "{file}");
            s.mesh().unwrap();
        }
        // Unknown fields are errors.
        let bad = "(length: 10.0, width: 5.0, height: 4.0, slope_deg: 55.0, ground_margin: 15.0, \
                   start_back: 1.0, anchors: [], pole: None, colour: 3)";
        assert!(ron::from_str::<PatonScene>(bad).is_err());
    }

    #[test]
    fn bad_fields_are_errors() {
        let mut s = PatonScene::paper(false);
        s.slope_deg = 90.0;
        assert!(matches!(
            s.mesh(),
            Err(SceneError::Field {
                field: "slope_deg",
                ..
            })
        ));
        let mut s = PatonScene::paper(true);
        s.pole = Some(Pole {
            radius: 3.0,
            height: 1.0,
        });
        assert!(matches!(
            s.mesh(),
            Err(SceneError::Field {
                field: "pole.radius",
                ..
            })
        ));
        let mut s = PatonScene::paper(false);
        s.height = f64::NAN;
        assert!(s.mesh().is_err());
    }
}
