//! The off-screen renderer (issue #2): grayscale 45-degree corner views of a scene, rendered with
//! wgpu (Vulkan on lavapipe by default), plus their ground truth: depth, block ids and the exact
//! visible line drawing computed from geometry.
//!
//! `camera` is pure math shared with `vision`; `truth` is pure geometry; only `gpu` touches wgpu.

pub mod camera;
pub mod truth;

pub use camera::{Camera, CameraOptions, CornerView, Projection};
