//! The Chapter VII parts through the pipeline's stages (the thesis's conclusion: "the algorithm
//! is also applied to recognize trapezoidal blocks ... (figure 7.1)"; "with other kinds of
//! blocks like pyramids or circles, the parallelogram surface searching fails"): the wedge `w30`
//! and the round part `c15` rendered, drawn, scored and exported.

mod common;
use common::{distance_to_segment, same_blocks};

use blockworld::camera::{Camera, CameraOptions, CornerView, Projection};
use blockworld::drawing::LineDrawing;
use blockworld::geom::{DVec2, DVec3};
use blockworld::linedraw::visible_line_drawing;
use blockworld::render::RenderOptions;
use blockworld::scene::{Block, Scene};

/// A wedge on a Baustein 30 and a round part standing apart on the floor.
fn wedge_and_round_part() -> Scene {
    Scene::new(
        "wedge_and_round",
        vec![
            Block::new("b30", DVec3::new(0.0, 7.5, 0.0), 0.0),
            Block::new("w30", DVec3::new(0.0, 22.5, 0.0), 0.0),
            Block::new("c15", DVec3::new(0.0, 7.5, 30.0), 0.0),
        ],
    )
}

/// Whether the ray `o + t d` (t > 0) meets the solid upright cylinder of radius `r_mm` whose
/// axis is the vertical through `c` between heights `y0` and `y1`: the side in closed form
/// (a quadratic in t) and the two caps.
fn ray_hits_cylinder(o: DVec3, d: DVec3, c: DVec3, r_mm: f64, [y0, y1]: [f64; 2]) -> bool {
    let (px, pz) = (o.x - c.x, o.z - c.z);
    let a = d.x * d.x + d.z * d.z;
    let b = 2.0 * (px * d.x + pz * d.z);
    let k = px * px + pz * pz - r_mm * r_mm;
    let disc = b * b - 4.0 * a * k;
    if a > 0.0 && disc >= 0.0 {
        for t in [
            (-b - disc.sqrt()) / (2.0 * a),
            (-b + disc.sqrt()) / (2.0 * a),
        ] {
            let y = o.y + t * d.y;
            if t > 0.0 && (y0..=y1).contains(&y) {
                return true;
            }
        }
    }
    [y0, y1].into_iter().any(|y| {
        let t = (y - o.y) / d.y;
        let (x, z) = (o.x + t * d.x - c.x, o.z + t * d.z - c.z);
        t > 0.0 && x * x + z * z <= r_mm * r_mm
    })
}

/// Pixels whose id says "round part" but whose ray misses the exact cylinder of radius `r_mm`,
/// plus pixels the other way round, and the number of pixels of the round part.
fn round_part_id_mismatches(view: &blockworld::render::RenderedView, r_mm: f64) -> (usize, usize) {
    let (w, h) = view.ids.dimensions();
    let (mut wrong, mut area) = (0, 0);
    for row in 0..h {
        for col in 0..w {
            let (o, d) = view
                .camera
                .ray_through_picture(col as f64 + 0.5, h as f64 - row as f64 - 0.5);
            let exact = ray_hits_cylinder(o, d, DVec3::new(0.0, 0.0, 30.0), r_mm, [0.0, 15.0]);
            let drawn = view.ids.get_pixel(col, row)[0] == 3;
            area += drawn as usize;
            wrong += (exact != drawn) as usize;
        }
    }
    (wrong, area)
}

