//! Why each row of the `blocks` catalog ([`super::BLOCKS_EXTENSIONS`]) is there: the rules that
//! sort the rows into reasons, and the 3D facts of a junction of an exact drawing that the rules
//! read. Huffman (1971) and Clowes (1971) assume one trihedral solid in general position; a
//! stack of boxes breaks both assumptions, and each [`ExtensionReason`] names one way it does.
//! The generated `docs/kanade-blocks-catalog.md` lists every row with its reason and a junction
//! of a training scene where it occurs.

use super::graph::JunctionSite;
use super::label::EndLabel;
use crate::drawing::{Junction, LineDrawing};
use crate::geom::DVec3;

/// How close (mm) the 3D ends of a junction's lines must be to count as one point in space:
/// far below the 7.5 mm grid of the generated scenes, far above the exact drawing's rounding.
pub const SAME_POINT_TOLERANCE_MM: f64 = 1e-3;

/// The 3D facts of one junction of an exact drawing (`linedraw`, whose lines carry their
/// blocks and 3D ends, docs/formats.md "The exact line drawing").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct JunctionFacts {
    /// How many blocks own the junction's lines (for cracks and contact edges the touching
    /// block counts too).
    pub blocks: usize,
    /// Whether every line ends at the same 3D point (within [`SAME_POINT_TOLERANCE_MM`]): the
    /// lines meet in space, not only in the picture.
    pub in_space: bool,
}

/// The facts of `site` in `drawing`; `None` when the drawing carries no 3D edges (a drawing
/// from vision or by hand) or the site has no lines.
pub fn junction_facts(drawing: &LineDrawing, site: &JunctionSite) -> Option<JunctionFacts> {
    let mut blocks = Vec::new();
    let mut ends_mm = Vec::new();
    for e in &site.ends {
        let edge = drawing.edges.get(e.line)?;
        blocks.push(edge.block);
        blocks.extend(edge.other_block);
        let end = if e.at_start { edge.from_mm } else { edge.to_mm };
        ends_mm.push(DVec3::from_array(end));
    }
    let first = *ends_mm.first()?;
    blocks.sort_unstable();
    blocks.dedup();
    Some(JunctionFacts {
        blocks: blocks.len(),
        in_space: ends_mm
            .iter()
            .all(|p| p.distance(first) < SAME_POINT_TOLERANCE_MM),
    })
}

/// What every sighting of one catalog row showed, summed over the training scenes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct RowFacts {
    /// Junctions that showed the row.
    pub sightings: usize,
    /// Of those, how many met in space.
    pub in_space: usize,
    /// The most blocks seen at one of them.
    pub max_blocks: usize,
}

impl RowFacts {
    /// Adds one sighting.
    pub fn add(&mut self, f: JunctionFacts) {
        self.sightings += 1;
        self.in_space += usize::from(f.in_space);
        self.max_blocks = self.max_blocks.max(f.blocks);
    }

    /// Whether most sightings (ties included) meet in space.
    pub fn mostly_in_space(&self) -> bool {
        2 * self.in_space >= self.sightings
    }
}

/// Why stacked blocks need a junction labelling that the trihedral catalog lacks. The rule that
/// picks each reason is [`extension_reason`]; [`ExtensionReason::argument`] states the argument.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum ExtensionReason {
    /// One block only, lines meeting in space: a face seen edge-on.
    FaceSeenEdgeOn,
    /// T whose stem is a crack, meeting in space: a seam ends on a line.
    CrackEndsOnLine,
    /// T with a crack in its bar, meeting in space: a seam turns into an edge.
    SeamBecomesEdge,
    /// Fork or arrow with a crack, meeting in space: a corner with a flush neighbour.
    CrackAtCorner,
    /// Four or more lines with a crack, meeting in space: seams crossing edges.
    SeamsCrossEdges,
    /// Two or more blocks meeting in space without a crack: contact edges.
    BlocksTouch,
    /// The Huffman-Clowes T (an occluding bar, the stem passing behind) with a crack as stem.
    CrackBehindOutline,
    /// Lines of blocks at different depths that meet only in the picture.
    PictureAlignment,
}

