//! BOP records of a dataset's views (docs/export-bop.md): the layout of the 6D object pose
//! benchmark (bop_toolkit's `bop_datasets_format.md`), which BOP's own loaders
//! (`bop_toolkit_lib/inout.py`) and pose estimators read.
//!
//! The catalog is BOP's object-model set: object `k + 1` is catalog entry `k` (the COCO category
//! id), its model a PLY in millimetres in BOP's model frame ([`model_from_local`]). Per view:
//! the `scene_camera.json` entry (OpenCV camera, [`super::opencv`]), one `scene_gt.json` and one
//! `scene_gt_info.json` entry per block of the scene (every block, seen or not, so the
//! annotation index is the block index), and per block a full and a visible mask.
//!
//! Pure: plain data in, JSON values and masks out.

use super::coco::{category_id, compare_silhouette, SilhouetteAgreement};
use super::masks::{polygon_mask, silhouette_hull_px, silhouette_mask, visible_masks};
use super::masks::{Mask, MaskError};
use super::opencv::OpenCvCamera;
use crate::camera::{Camera, DEPTH_UNITS_PER_MM};
use crate::geom::{DMat3, DVec2, DVec3};
use crate::scene::{symmetry_rotations, BlockType, Scene};
use serde_json::{json, Value};
use std::fmt::Write as _;

/// Why a view could not be exported to BOP.
#[derive(Debug, thiserror::Error)]
pub enum BopError {
    /// BOP's `cam_K` is a pinhole camera; an orthographic view has none.
    #[error("the camera is orthographic, and BOP's scene_camera.json needs a pinhole camera (cam_K); make the dataset with `blockworld generate --projection perspective`")]
    Orthographic,
    /// The id picture does not fit the scene or the camera.
    #[error(transparent)]
    Mask(#[from] MaskError),
    /// The depth picture is not the camera's size.
    #[error("depth picture holds {pixels} pixels but the camera is {width_px}x{height_px}; re-render the view")]
    DepthSize {
        /// Pixels held.
        pixels: usize,
        /// Width, px.
        width_px: u32,
        /// Height, px.
        height_px: u32,
    },
    /// A block of the scene has a type the catalog does not list.
    #[error("block {index} has type {block_type:?}, which is not in the catalog")]
    UnknownType {
        /// Block index.
        index: usize,
        /// Its type id.
        block_type: String,
    },
}

/// BOP's model frame from a catalog block's local frame. Both are centred on the block's
/// bounding box; BOP's z points up where blockworld's local +y does, so the model frame is the
/// local frame turned a quarter turn about x: `(x, y, z)_local -> (x, -z, y)_model`.
pub fn model_from_local() -> DMat3 {
    DMat3::from_cols(DVec3::X, DVec3::Z, -DVec3::Y)
}

/// The model file name of a catalog block type, `obj_000001.ply` for the first.
pub fn model_file_name(obj_id: usize) -> String {
    format!("obj_{obj_id:06}.ply")
}

/// A catalog block type as BOP's ASCII PLY: millimetres in the model frame, each face
/// fan-triangulated with its own copies of its corners carrying the face's outward normal
/// (flat faces, sharp edges), triangles counter-clockwise seen from outside.
pub fn model_ply(block_type: &BlockType) -> String {
    let r = model_from_local();
    let mut vertices = String::new();
    let mut faces = String::new();
    let (mut n_vertices, mut n_faces) = (0usize, 0usize);
    for (f, face) in block_type.faces().iter().enumerate() {
        // `+ 0.0` writes a zero as 0, not -0.
        let n = r * block_type.face_normal(f) + 0.0;
        for &k in face.iter() {
            let p = r * DVec3::from_array(block_type.vertices_mm()[k as usize]) + 0.0;
            let _ = writeln!(vertices, "{} {} {} {} {} {}", p.x, p.y, p.z, n.x, n.y, n.z);
        }
        for k in 1..face.len() - 1 {
            let _ = writeln!(
                faces,
                "3 {} {} {}",
                n_vertices,
                n_vertices + k,
                n_vertices + k + 1
            );
            n_faces += 1;
        }
        n_vertices += face.len();
    }
    format!(
        "ply\nformat ascii 1.0\ncomment blockworld catalog block {} ({}), mm, BOP model frame (z up)\nelement vertex {n_vertices}\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\nelement face {n_faces}\nproperty list uchar int vertex_indices\nend_header\n{vertices}{faces}",
        block_type.id, block_type.name
    )
}

/// The half turn about the model's x axis, as columns.
const HALF_TURN_ABOUT_X: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]];

