//! Homotopy tests (thesis §2.2, §2.2.1). Two paths with the same endpoints are homotopic exactly
//! when their reduced crossing sequences are equal: the reduced sequence is the unique path
//! between the endpoints' lifts in the dual tree of the universal cover (see
//! [`crate::crossing`]). Equivalently (Lemma 2.2.1) the loop `pi_1 . reverse(pi_2)` is
//! contractible, which holds exactly when a loop's reduced sequence is empty.
//!
//! Endpoints are compared exactly: homotopy is only defined for paths with the same endpoints.

use crate::crossing::{CrossingSequence, Tracer, cancels};
use crate::path::{Path, PathError};
use crate::sleeve::SleeveError;
use nalgebra::Point2;
use rappel_geometry::btm::Btm;

/// Why a homotopy question could not be answered.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum HomotopyError {
    /// The path is invalid.
    #[error(transparent)]
    Path(#[from] PathError),
    /// One of several paths is invalid (`path` counts from 1).
    #[error("path {path}: {source}")]
    NthPath {
        /// Which path, counting from 1.
        path: usize,
        /// What is wrong with it.
        #[source]
        source: PathError,
    },
    /// The sleeve or a point on it is invalid.
    #[error(transparent)]
    Sleeve(#[from] SleeveError),
    /// The two paths do not start and end at the same points.
    #[error("the paths do not share their endpoints: ({}, {}) -> ({}, {}) versus ({}, {}) -> ({}, {})", first.0.x, first.0.y, first.1.x, first.1.y, second.0.x, second.0.y, second.1.x, second.1.y)]
    EndpointsDiffer {
        /// Start and end of the first path.
        first: (Point2<f64>, Point2<f64>),
        /// Start and end of the second path.
        second: (Point2<f64>, Point2<f64>),
    },
    /// A loop was expected: the path must end where it starts.
    #[error("the path is not closed: it starts at ({}, {}) and ends at ({}, {})", start.x, start.y, end.x, end.y)]
    NotClosed {
        /// Its start.
        start: Point2<f64>,
        /// Its end.
        end: Point2<f64>,
    },
}

/// `true` when two paths with the same endpoints are homotopic in the free space of `btm`.
///
/// ```
/// use nalgebra::Point2;
/// use rappel_geometry::{btm::Btm, map::Map, polygon::Polygon};
/// use rappel_homotopy::{homotopy::are_homotopic, path::Path};
/// let p = |x, y| Point2::new(x, y);
/// let map = Map::new(
///     Polygon::new(vec![p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)]),
///     vec![Polygon::new(vec![p(4., 4.), p(6., 4.), p(6., 6.), p(4., 6.)])],
/// );
/// let btm = Btm::from_map(&map).unwrap();
/// let west = Path::new(vec![p(5., 9.), p(1., 5.), p(5., 1.)]).unwrap();
/// let west2 = Path::new(vec![p(5., 9.), p(3., 8.), p(2., 2.), p(5., 1.)]).unwrap();
/// let east = Path::new(vec![p(5., 9.), p(9., 5.), p(5., 1.)]).unwrap();
/// assert!(are_homotopic(&btm, &west, &west2).unwrap());
/// assert!(!are_homotopic(&btm, &west, &east).unwrap());
/// ```
pub fn are_homotopic(btm: &Btm, first: &Path, second: &Path) -> Result<bool, HomotopyError> {
    if first.start() != second.start() || first.end() != second.end() {
        return Err(HomotopyError::EndpointsDiffer {
            first: (first.start(), first.end()),
            second: (second.start(), second.end()),
        });
    }
    let a = CrossingSequence::reduced_of_path(btm, first)
        .map_err(|source| HomotopyError::NthPath { path: 1, source })?;
    let b = CrossingSequence::reduced_of_path(btm, second)
        .map_err(|source| HomotopyError::NthPath { path: 2, source })?;
    Ok(a == b)
}

/// `true` when a closed path (a loop) can be shrunk to its basepoint in free space (thesis
/// §2.2.1): its reduced crossing sequence is empty.
///
/// ```
/// use nalgebra::Point2;
/// use rappel_geometry::{btm::Btm, map::Map, polygon::Polygon};
/// use rappel_homotopy::{homotopy::is_contractible, path::Path};
/// let p = |x, y| Point2::new(x, y);
/// let map = Map::new(
///     Polygon::new(vec![p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)]),
///     vec![Polygon::new(vec![p(4., 4.), p(6., 4.), p(6., 6.), p(4., 6.)])],
/// );
/// let btm = Btm::from_map(&map).unwrap();
/// let around = Path::new(vec![p(1., 1.), p(9., 1.), p(9., 9.), p(1., 9.), p(1., 1.)]).unwrap();
/// let beside = Path::new(vec![p(1., 1.), p(3., 1.), p(3., 9.), p(1., 9.), p(1., 1.)]).unwrap();
/// assert!(!is_contractible(&btm, &around).unwrap());
/// assert!(is_contractible(&btm, &beside).unwrap());
/// ```
pub fn is_contractible(btm: &Btm, closed: &Path) -> Result<bool, HomotopyError> {
    if !closed.is_closed() {
        return Err(HomotopyError::NotClosed {
            start: closed.start(),
            end: closed.end(),
        });
    }
    Ok(CrossingSequence::reduced_of_path(btm, closed)?.is_empty())
}

/// The fixed beginning of a family of loops, traced once: [`LoopPrefix::closes_contractibly`]
/// answers [`is_contractible`] for the loop `prefix ++ rest` by walking only `rest`. For tests
/// that probe many loops sharing a long beginning (the bisection of a tether's sweep, where the
/// tether is fixed and only the far corner moves).
///
/// Same answers as [`is_contractible`] on the whole loop, by construction: the tracer is the
/// same walk resumed where the prefix ended (a walk's crossings only depend on the points
/// walked), and reducing a sequence is a left-to-right stack pass, so the reduced prefix
/// continued with the rest's crossings is the reduced whole.
///
/// ```
/// use nalgebra::Point2;
/// use rappel_geometry::{btm::Btm, map::Map, polygon::Polygon};
/// use rappel_homotopy::homotopy::{LoopPrefix, is_contractible};
/// use rappel_homotopy::path::Path;
/// let p = |x, y| Point2::new(x, y);
/// let map = Map::new(
///     Polygon::new(vec![p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)]),
///     vec![Polygon::new(vec![p(4., 4.), p(6., 4.), p(6., 6.), p(4., 6.)])],
/// );
/// let btm = Btm::from_map(&map).unwrap();
/// let mut tether = LoopPrefix::new(&btm, &[p(1., 1.), p(9., 1.)]).unwrap();
/// let beside = [p(9., 3.), p(1., 1.)];
/// let around = [p(9., 9.), p(1., 9.), p(1., 1.)];
/// let through = [p(9., 9.), p(1., 1.)]; // the diagonal crosses the obstacle
/// for rest in [&beside[..], &around, &through] {
///     let whole = Path::new([&[p(1., 1.), p(9., 1.)][..], rest].concat()).unwrap();
///     assert_eq!(
///         tether.closes_contractibly(rest).ok(),
///         is_contractible(&btm, &whole).ok()
///     );
/// }
/// assert_eq!(tether.closes_contractibly(&beside), Ok(true));
/// assert_eq!(tether.closes_contractibly(&around), Ok(false));
/// assert!(tether.closes_contractibly(&through).is_err());
/// ```
#[derive(Debug, Clone)]
pub struct LoopPrefix<'a> {
    btm: &'a Btm,
    /// The walk at the prefix's end, its crossings handed over to `reduced`.
    tracer: Tracer<'a>,
    /// The prefix's reduced crossing sequence (a stack, bottom first).
    reduced: Vec<rappel_geometry::dcel::HalfEdgeId>,
    /// The rest's unreduced part of the stack, reused between probes.
    scratch: Vec<rappel_geometry::dcel::HalfEdgeId>,
}

