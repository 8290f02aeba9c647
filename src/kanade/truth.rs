//! The true labelling of a ground-truth drawing (`lines_<view>.json` carries every line's kind,
//! docs/formats.md "The exact line drawing") and the check whether a labelling is consistent with a
//! catalog, junction by junction: how the labeller is measured on rendered scenes.

use super::catalog::Catalog;
use super::graph::{junction_sites, regions, validate};
use super::label::{EndLabel, LineLabel};
use super::KanadeError;
use crate::camera::Camera;
use crate::drawing::{Junction, LineDrawing, LineKind};
use crate::geom::{DVec2, DVec3};
use serde::Serialize;

/// The labels that a ground-truth drawing's `kinds` say, with each occluding arrow's side taken
/// from the picture position of the occluding block's centre (`block_centres_px[edges[i].block]`,
/// the caller projects them): a block is convex, so its projection lies on the face side of each
/// of its silhouette lines. `None` when the drawing carries no kinds or edges, or a block index
/// is out of range.
pub fn labelling_from_kinds(d: &LineDrawing, block_centres_px: &[DVec2]) -> Option<Vec<LineLabel>> {
    if d.kinds.len() != d.lines.len() || d.edges.len() != d.lines.len() {
        return None;
    }
    d.lines
        .iter()
        .zip(d.kinds.iter().zip(&d.edges))
        .map(|(&[a, b], (kind, edge))| {
            Some(match kind {
                LineKind::Convex => LineLabel::Convex,
                LineKind::Concave => LineLabel::Concave,
                LineKind::Crack => LineLabel::Crack,
                LineKind::Boundary => {
                    let c = *block_centres_px.get(edge.block)?;
                    let (pa, pb) = (*d.points.get(a)?, *d.points.get(b)?);
                    LineLabel::occluding((pb - pa).perp_dot(c - pa) < 0.0)
                }
            })
        })
        .collect()
}

/// Picture px per mm across the optical axis of an orthographic camera (the x scale of its
/// projection), the factor between the gradient space's px and the world's mm.
pub fn orthographic_px_per_mm(camera: &Camera) -> f64 {
    f64::from(camera.size_px[0]) / 2.0 * camera.clip_from_view[0]
}

/// The true 3D ends of every line of a ground-truth drawing (`edges[i].from_mm/to_mm`) in the
/// frame of [`super::ShapeRecovery::line_ends_px`]: picture x and y in px, and the depth towards
/// the viewer in px of an orthographic `camera`. `None` for lines without a 3D edge.
pub fn true_line_ends_px(d: &LineDrawing, camera: &Camera) -> Vec<Option<[DVec3; 2]>> {
    let s = orthographic_px_per_mm(camera);
    let f = |p: DVec3| {
        let q = camera.picture_from_world(p);
        DVec3::new(q.x, q.y, -q.z * s)
    };
    (0..d.lines.len())
        .map(|i| d.edge_world_mm(i).map(|(a, b)| [f(a), f(b)]))
        .collect()
}

/// A junction where a labelling is not one of the catalog's, or an outer line that breaks the
/// occluding-boundary constraint.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Violation {
    /// Point index (for an outer line, its first point).
    pub point: usize,
    /// For an outer line that is not occluding clockwise (Appendix A step 2): the line.
    pub line: Option<usize>,
    /// Junction class.
    pub junction: Junction,
    /// The labelling's labels at this junction in canonical order (PAIP letters).
    pub labels: String,
    /// `true` when the class is not in the catalog at all.
    pub uncatalogued: bool,
}

/// The junctions at which `labels` (one per line) is not a catalog labelling, and with
/// `boundary_occluding` the outer lines that are not occluding clockwise. The labelling is one
/// of those [`super::label_drawing`] finds with the same options exactly when every violation
/// is `uncatalogued` (junctions outside the catalog constrain nothing).
pub fn check_labelling(
    d: &LineDrawing,
    labels: &[LineLabel],
    catalog: Catalog,
    boundary_occluding: bool,
) -> Result<Vec<Violation>, KanadeError> {
    validate(d)?;
    let mut out = Vec::new();
    if boundary_occluding {
        for r in regions(d).iter().filter(|r| r.is_outside()) {
            for e in &r.walk {
                if labels.get(e.line) != Some(&LineLabel::occluding(e.at_start)) {
                    out.push(Violation {
                        point: d.lines[e.line][0],
                        line: Some(e.line),
                        junction: Junction::Other,
                        labels: labels
                            .get(e.line)
                            .map_or(String::new(), |l| l.symbol().into()),
                        uncatalogued: false,
                    });
                }
            }
        }
    }
    for s in junction_sites(d) {
        if s.ends.is_empty() {
            continue;
        }
        let Some(here): Option<Vec<EndLabel>> = s
            .ends
            .iter()
            .map(|e| {
                labels
                    .get(e.line)
                    .map(|l| EndLabel::from_line_label(*l, e.at_start))
            })
            .collect()
        else {
            continue;
        };
        let rows = catalog.labellings(s.junction, s.ends.len());
        let uncatalogued = rows.is_empty();
        if uncatalogued || !rows.contains(&here) {
            out.push(Violation {
                point: s.point,
                line: None,
                junction: s.junction,
                labels: here.iter().map(|l| l.symbol()).collect(),
                uncatalogued,
            });
        }
    }
    Ok(out)
}

/// Whether a labelling is among the consistent ones: no violation other than an uncatalogued
/// junction.
pub fn is_consistent(violations: &[Violation]) -> bool {
    violations.iter().all(|v| v.uncatalogued)
}