impl ExtensionReason {
    /// Every reason, in the order the document lists them.
    pub const ALL: [ExtensionReason; 8] = [
        ExtensionReason::CrackEndsOnLine,
        ExtensionReason::SeamBecomesEdge,
        ExtensionReason::CrackAtCorner,
        ExtensionReason::SeamsCrossEdges,
        ExtensionReason::BlocksTouch,
        ExtensionReason::CrackBehindOutline,
        ExtensionReason::PictureAlignment,
        ExtensionReason::FaceSeenEdgeOn,
    ];

    /// A short name, used in the catalog rows' notes and as the document's anchors.
    pub fn slug(self) -> &'static str {
        match self {
            ExtensionReason::FaceSeenEdgeOn => "face-edge-on",
            ExtensionReason::CrackEndsOnLine => "crack-ends-on-line",
            ExtensionReason::SeamBecomesEdge => "seam-becomes-edge",
            ExtensionReason::CrackAtCorner => "crack-at-corner",
            ExtensionReason::SeamsCrossEdges => "seams-cross-edges",
            ExtensionReason::BlocksTouch => "blocks-touch",
            ExtensionReason::CrackBehindOutline => "crack-behind-outline",
            ExtensionReason::PictureAlignment => "picture-alignment",
        }
    }

    /// A short title.
    pub fn title(self) -> &'static str {
        match self {
            ExtensionReason::FaceSeenEdgeOn => "A face seen edge-on (accidental view)",
            ExtensionReason::CrackEndsOnLine => "T junctions on cracks: a seam ends on a line",
            ExtensionReason::SeamBecomesEdge => "A seam that carries on as an edge",
            ExtensionReason::CrackAtCorner => "Cracks at three-line corners",
            ExtensionReason::SeamsCrossEdges => {
                "Kanade's K, X and psi and multi-line junctions where flush blocks meet"
            }
            ExtensionReason::BlocksTouch => "Blocks touching along edges, without a crack",
            ExtensionReason::CrackBehindOutline => "The trihedral T with a crack as its stem",
            ExtensionReason::PictureAlignment => {
                "Lines of blocks at different depths aligned in the picture"
            }
        }
    }

    /// Why stacked blocks make such junctions (rule, physical argument, and the Huffman-Clowes
    /// assumption it breaks).
    pub fn argument(self) -> &'static str {
        match self {
            ExtensionReason::FaceSeenEdgeOn => {
                "Rule: every sighting involves one block only and its lines meet in space. A \
                 single box in general position shows only trihedral corners, all in the \
                 Huffman-Clowes catalog; these rows break general position instead: a block \
                 yawed by 45 degrees (the `yaw` family) seen from a corner view has a vertical \
                 face edge-on, so two of a corner's edges project onto one line (a straight \
                 junction of two occluding halves, a T or an arrow whose lines are all \
                 outline)."
            }
            ExtensionReason::CrackEndsOnLine => {
                "Rule: a T whose stem is a crack, its lines meeting in space. A crack is the \
                 seam between coplanar faces of two touching blocks (Waltz 1975); it ends where \
                 those faces end, on a straight line that runs through: their common outline \
                 (`L R c`, the occluding face on the stem's side), the concave edge where they \
                 stand on a third block (`- - c`), or another seam of a third flush block \
                 (`c c c`). A trihedral catalog has no cracks."
            }
            ExtensionReason::SeamBecomesEdge => {
                "Rule: a T with a crack in its bar, meeting in space. Two blocks touch face to \
                 face and one is longer: along a straight line the seam between their flush \
                 faces carries on as an edge (convex, concave or outline) of the longer block, \
                 and the stem is the edge of the shorter block's face that ends there."
            }
            ExtensionReason::CrackAtCorner => {
                "Rule: a fork or arrow with a crack, meeting in space. A block's corner where a \
                 neighbour's face is flush with one of the corner's faces: one of the corner's \
                 three edges is replaced by the seam, and the corner joins two or three blocks, \
                 which no trihedral solid does."
            }
            ExtensionReason::SeamsCrossEdges => {
                "Rule: four or more lines with a crack, meeting in space. Where blocks side by \
                 side or stacked are flush, the seam crosses their common convex or concave \
                 edge and continues on the other face (psi `c + c +`, K `+ - + c`), and where \
                 four flush faces meet the seams cross (X `c c c c`). These are Kanade's (1980) \
                 K, X and psi junctions and junctions of five and six lines; every line is \
                 still a real edge or seam at one 3D point."
            }
            ExtensionReason::BlocksTouch => {
                "Rule: two or more blocks, lines meeting in space, no crack. A block resting on \
                 or against another meets it along an edge: a convex edge of one block ends on, \
                 or runs into, a concave contact edge of the pair, so a 3D point joins the \
                 edges of two blocks and four or more faces, beyond the trihedral vertex."
            }
            ExtensionReason::CrackBehindOutline => {
                "Rule: a T whose bar is occluding (`R L`, the occluding face away from the stem) \
                 and whose stem is a crack, lines not meeting in space. It is the Huffman-Clowes \
                 T rule (the bar occludes, the stem passes behind with any label) applied to \
                 the one label the trihedral catalog lacks: a seam between flush blocks passing \
                 behind a nearer block."
            }
            ExtensionReason::PictureAlignment => {
                "Rule: the lines (mostly) do not meet in space. The generated scenes put blocks \
                 on a 7.5 mm grid and the corner views look along the grid's diagonals, so edges \
                 of blocks at different depths project onto the same picture lines and points \
                 (accidental alignment, which Huffman-Clowes exclude by general position): an \
                 outline ending exactly on another block's edge, or edges of a near and a far \
                 block lining up into K, psi, X and multi-line junctions."
            }
        }
    }
}

