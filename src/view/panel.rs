//! From models and view parameters to a sheet of viewports holding picture lines, shaded
//! faces and From/At/Up labels (Chapter VI "Display the Final Sample"; Chapter VII
//! viewports, hidden surfaces and shading).

use super::clip::{clip_line, point_at, Clipped};
use super::transform::{rotation_y, translation, ViewingTransform};
use super::{ViewError, MAX_VIEW_COORD_MM};
use crate::geom::{bounds3, newell_vector, DVec2, DVec3};
use crate::linedraw::eye_space::{clip_polygon_to_hither, occluder, visible_parts, Occluder};
use crate::scene::Scene;

/// What a model is, which sets its colour: the one model of a plain view, or the truth and the
/// reconstruction of an `--overlay`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    /// The model of a plain view (black).
    Model,
    /// The ground truth of an overlay (blue).
    Truth,
    /// The reconstruction of an overlay (red).
    Reconstruction,
}

/// A block sample as the thesis's viewer holds it (Appendix B): vertices, and faces as loops of
/// vertex indices; the lines drawn are the faces' edges, each once.
#[derive(Debug, Clone, PartialEq)]
pub struct WireModel {
    /// Its colour.
    pub role: Role,
    /// World vertices in mm.
    pub vertices_mm: Vec<DVec3>,
    /// Convex faces as vertex-index loops.
    pub faces: Vec<Vec<usize>>,
    /// Edges as vertex-index pairs, each once.
    pub edges: Vec<[usize; 2]>,
}

/// The wire model of a scene: every block's catalog vertices, faces and edges in world mm.
pub fn wire_model(scene: &Scene, role: Role) -> WireModel {
    let mut m = WireModel {
        role,
        vertices_mm: Vec::new(),
        faces: Vec::new(),
        edges: Vec::new(),
    };
    for block in &scene.blocks {
        let base = m.vertices_mm.len();
        m.vertices_mm.extend(block.world_vertices());
        let t = block.block_type;
        m.faces.extend(
            t.faces()
                .iter()
                .map(|f| f.iter().map(|&i| base + i as usize).collect()),
        );
        m.edges
            .extend(t.edges().iter().map(|e| [base + e.0, base + e.1]));
    }
    m
}

/// The thesis's viewing parameters (Chapter VI menu: f, a, u, z).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewParams {
    /// The From point F: the eye, world mm.
    pub from_mm: DVec3,
    /// The At point A: where the eye looks, world mm.
    pub at_mm: DVec3,
    /// The Up direction (the thesis's "up point" relative to At); only its part across the
    /// line of sight matters (eq. 2.5c).
    pub up: DVec3,
    /// The view angle in degrees (eq. 2.6); the thesis shows 60 and 30 (Figures 6.11-6.12).
    pub view_angle_deg: f64,
}

impl ViewParams {
    /// A view of all `scenes` from the south-east corner at the isometric elevation (direction
    /// (1, 1, 1)), At at the centre of their bounds, Up = +y, far enough that the bounding
    /// sphere fits the view angle.
    pub fn framing(scenes: &[&Scene], view_angle_deg: f64) -> Result<ViewParams, ViewError> {
        let (lo, hi) = bounds3(scenes.iter().flat_map(|s| s.world_vertices()))
            .ok_or(ViewError::NothingToView)?;
        check_angle(view_angle_deg)?;
        let at_mm = (lo + hi) / 2.0;
        let radius = ((hi - lo) / 2.0).length().max(1.0);
        let distance = radius / (view_angle_deg.to_radians() / 2.0).sin() * 1.1;
        Ok(ViewParams {
            from_mm: at_mm + DVec3::ONE.normalize() * distance,
            at_mm,
            up: DVec3::Y,
            view_angle_deg,
        })
    }

    /// The menu's m ("move from point"): From moved `distance_mm` toward At (negative: away).
    pub fn move_from(self, distance_mm: f64) -> Result<ViewParams, ViewError> {
        if !distance_mm.is_finite() {
            return Err(ViewError::NotFinite {
                option: "--move-from",
            });
        }
        let sight = self.at_mm - self.from_mm;
        let available_mm = sight.length();
        if distance_mm >= available_mm {
            return Err(ViewError::MoveFromPastAt {
                distance_mm,
                available_mm,
            });
        }
        Ok(ViewParams {
            from_mm: self.from_mm + sight / available_mm * distance_mm,
            ..self
        })
    }

