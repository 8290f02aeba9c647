//! The entities of a recording: the world (floor, truth and recognized blocks), each camera's
//! pose and pinhole, and each view's pictures and line drawing (docs/rerun.md "Entity tree").

use super::{Fall, Picture, RecordingData, RrdError, ViewData, FALL_TIMELINE};
use crate::camera::{Camera, DEPTH_UNITS_PER_MM};
use crate::drawing::{LineDrawing, LineKind};
use crate::export::mesh::{flat_mesh, METRES_PER_MM};
use crate::geom::{bounds3, DQuat, DVec3};
use crate::scene::Scene;
use rerun::datatypes::{ChannelDatatype, ImageFormat, Quaternion};
use rerun::RecordingStream;

/// The floor: a thin box under the blocks, its top at height 0.
pub const FLOOR: &str = "world/floor";
/// Parent of the scene's blocks, one child per block (`world/truth/blocks/<index>`).
pub const BLOCKS_TRUTH: &str = "world/truth/blocks";
/// Parent of the recognizer's blocks, one child per block.
pub const BLOCKS_RECOGNIZED: &str = "world/recognized/blocks";
/// Depth picture steps per metre: the `meter` of every `DepthImage`.
pub const DEPTH_METER: f32 = (DEPTH_UNITS_PER_MM * 1000.0) as f32;

const TRUTH_RGB: [u8; 3] = [150, 170, 200];
const RECOGNIZED_RGB: [u8; 3] = [235, 140, 40];

/// What logging one entity can fail with.
pub(super) enum LogError {
    /// Bad input.
    Rrd(RrdError),
    /// The SDK refused the data.
    Stream(rerun::RecordingStreamError),
}

impl From<RrdError> for LogError {
    fn from(e: RrdError) -> Self {
        LogError::Rrd(e)
    }
}

impl From<rerun::RecordingStreamError> for LogError {
    fn from(e: rerun::RecordingStreamError) -> Self {
        LogError::Stream(e)
    }
}

/// The entity the 2D content of `camera`'s view lives under: `world/cameras/<v>` for a
/// perspective camera (under its `Pinhole`, so the picture shows in 3D), `views/<v>` for an
/// orthographic one (a 2D space of its own: Rerun's `Pinhole` is perspective only).
pub fn view_entity(camera: &Camera) -> String {
    if camera.is_orthographic() {
        format!("views/{}", camera.view.name())
    } else {
        format!("world/cameras/{}", camera.view.name())
    }
}

/// The pinhole intrinsics `[fx, fy, cx, cy]` in px of a perspective camera (image x right,
/// y down, origin at the top-left corner), read from its `clip_from_view` and `size_px`;
/// `None` for an orthographic camera.
pub fn pinhole_intrinsics_px(camera: &Camera) -> Option<[f64; 4]> {
    if camera.is_orthographic() {
        return None;
    }
    let p = &camera.clip_from_view;
    let [w, h] = [camera.size_px[0] as f64, camera.size_px[1] as f64];
    Some([
        p[0] * w / 2.0,
        p[5] * h / 2.0,
        w / 2.0 * (1.0 - p[8]),
        h / 2.0 * (1.0 + p[9]),
    ])
}

/// Logs the world's axes (+y up, right-handed), the floor and the blocks.
pub(super) fn log_world(rec: &RecordingStream, data: &RecordingData) -> Result<(), LogError> {
    rec.log_static("world", &rerun::ViewCoordinates::RIGHT_HAND_Y_UP())?;
    let scenes: Vec<&Scene> = [data.truth, data.recognized]
        .into_iter()
        .flatten()
        .collect();
    let corners: Vec<DVec3> = scenes
        .iter()
        .flat_map(|s| s.blocks.iter().flat_map(|b| b.world_vertices()))
        .collect();
    if let Some((lo, hi)) = bounds3(corners.iter().copied()) {
        let centre_m = (lo + hi) / 2.0 * METRES_PER_MM;
        let half_m = ((hi - lo).max_element() * 0.75 + 50.0) * METRES_PER_MM;
        rec.log_static(
            FLOOR,
            &rerun::Boxes3D::from_centers_and_half_sizes(
                [[centre_m.x as f32, -0.0005, centre_m.z as f32]],
                [[half_m as f32, 0.0005, half_m as f32]],
            )
            .with_colors([rerun::Color::from_rgb(90, 90, 90)])
            .with_fill_mode(rerun::FillMode::Solid),
        )?;
    }
    if let Some(scene) = data.truth {
        log_blocks(rec, BLOCKS_TRUTH, scene, TRUTH_RGB)?;
        log_block_classes(rec, scene)?;
        match data.fall {
            Some(fall) => log_fall(rec, scene, &fall)?,
            None => log_poses(rec, BLOCKS_TRUTH, scene)?,
        }
    }
    if let Some(scene) = data.recognized {
        log_blocks(rec, BLOCKS_RECOGNIZED, scene, RECOGNIZED_RGB)?;
        log_poses(rec, BLOCKS_RECOGNIZED, scene)?;
    }
    Ok(())
}

