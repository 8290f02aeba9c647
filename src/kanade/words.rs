//! Computer words, counted by the thesis's rules of Chapter VI ("Comparisons of the Two
//! Models", Figures 6.16 and 6.17):
//! - Kanade's model: one word per line label ("the number of line labels is equal to the number
//!   of lines in the picture"), one word per junction label, and per link of the surface
//!   connection graph three words to name the link and its two surfaces and two more for the
//!   gradient constraint and its link (Figure 6.16): five per link. The cube's 3 convex links
//!   and 7 junctions give the thesis's 22.
//! - The modified model: one word per vertex, its six-bit code ("each vertex is represented by
//!   a computer word with line information on it").
//!
//! Only one labelling is stored (the thesis: "Only a unique labeling for each junction in the
//! picture is selected").

use super::gradient::SurfaceConnectionGraph;
use crate::drawing::LineDrawing;
use serde::Serialize;

/// Words of memory each model uses for one drawing (Figure 6.17's rows).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct ComputerWords {
    /// Kanade: one per line label.
    pub line_labels: usize,
    /// Kanade: one per junction label plus five per SCG link between two surfaces.
    pub junction_labels: usize,
    /// SCG links between two surfaces counted in `junction_labels`.
    pub scg_links: usize,
    /// Modified model: one six-bit code per vertex.
    pub six_bit: usize,
}

impl ComputerWords {
    /// Share of Kanade's words the six-bit coding saves (Figure 6.17's last row).
    pub fn saved(&self) -> f64 {
        let kanade = (self.line_labels + self.junction_labels) as f64;
        1.0 - self.six_bit as f64 / kanade
    }
}

/// Counts the words for a drawing and the SCG of its chosen labelling.
pub fn computer_words(d: &LineDrawing, scg: &SurfaceConnectionGraph) -> ComputerWords {
    let mut degree = vec![0usize; d.points.len()];
    for &[a, b] in &d.lines {
        degree[a] += 1;
        degree[b] += 1;
    }
    let junctions = degree.iter().filter(|n| **n > 0).count();
    let scg_links = scg
        .links
        .iter()
        .filter(|l| scg.surface[l.a] && scg.surface[l.b])
        .count();
    ComputerWords {
        line_labels: d.lines.len(),
        junction_labels: junctions + 5 * scg_links,
        scg_links,
        six_bit: junctions,
    }
}
