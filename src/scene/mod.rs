//! The scene model: Fischer-Technik blocks resting on the floor (Chapter VI, Figure 6.1), the
//! scene-file format that every later stage reads, and its validation.
//!
//! A [`Scene`] is plain data. `scene::file` reads and writes it as JSON (the contract of
//! docs/formats.md "Scene files"); [`Scene::validate`] rejects what cannot be a real
//! stack:
//! blocks that overlap or sink below the floor, NaN poses.

mod catalog;
mod error;
mod file;
mod reconstruction;
mod sat;

pub use catalog::{
    basic_blocks, block_type, symmetry_rotations, BlockType, ConvexPolyhedron, RoundPart, Shape,
    CATALOG, ROUND_PRISM_SIDES,
};
pub use error::SceneError;
pub use file::{
    parse_reconstruction, parse_scene, parse_scene_with_progress, read_reconstruction, read_scene,
    read_scene_with_progress, reconstruction_to_json, scene_to_json, write_reconstruction,
    write_scene, write_scene_with,
};
pub use reconstruction::{CsgNode, Evidence, ReconStatus, Reconstruction, ViewEvidence};

use crate::geom::{bounds3, outside_world, touching_box_pairs, DVec3, CONTACT_TOL_MM};
use glam::DQuat;
use serde::{Deserialize, Serialize};

/// `n` Baustein 15 in layers of `side` x `side` touching cubes, filled layer by layer from the
/// floor (a stable stack whose every view shows seams): the one stack generator of the
/// benchmarks (docs/benchmarks.md "Benchmarks") and of the tests that count their cost.
pub fn b15_layers(n: usize, side: usize, name: String) -> Scene {
    let side = side.max(1);
    let blocks = (0..n)
        .map(|i| {
            let (layer, cell) = (i / (side * side), i % (side * side));
            let centre = DVec3::new(
                (cell % side) as f64 * 15.0,
                layer as f64 * 15.0 + 7.5,
                (cell / side) as f64 * 15.0,
            );
            Block::new("b15", centre, 0.0)
        })
        .collect();
    Scene::new(name, blocks)
}

/// How a block's orientation was given in its scene file; kept so a file round-trips as written.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Orientation {
    /// Rotation about +y in degrees (`"yaw_deg"`, default 0).
    YawDeg(f64),
    /// A unit quaternion `[x, y, z, w]` (`"rotation"`; settled scenes carry it).
    Quaternion(DQuat),
}

impl Orientation {
    /// The orientation as a unit quaternion.
    pub fn quat(&self) -> DQuat {
        match *self {
            Orientation::YawDeg(deg) => DQuat::from_rotation_y(deg.to_radians()),
            Orientation::Quaternion(q) => q,
        }
    }
}

/// One block placed in the world.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Block {
    /// Its catalog entry.
    pub block_type: &'static BlockType,
    /// Centre of its bounding box in world mm.
    pub center_mm: DVec3,
    /// Its orientation.
    pub orientation: Orientation,
}

impl Block {
    /// A block of catalog type `id` at `center_mm` turned `yaw_deg` about +y.
    /// Panics on an unknown id: for tests and generators that use catalog ids only.
    pub fn new(id: &str, center_mm: DVec3, yaw_deg: f64) -> Block {
        Block {
            block_type: block_type(id).unwrap_or_else(|| panic!("unknown block type {id}")),
            center_mm,
            orientation: Orientation::YawDeg(yaw_deg),
        }
    }

    /// The block's rotation as a unit quaternion.
    pub fn rotation(&self) -> DQuat {
        self.orientation.quat()
    }

    /// World position of local point `p_mm`.
    pub fn world_point(&self, p_mm: DVec3) -> DVec3 {
        self.center_mm + self.rotation() * p_mm
    }

    /// The polyhedron's vertices in world mm, in catalog order.
    pub fn world_vertices(&self) -> Vec<DVec3> {
        let q = self.rotation();
        self.block_type
            .vertices()
            .map(|v| self.center_mm + q * v)
            .collect()
    }

    /// Outward unit normal of face `f` in world coordinates.
    pub fn world_face_normal(&self, f: usize) -> DVec3 {
        self.rotation() * self.block_type.face_normal(f)
    }

    /// Volume in mm^3.
    pub fn volume_mm3(&self) -> f64 {
        self.block_type.volume_mm3()
    }

