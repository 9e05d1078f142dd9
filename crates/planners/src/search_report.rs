//! The SPT search's outcome as reports spell it (`docs/output-format.md`): [`TerminationName`]
//! (snake_case names of [`Termination`]) and [`SearchStatsReport`] (the counters of
//! [`SearchStats`]), both readable back and with JSON Schemas. The search itself keeps its own
//! types; reports convert at the boundary.

use crate::spt::{SearchStats, Termination};
use serde::{Deserialize, Serialize};

/// Why a search stopped, as a report spells it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum TerminationName {
    /// [`Termination::ClassCount`].
    ClassCount,
    /// [`Termination::LengthFactor`].
    LengthFactor,
    /// [`Termination::Expansions`].
    Expansions,
    /// [`Termination::TimeLimit`].
    TimeLimit,
    /// [`Termination::Cancelled`].
    Cancelled,
    /// [`Termination::Exhausted`].
    Exhausted,
    /// [`Termination::Disconnected`].
    Disconnected,
}

impl From<Termination> for TerminationName {
    fn from(t: Termination) -> Self {
        match t {
            Termination::ClassCount => TerminationName::ClassCount,
            Termination::LengthFactor => TerminationName::LengthFactor,
            Termination::Expansions => TerminationName::Expansions,
            Termination::TimeLimit => TerminationName::TimeLimit,
            Termination::Cancelled => TerminationName::Cancelled,
            Termination::Exhausted => TerminationName::Exhausted,
            Termination::Disconnected => TerminationName::Disconnected,
        }
    }
}

impl From<TerminationName> for Termination {
    fn from(t: TerminationName) -> Self {
        match t {
            TerminationName::ClassCount => Termination::ClassCount,
            TerminationName::LengthFactor => Termination::LengthFactor,
            TerminationName::Expansions => Termination::Expansions,
            TerminationName::TimeLimit => Termination::TimeLimit,
            TerminationName::Cancelled => Termination::Cancelled,
            TerminationName::Exhausted => Termination::Exhausted,
            TerminationName::Disconnected => Termination::Disconnected,
        }
    }
}

/// `#[serde(with = "crate::search_report::termination_serde")]` on a [`Termination`] field:
/// written and read as its [`TerminationName`].
pub mod termination_serde {
    use super::*;

    /// Writes `t` as its snake_case name.
    pub fn serialize<S: serde::Serializer>(t: &Termination, s: S) -> Result<S::Ok, S::Error> {
        TerminationName::from(*t).serialize(s)
    }

    /// Reads a snake_case name.
    pub fn deserialize<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Termination, D::Error> {
        TerminationName::deserialize(d).map(Termination::from)
    }
}

/// `#[serde(with = "crate::search_report::option_termination_serde")]` on an
/// `Option<Termination>` field.
pub mod option_termination_serde {
    use super::*;

    /// Writes the snake_case name, or `null`.
    pub fn serialize<S: serde::Serializer>(
        t: &Option<Termination>,
        s: S,
    ) -> Result<S::Ok, S::Error> {
        t.map(TerminationName::from).serialize(s)
    }

    /// Reads a snake_case name or `null`.
    pub fn deserialize<'de, D: serde::Deserializer<'de>>(
        d: D,
    ) -> Result<Option<Termination>, D::Error> {
        Option::<TerminationName>::deserialize(d).map(|t| t.map(Termination::from))
    }
}

/// The counters of a search ([`SearchStats`]) in a report.
#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema,
)]
pub struct SearchStatsReport {
    /// Funnels expanded (Alg. 4 calls).
    pub expansions: usize,
    /// Funnels dropped by dominance pruning.
    pub pruned_dominated: usize,
    /// Funnels dropped because their mouth is covered (one class wanted).
    #[serde(default)]
    pub pruned_covered: usize,
    /// Funnels dropped by the length bound.
    pub pruned_length: usize,
    /// Funnels never queued because enough queued goals are at least as short.
    #[serde(default)]
    pub pruned_incumbent: usize,
    /// Funnels dropped because their apex chain is not simple (simple-classes mode).
    pub pruned_simple: usize,
    /// Goal lifts reached whose class was not simple (simple-classes mode).
    pub skipped_not_simple: usize,
    /// Nodes held in the shortest path tree at the end (after any collection of it).
    pub tree_nodes: usize,
    /// Split nodes removed because both children were dropped.
    #[serde(default)]
    pub nodes_discarded: usize,
    /// Nodes dropped by collections of the tree (no queued funnel held them).
    #[serde(default)]
    pub nodes_collected: usize,
    /// Largest number of queued entries.
    pub queue_peak: usize,
    /// The expansions made when the one-class search's automatic order switched to one band
    /// (a single sweep by the reach bound); absent when it did not.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub swept_at: Option<usize>,
    /// The expansions the search was allowed (the automatic budget of the map, or the given one;
    /// `rappel_planners::budget`).
    #[serde(default)]
    pub expansion_limit: usize,
    /// Expansions of the reverse search that bounded the distances to the goal before a
    /// several-class search (not in `expansions`).
    #[serde(default)]
    pub bound_expansions: usize,
    /// Peak bytes held by the search's own structures.
    pub peak_bytes: usize,
}

impl From<SearchStats> for SearchStatsReport {
    fn from(s: SearchStats) -> Self {
        SearchStatsReport {
            expansions: s.expansions,
            pruned_dominated: s.pruned_dominated,
            pruned_covered: s.pruned_covered,
            pruned_length: s.pruned_length,
            pruned_incumbent: s.pruned_incumbent,
            pruned_simple: s.pruned_simple,
            skipped_not_simple: s.skipped_not_simple,
            tree_nodes: s.tree_nodes,
            nodes_discarded: s.nodes_discarded,
            nodes_collected: s.nodes_collected,
            queue_peak: s.queue_peak,
            swept_at: s.swept_at,
            expansion_limit: s.expansion_limit,
            bound_expansions: s.bound_expansions,
            peak_bytes: s.peak_bytes,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_termination_has_a_snake_case_name_that_reads_back() {
        for t in [
            Termination::ClassCount,
            Termination::LengthFactor,
            Termination::Expansions,
            Termination::TimeLimit,
            Termination::Cancelled,
            Termination::Exhausted,
            Termination::Disconnected,
        ] {
            let text = serde_json::to_string(&TerminationName::from(t)).unwrap();
            assert!(text.chars().all(|c| !c.is_ascii_uppercase()), "{text}");
            let back: TerminationName = serde_json::from_str(&text).unwrap();
            assert_eq!(Termination::from(back), t);
        }
        assert_eq!(
            serde_json::to_string(&TerminationName::ClassCount).unwrap(),
            "\"class_count\""
        );
    }
}
