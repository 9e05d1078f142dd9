//! Homotopy of tether paths in a boundary-triangulated 2-manifold (thesis §2.2-2.3): crossing
//! sequences and their reduction, sleeves, the funnel algorithm, shortest homotopic paths (SHPs),
//! H-signatures, and funnel states on the universal cover. Knows nothing of friction or robots.
//!
//! The taut tether is the shortest path in its homotopy class. Following Hershberger and
//! Snoeyink, rappel computes it in four steps ([`shp::shortest_homotopic_path`]):
//! 1. walk the path through the BTM and record its [`crossing::CrossingSequence`] (thesis
//!    §2.2.3), with a symbolic perturbation for paths through vertices and along edges;
//! 2. reduce it: the reduced sequence is the canonical word of the homotopy class;
//! 3. its triangles form the [`sleeve::Sleeve`];
//! 4. the Funnel Algorithm ([`funnel::shortest_path_in_sleeve`], thesis Alg. 1) finds the
//!    shortest path in the sleeve, with its [`funnel::Anchor`]s.
//!
//! Homotopy tests ([`homotopy`]) compare reduced sequences; H-signatures ([`h_signature`], thesis
//! eqs. 2.2-2.3) give the homology class through per-obstacle winding numbers; funnel states
//! ([`funnel_state`], thesis Alg. 2) are the primitive of the shortest-path-tree search.
//!
//! ```
//! use nalgebra::Point2;
//! use rappel_geometry::{btm::Btm, map::Map, polygon::Polygon};
//! use rappel_homotopy::{path::Path, shp::shortest_homotopic_path};
//! let p = |x, y| Point2::new(x, y);
//! let map = Map::new(
//!     Polygon::new(vec![p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)]),
//!     vec![Polygon::new(vec![p(4., 4.), p(6., 4.), p(6., 6.), p(4., 6.)])],
//! );
//! let btm = Btm::from_map(&map).unwrap();
//! // A slack tether that went down the east side of the obstacle.
//! let slack = Path::new(vec![p(5., 9.), p(9., 8.), p(8., 2.), p(5., 1.)]).unwrap();
//! let shp = shortest_homotopic_path(&btm, &slack).unwrap();
//! assert_eq!(shp.taut.points, vec![p(5., 9.), p(6., 6.), p(6., 4.), p(5., 1.)]);
//! assert!(shp.taut.length < slack.length());
//! ```

mod geom;

pub mod crossing;
pub mod funnel;
pub mod funnel_state;
pub mod h_signature;
pub mod homotopy;
pub mod kite;
pub mod path;
pub mod shp;
pub mod sleeve;

pub use crossing::{CrossingSequence, Tracer};
pub use funnel::{Anchor, Side, TautPath, shortest_path_in_sleeve};
pub use funnel_state::{FunnelState, FunnelTree, NodeId, Split, TreeMarks};
pub use h_signature::{HSignature, Poles};
pub use homotopy::{HomotopyError, are_homotopic, is_contractible};
pub use path::{Blocker, Path, PathError};
pub use shp::{ShortestHomotopicPath, shortest_homotopic_path};
pub use sleeve::{Sleeve, SleeveError};
