//! Seeded mutations of text inputs (scene files, line drawings, cameras, Appendix B files):
//! numbers swapped for extreme values, tokens inserted, spans deleted, duplicated or truncated,
//! bytes flipped. Shared by `tests/mutants.rs` and `tests/fuzz_corpus.rs`.

use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// Values a hostile file puts where a number belongs.
pub const EXTREMES: &[&str] = &[
    "1e308",
    "-1e308",
    "1e999",
    "-0",
    "0",
    "4e-320",
    "99999999999999999999",
    "-7.5",
    "10000",
    "10007.5",
    "-10007.5",
    "NaN",
    "null",
    "true",
    "\"b15\"",
    "[]",
    "{}",
    "[0, 0, 0]",
    "[0, 0, 0, 1]",
    "[0, 0, 0, 0]",
    "0.7071",
    "1e-9",
    "360",
    "-1e5",
];

/// Tokens inserted at random places.
pub const TOKENS: &[&str] = &[
    "\"type\"",
    "\"center\"",
    "\"yaw_deg\"",
    "\"rotation\"",
    "\"blocks\"",
    "\"name\"",
    "\"expect\"",
    "\"status\"",
    "\"csg\"",
    "\"meta\"",
    "\"b30\"",
    "\"b7_5\"",
    "\"b45\"",
    "\u{feff}",
    "\\u0000",
    "\\ud800",
    ",",
    "[",
    "]",
    "{",
    "}",
    ":",
    "\"",
    "\u{0}",
    "\n",
    "{\"type\": \"b15\", \"center\": [0, 7.5, 0]},",
];

/// Byte ranges of the numbers in `text`.
pub fn number_spans(text: &[u8]) -> Vec<(usize, usize)> {
    let mut spans = Vec::new();
    let mut i = 0;
    while i < text.len() {
        let starts = text[i].is_ascii_digit() || (text[i] == b'-' && i + 1 < text.len());
        let after_word = i > 0 && (text[i - 1].is_ascii_alphanumeric() || text[i - 1] == b'_');
        if starts && !after_word {
            let j = i
                + 1
                + text[i + 1..]
                    .iter()
                    .take_while(|c| c.is_ascii_digit() || b".eE+-".contains(c))
                    .count();
            spans.push((i, j));
            i = j;
        } else {
            i += 1;
        }
    }
    spans
}

/// One to three mutations of `text`.
pub fn mutate(text: &str, rng: &mut ChaCha8Rng) -> Vec<u8> {
    let mut b = text.as_bytes().to_vec();
    for _ in 0..rng.random_range(1..=3) {
        if b.is_empty() {
            break;
        }
        let at = rng.random_range(0..b.len());
        let len = rng.random_range(1..=40).min(b.len() - at);
        match rng.random_range(0..8) {
            0..=2 => {
                let spans = number_spans(&b);
                if let Some(&(s, e)) = spans.get(rng.random_range(0..spans.len().max(1))) {
                    let v = EXTREMES[rng.random_range(0..EXTREMES.len())];
                    b.splice(s..e, v.bytes());
                }
            }
            3 => {
                let t = TOKENS[rng.random_range(0..TOKENS.len())];
                b.splice(at..at, t.bytes());
            }
            4 => {
                b.drain(at..at + len);
            }
            5 => {
                let span: Vec<u8> = b[at..at + len].to_vec();
                b.splice(at..at, span);
            }
            6 => b[at] = rng.random(),
            _ => b.truncate(at),
        }
    }
    b
}
