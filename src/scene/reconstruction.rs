//! A recognizer's answer: the blocks it placed, whether it stands behind them, why, the
//! constructive solid geometry that composes them (Chapter IV "Construction of the Final
//! Sample", Figure 4.6) and the evidence it checked them against (docs/formats.md "Reconstruction files").
//!
//! The file format is a scene file plus `status`, `reason`, `csg` and `evidence`, so every
//! command that reads scenes reads the blocks of a reconstruction the same way.

use super::{Block, Scene};
use serde::{Deserialize, Serialize};

/// A reconstruction's verdict on a scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ReconStatus {
    /// The recognizer produced blocks and every view is explained by them.
    Ok,
    /// The recognizer declined the scene (with a `reason`): the pictures are not explained by
    /// any answer it can give, or the scene is outside the method (Chapter VII).
    Unsupported,
}

/// A node of the CSG tree (Boyse 1979; Requicha & Voelcker 1982; the thesis's Figure 4.6): a
/// leaf is a positioned primitive from the block database, an inner node combines its children
/// from the bottom of the tree to the top. In JSON a node is `{"block": i}`, `{"union": [...]}`,
/// `{"difference": [a, b]}` or `{"intersection": [...]}`.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase", deny_unknown_fields)]
pub enum CsgNode {
    /// Block `i` of the reconstruction's `blocks`: a catalog primitive at its pose.
    Block(usize),
    /// The union of the children (the thesis's "adds the data together").
    Union(Vec<CsgNode>),
    /// The first child minus the second.
    Difference(Box<[CsgNode; 2]>),
    /// The intersection of the children.
    Intersection(Vec<CsgNode>),
}

impl CsgNode {
    /// The block indices of the leaves, left to right.
    pub fn leaves(&self) -> Vec<usize> {
        let mut out = Vec::new();
        self.collect_leaves(&mut out);
        out
    }

    fn collect_leaves(&self, out: &mut Vec<usize>) {
        match self {
            CsgNode::Block(i) => out.push(*i),
            CsgNode::Union(c) | CsgNode::Intersection(c) => {
                c.iter().for_each(|n| n.collect_leaves(out))
            }
            CsgNode::Difference(pair) => pair.iter().for_each(|n| n.collect_leaves(out)),
        }
    }

    /// `true` when the tree holds only unions and leaves: its solid is the union of its blocks.
    pub fn is_pure_union(&self) -> bool {
        match self {
            CsgNode::Block(_) => true,
            CsgNode::Union(c) => c.iter().all(CsgNode::is_pure_union),
            _ => false,
        }
    }
}

/// What one view contributed and how the answer's own exact drawing of that view compares with
/// the observed one (the thesis's intermediate data, Chapter VI; the check of Chapter V's
/// comparison of views). All four mismatch counts are 0 when the view is explained.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ViewEvidence {
    /// The view's name (`ne`, `se`, `sw`, `nw`).
    pub view: String,
    /// "Y" and collinear "T" vertices selected (Figure 5.1).
    pub selected_vertices: usize,
    /// Parallelograms searched from them (Figure 4.5).
    pub parallelograms: usize,
    /// Of those, closed ones.
    pub closed_parallelograms: usize,
    /// Catalog blocks proposed from them.
    pub proposals: usize,
    /// Observed points the answer's drawing does not have.
    pub unexplained_points: usize,
    /// Points the answer draws that were not observed.
    pub extra_points: usize,
    /// Observed lines the answer's drawing does not have.
    pub unexplained_lines: usize,
    /// Lines the answer draws that were not observed.
    pub extra_lines: usize,
}

impl ViewEvidence {
    /// `true` when the answer's drawing and the observed one agree.
    pub fn is_explained(&self) -> bool {
        self.unexplained_points + self.extra_points + self.unexplained_lines + self.extra_lines == 0
    }
}

/// The checks a recognizer made before answering.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Evidence {
    /// One entry per view used.
    pub views: Vec<ViewEvidence>,
    /// Distinct candidate blocks after the views were pooled.
    pub pooled_candidates: usize,
}

/// A recognizer's answer (docs/formats.md "Reconstruction files").
#[derive(Debug, Clone, PartialEq)]
pub struct Reconstruction {
    /// The scene's name.
    pub name: String,
    /// The placed catalog blocks; the solid is their union unless `csg` says otherwise.
    pub blocks: Vec<Block>,
    /// `ok` or `unsupported`.
    pub status: ReconStatus,
    /// Why `unsupported`, or remarks on an `ok` answer.
    pub reason: Option<String>,
    /// How the blocks compose the solid (Figure 4.6); `None` means the union of `blocks`.
    pub csg: Option<CsgNode>,
    /// What the answer was checked against.
    pub evidence: Option<Evidence>,
    /// Free-form provenance, kept as written.
    pub meta: Option<serde_json::Map<String, serde_json::Value>>,
}

impl Reconstruction {
    /// An `ok` reconstruction of `blocks` with a flat union as its CSG.
    pub fn ok(name: impl Into<String>, blocks: Vec<Block>) -> Reconstruction {
        let csg = CsgNode::Union((0..blocks.len()).map(CsgNode::Block).collect());
        Reconstruction {
            name: name.into(),
            blocks,
            status: ReconStatus::Ok,
            reason: None,
            csg: Some(csg),
            evidence: None,
            meta: None,
        }
    }

    /// An `unsupported` answer with its reason and no blocks.
    pub fn unsupported(name: impl Into<String>, reason: impl Into<String>) -> Reconstruction {
        Reconstruction {
            name: name.into(),
            blocks: Vec::new(),
            status: ReconStatus::Unsupported,
            reason: Some(reason.into()),
            csg: None,
            evidence: None,
            meta: None,
        }
    }

    /// The answer's blocks as a scene (for drawing, exporting or viewing it).
    pub fn to_scene(&self) -> Scene {
        let mut s = Scene::new(self.name.clone(), self.blocks.clone());
        s.meta = self.meta.clone();
        s
    }

    /// `true` for `status: ok`.
    pub fn is_ok(&self) -> bool {
        self.status == ReconStatus::Ok
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csg_json_is_compact_and_round_trips() {
        let t = CsgNode::Union(vec![
            CsgNode::Block(0),
            CsgNode::Difference(Box::new([CsgNode::Block(1), CsgNode::Block(2)])),
        ]);
        let j = serde_json::to_string(&t).unwrap();
        assert_eq!(
            j,
            r#"{"union":[{"block":0},{"difference":[{"block":1},{"block":2}]}]}"#
        );
        let back: CsgNode = serde_json::from_str(&j).unwrap();
        assert_eq!(back, t);
        assert_eq!(back.leaves(), vec![0, 1, 2]);
        assert!(!back.is_pure_union());
        assert!(serde_json::from_str::<CsgNode>(r#"{"subtract": []}"#).is_err());
    }
}
