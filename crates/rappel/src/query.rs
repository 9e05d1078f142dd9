//! Many start/goal queries on one map (issue 10): the BTM and the planner are built once, each
//! pair is answered by the SPT search (its shortest length, or its `K` shortest homotopy classes),
//! timed over repeats (median). For tether-length tables, batch studies and benchmarks.
//!
//! Pairs file (JSON): `[{"start": [x, y], "goal": [x, y]}, ...]`, unknown fields refused, at most
//! [`MAX_PAIRS`] pairs. A pair whose point is not in free space gets its own error, naming its
//! index; the others are answered.

use crate::progress::{Progress, Quiet};
use crate::scenario::Scenario;
use nalgebra::Point2;
use rappel_geometry::btm::Btm;
use rappel_geometry::map::{Map, ValidMap};
use rappel_planners::spt::{SearchError, SearchOptions, SptPlanner};
use rappel_planners::stop::{StopCondition, StopReason};
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::time::Instant;

/// Most pairs in one file.
pub const MAX_PAIRS: usize = 100_000;
/// Most repeats of each query.
pub const MAX_REPEATS: usize = 1000;
/// Most classes per pair.
pub const MAX_QUERY_CLASSES: usize = 100;

/// One start/goal pair.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct QueryPair {
    /// Start point (map frame).
    pub start: Point2<f64>,
    /// Goal point.
    pub goal: Point2<f64>,
}

/// The answer for one pair.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct QueryAnswer {
    /// Index of the pair in the file, from 0.
    pub index: usize,
    /// The pair.
    #[schemars(with = "[f64; 2]")]
    pub start: Point2<f64>,
    /// The pair's goal.
    #[schemars(with = "[f64; 2]")]
    pub goal: Point2<f64>,
    /// Lengths of the shortest homotopy classes found, shortest first, m (empty: not connected).
    pub lengths_m: Vec<f64>,
    /// Median time of one query over the repeats, whole nanoseconds (`None` before any run).
    pub median_ns: Option<u64>,
    /// Why the pair could not be answered (a point outside free space, a spent budget...).
    pub error: Option<String>,
    /// Which condition of the stop condition stopped the pair's search, or kept it from being
    /// searched ([`answer`]): its expansion budget, the time limit, a cancel request.
    /// Absent when the search ended by its own rules.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stop_reason: Option<StopReason>,
}

/// What `rappel query --json` prints: the answers in file order.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct QueryReport {
    /// One answer per pair.
    pub answers: Vec<QueryAnswer>,
}

crate::report::report!(QueryReport, "query");

/// Why a query run could not start.
#[derive(Debug, thiserror::Error)]
pub enum QueryError {
    /// The file was not read: not a regular file, over the input size cap, not text
    /// ([`rappel_terrain::input`]).
    #[error(transparent)]
    Input(#[from] rappel_terrain::input::InputError),
    /// A file could not be read or parsed.
    #[error("{path}: {message}")]
    File {
        /// The file.
        path: String,
        /// What is wrong.
        message: String,
    },
    /// An option is out of range.
    #[error("{0}")]
    Option(String),
}

/// A map file as read, not yet validated: a whole scenario file, or a map-only file (the `map`
/// section's form). [`MapFile::validate`] checks it once and hands out the [`ValidMap`] proof
/// that [`answer`] builds its BTM from.
#[derive(Debug, Clone)]
pub struct MapFile {
    path: std::path::PathBuf,
    contents: MapFileContents,
}

/// What a [`MapFile`] holds.
#[derive(Debug, Clone)]
enum MapFileContents {
    /// A scenario file: validated as a whole (map, start, goal, planes, robot).
    Scenario(Box<Scenario>),
    /// A map-only file: its map validated.
    Map(Map),
}

impl MapFile {
    /// The map (not validated until [`MapFile::validate`]).
    pub fn map(&self) -> &Map {
        match &self.contents {
            MapFileContents::Scenario(s) => &s.map,
            MapFileContents::Map(m) => m,
        }
    }

    /// Validates the file once (a scenario as a whole, a map-only file's map) and returns the
    /// proof that its map is valid, for [`answer`].
    pub fn validate(&self) -> Result<ValidMap<'_>, QueryError> {
        let bad = |message: String| QueryError::File {
            path: self.path.display().to_string(),
            message,
        };
        match &self.contents {
            MapFileContents::Scenario(s) => s
                .validate_at(&self.path)
                .map(|v| v.map())
                .map_err(|e| bad(e.to_string())),
            MapFileContents::Map(m) => m.validate().map_err(|e| bad(e.to_string())),
        }
    }
}

