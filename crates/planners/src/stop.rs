//! When a long computation stops early: one termination condition shared by every long call (the
//! SPT search, the shortest path map, the sampler, the online simulation), in the spirit of
//! OMPL's `PlannerTerminationCondition`.
//!
//! A [`StopCondition`] combines, with "or" (whichever fires first stops the work):
//! - an **expansion budget** ([`ExpansionBudget`]): a fixed number of expansions, or the
//!   automatic budget scaled to the map ([`ExpansionBudget::Auto`], the default, which is always
//!   in force unless a fixed budget replaces it: it bounds memory);
//! - a **time limit** ([`Duration`]), measured from when the work starts, or from the moment the
//!   condition was [started](StopCondition::started) when the caller wants several pieces of work
//!   (a simulation's searches, say) to share one deadline;
//! - **cancel flags** ([`CancelFlag`]): another thread sets one and the work stops soon after.
//!
//! The work reports which condition fired as a [`StopReason`].
//!
//! # Sharing a flag
//! A [`CancelFlag`] is a cheap [`Clone`] of one shared atomic boolean (an [`Arc`]): clone it into
//! the thread (or signal handler) that cancels and into the condition that watches it; the flag
//! is freed when the last clone goes. A condition holds any number of flags; [`Clone`]ing a
//! condition (or the options that hold it) shares its flags, it does not copy them.
//!
//! # Check cadence and determinism
//! Reading the clock on every expansion would cost more than some expansions. A running check
//! ([`StopWatch`]) compares the expansion count with its limit exactly on every call, and reads
//! the clock and the cancel flags only every [`CHECK_INTERVAL`] expansions (and on the first
//! call, so a flag already set or a zero time limit stops the work before it starts). A search
//! therefore overruns its time limit by at most the time of [`CHECK_INTERVAL`] expansions (well
//! under a millisecond on the crater strips), and stops at most [`CHECK_INTERVAL`] expansions
//! after a cancel; the SPT search also reads them before each class it emits
//! (`StopWatch::poll_now`), since its caller's work per class (feasibility, the path pair) can
//! outweigh the expansions between two classes. Loops whose iterations are expensive (the sampler's edges, the simulation's
//! steps) poll on every iteration ([`StopCondition::poll`]).
//!
//! With an expansion budget alone no clock is read at all, so results are bit-identical to a
//! budget-only search; a time limit or a cancel makes the point where the work stops (not what it
//! computes until then) depend on the machine.
//!
//! ```
//! use std::time::Duration;
//! use rappel_planners::stop::{CancelFlag, StopCondition, StopReason};
//! let flag = CancelFlag::new();
//! let stop = StopCondition::expansions(1_000_000)
//!     .or_time(Duration::from_secs(60))
//!     .or_cancel(flag.clone());
//! let mut watch = stop.watch(stop.expansion_limit(1_000, 1));
//! assert_eq!(watch.check(10), None);
//! // Another thread (here the same one) cancels: seen at the next clock reading.
//! flag.cancel();
//! assert_eq!(watch.check(11 + 1024), Some(StopReason::Cancelled));
//! // The expansion budget is exact.
//! assert!(matches!(watch.check(1_000_000), Some(StopReason::Expansions { limit: 1_000_000, .. })));
//! ```

use std::fmt;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use serde::{Deserialize, Serialize};

use crate::budget::{BudgetKind, ExpansionBudget};

/// Expansions between two readings of the clock and the cancel flags (module docs, "Check
/// cadence").
pub const CHECK_INTERVAL: usize = 1024;

/// A flag another thread sets to stop the work: a [`Clone`]able handle to one shared atomic
/// boolean (module docs, "Sharing a flag").
///
/// ```
/// use rappel_planners::stop::CancelFlag;
/// let flag = CancelFlag::new();
/// let other = flag.clone();
/// std::thread::spawn(move || other.cancel()).join().unwrap();
/// assert!(flag.is_cancelled());
/// flag.reset();
/// assert!(!flag.is_cancelled());
/// ```
#[derive(Debug, Clone)]
pub struct CancelFlag(Arc<AtomicBool>);

