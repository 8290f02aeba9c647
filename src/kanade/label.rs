//! Line labels (Huffman 1971, Clowes 1971; Kanade 1981, thesis Chapter II and Appendix A):
//! `+` convex, `-` concave, an occluding arrow whose face lies on one side, and the crack
//! between two touching blocks (Waltz 1975), which only the `blocks` catalog uses.

use serde::{Serialize, Serializer};

/// The label of a whole line, relative to the line's stored direction `lines[i] = [a, b]`.
///
/// Appendix A: "convex `+`: edge along which two surfaces meet and form a convexity; concave `-`;
/// occluding `->` or `<-`: edge along which one surface occludes another". The arrow follows
/// PAIP ch. 17: walking along the arrow, the occluding face (the solid) is on the right.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum LineLabel {
    /// `+`: two visible faces meet in a convexity.
    Convex,
    /// `-`: two visible faces meet in a concavity.
    Concave,
    /// `>`: occluding, arrow from `a` to `b`: walking from `a` to `b`, the occluding face is on
    /// the right and the occluded surface (or background) on the left.
    OccludingForward,
    /// `<`: occluding, arrow from `b` to `a`: the occluding face is on the left walking `a` → `b`.
    OccludingBackward,
    /// `c`: a crack, a flush seam between coplanar faces of two touching blocks (Waltz 1975);
    /// only in the `blocks` catalog.
    Crack,
}

impl LineLabel {
    /// Every label, in a fixed order (the bit order of [`LabelSet`]).
    pub const ALL: [LineLabel; 5] = [
        LineLabel::Convex,
        LineLabel::Concave,
        LineLabel::OccludingForward,
        LineLabel::OccludingBackward,
        LineLabel::Crack,
    ];

    /// One character: `+`, `-`, `>` (arrow a → b), `<` (arrow b → a), `c`.
    pub fn symbol(self) -> char {
        match self {
            LineLabel::Convex => '+',
            LineLabel::Concave => '-',
            LineLabel::OccludingForward => '>',
            LineLabel::OccludingBackward => '<',
            LineLabel::Crack => 'c',
        }
    }

    /// `true` for the two occluding arrows.
    pub fn is_occluding(self) -> bool {
        matches!(
            self,
            LineLabel::OccludingForward | LineLabel::OccludingBackward
        )
    }

    /// The occluding label whose face lies on the right of the walk `a` → `b` when
    /// `face_on_right` is true, else on the left.
    pub fn occluding(face_on_right: bool) -> LineLabel {
        if face_on_right {
            LineLabel::OccludingForward
        } else {
            LineLabel::OccludingBackward
        }
    }

    fn bit(self) -> u8 {
        1 << (self as u8)
    }
}

impl Serialize for LineLabel {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_char(self.symbol())
    }
}

/// A set of [`LineLabel`]s as five bits (Waltz filtering keeps one per line).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct LabelSet(pub u8);

impl LabelSet {
    /// Every label.
    pub const ANY: LabelSet = LabelSet(0b1_1111);

    /// Adds a label.
    pub fn insert(&mut self, l: LineLabel) {
        self.0 |= l.bit();
    }

    /// Whether `l` is in the set.
    pub fn contains(self, l: LineLabel) -> bool {
        self.0 & l.bit() != 0
    }

    /// The set of one label.
    pub fn only(l: LineLabel) -> LabelSet {
        LabelSet(l.bit())
    }
}

/// A label seen from one end of a line (the vocabulary of junction catalogs, PAIP ch. 17):
/// arrows are `Out` (pointing away from the junction) or `In` (pointing at it).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum EndLabel {
    /// `+` convex.
    Plus,
    /// `-` concave.
    Minus,
    /// PAIP's `R`: the arrow points away from the junction; walking out along the line, the
    /// occluding face is on the right.
    Out,
    /// PAIP's `L`: the arrow points at the junction; walking out along the line, the occluding
    /// face is on the left.
    In,
    /// `c`: a crack.
    Crack,
}

impl EndLabel {
    /// The whole line's label when this end label is seen at the line's first point `a`
    /// (`at_start`) or at its second point `b`.
    pub fn to_line_label(self, at_start: bool) -> LineLabel {
        match (self, at_start) {
            (EndLabel::Plus, _) => LineLabel::Convex,
            (EndLabel::Minus, _) => LineLabel::Concave,
            (EndLabel::Crack, _) => LineLabel::Crack,
            (EndLabel::Out, true) | (EndLabel::In, false) => LineLabel::OccludingForward,
            (EndLabel::Out, false) | (EndLabel::In, true) => LineLabel::OccludingBackward,
        }
    }

    /// The end label of a whole-line label seen at its first point (`at_start`) or second.
    pub fn from_line_label(l: LineLabel, at_start: bool) -> EndLabel {
        match (l, at_start) {
            (LineLabel::Convex, _) => EndLabel::Plus,
            (LineLabel::Concave, _) => EndLabel::Minus,
            (LineLabel::Crack, _) => EndLabel::Crack,
            (LineLabel::OccludingForward, true) | (LineLabel::OccludingBackward, false) => {
                EndLabel::Out
            }
            (LineLabel::OccludingForward, false) | (LineLabel::OccludingBackward, true) => {
                EndLabel::In
            }
        }
    }

    /// PAIP's one-letter name: `+`, `-`, `R` (out), `L` (in), `c`.
    pub fn symbol(self) -> char {
        match self {
            EndLabel::Plus => '+',
            EndLabel::Minus => '-',
            EndLabel::Out => 'R',
            EndLabel::In => 'L',
            EndLabel::Crack => 'c',
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_arrow_leaving_one_end_arrives_at_the_other() {
        // PAIP's reverse-label: one junction's R is its neighbour's L.
        let l = EndLabel::Out.to_line_label(true);
        assert_eq!(l, LineLabel::OccludingForward);
        assert_eq!(EndLabel::from_line_label(l, false), EndLabel::In);
        for e in [
            EndLabel::Plus,
            EndLabel::Minus,
            EndLabel::Out,
            EndLabel::In,
            EndLabel::Crack,
        ] {
            for s in [true, false] {
                assert_eq!(EndLabel::from_line_label(e.to_line_label(s), s), e);
            }
        }
    }

    #[test]
    fn label_sets_hold_exactly_what_was_inserted() {
        let mut s = LabelSet::default();
        s.insert(LineLabel::Crack);
        assert!(s.contains(LineLabel::Crack));
        assert!(!s.contains(LineLabel::Convex));
        assert!(LineLabel::ALL.iter().all(|l| LabelSet::ANY.contains(*l)));
    }
}
