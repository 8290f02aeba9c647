//! Fuzz target for the scene and reconstruction readers (docs/formats.md "Scene files"): arbitrary
//! bytes either fail with an error naming the source or read back to the same scene. The
//! property lives in `scene_check.rs`, which `tests/mutants.rs` replays on stable Rust over the
//! committed corpus `tests/fuzz/seeds/scene/`.
//!
//! Run (new inputs go to the ignored `tests/fuzz/corpus/scene`, the committed seeds are read):
//! `RUSTC_BOOTSTRAP=1 cargo fuzz run --fuzz-dir tests/fuzz scene tests/fuzz/corpus/scene
//! tests/fuzz/seeds/scene -- -max_total_time=120`
#![no_main]

include!("scene_check.rs");

libfuzzer_sys::fuzz_target!(|data: &[u8]| check_scene_bytes(data));
