//! `blockworld label DRAWING.json [--json] [--boundary-occluding] [--catalog C] [--limit N]`:
//! Kanade's line labelling (thesis Chapter III step 1, Appendix A; Waltz 1975, PAIP ch. 17) of
//! any line drawing: `lines_<view>.json`, the `vertices` output of the vision stage, or a
//! hand-made `{"points": [[x, y], ...], "lines": [[i, j], ...]}` (px, x right, y up), read and
//! checked by `LineDrawing::from_json`; the labeller also refuses zero-length lines.

use anyhow::Context;
use blockworld::drawing::LineDrawing;
use blockworld::kanade::{label_drawing, Catalog, LabelOptions, LabelReport, LineLabel};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Options of `blockworld label`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The line drawing (JSON with `points` and `lines`; other fields ignored), at most
    /// 100000 lines.
    pub drawing: PathBuf,
    /// Print the report as JSON instead of text.
    #[arg(long)]
    pub json: bool,
    /// Appendix A step 2: the outer boundary is occluding, its arrows clockwise.
    #[arg(long)]
    pub boundary_occluding: bool,
    /// Appendix A step 3: lines between surfaces take only the labels their gradients fit.
    #[arg(long)]
    pub gradient_check: bool,
    /// Junction catalog: `huffman-clowes` (PAIP's 18 trihedral labellings) or `blocks`.
    #[arg(long, default_value = "huffman-clowes", value_parser = parse_catalog)]
    pub catalog: Catalog,
    /// List at most this many labellings (the count goes on).
    #[arg(long, default_value_t = 10)]
    pub limit: usize,
    /// Stop the search after this many nodes and report the count as a lower bound (a node
    /// costs time in proportion to its group of junctions, never to the drawing).
    #[arg(long, default_value_t = LabelOptions::default().node_budget)]
    pub node_budget: u64,
    /// Stop the search after this many seconds (more than 0, at most 1000000) and report the
    /// count as a lower bound.
    #[arg(long, default_value_t = LabelOptions::default().time_budget_s)]
    pub time_budget_s: f64,
}

fn parse_catalog(s: &str) -> Result<Catalog, String> {
    Catalog::parse(s).ok_or_else(|| format!("unknown catalog {s:?}; use huffman-clowes or blocks"))
}

/// Runs `blockworld label`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let d = read_points_and_lines(&args.drawing)?;
    let budget_s = args.time_budget_s;
    let takes = "use a positive number of seconds, at most 1000000";
    let ok = budget_s > 0.0 && budget_s <= 1e6;
    crate::cli::check_number("--time-budget-s", budget_s, ok, takes)?;
    let opts = LabelOptions {
        catalog: args.catalog,
        boundary_occluding: args.boundary_occluding,
        gradient_check: args.gradient_check,
        limit: args.limit,
        node_budget: args.node_budget,
        time_budget_s: args.time_budget_s,
        ..Default::default()
    };
    let start = Instant::now();
    let mut last = Instant::now();
    let report = label_drawing(&d, &opts, &mut |p| {
        if last.elapsed().as_secs_f64() >= 1.0 {
            eprintln!(
                "label: {} nodes, group {} of {}",
                p.nodes,
                p.group + 1,
                p.groups
            );
            last = Instant::now();
        }
    })
    .with_context(|| format!("labelling {}", args.drawing.display()))?;
    let elapsed_ms = start.elapsed().as_secs_f64() * 1e3;
    if args.json {
        let v = serde_json::json!({
            "drawing": args.drawing.display().to_string(),
            "elapsed_ms": elapsed_ms,
            "report": report,
            "labellings": report.labellings.iter().map(|l| labelling_string(l)).collect::<Vec<_>>(),
        });
        println!("{}", serde_json::to_string_pretty(&v)?);
    } else {
        print!("{}", report_text(&args.drawing, &d, &report, elapsed_ms));
    }
    Ok(())
}