impl Default for CancelFlag {
    fn default() -> Self {
        Self::new()
    }
}

impl CancelFlag {
    /// A new flag, not set.
    pub fn new() -> Self {
        CancelFlag(Arc::new(AtomicBool::new(false)))
    }

    /// Sets the flag (from any thread); the work sees it at its next check.
    pub fn cancel(&self) {
        self.0.store(true, Ordering::Release);
    }

    /// Whether the flag is set.
    pub fn is_cancelled(&self) -> bool {
        self.0.load(Ordering::Acquire)
    }

    /// Clears the flag, for the next job.
    pub fn reset(&self) {
        self.0.store(false, Ordering::Release);
    }
}

impl PartialEq for CancelFlag {
    /// The same flag (clones of one another), not merely the same state.
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

impl Eq for CancelFlag {}

/// Which condition stopped the work, with the words a report uses ([`fmt::Display`]).
///
/// ```
/// use std::time::Duration;
/// use rappel_planners::budget::BudgetKind;
/// use rappel_planners::stop::StopReason;
/// let r = StopReason::Expansions { limit: 7, budget: BudgetKind::Fixed };
/// assert_eq!(r.to_string(), BudgetKind::Fixed.describe(7));
/// let t = StopReason::TimeLimit { limit: Duration::from_millis(2500) };
/// assert_eq!(t.to_string(), "the time limit of 2.5 s");
/// assert_eq!(StopReason::Cancelled.to_string(), "a cancel request");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum StopReason {
    /// The expansion budget ran out.
    Expansions {
        /// The expansions allowed.
        limit: usize,
        /// Whether the budget was the automatic one or given.
        budget: BudgetKind,
    },
    /// The iteration limit of an iterative planner (the sampler) ran out.
    Iterations {
        /// The iterations allowed.
        limit: u64,
    },
    /// The time limit ran out.
    TimeLimit {
        /// The time allowed, written in seconds.
        #[serde(rename = "limit_s", with = "secs")]
        #[schemars(with = "f64")]
        limit: Duration,
    },
    /// A [`CancelFlag`] was set.
    Cancelled,
}

impl fmt::Display for StopReason {
    /// The expansion budget as [`BudgetKind::describe`] words it (the limit and how to raise
    /// it); "the iteration limit of N", "the time limit of T s", "a cancel request".
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StopReason::Expansions { limit, budget } => f.write_str(&budget.describe(*limit)),
            StopReason::Iterations { limit } => write!(f, "the iteration limit of {limit}"),
            StopReason::TimeLimit { limit } => {
                write!(f, "the time limit of {} s", limit.as_secs_f64())
            }
            StopReason::Cancelled => f.write_str("a cancel request"),
        }
    }
}

/// A [`Duration`] written as seconds (`f64`).
mod secs {
    use super::*;

    pub fn serialize<S: serde::Serializer>(d: &Duration, s: S) -> Result<S::Ok, S::Error> {
        d.as_secs_f64().serialize(s)
    }

    pub fn deserialize<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Duration, D::Error> {
        let v = f64::deserialize(d)?;
        Duration::try_from_secs_f64(v).map_err(serde::de::Error::custom)
    }
}

/// An optional [`Duration`] written as seconds.
mod option_secs {
    use super::*;

    pub fn serialize<S: serde::Serializer>(d: &Option<Duration>, s: S) -> Result<S::Ok, S::Error> {
        d.map(|d| d.as_secs_f64()).serialize(s)
    }

    pub fn deserialize<'de, D: serde::Deserializer<'de>>(
        d: D,
    ) -> Result<Option<Duration>, D::Error> {
        Option::<f64>::deserialize(d)?
            .map(|v| Duration::try_from_secs_f64(v).map_err(serde::de::Error::custom))
            .transpose()
    }
}

