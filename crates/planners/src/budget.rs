//! Expansion budgets that follow the map: the bound on funnel expansions of an SPT search
//! ([`crate::spt`]) or a shortest path map ([`crate::shortest_path_map`]), either fixed by the
//! caller or scaled to the map's triangles and the classes asked for, under a hard cap that bounds
//! memory.
//!
//! # The automatic budget
//! On the generated crater strips the first class costs about 15 funnel expansions per BTM
//! triangle (16.5 M on the 1.1 M triangles of the 100,000-obstacle strip, seed 1), and `K` classes
//! with dominance pruning cost about `K` times that (82.6 M for 5 classes there). The automatic
//! budget is [`AUTO_EXPANSIONS_PER_TRIANGLE`] per triangle per class (twice that measure), at
//! least [`AUTO_MIN_EXPANSIONS`] and at most [`AUTO_MAX_EXPANSIONS`]. Search state is about 60
//! bytes per expansion on the strips (5.0 GB of resident memory for the 82.6 M expansions above,
//! the map included) and at most about 130 (module docs of [`crate::shortest_path_map`]), so the
//! cap bounds a search near 6 GB, 13 GB at worst. A budget that runs out is reported as such,
//! naming the limit and how to raise it ([`BudgetKind::describe`]).

use serde::{Deserialize, Serialize};

/// Expansions per BTM triangle per class of the automatic budget (module docs).
pub const AUTO_EXPANSIONS_PER_TRIANGLE: usize = 32;
/// Smallest automatic budget: small maps get the fixed budget the searches always had.
pub const AUTO_MIN_EXPANSIONS: usize = 1_000_000;
/// Largest automatic budget: the hard memory bound (module docs). A fixed budget may exceed it.
pub const AUTO_MAX_EXPANSIONS: usize = 100_000_000;

/// How a search's expansions are bounded.
///
/// ```
/// use rappel_planners::budget::{AUTO_MAX_EXPANSIONS, AUTO_MIN_EXPANSIONS, ExpansionBudget};
/// assert_eq!(ExpansionBudget::Auto.limit(1_000, 5), AUTO_MIN_EXPANSIONS);
/// assert_eq!(ExpansionBudget::Auto.limit(100_000, 5), 16_000_000);
/// assert_eq!(ExpansionBudget::Auto.limit(10_000_000, 5), AUTO_MAX_EXPANSIONS);
/// assert_eq!(ExpansionBudget::Fixed(7).limit(10_000_000, 5), 7);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ExpansionBudget {
    /// Scaled to the map and the classes (module docs).
    #[default]
    Auto,
    /// At most this many expansions (at least 1).
    Fixed(usize),
}

impl ExpansionBudget {
    /// The number of expansions allowed on a map of `triangles` BTM triangles asked for
    /// `classes` classes (at least 1 of each is assumed).
    pub fn limit(&self, triangles: usize, classes: usize) -> usize {
        match *self {
            ExpansionBudget::Fixed(n) => n,
            ExpansionBudget::Auto => AUTO_EXPANSIONS_PER_TRIANGLE
                .saturating_mul(triangles.max(1))
                .saturating_mul(classes.max(1))
                .clamp(AUTO_MIN_EXPANSIONS, AUTO_MAX_EXPANSIONS),
        }
    }

    /// The kind of this budget, for reports.
    pub fn kind(&self) -> BudgetKind {
        match self {
            ExpansionBudget::Auto => BudgetKind::Auto,
            ExpansionBudget::Fixed(_) => BudgetKind::Fixed,
        }
    }

    /// Parses a command-line value: `auto`, or a positive number of expansions.
    ///
    /// ```
    /// use rappel_planners::budget::ExpansionBudget;
    /// assert_eq!(ExpansionBudget::parse("auto"), Ok(ExpansionBudget::Auto));
    /// assert_eq!(ExpansionBudget::parse("2500"), Ok(ExpansionBudget::Fixed(2500)));
    /// assert!(ExpansionBudget::parse("0").is_err());
    /// assert!(ExpansionBudget::parse("lots").is_err());
    /// ```
    pub fn parse(s: &str) -> Result<ExpansionBudget, String> {
        if s == "auto" {
            return Ok(ExpansionBudget::Auto);
        }
        match s.parse::<usize>() {
            Ok(n) if n >= 1 => Ok(ExpansionBudget::Fixed(n)),
            _ => Err(format!(
                "'{s}' is not a budget: give 'auto' or a number of expansions of at least 1"
            )),
        }
    }
}

/// Which kind of budget stopped a search, with the words a report uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum BudgetKind {
    /// The automatic budget of the map.
    Auto,
    /// A budget the caller fixed.
    Fixed,
}

impl BudgetKind {
    /// What the limit of `limit` expansions was and how to raise it.
    ///
    /// ```
    /// use rappel_planners::budget::BudgetKind;
    /// assert!(BudgetKind::Auto.describe(16_000_000).contains("--max-expansions"));
    /// ```
    pub fn describe(&self, limit: usize) -> String {
        match self {
            BudgetKind::Auto => format!(
                "the automatic budget of {limit} expansions ({AUTO_EXPANSIONS_PER_TRIANGLE} per \
                 BTM triangle per class, at least {AUTO_MIN_EXPANSIONS} and at most \
                 {AUTO_MAX_EXPANSIONS}, a memory bound of about 60-130 bytes each); raise it with \
                 --max-expansions N"
            ),
            BudgetKind::Fixed => {
                format!("the given budget of {limit} expansions; raise --max-expansions")
            }
        }
    }
}
