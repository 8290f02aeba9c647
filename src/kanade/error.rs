//! Errors of the Kanade stage: a drawing that cannot be a line drawing.

use crate::drawing::DrawingError;
use thiserror::Error;

/// Why a drawing cannot be labelled. Each message says what to fix in the drawing file.
#[derive(Debug, Error, PartialEq)]
pub enum KanadeError {
    /// The drawing's geometry is broken ([`crate::drawing::LineDrawing::check_geometry`]): a
    /// line naming a missing point or joining a point to itself or to another at the same
    /// place, or a coordinate that is not finite.
    #[error("{0}; fix the drawing file")]
    Drawing(#[from] DrawingError),
    /// Two lines join the same two points (the same line twice, or once reversed).
    #[error("lines {first} and {second} join the same two points; remove line {second}")]
    DuplicateLine {
        /// The first of the two.
        first: usize,
        /// The repeat.
        second: usize,
    },
    /// More lines than the labeller takes ([`super::MAX_LABEL_LINES`]).
    #[error("the drawing has {lines} lines, more than the {max} the labeller takes; label its parts in files of at most {max} lines (separate pieces of a drawing label independently)")]
    TooManyLines {
        /// Lines in the drawing.
        lines: usize,
        /// The most the labeller takes.
        max: usize,
    },
    /// A `ground` pair is not a line of the drawing.
    #[error("no line joins points {a} and {b}; ground a pair of points that a line joins")]
    NoSuchLine {
        /// First point.
        a: usize,
        /// Second point.
        b: usize,
    },
    /// The drawing has fewer than three directions of parallel lines, or they cannot depict
    /// three perpendicular edges.
    #[error("the drawing does not have three directions of parallel lines depicting perpendicular edges (Kanade's parallel-line and skewed-symmetry heuristics); gradients need a block drawing")]
    NoGradientSpace,
}