/// The reason for a catalog row, from its junction class, its labels in canonical order and
/// what its sightings showed. The rules, applied in this order:
/// 1. every sighting shows one block: [`ExtensionReason::FaceSeenEdgeOn`];
/// 2. most sightings meet in space: no crack → [`ExtensionReason::BlocksTouch`]; a T whose stem
///    (third line) is a crack → [`ExtensionReason::CrackEndsOnLine`]; a T with a crack in its
///    bar → [`ExtensionReason::SeamBecomesEdge`]; a fork or arrow →
///    [`ExtensionReason::CrackAtCorner`]; else [`ExtensionReason::SeamsCrossEdges`];
/// 3. otherwise a T `R L c` → [`ExtensionReason::CrackBehindOutline`], anything else
///    [`ExtensionReason::PictureAlignment`].
pub fn extension_reason(
    junction: Junction,
    labels: &[EndLabel],
    facts: &RowFacts,
) -> ExtensionReason {
    let crack = labels.contains(&EndLabel::Crack);
    if facts.max_blocks <= 1 {
        return ExtensionReason::FaceSeenEdgeOn;
    }
    if facts.mostly_in_space() {
        return match junction {
            _ if !crack => ExtensionReason::BlocksTouch,
            Junction::T if labels.get(2) == Some(&EndLabel::Crack) => {
                ExtensionReason::CrackEndsOnLine
            }
            Junction::T => ExtensionReason::SeamBecomesEdge,
            Junction::Fork | Junction::Arrow | Junction::L => ExtensionReason::CrackAtCorner,
            _ => ExtensionReason::SeamsCrossEdges,
        };
    }
    if junction == Junction::T && labels == [EndLabel::Out, EndLabel::In, EndLabel::Crack] {
        ExtensionReason::CrackBehindOutline
    } else {
        ExtensionReason::PictureAlignment
    }
}

/// A rule that derives catalog rows without looking at any scene; the training scenes check it
/// (`tests/kanade.rs` fails when a derived row is not among the rows they show).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum DerivationRule {
    /// The Huffman-Clowes T with a crack as its stem.
    TStemAnyLabel,
    /// A seam ends on a straight line through.
    SeamEndsOnLine,
    /// A seam crosses an edge or another seam and goes on.
    SeamCrossesLine,
}

impl DerivationRule {
    /// Every rule, in the order the document lists them.
    pub const ALL: [DerivationRule; 3] = [
        DerivationRule::TStemAnyLabel,
        DerivationRule::SeamEndsOnLine,
        DerivationRule::SeamCrossesLine,
    ];

