//! Waltz filtering (arc consistency, Waltz 1975; PAIP ch. 17 `propagate-constraints`) and a
//! backtracking search that enumerates every consistent labelling (PAIP's `search-solutions`),
//! with the statistics the thesis's comparison needs (Chapter VI, Figure 6.18).
//!
//! The variables are the junctions whose class is in the catalog; a variable's domain is the
//! set of catalog labellings still possible, a 64-bit mask. Two junctions joined by a line
//! must give it the same label ("two junction labels match if and only if the line segment
//! which joins the junctions gets the same interpretation from both", Chapter III). Junctions
//! outside the catalog constrain nothing and are reported. After filtering, the undecided
//! junctions fall into independent groups (no line joins two groups), each searched on its
//! own, and the number of labellings is the product of the groups' counts.

use super::catalog::Catalog;
use super::graph::{junction_sites, regions, validate, JunctionSite};
use super::label::{LabelSet, LineLabel};
use super::KanadeError;
use crate::drawing::{Junction, LineDrawing};
use serde::Serialize;

mod groups;
mod search;

use groups::enumerate;

/// The most lines [`label_drawing`] takes (docs/limits.md "Labeller"): every step before the
/// search costs time and memory in proportion to the lines (100,000 random lines label in
/// about a second), and a drawing beyond this is refused before any of it.
pub const MAX_LABEL_LINES: usize = 100_000;

/// How to label (`blockworld label` flags).
#[derive(Debug, Clone, PartialEq)]
pub struct LabelOptions {
    /// The junction catalog; default Huffman-Clowes.
    pub catalog: Catalog,
    /// Appendix A step 2: every line on the outer boundary of the drawing is occluding, with
    /// its arrow clockwise around the object. Default off.
    pub boundary_occluding: bool,
    /// PAIP's `ground`: `[a, b]` keeps only junction `a`'s labellings that make the line from
    /// point `a` to point `b` concave (`-`), a block resting on the ground.
    pub ground: Vec<[usize; 2]>,
    /// Appendix A step 3 before the search: a line between two surfaces whose gradients the
    /// heuristics give may only take labels those gradients fit (under either Necker reading).
    /// Default off.
    pub gradient_check: bool,
    /// At most this many labellings are listed (the count goes on); default 100.
    pub limit: usize,
    /// The search stops after this many nodes and reports its count as a lower bound; default
    /// 5,000,000 (about a second in a release build). A node costs time in proportion to its
    /// group of junctions (at most 256 when the group is split into independent parts), never
    /// to the drawing.
    pub node_budget: u64,
    /// The search stops after this many seconds and reports its count as a lower bound;
    /// default 10.
    pub time_budget_s: f64,
}

impl Default for LabelOptions {
    fn default() -> Self {
        LabelOptions {
            catalog: Catalog::HuffmanClowes,
            boundary_occluding: false,
            gradient_check: false,
            ground: Vec::new(),
            limit: 100,
            node_budget: 5_000_000,
            time_budget_s: 10.0,
        }
    }
}

/// A number of combinations that may exceed `u128`: exact when it fits, always as log10.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Combinations {
    /// The exact product, when it fits in 128 bits (in JSON a string above `u64::MAX`).
    #[serde(serialize_with = "serialize_optional_count")]
    pub exact: Option<u128>,
    /// log10 of the product (`-inf` for zero).
    pub log10: f64,
}

impl Combinations {
    fn product(factors: impl Iterator<Item = u32>) -> Combinations {
        let mut exact = Some(1u128);
        let mut log10 = 0.0;
        for f in factors {
            exact = exact.and_then(|x| x.checked_mul(u128::from(f)));
            log10 += f64::from(f).log10();
        }
        Combinations { exact, log10 }
    }
}

/// Search statistics (PAIP ch. 17 prints the first two as "For 29,160 interpretations").
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SearchStats {
    /// Product of the catalog domain sizes before filtering (after fixed lines).
    pub combinations_before: Combinations,
    /// Product of the domain sizes after Waltz filtering.
    pub combinations_after: Combinations,
    /// Domain revisions done by filtering, initial and during search.
    pub revisions: u64,
    /// Search nodes: labellings tried at a junction.
    pub nodes: u64,
    /// Dead ends: a tried labelling whose propagation emptied a domain.
    pub backtracks: u64,
    /// Independent groups of undecided junctions after filtering.
    pub groups: usize,
}

/// How many consistent labellings there are.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LabellingCount {
    /// The count (saturating at `u128::MAX`); a lower bound when `exact` is false. In JSON a
    /// number up to `u64::MAX` and a decimal string above it (JSON numbers stop there).
    #[serde(serialize_with = "serialize_count")]
    pub value: u128,
    /// Whether `value` is the exact count.
    pub exact: bool,
    /// Why the count is a lower bound, when it is.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
}

