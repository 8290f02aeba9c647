//! A fall as a glTF animation (docs/stability.md "The fall in glTF"): the scene's model (one
//! node per block, as [`super::scene_to_gltf`] writes it) and one animation, `fall`, with a
//! translation and a rotation channel per node, LINEAR, keyed at the recorded frame times.
//! Translations are in metres like the nodes; rotations are unit quaternions `[x, y, z, w]`,
//! each keyframe's sign chosen nearest the previous one so interpolation takes the short way.

use super::mesh::METRES_PER_MM;
use super::{DocumentBuilder, ExportError, GltfFiles};
use crate::geom::{DQuat, DVec3};
use crate::scene::Scene;
use gltf::json;
use json::validation::Checked::Valid;

/// The scene with its fall: `frames[k][i]` is block `i`'s (centre mm, rotation) at
/// `times_s[k]`; the times strictly increasing, one pose per block in every frame.
pub fn scene_fall_to_gltf(
    scene: &Scene,
    times_s: &[f64],
    frames: &[Vec<(DVec3, DQuat)>],
) -> Result<GltfFiles, ExportError> {
    scene_animation_to_gltf(scene, "fall", times_s, frames)
}

/// [`scene_fall_to_gltf`] with the animation named `name` (`plan --glb` writes its
/// `disassembly` with it, docs/plan.md "Output").
pub fn scene_animation_to_gltf(
    scene: &Scene,
    name: &str,
    times_s: &[f64],
    frames: &[Vec<(DVec3, DQuat)>],
) -> Result<GltfFiles, ExportError> {
    check_keyframes(scene, times_s, frames)?;
    let mut doc = DocumentBuilder::new(scene)?;
    let nodes = doc.push_block_nodes(scene, None)?;
    doc.push_fall(name, &nodes, times_s, frames);
    Ok(doc.finish(scene, nodes))
}

/// [`scene_fall_to_gltf`] as a binary glTF (`fall.glb`).
pub fn scene_fall_to_glb(
    scene: &Scene,
    times_s: &[f64],
    frames: &[Vec<(DVec3, DQuat)>],
) -> Result<Vec<u8>, ExportError> {
    scene_fall_to_gltf(scene, times_s, frames)?.to_glb()
}

/// Refuses keyframes that do not fit `scene`: no frame, a time count unlike the frame count,
/// times negative or not strictly increasing (in f32), a frame without one pose per block, a
/// non-finite or zero pose. Also the check of the Rerun fall timeline (`export::rrd`).
pub(super) fn check_keyframes(
    scene: &Scene,
    times_s: &[f64],
    frames: &[Vec<(DVec3, DQuat)>],
) -> Result<(), ExportError> {
    let bad = |reason: String| {
        Err(ExportError::BadAnimation {
            scene: scene.name.clone(),
            reason,
        })
    };
    if times_s.is_empty() || times_s.len() != frames.len() {
        return bad(format!(
            "has {} times for {} frames (need as many, at least one)",
            times_s.len(),
            frames.len()
        ));
    }
    // Strictly increasing also in f32, the precision glTF stores.
    let increasing = times_s.windows(2).all(|w| (w[0] as f32) < (w[1] as f32));
    if !increasing || times_s[0].is_nan() || times_s[0] < 0.0 {
        return bad("has times that are negative or not strictly increasing".into());
    }
    let n = scene.blocks.len();
    if let Some(k) = frames.iter().position(|f| f.len() != n) {
        return bad(format!(
            "frame {k} has {} poses for {n} blocks",
            frames[k].len()
        ));
    }
    let finite = |(c, q): &(DVec3, DQuat)| c.is_finite() && q.is_finite() && q.length() > 0.0;
    if let Some(k) = frames.iter().position(|f| !f.iter().all(finite)) {
        return bad(format!("frame {k} has a non-finite or zero pose"));
    }
    Ok(())
}

