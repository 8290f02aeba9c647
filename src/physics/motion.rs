//! What happens while a scene settles (docs/stability.md "The label"): the first block to move
//! beyond the tolerances and when, each block's largest displacement and turn, and on request
//! the trajectory, every block's pose at a fixed frame rate until rest or the time limit.
//!
//! Everything is measured against the scene's intended poses with the tolerances of
//! [`SettleParams`] (0.5 mm, 1 degree), the same measure the verdict uses, on every simulation
//! step (1/240 s, or the stiffened step of a tall stack).

use super::SettleParams;
use crate::geom::{DQuat, DVec3};
use crate::scene::Scene;

/// Frame rate of recorded trajectories, Hz; a frame every 8 steps of 1/240 s.
pub const TRAJECTORY_FPS: f64 = 30.0;

/// The first block to leave its intended pose by more than the tolerances.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FirstMove {
    /// Block index (0-based, scene order).
    pub block: usize,
    /// Simulated time of the first step on which it was beyond a tolerance, s.
    pub time_s: f64,
}

/// Every block's pose at fixed times: `frames[k][i]` is block `i`'s (centre mm, rotation) at
/// `times_s[k]`. Frame 0 is the start of the simulation (the blocks lifted by the drop gap),
/// then one frame every `1 / fps` s, and a last frame at the step the simulation ended (at rest
/// or at the time limit) when that falls between two frames.
#[derive(Debug, Clone, PartialEq)]
pub struct Trajectory {
    /// Nominal frame rate, Hz ([`TRAJECTORY_FPS`]).
    pub fps: f64,
    /// Time of each frame, s, strictly increasing from 0.
    pub times_s: Vec<f64>,
    /// Per frame, per block: centre in mm and unit rotation.
    pub frames: Vec<Vec<(DVec3, DQuat)>>,
}

/// The measurements of one simulation.
#[derive(Debug, Clone, PartialEq)]
pub struct Motion {
    /// The first block beyond a tolerance; `None` when no block ever was.
    pub first_moved: Option<FirstMove>,
    /// Per block, its largest centre displacement from the intended pose over the run, mm.
    pub max_drift_mm: Vec<f64>,
    /// Per block, its largest turn from the intended orientation over the run, degrees.
    pub max_turn_deg: Vec<f64>,
    /// The trajectory, when one was asked for.
    pub trajectory: Option<Trajectory>,
}

impl Motion {
    /// The largest displacement of any block at any time, mm (0 for an empty scene).
    pub fn max_displacement_mm(&self) -> f64 {
        self.max_drift_mm.iter().copied().fold(0.0, f64::max)
    }

    /// Blocks that were beyond a tolerance at some step.
    pub fn moved_blocks(&self, params: &SettleParams) -> Vec<usize> {
        (0..self.max_drift_mm.len())
            .filter(|&i| {
                self.max_drift_mm[i] > params.drift_tol_mm
                    || self.max_turn_deg[i] > params.turn_tol_deg
            })
            .collect()
    }
}

/// Watches the simulation step by step (see [`super::settle_recorded`]).
pub(super) struct Recorder {
    intended: Vec<(DVec3, DQuat)>,
    drift_tol_mm: f64,
    turn_tol_deg: f64,
    dt_s: f64,
    stride: u32,
    record_frames: bool,
    last_step: u32,
    motion: Motion,
}

impl Recorder {
    /// A recorder of `scene` measured with `params` (the tolerances); frames only when
    /// `record_frames`.
    pub(super) fn new(scene: &Scene, params: &SettleParams, record_frames: bool) -> Recorder {
        let n = scene.blocks.len();
        Recorder {
            intended: scene
                .blocks
                .iter()
                .map(|b| (b.center_mm, b.rotation().normalize()))
                .collect(),
            drift_tol_mm: params.drift_tol_mm,
            turn_tol_deg: params.turn_tol_deg,
            dt_s: params.dt_s,
            stride: 1,
            record_frames,
            last_step: 0,
            motion: Motion {
                first_moved: None,
                max_drift_mm: vec![0.0; n],
                max_turn_deg: vec![0.0; n],
                trajectory: record_frames.then(|| Trajectory {
                    fps: TRAJECTORY_FPS,
                    times_s: Vec::new(),
                    frames: Vec::new(),
                }),
            },
        }
    }

