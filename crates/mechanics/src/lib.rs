//! Tether and rover mechanics (thesis Ch. 3, Paton §IV, Kumar §II-III): rope statics with friction,
//! terrain curvature, potential tether friction obstacles, robot models and the wheel/tether
//! stability QP and tension-limited LP. Pure functions of geometry and parameters; no search.
//!
//! Module map (one concept each; the math and the paper equations are in each module's docs):
//!
//! | module | computes | source |
//! |---|---|---|
//! | [`ode`] | adaptive Dormand-Prince RK45 integration | thesis §3.3.4 (ode45) |
//! | [`darboux`] | Darboux frame, `κ_n`, `κ_g`, `φ` of a curve on a surface | eqs. 3.1-3.5 |
//! | [`surface_curve`] | tether curves on surfaces (capstan, helix, plane line) | §3.3.4 |
//! | [`sticking`] | `ω²`, Konyukhov's conditions, Alg. 9 `TetherSlips` | eqs. 3.16-3.19, 3.25-3.27 |
//! | [`capstan`] | capstan relation and its constant-`ω` generalisation | eqs. 3.20-3.24 |
//! | [`heavy_rope`] | limiting tension of a heavy rope | eq. 3.14 |
//! | [`curvature`] | principal curvatures, convexity, saddle break angle | eqs. 3.28-3.31 |
//! | [`friction`] | friction intervals used conservatively | §3.6.1 |
//! | [`ptfo`] | solid / slides / volatile PTFO classes | §3.4.1, Alg. 9 |
//! | [`ptfo_surface`] | PTFO surfaces and the tether's wrap contact on them | §3.3.5, §3.4 |
//! | [`ptfo_detection`] | PTFOs on a DEM: convex patches, hulls, height patches | §3.1.1, §3.3.3, §3.4 |
//! | [`sticking_profile`] | where a tether draped over a DEM may stick along its length | §3.3.5, Figs. 3.13-3.15 |
//! | [`robot`] | the robot-model trait, planes, poses, placement | Paton §IV-A |
//! | [`axel`] | the Axel model and its tether-tension estimate | eq. 3.32 |
//! | [`four_wheel`] | a generic four-wheel rover | Kumar §II |
//! | [`point_body`] | Kumar's free body: one ground force in one pyramid | Kumar Fig. 4, eq. 3c |
//! | [`traversability`] | the stability-criterion seam, settings | GUIDE §2 |
//! | [`stability_error`] | why a stability question could not be answered | GUIDE §3 |
//! | [`conic`] | the clarabel adapter and status mapping | GUIDE §3 |
//! | [`dense_qp`] | dense Goldfarb-Idnani QP (diagonal Hessian) | Goldfarb-Idnani 1983 |
//! | [`stability_qp`] | wheel/tether stability QP | Paton eqs. 1-9 |
//! | [`tension_limit`] | holding limit, winding angles, capstan amplification | Kumar eqs. 1-2 |
//! | [`tension_lp`] | tension-limited stability LP | Kumar eqs. 3a-3e |
//! | [`stability_map`] | parallel pose grids over planes | Kumar Fig. 5 |
//! | [`anchor_traversability`] | the tether-limit seam of the Chapter-2 planner | thesis §2.4 |
//! | [`friction_cone`] | point-robot tether friction cone | thesis eq. 2.7 |
//!
//! Sign convention: surface normals point out of the ground, and normal curvatures are
//! `ρ''·n`, so a tether over a hump has `κ_n < 0` (see [`darboux`]).

/// The linear-algebra crate of every public signature, re-exported so that users name the same
/// version.
pub use nalgebra;

pub mod anchor_traversability;
pub mod axel;
#[cfg(feature = "mesh")]
pub mod boom_contact;
pub mod capstan;
pub mod conic;
pub mod curvature;
pub mod darboux;
pub mod dense_lp;
pub mod dense_qp;
pub mod four_wheel;
pub mod four_wheel_settle;
pub mod friction;
pub mod friction_cone;
pub mod heavy_rope;
pub mod ode;
pub mod point_body;
pub mod ptfo;
pub mod ptfo_detection;
pub mod ptfo_surface;
pub mod robot;
pub mod settle;
pub mod stability_error;
pub mod stability_map;
pub mod stability_qp;
mod statics;
pub mod sticking;
pub mod sticking_profile;
pub mod surface_curve;
pub mod tension_limit;
pub mod tension_lp;
pub mod traversability;
pub mod wheeled_tether_cone;