/// The round part is drawn as a cylinder: at 512 x 480 its pixels (ids) are the pixels whose
/// ray meets the exact cylinder, except for fewer than 1 % at its outline (where the pixel
/// centre falls within the 0.009 mm between the circle and the 64-sided prism, or the
/// rasterizer's rounding); a cylinder 0.3 mm wider already fails the check. The wedge shows
/// too, with its sloped face in its own gray level.
#[test]
fn round_part_renders_with_a_smooth_silhouette_and_the_wedge_with_its_slope() {
    let Some(renderer) = common::renderer() else {
        return;
    };
    let scene = wedge_and_round_part();
    let opts = RenderOptions::default();
    assert_eq!(opts.camera.size_px, [512, 480]);
    for view in [CornerView::Sw, CornerView::Ne] {
        let v = renderer.render_pixels(&scene, view, &opts).unwrap();
        let (wrong, area) = round_part_id_mismatches(&v, 7.5);
        assert!(area > 2000, "{view:?}: round part covers {area} px");
        assert!(
            wrong * 100 < area,
            "{view:?}: {wrong} of {area} px off the cylinder"
        );
        let (wider, _) = round_part_id_mismatches(&v, 7.8);
        eprintln!(
            "{view:?}: {wrong} of {area} round-part px off the cylinder; r + 0.3 mm: {wider}"
        );
        assert!(
            wider * 100 > area,
            "{view:?}: the check cannot tell r + 0.3 mm ({wider})"
        );
        let wedge_px = v.ids.pixels().filter(|p| p[0] == 2).count();
        assert!(wedge_px > 1000, "{view:?}: wedge covers {wedge_px} px");
    }
}

/// The first `t > 0` where the ray `o + t d` enters the solid upright cylinder (axis the
/// vertical through `c`, radius `r_mm`, heights `y0..y1`), if any.
fn ray_enters_cylinder(o: DVec3, d: DVec3, c: DVec3, r_mm: f64, [y0, y1]: [f64; 2]) -> Option<f64> {
    let inside = |t: f64| {
        let p = o + d * t;
        (p.x - c.x).hypot(p.z - c.z) <= r_mm + 1e-9 && p.y >= y0 - 1e-9 && p.y <= y1 + 1e-9
    };
    let (px, pz) = (o.x - c.x, o.z - c.z);
    let a = d.x * d.x + d.z * d.z;
    let b = 2.0 * (px * d.x + pz * d.z);
    let k = px * px + pz * pz - r_mm * r_mm;
    let mut ts = Vec::new();
    if a > 1e-15 && b * b - 4.0 * a * k >= 0.0 {
        let q = (b * b - 4.0 * a * k).sqrt();
        ts.extend([(-b - q) / (2.0 * a), (-b + q) / (2.0 * a)]);
    }
    if d.y.abs() > 1e-15 {
        ts.extend([(y0 - o.y) / d.y, (y1 - o.y) / d.y]);
    }
    ts.into_iter()
        .filter(|&t| t > 0.0 && inside(t))
        .min_by(f64::total_cmp)
}

/// The first `t > 0` where the ray enters convex block `b` (its face planes), if any.
fn ray_enters_block(o: DVec3, d: DVec3, b: &Block) -> Option<f64> {
    let v = b.world_vertices();
    let (mut t0, mut t1) = (0.0f64, f64::INFINITY);
    for (f, face) in b.block_type.faces().iter().enumerate() {
        let n = b.world_face_normal(f);
        let (den, dist) = (n.dot(d), n.dot(v[face[0] as usize]) - n.dot(o));
        if den.abs() < 1e-15 {
            if dist < 0.0 {
                return None;
            }
        } else if den > 0.0 {
            t1 = t1.min(dist / den);
        } else {
            t0 = t0.max(dist / den);
        }
    }
    (t0 < t1 && t0 > 0.0).then_some(t0)
}

/// Whether scene point `p` is seen from `camera`: nothing (the round part `round` as its exact
/// cylinder, every other block as its polyhedron) lies on the way to the eye beyond 0.05 mm
/// (the contact tolerance of docs/formats.md "The exact line drawing").
fn seen(scene: &Scene, round: usize, camera: &blockworld::camera::Camera, p: DVec3) -> bool {
    let d = if camera.is_orthographic() {
        camera.towards_eye()
    } else {
        (camera.eye() - p).normalize()
    };
    let o = p + d * 0.05;
    scene.blocks.iter().enumerate().all(|(i, b)| {
        let hit = if i == round {
            let c = b.center_mm;
            ray_enters_cylinder(o, d, c, 7.5, [c.y - 7.5, c.y + 7.5])
        } else {
            ray_enters_block(o, d, b)
        };
        hit.is_none()
    })
}