    /// The same view with From (and Up) turned `angle_deg` about the vertical line through At:
    /// T(-A) R_y T(A) in the thesis's row-vector order (eq. 2.2, 2.3b).
    pub fn turned_about_at(self, angle_deg: f64) -> ViewParams {
        let m = translation(self.at_mm) * rotation_y(angle_deg) * translation(-self.at_mm);
        ViewParams {
            from_mm: m.transform_point3(self.from_mm),
            up: m.transform_vector3(self.up),
            ..self
        }
    }

    fn check(&self) -> Result<(), ViewError> {
        for (option, v) in [
            ("--at", self.at_mm),
            ("--from", self.from_mm),
            ("--up", self.up),
        ] {
            if !v.is_finite() {
                return Err(ViewError::NotFinite { option });
            }
            let far = v
                .to_array()
                .into_iter()
                .find(|c| c.abs() > MAX_VIEW_COORD_MM);
            if let (Some(value_mm), false) = (far, option == "--up") {
                return Err(ViewError::TooFar { option, value_mm });
            }
        }
        check_angle(self.view_angle_deg)
    }
}

fn check_angle(deg: f64) -> Result<(), ViewError> {
    if (1.0..=170.0).contains(&deg) {
        Ok(())
    } else {
        Err(ViewError::BadViewAngle { deg })
    }
}

/// Whether hidden lines are drawn (the thesis's wireframe) or removed (Chapter VII).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum HiddenLines {
    /// Every edge is drawn, as in Figures 6.7-6.12.
    #[default]
    Show,
    /// Edges behind faces of the same model are removed.
    Remove,
}

/// How the sheet is laid out and drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SheetOptions {
    /// Sheet size in pixels, width and height (default 512 x 512).
    pub size_px: [u32; 2],
    /// Viewports on the sheet (default 1); viewport k looks from From turned k·360°/N about
    /// the vertical through At (Chapter VII: "several viewports that show the objects at
    /// different perspectives on the screen at the same time").
    pub viewports: u32,
    /// Hidden lines shown (default, the thesis) or removed.
    pub hidden_lines: HiddenLines,
    /// Fill faces with flat shading (Chapter VII); implies hidden-line removal.
    pub shade: bool,
    /// The hither plane's distance from the eye in mm (default 1).
    pub hither_mm: f64,
}

impl Default for SheetOptions {
    fn default() -> Self {
        SheetOptions {
            size_px: [512, 512],
            viewports: 1,
            hidden_lines: HiddenLines::Show,
            shade: false,
            hither_mm: 1.0,
        }
    }
}

/// A rectangle of the sheet in picture pixels (x right, y up, origin bottom-left: docs/formats.md
/// "Conventions").
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PixelRect {
    /// Left edge, px.
    pub x0_px: f64,
    /// Bottom edge, px.
    pub y0_px: f64,
    /// Width, px.
    pub width_px: f64,
    /// Height, px.
    pub height_px: f64,
}

/// A drawn piece of a model edge, in sheet picture pixels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PictureLine {
    /// Start, px.
    pub a_px: DVec2,
    /// End, px.
    pub b_px: DVec2,
    /// Whose edge it is.
    pub role: Role,
}

/// A face to fill when shading: its polygon in canonical coordinates (beyond the hither
/// plane) and its flat-shading intensity in [0, 1].
#[derive(Debug, Clone, PartialEq)]
pub struct PictureFace {
    /// The polygon in canonical coordinates (x/z, y/z in [-1, 1] inside the window).
    pub canonical: Vec<DVec3>,
    /// Lambert intensity: ambient plus diffuse from a light above-left of the eye.
    pub intensity: f64,
    /// Whose face it is.
    pub role: Role,
}

/// One viewport: its rectangle, parameters, what it shows and what clipping did.
#[derive(Debug, Clone, PartialEq)]
pub struct Panel {
    /// Where it sits on the sheet.
    pub rect_px: PixelRect,
    /// Its view.
    pub params: ViewParams,
    /// The visible pieces of the edges.
    pub lines: Vec<PictureLine>,
    /// The faces to fill (empty unless shading).
    pub faces: Vec<PictureFace>,
    /// Edges cut by the view volume (eq. 2.7-2.8).
    pub clipped_lines: usize,
    /// Edges wholly outside the view volume.
    pub rejected_lines: usize,
    /// The From/At/Up text of the panel's top right-hand corner (Chapter VI).
    pub label: Vec<String>,
}

