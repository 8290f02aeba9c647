//! The thesis's viewer (Chapter II "Mathematics of Planar Geometric Projections", Chapter VI
//! "Display the Final Sample", Figures 6.7-6.12): a block sample seen from a From point
//! looking at an At point with an Up direction and a view angle, in one-point perspective,
//! clipped in 3D against the canonical view volume and drawn as a wireframe.
//!
//! The flow is Figure 2.11's: world → translate F to the origin (eq. 2.2) → turn into the
//! left-handed viewing axes (eq. 2.4-2.5) → scale by the view angle (eq. 2.6) → clip against
//! y = ±z, x = ±z, z = z_min, z = 1 (eq. 2.7-2.8) → divide by z → picture. Beyond the thesis,
//! as its Chapter VII recommends: several viewports on one sheet, hidden-line removal and flat
//! shading. [`draw_sheet`] returns plain data (picture lines, faces, labels);
//! [`rasterize_sheet`] turns it into an RGB image with its own line rasterizer and bitmap
//! font, [`sheet_to_svg`] into SVG text. File I/O is the CLI's.

mod clip;
mod figures;
mod font;
mod panel;
mod raster;
mod svg;
mod transform;

pub use clip::{clip_line, point_at, Clipped, OutCode};
pub use figures::{
    ThesisFigure, FIGURE_AT_MM, FIGURE_FROM_MM, FIGURE_MOVE_FROM_MM, THESIS_FIGURES,
};
pub use panel::{
    draw_sheet, wire_model, HiddenLines, Panel, PictureFace, PictureLine, PixelRect, Role, Sheet,
    SheetOptions, ViewParams, WireModel,
};
pub use raster::rasterize_sheet;
pub use svg::sheet_to_svg;
pub use transform::{
    orientation, rotation_x, rotation_y, rotation_z, translation, view_angle_matrix,
    view_angle_scale, viewing_axes, ViewingAxes, ViewingTransform,
};

/// Largest |coordinate| of From and At, mm: 100 times the world's half extent
/// ([`crate::geom::WORLD_HALF_EXTENT_MM`]), far beyond any useful eye point, and small enough
/// that the viewing axes (eq. 2.5) are computed without overflow.
pub const MAX_VIEW_COORD_MM: f64 = 1e6;

/// Why a view cannot be drawn; each names the option to change.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ViewError {
    /// From and At coincide, so there is no line of sight (eq. 2.5a divides by |A - F|).
    #[error("--from and --at are the same point {at_mm:?}; move --from away from --at")]
    FromAtSamePoint {
        /// The At point, mm.
        at_mm: [f64; 3],
    },
    /// Up is zero or along the line of sight, so eq. 2.5b's cross product vanishes.
    #[error("--up {up:?} is zero or along the line of sight from --from to --at; pick an up direction across it, e.g. 0,1,0")]
    UpAlongLineOfSight {
        /// The Up direction as given.
        up: [f64; 3],
    },
    /// A view angle outside (0, 180) degrees has no tangent for eq. 2.6.
    #[error(
        "--view-angle {} is out of range; use 1..=170 degrees (the thesis shows 30 and 60)", crate::io::echo_number(*.deg)
    )]
    BadViewAngle {
        /// The angle as given, degrees.
        deg: f64,
    },
    /// Moving From toward At by this much would reach or pass At.
    #[error("--move-from {} mm would reach or pass --at ({available_mm:.3} mm away); use less than that, or a negative distance to move away", crate::io::echo_number(*.distance_mm))]
    MoveFromPastAt {
        /// The distance asked for, mm.
        distance_mm: f64,
        /// The distance from From to At, mm.
        available_mm: f64,
    },
    /// A From or At coordinate beyond [`MAX_VIEW_COORD_MM`]: eq. 2.5's products would lose
    /// the line of sight to overflow and rounding.
    #[error("{option} coordinate {value} mm is out of range; give each coordinate of --from and --at within ±{max} mm (docs/limits.md \"Viewer\")", value = crate::io::echo_number(*.value_mm), max = MAX_VIEW_COORD_MM)]
    TooFar {
        /// The option.
        option: &'static str,
        /// The coordinate as given, mm.
        value_mm: f64,
    },
    /// A NaN or infinite number in From, At, Up or a distance.
    #[error("{option} has a non-finite value; give finite numbers")]
    NotFinite {
        /// The option.
        option: &'static str,
    },
    /// Zero viewports, or more than the sheet can hold.
    #[error("--viewports {viewports} is out of range; use 1..=16")]
    BadViewports {
        /// The count as given.
        viewports: u32,
    },
    /// A sheet too small to draw on.
    #[error(
        "--size {width_px}x{height_px} is too small; each viewport needs at least 32x32 pixels"
    )]
    TooSmall {
        /// Sheet width, px.
        width_px: u32,
        /// Sheet height, px.
        height_px: u32,
    },
    /// No vertex to frame a default view on.
    #[error("the model has no blocks, so there is nothing to look at; give a model with blocks")]
    NothingToView,
}
