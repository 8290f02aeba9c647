//! Shared planes. Chapter V: "the gradients of the left and the right side of a block are
//! constant", and blocks in a stack meet face to face. A face seen in several views, or shared
//! by two touching blocks, is one plane measured several times; measured from pictures, each
//! proposal puts it a little elsewhere (a tenth of a millimetre at 4 px/mm), enough to open a
//! gap the exact drawing then shows as lines no picture has. Here the face planes of all
//! proposals that lie within [`SHARED_PLANE_TOL_MM`] of each other are taken as one plane at
//! their mean, and each proposal moves onto the shared plane that most proposals agree on. Only
//! positions move, never sizes; the check of step 6 still judges the result.

use crate::geom::bounds3;
use crate::scene::Block;

/// Face planes closer than this are one plane measured twice, mm: well above the vision
/// front end's placement error (about 0.5 px, 0.03-0.15 mm at the suite's scales) and well
/// below the 7.5 mm grid of the catalog.
pub const SHARED_PLANE_TOL_MM: f64 = 0.3;

/// One face plane of one proposal along one axis.
struct FacePlane {
    value_mm: f64,
    view: usize,
    block: usize,
    is_min: bool,
}

/// Groups sorted plane values: a new group starts where a value lies more than `tol_mm` past
/// its group's first value. Returns each plane's group and each group's (mean, count).
fn group_planes(planes: &[FacePlane], tol_mm: f64) -> (Vec<usize>, Vec<(f64, usize)>) {
    let mut order: Vec<usize> = (0..planes.len()).collect();
    order.sort_by(|&a, &b| planes[a].value_mm.total_cmp(&planes[b].value_mm));
    let mut group_of = vec![0; planes.len()];
    let mut groups: Vec<(f64, f64, usize)> = Vec::new();
    for &i in &order {
        let v = planes[i].value_mm;
        match groups.last_mut() {
            Some((first, sum, n)) if v - *first <= tol_mm => {
                *sum += v;
                *n += 1;
            }
            _ => groups.push((v, v, 1)),
        }
        group_of[i] = groups.len() - 1;
    }
    let means = groups.iter().map(|&(_, s, n)| (s / n as f64, n)).collect();
    (group_of, means)
}

/// Moves every proposal along world axis `axis` (0 = x, 2 = z) onto its best shared plane.
fn snap_axis(per_view: &mut [Vec<Block>], axis: usize, tol_mm: f64) {
    let mut planes = Vec::new();
    for (view, blocks) in per_view.iter().enumerate() {
        for (block, b) in blocks.iter().enumerate() {
            let Some((lo, hi)) = bounds3(b.world_vertices()) else {
                continue;
            };
            for (value_mm, is_min) in [(lo[axis], true), (hi[axis], false)] {
                planes.push(FacePlane {
                    value_mm,
                    view,
                    block,
                    is_min,
                });
            }
        }
    }
    let (group_of, groups) = group_planes(&planes, tol_mm);
    for pair in planes.chunks(2).zip(group_of.chunks(2)) {
        let ([lo, hi], [g_lo, g_hi]) = pair else {
            continue;
        };
        debug_assert!(lo.is_min && !hi.is_min);
        let (m_lo, n_lo) = groups[*g_lo];
        let (m_hi, n_hi) = groups[*g_hi];
        let shift = if n_lo > n_hi
            || (n_lo == n_hi && (m_lo - lo.value_mm).abs() <= (m_hi - hi.value_mm).abs())
        {
            m_lo - lo.value_mm
        } else {
            m_hi - hi.value_mm
        };
        per_view[lo.view][lo.block].center_mm[axis] += shift;
    }
}

/// The proposals of every view, each moved onto the shared face planes (see the module doc),
/// along the two horizontal axes (heights are already the catalog's layer heights).
pub fn snap_to_shared_planes(per_view: &[Vec<Block>], tol_mm: f64) -> Vec<Vec<Block>> {
    let mut out = per_view.to_vec();
    snap_axis(&mut out, 0, tol_mm);
    snap_axis(&mut out, 2, tol_mm);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::DVec3;

    #[test]
    fn planes_measured_twice_become_one_and_sizes_stay() {
        // A b30 and a b15 meant to stand flush at z = 15 (the b15 in front), measured 0.06 and
        // 0.03 mm off by two views; a lone block far away stays where it is.
        let per_view = vec![
            vec![Block::new("b30", DVec3::new(15.0, 7.5, 7.56), 0.0)],
            vec![
                Block::new("b15", DVec3::new(7.5, 7.5, 22.47), 0.0),
                Block::new("b15", DVec3::new(100.2, 7.5, 100.0), 0.0),
            ],
        ];
        let out = snap_to_shared_planes(&per_view, SHARED_PLANE_TOL_MM);
        let back_of_b30 = out[0][0].center_mm.z + 7.5;
        let front_b15 = out[1][0].center_mm.z - 7.5;
        assert!(
            (back_of_b30 - front_b15).abs() < 1e-12,
            "{back_of_b30} vs {front_b15}"
        );
        assert!(
            (back_of_b30 - 15.015).abs() < 1e-9,
            "the mean of 15.06 and 14.97"
        );
        assert_eq!(out[1][1].center_mm, DVec3::new(100.2, 7.5, 100.0));
        // Planes farther apart than the tolerance are not merged.
        let apart = vec![vec![
            Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 0.0),
            Block::new("b15", DVec3::new(15.5, 7.5, 0.0), 0.0),
        ]];
        assert_eq!(snap_to_shared_planes(&apart, SHARED_PLANE_TOL_MM), apart);
    }
}
