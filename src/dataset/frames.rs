//! Rendered frames of a stability dataset's trajectories (`generate --trajectory-views`,
//! docs/stability.md "Rendered frames"): every Nth frame of a scene's trajectory, and its last,
//! drawn from chosen views with the cameras of the scene at rest-start (the cameras of its
//! still views), each with the ground truth a still view has: depth, block ids, the exact line
//! drawing and the camera. Written into the scene folder's `frames/` and listed in the
//! manifest like every other file.

use super::generate::{DrawnScene, SceneSpec};
use super::writer::{io_err, remove_temporaries, DatasetOptions};
use super::DatasetError;
use crate::camera::CornerView;
use crate::physics::{SettleParams, Trajectory};
use crate::render::{Look, RenderOptions, Renderer};
use std::collections::BTreeMap;
use std::path::Path;

/// The folder of the rendered frames inside a scene folder.
pub const FRAMES_DIR: &str = "frames";

/// Most pictures (frames x views) rendered per scene: with the default 4 s limit a trajectory
/// has at most 122 frames, so all four views fit at every 4th frame.
pub const MAX_FRAME_PICTURES: usize = 128;

/// The default `--trajectory-every`: every 4th frame (7.5 Hz of the 30 Hz trajectory).
pub const DEFAULT_FRAME_EVERY: u32 = 4;

/// Which frames of each trajectory are rendered, and from which views.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TrajectoryFrames {
    /// The views drawn at each chosen frame, in this order.
    pub views: Vec<CornerView>,
    /// Every how many frames one is drawn (1 = all); the last frame is always drawn.
    pub every: u32,
}

impl TrajectoryFrames {
    /// The frame indices drawn of a trajectory of `frames` frames: 0, N, 2N, ... and the last.
    pub fn chosen(&self, frames: usize) -> Vec<usize> {
        let mut out: Vec<usize> = (0..frames).step_by(self.every.max(1) as usize).collect();
        if frames > 0 && out.last() != Some(&(frames - 1)) {
            out.push(frames - 1);
        }
        out
    }

    /// Most pictures one scene can need under `settle`: the chosen frames of the longest
    /// trajectory times the views.
    pub fn max_pictures(&self, settle: &SettleParams) -> usize {
        self.chosen(Trajectory::max_frames(settle)).len() * self.views.len()
    }

    /// Checks the request before anything is written: at least one view, `every` of at least
    /// 1, at most [`MAX_FRAME_PICTURES`] pictures per scene, and line art at full size (the
    /// only look a camera fixed on given points draws). The message names the fix.
    pub fn check(&self, settle: &SettleParams, render: &RenderOptions) -> Result<(), String> {
        if self.views.is_empty() {
            return Err("--trajectory-views: name at least one view (ne, se, sw, nw)".into());
        }
        if self.every == 0 {
            return Err("--trajectory-every 0: give 1 or more (1 draws every frame)".into());
        }
        let pictures = self.max_pictures(settle);
        if pictures > MAX_FRAME_PICTURES {
            let fits = (self.every..=u32::MAX)
                .find(|&every| {
                    let f = TrajectoryFrames {
                        every,
                        ..self.clone()
                    };
                    f.max_pictures(settle) <= MAX_FRAME_PICTURES
                })
                .unwrap_or(u32::MAX);
            return Err(format!(
                "--trajectory-every {} with {} view(s) draws up to {pictures} pictures per scene \
                 ({} frames at most), more than {MAX_FRAME_PICTURES}; use --trajectory-every \
                 {fits} or more, or fewer --trajectory-views",
                self.every,
                self.views.len(),
                Trajectory::max_frames(settle)
            ));
        }
        if render.look != Look::LineArt || render.downsample != 1 {
            return Err(
                "--trajectory-views draws line art at full size; drop --look and --downsample"
                    .into(),
            );
        }
        Ok(())
    }
}

/// The name of a frame's file `file` (`view_ne.png`) in the scene folder:
/// `frames/f0003_view_ne.png` for frame 3.
pub fn frame_file_name(frame: usize, file: &str) -> String {
    format!("{FRAMES_DIR}/f{frame:04}_{file}")
}

