//! COCO `instances` records of a dataset's views (docs/export-coco.md): what detection and
//! segmentation stacks, pycocotools and FiftyOne load with no code.
//!
//! One image per view of every scene; categories are the catalog's block types; one annotation
//! per block seen in the view, its `segmentation` the visible mask read exactly from the id
//! picture as a compressed COCO RLE, `bbox` and `area` from that mask, `iscrowd` 0. Extra keys,
//! which COCO readers pass over: the full (amodal) mask from the block's projected silhouette
//! (`amodal_segmentation`, `amodal_bbox`, `amodal_area`, `visible_fraction`), the block's
//! index in its scene, and per image the camera in OpenCV's convention and the exact line
//! drawing with its six-bit codes in raster px.
//!
//! Pure: plain data in, JSON values out. Image and annotation ids are given by the caller when it
//! joins the views into one document ([`coco_document`]).

use super::masks::{silhouette_mask, visible_masks, Mask, MaskError};
use super::opencv::OpenCvCamera;
use super::wireframe::{wireframe_from_drawing, Wireframe, WireframeError};
use crate::camera::{Camera, DEPTH_UNITS_PER_MM};
use crate::drawing::LineDrawing;
use crate::scene::{Scene, CATALOG};
use serde_json::{json, Value};

/// Why a view could not be exported.
#[derive(Debug, thiserror::Error)]
pub enum CocoError {
    /// The id picture does not fit the scene or the camera.
    #[error(transparent)]
    Mask(#[from] MaskError),
    /// The line drawing names points it does not have.
    #[error(transparent)]
    Drawing(#[from] WireframeError),
    /// A block of the scene has a type the catalog does not list.
    #[error("block {index} has type {block_type:?}, which is not in the catalog")]
    UnknownType {
        /// Block index.
        index: usize,
        /// Its type id.
        block_type: String,
    },
}

/// One view of one scene, as the dataset holds it.
#[derive(Debug, Clone, Copy)]
pub struct ViewInput<'a> {
    /// The scene's id in the dataset (its folder name).
    pub scene_id: &'a str,
    /// The scene (`scene.json`: settled poses; block `k` has id `k + 1` in the id picture).
    pub scene: &'a Scene,
    /// The view's camera (`camera_<v>.json`).
    pub camera: &'a Camera,
    /// The id picture (`ids_<v>.png`) in raster order, the camera's size.
    pub ids: &'a [u16],
    /// The exact line drawing (`lines_<v>.json`).
    pub drawing: &'a LineDrawing,
    /// The picture's file name in the export.
    pub file_name: &'a str,
}

/// The COCO records of one view: the image (no `id` yet) and its annotations (no `id` or
/// `image_id` yet), with how well the silhouettes agree with the id picture.
#[derive(Debug, Clone)]
pub struct CocoView {
    /// The `images` entry.
    pub image: Value,
    /// The `annotations` entries, in block order.
    pub annotations: Vec<Value>,
    /// Agreement of the full masks with the id picture.
    pub agreement: SilhouetteAgreement,
}

/// How well the full (amodal) masks agree with the id picture: both counts are 0 when every
/// silhouette is rasterized exactly as the renderer drew it.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SilhouetteAgreement {
    /// Pixels of a block's visible mask outside its silhouette.
    pub visible_outside_px: u64,
    /// Pixels of a block's silhouette where the id picture shows floor or background (nothing
    /// but a block can hide a block, so these are silhouette pixels the renderer did not draw).
    pub silhouette_on_background_px: u64,
    /// Pixels of all silhouettes.
    pub silhouette_px: u64,
}

impl SilhouetteAgreement {
    /// Adds another view's counts.
    pub fn add(&mut self, other: SilhouetteAgreement) {
        self.visible_outside_px += other.visible_outside_px;
        self.silhouette_on_background_px += other.silhouette_on_background_px;
        self.silhouette_px += other.silhouette_px;
    }
}

/// The category id of a catalog block type: its position in the catalog plus one.
pub fn category_id(block_type_id: &str) -> Option<usize> {
    CATALOG
        .iter()
        .position(|t| t.id == block_type_id)
        .map(|k| k + 1)
}

