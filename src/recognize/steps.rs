//! The recognizer's steps one at a time (the numbered steps of the module doc, Figure 5.3), for
//! what looks inside a step rather than at the answer: the `recognize-debug` command's Figure
//! A.6 pictures and the tests of Chapter VII's parts and of the picture-aware check.
//! [`super::recognize_in_pictures`] runs them all in order.

pub use super::catalog_match::{
    catalog_candidates, catalog_proposals, measure_parallelogram_mm, ParallelogramMm, Proposal,
};
pub use super::compare::{choose_blocks, pool_candidates, PooledCandidate, SearchLimits};
pub use super::constraints::curved_chain_lines;
pub use super::direct::direct_hypothesis;
pub use super::edge_profile::{edge_profile, EdgeProfile, ViewPicture};
pub use super::parallelogram::{
    drop_below_mm, horizontal_axis_for, point_at_height_mm, ChainStop, Face, Parallelogram,
    ParallelogramSearch, TopCorner,
};
pub use super::picture::{picture_check, pictures_mismatch};
pub use super::select::{select_vertices, SelectedVertex};
pub use super::trapezoid::{sloped_faces, FaceGradient};
pub use super::verify::{mismatched_features, ViewMismatch};
