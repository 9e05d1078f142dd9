//! The chosen ascent/descent pair as reports show it (thesis Alg. 6): both paths, their lengths
//! and how close they pass to the anchors. Shared by the Chapter-2 plan and the frictional plan.

use nalgebra::Point2;
use rappel_planners::path_pair::PathPair;
use serde::{Deserialize, Serialize};

/// The chosen ascent/descent pair.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct PairReport {
    /// The class's rank.
    pub rank: usize,
    /// Ascent, goal to start.
    #[schemars(with = "Vec<[f64; 2]>")]
    pub ascent: Vec<Point2<f64>>,
    /// Descent, start to goal.
    #[schemars(with = "Vec<[f64; 2]>")]
    pub descent: Vec<Point2<f64>>,
    /// Ascent length, m.
    pub ascent_length_m: f64,
    /// Descent length, m.
    pub descent_length_m: f64,
    /// The descent is the ascent reversed.
    pub descent_is_reversed_ascent: bool,
    /// Smallest distance from either path to an anchor, m (`null` without anchors).
    pub min_anchor_distance_m: Option<f64>,
}

impl From<&PathPair> for PairReport {
    fn from(p: &PathPair) -> Self {
        PairReport {
            rank: p.rank,
            ascent: p.ascent.clone(),
            descent: p.descent.clone(),
            ascent_length_m: p.ascent_length,
            descent_length_m: p.descent_length,
            descent_is_reversed_ascent: p.descent_is_reversed_ascent,
            min_anchor_distance_m: p
                .min_anchor_distance
                .is_finite()
                .then_some(p.min_anchor_distance),
        }
    }
}