/// One `Mesh3D` per block under `parent`, in block-local metres (its pose is the entity's
/// `Transform3D`: [`log_poses`] or [`log_fall`]).
fn log_blocks(
    rec: &RecordingStream,
    parent: &str,
    scene: &Scene,
    rgb: [u8; 3],
) -> Result<(), LogError> {
    for (i, block) in scene.blocks.iter().enumerate() {
        let mesh = flat_mesh(block.block_type).map_err(RrdError::from)?;
        let triangles: Vec<[u32; 3]> = mesh
            .indices
            .chunks_exact(3)
            .map(|t| [t[0], t[1], t[2]])
            .collect();
        rec.log_static(
            format!("{parent}/{i}"),
            &rerun::Mesh3D::new(mesh.positions_m)
                .with_triangle_indices(triangles)
                .with_vertex_normals(mesh.normals)
                .with_albedo_factor(rerun::datatypes::Rgba32::from_rgb(rgb[0], rgb[1], rgb[2])),
        )?;
    }
    Ok(())
}

/// A block's pose as Rerun's transform: centre in metres, rotation as a quaternion.
fn block_transform(center_mm: DVec3, rotation: DQuat) -> rerun::Transform3D {
    let c = center_mm * METRES_PER_MM;
    let q = rotation.normalize();
    rerun::Transform3D::from_translation([c.x as f32, c.y as f32, c.z as f32]).with_quaternion(
        Quaternion::from_xyzw([q.x as f32, q.y as f32, q.z as f32, q.w as f32]),
    )
}

/// Each block's pose under `parent`, once (static).
fn log_poses(rec: &RecordingStream, parent: &str, scene: &Scene) -> Result<(), LogError> {
    for (i, block) in scene.blocks.iter().enumerate() {
        let pose = block_transform(block.center_mm, block.rotation());
        rec.log_static(format!("{parent}/{i}"), &pose)?;
    }
    Ok(())
}

/// The truth's block poses at every frame of `fall`, on the timeline [`FALL_TIMELINE`] (s).
fn log_fall(rec: &RecordingStream, scene: &Scene, fall: &Fall) -> Result<(), LogError> {
    crate::export::animation::check_keyframes(scene, fall.times_s, fall.frames)
        .map_err(RrdError::from)?;
    for (&t, poses) in fall.times_s.iter().zip(fall.frames) {
        rec.set_duration_secs(FALL_TIMELINE, t);
        for (i, &(c, q)) in poses.iter().enumerate() {
            rec.log(format!("{BLOCKS_TRUTH}/{i}"), &block_transform(c, q))?;
        }
    }
    rec.reset_time();
    Ok(())
}

/// The id pictures' classes: id `i + 1` is block `i` of the scene (its type in the label).
fn log_block_classes(rec: &RecordingStream, scene: &Scene) -> Result<(), LogError> {
    let mut classes: Vec<rerun::datatypes::ClassDescriptionMapElem> =
        vec![(0u16, "floor or background").into()];
    let labels: Vec<String> = scene
        .blocks
        .iter()
        .enumerate()
        .map(|(i, b)| format!("block {i} ({})", b.block_type.id))
        .collect();
    for (i, label) in labels.iter().enumerate() {
        let id = u16::try_from(i + 1).unwrap_or(u16::MAX);
        classes.push((id, label.as_str()).into());
    }
    rec.log_static("/", &rerun::AnnotationContext::new(classes))?;
    Ok(())
}