/// When to stop a long computation (module docs): an expansion budget, a time limit, cancel
/// flags, combined with "or". The default ([`StopCondition::none`]) is the automatic expansion
/// budget alone.
///
/// Serialized as its expansion budget (`max_expansions`) and time limit (`time_limit_s`); cancel
/// flags and a started clock are not serialized.
///
/// ```
/// use std::time::Duration;
/// use rappel_planners::budget::ExpansionBudget;
/// use rappel_planners::stop::{CancelFlag, StopCondition};
/// let none = StopCondition::none();
/// assert_eq!(none.budget(), ExpansionBudget::Auto);
/// assert_eq!(none.time_limit(), None);
/// // Combinations keep the tighter of two limits of a kind.
/// let s = StopCondition::time(Duration::from_secs(5))
///     .or_time(Duration::from_secs(2))
///     .or_expansions(300)
///     .or_expansions(500)
///     .or_cancel(CancelFlag::new());
/// assert_eq!(s.time_limit(), Some(Duration::from_secs(2)));
/// assert_eq!(s.budget(), ExpansionBudget::Fixed(300));
/// assert_eq!(s.cancel_flags().count(), 1);
/// ```
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct StopCondition {
    #[serde(rename = "max_expansions")]
    budget: ExpansionBudget,
    #[serde(
        rename = "time_limit_s",
        default,
        skip_serializing_if = "Option::is_none",
        with = "option_secs"
    )]
    time_limit: Option<Duration>,
    #[serde(skip)]
    cancel: Vec<CancelFlag>,
    /// When the time limit runs out, once [started](StopCondition::started).
    #[serde(skip)]
    deadline: Option<Instant>,
}

impl StopCondition {
    /// The automatic expansion budget alone (what every long call did before time limits and
    /// cancel flags).
    pub fn none() -> Self {
        Self::default()
    }

    /// At most `n` expansions (replacing the automatic budget).
    pub fn expansions(n: usize) -> Self {
        Self::budget_of(ExpansionBudget::Fixed(n))
    }

    /// The expansions bounded as `budget` says.
    pub fn budget_of(budget: ExpansionBudget) -> Self {
        Self {
            budget,
            ..Self::default()
        }
    }

    /// The automatic expansion budget, or the time limit `t`.
    pub fn time(t: Duration) -> Self {
        Self::none().or_time(t)
    }

    /// The automatic expansion budget, or `flag`.
    pub fn cancel(flag: CancelFlag) -> Self {
        Self::none().or_cancel(flag)
    }

    /// The same condition with its expansion budget replaced by `budget`.
    pub fn with_budget(mut self, budget: ExpansionBudget) -> Self {
        self.budget = budget;
        self
    }

    /// Also stop after `n` expansions: a fixed budget replaces the automatic one; of two fixed
    /// budgets the smaller holds.
    pub fn or_expansions(self, n: usize) -> Self {
        self.or_budget(ExpansionBudget::Fixed(n))
    }

    /// Also bound the expansions as `budget` says ([`StopCondition::or_expansions`] for a fixed
    /// budget; the automatic budget changes nothing).
    pub fn or_budget(mut self, budget: ExpansionBudget) -> Self {
        self.budget = match (self.budget, budget) {
            (ExpansionBudget::Fixed(a), ExpansionBudget::Fixed(b)) => {
                ExpansionBudget::Fixed(a.min(b))
            }
            (ExpansionBudget::Fixed(a), ExpansionBudget::Auto)
            | (ExpansionBudget::Auto, ExpansionBudget::Fixed(a)) => ExpansionBudget::Fixed(a),
            (ExpansionBudget::Auto, ExpansionBudget::Auto) => ExpansionBudget::Auto,
        };
        self
    }

    /// Also stop after wall-clock time `t` (of two limits the shorter holds).
    pub fn or_time(mut self, t: Duration) -> Self {
        self.time_limit = Some(self.time_limit.map_or(t, |u| u.min(t)));
        self
    }

    /// Also stop once `flag` is set (a flag the condition already holds is not added twice).
    pub fn or_cancel(mut self, flag: CancelFlag) -> Self {
        if !self.cancel.contains(&flag) {
            self.cancel.push(flag);
        }
        self
    }