/// Reads the map of a scenario file, or of a map-only file (the `map` section's form), without
/// validating it ([`MapFile::validate`] does, once).
pub fn read_map(path: &Path) -> Result<MapFile, QueryError> {
    let bad = |message: String| QueryError::File {
        path: path.display().to_string(),
        message,
    };
    let contents = match Scenario::read(path) {
        Ok(s) => MapFileContents::Scenario(Box::new(s)),
        Err(scenario_error) => {
            let text = rappel_terrain::input::read_text(path)?;
            let map: Map = match path.extension().and_then(|e| e.to_str()) {
                Some("json") => {
                    serde_json::from_str(&text).map_err(|_| bad(scenario_error.to_string()))?
                }
                _ => ron::from_str(&text).map_err(|_| bad(scenario_error.to_string()))?,
            };
            MapFileContents::Map(map)
        }
    };
    Ok(MapFile {
        path: path.to_path_buf(),
        contents,
    })
}

/// Reads a pairs file (module docs).
pub fn load_pairs(path: &Path) -> Result<Vec<QueryPair>, QueryError> {
    let bad = |message: String| QueryError::File {
        path: path.display().to_string(),
        message,
    };
    let text = rappel_terrain::input::read_text(path)?;
    /// A pair as written, its points as lists of numbers, so that a point of 3 numbers is named
    /// as such (a fixed-size point would report "invalid length").
    #[derive(Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Written {
        start: Vec<f64>,
        goal: Vec<f64>,
    }
    let written: Vec<Written> = serde_json::from_str(&text)
        .map_err(|e| bad(crate::scenario::readable_message(&e.to_string())))?;
    if written.len() > MAX_PAIRS {
        return Err(bad(format!(
            "{} pairs, more than the {MAX_PAIRS} accepted",
            written.len()
        )));
    }
    let point = |i: usize, which: &str, v: &[f64]| match v {
        [x, y] => Ok(Point2::new(*x, *y)),
        _ => Err(bad(format!(
            "pair {i}: the {which} has {} numbers; a point is [x, y]",
            v.len()
        ))),
    };
    written
        .iter()
        .enumerate()
        .map(|(i, w)| {
            Ok(QueryPair {
                start: point(i, "start", &w.start)?,
                goal: point(i, "goal", &w.goal)?,
            })
        })
        .collect()
}

/// Options of a query run: the classes per pair, the repeats of each query, and when to stop.
#[derive(Debug, Clone)]
pub struct QueryOptions {
    /// Classes per pair, from 1 to [`MAX_QUERY_CLASSES`]; 1 answers the shortest path alone.
    pub classes: usize,
    /// Times each query is run (the median time is reported), from 1 to [`MAX_REPEATS`].
    pub repeat: usize,
    /// When to stop ([`rappel_planners::stop`]): the expansion budget bounds each pair's search
    /// (each repeat's); the time limit bounds the whole call (its clock starts at the call unless
    /// the condition was [started](StopCondition::started)); the time limit and cancel flags are
    /// shared by every pair.
    pub stop: StopCondition,
}

impl Default for QueryOptions {
    /// One class, one run, the automatic expansion budget.
    fn default() -> Self {
        QueryOptions {
            classes: 1,
            repeat: 1,
            stop: StopCondition::none(),
        }
    }
}

/// Answers every pair on `map` as `options` say.
///
/// Once the time limit or a cancel request fires, the pair being searched and every later pair
/// are answered with an error naming the condition ("pair 3: the search stopped at the time
/// limit of 0.5 s after ...", "pair 4: not searched: the query stopped at a cancel request");
/// the answers before are kept. A pair that found some of its classes first keeps their lengths,
/// with an error saying it was stopped. A pair whose expansion budget runs out is answered with
/// an error naming the budget.
///
/// ```
/// use nalgebra::Point2;
/// use rappel::query::{answer, QueryOptions, QueryPair};
/// use rappel::geometry::{map::Map, polygon::Polygon};
/// use rappel::planners::stop::{CancelFlag, StopCondition};
/// let p = |x, y| Point2::new(x, y);
/// let map = Map::new(Polygon::rectangle(0.0, 0.0, 10.0, 10.0), vec![]);
/// let pairs = [QueryPair { start: p(1.0, 1.0), goal: p(4.0, 5.0) }, QueryPair { start: p(1.0, 1.0), goal: p(20.0, 5.0) }];
/// let options = QueryOptions { repeat: 3, ..Default::default() };
/// let out = answer(map.validate().unwrap(), &pairs, &options).unwrap();
/// assert!((out[0].lengths_m[0] - 5.0).abs() < 1e-12);
/// assert!(out[1].error.as_ref().unwrap().contains("goal"));
/// // A cancel request stops the pair under way and every later one.
/// let flag = CancelFlag::new();
/// flag.cancel();
/// let stopped = QueryOptions { stop: StopCondition::cancel(flag), ..Default::default() };
/// let out = answer(map.validate().unwrap(), &[pairs[0]; 2], &stopped).unwrap();
/// assert!(out[0].error.as_ref().unwrap().contains("a cancel request"));
/// assert!(out[1].error.as_ref().unwrap().contains("not searched"));
/// ```
pub fn answer(
    map: ValidMap<'_>,
    pairs: &[QueryPair],
    options: &QueryOptions,
) -> Result<Vec<QueryAnswer>, QueryError> {
    answer_observed(map, pairs, options, &Quiet)
}