impl Panel {
    /// The picture point (px) of a canonical point: x/z and y/z in [-1, 1] fill the largest
    /// square centred in the panel.
    pub fn picture_px(&self, canonical: DVec3) -> DVec2 {
        let (centre, half) = self.window();
        centre + DVec2::new(canonical.x, canonical.y) / canonical.z * half
    }

    /// The window's centre and half side in px.
    pub fn window(&self) -> (DVec2, f64) {
        let r = &self.rect_px;
        let centre = DVec2::new(r.x0_px + r.width_px / 2.0, r.y0_px + r.height_px / 2.0);
        (centre, r.width_px.min(r.height_px) / 2.0)
    }
}

/// A whole sheet: its size and viewports.
#[derive(Debug, Clone, PartialEq)]
pub struct Sheet {
    /// Width, px.
    pub width_px: u32,
    /// Height, px.
    pub height_px: u32,
    /// The viewports, in reading order.
    pub panels: Vec<Panel>,
}

/// Draws `models` on a sheet: one viewport per view (see [`SheetOptions::viewports`]), each
/// through the thesis's pipeline (Figure 2.11).
pub fn draw_sheet(
    models: &[WireModel],
    params: &ViewParams,
    opts: &SheetOptions,
) -> Result<Sheet, ViewError> {
    params.check()?;
    if !(1..=16).contains(&opts.viewports) {
        return Err(ViewError::BadViewports {
            viewports: opts.viewports,
        });
    }
    let [w, h] = opts.size_px;
    let cols = (f64::from(opts.viewports).sqrt().ceil()) as u32;
    let rows = opts.viewports.div_ceil(cols);
    if w / cols < 32 || h / rows < 32 {
        return Err(ViewError::TooSmall {
            width_px: w,
            height_px: h,
        });
    }
    let (pw, ph) = (f64::from(w / cols), f64::from(h / rows));
    let mut panels = Vec::new();
    for k in 0..opts.viewports {
        let rect = PixelRect {
            x0_px: f64::from(k % cols) * pw,
            y0_px: f64::from(h) - f64::from(k / cols + 1) * ph,
            width_px: pw,
            height_px: ph,
        };
        let p = params.turned_about_at(f64::from(k) * 360.0 / f64::from(opts.viewports));
        panels.push(draw_panel(models, &p, opts, rect)?);
    }
    Ok(Sheet {
        width_px: w,
        height_px: h,
        panels,
    })
}

/// The yon distance: just beyond the farthest vertex, so the far plane cuts nothing.
fn yon_mm(models: &[WireModel], params: &ViewParams, hither_mm: f64) -> f64 {
    let far = models
        .iter()
        .flat_map(|m| m.vertices_mm.iter())
        .map(|v| (*v - params.from_mm).length())
        .fold(0.0f64, f64::max);
    (far * 1.01 + 1.0).max(hither_mm * 2.0)
}

fn draw_panel(
    models: &[WireModel],
    params: &ViewParams,
    opts: &SheetOptions,
    rect_px: PixelRect,
) -> Result<Panel, ViewError> {
    let yon = yon_mm(models, params, opts.hither_mm);
    let t = ViewingTransform::new(
        params.from_mm,
        params.at_mm,
        params.up,
        params.view_angle_deg,
        (opts.hither_mm, yon),
    )?;
    let mut panel = Panel {
        rect_px,
        params: *params,
        lines: Vec::new(),
        faces: Vec::new(),
        clipped_lines: 0,
        rejected_lines: 0,
        label: label_lines(params),
    };
    let remove = opts.shade || opts.hidden_lines == HiddenLines::Remove;
    for model in models {
        let eye: Vec<DVec3> = model.vertices_mm.iter().map(|v| t.eye(*v)).collect();
        let faces_eye: Vec<Vec<DVec3>> = model
            .faces
            .iter()
            .map(|f| {
                clip_polygon_to_hither(
                    &f.iter().map(|&i| eye[i]).collect::<Vec<_>>(),
                    opts.hither_mm,
                )
            })
            .filter(|f| f.len() >= 3)
            .collect();
        let occluders: Vec<Occluder> = if remove {
            faces_eye.iter().filter_map(|f| occluder(f)).collect()
        } else {
            Vec::new()
        };
        for &[a, b] in &model.edges {
            draw_edge(&mut panel, &t, (eye[a], eye[b]), &occluders, model.role);
        }
        if opts.shade {
            panel
                .faces
                .extend(faces_eye.iter().map(|f| shaded_face(&t, f, model.role)));
        }
    }
    Ok(panel)
}

