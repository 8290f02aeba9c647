//! The vision stage's errors: each names the input and says what to do.

/// Errors of the vision front end.
#[derive(Debug, thiserror::Error)]
pub enum VisionError {
    /// The picture's size differs from the camera's `size_px`.
    #[error("the picture is {got_w}x{got_h} px but its camera says {want_w}x{want_h} px; pass the camera_<view>.json written with this view")]
    SizeMismatch {
        /// Picture width.
        got_w: u32,
        /// Picture height.
        got_h: u32,
        /// Camera width.
        want_w: u32,
        /// Camera height.
        want_h: u32,
    },
    /// The picture is larger than [`super::MAX_PICTURE_SIDE_PX`] on a side.
    #[error("the picture is {w}x{h} px; at most {max}x{max} px is supported (downscale it first)")]
    TooLarge {
        /// Picture width.
        w: u32,
        /// Picture height.
        h: u32,
        /// The limit per side.
        max: u32,
    },
    /// Far more edge pixels than any block scene gives (noise, texture): line finding would
    /// take minutes.
    #[error("the picture has {edge_px} edge pixels, more than any block scene gives (at most {cap_px}: 200 per pixel of width + height); it looks like noise or texture: smooth it, raise --threshold, or give a rendered view")]
    TooManyEdges {
        /// Edge pixels after the threshold.
        edge_px: u64,
        /// The cap for this picture size.
        cap_px: u64,
    },
    /// The bytes are not a decodable image.
    #[error(
        "not a readable image: {0}; give a PNG (8-bit grayscale, as `blockworld render` writes)"
    )]
    Decode(String),
}
