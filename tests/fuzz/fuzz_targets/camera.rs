//! Fuzz target for the camera reader (`camera_<view>.json`, docs/rendering.md "Rendering"): arbitrary bytes
//! either fail to read as a camera or read as one that is written without `null` and reads back
//! to the same camera. The property lives in `camera_check.rs`, which `tests/mutants.rs` runs on
//! seeded mutants and `tests/fuzz_corpus.rs` replays over the committed corpus
//! `tests/fuzz/seeds/camera/`.
//!
//! Run: `cargo +nightly fuzz run --fuzz-dir tests/fuzz camera tests/fuzz/corpus/camera
//! tests/fuzz/seeds/camera -- -max_total_time=300`.
#![no_main]

include!("camera_check.rs");

libfuzzer_sys::fuzz_target!(|data: &[u8]| check_camera_bytes(data));
