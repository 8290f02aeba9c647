//! Quantitative shape (thesis Chapter II, Figures 2.2-2.6; Kanade 1981): the surface connection
//! graph of a labelling, gradients from the parallel-line and skewed-symmetry heuristics under
//! orthographic projection, the plane of every surface, and depths up to one reference point.
//!
//! ## Gradient space
//! A plane `z = p x + q y + c` (picture px, x right, y up, z towards the viewer, as the
//! thesis's cube planes S1-S3 of Chapter VI) has the gradient `G = (p, q)`. Along a 3D direction
//! whose picture image is `a u` (`u` a unit picture vector) and whose depth change is `w`,
//! `G . (a u) = w`.
//!
//! ## Heuristics
//! - **Parallel lines** ("if two lines are parallel in the picture, they depict parallel lines
//!   in the scene"): the drawing's lines fall into families of parallel lines (within
//!   [`COLLINEAR_TOL_DEG`]); the three longest families are the three edge directions of the
//!   blocks.
//! - **Skewed symmetry and perpendicular faces** (Kanade's second and fourth rules, Figure 2.6):
//!   each face is a parallelogram depicting a rectangle, whose symmetry axes, parallel to its
//!   sides, are perpendicular in space; the faces meet at right angles. So the three directions
//!   are orthonormal in 3D: with `e_i = (a_i u_i, w_i)`, `sum a_i^2 u_ix^2 = sum a_i^2 u_iy^2 = 1`
//!   and `sum a_i^2 u_ix u_iy = 0` (the rows of a rotation), linear in `a_i^2`; then
//!   `w_i w_j = -a_i a_j (u_i . u_j)` fixes every depth change up to one sign for all
//!   (the Necker reversal), which the labelling's convex and concave lines decide.
//! - A surface bounded by lines of two families `i, j` gets the gradient solving
//!   `G . (a_i u_i) = w_i`, `G . (a_j u_j) = w_j`.

use super::graph::{regions, validate, LineEnd, Region};
use super::label::{LabelSet, LineLabel};
use super::KanadeError;
use crate::drawing::{LineDrawing, COLLINEAR_TOL_DEG};
use crate::geom::{DVec2, DVec3};
use serde::Serialize;

/// The three edge directions of the drawing as orthonormal 3D directions (picture px frame, z
/// towards the viewer).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct GradientSpace {
    /// Unit picture direction of each family of parallel lines (angle in [0°, 180°)).
    pub directions_px: [DVec2; 3],
    /// The 3D unit direction each family depicts, `(a u, w)`.
    pub axes: [DVec3; 3],
}

/// What kind of constraint a surface connection graph link carries (Chapter II, Figure 2.2b).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum LinkKind {
    /// A convex edge: the gradients' difference is perpendicular to the line, pointing away
    /// from the first surface's side.
    Convex,
    /// A concave edge: the same with the other sign.
    Concave,
    /// A crack: the two surfaces are one plane (equal gradients).
    Crack,
    /// The first surface occludes the second (no gradient constraint, a depth step).
    Occluding,
}

/// A link of the surface connection graph: a line between two surfaces.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SurfaceLink {
    /// The line.
    pub line: usize,
    /// The surface on the line's left (walking from its first point to its second) — for an
    /// occluding link, the occluding surface.
    pub a: usize,
    /// The other surface.
    pub b: usize,
    /// Its constraint.
    pub kind: LinkKind,
}

/// Kanade's surface connection graph (SCG, Chapter II; Appendix A step 3): nodes are the
/// picture's regions that depict surfaces, links the labelled lines between them.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SurfaceConnectionGraph {
    /// Regions of the drawing (faces of the planar graph); `surface[r]` says which are surfaces.
    #[serde(skip)]
    pub regions: Vec<Region>,
    /// Whether each region depicts a surface (some boundary line has its face on that side).
    pub surface: Vec<bool>,
    /// Links between surfaces.
    pub links: Vec<SurfaceLink>,
}