/// A count as a JSON number when it fits in `u64` (serde_json's largest integer), else as its
/// decimal string: five separate cubes already have more labellings than `u64` holds.
fn serialize_count<S: serde::Serializer>(n: &u128, s: S) -> Result<S::Ok, S::Error> {
    match u64::try_from(*n) {
        Ok(small) => s.serialize_u64(small),
        Err(_) => s.serialize_str(&n.to_string()),
    }
}

/// [`serialize_count`] of an optional count (`null` when absent).
fn serialize_optional_count<S: serde::Serializer>(
    n: &Option<u128>,
    s: S,
) -> Result<S::Ok, S::Error> {
    match n {
        Some(n) => serialize_count(n, s),
        None => s.serialize_none(),
    }
}

/// Progress of a long search, passed to the caller's callback every 2^14 nodes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Progress {
    /// Nodes so far.
    pub nodes: u64,
    /// The group being searched, and how many there are.
    pub group: usize,
    /// Number of groups.
    pub groups: usize,
}

/// One junction as the report shows it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JunctionReport {
    /// Point index.
    pub point: usize,
    /// Junction class from geometry.
    pub junction: Junction,
    /// Lines in canonical order.
    pub lines: Vec<usize>,
    /// Catalog labellings before and after filtering (`None` when not in the catalog).
    pub domain_before: Option<u32>,
    /// Catalog labellings left after filtering.
    pub domain_after: Option<u32>,
}

/// The result of labelling a drawing.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LabelReport {
    /// The catalog used.
    pub catalog: Catalog,
    /// Every point's junction.
    pub junctions: Vec<JunctionReport>,
    /// Points whose junction class the catalog lacks (they constrain nothing).
    pub uncatalogued: Vec<usize>,
    /// Lines with no catalogued junction at either end (labelled `?` unless fixed).
    pub free_lines: Vec<usize>,
    /// Listed labellings, at most `limit`; each gives every line's label (`None` = free).
    pub labellings: Vec<Vec<Option<LineLabel>>>,
    /// How many labellings are consistent.
    pub count: LabellingCount,
    /// Search statistics.
    pub stats: SearchStats,
}

/// The variable and end position at a line's other end, when that junction is catalogued.
type Neighbour = Option<(usize, usize)>;

/// The constraint problem: catalogued junctions as variables.
struct Csp {
    /// Per variable: its site index.
    site: Vec<usize>,
    /// Per variable, per catalog labelling, the whole-line label of each end.
    cand: Vec<Vec<Vec<LineLabel>>>,
    /// Per variable, per end: (line, the variable and end position at the line's other end).
    ends: Vec<Vec<(usize, Neighbour)>>,
    /// Per line: labels allowed by the boundary constraint.
    allowed: Vec<LabelSet>,
    /// Per variable: labellings allowed by `ground` (a mask).
    unary: Vec<Mask>,
}

/// A domain: bit `k` set while catalog labelling `k` is possible.
type Mask = u128;

/// Most labellings a junction class may have (the bits of [`Mask`]); a larger class would
/// count as outside the catalog.
const MAX_DOMAIN: usize = Mask::BITS as usize;

fn full_mask(n: usize) -> Mask {
    if n >= MAX_DOMAIN {
        Mask::MAX
    } else {
        (1 << n) - 1
    }
}

/// The set bits of `mask`, lowest first.
fn bits(mask: Mask) -> impl Iterator<Item = usize> {
    let mut rest = mask;
    std::iter::from_fn(move || {
        if rest == 0 {
            return None;
        }
        let i = rest.trailing_zeros() as usize;
        rest &= rest - 1;
        Some(i)
    })
}

impl Csp {
    fn build(d: &LineDrawing, sites: &[JunctionSite], catalog: Catalog) -> Csp {
        let mut var_of = vec![None; sites.len()];
        let mut site = Vec::new();
        let mut cand = Vec::new();
        for s in sites {
            let rows = catalog.labellings(s.junction, s.ends.len());
            if rows.is_empty() || rows.len() > MAX_DOMAIN {
                continue;
            }
            var_of[s.point] = Some(site.len());
            site.push(s.point);
            cand.push(
                rows.iter()
                    .map(|r| {
                        r.iter()
                            .zip(&s.ends)
                            .map(|(l, e)| l.to_line_label(e.at_start))
                            .collect()
                    })
                    .collect(),
            );
        }
        let pos_at = |point: usize, line: usize| -> Option<(usize, usize)> {
            let v = var_of[point]?;
            let k = sites[point].ends.iter().position(|e| e.line == line)?;
            Some((v, k))
        };
        let ends = site
            .iter()
            .map(|&p| {
                sites[p]
                    .ends
                    .iter()
                    .map(|e| {
                        let [a, b] = d.lines[e.line];
                        let other = if e.at_start { b } else { a };
                        (e.line, pos_at(other, e.line))
                    })
                    .collect()
            })
            .collect();
        let unary = cand
            .iter()
            .map(|c: &Vec<Vec<LineLabel>>| full_mask(c.len()))
            .collect();
        Csp {
            site,
            cand,
            ends,
            allowed: vec![LabelSet::ANY; d.lines.len()],
            unary,
        }
    }