/// Ray-cast check of a round part's rims in `drawing` (the part is block `round` of `scene`,
/// drawn in `camera`): 720 exact points per rim; each that should be a line (the top rim
/// always, the bottom rim where the side faces the eye) and is seen, with its neighbours half a
/// degree either side seen too, must lie within 0.5 px of a drawn line; each curved line of the
/// drawing must have both 3D ends exactly on a rim circle and its middle seen. Returns the
/// failures.
fn check_round_part_rims(
    scene: &Scene,
    round: usize,
    camera: &blockworld::camera::Camera,
    drawing: &LineDrawing,
) -> Vec<String> {
    let c = scene.blocks[round].center_mm;
    let at = |theta: f64, y: f64| DVec3::new(c.x + 7.5 * theta.cos(), y, c.z + 7.5 * theta.sin());
    let normal = |theta: f64| DVec3::new(theta.cos(), 0.0, theta.sin());
    let px = |p: DVec3| camera.picture_from_world(p).truncate();
    let mut bad = Vec::new();
    for y in [c.y - 7.5, c.y + 7.5] {
        let is_edge = |t: f64| y > c.y || camera.faces_eye(normal(t), at(t, y));
        for k in 0..720 {
            let t = (k as f64 + 0.5).to_radians() / 2.0;
            let steady = [-0.5f64, 0.0, 0.5].map(|dt| {
                let u = t + dt.to_radians();
                is_edge(u) && seen(scene, round, camera, at(u, y))
            });
            if steady != [true; 3] {
                continue;
            }
            let q = px(at(t, y));
            let near = drawing
                .lines
                .iter()
                .any(|&[i, j]| distance_to_segment(q, drawing.points[i], drawing.points[j]) <= 0.5);
            if !near {
                bad.push(format!(
                    "rim y {y} at {:.1} deg: no line within 0.5 px",
                    t.to_degrees()
                ));
            }
        }
    }
    for &l in &drawing.curved_lines {
        let e = &drawing.edges[l];
        let (a, b) = (DVec3::from_array(e.from_mm), DVec3::from_array(e.to_mm));
        for p in [a, b] {
            let r = (p.x - c.x).hypot(p.z - c.z);
            let on_rim = (r - 7.5).abs() < 1e-9 && ((p.y - c.y).abs() - 7.5).abs() < 1e-9;
            if !on_rim {
                bad.push(format!("curved line {l} ends at {p}, off the rims"));
            }
        }
        let m = (a + b) / 2.0;
        let t = (m.z - c.z).atan2(m.x - c.x);
        let steady =
            [-0.5f64, 0.0, 0.5].map(|dt| seen(scene, round, camera, at(t + dt.to_radians(), m.y)));
        if steady == [false; 3] {
            bad.push(format!(
                "curved line {l} at {:.1} deg is hidden",
                t.to_degrees()
            ));
        }
    }
    bad
}

/// The exact drawing of a round part agrees with a ray cast of its exact cylinder: every seen
/// rim point (top rim, and the bottom rim where the side faces the eye) is on a drawn line,
/// every curved line lies on a rim and is seen, and the two silhouette generators are drawn at
/// the exact tangent angles, in all four corner views, orthographic and perspective, for a round
/// part alone, beside a cube (partly hidden by it in some views) and on a cube. A drawing of the
/// part moved 1 mm fails the same check.
#[test]
fn round_part_drawing_matches_a_ray_cast_of_the_exact_cylinder() {
    for (scene, round) in &round_scenes() {
        scene.validate(&scene.name).unwrap();
        for projection in PROJECTIONS {
            let opts = CameraOptions {
                projection,
                ..CameraOptions::default()
            };
            for view in CornerView::ALL {
                let cam = common::frame(scene, view, &opts);
                let d = visible_line_drawing(scene, &cam);
                let what = format!("{} {view:?} {projection:?}", scene.name);
                let curved = d.curved_lines.len();
                assert!(curved > 40, "{what}: {curved} curved");
                let bad = check_round_part_rims(scene, *round, &cam, &d);
                assert!(bad.is_empty(), "{what}: {bad:#?}");
                let generators = generator_lines(scene, *round, &cam, &d);
                assert_eq!(generators, 2, "{what}: generators");
                let mut moved = scene.clone();
                moved.blocks[*round].center_mm.x += 1.0;
                let wrong = visible_line_drawing(&moved, &cam);
                let caught = check_round_part_rims(scene, *round, &cam, &wrong);
                assert!(!caught.is_empty(), "{what}");
            }
        }
    }
}