/// A catalog block type's `models_info.json` entry as bop_toolkit's `calc_model_info.py` and
/// `misc.get_symmetry_transformations` read it: `diameter` (the largest distance between two
/// model vertices), `min_x/y/z` and `size_x/y/z` (the model's box, mm), and its symmetries:
/// `symmetries_discrete` (row-major 4 x 4 rotations, the identity left out) and, for a round
/// part, `symmetries_continuous` about the model's z axis (its discrete list then holds only
/// the half turn about x, which BOP combines with every turn about z).
pub fn model_info(block_type: &BlockType) -> Value {
    let r = model_from_local();
    let points: Vec<DVec3> = block_type.vertices().map(|v| r * v).collect();
    let diameter = points
        .iter()
        .flat_map(|a| points.iter().map(move |b| a.distance(*b)))
        .fold(0.0, f64::max);
    let lo = points.iter().fold(DVec3::INFINITY, |a, p| a.min(*p));
    let hi = points.iter().fold(DVec3::NEG_INFINITY, |a, p| a.max(*p));
    let round = block_type.round().is_some();
    let discrete: Vec<Value> = symmetry_rotations(block_type)
        .into_iter()
        .map(|q| (r * DMat3::from_quat(q) * r.transpose()).to_cols_array_2d())
        // Every rotation of the cube group is a signed permutation: round off the quaternion's
        // last-bit noise.
        .map(|cols| cols.map(|c| c.map(|v| v.round() + 0.0)))
        .filter(|c| *c != DMat3::IDENTITY.to_cols_array_2d())
        // For a round part every turn about z is in the continuous symmetry already, so the one
        // half turn about x stands for the four that turn it upside down.
        .filter(|c| !round || *c == HALF_TURN_ABOUT_X)
        .map(|c| {
            let m = DMat3::from_cols_array_2d(&c);
            let row = |i: usize| m.row(i).extend(0.0).to_array();
            json!([row(0), row(1), row(2), [0.0, 0.0, 0.0, 1.0]].concat())
        })
        .collect();
    let mut info = json!({
        "diameter": diameter,
        "min_x": lo.x, "min_y": lo.y, "min_z": lo.z,
        "size_x": hi.x - lo.x, "size_y": hi.y - lo.y, "size_z": hi.z - lo.z,
    });
    if !discrete.is_empty() {
        info["symmetries_discrete"] = json!(discrete);
    }
    if round {
        info["symmetries_continuous"] = json!([{"axis": [0, 0, 1], "offset": [0, 0, 0]}]);
    }
    info
}

/// One view of one scene, as the dataset holds it.
#[derive(Debug, Clone, Copy)]
pub struct BopViewInput<'a> {
    /// The scene (block `k` has id `k + 1` in the id picture).
    pub scene: &'a Scene,
    /// The view's camera; must be a perspective one.
    pub camera: &'a Camera,
    /// The id picture in raster order, the camera's size.
    pub ids: &'a [u16],
    /// The depth picture in raster order (1 / 16 mm steps along the optical axis, 0 = nothing).
    pub depth: &'a [u16],
}

/// One block in one view.
#[derive(Debug, Clone)]
pub struct BopInstance {
    /// Its `scene_gt.json` entry.
    pub gt: Value,
    /// Its `scene_gt_info.json` entry.
    pub info: Value,
    /// The full mask (`mask/`): its silhouette, as if nothing hid it, cut at the picture's edge.
    pub mask: Mask,
    /// The visible mask (`mask_visib/`): its pixels in the id picture.
    pub mask_visib: Mask,
}

/// The BOP records of one view.
#[derive(Debug, Clone)]
pub struct BopView {
    /// Its `scene_camera.json` entry.
    pub camera: Value,
    /// One per block of the scene, in block order.
    pub instances: Vec<BopInstance>,
    /// Agreement of the full masks with the id picture.
    pub agreement: SilhouetteAgreement,
}

/// The `scene_camera.json` entry of a camera (docs/export-bop.md "Files"): `cam_K`,
/// `depth_scale` (mm per depth unit), `cam_R_w2c`, `cam_t_w2c` (mm); `None` for an
/// orthographic camera.
pub fn scene_camera_entry(camera: &Camera) -> Option<Value> {
    let cv = OpenCvCamera::from_camera(camera);
    let k = cv.k?;
    Some(json!({
        "cam_K": k.concat(),
        "depth_scale": 1.0 / DEPTH_UNITS_PER_MM,
        "cam_R_w2c": cv.r_w2c.concat(),
        "cam_t_w2c": cv.t_w2c_mm,
    }))
}

