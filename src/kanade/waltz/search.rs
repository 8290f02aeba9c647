//! What bounds the labeller's search: a node budget whose cost per node does not grow with the
//! drawing, and a time budget (docs/limits.md "Labeller").
//!
//! Each independent group of undecided junctions is searched as its own small problem
//! ([`Csp::restrict`]: its junctions numbered from 0, the lines to decided junctions outside
//! folded into the allowed labels), so a search node copies and scans the group, never the
//! drawing. A group of at most [`DECOMPOSE_MAX`] junctions is searched with the splitting into
//! independent parts that makes counts multiply (`GroupSearch`), at a cost per node bounded
//! by that size; a larger group is searched depth first with an undo trail ([`search_plain`]),
//! at a cost per node of the junctions its propagation touches.

use super::{Csp, Mask, Progress, SearchStats};
use std::collections::HashMap;
use std::time::{Duration, Instant};

/// Largest group searched with splitting into independent parts; larger groups are searched
/// depth first without it (their count then grows one labelling at a time, so the budget
/// usually makes it a lower bound).
pub(super) const DECOMPOSE_MAX: usize = 256;

/// The deadline is read once per this many nodes or revisions (reading the clock costs about
/// as much as a node).
const CLOCK_EVERY: u64 = 1 << 10;

/// Search nodes and time spent, against their budgets; the progress callback every 2^14
/// nodes.
pub(super) struct Meter<'a> {
    pub(super) stats: &'a mut SearchStats,
    pub(super) progress: &'a mut dyn FnMut(Progress),
    node_budget: u64,
    time_budget_s: f64,
    deadline: Instant,
    /// The group being searched and how many there are (for progress and the reason).
    pub(super) group: usize,
    pub(super) groups: usize,
    /// Why the search stopped early, once a budget ran out.
    pub(super) ran_out: Option<String>,
}

impl<'a> Meter<'a> {
    pub(super) fn new(
        stats: &'a mut SearchStats,
        progress: &'a mut dyn FnMut(Progress),
        node_budget: u64,
        time_budget_s: f64,
    ) -> Meter<'a> {
        let budget = Duration::try_from_secs_f64(time_budget_s.max(0.0)).unwrap_or(Duration::MAX);
        let now = Instant::now();
        Meter {
            stats,
            progress,
            node_budget,
            time_budget_s,
            deadline: now
                .checked_add(budget)
                .unwrap_or(now + Duration::from_secs(1 << 40)),
            group: 0,
            groups: 0,
            ran_out: None,
        }
    }

    /// Counts one search node; false when a budget is spent.
    pub(super) fn step(&mut self) -> bool {
        if self.ran_out.is_some() {
            return false;
        }
        if self.stats.nodes >= self.node_budget {
            self.ran_out = Some(format!(
                "the node budget of {} ran out in group {} of {}",
                self.node_budget,
                self.group + 1,
                self.groups
            ));
            return false;
        }
        self.stats.nodes += 1;
        if self.stats.nodes % (1 << 14) == 0 {
            (self.progress)(Progress {
                nodes: self.stats.nodes,
                group: self.group,
                groups: self.groups,
            });
        }
        self.stats.nodes % CLOCK_EVERY != 0 || self.in_time()
    }

    /// Counts one revision; false when the time is spent (checked every [`CLOCK_EVERY`]).
    fn revision(&mut self) -> bool {
        self.stats.revisions += 1;
        self.ran_out.is_none() && (self.stats.revisions % CLOCK_EVERY != 0 || self.in_time())
    }

    fn in_time(&mut self) -> bool {
        if Instant::now() < self.deadline {
            return true;
        }
        self.ran_out = Some(format!(
            "the time budget of {} s ran out in group {} of {}",
            self.time_budget_s,
            self.group + 1,
            self.groups
        ));
        false
    }
}