/// The projections the drawing tests take every corner view in.
const PROJECTIONS: [Projection; 2] = [
    Projection::Orthographic,
    Projection::Perspective { fov_y_deg: 30.0 },
];

/// Scenes with no round part, in which no curve may be reported: the wedge and cube of
/// [`wedge_and_round_part`] without its round part, and a two-layer stack of the basic blocks.
fn scenes_without_round_parts() -> [Scene; 2] {
    let wedge = wedge_and_round_part();
    [
        Scene::new("wedge", wedge.blocks[..2].to_vec()),
        Scene::new(
            "two_layer",
            vec![
                Block::new("b30", DVec3::new(0.0, 7.5, 0.0), 0.0),
                Block::new("b15", DVec3::new(0.0, 22.5, 0.0), 90.0),
                Block::new("b7_5", DVec3::new(22.5, 3.75, 0.0), 0.0),
            ],
        ),
    ]
}

/// Scenes with one round part, and its index: alone, beside a cube, on a cube.
fn round_scenes() -> Vec<(Scene, usize)> {
    let cube = Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 0.0);
    let round = |x: f64, y: f64, z: f64| Block::new("c15", DVec3::new(x, y, z), 0.0);
    vec![
        (Scene::new("alone", vec![round(0.0, 7.5, 0.0)]), 0),
        (Scene::new("beside", vec![cube, round(15.0, 7.5, 15.0)]), 1),
        (Scene::new("on_cube", vec![cube, round(0.0, 22.5, 0.0)]), 1),
    ]
}

/// How many silhouette generators of the round part `drawing` shows (a generator may be cut into
/// several lines by T junctions): its straight lines with both 3D ends on the side where the
/// side's normal is perpendicular to the line of sight (1e-9), counted by angle.
fn generator_lines(
    scene: &Scene,
    round: usize,
    camera: &blockworld::camera::Camera,
    drawing: &LineDrawing,
) -> usize {
    let c = scene.blocks[round].center_mm;
    (0..drawing.lines.len())
        .filter(|l| !drawing.curved_lines.contains(l))
        .filter(|&l| drawing.edges[l].block == round)
        .filter(|&l| {
            let e = &drawing.edges[l];
            [e.from_mm, e.to_mm].iter().all(|p| {
                let p = DVec3::from_array(*p);
                let n = DVec3::new(p.x - c.x, 0.0, p.z - c.z) / 7.5;
                let sight = if camera.is_orthographic() {
                    camera.towards_eye()
                } else {
                    (camera.eye() - p).normalize()
                };
                (n.length() - 1.0).abs() < 1e-9 && n.dot(sight).abs() < 1e-9
            })
        })
        .map(|l| {
            let p = drawing.edges[l].from_mm;
            ((p[2] - c.z).atan2(p[0] - c.x) * 1e6).round() as i64
        })
        .collect::<std::collections::BTreeSet<i64>>()
        .len()
}

