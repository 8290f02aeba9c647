//! Fuzz target for the recognizer's input (docs/recognizer.md "Recognizer"): arbitrary bytes become line
//! drawings with their cameras and go through `recognize`; the property lives in
//! `recognize_check.rs`, which `tests/recognize_inputs.rs` also runs on seeded random bytes.
//!
//! Run: `RUSTC_BOOTSTRAP=1 cargo fuzz run --fuzz-dir tests/fuzz recognize -- -max_total_time=120`.
#![no_main]

include!("recognize_check.rs");

libfuzzer_sys::fuzz_target!(|data: &[u8]| check_recognizer_bytes(data));
