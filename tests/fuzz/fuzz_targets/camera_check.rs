// The property `tests/mutants.rs` checks on camera files (`camera_<view>.json`) through
// `include!`: any bytes either fail to read as a camera or read as one that is written without
// `null` and reads back to the same camera. Nothing may panic.

/// Checks one input; panics (a finding) when the property breaks.
pub fn check_camera_bytes(data: &[u8]) {
    use blockworld::camera::{camera_json, parse_camera_json};
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(camera) = parse_camera_json(text) else {
        return;
    };
    let json = camera_json(&camera);
    assert!(!json.contains("null"), "null written:\n{json}");
    let again = parse_camera_json(&json)
        .unwrap_or_else(|e| panic!("a read camera does not read back: {e}\n{json}"));
    assert_eq!(again, camera, "round trip changed the camera");
}