/// Chapter VII: "with other kinds of blocks like pyramids or circles, the parallelogram surface
/// searching fails and other algorithms will have to be used". A round part alone gives the
/// parallelogram search nothing to close in any view (no closed parallelogram from any selected
/// vertex); the recognizer sees the rims' curved chains in the drawing and declines every round
/// scene as unsupported, also with the drawing's `curved_lines` flags removed (it reads the
/// picture geometry, never the truth); drawings of basic blocks and wedges show no curved chain.
#[test]
fn parallelogram_search_fails_on_round_parts_chapter_vii() {
    use blockworld::recognize::steps::{
        curved_chain_lines, select_vertices, Face, ParallelogramSearch,
    };
    use blockworld::recognize::{recognize, ObservedView, RecognizeOptions};
    use blockworld::scene::ReconStatus;
    let alone = Scene::new(
        "alone",
        vec![Block::new("c15", DVec3::new(0.0, 7.5, 0.0), 0.0)],
    );
    let on_cube = Scene::new(
        "on_cube",
        vec![
            Block::new("b15", DVec3::new(0.0, 7.5, 0.0), 0.0),
            Block::new("c15", DVec3::new(0.0, 22.5, 0.0), 0.0),
            Block::new("b30", DVec3::new(22.5 + 7.5, 7.5, 0.0), 0.0),
        ],
    );
    let views_of = |scene: &Scene, strip_flags: bool| -> Vec<ObservedView> {
        let mut views = common::exact_views(scene, &CornerView::ALL, &CameraOptions::default());
        if strip_flags {
            views
                .iter_mut()
                .for_each(|v| v.drawing.curved_lines.clear());
        }
        views
    };
    for v in views_of(&alone, true) {
        let search = ParallelogramSearch::new(&v.drawing, 2.0);
        let closed = select_vertices(&v.drawing)
            .iter()
            .flat_map(|s| Face::ALL.map(|f| search.search(s, f)))
            .flatten()
            .filter(|p| p.closed.is_some())
            .count();
        assert_eq!(
            closed, 0,
            "{:?}: a closed parallelogram on a cylinder",
            v.camera.view
        );
    }
    for scene in [&alone, &on_cube] {
        for strip in [false, true] {
            let r = recognize(&views_of(scene, strip), &RecognizeOptions::default()).unwrap();
            assert_eq!(r.status, ReconStatus::Unsupported, "{}", scene.name);
            let reason = r.reason.unwrap();
            assert!(
                reason.contains("circles") && reason.contains("curved"),
                "{reason}"
            );
        }
    }
    let basic = scenes_without_round_parts();
    for scene in &basic {
        for v in views_of(scene, false) {
            let curved = curved_chain_lines(&v.drawing);
            assert!(
                curved.is_empty(),
                "{} {:?}: {curved:?}",
                scene.name,
                v.camera.view
            );
        }
    }
}

/// Chapter VII, Figure 7.1: "Because of the gradient constraints, solid blocks and trapezoidal
/// blocks can be distinguished". In every corner view, orthographic and perspective, the face
/// planes spanned at the junctions of a Baustein 30's drawing all have axis-plane gradients,
/// while the wedge of the same size shows, in at least two of the four views, a plane whose
/// normal is its sloped face's, (1, 1, 0) / sqrt 2 turned with the wedge, with exactly the
/// gradient that face has in the camera (and no other sloped plane in any view); the
/// recognizer reconstructs the wedge from the four views, at its place and facing its way.
#[test]
fn solid_and_trapezoidal_blocks_are_distinguished_by_gradient_figure_7_1() {
    use blockworld::recognize::steps::sloped_faces;
    use blockworld::recognize::{recognize, ObservedView, RecognizeOptions};
    use blockworld::scene::ReconStatus;
    for yaw in [0.0, 90.0, 180.0, 270.0] {
        let block = |id: &str| Scene::new(id, vec![Block::new(id, DVec3::new(0.0, 7.5, 0.0), yaw)]);
        let (solid, wedge) = (block("b30"), block("w30"));
        let slope = wedge.blocks[0].rotation() * DVec3::new(1.0, 1.0, 0.0).normalize();
        for projection in PROJECTIONS {
            let opts = CameraOptions {
                projection,
                ..CameraOptions::default()
            };
            let (mut views, mut seen_sloped) = (Vec::new(), 0);
            for view in CornerView::ALL {
                let what = format!("yaw {yaw} {view:?} {projection:?}");
                let cam = Camera::frame(&solid.blocks[0].world_vertices(), view, &opts);
                let d = visible_line_drawing(&solid, &cam);
                assert!(sloped_faces(&d, &cam, 3.0).is_empty(), "{what}: solid");
                let d = visible_line_drawing(&wedge, &cam);
                let sloped = sloped_faces(&d, &cam, 3.0);
                seen_sloped += usize::from(!sloped.is_empty());
                for g in &sloped {
                    check_sloped_gradient(g, slope, &cam, &what);
                }
                views.push(ObservedView::new(d, cam));
            }
            // A 45-degree slope in a vertical plane projects parallel to a horizontal axis
            // where the viewing direction lies in the plane of the two (isometric corner views:
            // two of four); the other two views show it as a fourth and fifth direction.
            let what = format!("yaw {yaw} {projection:?}");
            assert!(seen_sloped >= 2, "{what}: {seen_sloped} views");
            let r = recognize(&views, &RecognizeOptions::default()).unwrap();
            assert_eq!(r.status, ReconStatus::Ok, "{what}: {:?}", r.reason);
            assert!(
                same_blocks(&r.blocks, &wedge.blocks, SAME_CORNER_MM),
                "{what}: {:?}",
                r.blocks
            );
        }
    }
}