    /// Labels that variable `v`'s live labellings give its end `k`.
    fn support(&self, dom: &[Mask], v: usize, k: usize) -> LabelSet {
        let mut s = LabelSet::default();
        for e in bits(dom[v]) {
            s.insert(self.cand[v][e][k]);
        }
        s
    }

    /// Removes `v`'s labellings that a neighbour or an allowed set cannot match.
    fn revise(&self, dom: &mut [Mask], v: usize) -> bool {
        let before = dom[v];
        dom[v] = self.revised(dom, v);
        dom[v] != before
    }

    /// `v`'s labellings that its neighbours and the allowed sets can match.
    fn revised(&self, dom: &[Mask], v: usize) -> Mask {
        let supports: Vec<LabelSet> = self.ends[v]
            .iter()
            .map(|(line, other)| match other {
                Some((w, k)) => LabelSet(self.support(dom, *w, *k).0 & self.allowed[*line].0),
                None => self.allowed[*line],
            })
            .collect();
        let mut m = dom[v];
        for e in bits(m) {
            let ok = self.cand[v][e]
                .iter()
                .zip(&supports)
                .all(|(l, s)| s.contains(*l));
            if !ok {
                m &= !(1 << e);
            }
        }
        m
    }

    /// Arc consistency from the variables in `queue` (AC-3); false when a domain empties.
    fn propagate(&self, dom: &mut [Mask], mut queue: Vec<usize>, revisions: &mut u64) -> bool {
        let mut queued = vec![false; dom.len()];
        for &v in &queue {
            queued[v] = true;
        }
        while let Some(v) = queue.pop() {
            queued[v] = false;
            *revisions += 1;
            if self.revise(dom, v) {
                if dom[v] == 0 {
                    return false;
                }
                for (_, other) in &self.ends[v] {
                    if let Some((w, _)) = other {
                        if !queued[*w] {
                            queued[*w] = true;
                            queue.push(*w);
                        }
                    }
                }
            }
        }
        true
    }
}

/// The catalog domains with `ground` and the boundary constraint applied, before filtering.
fn initial_domains(csp: &Csp) -> Vec<Mask> {
    (0..csp.cand.len())
        .map(|v| {
            let mut m = csp.unary[v];
            for e in bits(m) {
                let ok = csp.cand[v][e]
                    .iter()
                    .zip(&csp.ends[v])
                    .all(|(l, (line, _))| csp.allowed[*line].contains(*l));
                if !ok {
                    m &= !(1 << e);
                }
            }
            m
        })
        .collect()
}

/// Appendix A steps 2 and 3 and PAIP's `ground`, as constraints on `csp`.
fn apply_line_constraints(
    d: &LineDrawing,
    sites: &[JunctionSite],
    opts: &LabelOptions,
    csp: &mut Csp,
) -> Result<(), KanadeError> {
    if opts.boundary_occluding {
        for r in regions(d).iter().filter(|r| r.is_outside()) {
            for e in &r.walk {
                // The outside is on the left of this walk, so the face is on its right.
                let l = LineLabel::occluding(e.at_start);
                csp.allowed[e.line].0 &= LabelSet::only(l).0;
            }
        }
    }
    if opts.gradient_check {
        if let Some(sets) = super::gradient::gradient_label_sets(d) {
            for (allowed, set) in csp.allowed.iter_mut().zip(sets) {
                allowed.0 &= set.0;
            }
        }
    }
    for &[a, b] in &opts.ground {
        let site = sites.get(a).ok_or(KanadeError::NoSuchLine { a, b })?;
        let k = site
            .ends
            .iter()
            .position(|e| {
                let [p, q] = d.lines[e.line];
                (p == a && q == b) || (p == b && q == a)
            })
            .ok_or(KanadeError::NoSuchLine { a, b })?;
        let Some(v) = csp.site.iter().position(|&p| p == a) else {
            continue;
        };
        for e in bits(csp.unary[v]) {
            if csp.cand[v][e][k] != LineLabel::Concave {
                csp.unary[v] &= !(1 << e);
            }
        }
    }
    Ok(())
}

