//! The SPT search's stop reason as reports spell it (`docs/output-format.md`):
//! [`TerminationName`], the snake_case names of [`Termination`], readable back and with a JSON
//! Schema. The search keeps its own enum; reports convert at the boundary. (The counters,
//! [`crate::spt::SearchStats`], are written as they are.)

use crate::spt::Termination;
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

    /// The counters are written as the search keeps them: `swept_at` only when the order
    /// switched, every field read back; the fields added since the first reports default when
    /// an older report lacks them.
    #[test]
    fn search_counters_write_swept_at_only_when_set_and_read_back() {
        use crate::spt::SearchStats;
        let mut s = SearchStats {
            expansions: 7,
            tree_nodes: 9,
            ..SearchStats::default()
        };
        let text = serde_json::to_string(&s).unwrap();
        assert!(!text.contains("swept_at"), "{text}");
        assert_eq!(serde_json::from_str::<SearchStats>(&text).unwrap(), s);
        s.swept_at = Some(5);
        let text = serde_json::to_string(&s).unwrap();
        assert!(text.contains("\"swept_at\":5"), "{text}");
        assert_eq!(serde_json::from_str::<SearchStats>(&text).unwrap(), s);
        let old = r#"{"expansions":1,"pruned_dominated":0,"pruned_length":0,"pruned_simple":0,
            "skipped_not_simple":0,"tree_nodes":2,"queue_peak":3,"peak_bytes":4}"#;
        let read: SearchStats = serde_json::from_str(old).unwrap();
        assert_eq!(
            (read.expansions, read.swept_at, read.bound_expansions),
            (1, None, 0)
        );
    }
}