/// The recovered shape of one labelling.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ShapeRecovery {
    /// The gradient space used.
    pub space: GradientSpace,
    /// Gradient `(p, q)` of every region (`None` for background or undetermined regions).
    pub gradients: Vec<Option<DVec2>>,
    /// Plane offset `c` of every region in px (`z = p x + q y + c`), relative to its
    /// component's reference.
    pub offsets_px: Vec<Option<f64>>,
    /// Connected component (by convex, concave and crack links) of every region.
    pub component: Vec<Option<usize>>,
    /// Per line: the 3D position (x, y, z px) of both ends on the surface that carries it
    /// (for an occluding line, the occluding surface), when known.
    pub line_ends_px: Vec<Option<[DVec3; 2]>>,
    /// Per line: its component.
    pub line_component: Vec<Option<usize>>,
    /// Convex and concave links whose gradients break their constraint (Appendix A step 3's
    /// check), and crack links whose gradients differ.
    pub inconsistent_links: usize,
}

/// The angle of a line modulo 180 degrees, in degrees.
fn undirected_deg(v: DVec2) -> f64 {
    v.y.atan2(v.x).to_degrees().rem_euclid(180.0)
}

fn angle_gap_deg(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(180.0);
    d.min(180.0 - d)
}

/// Families of parallel lines: each line's family (or `None`), and the three longest families'
/// mean directions.
fn parallel_families(d: &LineDrawing) -> (Vec<Option<usize>>, Vec<DVec2>) {
    let mut fams: Vec<(f64, f64)> = Vec::new(); // (angle of first line, total length)
    let mut of_line = Vec::with_capacity(d.lines.len());
    for &[a, b] in &d.lines {
        let v = d.points[b] - d.points[a];
        let ang = undirected_deg(v);
        let k = fams
            .iter()
            .position(|(f, _)| angle_gap_deg(*f, ang) <= COLLINEAR_TOL_DEG);
        let k = k.unwrap_or_else(|| {
            fams.push((ang, 0.0));
            fams.len() - 1
        });
        fams[k].1 += v.length();
        of_line.push(k);
    }
    let mut order: Vec<usize> = (0..fams.len()).collect();
    order.sort_by(|x, y| fams[*y].1.total_cmp(&fams[*x].1).then(x.cmp(y)));
    order.truncate(3);
    order.sort_by(|x, y| fams[*x].0.total_cmp(&fams[*y].0));
    let dirs = order
        .iter()
        .map(|k| {
            let r = fams[*k].0.to_radians();
            DVec2::new(r.cos(), r.sin())
        })
        .collect();
    let family = of_line
        .iter()
        .map(|k| order.iter().position(|o| o == k))
        .collect();
    (family, dirs)
}

/// The gradient space of three picture directions depicting orthonormal 3D directions, with
/// the depth changes' common sign `sign` (±1). `None` when no such directions exist (e.g. two
/// directions parallel).
pub fn orthonormal_axes(u: [DVec2; 3], sign: f64) -> Option<GradientSpace> {
    // Solve M [a1², a2², a3²] = [1, 1, 0].
    let m = glam::DMat3::from_cols(
        DVec3::new(u[0].x * u[0].x, u[0].y * u[0].y, u[0].x * u[0].y),
        DVec3::new(u[1].x * u[1].x, u[1].y * u[1].y, u[1].x * u[1].y),
        DVec3::new(u[2].x * u[2].x, u[2].y * u[2].y, u[2].x * u[2].y),
    );
    if m.determinant().abs() < 1e-9 {
        return None;
    }
    let a2 = m.inverse() * DVec3::new(1.0, 1.0, 0.0);
    if !(a2.min_element() > 0.0 && a2.max_element() <= 1.0 + 1e-9) {
        return None;
    }
    let a = [a2.x.sqrt(), a2.y.sqrt(), a2.z.sqrt()];
    let w0 = sign * (1.0 - a2.x).max(0.0).sqrt();
    let w = if w0.abs() > 1e-9 {
        [
            w0,
            -a[0] * a[1] * u[0].dot(u[1]) / w0,
            -a[0] * a[2] * u[0].dot(u[2]) / w0,
        ]
    } else {
        // The first direction lies in the picture plane; the other two are then opposite.
        let w1 = sign * (1.0 - a2.y).max(0.0).sqrt();
        [0.0, w1, -w1]
    };
    Some(GradientSpace {
        directions_px: u,
        axes: [0, 1, 2].map(|i| (u[i] * a[i]).extend(w[i])),
    })
}