/// Clips one edge (eye mm) against the view volume, removes its hidden parts and adds the rest
/// to the panel as picture lines.
fn draw_edge(
    panel: &mut Panel,
    t: &ViewingTransform,
    (e1, e2): (DVec3, DVec3),
    occluders: &[Occluder],
    role: Role,
) {
    let clipped = clip_line(t.canonical(e1), t.canonical(e2), t.z_min);
    match clipped {
        Clipped::Cut { .. } => panel.clipped_lines += 1,
        Clipped::Outside => panel.rejected_lines += 1,
        Clipped::Inside => {}
    }
    let Some((t0, t1)) = clipped.range() else {
        return;
    };
    // The canonical transform is linear, so a parameter means the same point in both spaces.
    let (p1, p2) = (point_at(e1, e2, t0), point_at(e1, e2, t1));
    for (s0, s1) in visible_parts(p1, p2, occluders) {
        let a = panel.picture_px(t.canonical(point_at(p1, p2, s0)));
        let b = panel.picture_px(t.canonical(point_at(p1, p2, s1)));
        let split = (s0, s1) != (0.0, 1.0);
        if split && (b - a).length() < MIN_PIECE_PX {
            continue;
        }
        panel.lines.push(PictureLine {
            a_px: a,
            b_px: b,
            role,
        });
    }
}

/// Pieces of an edge that hidden-line removal leaves shorter than this (px) are dropped: they
/// are the ends of hidden edges within the contact tolerance of the vertex where they meet a
/// visible face, and less than a pixel long.
const MIN_PIECE_PX: f64 = 1.0;

/// Ambient share of the flat shading; the rest is diffuse (Lambert).
const AMBIENT: f64 = 0.35;

/// A face's canonical polygon and its Lambert intensity under a light above-left of the eye
/// (eye coordinates: x right, y up, z into the screen).
fn shaded_face(t: &ViewingTransform, face_eye: &[DVec3], role: Role) -> PictureFace {
    let light = DVec3::new(-0.5, 0.7, -1.0).normalize();
    let n = newell_vector(face_eye);
    // Catalog faces run counter-clockwise seen from outside in a right-handed world; the eye
    // frame is left-handed, so the loop's Newell normal points inward: flip it.
    let outward = -n.normalize_or_zero();
    PictureFace {
        canonical: face_eye.iter().map(|p| t.canonical(*p)).collect(),
        intensity: AMBIENT + (1.0 - AMBIENT) * outward.dot(light).max(0.0),
        role,
    }
}