impl DocumentBuilder {
    /// Adds the animation `name` over `nodes` (block order).
    fn push_fall(
        &mut self,
        name: &str,
        nodes: &[json::Index<json::Node>],
        times_s: &[f64],
        frames: &[Vec<(DVec3, DQuat)>],
    ) {
        use json::accessor::{ComponentType, Type};
        let count = times_s.len();
        let times: Vec<f32> = times_s.iter().map(|&t| t as f32).collect();
        let bounds = (
            json::Value::from(vec![times[0]]),
            json::Value::from(vec![times[count - 1]]),
        );
        let input = self.push_accessor(
            &f32_bytes(times.iter().copied()),
            count,
            (ComponentType::F32, Type::Scalar),
            None,
            Some(bounds),
        );
        let mut samplers = Vec::with_capacity(2 * nodes.len());
        let mut channels = Vec::with_capacity(2 * nodes.len());
        for (i, node) in nodes.iter().enumerate() {
            let moves = frames.iter().flat_map(|f| {
                let c = f[i].0 * METRES_PER_MM;
                [c.x as f32, c.y as f32, c.z as f32]
            });
            let turns = continuous_rotations(frames.iter().map(|f| f[i].1))
                .into_iter()
                .flat_map(|q| q.to_array().map(|v| v as f32));
            let outputs = [
                (
                    f32_bytes(moves),
                    Type::Vec3,
                    json::animation::Property::Translation,
                ),
                (
                    f32_bytes(turns),
                    Type::Vec4,
                    json::animation::Property::Rotation,
                ),
            ];
            for (bytes, kind, path) in outputs {
                let output =
                    self.push_accessor(&bytes, count, (ComponentType::F32, kind), None, None);
                channels.push(json::animation::Channel {
                    sampler: json::Index::new(samplers.len() as u32),
                    target: json::animation::Target {
                        node: *node,
                        path: Valid(path),
                        extensions: Default::default(),
                        extras: Default::default(),
                    },
                    extensions: Default::default(),
                    extras: Default::default(),
                });
                samplers.push(json::animation::Sampler {
                    input,
                    interpolation: Valid(json::animation::Interpolation::Linear),
                    output,
                    extensions: Default::default(),
                    extras: Default::default(),
                });
            }
        }
        self.root.push(json::Animation {
            name: Some(name.to_string()),
            channels,
            samplers,
            extensions: Default::default(),
            extras: Default::default(),
        });
    }
}

/// Unit quaternions, each negated where that brings it nearer the one before.
fn continuous_rotations(qs: impl Iterator<Item = DQuat>) -> Vec<DQuat> {
    let mut out: Vec<DQuat> = Vec::new();
    for q in qs {
        let q = q.normalize();
        let q = match out.last() {
            Some(prev) if prev.dot(q) < 0.0 => -q,
            _ => q,
        };
        out.push(q);
    }
    out
}

fn f32_bytes(values: impl Iterator<Item = f32>) -> Vec<u8> {
    values.flat_map(f32::to_le_bytes).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Block;

    type Frames = Vec<Vec<(DVec3, DQuat)>>;

    fn falling() -> (Scene, Vec<f64>, Frames) {
        let scene = Scene::new(
            "fall",
            vec![
                Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 0.0),
                Block::new("b15", DVec3::new(10.0, 22.5, 0.0), 0.0),
            ],
        );
        let times = vec![0.0, 0.5, 1.0];
        let frames = (0..3)
            .map(|k| {
                let t = k as f64 * 0.5;
                vec![
                    (DVec3::new(0.0, 7.5, 0.0), DQuat::IDENTITY),
                    (
                        DVec3::new(10.0 + 5.0 * t, 22.5 - 10.0 * t, 0.0),
                        DQuat::from_rotation_z(-t),
                    ),
                ]
            })
            .collect();
        (scene, times, frames)
    }

    #[test]
    fn two_channels_per_block_keyed_at_the_frame_times() {
        let (scene, times, frames) = falling();
        let files = scene_fall_to_gltf(&scene, &times, &frames).unwrap();
        let a = &files.root.animations[0];
        assert_eq!((a.channels.len(), a.samplers.len()), (4, 4));
        let glb = files.to_glb().unwrap();
        let read = gltf::Gltf::from_slice(&glb).unwrap();
        let anim = read.animations().next().unwrap();
        let input = anim.samplers().next().unwrap().input();
        assert_eq!(input.count(), 3);
        assert_eq!(input.max(), Some(json::Value::from(vec![1.0f32])));
    }

    #[test]
    fn mismatched_keyframes_are_refused() {
        let (scene, times, mut frames) = falling();
        let short = scene_fall_to_glb(&scene, &times[..2], &frames).unwrap_err();
        assert!(
            short.to_string().contains("2 times for 3 frames"),
            "{short}"
        );
        let backwards = scene_fall_to_glb(&scene, &[0.0, 1.0, 0.5], &frames).unwrap_err();
        assert!(backwards.to_string().contains("strictly increasing"));
        frames[1].pop();
        let missing = scene_fall_to_glb(&scene, &times, &frames).unwrap_err();
        assert!(
            missing
                .to_string()
                .contains("frame 1 has 1 poses for 2 blocks"),
            "{missing}"
        );
    }

    #[test]
    fn rotations_keep_the_short_way() {
        let q = DQuat::from_rotation_z(0.1);
        let out = continuous_rotations([q, -q, q].into_iter());
        assert!(out.windows(2).all(|w| w[0].dot(w[1]) > 0.0));
    }
}