/// Reads the drawing's `points` and `lines` only, as the help promises: its other fields
/// (`kinds`, `codes`, `junctions`, ...) are ignored, so a `kinds` list of another length does
/// not stop the labelling; codes and junctions come from the geometry.
fn read_points_and_lines(path: &Path) -> anyhow::Result<LineDrawing> {
    let text =
        blockworld::io::read_text(path).with_context(|| format!("reading {}", path.display()))?;
    let value: serde_json::Value = serde_json::from_str(&text).with_context(|| {
        format!(
            "{}: not JSON; give a drawing {{\"points\": [[x, y], ...], \"lines\": [[i, j], ...]}}",
            path.display()
        )
    })?;
    let kept = serde_json::json!({ "points": value["points"], "lines": value["lines"] });
    LineDrawing::from_json(&kept.to_string()).with_context(|| format!("{}", path.display()))
}

/// One labelling as one symbol per line: `+ - > < c`, `?` for a free line.
pub fn labelling_string(l: &[Option<LineLabel>]) -> String {
    l.iter().map(|x| x.map_or('?', |x| x.symbol())).collect()
}

fn with_commas(n: u128) -> String {
    let s = n.to_string();
    let mut out = String::new();
    for (i, c) in s.chars().enumerate() {
        if i > 0 && (s.len() - i) % 3 == 0 {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// A combination count for humans: exact with commas, or `10^x` when it is too large.
pub fn combinations_text(c: &blockworld::kanade::Combinations) -> String {
    match c.exact {
        Some(n) => with_commas(n),
        None => format!("about 10^{:.1}", c.log10),
    }
}

/// One line per junction: its class, lines in canonical order, and catalog labellings before
/// and after filtering.
fn junction_lines(r: &LabelReport) -> String {
    let mut t = String::new();
    for j in r.junctions.iter().filter(|j| !j.lines.is_empty()) {
        let dom = match (j.domain_before, j.domain_after) {
            (Some(a), Some(b)) => format!("{a} -> {b}"),
            _ => "not in catalog".into(),
        };
        t += &format!(
            "  point {:>4}  {:<8} lines {:?}  labellings {dom}\n",
            j.point,
            format!("{:?}", j.junction),
            j.lines
        );
    }
    t
}

fn report_text(path: &Path, d: &LineDrawing, r: &LabelReport, elapsed_ms: f64) -> String {
    let mut t = format!(
        "{}: {} points, {} lines; catalog {}\n",
        path.display(),
        d.points.len(),
        d.lines.len(),
        r.catalog.name()
    );
    let mut classes = std::collections::BTreeMap::new();
    for j in &r.junctions {
        if !j.lines.is_empty() {
            *classes.entry(format!("{:?}", j.junction)).or_insert(0) += 1;
        }
    }
    let list: Vec<String> = classes.iter().map(|(k, n)| format!("{n} {k}")).collect();
    t += &format!("junctions: {}\n", list.join(", "));
    t += &format!(
        "outside the catalog (constrain nothing): {}\n",
        if r.uncatalogued.is_empty() {
            "none".to_string()
        } else {
            format!("points {:?}", r.uncatalogued)
        }
    );
    t += &junction_lines(r);
    t += &format!(
        "combinations: {} before filtering, {} after\n",
        combinations_text(&r.stats.combinations_before),
        combinations_text(&r.stats.combinations_after)
    );
    let count = with_commas(r.count.value);
    t += &match &r.count.reason {
        None => format!("consistent labellings: {count}\n"),
        Some(why) => format!("consistent labellings: at least {count} ({why})\n"),
    };
    t += &format!(
        "search: {} nodes, {} backtracks, {} revisions, {} independent groups, {:.3} ms\n",
        r.stats.nodes, r.stats.backtracks, r.stats.revisions, r.stats.groups, elapsed_ms
    );
    t += "labels per line in line order: + convex, - concave, > occluding with the face on the right walking from its first point to its second, < the other way, c crack, ? free\n";
    for (i, l) in r.labellings.iter().enumerate() {
        t += &format!("  {:>3}: {}\n", i + 1, labelling_string(l));
    }
    if (r.labellings.len() as u128) < r.count.value {
        t += &format!(
            "  (first {} listed; --limit lists more)\n",
            r.labellings.len()
        );
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn large_counts_get_commas() {
        assert_eq!(with_commas(29_160), "29,160");
        assert_eq!(with_commas(544_195_584), "544,195,584");
        assert_eq!(with_commas(7), "7");
    }
}
