//! Unstable draws for stability datasets (docs/stability.md "Balance and perturbations"): a
//! family's stable draw changed so that it should fall.
//!
//! - **shift**: a block resting on others (not on the floor) is pushed along one of the four
//!   horizontal directions, with every block it carries, until its centre of mass lies beyond
//!   its support by a drawn margin of 0.5 mm up to its whole length in that direction (beyond
//!   half its length the block is off its support altogether);
//! - **tilt**: a block that carries nothing is turned about one of its bottom edges by 10 to
//!   50 degrees, so it stands on that edge.
//!
//! Where the scene has blocks off the floor, a shift is drawn with probability 0.7 and a tilt
//! otherwise; a scene of one layer is tilted. Directions and edges are tried in a drawn order
//! until the changed blocks overlap nothing ([`Scene::validate`]); when none fits, the draw is
//! counted as unplaceable and redrawn. Whether the result falls is still up to the simulation.

use crate::geom::{bounds3, DQuat, DVec3};
use crate::physics::{centre_of_mass_overhang_mm, supports_of, Support};
use crate::scene::{Block, Orientation, Scene};
use rand::seq::SliceRandom;
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use serde_json::{json, Value};

/// Probability of a shift where a block is off the floor.
pub const SHIFT_PROBABILITY: f64 = 0.7;
/// The range of a tilt, degrees.
pub const TILT_RANGE_DEG: (f64, f64) = (10.0, 50.0);
/// Steps in which a shift advances until its margin is reached, mm.
const SHIFT_STEP_MM: f64 = 0.25;
/// Most a shift travels, mm (two Baustein 30 lengths).
const MAX_SHIFT_MM: f64 = 60.0;

/// What was changed, for `meta.perturbation`.
#[derive(Debug, Clone, PartialEq)]
pub enum Perturbation {
    /// `block` and the blocks it carries moved by `by_mm`.
    Shift {
        /// The block pushed.
        block: usize,
        /// The blocks moved with it, itself included.
        moved: Vec<usize>,
        /// The horizontal displacement, mm.
        by_mm: DVec3,
    },
    /// `block` turned about its bottom edge on the side `towards` by `angle_deg`.
    Tilt {
        /// The block tilted.
        block: usize,
        /// Horizontal unit direction from its centre to the edge it stands on.
        towards: DVec3,
        /// The turn, degrees.
        angle_deg: f64,
    },
}

impl Perturbation {
    /// The `meta.perturbation` entry.
    pub fn to_meta(&self) -> Value {
        let r6 = |x: f64| (x * 1e6).round() / 1e6;
        let v3 = |v: DVec3| json!([r6(v.x), r6(v.y), r6(v.z)]);
        match self {
            Perturbation::Shift {
                block,
                moved,
                by_mm,
            } => {
                json!({"kind": "shift", "block": block, "moved": moved, "by_mm": v3(*by_mm)})
            }
            Perturbation::Tilt {
                block,
                towards,
                angle_deg,
            } => {
                json!({"kind": "tilt", "block": block, "towards": v3(*towards), "angle_deg": r6(*angle_deg)})
            }
        }
    }
}

/// Changes `blocks` (a valid draw) so that it should fall; `None` when no change fits.
pub fn perturb(blocks: &mut [Block], rng: &mut ChaCha8Rng) -> Option<Perturbation> {
    let supports = supports_of(blocks);
    let raised: Vec<usize> = (0..blocks.len())
        .filter(|&i| !supports[i].contains(&Support::Floor))
        .collect();
    if !raised.is_empty() && rng.random_bool(SHIFT_PROBABILITY) {
        let block = raised[rng.random_range(0..raised.len())];
        if let Some(p) = shift(blocks, &supports, block, rng) {
            return Some(p);
        }
    }
    let bare: Vec<usize> = (0..blocks.len())
        .filter(|&i| !supports.iter().any(|s| s.contains(&Support::Block(i))))
        .collect();
    let block = *bare.get(rng.random_range(0..bare.len().max(1)))?;
    tilt(blocks, block, rng)
}

/// The four horizontal directions in a drawn order.
fn directions(rng: &mut ChaCha8Rng) -> [DVec3; 4] {
    let mut d = [DVec3::X, DVec3::NEG_X, DVec3::Z, DVec3::NEG_Z];
    d.shuffle(rng);
    d
}

/// `block` and every block resting on it, directly or through others, in index order.
fn carried(supports: &[Vec<Support>], block: usize) -> Vec<usize> {
    let mut set = vec![block];
    loop {
        let next = (0..supports.len()).find(|j| {
            !set.contains(j)
                && supports[*j]
                    .iter()
                    .any(|s| matches!(s, Support::Block(k) if set.contains(k)))
        });
        match next {
            Some(j) => set.push(j),
            None => break,
        }
    }
    set.sort_unstable();
    set
}