/// The records of one view (module doc).
pub fn bop_view(input: &BopViewInput) -> Result<BopView, BopError> {
    let camera = scene_camera_entry(input.camera).ok_or(BopError::Orthographic)?;
    let [w, h] = input.camera.size_px;
    if input.depth.len() != w as usize * h as usize {
        return Err(BopError::DepthSize {
            pixels: input.depth.len(),
            width_px: w,
            height_px: h,
        });
    }
    let cv = OpenCvCamera::from_camera(input.camera);
    let cam_from_world = DMat3::from_cols_array_2d(&cv.r_w2c).transpose();
    let local_from_model = model_from_local().transpose();
    let visible = visible_masks(input.ids, w, h, input.scene.blocks.len())?;
    let mut instances = Vec::new();
    let mut agreement = SilhouetteAgreement::default();
    for (index, (block, mask_visib)) in input.scene.blocks.iter().zip(visible).enumerate() {
        let obj_id = category_id(block.block_type.id).ok_or_else(|| BopError::UnknownType {
            index,
            block_type: block.block_type.id.to_string(),
        })?;
        let r_m2c = cam_from_world * DMat3::from_quat(block.rotation()) * local_from_model;
        let gt = json!({
            "obj_id": obj_id,
            "cam_R_m2c": r_m2c.transpose().to_cols_array(),
            "cam_t_m2c": cv.camera_from_world(block.center_mm).to_array(),
        });
        let mask = silhouette_mask(block, input.camera);
        agreement.add(compare_silhouette(&mask_visib, &mask, input.ids));
        let info = gt_info(
            &silhouette_hull_px(block, input.camera),
            &mask,
            &mask_visib,
            input,
        );
        instances.push(BopInstance {
            gt,
            info,
            mask,
            mask_visib,
        });
    }
    Ok(BopView {
        camera,
        instances,
        agreement,
    })
}