impl<'a> LoopPrefix<'a> {
    /// Traces `points` (at least one; the loop's start first). Errors as the path's would: a
    /// point not in free space, a segment leaving it, a non-finite point.
    pub fn new(btm: &'a Btm, points: &[Point2<f64>]) -> Result<LoopPrefix<'a>, PathError> {
        let (&start, rest) = points.split_first().ok_or(PathError::Empty)?;
        let mut tracer = Tracer::new(btm, start)?;
        for q in rest {
            tracer.push(*q)?;
        }
        let raw = tracer.take_crossings();
        let reduced = CrossingSequence::from_parts(tracer.triangle(), tracer.triangle(), raw)
            .reduced(btm)
            .into_crossings();
        Ok(LoopPrefix {
            btm,
            tracer,
            reduced,
            scratch: Vec::new(),
        })
    }

    /// [`is_contractible`] of the loop `prefix ++ rest`, where `rest` ends at the prefix's first
    /// point (not checked here beyond what [`is_contractible`] checks: an open loop's answer is
    /// that of its crossings, so callers close it). Walks `rest` only; an error is the one
    /// walking the whole loop would give for `rest`'s segments.
    pub fn closes_contractibly(&mut self, rest: &[Point2<f64>]) -> Result<bool, PathError> {
        let mut tracer = self.tracer.clone();
        for q in rest {
            tracer.push(*q)?;
        }
        let d = self.btm.dcel();
        // The stack is `reduced[..k] ++ scratch`; the rest's crossings continue the reduction.
        let mut k = self.reduced.len();
        self.scratch.clear();
        for &h in tracer.finish().crossings() {
            let top = match self.scratch.last() {
                Some(&top) => Some(top),
                None => k.checked_sub(1).map(|i| self.reduced[i]),
            };
            if top.is_some_and(|top| cancels(d, top, h)) {
                if self.scratch.pop().is_none() {
                    k -= 1;
                }
            } else {
                self.scratch.push(h);
            }
        }
        Ok(k == 0 && self.scratch.is_empty())
    }
}