impl GradientSpace {
    /// The gradient of a surface spanned by families `i` and `j`.
    pub fn gradient(&self, i: usize, j: usize) -> Option<DVec2> {
        let (ei, ej) = (self.axes[i], self.axes[j]);
        let m = glam::DMat2::from_cols(ei.truncate(), ej.truncate()).transpose();
        if m.determinant().abs() < 1e-12 {
            return None;
        }
        Some(m.inverse() * DVec2::new(ei.z, ej.z))
    }
}

/// Region index of every directed line: `side[2 * line + k]` is the region on the left of the
/// line walked from its first point (`k = 0`) or from its second (`k = 1`).
fn region_of_half_edges(regions: &[Region], lines: usize) -> Vec<usize> {
    let mut side = vec![usize::MAX; 2 * lines];
    for (r, reg) in regions.iter().enumerate() {
        for e in &reg.walk {
            side[2 * e.line + usize::from(!e.at_start)] = r;
        }
    }
    side
}

/// Builds the SCG of a labelling (one label per line; `None` lines give no link).
pub fn surface_connection_graph(
    d: &LineDrawing,
    labels: &[Option<LineLabel>],
) -> Result<SurfaceConnectionGraph, KanadeError> {
    validate(d)?;
    let regions = regions(d);
    let side = region_of_half_edges(&regions, d.lines.len());
    let mut surface = vec![false; regions.len()];
    let mut links = Vec::new();
    for (line, label) in labels.iter().enumerate().take(d.lines.len()) {
        let (left, right) = (side[2 * line], side[2 * line + 1]);
        let Some(label) = label else { continue };
        let (a, b, kind) = match label {
            LineLabel::Convex => (left, right, LinkKind::Convex),
            LineLabel::Concave => (left, right, LinkKind::Concave),
            LineLabel::Crack => (left, right, LinkKind::Crack),
            // Face on the right walking first -> second: the right region occludes.
            LineLabel::OccludingForward => (right, left, LinkKind::Occluding),
            LineLabel::OccludingBackward => (left, right, LinkKind::Occluding),
        };
        surface[a] = true;
        if kind != LinkKind::Occluding {
            surface[b] = true;
        }
        links.push(SurfaceLink { line, a, b, kind });
    }
    for (r, reg) in regions.iter().enumerate() {
        if reg.is_outside() {
            surface[r] = false;
        }
    }
    Ok(SurfaceConnectionGraph {
        regions,
        surface,
        links,
    })
}

/// Whether gradients `ga` (the region on the left of a line with unit picture direction `t`)
/// and `gb` (on its right) fit a link: convex when, walking into `a` (the left normal `m`),
/// `a` falls behind the plane of `b`: `(G_a - G_b) . m < 0` with `G_a - G_b` perpendicular to
/// the line (Mackworth's rule; Appendix A step 3); concave `> 0`; a crack joins equal
/// gradients; an occlusion fits any.
fn link_fits(kind: LinkKind, ga: DVec2, gb: DVec2, t: DVec2) -> bool {
    let diff = ga - gb;
    let along = diff.dot(t).abs() <= 1e-3;
    let s = diff.dot(t.perp());
    match kind {
        LinkKind::Convex => along && s < -1e-6,
        LinkKind::Concave => along && s > 1e-6,
        LinkKind::Crack => diff.length() <= 1e-3,
        LinkKind::Occluding => true,
    }
}

fn unit_direction(d: &LineDrawing, line: usize) -> DVec2 {
    let [p, q] = d.lines[line];
    (d.points[q] - d.points[p]).normalize()
}

/// How many links a set of gradients breaks (convex, concave and crack links).
fn count_inconsistent(d: &LineDrawing, scg: &SurfaceConnectionGraph, g: &[Option<DVec2>]) -> usize {
    scg.links
        .iter()
        .filter(|l| match (g[l.a], g[l.b]) {
            (Some(ga), Some(gb)) => !link_fits(l.kind, ga, gb, unit_direction(d, l.line)),
            _ => false,
        })
        .count()
}