    /// A short name for the document.
    pub fn slug(self) -> &'static str {
        match self {
            DerivationRule::TStemAnyLabel => "t-stem-any-label",
            DerivationRule::SeamEndsOnLine => "seam-ends-on-line",
            DerivationRule::SeamCrossesLine => "seam-crosses-line",
        }
    }

    /// The rule and its argument.
    pub fn argument(self) -> &'static str {
        match self {
            DerivationRule::TStemAnyLabel => {
                "Huffman-Clowes T: an occluding bar `R L` (the occluding face away from the \
                 stem) lets the stem pass behind with any label. PAIP's catalog lists the \
                 stems `+ - R L`; the fifth label, `c`, adds `R L c`."
            }
            DerivationRule::SeamEndsOnLine => {
                "A crack lies inside the plane of two flush faces and ends where they end, on a \
                 straight line that runs through: their outline seen from the faces' side \
                 (`L R c`), the concave edge where both stand on one block (`- - c`), or a seam \
                 of a third flush block (`c c c`). It cannot end on a convex edge: both faces \
                 of a convex edge are visible, so the seam goes on over the edge (next rule)."
            }
            DerivationRule::SeamCrossesLine => {
                "A seam crosses an edge that both flush blocks share and goes on, on the other \
                 face. Over a convex or concave edge it bends: a psi whose collinear pair is \
                 the edge and whose other two lines are the seam's halves, in both quarter \
                 turns of the canonical order (psi fixes only half turns), so `c + c +`, \
                 `+ c + c`, `c - c -`, `- c - c`. Over a seam of the same plane it runs \
                 straight: X `c c c c`, four flush faces."
            }
        }
    }

    /// The rows the rule derives, at their smallest rotation, without the trihedral ones.
    pub fn rows(self) -> Vec<DerivedRow> {
        use EndLabel::{Crack as C, In as L, Minus as M, Out as R, Plus as P};
        let raw: Vec<(Junction, Vec<EndLabel>)> = match self {
            DerivationRule::TStemAnyLabel => [P, M, R, L, C]
                .iter()
                .map(|&x| (Junction::T, vec![R, L, x]))
                .collect(),
            DerivationRule::SeamEndsOnLine => [[L, R], [M, M], [C, C]]
                .iter()
                .map(|&[a, b]| (Junction::T, vec![a, b, C]))
                .collect(),
            DerivationRule::SeamCrossesLine => vec![
                (Junction::Psi, vec![C, P, C, P]),
                (Junction::Psi, vec![P, C, P, C]),
                (Junction::Psi, vec![C, M, C, M]),
                (Junction::Psi, vec![M, C, M, C]),
                (Junction::X, vec![C, C, C, C]),
            ],
        };
        let trihedral = super::Catalog::HuffmanClowes;
        raw.into_iter()
            .filter(|(j, l)| !trihedral.labellings(*j, l.len()).contains(l))
            .map(|(junction, l)| DerivedRow {
                junction,
                labels: super::smallest_rotation(junction, &l),
                rule: self,
            })
            .collect()
    }
}

/// A catalog row that follows from a [`DerivationRule`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DerivedRow {
    /// The junction class.
    pub junction: Junction,
    /// Its labels in canonical order at the smallest rotation (as catalogs write them).
    pub labels: Vec<EndLabel>,
    /// The rule it follows from.
    pub rule: DerivationRule,
}

