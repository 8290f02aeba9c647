//! The thesis's display figures (Chapter VI, "Display the Final Sample", Figures 6.7-6.12): the
//! sample seen with Up at (1,0,0), (0,0,1), (0,1,0) and (2,1,3), then with From moved toward
//! the object until clipping cuts it (Figure 6.11), then with the view angle narrowed from 60
//! to 30 degrees (Figure 6.12). The thesis's own From and At values are lost with its figures,
//! so these views fix their own: At at the sample's centre, From above its south-east corner.
//! One home for the golden test and for `demo`, which draws them for the reconstruction.

use super::{ViewError, ViewParams};
use crate::geom::DVec3;

/// At: the centre of the thesis sample (`scenes/thesis_sample.json`), mm.
pub const FIGURE_AT_MM: [f64; 3] = [22.5, 15.0, 15.0];
/// From: above the sample's south-east corner, about 96 mm from At.
pub const FIGURE_FROM_MM: [f64; 3] = [82.5, 60.0, 75.0];
/// Figure 6.11's "move From point": 60 mm toward At, leaving 36 mm.
pub const FIGURE_MOVE_FROM_MM: f64 = 60.0;

/// One of the display figures.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThesisFigure {
    /// File stem, e.g. `fig6_7_up_x`.
    pub name: &'static str,
    /// The Up direction.
    pub up: [f64; 3],
    /// From moved this far toward At (Figures 6.11, 6.12).
    pub move_from_mm: Option<f64>,
    /// The view angle, degrees.
    pub view_angle_deg: f64,
}

const fn figure(
    name: &'static str,
    up: [f64; 3],
    move_from_mm: Option<f64>,
    view_angle_deg: f64,
) -> ThesisFigure {
    ThesisFigure {
        name,
        up,
        move_from_mm,
        view_angle_deg,
    }
}

/// Figures 6.7-6.12, in order.
pub const THESIS_FIGURES: [ThesisFigure; 6] = [
    figure("fig6_7_up_x", [1.0, 0.0, 0.0], None, 60.0),
    figure("fig6_8_up_z", [0.0, 0.0, 1.0], None, 60.0),
    figure("fig6_9_up_y", [0.0, 1.0, 0.0], None, 60.0),
    figure("fig6_10_up_213", [2.0, 1.0, 3.0], None, 60.0),
    figure(
        "fig6_11_moved_from",
        [0.0, 1.0, 0.0],
        Some(FIGURE_MOVE_FROM_MM),
        60.0,
    ),
    figure(
        "fig6_12_view_angle_30",
        [0.0, 1.0, 0.0],
        Some(FIGURE_MOVE_FROM_MM),
        30.0,
    ),
];

impl ThesisFigure {
    /// The figure's From/At/Up and view angle.
    pub fn params(&self) -> Result<ViewParams, ViewError> {
        let params = ViewParams {
            from_mm: DVec3::from_array(FIGURE_FROM_MM),
            at_mm: DVec3::from_array(FIGURE_AT_MM),
            up: DVec3::from_array(self.up),
            view_angle_deg: self.view_angle_deg,
        };
        match self.move_from_mm {
            Some(d) => params.move_from(d),
            None => Ok(params),
        }
    }
}