/// Gradients of the regions marked `eligible`: from the two families of parallel lines
/// bounding each.
fn region_gradients(
    regions: &[Region],
    eligible: &[bool],
    family: &[Option<usize>],
    space: &GradientSpace,
) -> Vec<Option<DVec2>> {
    regions
        .iter()
        .zip(eligible)
        .map(|(reg, ok)| {
            if !ok {
                return None;
            }
            let mut fams: Vec<usize> = reg.walk.iter().filter_map(|e| family[e.line]).collect();
            fams.sort_unstable();
            fams.dedup();
            match fams[..] {
                [i, j] => space.gradient(i, j),
                _ => None,
            }
        })
        .collect()
}

fn surface_gradients(
    scg: &SurfaceConnectionGraph,
    family: &[Option<usize>],
    space: &GradientSpace,
) -> Vec<Option<DVec2>> {
    region_gradients(&scg.regions, &scg.surface, family, space)
}

/// Appendix A step 3 as a filter on line labels before the search: for each line between two
/// regions whose gradients the heuristics give, the labels whose link the gradients fit
/// ([`link_fits`]) under either Necker reading, occluding labels always. `None` when the
/// drawing has no gradient space. The drawing must be valid.
pub fn gradient_label_sets(d: &LineDrawing) -> Option<Vec<LabelSet>> {
    let regs = regions(d);
    let side = region_of_half_edges(&regs, d.lines.len());
    let (family, dirs) = parallel_families(d);
    let u: [DVec2; 3] = match dirs[..] {
        [a, b, c] => [a, b, c],
        _ => return None,
    };
    let inside: Vec<bool> = regs.iter().map(|r| !r.is_outside()).collect();
    let mut out = vec![LabelSet::default(); d.lines.len()];
    let mut any = false;
    for space in [1.0, -1.0]
        .into_iter()
        .filter_map(|s| orthonormal_axes(u, s))
    {
        any = true;
        let g = region_gradients(&regs, &inside, &family, &space);
        for (line, set) in out.iter_mut().enumerate() {
            set.insert(LineLabel::OccludingForward);
            set.insert(LineLabel::OccludingBackward);
            let (Some(ga), Some(gb)) = (g[side[2 * line]], g[side[2 * line + 1]]) else {
                *set = LabelSet::ANY;
                continue;
            };
            let t = unit_direction(d, line);
            for (kind, label) in [
                (LinkKind::Convex, LineLabel::Convex),
                (LinkKind::Concave, LineLabel::Concave),
                (LinkKind::Crack, LineLabel::Crack),
            ] {
                if link_fits(kind, ga, gb, t) {
                    set.insert(label);
                }
            }
        }
    }
    any.then_some(out)
}

/// Recovers the shape of a labelling (Chapter II; Appendix A step 3): the SCG, the gradient
/// space from the heuristics, each surface's gradient, its plane through its component's
/// reference point (z = 0 at the first point met of the component), and both ends of every
/// line in 3D. The Necker sign is the one whose gradients break fewer convex and concave links.
pub fn recover_shape(
    d: &LineDrawing,
    labels: &[Option<LineLabel>],
) -> Result<ShapeRecovery, KanadeError> {
    let scg = surface_connection_graph(d, labels)?;
    let (family, dirs) = parallel_families(d);
    let u: [DVec2; 3] = match dirs[..] {
        [a, b, c] => [a, b, c],
        _ => return Err(KanadeError::NoGradientSpace),
    };
    let best = [1.0, -1.0]
        .into_iter()
        .filter_map(|sign| orthonormal_axes(u, sign))
        .map(|space| {
            let g = surface_gradients(&scg, &family, &space);
            let bad = count_inconsistent(d, &scg, &g);
            (space, g, bad)
        })
        .min_by_key(|(_, _, bad)| *bad);
    let Some((space, gradients, inconsistent_links)) = best else {
        return Err(KanadeError::NoGradientSpace);
    };
    let (offsets_px, component) = plane_offsets(d, &scg, &gradients);
    let (line_ends_px, line_component) = line_ends(d, &scg, &gradients, &offsets_px, &component);
    Ok(ShapeRecovery {
        space,
        gradients,
        offsets_px,
        component,
        line_ends_px,
        line_component,
        inconsistent_links,
    })
}