/// Logs one view: the camera's pose (and pinhole, when perspective), its pictures and lines.
pub(super) fn log_view(rec: &RecordingStream, view: &ViewData) -> Result<(), LogError> {
    let camera = view.camera;
    let name = camera.view.name();
    let pose_path = format!("world/cameras/{name}");
    let world_from_view = camera.view_matrix().inverse();
    let col = |k: usize| {
        let c = world_from_view.col(k);
        [c.x as f32, c.y as f32, c.z as f32]
    };
    let eye_m = camera.eye() * METRES_PER_MM;
    rec.log_static(
        pose_path.as_str(),
        &rerun::Transform3D::from_translation_mat3x3(
            [eye_m.x as f32, eye_m.y as f32, eye_m.z as f32],
            [col(0), col(1), col(2)],
        ),
    )?;
    if let Some([fx, fy, cx, cy]) = pinhole_intrinsics_px(camera) {
        let [w, h] = camera.size_px;
        rec.log_static(
            pose_path.as_str(),
            &rerun::Pinhole::new([
                [fx as f32, 0.0, 0.0],
                [0.0, fy as f32, 0.0],
                [cx as f32, cy as f32, 1.0],
            ])
            .with_resolution([w as f32, h as f32])
            .with_camera_xyz(rerun::components::ViewCoordinates::RUB)
            .with_image_plane_distance(0.1),
        )?;
    }
    log_pictures(rec, view, &view_entity(camera))?;
    if let Some(lines) = view.lines {
        let strips = line_strips(lines, camera.size_px[1]);
        rec.log_static(format!("{}/lines", view_entity(camera)), &strips)?;
    }
    Ok(())
}

/// Checks a picture's pixel count against its size.
fn checked<T>(
    view: &'static str,
    what: &'static str,
    p: &Picture<T>,
) -> Result<[u32; 2], RrdError> {
    let want = p.size_px[0] as usize * p.size_px[1] as usize;
    if p.pixels.len() != want {
        return Err(RrdError::PictureSize {
            view,
            what,
            size_px: p.size_px,
            got: p.pixels.len(),
            want,
        });
    }
    Ok(p.size_px)
}

/// Little-endian bytes of 16-bit pixels (Rerun's image buffers are native `u16`, little-endian).
fn le_bytes(pixels: &[u16]) -> Vec<u8> {
    pixels.iter().flat_map(|p| p.to_le_bytes()).collect()
}

/// The picture (`image`), depth (`depth`, [`DEPTH_METER`] steps per metre) and instance ids
/// (`ids`, a segmentation image) under `parent`.
fn log_pictures(rec: &RecordingStream, view: &ViewData, parent: &str) -> Result<(), LogError> {
    let name = view.camera.view.name();
    if let Some(p) = &view.picture {
        let size = checked(name, "picture", p)?;
        rec.log_static(
            format!("{parent}/image"),
            &rerun::Image::from_l8(p.pixels.to_vec(), size),
        )?;
    }
    if let Some(p) = &view.depth {
        let size = checked(name, "depth", p)?;
        rec.log_static(
            format!("{parent}/depth"),
            &rerun::DepthImage::from_gray16(le_bytes(p.pixels), size).with_meter(DEPTH_METER),
        )?;
    }
    if let Some(p) = &view.ids {
        let size = checked(name, "ids", p)?;
        rec.log_static(
            format!("{parent}/ids"),
            &rerun::SegmentationImage::new(
                le_bytes(p.pixels),
                ImageFormat::segmentation(size, ChannelDatatype::U16),
            )
            .with_opacity(0.5),
        )?;
    }
    Ok(())
}

/// One two-point strip per line, in image px (x right, y down: `height - y` of blockworld's
/// picture px), coloured by kind when the drawing has kinds.
fn line_strips(lines: &LineDrawing, height_px: u32) -> rerun::LineStrips2D {
    let h = height_px as f64;
    let strips: Vec<Vec<[f32; 2]>> = lines
        .lines
        .iter()
        .map(|&[a, b]| {
            [lines.points[a], lines.points[b]]
                .iter()
                .map(|p| [p.x as f32, (h - p.y) as f32])
                .collect()
        })
        .collect();
    let colors: Vec<rerun::Color> = (0..lines.lines.len())
        .map(|i| match lines.kinds.get(i) {
            Some(LineKind::Boundary) => rerun::Color::from_rgb(255, 60, 60),
            Some(LineKind::Convex) => rerun::Color::from_rgb(60, 200, 60),
            Some(LineKind::Concave) => rerun::Color::from_rgb(60, 120, 255),
            Some(LineKind::Crack) => rerun::Color::from_rgb(230, 200, 40),
            None => rerun::Color::from_rgb(255, 0, 255),
        })
        .collect();
    rerun::LineStrips2D::new(strips)
        .with_colors(colors)
        .with_radii([rerun::Radius::new_ui_points(1.0)])
        .with_draw_order(10.0)
}