impl Csp {
    /// The problem of one group of undecided junctions: `members` numbered 0.. in order, their
    /// lines numbered 0.. as met, and each line to a junction outside the group (decided, as
    /// the groups are split by decided junctions) allowing only the label that junction gives
    /// it. Costs time in proportion to the group, not the drawing.
    pub(super) fn restrict(&self, dom: &[Mask], members: &[usize]) -> Csp {
        let local: HashMap<usize, usize> =
            members.iter().enumerate().map(|(i, v)| (*v, i)).collect();
        let mut line_ids: HashMap<usize, usize> = HashMap::new();
        let mut allowed = Vec::new();
        let mut ends = Vec::with_capacity(members.len());
        for &v in members {
            let mut list = Vec::with_capacity(self.ends[v].len());
            for &(line, other) in &self.ends[v] {
                let id = *line_ids.entry(line).or_insert_with(|| {
                    allowed.push(self.allowed[line]);
                    allowed.len() - 1
                });
                let other = other.and_then(|(w, k)| match local.get(&w) {
                    Some(&lw) => Some((lw, k)),
                    None => {
                        allowed[id].0 &= self.support(dom, w, k).0;
                        None
                    }
                });
                list.push((id, other));
            }
            ends.push(list);
        }
        Csp {
            site: members.iter().map(|v| self.site[*v]).collect(),
            cand: members.iter().map(|v| self.cand[*v].clone()).collect(),
            ends,
            allowed,
            unary: members.iter().map(|v| dom[*v]).collect(),
        }
    }
}

/// Depth-first search of a whole group (`csp` restricted to it, its domains `csp.unary`)
/// with one domain vector and an undo trail, junctions in index order: the solutions listed
/// (with `stop_after`, the search stops at that many; without, it lists none and counts all)
/// and the number found before the search ended.
pub(super) fn search_plain(
    csp: &Csp,
    stop_after: Option<usize>,
    meter: &mut Meter,
) -> (Vec<Vec<Mask>>, u128) {
    let n = csp.unary.len();
    let mut state = Trail {
        dom: csp.unary.clone(),
        trail: Vec::new(),
        queued: vec![false; n],
        queue: Vec::new(),
    };
    let (mut listed, mut count) = (Vec::new(), 0u128);
    // Frames: (junction, labellings not yet tried, trail length before trying one).
    let mut frames: Vec<(usize, Mask, usize)> = Vec::new();
    let mut next = 0;
    'descend: loop {
        while next < n && state.dom[next].count_ones() == 1 {
            next += 1;
        }
        if next == n {
            count = count.saturating_add(1);
            if let Some(stop) = stop_after {
                listed.push(state.dom.clone());
                if listed.len() >= stop {
                    break;
                }
            }
        } else {
            frames.push((next, state.dom[next], state.trail.len()));
        }
        while let Some((v, untried, mark)) = frames.last_mut() {
            state.undo(*mark);
            if *untried == 0 {
                frames.pop();
                continue;
            }
            let e = untried.trailing_zeros() as usize;
            *untried &= !(1 << e);
            let v = *v;
            if !meter.step() {
                break 'descend;
            }
            match state.assign(csp, v, e, meter) {
                Some(true) => {
                    next = v + 1;
                    continue 'descend;
                }
                Some(false) => meter.stats.backtracks += 1,
                None => break 'descend,
            }
        }
        break;
    }
    (listed, count)
}

/// One domain vector changed in place, with the old values to restore.
struct Trail {
    dom: Vec<Mask>,
    trail: Vec<(usize, Mask)>,
    queued: Vec<bool>,
    queue: Vec<usize>,
}

impl Trail {
    fn set(&mut self, v: usize, m: Mask) {
        self.trail.push((v, self.dom[v]));
        self.dom[v] = m;
    }

    fn undo(&mut self, mark: usize) {
        while self.trail.len() > mark {
            let (v, m) = self.trail.pop().expect("longer than mark");
            self.dom[v] = m;
        }
    }

    /// Tries labelling `e` at `v` and filters from its neighbours: `Some(false)` on a dead
    /// end, `None` when the time ran out.
    fn assign(&mut self, csp: &Csp, v: usize, e: usize, meter: &mut Meter) -> Option<bool> {
        self.set(v, 1 << e);
        self.push_neighbours(csp, v);
        let mut alive = true;
        while let Some(w) = self.queue.pop() {
            self.queued[w] = false;
            if !alive {
                continue;
            }
            if !meter.revision() {
                alive = false;
                continue;
            }
            let m = csp.revised(&self.dom, w);
            if m != self.dom[w] {
                self.set(w, m);
                if m == 0 {
                    alive = false;
                    continue;
                }
                self.push_neighbours(csp, w);
            }
        }
        if meter.ran_out.is_some() {
            return None;
        }
        Some(alive)
    }

    fn push_neighbours(&mut self, csp: &Csp, v: usize) {
        for (w, _) in csp.ends[v].iter().filter_map(|(_, o)| *o) {
            if !self.queued[w] {
                self.queued[w] = true;
                self.queue.push(w);
            }
        }
    }
}

/// Junction domains held by the keys of one group's count cache, at most (32 bytes each): the
/// cache stays under about 64 MB whatever the group's size.
pub(super) const CACHE_KEY_ENTRIES: usize = (64 << 20) / 32;
