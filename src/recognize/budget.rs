//! What bounds the recognizer's search (docs/limits.md "Recognizer"): a node budget and a time
//! budget, spent by the hypothesize-and-test search of step 4 ([`super::compare`]) and its
//! repair ([`super::repair`]). A node is one candidate weighed: ranked by its corners
//! ([`super::compare::corner_gain`]) or redrawn and compared (step 6). Weighing a candidate
//! costs time in proportion to the observed points, so it spends `1 + P / 64` nodes, `P` the
//! observed points of all views ([`node_cost`]): the node budget then bounds the work on a
//! large drawing as on a small one, the same on every machine. The first budget spent
//! stops the search, and the recognizer declines with the reason ([`Decline::SearchBudget`]):
//! a hypothesis cut short is no answer.

use super::answer::Decline;
use std::cell::Cell;
use std::time::{Duration, Instant};

/// The clock is read once per this many nodes (a node costs far more than reading it, but the
/// cheapest nodes, corner rankings, cost little more).
const CLOCK_EVERY: u64 = 16;

/// Progress is reported once per this many nodes.
const PROGRESS_EVERY: u64 = 1 << 10;

/// The nodes one candidate weighed spends when the views hold `points` observed points
/// (module doc).
pub fn node_cost(points: usize) -> u64 {
    1 + points as u64 / 64
}

/// How far the search has gone, for a progress report.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SearchProgress {
    /// Nodes spent so far.
    pub nodes: u64,
    /// The node budget.
    pub node_budget: u64,
    /// Seconds since the search started.
    pub elapsed_s: f64,
    /// The time budget, s.
    pub time_budget_s: f64,
}

/// The search's budgets and what it has spent of them (interior mutability: the search passes
/// it by shared reference inside its limits).
pub struct SearchBudget<'a> {
    node_budget: u64,
    time_budget_s: f64,
    started: Instant,
    deadline: Instant,
    node_cost: u64,
    nodes: Cell<u64>,
    ran_out: Cell<Option<(u64, f64)>>,
    progress: &'a dyn Fn(SearchProgress),
}

impl std::fmt::Debug for SearchBudget<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SearchBudget")
            .field("node_budget", &self.node_budget)
            .field("time_budget_s", &self.time_budget_s)
            .field("nodes", &self.nodes.get())
            .finish()
    }
}

impl<'a> SearchBudget<'a> {
    /// A budget of `node_budget` nodes and `time_budget_s` seconds from now (a negative or NaN
    /// time is none; an infinite one never runs out) for weighing candidates at `node_cost`
    /// nodes each ([`node_cost`]), reporting to `progress` about every 1,024 nodes.
    pub fn new(
        (node_budget, time_budget_s): (u64, f64),
        node_cost: u64,
        progress: &'a dyn Fn(SearchProgress),
    ) -> SearchBudget<'a> {
        let budget = Duration::try_from_secs_f64(time_budget_s.max(0.0)).unwrap_or(Duration::MAX);
        let started = Instant::now();
        SearchBudget {
            node_budget,
            time_budget_s,
            started,
            deadline: started
                .checked_add(budget)
                .unwrap_or(started + Duration::from_secs(1 << 40)),
            node_cost: node_cost.max(1),
            nodes: Cell::new(0),
            ran_out: Cell::new(None),
            progress,
        }
    }

    /// Spends the nodes of one candidate weighed; `false` once a budget is spent (and ever
    /// after). The clock is read about every [`CLOCK_EVERY`] candidates.
    pub fn spend(&self) -> bool {
        if self.ran_out.get().is_some() {
            return false;
        }
        let (n, cost) = (self.nodes.get(), self.node_cost);
        let late = (n / cost) % CLOCK_EVERY == 0 && Instant::now() >= self.deadline;
        if n.saturating_add(cost) > self.node_budget || late {
            self.ran_out.set(Some((n, self.elapsed_s())));
            return false;
        }
        self.nodes.set(n + cost);
        if n / PROGRESS_EVERY != (n + cost) / PROGRESS_EVERY {
            (self.progress)(self.progress_now());
        }
        true
    }

    /// `true` once a budget is spent.
    pub fn spent(&self) -> bool {
        self.ran_out.get().is_some()
    }

    /// Nodes spent so far.
    pub fn nodes(&self) -> u64 {
        self.nodes.get()
    }

    /// Why to decline, once a budget is spent.
    pub(super) fn decline(&self) -> Option<Decline> {
        let (nodes, elapsed_s) = self.ran_out.get()?;
        let which = if nodes.saturating_add(self.node_cost) > self.node_budget {
            "the node budget"
        } else {
            "the time budget"
        };
        Some(Decline::SearchBudget {
            node_budget: self.node_budget,
            time_budget_s: self.time_budget_s,
            detail: format!(
                "{which} ran out after {nodes} nodes and {elapsed_s:.1} s, before any hypothesis explained every view"
            ),
        })
    }

    fn elapsed_s(&self) -> f64 {
        self.started.elapsed().as_secs_f64()
    }

    fn progress_now(&self) -> SearchProgress {
        SearchProgress {
            nodes: self.nodes.get(),
            node_budget: self.node_budget,
            elapsed_s: self.elapsed_s(),
            time_budget_s: self.time_budget_s,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_node_budget_stops_the_search_and_names_itself() {
        let budget = SearchBudget::new((3, f64::INFINITY), 1, &|_| {});
        assert!((0..3).all(|_| budget.spend()));
        assert!(budget.decline().is_none());
        assert!(!budget.spend());
        assert!(budget.spent() && !budget.spend(), "spent stays spent");
        let reason = budget.decline().unwrap().to_string();
        assert!(
            reason.starts_with(
                "search budget of 3 nodes / inf s spent: the node budget ran out after 3 nodes"
            ),
            "{reason}"
        );
    }

    #[test]
    fn the_time_budget_stops_the_search_at_its_first_clock_reading() {
        let budget = SearchBudget::new((u64::MAX, 0.0), 1, &|_| {});
        assert!(!budget.spend());
        let reason = budget.decline().unwrap().to_string();
        assert!(
            reason.contains("the time budget ran out after 0 nodes"),
            "{reason}"
        );
        let reports = Cell::new(0);
        let count = |_: SearchProgress| reports.set(reports.get() + 1);
        let budget = SearchBudget::new((u64::MAX, f64::NAN), 1, &count);
        assert!(!budget.spend(), "a NaN time budget is none");
        let budget = SearchBudget::new((2 * PROGRESS_EVERY, 60.0), 1, &count);
        assert!((0..2 * PROGRESS_EVERY).all(|_| budget.spend()));
        assert_eq!(reports.get(), 2);
    }

    #[test]
    fn a_larger_drawing_spends_more_nodes_per_candidate() {
        assert_eq!((node_cost(0), node_cost(63), node_cost(640)), (1, 1, 11));
        let budget = SearchBudget::new((25, f64::INFINITY), node_cost(640), &|_| {});
        assert!(budget.spend() && budget.spend() && !budget.spend());
        assert_eq!(budget.nodes(), 22);
        let reason = budget.decline().unwrap().to_string();
        assert!(
            reason.contains("the node budget ran out after 22 nodes"),
            "{reason}"
        );
    }
}
