//! # blockworld
//!
//! A rendering-and-simulation testbed for three-dimensional block recognition, built around the
//! thesis "A Modified Kanade Model for Three-Dimensional Object Recognition" (the seed). Data
//! flows one way, following the thesis's flow chart (Figure 5.3):
//!
//! `scene` → `physics` (rapier3d settling) → `render` (wgpu views + ground truth,
//! whose exact line drawing is [`linedraw`]) →
//! `vision` (Sobel, least-squares lines, six-bit codes) → `recognize` → `csg` → `score` (parry3d
//! volume overlap); `export` writes glTF and the thesis's data files. Every stage maps pixels
//! to the world through the one [`camera`]. `dataset` produces synthetic datasets at scale; the
//! command line lives in the binary (`src/main.rs`), so the library carries no clap, anyhow or
//! indicatif. Conventions (units, axes, picture coordinates) live in [`geom`]. Every public item
//! is documented (`missing_docs` is a lint error in CI).
//!
//! The reference for users is in `docs/` (docs/architecture.md "Stages" maps the modules);
//! `examples/recognize_scene.rs` runs the whole pipeline on a scene file.
//!
//! # Example
//!
//! A scene is plain data read from JSON (docs/formats.md "Scene files"); a recognizer's answer
//! is a [`scene::Reconstruction`], scored against the truth by volume overlap:
//!
//! ```
//! use blockworld::scene::{parse_scene, Reconstruction};
//! use blockworld::score::score_reconstruction;
//!
//! let truth = parse_scene(
//!     r#"{"name": "two_layer",
//!         "blocks": [{"type": "b30", "center": [0, 7.5, 0]},
//!                    {"type": "b15", "center": [0, 22.5, 0]}]}"#,
//!     "two_layer.json",
//! )?;
//! // An answer with the upper cube moved 7.5 mm (half its size) along x: IoU 8437.5 / 11812.5.
//! let mut blocks = truth.blocks.clone();
//! blocks[1].center_mm.x += 7.5;
//! let answer = Reconstruction::ok("answer", blocks);
//! let score = score_reconstruction(&truth, &answer)?;
//! assert!((score.iou - 8437.5 / 11812.5).abs() < 1e-6, "IoU {}", score.iou);
//! assert_eq!(score.verdict.as_str(), "partial");
//!
//! let exact = score_reconstruction(&truth, &Reconstruction::ok("same", truth.blocks.clone()))?;
//! assert_eq!(exact.verdict.as_str(), "exact");
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![warn(missing_docs)]

pub mod camera;
pub mod csg;
pub mod dataset;
pub mod drawing;
pub mod export;
pub mod geom;
pub mod io;
pub mod kanade;
pub mod linedraw;
pub mod output;
pub mod physics;
pub mod pipeline;
pub mod recognize;
pub mod render;
pub mod report;
pub mod scene;
pub mod score;
pub mod view;
pub mod vision;