    /// The simulation starts with step `dt_s` (the stiffened one) at `poses`.
    pub(super) fn start(&mut self, dt_s: f64, poses: Vec<(DVec3, DQuat)>) {
        self.dt_s = dt_s;
        self.stride = ((1.0 / (TRAJECTORY_FPS * dt_s)).round() as u32).max(1);
        self.push_frame(0, poses);
    }

    /// The poses after simulation step `step` (from 1).
    pub(super) fn observe(&mut self, step: u32, poses: Vec<(DVec3, DQuat)>) {
        self.last_step = step;
        let mut worst: Option<(usize, f64)> = None;
        for (i, ((c, q), (c0, q0))) in poses.iter().zip(&self.intended).enumerate() {
            let drift = (*c - *c0).length();
            let turn = q0.angle_between(*q).to_degrees();
            let m = &mut self.motion;
            m.max_drift_mm[i] = m.max_drift_mm[i].max(drift);
            m.max_turn_deg[i] = m.max_turn_deg[i].max(turn);
            let beyond =
                (drift / self.drift_tol_mm.max(1e-12)).max(turn / self.turn_tol_deg.max(1e-12));
            if beyond > 1.0 && worst.is_none_or(|(_, w)| beyond > w) {
                worst = Some((i, beyond));
            }
        }
        if let (None, Some((block, _))) = (self.motion.first_moved, worst) {
            self.motion.first_moved = Some(FirstMove {
                block,
                time_s: step as f64 * self.dt_s,
            });
        }
        if step % self.stride == 0 {
            self.push_frame(step, poses);
        }
    }

    /// The measurements; the last poses become a frame when they fall between two frames.
    pub(super) fn finish(mut self, last_poses: Vec<(DVec3, DQuat)>) -> Motion {
        if self.last_step % self.stride != 0 {
            self.push_frame(self.last_step, last_poses);
        }
        self.motion
    }

    fn push_frame(&mut self, step: u32, poses: Vec<(DVec3, DQuat)>) {
        if let Some(t) = self
            .motion
            .trajectory
            .as_mut()
            .filter(|_| self.record_frames)
        {
            t.times_s.push(step as f64 * self.dt_s);
            t.frames.push(poses);
        }
    }
}

/// The first eight bytes of a trajectory file: the format and its version.
pub const TRAJECTORY_MAGIC: &[u8; 8] = b"BWTRAJ01";

/// Why trajectory bytes could not be read.
#[derive(Debug, thiserror::Error)]
pub enum TrajectoryError {
    /// The bytes are not a trajectory file of this version, or are cut short.
    #[error("not a blockworld trajectory (docs/stability.md \"Trajectories\"): {0}; regenerate it with `blockworld generate --keep-unstable --trajectory`")]
    Malformed(String),
}

impl Trajectory {
    /// Most frames a trajectory recorded under `params` can hold: one at the start, one every
    /// `1 / fps` s up to the time limit, and a last one at the final step (122 for the default
    /// 4 s at 30 Hz). Bounds the work of rendering frames (`generate --trajectory-views`).
    pub fn max_frames(params: &SettleParams) -> usize {
        (params.max_time_s.max(0.0) * TRAJECTORY_FPS).floor() as usize + 2
    }

    /// `scene` with every block at its pose of frame `k` (centre and rotation as a quaternion);
    /// `None` when there is no frame `k` or its block count differs from the scene's.
    pub fn scene_at(&self, scene: &Scene, k: usize) -> Option<Scene> {
        let poses = self.frames.get(k)?;
        if poses.len() != scene.blocks.len() {
            return None;
        }
        let mut out = scene.clone();
        for (b, (c, q)) in out.blocks.iter_mut().zip(poses) {
            b.center_mm = *c;
            b.orientation = crate::scene::Orientation::Quaternion(*q);
        }
        Some(out)
    }

