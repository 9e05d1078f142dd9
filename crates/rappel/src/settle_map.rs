//! `rappel settle-map`: a stability map of a mesh scene like Paton's Fig. 8, with the anchor
//! history carried along a drive from the start under the root anchor
//! ([`rappel_planners::rover::stability_map`] computes it; this module names what the use case
//! needs and makes the map a report).

pub use rappel_planners::rover::stability_map::{
    AxelMap, FourWheelMap, MAX_MAP_CELLS, MapCell, MapRobot, MapSpec, MeshStabilityError,
    StabilityMap, stability_map, stability_map_for, stability_map_through_field,
    stability_map_with,
};

impl crate::report::Report for StabilityMap {
    const KIND: &'static str = "settle_map";
}