    /// Height of its lowest vertex above the floor, mm: where it rests.
    pub fn bottom_mm(&self) -> f64 {
        self.world_vertices()
            .iter()
            .map(|v| v.y)
            .fold(f64::INFINITY, f64::min)
    }
}

/// The layers of a stack (Chapter V: "classify the number of levels"): the distinct resting
/// heights of block bottoms, ascending. Sorted bottoms join the current layer while within
/// `tol_mm` of its lowest bottom; a higher one starts the next layer. The one home of layer
/// counting: settling, scoring and the recognizer use it.
pub fn layer_bottoms_mm(blocks: &[Block], tol_mm: f64) -> Vec<f64> {
    let mut sorted: Vec<f64> = blocks.iter().map(Block::bottom_mm).collect();
    sorted.sort_by(f64::total_cmp);
    let mut layers: Vec<f64> = Vec::new();
    for b in sorted {
        if layers.last().is_none_or(|&d| b - d > tol_mm) {
            layers.push(b);
        }
    }
    layers
}

/// The layer of a block whose bottom is `bottom_mm`: how many layers of `layers` (from
/// [`layer_bottoms_mm`]) lie more than `tol_mm` below it (0 on the floor).
pub fn layer_index(layers: &[f64], bottom_mm: f64, tol_mm: f64) -> usize {
    layers.iter().filter(|&&d| bottom_mm - d > tol_mm).count()
}

/// What the thesis's method is expected to do with a scene (Chapter VII constraints).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Expect {
    /// `false` marks a scene the method is known not to cover.
    pub supported: bool,
    /// Why not, in the thesis's words where it has them (Ch. VII, Figure 7.2).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
}

/// The polyhedron vertices of `blocks` in world mm, block by block: the points a camera is
/// framed around (`Camera::frame`), the one home of that idiom for a scene or a bare block list.
pub fn world_vertices(blocks: &[Block]) -> Vec<DVec3> {
    blocks.iter().flat_map(|b| b.world_vertices()).collect()
}

/// `true` when `got` holds the blocks of `truth`: as many blocks, and for each of `truth` one of
/// `got` of the same type with every corner within `tol_mm` of one of its corners (the same
/// solid whatever symmetry its turn has; a wedge has none, so its facing counts). The one home
/// of this comparison for the unit and integration tests.
pub fn same_blocks(got: &[Block], truth: &[Block], tol_mm: f64) -> bool {
    got.len() == truth.len()
        && truth.iter().all(|t| {
            let corners = t.world_vertices();
            got.iter().any(|b| {
                let mine = b.world_vertices();
                b.block_type.id == t.block_type.id
                    && corners
                        .iter()
                        .all(|p| mine.iter().any(|q| q.distance(*p) < tol_mm))
            })
        })
}

/// A scene: blocks on the floor plus an optional expectation and provenance. A recognizer's
/// answer is a [`Reconstruction`].
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// A short name (`"two_layer"`).
    pub name: String,
    /// The blocks, in file order; their index + 1 is the id in `ids_<view>.png`.
    pub blocks: Vec<Block>,
    /// Whether the thesis's method covers the scene.
    pub expect: Option<Expect>,
    /// Free-form provenance (generator family, seed, settling report), kept as written.
    pub meta: Option<serde_json::Map<String, serde_json::Value>>,
}

impl Scene {
    /// Every block's polyhedron vertices in world mm, block by block: the points a camera is
    /// framed around (`Camera::frame`); see [`world_vertices`].
    pub fn world_vertices(&self) -> Vec<DVec3> {
        world_vertices(&self.blocks)
    }

    /// A scene with the given name and blocks and no metadata.
    pub fn new(name: impl Into<String>, blocks: Vec<Block>) -> Scene {
        Scene {
            name: name.into(),
            blocks,
            expect: None,
            meta: None,
        }
    }

    /// `true` unless `expect.supported` is `false`.
    pub fn is_supported(&self) -> bool {
        self.expect.as_ref().is_none_or(|e| e.supported)
    }

    /// World-space axis-aligned bounds (min, max) of all blocks, in mm; `None` when empty.
    pub fn bounds_mm(&self) -> Option<(DVec3, DVec3)> {
        bounds3(self.world_vertices())
    }

    /// Checks that every block is finite, rests on or above the floor and overlaps no other
    /// block by more than [`CONTACT_TOL_MM`]. `source` names the file in error messages.
    pub fn validate(&self, source: &str) -> Result<(), SceneError> {
        self.validate_with_progress(source, &|_, _| {})
    }