/// Every row the rules derive, rule by rule.
pub fn derived_rows() -> Vec<DerivedRow> {
    DerivationRule::ALL.iter().flat_map(|r| r.rows()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use EndLabel::{Crack as C, In as L, Minus as M, Out as R, Plus as P};

    fn facts(sightings: usize, in_space: usize, max_blocks: usize) -> RowFacts {
        RowFacts {
            sightings,
            in_space,
            max_blocks,
        }
    }

    #[test]
    fn the_rules_sort_the_big_rows_as_the_document_argues() {
        use ExtensionReason as X;
        let r = |j, l: &[EndLabel], f| extension_reason(j, l, &f);
        assert_eq!(
            r(Junction::T, &[L, R, C], facts(9, 9, 2)),
            X::CrackEndsOnLine
        );
        assert_eq!(
            r(Junction::T, &[C, P, R], facts(9, 9, 2)),
            X::SeamBecomesEdge
        );
        assert_eq!(
            r(Junction::Psi, &[C, P, C, P], facts(9, 9, 2)),
            X::SeamsCrossEdges
        );
        assert_eq!(
            r(Junction::Fork, &[M, L, C], facts(9, 9, 3)),
            X::CrackAtCorner
        );
        assert_eq!(r(Junction::T, &[M, L, P], facts(9, 9, 2)), X::BlocksTouch);
        assert_eq!(
            r(Junction::T, &[R, L, C], facts(9, 0, 3)),
            X::CrackBehindOutline
        );
        assert_eq!(
            r(Junction::T, &[L, R, C], facts(9, 0, 3)),
            X::PictureAlignment
        );
        assert_eq!(
            r(Junction::Arrow, &[L, R, R], facts(9, 9, 1)),
            X::FaceSeenEdgeOn
        );
        // A tie between sightings in space and in the picture only counts as in space.
        assert_eq!(
            r(Junction::X, &[P, P, L, R], facts(4, 2, 2)),
            X::BlocksTouch
        );
        assert_eq!(
            r(Junction::X, &[P, P, L, R], facts(5, 2, 2)),
            X::PictureAlignment
        );
    }

    #[test]
    fn facts_tell_a_corner_in_space_from_an_occlusion_in_the_picture() {
        use crate::drawing::{EdgeRef, LineDrawing};
        use crate::geom::DVec2;
        use crate::kanade::junction_sites;
        // A T: the bar (block 0) at depth 0, the stem (block 1) ending behind it at depth 5.
        let edge = |block, from_mm: [f64; 3], to_mm: [f64; 3]| EdgeRef {
            block,
            vertices: [0, 1],
            other_block: None,
            from_mm,
            to_mm,
            contact: false,
        };
        let mut d = LineDrawing {
            points: vec![
                DVec2::new(0.0, 0.0),
                DVec2::new(-10.0, 0.0),
                DVec2::new(10.0, 0.0),
                DVec2::new(0.0, -10.0),
            ],
            lines: vec![[0, 1], [0, 2], [0, 3]],
            edges: vec![
                edge(0, [0.0; 3], [-10.0, 0.0, 0.0]),
                edge(0, [0.0; 3], [10.0, 0.0, 0.0]),
                edge(1, [0.0, 0.0, 5.0], [0.0, -10.0, 5.0]),
            ],
            ..LineDrawing::default()
        };
        d.finalize();
        let site = junction_sites(&d)[0].clone();
        let occlusion = junction_facts(&d, &site).unwrap();
        assert_eq!(
            occlusion,
            JunctionFacts {
                blocks: 2,
                in_space: false
            }
        );
        d.edges[2].from_mm = [0.0; 3];
        assert!(junction_facts(&d, &site).unwrap().in_space);
        d.edges.clear();
        assert_eq!(
            junction_facts(&d, &site),
            None,
            "a drawing without 3D edges"
        );
    }

    #[test]
    fn the_rules_derive_nine_rows_and_drop_the_trihedral_t_stems() {
        let rows = derived_rows();
        let t: Vec<_> = DerivationRule::TStemAnyLabel.rows();
        assert_eq!(t.len(), 1, "PAIP lists R L with + - R L: {t:?}");
        assert_eq!(t[0].labels, [R, L, C]);
        assert_eq!(rows.len(), 9);
        assert!(rows
            .iter()
            .any(|r| r.junction == Junction::X && r.labels == [C, C, C, C]));
        // Psi fixes only half turns, so a seam over a convex edge is two rows.
        let psi: Vec<_> = rows
            .iter()
            .filter(|r| r.junction == Junction::Psi)
            .collect();
        assert_eq!(psi.len(), 4);
        assert!(psi.iter().any(|r| r.labels == [P, C, P, C]));
        assert!(psi.iter().any(|r| r.labels == [C, P, C, P]));
    }
}
