use super::*;
use crate::camera::{CameraOptions, CornerView, Projection};
use crate::geom::{DQuat, DVec3};
use crate::scene::Block;

fn pair() -> Scene {
    Scene::new(
        "pair",
        vec![
            Block::new("b30", DVec3::new(0.0, 7.5, 0.0), 0.0),
            Block::new("b15", DVec3::new(0.0, 22.5, 0.0), 30.0),
        ],
    )
}

fn camera(projection: Projection, pixel_aspect: f64) -> Camera {
    let opts = CameraOptions {
        projection,
        pixel_aspect,
        ..CameraOptions::default()
    };
    Camera::frame(&pair().world_vertices(), CornerView::Se, &opts)
}

/// The pinhole of a perspective camera, applied in Rerun's way (camera axes right-up-back
/// turned to right-down-forward, then `u = fx X / Z + cx`), lands every block corner on the
/// picture px `Camera::picture_from_world` gives (image y = height - picture y).
#[test]
fn pinhole_intrinsics_project_as_the_camera_does() {
    for aspect in [1.0, 1.173913] {
        let cam = camera(Projection::Perspective { fov_y_deg: 30.0 }, aspect);
        let [fx, fy, cx, cy] = pinhole_intrinsics_px(&cam).unwrap();
        let h = cam.size_px[1] as f64;
        for b in &pair().blocks {
            for p in b.world_vertices() {
                let c = cam.view_matrix().transform_point3(p);
                let (x, y, z) = (c.x, -c.y, -c.z);
                let want = cam.picture_from_world(p);
                assert!((fx * x / z + cx - want.x).abs() < 1e-6);
                assert!((fy * y / z + cy - (h - want.y)).abs() < 1e-6);
            }
        }
    }
}

#[test]
fn orthographic_views_get_a_2d_space_and_no_pinhole() {
    let ortho = camera(Projection::Orthographic, 1.0);
    assert_eq!(pinhole_intrinsics_px(&ortho), None);
    assert_eq!(view_entity(&ortho), "views/se");
    let persp = camera(Projection::Perspective { fov_y_deg: 30.0 }, 1.0);
    assert_eq!(view_entity(&persp), "world/cameras/se");
}

#[test]
fn a_picture_of_the_wrong_size_is_refused() {
    let scene = pair();
    let cam = camera(Projection::Orthographic, 1.0);
    let short = vec![0u8; 10];
    fn with<'a>(scene: &'a Scene, cam: &'a Camera, pixels: &'a [u8]) -> RecordingData<'a> {
        RecordingData {
            name: "pair",
            truth: Some(scene),
            recognized: None,
            views: vec![ViewData {
                camera: cam,
                picture: Some(Picture {
                    size_px: cam.size_px,
                    pixels,
                }),
                depth: None,
                ids: None,
                lines: None,
            }],
            fall: None,
        }
    }
    let view = |pixels| with(&scene, &cam, pixels);
    let err = recording_to_rrd(&view(&short)).unwrap_err();
    assert!(
        matches!(err, RrdError::PictureSize { got: 10, .. }),
        "{err}"
    );
    let full = vec![0u8; (cam.size_px[0] * cam.size_px[1]) as usize];
    let bytes = recording_to_rrd(&view(&full)).unwrap();
    assert!(bytes.len() > full.len(), "{} bytes", bytes.len());
}

/// A fall whose frames do not hold one pose per block of the truth is refused, naming the
/// frame; one that fits is recorded.
#[test]
fn a_fall_must_fit_the_truth() {
    let scene = pair();
    let poses: Vec<(DVec3, DQuat)> = scene
        .blocks
        .iter()
        .map(|b| (b.center_mm, b.rotation()))
        .collect();
    let frames = vec![poses.clone(), poses[..1].to_vec()];
    let times_s = [0.0, 1.0 / 30.0];
    let data = |frames| RecordingData {
        name: "pair",
        truth: Some(&scene),
        recognized: None,
        views: vec![],
        fall: Some(Fall {
            times_s: &times_s,
            frames,
        }),
    };
    let err = recording_to_rrd(&data(&frames)).unwrap_err();
    assert!(
        err.to_string().contains("frame 1 has 1 poses for 2 blocks"),
        "{err}"
    );
    let fits = vec![poses.clone(), poses];
    assert!(!recording_to_rrd(&data(&fits)).unwrap().is_empty());
}