/// How far (mm) a recognized block's corners may lie from the truth's and still be the same
/// block: the recognizer snaps to the 7.5 mm grid, so an exact answer is off by rounding only.
const SAME_CORNER_MM: f64 = 0.1;

/// A sloped face plane found in a drawing is the wedge's: its normal is `slope` (either sign)
/// and its gradient the one that face has in `cam` (relative to its size: a face seen nearly
/// edge-on has a huge gradient; exactly edge-on has none).
fn check_sloped_gradient(
    g: &blockworld::recognize::steps::FaceGradient,
    slope: DVec3,
    cam: &Camera,
    what: &str,
) {
    assert!(
        g.normal.dot(slope).abs() > 1.0 - 1e-6,
        "{what}: {}",
        g.normal
    );
    let [right, up, towards] = cam.axes_in_world();
    let n = slope * slope.dot(towards).signum();
    let c = DVec3::new(n.dot(right), n.dot(up), n.dot(towards));
    if c.z.abs() > 1e-9 {
        let want = DVec2::new(-c.x / c.z, -c.y / c.z);
        let tol = 1e-6 * want.length().max(1.0);
        assert!(
            g.gradient.distance(want) < tol,
            "{what}: {} vs {want}",
            g.gradient
        );
    }
}

/// `generate --family wedge,round` writes the Chapter VII scenes through every stage of the
/// dataset writer: wedge scenes `supported`, round scenes `supported: false` with the Chapter
/// VII reason, the round parts' drawings with `curved_lines` and the wedges' without, and the
/// same bytes with one worker and with two.
#[test]
fn generate_writes_wedge_and_round_scenes_deterministically() {
    let Some(_) = common::renderer() else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let run = |dir: &std::path::Path, jobs: &str| {
        common::ok(common::blockworld([
            "generate",
            "--family",
            "wedge,round",
            "--count",
            "4",
            "--seed",
            "3",
            "--jobs",
            jobs,
            "-o",
            dir.to_str().unwrap(),
        ]));
        std::fs::read_to_string(dir.join("manifest.jsonl")).unwrap()
    };
    let (a, b) = (tmp.path().join("a"), tmp.path().join("b"));
    assert_eq!(run(&a, "1"), run(&b, "2"));
    let mut families = std::collections::BTreeSet::new();
    for k in 0..4 {
        let dir = a.join(format!("s{k:06}"));
        let scene = blockworld::scene::read_scene(&dir.join("scene.json")).unwrap();
        let round = scene.blocks.iter().any(|b| b.block_type.id == "c15");
        let wedge = scene.blocks.iter().any(|b| b.block_type.id == "w30");
        assert!(round != wedge, "{k}: one part per family");
        assert_eq!(scene.is_supported(), wedge, "{k}");
        families.insert(round);
        for view in ["ne", "nw", "se", "sw"] {
            let text = std::fs::read_to_string(dir.join(format!("lines_{view}.json"))).unwrap();
            let d = LineDrawing::from_json(&text).unwrap();
            assert_eq!(!d.curved_lines.is_empty(), round, "{k} {view}");
            assert_eq!(text.contains("curved_lines"), round, "{k} {view}");
        }
    }
    assert_eq!(families.len(), 2, "both families drawn");
}