    /// [`Scene::validate`] reporting `(done, total)` over the block pairs whose bounding boxes
    /// touch (each costs a separating-axis test; a 1,000-block stack has about 13,000).
    pub fn validate_with_progress(
        &self,
        source: &str,
        progress: &(dyn Fn(u64, u64) + Sync),
    ) -> Result<(), SceneError> {
        for (index, b) in self.blocks.iter().enumerate() {
            let q = b.rotation();
            let finite = b.center_mm.is_finite() && q.is_finite();
            if !finite {
                return Err(SceneError::NotFinite {
                    source_name: source.to_string(),
                    index,
                });
            }
            check_in_world(b, index, source)?;
            let lowest = b
                .world_vertices()
                .iter()
                .map(|v| v.y)
                .fold(f64::INFINITY, f64::min);
            if lowest < -CONTACT_TOL_MM {
                return Err(SceneError::BelowFloor {
                    source_name: source.to_string(),
                    index,
                    depth_mm: -lowest,
                });
            }
        }
        // Blocks whose bounding boxes are disjoint cannot overlap (the separating-axis test is
        // exact for convex blocks), so only pairs with touching boxes pay for it, and a sweep
        // along x finds those pairs without testing every pair (a 20,000-block grid took 1 s
        // with every pair's boxes compared).
        let boxes: Vec<(DVec3, DVec3)> = self
            .blocks
            .iter()
            .map(|b| bounds3(b.world_vertices()).unwrap_or((b.center_mm, b.center_mm)))
            .collect();
        let pairs = touching_box_pairs(&boxes);
        let total = pairs.len() as u64;
        for (n, [a, b]) in pairs.into_iter().enumerate() {
            progress(n as u64 + 1, total);
            let depth = sat::penetration_depth_mm(&self.blocks[a], &self.blocks[b]);
            if depth > CONTACT_TOL_MM {
                return Err(SceneError::Overlap {
                    source_name: source.to_string(),
                    a,
                    b,
                    depth_mm: depth,
                });
            }
        }
        Ok(())
    }
}