    /// Stop when either condition fires (each kind combined as by the `or_` methods; of two
    /// started clocks the earlier deadline holds).
    pub fn or(mut self, other: StopCondition) -> Self {
        self = self.or_budget(other.budget);
        if let Some(t) = other.time_limit {
            self = self.or_time(t);
        }
        for flag in other.cancel {
            self = self.or_cancel(flag);
        }
        self.deadline = match (self.deadline, other.deadline) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        };
        self
    }

    /// The expansion budget.
    pub fn budget(&self) -> ExpansionBudget {
        self.budget
    }

    /// The time limit, if any.
    pub fn time_limit(&self) -> Option<Duration> {
        self.time_limit
    }

    /// The cancel flags.
    pub fn cancel_flags(&self) -> impl Iterator<Item = &CancelFlag> + '_ {
        self.cancel.iter()
    }

    /// When the time limit runs out, once started ([`StopCondition::started`]).
    pub fn deadline(&self) -> Option<Instant> {
        self.deadline
    }

    /// The expansions allowed on a map of `triangles` BTM triangles asked for `classes`
    /// classes ([`ExpansionBudget::limit`]).
    pub fn expansion_limit(&self, triangles: usize, classes: usize) -> usize {
        self.budget.limit(triangles, classes)
    }

    /// This condition with its clock started now (unchanged when already started or without a
    /// time limit): pass it to several pieces of work so that they share one deadline instead
    /// of each counting the time limit from its own start.
    pub fn started(&self) -> Self {
        let mut s = self.clone();
        if s.deadline.is_none() {
            s.deadline = s.time_limit.and_then(|t| Instant::now().checked_add(t));
        }
        s
    }

    /// Whether a cancel flag is set or a started clock ran out, now (the check of loops whose
    /// iterations are expensive; the expansion budget is the loop's own to count). A clock not
    /// [started](StopCondition::started) is not read.
    pub fn poll(&self) -> Option<StopReason> {
        poll(&self.cancel, self.deadline, self.time_limit)
    }

    /// Starts the check of one piece of work allowed `expansion_limit` expansions (usually
    /// [`StopCondition::expansion_limit`]); its clock starts now unless the condition was
    /// started before.
    pub fn watch(&self, expansion_limit: usize) -> StopWatch {
        let started = self.started();
        let polls = started.deadline.is_some() || !started.cancel.is_empty();
        StopWatch {
            limit: expansion_limit,
            budget: self.budget.kind(),
            time_limit: started.time_limit,
            deadline: started.deadline,
            cancel: started.cancel,
            next_poll: if polls { 0 } else { usize::MAX },
        }
    }
}

fn poll(
    cancel: &[CancelFlag],
    deadline: Option<Instant>,
    time_limit: Option<Duration>,
) -> Option<StopReason> {
    if cancel.iter().any(CancelFlag::is_cancelled) {
        return Some(StopReason::Cancelled);
    }
    match (deadline, time_limit) {
        (Some(d), Some(limit)) if Instant::now() >= d => Some(StopReason::TimeLimit { limit }),
        _ => None,
    }
}

/// The running check of one piece of work ([`StopCondition::watch`]): the expansion count
/// exactly, the clock and the cancel flags every [`CHECK_INTERVAL`] expansions (module docs).
#[derive(Debug, Clone)]
pub struct StopWatch {
    limit: usize,
    budget: BudgetKind,
    time_limit: Option<Duration>,
    deadline: Option<Instant>,
    cancel: Vec<CancelFlag>,
    /// The expansion count at which the clock and flags are read next (`usize::MAX`: never,
    /// nothing to read).
    next_poll: usize,
}

impl StopWatch {
    /// Why to stop after `expansions` expansions, if so: the expansion budget first (exact),
    /// then a cancel flag, then the time limit (both read every [`CHECK_INTERVAL`] expansions).
    #[inline]
    pub fn check(&mut self, expansions: usize) -> Option<StopReason> {
        if expansions >= self.limit {
            return Some(StopReason::Expansions {
                limit: self.limit,
                budget: self.budget,
            });
        }
        if expansions >= self.next_poll {
            self.next_poll = expansions.saturating_add(CHECK_INTERVAL);
            return poll(&self.cancel, self.deadline, self.time_limit);
        }
        None
    }

    /// The expansions allowed.
    pub fn limit(&self) -> usize {
        self.limit
    }