/// The vision front end's drawings of a scene's four rendered corner views (default options).
fn drawings_from_pictures(
    renderer: &blockworld::render::Renderer,
    scene: &Scene,
    noise_sigma: f64,
) -> Vec<blockworld::recognize::ObservedView> {
    use blockworld::vision::{detect_line_drawing, VisionOptions};
    let opts = RenderOptions {
        noise_sigma,
        seed: 1,
        ..RenderOptions::default()
    };
    renderer
        .render_views(scene, &CornerView::ALL, &opts)
        .unwrap()
        .into_iter()
        .map(|v| {
            let det = detect_line_drawing(&v.gray, &v.camera, &VisionOptions::default()).unwrap();
            blockworld::recognize::ObservedView::new(det.drawing, v.camera)
        })
        .collect()
}

/// Chapter VII's "circles" from pictures: in every rendered view of a round part (alone, beside
/// a cube, on a cube, beside a wedge; with and without sensor noise) vision reports the rims as
/// curves (`curved_lines`, chains the recognizer reads as curved), and the recognizer declines
/// the scene as unsupported for round parts; rendered basic blocks and a wedge give no curve.
#[test]
fn round_parts_are_declined_from_pictures_chapter_vii() {
    use blockworld::recognize::steps::curved_chain_lines;
    use blockworld::recognize::{recognize, RecognizeOptions};
    use blockworld::scene::ReconStatus;
    let Some(renderer) = common::renderer() else {
        return;
    };
    let mut scenes: Vec<Scene> = round_scenes().into_iter().map(|(s, _)| s).collect();
    scenes.push(wedge_and_round_part());
    for noise in [0.0, 8.0] {
        for scene in &scenes {
            let views = drawings_from_pictures(&renderer, scene, noise);
            for v in &views {
                let what = format!("{} {:?} noise {noise}", scene.name, v.camera.view);
                assert!(v.drawing.curved_lines.len() >= 8, "{what}: no curve");
                assert!(!curved_chain_lines(&v.drawing).is_empty(), "{what}");
            }
            let r = recognize(&views, &RecognizeOptions::default()).unwrap();
            assert_eq!(r.status, ReconStatus::Unsupported, "{}", scene.name);
            let reason = r.reason.unwrap_or_default();
            assert!(
                reason.contains("circles") && reason.contains("curved"),
                "{} noise {noise}: {reason}",
                scene.name
            );
        }
    }
    let basic = scenes_without_round_parts();
    for scene in &basic {
        for v in drawings_from_pictures(&renderer, scene, 0.0) {
            let curved = curved_chain_lines(&v.drawing);
            let what = format!("{} {:?}", scene.name, v.camera.view);
            assert!(v.drawing.curved_lines.is_empty(), "{what}");
            assert!(curved.is_empty(), "{what}: {curved:?}");
        }
    }
}

