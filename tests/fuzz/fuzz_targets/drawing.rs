//! Fuzz target for the line-drawing reader (docs/formats.md "The exact line drawing"): arbitrary bytes
//! either fail to read or read back to the same drawing, with no `null` written. The property
//! lives in `drawing_check.rs`, which `tests/mutants.rs` replays on stable Rust over seeded
//! mutants of `tests/fixtures/vision/single_cube/lines_*.json`.
//!
//! Run: `RUSTC_BOOTSTRAP=1 cargo fuzz run --fuzz-dir tests/fuzz drawing tests/fuzz/corpus/drawing
//! tests/fixtures/vision/single_cube -- -max_total_time=120`
#![no_main]

include!("drawing_check.rs");

libfuzzer_sys::fuzz_target!(|data: &[u8]| check_drawing_bytes(data));
