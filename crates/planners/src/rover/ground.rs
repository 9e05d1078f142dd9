//! Where settling and anchor prediction read their distances to a mesh ground (Paton §IV):
//! parry's exact BVH distances ([`rappel_terrain::parry_mesh`]), or the sparse signed distance
//! field at a resolution ([`rappel_terrain::sparse_sdf`], Paton's use of a Voxblox-style field:
//! the tether's swept triangle and the body points along the axle sampled in it). One choice,
//! [`DistanceSource`], built once per ground into [`GroundDistances`] and shared by
//! `rappel settle`, `rappel settle-map` and `rappel navigate` (their `--field RES`).
//!
//! The boom sweep and the stability placement always read the mesh's triangles (through the
//! same BVH), whatever the source: the boom's contact is exact (`mechanics::boom_contact`).

use std::sync::Arc;

use nalgebra::Point3;

use serde::{Deserialize, Serialize};

use crate::anchor_prediction::PredictParams;
use rappel_mechanics::axel::AxelParams;
use rappel_mechanics::four_wheel::FourWheelParams;
use rappel_mechanics::four_wheel_settle::{FourWheelPose, settle_four_wheel};
use rappel_mechanics::settle::{SettleError, SettleParams, SettledPose, settle_axel};
use rappel_terrain::mesh::TriMesh;
use rappel_terrain::parry_mesh::{ParryMesh, ParryMeshError};
use rappel_terrain::sdf::SdfError;
use rappel_terrain::sparse_sdf::{SparseSdf, SparseSdfParams};
use rappel_terrain::surface::SignedDistance;

/// Height above the mesh's top from which settling drops to the ground, metres.
pub const SETTLE_START_HEIGHT: f64 = 1.0;

/// Margin of the distance field around the mesh's bounding box, metres: settling starts
/// [`SETTLE_START_HEIGHT`] above the mesh's top, and its footprint probes and the wheels' circles
/// reach a little beyond the mesh's sides and top; the box must hold them.
pub const FIELD_MARGIN: f64 = 2.0;

/// Which distances settling and anchor prediction read.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DistanceSource {
    /// Parry's exact distances to the mesh (BVH point projection).
    Exact,
    /// The sparse signed distance field of the mesh at `resolution_m` metres, propagated to its
    /// default `max_distance` (`SparseSdfParams::new`), margin [`FIELD_MARGIN`].
    Field {
        /// Grid spacing, metres (`> 0`, finite).
        resolution_m: f64,
    },
}

/// Why a ground's distances cannot be built (the caller's input).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DistanceSourceError {
    /// The field's resolution is zero, negative, infinite or NaN.
    #[error("the resolution must be a positive, finite number of metres")]
    BadResolution(f64),
    /// The field's resolution is coarser than the ground's bounding-box diagonal (`.1`, metres):
    /// the field would have a single cell and say nothing about the ground's shape.
    #[error(
        "the resolution must be a positive, finite number of metres no coarser than the ground's extent ({} m diagonal)",
        rappel_geometry::compact::Rounded(*.1, 3)
    )]
    TooCoarse(f64, f64),
    /// The field could not be built at this resolution (over one of its caps: too fine for the
    /// scene's size).
    #[error("{0}")]
    Field(SdfError),
    /// Parry refused the mesh.
    #[error("{0}")]
    Bvh(ParryMeshError),
}

/// What a report states about its distances: the source, and through the field its resolution
/// and error bound.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct DistanceReport {
    /// `exact` (parry's BVH distances to the mesh) or `field` (the sparse distance field).
    pub source: String,
    /// The field's grid spacing, metres (`None` for exact distances).
    pub resolution_m: Option<f64>,
    /// The field's bound on `|field - exact distance|` within its propagation distance
    /// (`SparseSdf::error_bound`; its propagation term empirical), metres (`None` for exact
    /// distances).
    pub error_bound_m: Option<f64>,
}

/// A mesh ground's distances for settling and prediction: the mesh's BVH (always: the boom
/// sweep's candidate triangles and the stability placement) and, for [`DistanceSource::Field`],
/// the sparse field.
#[derive(Debug, Clone)]
pub struct GroundDistances {
    bvh: Arc<ParryMesh>,
    field: Option<SparseSdf>,
    z_top: f64,
}

impl GroundDistances {
    /// The distances of `mesh` from `source`: the BVH, and the field when asked for. The field's
    /// work and memory are bounded by its caps (`SparseSdfParams`); a resolution too fine for
    /// the mesh's size is [`DistanceSourceError::Field`].
    ///
    /// ```
    /// use nalgebra::Point3;
    /// use rappel_planners::rover::ground::{DistanceSource, GroundDistances};
    /// use rappel_terrain::mesh::TriMesh;
    /// let v = vec![
    ///     Point3::new(-5.0, -5.0, 0.0),
    ///     Point3::new(5.0, -5.0, 0.0),
    ///     Point3::new(5.0, 5.0, 0.0),
    ///     Point3::new(-5.0, 5.0, 0.0),
    /// ];
    /// let ground = TriMesh::new(v, vec![[0, 1, 2], [0, 2, 3]]).unwrap();
    /// let d = GroundDistances::new(&ground, DistanceSource::Field { resolution_m: 0.2 }).unwrap();
    /// let pose = d.settle(0.0, 0.0, 30.0).unwrap();
    /// assert!(pose.origin.z.abs() <= d.report().error_bound_m.unwrap());
    /// assert!(GroundDistances::new(&ground, DistanceSource::Field { resolution_m: 0.0 }).is_err());
    /// ```
    pub fn new(mesh: &TriMesh, source: DistanceSource) -> Result<Self, DistanceSourceError> {
        let field = match source {
            DistanceSource::Exact => None,
            DistanceSource::Field { resolution_m: h } => {
                if !(h > 0.0 && h.is_finite()) {
                    return Err(DistanceSourceError::BadResolution(h));
                }
                let (lo, hi) = mesh.bounds();
                let diagonal = (hi - lo).norm();
                if h > diagonal {
                    return Err(DistanceSourceError::TooCoarse(h, diagonal));
                }
                let mut params = SparseSdfParams::new(h);
                params.margin = params.margin.max(FIELD_MARGIN);
                Some(SparseSdf::from_mesh(mesh, &params).map_err(DistanceSourceError::Field)?)
            }
        };
        let bvh = Arc::new(ParryMesh::new(mesh).map_err(DistanceSourceError::Bvh)?);
        Ok(GroundDistances {
            bvh,
            field,
            z_top: mesh.bounds().1.z + SETTLE_START_HEIGHT,
        })
    }