/// The `categories` list: every catalog block type, `name` its scene-file id.
pub fn coco_categories() -> Value {
    CATALOG
        .iter()
        .enumerate()
        .map(|(k, t)| json!({"id": k + 1, "name": t.id, "supercategory": "block", "long_name": t.name}))
        .collect()
}

/// The whole COCO document of `images` and `annotations` (ids already set).
pub fn coco_document(images: Vec<Value>, annotations: Vec<Value>) -> Value {
    json!({
        "info": {"description": "blockworld dataset", "version": env!("CARGO_PKG_VERSION")},
        "licenses": [],
        "images": images,
        "annotations": annotations,
        "categories": coco_categories(),
    })
}

/// The records of one view (module doc).
pub fn coco_view(input: &ViewInput) -> Result<CocoView, CocoError> {
    let [w, h] = input.camera.size_px;
    let blocks = &input.scene.blocks;
    let visible = visible_masks(input.ids, w, h, blocks.len())?;
    let wireframe = wireframe_from_drawing(input.drawing, w, h)?;
    let mut agreement = SilhouetteAgreement::default();
    let mut annotations = Vec::new();
    for (index, (block, seen)) in blocks.iter().zip(&visible).enumerate() {
        let category = category_id(block.block_type.id).ok_or_else(|| CocoError::UnknownType {
            index,
            block_type: block.block_type.id.to_string(),
        })?;
        let full = silhouette_mask(block, input.camera);
        agreement.add(compare_silhouette(seen, &full, input.ids));
        let Some(bbox) = seen.bbox_px() else {
            continue;
        };
        let (area, full_area) = (seen.area_px(), full.area_px());
        annotations.push(json!({
            "category_id": category,
            "bbox": bbox,
            "area": area,
            "segmentation": rle_json(seen),
            "iscrowd": 0,
            "block_index": index,
            "amodal_bbox": full.bbox_px(),
            "amodal_area": full_area,
            "amodal_segmentation": rle_json(&full),
            "visible_fraction": area as f64 / full_area.max(area).max(1) as f64,
        }));
    }
    let image = json!({
        "file_name": input.file_name,
        "width": w,
        "height": h,
        "scene_id": input.scene_id,
        "view": input.camera.view.name(),
        "camera": camera_json(input.camera),
        "line_drawing": line_drawing_json(&wireframe),
    });
    Ok(CocoView {
        image,
        annotations,
        agreement,
    })
}

/// A mask as COCO's RLE object: `size` `[height, width]` and the compressed `counts` string.
pub fn rle_json(mask: &Mask) -> Value {
    json!({
        "size": [mask.height_px, mask.width_px],
        "counts": super::masks::rle_string(&mask.rle_counts()),
    })
}

/// How a block's visible mask and its full mask agree with the id picture `ids`.
pub(super) fn compare_silhouette(visible: &Mask, full: &Mask, ids: &[u16]) -> SilhouetteAgreement {
    let mut out = SilhouetteAgreement::default();
    for (i, (&v, &f)) in visible.pixels.iter().zip(&full.pixels).enumerate() {
        out.visible_outside_px += u64::from(v && !f);
        out.silhouette_on_background_px += u64::from(f && ids[i] == 0);
        out.silhouette_px += u64::from(f);
    }
    out
}

/// The camera as the exports write it (docs/exports.md "Cameras"): OpenCV's rotation and
/// translation (mm), `K` for a perspective camera, the 3 x 4 pixels-from-camera matrix for
/// either projection, the projection's name and the depth picture's scale.
pub fn camera_json(camera: &Camera) -> Value {
    let cv = OpenCvCamera::from_camera(camera);
    let flat = |m: &[[f64; 3]; 3]| m.iter().flatten().copied().collect::<Vec<f64>>();
    let mut out = json!({
        "projection": if camera.is_orthographic() { "orthographic" } else { "perspective" },
        "cam_R_w2c": flat(&cv.r_w2c),
        "cam_t_w2c": cv.t_w2c_mm,
        "pixels_from_camera": cv.pixels_from_camera.iter().flatten().copied().collect::<Vec<f64>>(),
        "depth_units_per_mm": DEPTH_UNITS_PER_MM,
    });
    if let Some(k) = cv.k {
        out["cam_K"] = json!(flat(&k));
    }
    out
}