/// Renders and writes the chosen frames of the scene's trajectory, when the dataset asks for
/// them; returns each file's name (under `frames/`) and sha256.
pub(super) fn write_trajectory_frames(
    scene_dir: &Path,
    spec: &SceneSpec,
    opts: &DatasetOptions,
    drawn: &DrawnScene,
    renderer: Option<&Renderer>,
) -> Result<BTreeMap<String, String>, DatasetError> {
    let mut files = BTreeMap::new();
    let frames = opts.stability.as_ref().and_then(|s| s.frames.as_ref());
    let (Some(frames), Some(t)) = (frames, &drawn.trajectory) else {
        return Ok(files);
    };
    let renderer = renderer.ok_or(DatasetError::NoRenderer)?;
    let dir = scene_dir.join(FRAMES_DIR);
    std::fs::create_dir_all(&dir).map_err(io_err(&dir))?;
    remove_temporaries(&dir, None)?;
    let render_opts = RenderOptions {
        seed: spec.seed,
        ..opts.render
    };
    // The cameras of the scene at rest-start: the still views' cameras, for every frame.
    let rest_start = drawn.scene.world_vertices();
    let render_err = |source| DatasetError::Render {
        id: spec.id(),
        source,
    };
    let bad_trajectory = |message: String| DatasetError::SceneFile {
        id: spec.id(),
        name: crate::dataset::TRAJECTORY_FILE.to_string(),
        message,
    };
    // The poses as `trajectory.bin` stores them (f32), so a reader of the file computes the
    // same ground truth for every frame.
    let t = Trajectory::from_bytes(&t.to_bytes()).map_err(|e| bad_trajectory(e.to_string()))?;
    for k in frames.chosen(t.frames.len()) {
        let scene = t
            .scene_at(&drawn.scene, k)
            .ok_or_else(|| bad_trajectory(format!("frame {k} does not hold one pose per block")))?;
        let views = renderer
            .render_views_framed(&scene, &frames.views, &render_opts, &rest_start)
            .map_err(render_err)?;
        let prefix = format!("f{k:04}_");
        let written =
            crate::output::write_rendered_views_prefixed(&dir, &prefix, &views, opts.file_sync)
                .map_err(io_err(&dir))?;
        files.extend(
            written
                .into_iter()
                .map(|w| (format!("{FRAMES_DIR}/{}", w.name), w.sha256)),
        );
    }
    Ok(files)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frames(views: usize, every: u32) -> TrajectoryFrames {
        TrajectoryFrames {
            views: CornerView::ALL[..views].to_vec(),
            every,
        }
    }

    #[test]
    fn every_nth_frame_and_the_last_are_chosen() {
        assert_eq!(frames(1, 3).chosen(8), vec![0, 3, 6, 7]);
        assert_eq!(frames(1, 3).chosen(7), vec![0, 3, 6]);
        assert_eq!(frames(1, 1).chosen(3), vec![0, 1, 2]);
        assert_eq!(frames(1, 10).chosen(1), vec![0]);
        assert!(frames(1, 2).chosen(0).is_empty());
        assert_eq!(
            frame_file_name(3, "view_ne.png"),
            "frames/f0003_view_ne.png"
        );
    }

    #[test]
    fn the_work_per_scene_is_bounded_and_bad_requests_name_the_fix() {
        let settle = SettleParams::default();
        let line_art = RenderOptions::default();
        assert_eq!(Trajectory::max_frames(&settle), 122);
        assert_eq!(frames(4, DEFAULT_FRAME_EVERY).max_pictures(&settle), 128);
        frames(4, DEFAULT_FRAME_EVERY)
            .check(&settle, &line_art)
            .unwrap();
        frames(1, 1).check(&settle, &line_art).unwrap();
        let err = frames(4, 3).check(&settle, &line_art).unwrap_err();
        assert!(err.contains("--trajectory-every 4 or more"), "{err}");
        let err = frames(2, 1).check(&settle, &line_art).unwrap_err();
        assert!(err.contains("--trajectory-every 2 or more"), "{err}");
        assert!(frames(1, 0)
            .check(&settle, &line_art)
            .unwrap_err()
            .contains("every 0"));
        assert!(frames(0, 4).check(&settle, &line_art).is_err());
        let photo = RenderOptions {
            look: Look::Photo,
            ..line_art
        };
        assert!(frames(1, 4)
            .check(&settle, &photo)
            .unwrap_err()
            .contains("--look"));
    }
}