    /// The mesh behind parry's BVH (exact distances, the boom sweep's candidate triangles).
    pub fn bvh(&self) -> &Arc<ParryMesh> {
        &self.bvh
    }

    /// The field, for [`DistanceSource::Field`].
    pub fn field(&self) -> Option<&SparseSdf> {
        self.field.as_ref()
    }

    /// The distances settling and prediction read: the field when built, else the BVH.
    pub fn distance(&self) -> &(dyn SignedDistance + Sync) {
        match &self.field {
            Some(f) => f,
            None => &*self.bvh,
        }
    }

    /// Anchor prediction's sampling resolution: [`PREDICT_RESOLUTION`] on exact distances, the
    /// field's resolution through it (finer sampling cannot resolve more than the grid).
    pub fn predict_resolution(&self) -> f64 {
        self.field
            .as_ref()
            .map_or(PREDICT_RESOLUTION, SparseSdf::resolution)
    }

    /// Anchor prediction's parameters: [`GroundDistances::predict_resolution`], with clear-ball
    /// skipping on exact distances ([`PredictParams::exact`]: parry's distances to the mesh, whose
    /// sign changes only across the ground inside the mesh's boundary), without it through the
    /// field (an interpolated distance).
    pub fn predict_params(&self) -> PredictParams {
        match self.field {
            None => PredictParams::exact(PREDICT_RESOLUTION),
            Some(_) => PredictParams::new(self.predict_resolution()),
        }
    }

    /// The height settling starts from: [`SETTLE_START_HEIGHT`] above the mesh's top.
    pub fn z_top(&self) -> f64 {
        self.z_top
    }

    /// Axel (default [`AxelParams`] and [`SettleParams`]) settled at ground point `(x, y)`
    /// heading `yaw_deg` (degrees counter-clockwise from `+x`) on [`GroundDistances::distance`].
    pub fn settle(&self, x: f64, y: f64, yaw_deg: f64) -> Result<SettledPose, SettleError> {
        let pose = settle_axel(
            self.distance(),
            &AxelParams::default(),
            x,
            y,
            self.z_top,
            yaw_deg.to_radians(),
            &SettleParams::default(),
        )?;
        self.on_the_mesh(&pose.contacts)?;
        Ok(pose)
    }

    /// Through the field, every contact must stand over the mesh: an open mesh's field changes
    /// sign just past its edge (the pseudo-normal's side), so a drop there meets ground that is
    /// not there. The exact vertical ray through the BVH ([`SignedDistance::ground_below`] of
    /// [`ParryMesh`]) decides, as settling on exact distances does. Exact distances need no
    /// check.
    fn on_the_mesh(&self, contacts: &[Point3<f64>]) -> Result<(), SettleError> {
        if self.field.is_none() {
            return Ok(());
        }
        for c in contacts {
            let above = Point3::new(c.x, c.y, self.z_top);
            if self.bvh.ground_below(&above, 0.0).is_err() {
                return Err(SettleError::NoGround {
                    x: c.x,
                    y: c.y,
                    z: c.z,
                });
            }
        }
        Ok(())
    }

    /// The four-wheel rover (default [`FourWheelParams`] and [`SettleParams`]) settled at ground
    /// point `(x, y)` heading `yaw_deg` (degrees counter-clockwise from `+x`) on
    /// [`GroundDistances::distance`].
    pub fn settle_four_wheel(
        &self,
        x: f64,
        y: f64,
        yaw_deg: f64,
    ) -> Result<FourWheelPose, SettleError> {
        let pose = settle_four_wheel(
            self.distance(),
            &FourWheelParams::default(),
            x,
            y,
            self.z_top,
            yaw_deg.to_radians(),
            &SettleParams::default(),
        )?;
        let support: Vec<Point3<f64>> = pose
            .support
            .iter()
            .map(|&w| pose.ground_points[w])
            .collect();
        self.on_the_mesh(&support)?;
        Ok(pose)
    }

    /// What a report states about these distances.
    pub fn report(&self) -> DistanceReport {
        match &self.field {
            None => DistanceReport {
                source: "exact".into(),
                resolution_m: None,
                error_bound_m: None,
            },
            Some(f) => DistanceReport {
                source: "field".into(),
                resolution_m: Some(f.resolution()),
                error_bound_m: Some(f.error_bound()),
            },
        }
    }
}

/// Sampling resolution of anchor prediction on exact mesh distances, metres: the smallest ground
/// feature the tether notices (contacts are found once the swept tether is this deep).
pub const PREDICT_RESOLUTION: f64 = 0.05;