/// The exact line drawing in raster px (y down, pixel centres at +0.5, the COCO boxes' frame):
/// junctions with their class and six-bit code, and lines as junction index pairs with their
/// kind (docs/wireframe.md "Wireframe datasets" describes the conversion).
fn line_drawing_json(wf: &Wireframe) -> Value {
    let kind = |k: &Option<crate::drawing::LineKind>| match k {
        Some(k) => serde_json::to_value(k).unwrap_or(Value::Null),
        None => Value::Null,
    };
    json!({
        "junctions": wf.junctions.iter().map(|j| j.xy_px).collect::<Vec<_>>(),
        "junction_types": wf.junctions.iter().map(|j| j.junction_type.as_str()).collect::<Vec<_>>(),
        "six_bit_codes": wf.junctions.iter().map(|j| j.six_bit_code).collect::<Vec<_>>(),
        "lines": wf.edges,
        "line_kinds": wf.line_kinds.iter().map(kind).collect::<Vec<_>>(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::{CameraOptions, CornerView};
    use crate::geom::DVec3;
    use crate::scene::Block;

    fn scene() -> Scene {
        Scene::new(
            "pair",
            vec![
                Block::new("b30", DVec3::new(0.0, 7.5, 0.0), 0.0),
                Block::new("b15", DVec3::new(0.0, 22.5, 0.0), 0.0),
            ],
        )
    }

    fn camera(scene: &Scene) -> Camera {
        let opts = CameraOptions {
            size_px: [64, 48],
            ..Default::default()
        };
        Camera::frame(&scene.world_vertices(), CornerView::Ne, &opts)
    }

    /// An id picture drawn from the silhouettes, upper block over lower (the top block is
    /// nearer the eye where they overlap in this view).
    fn ids_of(scene: &Scene, camera: &Camera) -> Vec<u16> {
        let mut ids = vec![0u16; 64 * 48];
        for (k, b) in scene.blocks.iter().enumerate() {
            for (i, &p) in silhouette_mask(b, camera).pixels.iter().enumerate() {
                if p {
                    ids[i] = k as u16 + 1;
                }
            }
        }
        ids
    }

    #[test]
    fn annotations_follow_the_id_picture_and_categories_the_catalog() {
        let s = scene();
        let c = camera(&s);
        let drawing = LineDrawing::default();
        let view_of = |ids: &[u16]| {
            coco_view(&ViewInput {
                scene_id: "s000000",
                scene: &s,
                camera: &c,
                ids,
                drawing: &drawing,
                file_name: "s000000_ne.png",
            })
        };
        let mut ids = ids_of(&s, &c);
        let view = view_of(&ids).unwrap();
        assert_eq!(view.annotations.len(), 2);
        assert_eq!(view.annotations[0]["category_id"], 2); // b30, second in the catalog
        assert_eq!(view.annotations[1]["category_id"], 1);
        assert_eq!(view.agreement.visible_outside_px, 0);
        assert_eq!(view.agreement.silhouette_on_background_px, 0);
        let top = &view.annotations[1];
        assert_eq!(top["area"], top["amodal_area"]);
        assert!(view.annotations[0]["visible_fraction"].as_f64().unwrap() < 1.0);
        assert_eq!(view.image["camera"]["projection"], "orthographic");
        assert!(view.image["camera"].get("cam_K").is_none());
        // A block hidden entirely gets no annotation; a stray id is refused.
        ids.iter_mut().filter(|v| **v == 1).for_each(|v| *v = 2);
        assert_eq!(view_of(&ids).unwrap().annotations.len(), 1);
        ids[0] = 3;
        assert!(matches!(view_of(&ids), Err(CocoError::Mask(_))));
    }

    #[test]
    fn categories_are_the_catalog_in_order() {
        let cats = coco_categories();
        assert_eq!(cats.as_array().unwrap().len(), CATALOG.len());
        assert_eq!(
            cats[0],
            json!({"id": 1, "name": "b15", "supercategory": "block", "long_name": "Baustein 15"})
        );
        assert_eq!(category_id("c15"), Some(5));
        assert_eq!(category_id("x"), None);
    }
}