fn depth(g: DVec2, c: f64, p: DVec2) -> f64 {
    g.dot(p) + c
}

/// Plane offsets by breadth-first search over convex, concave and crack links, each component
/// starting with z = 0 at the first point of its first surface.
fn plane_offsets(
    d: &LineDrawing,
    scg: &SurfaceConnectionGraph,
    g: &[Option<DVec2>],
) -> (Vec<Option<f64>>, Vec<Option<usize>>) {
    let n = scg.regions.len();
    let mut c = vec![None; n];
    let mut comp = vec![None; n];
    let mut next_comp = 0;
    for start in 0..n {
        let Some(gs) = g[start] else { continue };
        if c[start].is_some() {
            continue;
        }
        let p0 = point_of(d, scg.regions[start].walk[0]);
        c[start] = Some(-gs.dot(p0));
        comp[start] = Some(next_comp);
        let mut queue = vec![start];
        while let Some(r) = queue.pop() {
            let (gr, cr) = (g[r].unwrap_or_default(), c[r].unwrap_or_default());
            for l in scg.links.iter().filter(|l| l.kind != LinkKind::Occluding) {
                let other = if l.a == r {
                    l.b
                } else if l.b == r {
                    l.a
                } else {
                    continue;
                };
                let Some(go) = g[other] else { continue };
                if c[other].is_some() {
                    continue;
                }
                let p = d.points[d.lines[l.line][0]];
                c[other] = Some(depth(gr, cr, p) - go.dot(p));
                comp[other] = Some(next_comp);
                queue.push(other);
            }
        }
        next_comp += 1;
    }
    (c, comp)
}

fn point_of(d: &LineDrawing, e: LineEnd) -> DVec2 {
    let [a, b] = d.lines[e.line];
    d.points[if e.at_start { a } else { b }]
}

type LineEnds = (Vec<Option<[DVec3; 2]>>, Vec<Option<usize>>);

/// Both ends of each line on the surface that carries it.
fn line_ends(
    d: &LineDrawing,
    scg: &SurfaceConnectionGraph,
    g: &[Option<DVec2>],
    c: &[Option<f64>],
    comp: &[Option<usize>],
) -> LineEnds {
    let mut ends = vec![None; d.lines.len()];
    let mut lc = vec![None; d.lines.len()];
    for l in &scg.links {
        let carriers = if l.kind == LinkKind::Occluding {
            vec![l.a]
        } else {
            vec![l.a, l.b]
        };
        for r in carriers {
            if let (Some(gr), Some(cr)) = (g[r], c[r]) {
                let [p, q] = d.lines[l.line];
                let (pp, pq) = (d.points[p], d.points[q]);
                ends[l.line] = Some([pp.extend(depth(gr, cr, pp)), pq.extend(depth(gr, cr, pq))]);
                lc[l.line] = comp[r];
                break;
            }
        }
    }
    (ends, lc)
}

