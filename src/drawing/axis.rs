//! The world directions block edges run along. Chapter V: "the gradients of the left and the
//! right side of a block are constant", so a picture of blocks in one direction has one picture
//! direction per world axis: vertical, world x and world z. Other parts (a wedge's sloped face)
//! add directions of their own, so a list of axes, not a fixed three, describes a picture.

use crate::geom::DVec3;
use serde::{Deserialize, Serialize};
use std::f64::consts::FRAC_1_SQRT_2;

/// A world direction of block edges.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EdgeAxis {
    /// World +y: the heights of blocks.
    Vertical,
    /// World +x.
    WorldX,
    /// World +z.
    WorldZ,
    /// Any other world direction (unit vector), e.g. a wedge's sloped edge.
    World([f64; 3]),
}

impl EdgeAxis {
    /// The three axes of blocks placed in one direction (Chapter VII's constraint).
    pub const BLOCK_AXES: [EdgeAxis; 3] = [EdgeAxis::Vertical, EdgeAxis::WorldX, EdgeAxis::WorldZ];

    /// The world directions of a trapezoidal block's sloped edges (the wedge `w30`, thesis
    /// Figure 7.1; docs/formats.md "Block catalog"): 45 degrees up from x or z, either way. In a corner
    /// view they add a fourth and fifth picture direction to the three of [`Self::BLOCK_AXES`].
    pub const TRAPEZOID_SLOPES: [EdgeAxis; 4] = [
        EdgeAxis::World([FRAC_1_SQRT_2, FRAC_1_SQRT_2, 0.0]),
        EdgeAxis::World([FRAC_1_SQRT_2, -FRAC_1_SQRT_2, 0.0]),
        EdgeAxis::World([0.0, FRAC_1_SQRT_2, FRAC_1_SQRT_2]),
        EdgeAxis::World([0.0, FRAC_1_SQRT_2, -FRAC_1_SQRT_2]),
    ];

    /// The axis as a world unit vector.
    pub fn world_direction(self) -> DVec3 {
        match self {
            EdgeAxis::Vertical => DVec3::Y,
            EdgeAxis::WorldX => DVec3::X,
            EdgeAxis::WorldZ => DVec3::Z,
            EdgeAxis::World(d) => DVec3::from_array(d).normalize_or(DVec3::Y),
        }
    }
}
