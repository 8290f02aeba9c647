//! The constructed reference reconstructions that prove the accuracy gate before a recognizer
//! exists (`golden/recon_reference/`, made by `blockworld bench accuracy --make-reference DIR`).
//!
//! For a supported scene, each truth block is "read" the way a recognizer working from corner
//! views would report it (Ch. VI: blocks are placed in uniform directions on layers): the
//! orientation snapped to a pure yaw, plus a small reading error: the centre moved in x and z
//! by up to ±[`READING_ERROR_MM`] and the yaw by up to ±[`READING_ERROR_DEG`], drawn from a
//! ChaCha8 stream seeded by a hash of the scene id (so the set is reproducible byte for byte).
//! One supported scene, the first by id with at least three blocks, is made deliberately
//! partial by dropping its highest block. A scene marked unsupported gets `status: unsupported`
//! with the expectation's reason, as a recognizer that knows its Chapter VII limits would say.

use crate::geom::DVec3;
use crate::scene::{Block, Orientation, Reconstruction, Scene};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Largest centre reading error in x and z, mm.
pub const READING_ERROR_MM: f64 = 0.02;
/// Largest yaw reading error, degrees.
pub const READING_ERROR_DEG: f64 = 0.1;

/// Reference reconstructions for a suite of `(id, truth)` pairs, in the same order.
pub fn make_reference_reconstructions(suite: &[(String, Scene)]) -> Vec<(String, Reconstruction)> {
    let mut ids: Vec<&(String, Scene)> = suite
        .iter()
        .filter(|(_, s)| s.is_supported() && s.blocks.len() >= 3)
        .collect();
    ids.sort_by(|a, b| a.0.cmp(&b.0));
    let partial_id = ids.first().map(|(id, _)| id.clone());
    suite
        .iter()
        .map(|(id, truth)| {
            (
                id.clone(),
                make_reference_reconstruction(id, truth, partial_id.as_deref() == Some(id)),
            )
        })
        .collect()
}

/// The reference reconstruction of one scene (see the module doc); `partial` drops the highest
/// block.
pub fn make_reference_reconstruction(id: &str, truth: &Scene, partial: bool) -> Reconstruction {
    let mut recon = Reconstruction::ok(truth.name.clone(), Vec::new());
    recon.csg = None;
    if !truth.is_supported() {
        recon.status = crate::scene::ReconStatus::Unsupported;
        let why = truth
            .expect
            .as_ref()
            .and_then(|e| e.reason.clone())
            .unwrap_or_else(|| "outside the method's constraints".into());
        recon.reason = Some(format!("constructed reference: declined ({why})"));
        return recon;
    }
    let mut rng = ChaCha8Rng::seed_from_u64(fnv1a(id));
    recon.blocks = truth
        .blocks
        .iter()
        .map(|b| {
            let dx = rng.random_range(-READING_ERROR_MM..=READING_ERROR_MM);
            let dz = rng.random_range(-READING_ERROR_MM..=READING_ERROR_MM);
            let dyaw = rng.random_range(-READING_ERROR_DEG..=READING_ERROR_DEG);
            Block {
                block_type: b.block_type,
                center_mm: b.center_mm + DVec3::new(round6(dx), 0.0, round6(dz)),
                orientation: Orientation::YawDeg(round6(yaw_deg(b) + dyaw)),
            }
        })
        .collect();
    if partial {
        if let Some(top) = (0..recon.blocks.len()).max_by(|&a, &b| {
            recon.blocks[a]
                .center_mm
                .y
                .total_cmp(&recon.blocks[b].center_mm.y)
        }) {
            recon.blocks.remove(top);
        }
        recon.reason =
            Some("constructed reference: highest block dropped on purpose (partial)".into());
    }
    recon
}

/// The block's heading, degrees (tilt ignored).
fn yaw_deg(b: &Block) -> f64 {
    crate::geom::heading_deg(b.rotation())
}

fn round6(v: f64) -> f64 {
    (v * 1e6).round() / 1e6
}

/// FNV-1a 64-bit hash of a string (a stable seed from a scene id).
fn fnv1a(s: &str) -> u64 {
    s.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}
