// The property of the `vision` fuzz target, shared with `tests/fuzz_corpus.rs` (which replays
// the committed corpus `tests/fuzz/seeds/vision/` on stable Rust) through `include!`: arbitrary
// bytes are decoded as an image (PNG and the other formats the `image` crate guesses) and, when
// they decode, run through Sobel + smoothing + threshold, lines and vertices (docs/vision.md "Vision front end"). Nothing may panic; every vertex found has its six-bit code.

/// Checks one input; panics (a finding) when the property breaks.
pub fn check_vision_bytes(data: &[u8]) {
    use blockworld::vision::{
        decode_gray, detect_with_directions, isometric_edge_directions, VisionOptions,
    };
    // Keep each run short: pictures above 1024 px a side are refused here (the library itself
    // accepts up to MAX_PICTURE_SIDE_PX and refuses more with an error).
    let Ok(pic) = decode_gray(data) else { return };
    if pic.gray.width() > 1024 || pic.gray.height() > 1024 {
        return;
    }
    let dirs = isometric_edge_directions();
    let det = detect_with_directions(&pic.gray, &dirs, &VisionOptions::default());
    assert_eq!(det.drawing.codes.len(), det.drawing.points.len());
    assert!(
        det.drawing.points.iter().all(|p| p.is_finite()),
        "a non-finite vertex"
    );
}