/// [`answer`], telling `progress` of each pair begun ([`crate::progress`]).
pub fn answer_observed(
    map: ValidMap<'_>,
    pairs: &[QueryPair],
    options: &QueryOptions,
    progress: &dyn Progress,
) -> Result<Vec<QueryAnswer>, QueryError> {
    let (classes, repeat) = (options.classes, options.repeat);
    if !(1..=MAX_QUERY_CLASSES).contains(&classes) {
        return Err(QueryError::Option(format!(
            "--classes {classes}: between 1 and {MAX_QUERY_CLASSES}"
        )));
    }
    if !(1..=MAX_REPEATS).contains(&repeat) {
        return Err(QueryError::Option(format!(
            "--repeat {repeat}: between 1 and {MAX_REPEATS}"
        )));
    }
    // One clock for the whole call.
    let stop = options.stop.started();
    let budget = stop.budget();
    let btm = Btm::build(map).map_err(|e| QueryError::Option(e.to_string()))?;
    let planner = SptPlanner::new(&btm);
    let search = SearchOptions::default()
        .with_max_classes(Some(classes))
        .and_then(|o| o.with_stop(stop.clone()))
        .map_err(|e| QueryError::Option(e.to_string()))?;
    // The time limit or cancel request that stopped an earlier pair.
    let mut stopped: Option<StopReason> = None;
    let mut out = Vec::with_capacity(pairs.len());
    progress.begin("pairs", pairs.len() as u64);
    for (index, pair) in pairs.iter().enumerate() {
        progress.advance(1);
        let mut answer = QueryAnswer {
            index,
            start: pair.start,
            goal: pair.goal,
            lengths_m: Vec::new(),
            median_ns: None,
            error: None,
            stop_reason: None,
        };
        let checked = map
            .validate_point("start", &pair.start)
            .and_then(|()| map.validate_point("goal", &pair.goal));
        if let Err(e) = checked {
            answer.error = Some(format!("pair {index}: {e}"));
            out.push(answer);
            continue;
        }
        if let Some(reason) = stopped.or_else(|| stop.poll()) {
            stopped = Some(reason);
            answer.stop_reason = Some(reason);
            answer.error = Some(format!(
                "pair {index}: not searched: the query stopped at {reason}"
            ));
            out.push(answer);
            continue;
        }
        let mut times = Vec::with_capacity(repeat);
        for _ in 0..repeat {
            let t0 = Instant::now();
            // One class: the path alone (no sleeve, crossings or H-signature to build).
            // A time limit or cancel that stopped the search after some classes.
            let mut partial = None;
            let result = if classes == 1 {
                planner
                    .shortest_taut_path_until(pair.start, pair.goal, &stop)
                    .map(|t| t.map(|t| t.length).into_iter().collect())
            } else {
                planner
                    .search(pair.start, pair.goal, &search)
                    .and_then(|mut s| {
                        let mut lengths = Vec::with_capacity(classes);
                        while let Some(c) = s.next_best()? {
                            lengths.push(c.length());
                        }
                        let expansions = s.stats().expansions;
                        match s.stop_reason() {
                            Some(StopReason::Expansions { .. } | StopReason::Iterations { .. })
                                if lengths.is_empty() =>
                            {
                                Err(SearchError::BudgetExhausted { expansions })
                            }
                            Some(
                                reason @ (StopReason::TimeLimit { .. } | StopReason::Cancelled),
                            ) => {
                                if lengths.is_empty() {
                                    Err(SearchError::Stopped { reason, expansions })
                                } else {
                                    partial = Some((reason, lengths.len()));
                                    Ok(lengths)
                                }
                            }
                            _ => Ok(lengths),
                        }
                    })
            };
            times.push(u64::try_from(t0.elapsed().as_nanos()).unwrap_or(u64::MAX));
            match result {
                Ok(lengths) => {
                    answer.lengths_m = lengths;
                    if let Some((reason, found)) = partial {
                        stopped = Some(reason);
                        answer.stop_reason = Some(reason);
                        answer.error = Some(format!(
                            "pair {index}: the search stopped at {reason} after {found} of the \
                             {classes} classes asked for"
                        ));
                        break;
                    }
                }
                Err(SearchError::BudgetExhausted { .. }) => {
                    let limit = search.expansion_limit(&btm);
                    answer.stop_reason = Some(StopReason::Expansions {
                        limit,
                        budget: budget.kind(),
                    });
                    answer.error = Some(format!(
                        "pair {index}: no path found before the search stopped at {} (this does \
                         not mean start and goal are disconnected)",
                        budget.kind().describe(limit)
                    ));
                    break;
                }
                Err(e) => {
                    if let SearchError::Stopped { reason, .. } = e {
                        stopped = Some(reason);
                        answer.stop_reason = Some(reason);
                    }
                    answer.error = Some(format!("pair {index}: {e}"));
                    break;
                }
            }
        }
        times.sort_unstable();
        answer.median_ns = times.get(times.len() / 2).copied();
        out.push(answer);
    }
    progress.end();
    Ok(out)
}