/// The shift of the module doc; `None` when no direction fits.
fn shift(
    blocks: &mut [Block],
    supports: &[Vec<Support>],
    block: usize,
    rng: &mut ChaCha8Rng,
) -> Option<Perturbation> {
    let moved = carried(supports, block);
    let (lo, hi) = bounds3(blocks[block].world_vertices())?;
    let unit = rng.random_range(0.0..1.0);
    for dir in directions(rng) {
        let length_mm = (hi - lo).dot(dir).abs();
        let margin_mm = 0.5 + unit * (length_mm - 0.5).max(0.0);
        let mut trial = blocks.to_vec();
        let mut travelled_mm = 0.0;
        while travelled_mm < MAX_SHIFT_MM {
            travelled_mm += SHIFT_STEP_MM;
            for &j in &moved {
                trial[j].center_mm = blocks[j].center_mm + dir * travelled_mm;
            }
            let beyond = centre_of_mass_overhang_mm(&trial, block).is_none_or(|d| d >= margin_mm);
            if beyond {
                break;
            }
        }
        if fits(&trial) {
            blocks.clone_from_slice(&trial);
            return Some(Perturbation::Shift {
                block,
                moved,
                by_mm: dir * travelled_mm,
            });
        }
    }
    None
}

/// The tilt of the module doc; `None` when no edge fits.
fn tilt(blocks: &mut [Block], block: usize, rng: &mut ChaCha8Rng) -> Option<Perturbation> {
    let (lo, hi) = TILT_RANGE_DEG;
    let angle_deg = rng.random_range(lo..hi);
    let b = blocks[block];
    let (local_lo, local_hi) = b.block_type.local_bounds_mm();
    let q = b.rotation().normalize();
    for dir in directions(rng) {
        // The bottom edge on the side `dir`, in the block's frame (its x or z axis).
        let local_dir = q.inverse() * dir;
        let along_x = local_dir.x.abs() > 0.5;
        let edge_local = if along_x {
            let x = if local_dir.x > 0.0 {
                local_hi.x
            } else {
                local_lo.x
            };
            DVec3::new(x, local_lo.y, 0.0)
        } else {
            let z = if local_dir.z > 0.0 {
                local_hi.z
            } else {
                local_lo.z
            };
            DVec3::new(0.0, local_lo.y, z)
        };
        let towards = (q * if along_x {
            DVec3::X * local_dir.x.signum()
        } else {
            DVec3::Z * local_dir.z.signum()
        })
        .normalize();
        let pivot = b.world_point(edge_local);
        let turn =
            DQuat::from_axis_angle(DVec3::Y.cross(towards).normalize(), angle_deg.to_radians());
        let mut trial = blocks.to_vec();
        trial[block].center_mm = pivot + turn * (b.center_mm - pivot);
        trial[block].orientation = Orientation::Quaternion(turn * q);
        if fits(&trial) {
            blocks.clone_from_slice(&trial);
            return Some(Perturbation::Tilt {
                block,
                towards,
                angle_deg,
            });
        }
    }
    None
}

/// The changed blocks still form a valid scene: nothing overlaps, nothing below the floor.
fn fits(blocks: &[Block]) -> bool {
    Scene::new("perturbed", blocks.to_vec())
        .validate("perturbed")
        .is_ok()
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    fn tower() -> Vec<Block> {
        vec![
            Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 0.0),
            Block::new("b15", DVec3::new(0.0, 22.5, 0.0), 0.0),
            Block::new("b15", DVec3::new(0.0, 37.5, 0.0), 0.0),
        ]
    }

    #[test]
    fn a_shift_puts_the_centre_of_mass_beyond_the_support() {
        let mut shifted = 0;
        for seed in 0..12 {
            let mut blocks = tower();
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let p = perturb(&mut blocks, &mut rng).expect("a tower can be perturbed");
            if let Perturbation::Shift {
                block,
                moved,
                by_mm,
            } = &p
            {
                shifted += 1;
                assert!(
                    *block >= 1 && moved.contains(block) && moved.contains(&2),
                    "{p:?}"
                );
                assert!(by_mm.length() > 7.5 - 1e-9, "{p:?}");
                let over = centre_of_mass_overhang_mm(&blocks, *block);
                assert!(over.is_none_or(|d| d >= 0.5), "{p:?} {over:?}");
            }
            assert!(fits(&blocks));
        }
        assert!(shifted >= 4, "{shifted} of 12 draws shifted");
    }

    #[test]
    fn a_tilt_stands_the_block_on_an_edge() {
        let mut blocks = vec![Block::new("b30", DVec3::new(0.0, 7.5, 0.0), 90.0)];
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let p = perturb(&mut blocks, &mut rng).expect("a lone block can be tilted");
        let Perturbation::Tilt { angle_deg, .. } = p else {
            panic!("one layer is tilted: {p:?}")
        };
        assert!((10.0..50.0).contains(&angle_deg));
        let low = blocks[0].bottom_mm();
        assert!(low.abs() < 1e-9, "the edge stays on the floor: {low}");
        let turned = blocks[0]
            .rotation()
            .angle_between(DQuat::from_rotation_y(90f64.to_radians()));
        assert!((turned.to_degrees() - angle_deg).abs() < 1e-6);
    }
}
