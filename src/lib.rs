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
pub mod scene;
pub mod score;
pub mod view;
pub mod vision;