/// A block's `scene_gt_info.json` entry, field by field as bop_toolkit's `calc_gt_info.py`
/// computes it, with the exact masks in place of its depth test: `px_count_all` and
/// `bbox_obj` from the silhouette on a canvas three times the picture's size centred on it
/// (the truncated part counts), `px_count_valid` the silhouette pixels inside the picture with
/// a depth, `px_count_visib` the visible mask, `visib_fract` their ratio (0 when nothing of it
/// is in the canvas), boxes as `misc.calc_2d_bbox` gives them (`[x, y, x_max - x, y_max - y]`)
/// and `[-1, -1, -1, -1]`, both of them, when nothing of the block is seen.
fn gt_info(hull_px: &[DVec2], mask: &Mask, mask_visib: &Mask, input: &BopViewInput) -> Value {
    let [w, h] = input.camera.size_px;
    let offset = DVec2::new(f64::from(w), f64::from(h));
    let shifted: Vec<DVec2> = hull_px.iter().map(|p| *p + offset).collect();
    let large = polygon_mask(&shifted, 3 * w, 3 * h);
    let px_count_all = large.area_px();
    let px_count_visib = mask_visib.area_px();
    let px_count_valid = mask
        .pixels
        .iter()
        .zip(input.depth)
        .filter(|(&m, &d)| m && d > 0)
        .count();
    let seen = px_count_visib > 0;
    let bbox = |m: &Mask, shift: [i64; 2]| match (seen, m.bbox_px()) {
        (true, Some([x, y, bw, bh])) => [
            i64::from(x) - shift[0],
            i64::from(y) - shift[1],
            i64::from(bw) - 1,
            i64::from(bh) - 1,
        ],
        _ => [-1; 4],
    };
    json!({
        "bbox_obj": bbox(&large, [i64::from(w), i64::from(h)]),
        "bbox_visib": bbox(mask_visib, [0, 0]),
        "px_count_all": px_count_all,
        "px_count_valid": px_count_valid,
        "px_count_visib": px_count_visib,
        "visib_fract": if px_count_all > 0 { px_count_visib as f64 / px_count_all as f64 } else { 0.0 },
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::{CameraOptions, CornerView, Projection};
    use crate::scene::{block_type, Block, CATALOG};

    #[test]
    fn the_model_frame_puts_up_on_z_and_keeps_handedness() {
        let r = model_from_local();
        assert_eq!(r * DVec3::Y, DVec3::Z);
        assert_eq!(r.determinant(), 1.0);
        let b30 = model_info(block_type("b30").unwrap());
        assert_eq!(
            [
                b30["size_x"].as_f64(),
                b30["size_y"].as_f64(),
                b30["size_z"].as_f64()
            ],
            [Some(30.0), Some(15.0), Some(15.0)]
        );
        assert_eq!(b30["min_x"], -15.0);
        assert!((b30["diameter"].as_f64().unwrap() - (30f64.powi(2) + 450.0).sqrt()).abs() < 1e-12);
    }

    #[test]
    fn symmetries_follow_the_shapes() {
        let count = |id: &str| {
            let info = model_info(block_type(id).unwrap());
            let n = info["symmetries_discrete"].as_array().map_or(0, Vec::len);
            (n, info.get("symmetries_continuous").is_some())
        };
        // The identity is left out: a cube has 23 more, a 30 x 15 x 15 bar and a 15 x 7.5 x 15
        // plate 7, the wedge none, the round part one half turn (with every turn about z).
        assert_eq!(count("b15"), (23, false));
        assert_eq!(count("b30"), (7, false));
        assert_eq!(count("b7_5"), (7, false));
        assert_eq!(count("w30"), (0, false));
        assert_eq!(count("c15"), (1, true));
        // The b7_5's quarter turn is about the model's z (its thin local y).
        let info = model_info(block_type("b7_5").unwrap());
        let quarter_about_z = [0.0, -1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0];
        assert!(info["symmetries_discrete"]
            .as_array()
            .unwrap()
            .iter()
            .any(|m| m.as_array().unwrap()[..12] == quarter_about_z.map(|v| json!(v))[..]));
    }

    #[test]
    fn ply_models_list_every_face_as_triangles() {
        for t in CATALOG {
            let ply = model_ply(t);
            let triangles: usize = t.faces().iter().map(|f| f.len() - 2).sum();
            assert!(
                ply.contains(&format!("element face {triangles}\n")),
                "{}",
                t.id
            );
            let body = ply.split("end_header\n").nth(1).unwrap();
            assert_eq!(
                body.lines().filter(|l| l.starts_with("3 ")).count(),
                triangles
            );
        }
    }

    #[test]
    fn model_poses_put_the_model_where_the_camera_sees_the_block() {
        let block = Block::new("w30", DVec3::new(5.0, 7.5, -3.0), 30.0);
        let scene = Scene::new("one", vec![block]);
        let opts = CameraOptions {
            projection: Projection::Perspective { fov_y_deg: 40.0 },
            ..Default::default()
        };
        let camera = Camera::frame(&scene.world_vertices(), CornerView::Ne, &opts);
        let n = camera.size_px[0] as usize * camera.size_px[1] as usize;
        let (ids, depth) = (vec![0u16; n], vec![0u16; n]);
        let input = BopViewInput {
            scene: &scene,
            camera: &camera,
            ids: &ids,
            depth: &depth,
        };
        let view = bop_view(&input).unwrap();
        let gt = &view.instances[0].gt;
        let r: Vec<f64> = serde_json::from_value(gt["cam_R_m2c"].clone()).unwrap();
        let t: Vec<f64> = serde_json::from_value(gt["cam_t_m2c"].clone()).unwrap();
        let k: Vec<f64> = serde_json::from_value(view.camera["cam_K"].clone()).unwrap();
        let cv = OpenCvCamera::from_camera(&camera);
        for (local, world) in block.block_type.vertices().zip(block.world_vertices()) {
            let m = model_from_local() * local;
            let c: Vec<f64> = (0..3)
                .map(|i| r[3 * i] * m.x + r[3 * i + 1] * m.y + r[3 * i + 2] * m.z + t[i])
                .collect();
            let u = (k[0] * c[0] + k[1] * c[1] + k[2] * c[2]) / c[2];
            let v = (k[3] * c[0] + k[4] * c[1] + k[5] * c[2]) / c[2];
            let [u0, v0] = cv.pixel_from_world(world);
            assert!(
                (u - u0).abs() < 1e-9 && (v - v0).abs() < 1e-9,
                "{u} {v} vs {u0} {v0}"
            );
        }
        // Nothing seen: both boxes are BOP's "none".
        assert_eq!(
            view.instances[0].info["bbox_visib"],
            json!([-1, -1, -1, -1])
        );
        assert_eq!(view.instances[0].info["bbox_obj"], json!([-1, -1, -1, -1]));
        let ortho = Camera::frame(&scene.world_vertices(), CornerView::Ne, &Default::default());
        let input = BopViewInput {
            camera: &ortho,
            ..input
        };
        assert!(matches!(bop_view(&input), Err(BopError::Orthographic)));
    }
}
