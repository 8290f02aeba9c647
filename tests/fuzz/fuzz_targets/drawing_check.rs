// The property the `drawing` fuzz target checks, shared with `tests/mutants.rs` through
// `include!`: any bytes either fail to read as a line drawing (`lines_<view>.json`,
// `vertices_<view>.json`) or read as one that writes JSON without `null` which reads back and
// writes the same bytes again (points are written rounded to 1e-4 px). Nothing may panic.

/// Checks one input; panics (a finding) when the property breaks.
pub fn check_drawing_bytes(data: &[u8]) {
    use blockworld::drawing::LineDrawing;
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(drawing) = LineDrawing::from_json(text) else {
        return;
    };
    let json = drawing.to_json();
    assert!(!json.contains("null"), "null written:\n{json}");
    let again = LineDrawing::from_json(&json)
        .unwrap_or_else(|e| panic!("a read drawing does not read back: {e}\n{json}"));
    assert_eq!(again.to_json(), json, "writing a read drawing is not stable");
}