    /// Whether a cancel flag is set or the clock ran out, read now whatever the cadence.
    pub fn poll_now(&self) -> Option<StopReason> {
        poll(&self.cancel, self.deadline, self.time_limit)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn expansions_alone_never_poll() {
        let mut w = StopCondition::expansions(5).watch(5);
        assert_eq!(w.next_poll, usize::MAX);
        for e in 0..5 {
            assert_eq!(w.check(e), None);
        }
        assert_eq!(
            w.check(5),
            Some(StopReason::Expansions {
                limit: 5,
                budget: BudgetKind::Fixed
            })
        );
    }

    #[test]
    fn a_zero_time_limit_stops_at_the_first_check_and_cadence_holds() {
        let mut w = StopCondition::time(Duration::ZERO).watch(usize::MAX);
        assert_eq!(
            w.check(0),
            Some(StopReason::TimeLimit {
                limit: Duration::ZERO
            })
        );
        // Not read again before CHECK_INTERVAL more expansions.
        assert_eq!(w.check(1), None);
        assert_eq!(w.check(CHECK_INTERVAL - 1), None);
        assert!(w.check(CHECK_INTERVAL).is_some());
    }

    #[test]
    fn cancel_wins_over_time_and_budget_over_both() {
        let flag = CancelFlag::new();
        flag.cancel();
        let s = StopCondition::expansions(3)
            .or_time(Duration::ZERO)
            .or_cancel(flag.clone());
        let mut w = s.watch(3);
        assert_eq!(w.check(0), Some(StopReason::Cancelled));
        assert!(matches!(w.check(3), Some(StopReason::Expansions { .. })));
    }

    #[test]
    fn any_number_of_flags_and_each_is_seen() {
        let flags: Vec<CancelFlag> = (0..10).map(|_| CancelFlag::new()).collect();
        let s = flags
            .iter()
            .fold(StopCondition::none(), |s, f| s.or_cancel(f.clone()))
            .or_cancel(flags[3].clone());
        assert_eq!(s.cancel_flags().count(), 10);
        assert_eq!(s.poll(), None);
        flags[9].cancel();
        assert_eq!(s.poll(), Some(StopReason::Cancelled));
        // A clone of the condition shares the flags.
        let c = s.clone();
        flags[9].reset();
        assert_eq!(c.poll(), None);
        drop(s);
        flags[0].cancel();
        assert_eq!(c.watch(10).check(0), Some(StopReason::Cancelled));
    }

    #[test]
    fn a_started_clock_is_shared() {
        let s = StopCondition::time(Duration::from_millis(30)).started();
        let d = s.deadline();
        assert!(d.is_some());
        std::thread::sleep(Duration::from_millis(5));
        assert_eq!(s.started().deadline(), d);
        assert_eq!(s.watch(10).deadline, d);
        // Not started: poll does not read a clock.
        assert_eq!(StopCondition::time(Duration::ZERO).poll(), None);
        assert!(
            StopCondition::time(Duration::ZERO)
                .started()
                .poll()
                .is_some()
        );
    }

    #[test]
    fn serde_writes_budget_and_seconds() {
        let s = StopCondition::expansions(9)
            .or_time(Duration::from_millis(1500))
            .or_cancel(CancelFlag::new());
        let json = serde_json::to_string(&s).unwrap();
        assert_eq!(json, r#"{"max_expansions":{"fixed":9},"time_limit_s":1.5}"#);
        let back: StopCondition = serde_json::from_str(&json).unwrap();
        assert_eq!(
            back,
            StopCondition::expansions(9).or_time(Duration::from_millis(1500))
        );
        let r = StopReason::TimeLimit {
            limit: Duration::from_millis(250),
        };
        let json = serde_json::to_string(&r).unwrap();
        assert_eq!(json, r#"{"kind":"time_limit","limit_s":0.25}"#);
        assert_eq!(serde_json::from_str::<StopReason>(&json).unwrap(), r);
        assert_eq!(
            serde_json::to_string(&StopReason::Cancelled).unwrap(),
            r#"{"kind":"cancelled"}"#
        );
    }
}