/// Root-mean-square 3D distance in px between the recovered line ends and the true ones
/// (`truth_ends_px[line]` = both ends as picture x, y and depth z towards the viewer, all in
/// px), after fixing each component's free depth at its reference: the first line end of the
/// component in line order takes its true depth (Chapter II: "assuming the z position of one
/// point on the object to be known"). Returns (rms px, line ends compared).
pub fn depth_rms_px(
    rec: &ShapeRecovery,
    truth_ends_px: &[Option<[DVec3; 2]>],
) -> Option<(f64, usize)> {
    let mut offset: Vec<Option<f64>> = Vec::new();
    let (mut sum, mut n) = (0.0, 0usize);
    for (line, ends) in rec.line_ends_px.iter().enumerate() {
        let (Some(ends), Some(comp), Some(Some(truth))) =
            (ends, rec.line_component[line], truth_ends_px.get(line))
        else {
            continue;
        };
        if offset.len() <= comp {
            offset.resize(comp + 1, None);
        }
        let dz = *offset[comp].get_or_insert(truth[0].z - ends[0].z);
        for k in 0..2 {
            let p = ends[k] + DVec3::new(0.0, 0.0, dz);
            sum += p.distance_squared(truth[k]);
            n += 1;
        }
    }
    (n > 0).then(|| ((sum / n as f64).sqrt(), n))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The isometric cube of Chapter VI with its origin at the middle fork (the thesis's vertex
    /// L), top vertex first, clockwise; lines as in `drawing`'s cube.
    fn cube() -> LineDrawing {
        LineDrawing::isometric_cube(1.0, DVec2::ZERO)
    }

    /// The free-floating labelling: outline clockwise (face on the right of 0 -> 1 -> ...),
    /// the three inner lines convex.
    fn floating(convex: LineLabel) -> Vec<Option<LineLabel>> {
        let mut l = vec![Some(LineLabel::OccludingForward); 6];
        l.extend([Some(convex); 3]);
        l
    }

    fn planes(r: &ShapeRecovery) -> Vec<(f64, f64, f64)> {
        let mut v: Vec<(f64, f64, f64)> = r
            .gradients
            .iter()
            .zip(&r.offsets_px)
            .filter_map(|(g, c)| Some((g.as_ref()?.x, g.as_ref()?.y, (*c)?)))
            .collect();
        v.sort_by(|a, b| a.0.total_cmp(&b.0));
        v
    }

    #[test]
    fn cube_planes_are_the_theses_s1_s2_s3() {
        // Chapter VI: S1: sqrt(3/2) x - sqrt(1/2) y + z = 0, S2: -sqrt(3/2) x - sqrt(1/2) y + z = 0,
        // S3: sqrt(2) y + z = 0, origin at vertex L (the middle fork).
        let r = recover_shape(&cube(), &floating(LineLabel::Convex)).unwrap();
        assert_eq!(r.inconsistent_links, 0);
        let got = planes(&r);
        let want = [
            (-1.5f64.sqrt(), 0.5f64.sqrt()),
            (0.0, -(2f64.sqrt())),
            (1.5f64.sqrt(), 0.5f64.sqrt()),
        ];
        assert_eq!(got.len(), 3);
        for ((p, q, _), (wp, wq)) in got.iter().zip(want) {
            assert!((p - wp).abs() < 1e-9 && (q - wq).abs() < 1e-9, "{got:?}");
        }
        // Every plane passes through the fork at the origin: with z = 0 fixed there, every
        // offset is 0, as in S1-S3.
        let z_at_fork: Vec<f64> = got.iter().map(|(_, _, c)| *c).collect();
        assert!(z_at_fork.iter().all(|c| (c - z_at_fork[0]).abs() < 1e-9));
    }

    #[test]
    fn a_concave_labelling_of_the_cube_flips_the_necker_sign() {
        // Figure 2.3: the same drawing labelled as a concave corner gets the mirrored gradients.
        let r = recover_shape(&cube(), &floating(LineLabel::Concave)).unwrap();
        let got = planes(&r);
        assert!((got[1].1 - 2f64.sqrt()).abs() < 1e-9, "{got:?}");
    }

    #[test]
    fn the_check_catches_gradients_that_break_a_link() {
        let d = cube();
        let scg = surface_connection_graph(&d, &floating(LineLabel::Convex)).unwrap();
        let (family, dirs) = parallel_families(&d);
        let space = orthonormal_axes([dirs[0], dirs[1], dirs[2]], 1.0).unwrap();
        let g = surface_gradients(&scg, &family, &space);
        let flipped: Vec<Option<DVec2>> = g.iter().map(|x| x.map(|v| -v)).collect();
        let a = count_inconsistent(&d, &scg, &g);
        let b = count_inconsistent(&d, &scg, &flipped);
        assert_eq!(a.min(b), 0);
        assert_eq!(a.max(b), 3);
    }

    #[test]
    fn axes_are_orthonormal() {
        let s = 3f64.sqrt() / 2.0;
        let u = [
            DVec2::new(0.0, 1.0),
            DVec2::new(s, 0.5),
            DVec2::new(-s, 0.5),
        ];
        let g = orthonormal_axes(u, 1.0).unwrap();
        for i in 0..3 {
            assert!((g.axes[i].length() - 1.0).abs() < 1e-12);
            for j in i + 1..3 {
                assert!(g.axes[i].dot(g.axes[j]).abs() < 1e-12);
            }
        }
        assert!(orthonormal_axes([u[0], u[0], u[1]], 1.0).is_none());
    }
}