/// The corner text: From, At, Up and the view angle, as on the thesis's screen (Chapter VI).
fn label_lines(p: &ViewParams) -> Vec<String> {
    let v = |v: DVec3| format!("{:.1} {:.1} {:.1}", v.x, v.y, v.z);
    vec![
        format!("FROM {}", v(p.from_mm)),
        format!("AT {}", v(p.at_mm)),
        format!("UP {}", v(p.up)),
        format!("ANGLE {:.0}", p.view_angle_deg),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Block;

    /// One Baustein 15 resting on the floor at the origin.
    fn cube() -> Scene {
        Scene::new(
            "cube",
            vec![Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 0.0)],
        )
    }

    /// Looking at the cube from a corner above, 100 mm away.
    fn corner_view() -> ViewParams {
        ViewParams {
            from_mm: DVec3::new(60.0, 65.0, 60.0),
            at_mm: DVec3::new(0.0, 7.5, 0.0),
            up: DVec3::Y,
            view_angle_deg: 60.0,
        }
    }

    fn sheet(params: &ViewParams, opts: &SheetOptions) -> Sheet {
        draw_sheet(&[wire_model(&cube(), Role::Model)], params, opts).unwrap()
    }

    #[test]
    fn a_cube_is_8_vertices_6_faces_and_12_edges() {
        let m = wire_model(&cube(), Role::Model);
        assert_eq!(
            (m.vertices_mm.len(), m.faces.len(), m.edges.len()),
            (8, 6, 12)
        );
    }

    #[test]
    fn a_corner_view_shows_12_edges_or_the_9_visible_ones() {
        let all = sheet(&corner_view(), &SheetOptions::default());
        assert_eq!(all.panels[0].lines.len(), 12);
        assert_eq!(all.panels[0].clipped_lines, 0);
        let opts = SheetOptions {
            hidden_lines: HiddenLines::Remove,
            ..SheetOptions::default()
        };
        // From on the diagonal: the hidden back edge lies exactly behind the front one.
        assert_eq!(sheet(&corner_view(), &opts).panels[0].lines.len(), 9);
    }

    #[test]
    fn at_projects_to_the_window_centre() {
        let s = sheet(&corner_view(), &SheetOptions::default());
        let p = &s.panels[0];
        let t = ViewingTransform::new(
            p.params.from_mm,
            p.params.at_mm,
            p.params.up,
            60.0,
            (1.0, 500.0),
        )
        .unwrap();
        let at = p.picture_px(t.canonical(t.eye(p.params.at_mm)));
        assert!((at - DVec2::new(256.0, 256.0)).length() < 1e-9);
    }

    #[test]
    fn moving_from_toward_at_until_it_clips() {
        let near = corner_view().move_from(80.0).unwrap();
        assert!(((near.at_mm - near.from_mm).length() - 22.5).abs() < 1e-9);
        let s = sheet(&near, &SheetOptions::default());
        assert!(s.panels[0].clipped_lines > 0);
        let e = corner_view().move_from(200.0);
        assert!(matches!(e, Err(ViewError::MoveFromPastAt { .. })));
        assert!(corner_view().move_from(-50.0).is_ok());
    }

    #[test]
    fn a_smaller_view_angle_magnifies() {
        let span = |angle: f64| {
            let p = ViewParams {
                view_angle_deg: angle,
                ..corner_view()
            };
            let s = sheet(&p, &SheetOptions::default());
            let xs: Vec<f64> = s.panels[0]
                .lines
                .iter()
                .flat_map(|l| [l.a_px.x, l.b_px.x])
                .collect();
            xs.iter().cloned().fold(f64::MIN, f64::max)
                - xs.iter().cloned().fold(f64::MAX, f64::min)
        };
        // D = 1/tan(15°) against 1/tan(30°): 2.15 times larger.
        let ratio = span(30.0) / span(60.0);
        let expected = (30f64.to_radians()).tan() / (15f64.to_radians()).tan();
        assert!((ratio - expected).abs() < 1e-9, "{ratio} vs {expected}");
    }

    #[test]
    fn four_viewports_tile_the_sheet_and_turn_from_about_at() {
        let opts = SheetOptions {
            viewports: 4,
            ..SheetOptions::default()
        };
        let s = sheet(&corner_view(), &opts);
        assert_eq!(s.panels.len(), 4);
        assert_eq!(s.panels[0].rect_px.y0_px, 256.0);
        assert_eq!(s.panels[3].rect_px.x0_px, 256.0);
        // A quarter turn of R_y (eq. 2.3b) takes the south-east From (+x, +z) to (+x, -z).
        let f = s.panels[1].params.from_mm;
        assert!((f - DVec3::new(60.0, 65.0, -60.0)).length() < 1e-9, "{f}");
        assert!(matches!(
            draw_sheet(
                &[],
                &corner_view(),
                &SheetOptions {
                    viewports: 0,
                    ..opts
                }
            ),
            Err(ViewError::BadViewports { viewports: 0 })
        ));
    }

    #[test]
    fn shading_lights_the_faces_toward_the_light_and_hides_the_back_ones() {
        let opts = SheetOptions {
            shade: true,
            ..SheetOptions::default()
        };
        let s = sheet(&corner_view(), &opts);
        let p = &s.panels[0];
        assert_eq!(p.faces.len(), 6);
        assert_eq!(p.lines.len(), 9, "shading removes hidden lines");
        let lit = p
            .faces
            .iter()
            .filter(|f| f.intensity > AMBIENT + 1e-9)
            .count();
        assert!((1..=3).contains(&lit), "{lit} faces lit");
    }

    #[test]
    fn framing_sees_the_whole_model_and_an_empty_one_is_an_error() {
        let p = ViewParams::framing(&[&cube()], 60.0).unwrap();
        assert_eq!(p.at_mm, DVec3::new(0.0, 7.5, 0.0));
        let s = sheet(&p, &SheetOptions::default());
        assert_eq!(
            (s.panels[0].lines.len(), s.panels[0].clipped_lines),
            (12, 0)
        );
        let empty = Scene::new("empty", Vec::new());
        assert_eq!(
            ViewParams::framing(&[&empty], 60.0),
            Err(ViewError::NothingToView)
        );
        assert!(matches!(
            ViewParams::framing(&[&cube()], 180.0),
            Err(ViewError::BadViewAngle { .. })
        ));
    }
}
