//! Fuzz target for Kanade's labeller (`blockworld label`): arbitrary bytes become a line
//! drawing and run through validation, both catalogs, the labelling check and shape recovery;
//! the property lives in `label_check.rs`, which `tests/fuzz_corpus.rs` replays over the
//! committed corpus `tests/fuzz/seeds/label/`, and `tests/kanade.rs`
//! (`random_drawings_never_panic_and_found_labellings_check`) runs seeded random drawings through
//! the same library calls, so CI needs no nightly compiler.
//!
//! Run (docs/cli.md "Exit codes and progress output", fuzzing): `cargo +nightly fuzz run --fuzz-dir
//! tests/fuzz label tests/fuzz/corpus/label tests/fuzz/seeds/label -- -max_total_time=300`.
#![no_main]

include!("label_check.rs");

libfuzzer_sys::fuzz_target!(|data: &[u8]| check_label_bytes(data));
