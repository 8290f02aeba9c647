//! Junction catalogs: for each junction class, the labellings of its lines that a physical
//! corner can produce, in the canonical line order of [`super::JunctionSite`].
//!
//! ## `huffman-clowes` (the default)
//! The trihedral catalog (Huffman 1971, Clowes 1971) exactly as PAIP ch. 17 lists it, 18
//! entries; PAIP's `R` is [`EndLabel::Out`], `L` is [`EndLabel::In`]:
//!
//! | junction | entries | meaning |
//! |---|---|---|
//! | L (6) | `R L`, `L R` | an outline corner, the face inside the angle or outside it |
//! | | `+ R`, `L +` | a convex edge ending where the face beside it turns away (outline continues) |
//! | | `- L`, `R -` | a concave edge ending at an outline corner |
//! | fork (5) | `+ + +` | the near corner of a convex solid (the cube's middle) |
//! | | `- - -` | the inside of a concave corner (a room's corner) |
//! | | `L R -` and its two rotations | a concave edge between two faces, the third sector hidden |
//! | T (4) | `R L +`, `R L -`, `R L L`, `R L R` | an occluding bar; the stem passes behind it with any label |
//! | arrow (3) | `L R +` | the outline corner of a convex solid, the shaft convex |
//! | | `- - +` | a convex edge meeting two concave ones (a block's bottom corner on a floor) |
//! | | `+ + -` | a concave edge between two convex ones (an inside corner) |
//!
//! ## `blocks`
//! The trihedral entries plus what stacked blocks add ([`BLOCKS_EXTENSIONS`]): the crack label
//! `c` of Waltz (1975) (a flush seam between coplanar faces of touching blocks, unoriented
//! here), Kanade's K, X and psi junctions of four lines (thesis Chapter II), and the junctions
//! of five and more lines where block corners meet in the picture. Huffman and Clowes found their
//! catalog by enumerating the corners a trihedral solid can show; the blocks catalog is found
//! the same way for block stacks, by drawing them: every junction of the exact drawings
//! (`linedraw`) of 440 generated scenes (40 per generator family, seeds 1000-1439, four
//! corner views; disjoint from the accuracy suite `scenes/bench`, seed 2026) with its true
//! labels, each row noting how often it was seen and why stacked blocks need it
//! ([`super::ExtensionReason`], chosen by the rules of [`super::extension_reason`] from the
//! row's labels and the 3D facts of its sightings). `docs/kanade-blocks-catalog.md` lists every
//! row with its reason, the argument and an example junction. `tests/kanade.rs` redraws the
//! scenes and fails when the table or the document differs, or when a row has no entry in the
//! document; `BLESS=1 cargo test --test kanade blocks_catalog_and_its_document` rewrites both.
//!
//! Labels are local: a catalog only says which corners exist, so an impossible figure whose
//! every junction is possible (a Penrose triangle) is labelled.

pub use super::blocks_catalog::BLOCKS_EXTENSIONS;
use super::label::EndLabel;
use crate::drawing::Junction;
use serde::Serialize;

use EndLabel::{In as L, Minus as M, Out as R, Plus as P};

/// Which junction catalog to label with (`--catalog`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Catalog {
    /// The 18 trihedral junction labellings of PAIP ch. 17 (L 6, fork 5, T 4, arrow 3).
    #[default]
    HuffmanClowes,
    /// Trihedral plus the cracks and four-line junctions of stacked blocks
    /// ([`BLOCKS_EXTENSIONS`]).
    Blocks,
}

/// One catalog row: a junction class and its lines' labels in canonical order.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CatalogEntry {
    /// The junction class.
    pub junction: Junction,
    /// Labels of its lines in canonical order (rotations are added for forks, psi and X).
    pub labels: &'static [EndLabel],
    /// What physical corner the row depicts.
    pub note: &'static str,
}

pub(super) const fn e(
    junction: Junction,
    labels: &'static [EndLabel],
    note: &'static str,
) -> CatalogEntry {
    CatalogEntry {
        junction,
        labels,
        note,
    }
}

/// The trihedral catalog as PAIP ch. 17 prints it (`possible-labelings`).
pub const HUFFMAN_CLOWES: &[CatalogEntry] = &[
    e(
        Junction::L,
        &[R, L],
        "outline corner, face inside the angle",
    ),
    e(
        Junction::L,
        &[L, R],
        "outline corner, face outside the angle",
    ),
    e(Junction::L, &[P, R], "convex edge ending on the outline"),
    e(Junction::L, &[L, P], "convex edge ending on the outline"),
    e(Junction::L, &[M, L], "concave edge ending on the outline"),
    e(Junction::L, &[R, M], "concave edge ending on the outline"),
    e(Junction::Fork, &[P, P, P], "near corner of a convex solid"),
    e(Junction::Fork, &[M, M, M], "inside of a concave corner"),
    e(
        Junction::Fork,
        &[L, R, M],
        "concave edge, one sector hidden",
    ),
    e(
        Junction::T,
        &[R, L, P],
        "convex edge passing behind an outline",
    ),
    e(
        Junction::T,
        &[R, L, M],
        "concave edge passing behind an outline",
    ),
    e(Junction::T, &[R, L, L], "outline passing behind an outline"),
    e(Junction::T, &[R, L, R], "outline passing behind an outline"),
    e(
        Junction::Arrow,
        &[L, R, P],
        "outline corner of a convex solid",
    ),
    e(
        Junction::Arrow,
        &[M, M, P],
        "convex edge between two concave ones",
    ),
    e(
        Junction::Arrow,
        &[P, P, M],
        "concave edge between two convex ones",
    ),
];

