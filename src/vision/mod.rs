//! The vision front end (issue #5): Sobel with 3x3 smoothing and a threshold (Ch. II, VI),
//! least-squares lines, vertices and six-bit codes (Ch. IV, V).