/// Chapter VII, Figure 7.1 from pictures: vision finds a wedge's sloped edges (a fourth and
/// fifth picture direction, looked for among the edge pixels no block-axis line explains), so
/// the recognizer reads the sloped face's gradient and reconstructs wedges turned four ways,
/// on a Baustein 30 and beside a cube, at their places and facing their ways: every one from
/// noise-free pictures, and with noise never a wrong answer (exact, or declined); the same
/// scenes with a Baustein 30 in the wedge's place are recognized.
#[test]
fn trapezoidal_blocks_are_reconstructed_from_pictures_figure_7_1() {
    use blockworld::recognize::{recognize, RecognizeOptions};
    use blockworld::scene::ReconStatus;
    let Some(renderer) = common::renderer() else {
        return;
    };
    let mut noisy_exact = 0;
    for yaw in [0.0, 90.0, 180.0, 270.0] {
        for (part, on_top) in [("w30", true), ("w30", false), ("b30", true)] {
            let (part_y, cube_y) = if on_top { (22.5, 7.5) } else { (7.5, 7.5) };
            let part_block = Block::new(part, DVec3::new(0.0, part_y, 0.0), yaw);
            let mut blocks = vec![part_block];
            if on_top {
                blocks.push(Block::new("b30", DVec3::new(0.0, cube_y, 0.0), yaw));
            } else {
                // Beside the wedge's vertical end, whichever way it faces.
                let end = part_block.world_point(DVec3::new(-22.5, 0.0, 0.0));
                blocks.push(Block::new("b15", end, 0.0));
            }
            let scene = Scene::new("part", blocks);
            for noise in [0.0, 8.0] {
                let views = drawings_from_pictures(&renderer, &scene, noise);
                let r = recognize(&views, &RecognizeOptions::default()).unwrap();
                let what = format!("{part} yaw {yaw} on top {on_top} noise {noise}");
                let exact = r.status == ReconStatus::Ok
                    && same_blocks(&r.blocks, &scene.blocks, SAME_CORNER_MM);
                if noise == 0.0 {
                    assert!(exact, "{what}: {:?} {:?}", r.reason, r.blocks);
                } else {
                    assert!(
                        exact || r.status == ReconStatus::Unsupported,
                        "{what}: {:?}",
                        r.blocks
                    );
                    noisy_exact += usize::from(exact);
                }
            }
        }
    }
    assert!(
        noisy_exact >= 6,
        "with noise only {noisy_exact} of 12 exact"
    );
}

/// The `wedge` family through the whole pipeline from pictures (render, vision, recognizer,
/// score; four noise-free orthographic views, as the accuracy gate runs): stable draws of
/// wedges facing all four ways, on the floor or on a b30, with cubes on and beside them, come
/// out exact, and none is answered wrongly.
#[test]
fn wedge_family_scenes_are_reconstructed_from_pictures() {
    use blockworld::dataset::{draw_stable_scene, scene_seed, Family, SceneSpec};
    use blockworld::physics::SettleParams;
    use blockworld::pipeline::{is_confidently_wrong, run_scene, PipelineOptions};
    use blockworld::score::Verdict;
    let Some(renderer) = common::renderer() else {
        return;
    };
    let opts = PipelineOptions::default();
    let (mut exact, mut facings) = (0, std::collections::BTreeSet::new());
    let count = 12;
    for index in 0..count {
        let spec = SceneSpec {
            index,
            family: Family::Wedge,
            seed: scene_seed(2026, index),
        };
        let scene = draw_stable_scene(&spec, &SettleParams::default())
            .unwrap()
            .scene;
        let run = run_scene(&renderer, &format!("w{index}"), &scene, &opts);
        let reason = run.reconstruction.as_ref().and_then(|r| r.reason.clone());
        assert!(!is_confidently_wrong(&run), "{index}: {:?}", run.result);
        if run.result.verdict == Verdict::Exact {
            exact += 1;
            let wedge = scene
                .blocks
                .iter()
                .find(|b| b.block_type.id == "w30")
                .unwrap();
            facings.insert(
                (wedge
                    .rotation()
                    .to_euler(glam::EulerRot::YXZ)
                    .0
                    .to_degrees()
                    .round() as i64)
                    .rem_euclid(360),
            );
        } else {
            eprintln!("{index}: {:?} {reason:?}", run.result.verdict);
        }
    }
    assert!(exact >= count - 1, "{exact} of {count} exact");
    assert!(facings.len() >= 3, "exact wedges face {facings:?}");
}
