//! The search over the junctions that filtering left undecided: they fall into independent
//! groups (no line joins two groups), each searched on its own ([`search`] bounds it), the
//! count the product of the groups' counts and the listed labellings their product in odometer
//! order.

use super::search;
use super::{bits, Csp, LabelOptions, LabellingCount, Mask, Progress, SearchStats};

/// Groups of undecided variables among `candidates` joined by lines between undecided
/// variables (breadth-first search).
fn groups(csp: &Csp, dom: &[Mask], candidates: &[usize]) -> Vec<Vec<usize>> {
    let mut state = vec![0u8; dom.len()]; // 1 = candidate, 2 = placed
    for &v in candidates {
        if dom[v].count_ones() > 1 {
            state[v] = 1;
        }
    }
    let mut out = Vec::new();
    for &start in candidates {
        if state[start] != 1 {
            continue;
        }
        state[start] = 2;
        let mut members = vec![start];
        let mut i = 0;
        while i < members.len() {
            let v = members[i];
            i += 1;
            for (w, _) in csp.ends[v].iter().filter_map(|(_, o)| *o) {
                if state[w] == 1 {
                    state[w] = 2;
                    members.push(w);
                }
            }
        }
        members.sort_unstable();
        out.push(members);
    }
    out
}

/// The search state of one group of at most [`search::DECOMPOSE_MAX`] junctions.
struct GroupSearch<'a, 'm> {
    csp: &'a Csp,
    meter: &'a mut search::Meter<'m>,
    /// Counts of groups already met, by their members' domains (a group's count depends on
    /// nothing else: its neighbours outside are decided and filtered).
    cache: std::collections::HashMap<Vec<(usize, Mask)>, u128>,
    /// Domains held by the cache's keys.
    cache_key_entries: usize,
}

impl GroupSearch<'_, '_> {
    /// Counts one search node; false when a budget is spent.
    fn step(&mut self) -> bool {
        self.meter.step()
    }

    /// The domains after trying labelling `e` at `v` and propagating; `None` on a dead end.
    fn try_value(&mut self, dom: &[Mask], v: usize, e: usize) -> Option<Vec<Mask>> {
        let mut d2 = dom.to_vec();
        d2[v] = 1 << e;
        // Filter from v's neighbours: v itself lost labellings, so they may lose theirs.
        let queue: Vec<usize> = self.csp.ends[v]
            .iter()
            .filter_map(|(_, o)| o.map(|o| o.0))
            .collect();
        if self
            .csp
            .propagate(&mut d2, queue, &mut self.meter.stats.revisions)
        {
            Some(d2)
        } else {
            self.meter.stats.backtracks += 1;
            None
        }
    }

    fn pick(dom: &[Mask], members: &[usize]) -> Option<usize> {
        members
            .iter()
            .copied()
            .filter(|v| dom[*v].count_ones() > 1)
            .min_by_key(|v| (dom[*v].count_ones(), *v))
    }

    /// PAIP's `search-solutions` with the same decomposition as [`Self::count`]: up to `limit`
    /// full domain vectors in which every member is decided. Independent groups are solved
    /// apart, so one group without a solution ends the search at once.
    fn solutions(&mut self, dom: &[Mask], members: &[usize], limit: usize) -> Vec<Vec<Mask>> {
        let gs = groups(self.csp, dom, members);
        match gs.len() {
            0 => vec![dom.to_vec()],
            1 => {
                let Some(v) = Self::pick(dom, &gs[0]) else {
                    return vec![dom.to_vec()];
                };
                let mut out = Vec::new();
                for e in bits(dom[v]) {
                    if out.len() >= limit || !self.step() {
                        break;
                    }
                    if let Some(d2) = self.try_value(dom, v, e) {
                        let more = self.solutions(&d2, &gs[0], limit - out.len());
                        out.extend(more);
                    }
                }
                out
            }
            _ => {
                let mut per: Vec<Vec<Vec<Mask>>> = Vec::new();
                for g in &gs {
                    let sols = self.solutions(dom, g, limit);
                    if sols.is_empty() {
                        return Vec::new();
                    }
                    per.push(sols);
                }
                combine(dom, &gs, &per, limit)
            }
        }
    }

