//! Kanade's model (thesis Chapter II "The Kanade Model for Object Recognition", Chapter III,
//! Chapter VI "Three-Dimensional Object Recognition by Kanade Model", Appendix A) on the same
//! [`LineDrawing`](crate::drawing::LineDrawing) the modified model reads: the baseline the thesis
//! compares itself with.
//!
//! 1. **Line labels** (Chapter III step 1; Huffman 1971, Clowes 1971, Waltz 1975, PAIP ch. 17):
//!    junction classes from geometry, a junction [`Catalog`], Waltz filtering and a search for
//!    every consistent labelling ([`label_drawing`]). Labels are local: a figure that is
//!    impossible as a whole but possible at every junction (a Penrose triangle) is labelled.
//! 2. **Surface connection graph** (Chapter II, Figure 2.2b; Appendix A step 3).
//! 3. **Gradient space** (Chapter II, Figure 2.5): gradients from the parallel-line and skewed
//!    symmetry heuristics, plane equations, and 3D vertices up to one reference depth.

mod blocks_catalog;
mod catalog;
mod error;
mod extensions;
mod gradient;
mod graph;
mod label;
mod truth;
mod waltz;
mod words;

pub use catalog::{
    rotations, smallest_rotation, Catalog, CatalogEntry, BLOCKS_EXTENSIONS, HUFFMAN_CLOWES,
};
pub use error::KanadeError;
pub use extensions::{
    derived_rows, extension_reason, junction_facts, DerivationRule, DerivedRow, ExtensionReason,
    JunctionFacts, RowFacts, SAME_POINT_TOLERANCE_MM,
};
pub use gradient::{
    depth_rms_px, gradient_label_sets, orthonormal_axes, recover_shape, surface_connection_graph,
    GradientSpace, LinkKind, ShapeRecovery, SurfaceConnectionGraph, SurfaceLink,
};
pub use graph::{junction_sites, regions, validate, JunctionSite, LineEnd, Region};
pub use label::{EndLabel, LabelSet, LineLabel};
pub use truth::{
    check_labelling, is_consistent, labelling_from_kinds, orthographic_px_per_mm,
    true_line_ends_px, Violation,
};
pub use waltz::{
    label_drawing, Combinations, JunctionReport, LabelOptions, LabelReport, LabellingCount,
    Progress, SearchStats, MAX_LABEL_LINES,
};
pub use words::{computer_words, ComputerWords};