impl Catalog {
    /// Parses `huffman-clowes` or `blocks`.
    pub fn parse(s: &str) -> Option<Catalog> {
        match s {
            "huffman-clowes" => Some(Catalog::HuffmanClowes),
            "blocks" => Some(Catalog::Blocks),
            _ => None,
        }
    }

    /// The catalog's name as `--catalog` spells it.
    pub fn name(self) -> &'static str {
        match self {
            Catalog::HuffmanClowes => "huffman-clowes",
            Catalog::Blocks => "blocks",
        }
    }

    /// The rows, before rotations are added.
    pub fn rows(self) -> Vec<CatalogEntry> {
        let mut rows = HUFFMAN_CLOWES.to_vec();
        if self == Catalog::Blocks {
            rows.extend_from_slice(BLOCKS_EXTENSIONS);
        }
        rows
    }

    /// Every labelling of a junction class of `lines` lines in canonical order, rotations
    /// included and duplicates removed, in table order; empty when the catalog lacks it.
    pub fn labellings(self, junction: Junction, lines: usize) -> Vec<Vec<EndLabel>> {
        let mut out: Vec<Vec<EndLabel>> = Vec::new();
        let rows = self.rows();
        let rows = rows
            .iter()
            .filter(|r| r.junction == junction && r.labels.len() == lines);
        for row in rows {
            for k in rotations(junction, row.labels.len()) {
                let n = row.labels.len();
                let v: Vec<EndLabel> = (0..n).map(|i| row.labels[(i + k) % n]).collect();
                if !out.contains(&v) {
                    out.push(v);
                }
            }
        }
        out
    }

    /// Number of labellings of a class (of its usual number of lines), rotations included.
    pub fn size(self, junction: Junction) -> usize {
        let lines = match junction {
            Junction::End => 1,
            Junction::L | Junction::Straight => 2,
            Junction::Fork | Junction::Arrow | Junction::T => 3,
            _ => 4,
        };
        self.labellings(junction, lines).len()
    }
}

/// The rotations of the canonical order that the geometry does not fix: all of them for a
/// fork, X and straight (whose order starts at the lowest angle), a half turn for psi, none for
/// L, arrow, T, K and five or more lines (which start after the widest gap).
pub fn rotations(junction: Junction, n: usize) -> Vec<usize> {
    match junction {
        Junction::Fork | Junction::X | Junction::Straight => (0..n).collect(),
        Junction::Psi => vec![0, 2],
        _ => vec![0],
    }
}

/// The rotation of `labels` (a junction's labels in canonical order) that the catalogs write:
/// the smallest, in `EndLabel` order, of those [`rotations`] allows.
pub fn smallest_rotation(junction: Junction, labels: &[EndLabel]) -> Vec<EndLabel> {
    let n = labels.len();
    rotations(junction, n)
        .into_iter()
        .map(|k| (0..n).map(|i| labels[(i + k) % n]).collect::<Vec<_>>())
        .min()
        .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn huffman_clowes_has_pauls_eighteen_labellings() {
        // PAIP ch. 17: "An L vertex has six possibilities, Y has five, T has four, and W has
        // three."
        let c = Catalog::HuffmanClowes;
        assert_eq!(c.size(Junction::L), 6);
        assert_eq!(c.size(Junction::Fork), 5);
        assert_eq!(c.size(Junction::T), 4);
        assert_eq!(c.size(Junction::Arrow), 3);
        assert_eq!(c.size(Junction::K), 0);
        let total: usize = [Junction::L, Junction::Fork, Junction::T, Junction::Arrow]
            .iter()
            .map(|j| c.size(*j))
            .sum();
        assert_eq!(total, 18);
    }

    #[test]
    fn fork_rotations_are_the_three_paip_lists() {
        let f = Catalog::HuffmanClowes.labellings(Junction::Fork, 3);
        assert!(f.contains(&vec![M, L, R]));
        assert!(f.contains(&vec![R, M, L]));
        assert!(!f.contains(&vec![R, L, M]), "a fork has a handedness");
    }

    #[test]
    fn blocks_extends_and_never_drops_a_trihedral_row() {
        for (j, n) in [
            (Junction::L, 2),
            (Junction::Fork, 3),
            (Junction::T, 3),
            (Junction::Arrow, 3),
        ] {
            let hc = Catalog::HuffmanClowes.labellings(j, n);
            let b = Catalog::Blocks.labellings(j, n);
            assert!(hc.iter().all(|x| b.contains(x)));
        }
        // Every class fits the labeller's 128-bit domains (rotations included).
        for row in Catalog::Blocks.rows() {
            let n = Catalog::Blocks
                .labellings(row.junction, row.labels.len())
                .len();
            assert!(
                n <= 128,
                "{:?} of {} lines: {n}",
                row.junction,
                row.labels.len()
            );
        }
        assert!(Catalog::Blocks.size(Junction::Psi) >= 1);
    }
}