    /// The binary file (docs/stability.md "Trajectories"), little-endian: the magic
    /// `BWTRAJ01`, u32 blocks, u32 frames, f32 fps, f32 time of each frame (s), then per frame
    /// and block seven f32: centre x, y, z (mm) and rotation x, y, z, w.
    pub fn to_bytes(&self) -> Vec<u8> {
        let blocks = self.frames.first().map_or(0, Vec::len);
        let mut out = Vec::with_capacity(20 + self.times_s.len() * (4 + blocks * 28));
        out.extend_from_slice(TRAJECTORY_MAGIC);
        out.extend_from_slice(&(blocks as u32).to_le_bytes());
        out.extend_from_slice(&(self.times_s.len() as u32).to_le_bytes());
        out.extend_from_slice(&(self.fps as f32).to_le_bytes());
        for t in &self.times_s {
            out.extend_from_slice(&(*t as f32).to_le_bytes());
        }
        for frame in &self.frames {
            for (c, q) in frame {
                let q = q.normalize();
                for v in [c.x, c.y, c.z, q.x, q.y, q.z, q.w] {
                    out.extend_from_slice(&(v as f32).to_le_bytes());
                }
            }
        }
        out
    }

    /// Reads [`Trajectory::to_bytes`] back (values as stored, in f32 precision).
    pub fn from_bytes(bytes: &[u8]) -> Result<Trajectory, TrajectoryError> {
        let bad = |m: &str| TrajectoryError::Malformed(m.to_string());
        if bytes.len() < 20 || &bytes[..8] != TRAJECTORY_MAGIC {
            return Err(bad("no BWTRAJ01 header"));
        }
        let word = |at: usize| -> [u8; 4] { bytes[at..at + 4].try_into().expect("4 bytes") };
        let blocks = u32::from_le_bytes(word(8)) as usize;
        let frames = u32::from_le_bytes(word(12)) as usize;
        let fps = f32::from_le_bytes(word(16)) as f64;
        let want = frames
            .checked_mul(4 + blocks.saturating_mul(28))
            .and_then(|n| n.checked_add(20));
        if want != Some(bytes.len()) {
            return Err(bad("its length does not match its block and frame counts"));
        }
        let f = |k: usize| f32::from_le_bytes(word(k * 4)) as f64;
        let times_s = (0..frames).map(|k| f(5 + k)).collect();
        let base = 5 + frames;
        let frames = (0..frames)
            .map(|k| {
                (0..blocks)
                    .map(|i| {
                        let o = base + (k * blocks + i) * 7;
                        let c = DVec3::new(f(o), f(o + 1), f(o + 2));
                        (c, DQuat::from_xyzw(f(o + 3), f(o + 4), f(o + 5), f(o + 6)))
                    })
                    .collect()
            })
            .collect();
        Ok(Trajectory {
            fps,
            times_s,
            frames,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trajectory_bytes_round_trip_and_truncation_is_refused() {
        let t = Trajectory {
            fps: TRAJECTORY_FPS,
            times_s: vec![0.0, 0.5],
            frames: vec![
                vec![(DVec3::new(1.0, 2.0, 3.0), DQuat::IDENTITY)],
                vec![(DVec3::new(1.5, 2.0, 3.0), DQuat::from_rotation_y(0.25))],
            ],
        };
        let bytes = t.to_bytes();
        assert_eq!(bytes.len(), 20 + 2 * 4 + 2 * 28);
        let back = Trajectory::from_bytes(&bytes).unwrap();
        assert_eq!(back.times_s, t.times_s);
        assert_eq!(back.frames[1][0].0, DVec3::new(1.5, 2.0, 3.0));
        assert!(back.frames[1][0].1.angle_between(t.frames[1][0].1) < 1e-6);
        let cut = Trajectory::from_bytes(&bytes[..bytes.len() - 1]).unwrap_err();
        assert!(cut.to_string().contains("length"), "{cut}");
        assert!(Trajectory::from_bytes(b"BWTRAJ02............").is_err());
    }
}
