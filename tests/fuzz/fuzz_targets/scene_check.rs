// The property the `scene` fuzz target checks, shared with `tests/mutants.rs` (which replays
// the committed corpus `tests/fuzz/seeds/scene/` and thousands of seeded mutants on stable
// Rust) through `include!`: any bytes either fail to read as a scene or reconstruction with an
// error naming the source, or read as one whose JSON has no `null` where a number belongs and
// reads back to the same value. Nothing may panic.

/// Checks one input; panics (a finding) when the property breaks.
pub fn check_scene_bytes(data: &[u8]) {
    use blockworld::scene::{
        parse_reconstruction, parse_scene, reconstruction_to_json, scene_to_json,
    };
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    match parse_scene(text, "fuzz.json") {
        Ok(scene) => {
            let json = scene_to_json(&scene);
            let again = parse_scene(&json, "again.json")
                .unwrap_or_else(|e| panic!("a read scene does not read back: {e}\n{json}"));
            assert_eq!(again, scene, "round trip changed the scene");
        }
        Err(e) => assert!(e.to_string().contains("fuzz.json"), "unnamed source: {e}"),
    }
    match parse_reconstruction(text, "fuzz.json") {
        Ok(recon) => {
            let json = reconstruction_to_json(&recon);
            let again = parse_reconstruction(&json, "again.json")
                .unwrap_or_else(|e| panic!("a reconstruction does not read back: {e}\n{json}"));
            assert_eq!(again, recon, "round trip changed the reconstruction");
        }
        Err(e) => assert!(e.to_string().contains("fuzz.json"), "unnamed source: {e}"),
    }
}
