//! Constructive solid geometry of a recognized sample (thesis Chapter IV, Figure 4.6; step 5 of
//! Chapter V): the final object as the union of positioned primitive blocks, "starting from the
//! lowest level to the upper levels".
//!
//! ## Frame
//! Positions are world millimetres as the cameras define them (docs/formats.md "Conventions": +y up,
//! the floor at y = 0, +x east, -z north), so a reconstruction scores directly against its
//! truth scene. The thesis instead places its sample relative to a **reference vertex**
//! (Chapter VI, "Display the Final Sample"): the vertex with the least picture x, where x = 0,
//! with y taken from its layer (bottom layer at y = 0). The two frames share the y axis and the
//! floor; they differ by a horizontal translation only, which [`reference_vertex_mm`] gives:
//! thesis coordinates = world − (ref.x, 0, ref.z).

use crate::camera::Camera;
use crate::geom::DVec3;
use crate::recognize::{classify_layers, Recognition};
use crate::scene::Block;
use crate::scene::{CsgNode, Evidence, ReconStatus, Reconstruction};

/// The CSG union of `blocks` (Figure 4.6; Chapter V: "adds the data together ... starting from
/// the lowest level to the upper levels"): one union per layer, lowest layer first, leaves
/// indexing `blocks`. Blocks within a layer keep their order. Layers are bottoms within
/// `layer_tol_mm`.
pub fn build_csg(blocks: &[Block], layer_tol_mm: f64) -> CsgNode {
    CsgNode::Union(
        classify_layers(blocks, layer_tol_mm)
            .into_iter()
            .map(|layer| CsgNode::Union(layer.blocks.iter().map(|&i| CsgNode::Block(i)).collect()))
            .collect(),
    )
}

/// The reconstruction of a recognition (step 5 of Chapter V): its blocks in world mm, the CSG
/// union of [`build_csg`] (for an `ok` answer), status, reason and the per-view evidence.
pub fn reconstruction(name: &str, r: &Recognition, layer_tol_mm: f64) -> Reconstruction {
    let csg = (r.status == ReconStatus::Ok).then(|| build_csg(&r.blocks, layer_tol_mm));
    Reconstruction {
        name: name.to_string(),
        blocks: r.blocks.clone(),
        status: r.status,
        reason: r.reason.clone(),
        csg,
        evidence: Some(Evidence {
            views: r.evidence.views.clone(),
            pooled_candidates: r.evidence.pooled_candidates,
        }),
        meta: None,
    }
}

/// The thesis's reference vertex (Chapter VI): of all block vertices, the one with the least
/// picture x in `camera` (ties: lowest y). `None` for no blocks.
pub fn reference_vertex_mm(blocks: &[Block], camera: &Camera) -> Option<DVec3> {
    blocks
        .iter()
        .flat_map(Block::world_vertices)
        .map(|v| (camera.picture_from_world(v), v))
        .min_by(|a, b| a.0.x.total_cmp(&b.0.x).then(a.1.y.total_cmp(&b.1.y)))
        .map(|(_, v)| v)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::{CameraOptions, CornerView};

    fn stack() -> Vec<Block> {
        vec![
            Block::new("b15", DVec3::new(7.5, 22.5, 7.5), 0.0),
            Block::new("b30", DVec3::new(15.0, 7.5, 7.5), 90.0),
            Block::new("b15", DVec3::new(45.0, 7.5, 7.5), 0.0),
        ]
    }

    #[test]
    fn the_union_puts_the_lowest_layer_first() {
        let blocks = stack();
        let tree = build_csg(&blocks, 0.5);
        let CsgNode::Union(layers) = &tree else {
            panic!("root is a union")
        };
        assert_eq!(layers.len(), 2);
        assert_eq!(layers[0].leaves().len(), 2);
        let ids: Vec<&str> = tree
            .leaves()
            .iter()
            .map(|&i| blocks[i].block_type.id)
            .collect();
        assert_eq!(ids, vec!["b30", "b15", "b15"]);
        assert_eq!(tree.leaves()[2], 0, "the upper cube comes last");
        assert!(tree.is_pure_union());
    }

    #[test]
    fn the_reference_vertex_is_the_leftmost_in_the_picture() {
        let blocks = stack();
        let v = crate::scene::world_vertices(&blocks);
        let cam = Camera::frame(&v, CornerView::Ne, &CameraOptions::default());
        let r = reference_vertex_mm(&blocks, &cam).unwrap();
        let rx = cam.picture_from_world(r).x;
        assert!(v.iter().all(|p| cam.picture_from_world(*p).x >= rx - 1e-9));
        assert_eq!(r.y, 0.0, "the lowest of the leftmost vertical edge");
        assert!(reference_vertex_mm(&[], &cam).is_none());
    }
}