/// Labels `d` (thesis Chapter III's first step; Appendix A steps 1 and 2, and step 3's search,
/// with its gradient check when `opts.gradient_check`): filtering, then all consistent
/// labellings. `progress` is called
/// every 2^14 search nodes. Errors only on a drawing of more than [`MAX_LABEL_LINES`] lines, a
/// broken drawing (bad indices, a line from a point to itself, a non-finite coordinate) or a
/// `ground` pair that is not a line.
pub fn label_drawing(
    d: &LineDrawing,
    opts: &LabelOptions,
    progress: &mut dyn FnMut(Progress),
) -> Result<LabelReport, KanadeError> {
    if d.lines.len() > MAX_LABEL_LINES {
        return Err(KanadeError::TooManyLines {
            lines: d.lines.len(),
            max: MAX_LABEL_LINES,
        });
    }
    validate(d)?;
    let sites = junction_sites(d);
    let mut csp = Csp::build(d, &sites, opts.catalog);
    apply_line_constraints(d, &sites, opts, &mut csp)?;
    let mut dom = initial_domains(&csp);
    let initial = dom.clone();
    let mut stats = SearchStats {
        combinations_before: Combinations::product(dom.iter().map(|m| m.count_ones())),
        combinations_after: Combinations::product(std::iter::empty()),
        revisions: 0,
        nodes: 0,
        backtracks: 0,
        groups: 0,
    };
    let all: Vec<usize> = (0..dom.len()).rev().collect();
    let consistent =
        dom.iter().all(|m| *m != 0) && csp.propagate(&mut dom, all, &mut stats.revisions);
    if !consistent {
        dom.iter_mut().for_each(|m| *m = 0);
    }
    stats.combinations_after = Combinations::product(dom.iter().map(|m| m.count_ones()));
    let (solutions, count) = if consistent {
        enumerate(&csp, &dom, opts, &mut stats, progress)
    } else {
        (
            Vec::new(),
            LabellingCount {
                value: 0,
                exact: true,
                reason: None,
            },
        )
    };
    let labellings = solutions.iter().map(|s| line_labels(d, &csp, s)).collect();
    Ok(LabelReport {
        catalog: opts.catalog,
        junctions: junction_reports(&sites, &csp, &initial, &dom),
        uncatalogued: uncatalogued(&sites, &csp),
        free_lines: free_lines(d, &csp),
        labellings,
        count,
        stats,
    })
}

/// Each point's variable, when its junction is catalogued (indexed once: looking a point up
/// in `csp.site` for every point would cost time in the square of the drawing).
fn variables_of_points(sites: &[JunctionSite], csp: &Csp) -> Vec<Option<usize>> {
    let mut var_of = vec![None; sites.len()];
    for (v, &p) in csp.site.iter().enumerate() {
        var_of[p] = Some(v);
    }
    var_of
}

fn junction_reports(
    sites: &[JunctionSite],
    csp: &Csp,
    initial: &[Mask],
    dom: &[Mask],
) -> Vec<JunctionReport> {
    let var_of = variables_of_points(sites, csp);
    sites
        .iter()
        .map(|s| {
            let v = var_of[s.point];
            JunctionReport {
                point: s.point,
                junction: s.junction,
                lines: s.ends.iter().map(|e| e.line).collect(),
                domain_before: v.map(|v| initial[v].count_ones()),
                domain_after: v.map(|v| dom[v].count_ones()),
            }
        })
        .collect()
}

fn uncatalogued(sites: &[JunctionSite], csp: &Csp) -> Vec<usize> {
    let var_of = variables_of_points(sites, csp);
    sites
        .iter()
        .filter(|s| !s.ends.is_empty() && var_of[s.point].is_none())
        .map(|s| s.point)
        .collect()
}

fn free_lines(d: &LineDrawing, csp: &Csp) -> Vec<usize> {
    let mut constrained = vec![false; d.lines.len()];
    for ends in &csp.ends {
        for (line, _) in ends {
            constrained[*line] = true;
        }
    }
    (0..d.lines.len()).filter(|l| !constrained[*l]).collect()
}

/// Every line's label under one solution (one live labelling per variable).
fn line_labels(d: &LineDrawing, csp: &Csp, solution: &[Mask]) -> Vec<Option<LineLabel>> {
    let mut out: Vec<Option<LineLabel>> = csp
        .allowed
        .iter()
        .map(|s| {
            LineLabel::ALL
                .into_iter()
                .find(|l| *s == LabelSet::only(*l))
        })
        .collect();
    out.truncate(d.lines.len());
    for (v, m) in solution.iter().enumerate() {
        if let Some(e) = bits(*m).next() {
            for (k, (line, _)) in csp.ends[v].iter().enumerate() {
                out[*line] = Some(csp.cand[v][e][k]);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests;
