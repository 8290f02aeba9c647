//! Fuzz target for the vision front end: arbitrary bytes decoded as a picture and run through
//! edges, lines and vertices; the property lives in `vision_check.rs`, which
//! `tests/fuzz_corpus.rs` replays over the committed corpus `tests/fuzz/seeds/vision/`, and
//! `tests/vision.rs` (`random_small_pictures_never_panic`) runs a few hundred seeded random
//! pictures through the same calls, so CI needs no nightly compiler.
//!
//! Run (docs/cli.md "Exit codes and progress output", fuzzing): `cargo +nightly fuzz run --fuzz-dir
//! tests/fuzz vision tests/fuzz/corpus/vision tests/fuzz/seeds/vision -- -max_total_time=300
//! -max_len=20000`.
#![no_main]

include!("vision_check.rs");

libfuzzer_sys::fuzz_target!(|data: &[u8]| check_vision_bytes(data));