    /// The number of solutions of `members`: once the undecided ones fall apart into groups no
    /// line joins, the product of the groups' counts (so independent ambiguities multiply
    /// instead of being enumerated).
    fn count(&mut self, dom: &[Mask], members: &[usize]) -> u128 {
        let gs = groups(self.csp, dom, members);
        match gs.len() {
            0 => 1,
            1 => {
                let Some(v) = Self::pick(dom, &gs[0]) else {
                    return 1;
                };
                let key: Vec<(usize, Mask)> = gs[0].iter().map(|m| (*m, dom[*m])).collect();
                if let Some(n) = self.cache.get(&key) {
                    return *n;
                }
                let mut total = 0u128;
                for e in bits(dom[v]) {
                    if !self.step() {
                        return total;
                    }
                    if let Some(d2) = self.try_value(dom, v, e) {
                        total = total.saturating_add(self.count(&d2, &gs[0]));
                    }
                }
                let fits = self.cache_key_entries + key.len() <= search::CACHE_KEY_ENTRIES;
                if self.meter.ran_out.is_none() && fits {
                    self.cache_key_entries += key.len();
                    self.cache.insert(key, total);
                }
                total
            }
            _ => gs
                .iter()
                .fold(1u128, |acc, g| acc.saturating_mul(self.count(dom, g))),
        }
    }
}

/// All consistent labellings after filtering: each group searched on its own (as its own
/// problem, `search`), the count the product of the groups' counts, the first `limit`
/// solutions listed in odometer order. Every group's first solutions are found before any
/// group is counted, so when a budget runs out while counting, the groups not counted still
/// add the solutions found (the count stays a true lower bound instead of dropping to 0).
pub(super) fn enumerate(
    csp: &Csp,
    dom: &[Mask],
    opts: &LabelOptions,
    stats: &mut SearchStats,
    progress: &mut dyn FnMut(Progress),
) -> (Vec<Vec<Mask>>, LabellingCount) {
    let all: Vec<usize> = (0..dom.len()).collect();
    let gs = groups(csp, dom, &all);
    stats.groups = gs.len();
    let mut meter = search::Meter::new(stats, progress, opts.node_budget, opts.time_budget_s);
    meter.groups = gs.len();
    let limit = opts.limit.max(1);
    let mut listed = Vec::with_capacity(gs.len());
    for (g, members) in gs.iter().enumerate() {
        meter.group = g;
        let local = csp.restrict(dom, members);
        let sols = search_group(&local, Some(limit + 1), &mut meter).0;
        listed.push((local, sols));
    }
    let mut value = 1u128;
    for (g, (local, sols)) in listed.iter().enumerate() {
        meter.group = g;
        let found = if sols.len() > limit && meter.ran_out.is_none() {
            search_group(local, None, &mut meter)
                .1
                .max(sols.len() as u128)
        } else {
            sols.len() as u128
        };
        value = value.saturating_mul(found);
    }
    let mut count = LabellingCount {
        value,
        exact: meter.ran_out.is_none(),
        reason: meter.ran_out.take(),
    };
    if count.value == u128::MAX && count.exact {
        count.exact = false;
        count.reason = Some("the count exceeds 2^128".into());
    }
    let per_group: Vec<Vec<Vec<Mask>>> = listed
        .into_iter()
        .map(|(_, mut sols)| {
            sols.truncate(limit);
            sols
        })
        .collect();
    (combine(dom, &gs, &per_group, opts.limit), count)
}

/// One group (`local`: restricted to it, its domains `local.unary`): its solutions in member
/// order (at most `stop_after`, else as many as the search listed) and its count (a lower
/// bound when the meter ran out).
fn search_group(
    local: &Csp,
    stop_after: Option<usize>,
    meter: &mut search::Meter,
) -> (Vec<Vec<Mask>>, u128) {
    if local.unary.len() > search::DECOMPOSE_MAX {
        return search::search_plain(local, stop_after, meter);
    }
    let members: Vec<usize> = (0..local.unary.len()).collect();
    let mut s = GroupSearch {
        csp: local,
        meter,
        cache: std::collections::HashMap::new(),
        cache_key_entries: 0,
    };
    match stop_after {
        Some(n) => {
            let sols = s.solutions(&local.unary, &members, n);
            let found = sols.len() as u128;
            (sols, found)
        }
        None => (Vec::new(), s.count(&local.unary, &members)),
    }
}

/// The first `limit` full solutions of the product of the groups' solutions.
fn combine(
    dom: &[Mask],
    gs: &[Vec<usize>],
    per_group: &[Vec<Vec<Mask>>],
    limit: usize,
) -> Vec<Vec<Mask>> {
    if per_group.iter().any(|p| p.is_empty()) {
        return Vec::new();
    }
    let mut out = Vec::new();
    let mut idx = vec![0usize; gs.len()];
    while out.len() < limit {
        let mut s = dom.to_vec();
        for (g, members) in gs.iter().enumerate() {
            let sol = &per_group[g][idx[g]];
            for (k, v) in members.iter().enumerate() {
                s[*v] = if sol.len() == dom.len() {
                    sol[*v]
                } else {
                    sol[k]
                };
            }
        }
        out.push(s);
        // odometer, last group fastest
        let mut g = gs.len();
        loop {
            if g == 0 {
                return out;
            }
            g -= 1;
            idx[g] += 1;
            if idx[g] < per_group[g].len() {
                break;
            }
            idx[g] = 0;
        }
    }
    out
}