/// Refuses a block with a vertex outside the world extent (docs/formats.md "Conventions"): finite but
/// huge coordinates would overflow the renderer's f32 and write `null` into cameras and glTF.
pub(crate) fn check_in_world(b: &Block, index: usize, source: &str) -> Result<(), SceneError> {
    match b.world_vertices().into_iter().find_map(outside_world) {
        Some(message) => Err(SceneError::OutsideWorld {
            source_name: source.to_string(),
            index,
            message,
        }),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Regression: validation ran the separating-axis test on every pair (a 5,000-block grid
    /// took 78 s); the bounding-box pre-check must still find the first overlapping pair, also
    /// between turned blocks whose boxes overlap while the blocks only touch.
    #[test]
    fn bounding_box_precheck_keeps_every_overlap() {
        let grid: Vec<Block> = (0..900)
            .map(|i| {
                Block::new(
                    "b15",
                    DVec3::new((i % 30) as f64 * 15.0, 7.5, (i / 30) as f64 * 15.0),
                    0.0,
                )
            })
            .collect();
        let mut scene = Scene::new("grid", grid);
        scene.validate("g").unwrap();
        scene
            .blocks
            .push(Block::new("b15", DVec3::new(440.0, 7.5, 15.0), 0.0));
        match scene.validate("g") {
            Err(SceneError::Overlap { a: 59, b: 900, .. }) => {}
            other => panic!("expected blocks 59 and 900, got {other:?}"),
        }
        // Two b15 turned 45 degrees, 21.3 mm apart along x: the boxes (21.2 mm wide) overlap,
        // the blocks do not; 20 mm apart they do.
        let turned = |x: f64| Block::new("b15", DVec3::new(x, 7.5, 0.0), 45.0);
        Scene::new("t", vec![turned(0.0), turned(21.3)])
            .validate("t")
            .unwrap();
        let close = Scene::new("t", vec![turned(0.0), turned(20.0)]);
        assert!(matches!(
            close.validate("t"),
            Err(SceneError::Overlap { a: 0, b: 1, .. })
        ));
    }

    #[test]
    fn same_blocks_is_blind_to_symmetry_but_not_to_a_shift_a_facing_or_a_type() {
        let b30 = Block::new("b30", DVec3::new(15.0, 7.5, 7.5), 0.0);
        let wedge = Block::new("w30", DVec3::new(0.0, 7.5, 0.0), 0.0);
        let truth = [b30, wedge];
        let turned = Block::new("b30", DVec3::new(15.0, 7.5, 7.5), 180.0);
        assert!(same_blocks(&[wedge, turned], &truth, 0.05));
        let shifted = Block::new("b30", DVec3::new(15.1, 7.5, 7.5), 0.0);
        assert!(!same_blocks(&[shifted, wedge], &truth, 0.05));
        let facing_back = Block::new("w30", DVec3::new(0.0, 7.5, 0.0), 180.0);
        assert!(!same_blocks(&[b30, facing_back], &truth, 0.05));
        let cube = Block::new("b15", DVec3::new(15.0, 7.5, 7.5), 0.0);
        assert!(!same_blocks(&[cube, wedge], &truth, 0.05));
        assert!(!same_blocks(&[b30], &truth, 0.05));
    }

    #[test]
    fn two_layer_stack_is_valid_and_overlap_is_caught() {
        let ok = Scene::new(
            "t",
            vec![
                Block::new("b30", DVec3::new(0.0, 7.5, 0.0), 0.0),
                Block::new("b15", DVec3::new(0.0, 22.5, 0.0), 0.0),
            ],
        );
        ok.validate("t").unwrap();
        let mut bad = ok.clone();
        bad.blocks[1].center_mm.y = 20.0;
        match bad.validate("t") {
            Err(SceneError::Overlap { a: 0, b: 1, .. }) => {}
            other => panic!("expected overlap, got {other:?}"),
        }
        let mut sunk = ok;
        sunk.blocks[0].center_mm.y = 7.0;
        assert!(matches!(
            sunk.validate("t"),
            Err(SceneError::BelowFloor { index: 0, .. })
        ));
    }

    /// The wedge and the round part validate by their own shapes: a round part next to a cube's
    /// corner is judged by its circle (the inscribed prism, within 0.009 mm), not its bounding
    /// box, and a wedge's slope lets a cube sit over its low end only where the slope clears it.
    #[test]
    fn wedge_and_round_part_overlaps_use_their_exact_shapes() {
        let cube = Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 0.0);
        // Centre 5.4 mm out along both x and z from the cube's corner: the circle clears the
        // corner by 5.4 sqrt 2 - 7.5 = 0.137 mm while the boxes overlap by 2.1 mm.
        let round_at = |a: f64| Block::new("c15", DVec3::new(7.5 + a, 7.5, 7.5 + a), 0.0);
        Scene::new("r", vec![cube, round_at(5.4)])
            .validate("r")
            .unwrap();
        // 5.2 mm out the circle cuts 0.146 mm into the corner.
        match Scene::new("r", vec![cube, round_at(5.2)]).validate("r") {
            Err(SceneError::Overlap { depth_mm, .. }) => {
                assert!((depth_mm - 0.146).abs() < 0.01, "{depth_mm}")
            }
            other => panic!("expected overlap, got {other:?}"),
        }
        // Two round parts 15 mm apart touch; 14.8 mm apart they overlap by 0.2 mm.
        let round = |x: f64| Block::new("c15", DVec3::new(x, 7.5, 0.0), 0.0);
        Scene::new("rr", vec![round(0.0), round(15.0)])
            .validate("rr")
            .unwrap();
        assert!(Scene::new("rr", vec![round(0.0), round(14.8)])
            .validate("rr")
            .is_err());
        // A wedge on the floor, its slope falling over x in 0..15: a cube resting at the slope's
        // foot level with its centre at x = 15 clears it above y = 15 only.
        let wedge = Block::new("w30", DVec3::new(0.0, 7.5, 0.0), 0.0);
        let over = |y: f64| Block::new("b15", DVec3::new(11.0, y, 0.0), 0.0);
        Scene::new("w", vec![wedge, over(22.5)])
            .validate("w")
            .unwrap();
        // At y = 16 the cube's bottom (8.5) cuts into the slope, whose height at x = 3.5 is 11.5.
        assert!(Scene::new("w", vec![wedge, over(16.0)])
            .validate("w")
            .is_err());
        // A cube against the wedge's vertical -x end touches; the box test alone would too.
        let end = Block::new("b15", DVec3::new(-22.5, 7.5, 0.0), 0.0);
        Scene::new("w", vec![wedge, end]).validate("w").unwrap();
    }
}
