//! The varied photo look (`--look photo_varied`, docs/varied-look.md "What is drawn"): per
//! scene, a seeded draw of what a camera on a bench meets (one to three lights anywhere above
//! the horizon, some turning with each camera and some fixed in the room; ambient; hard to
//! soft shadows; rounded block edges; block and floor albedos, low contrast included; gloss;
//! exposure; blur and noise; picture size with the thesis's 2 x 2 averaging; orthographic or
//! perspective cameras). [`LookDraw`] is that draw, written beside each scene as `look.json`
//! (docs/varied-look.md "look.json") so that a benchmark can bin results by factor and another
//! renderer can draw the same scene the same way. The ground truth stays that of the sharp
//! catalog solids whatever the draw.
//!
//! Plain data, no GPU: the draw depends only on the scene's seed, its block count and the
//! views' elevation, so it is the same whatever `--jobs`.

use super::mesh::{ambient_radiance, EdgeProfile, KeyLight, MeshLook};
use super::sensor::SensorModel;
use super::{Look, PhotoOptions};
use crate::camera::{CameraOptions, CornerView, Projection};
use crate::geom::DVec3;
use crate::render::RenderOptions;
use rand::{Rng, SeedableRng};
use std::collections::BTreeMap;

/// The `format` field of every `look.json` this version writes.
pub const LOOK_FORMAT: &str = "blockworld-look/1";

/// The share of the sensor's range a metered exposure gives the brightest possible block face
/// ([`SensorDraw::gain`]).
pub const METERED_LEVEL: f64 = 0.85;

/// The file written beside each scene's pictures.
pub const LOOK_FILE: &str = "look.json";

/// Where a light hangs (docs/varied-look.md "What is drawn").
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Placement {
    /// A lamp beside the camera: its bearing is relative to each view's camera, so it turns
    /// with the camera and lights every view from the front or side.
    Camera,
    /// A light fixed in the room high above the table (elevation 65 to 88 degrees).
    Overhead,
    /// A light fixed in the room low over the table (a window; elevation 12 to 45 degrees),
    /// behind the blocks in some views.
    Window,
}

/// One light of a draw.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LightDraw {
    /// Where it hangs.
    pub placement: Placement,
    /// Compass bearing of the light seen from the scene, degrees clockwise from north (the
    /// convention of `Camera::azimuth_deg`); for [`Placement::Camera`] relative to each view's
    /// camera bearing (0 = from the camera's own bearing, positive = turned clockwise seen
    /// from above).
    pub bearing_deg: f64,
    /// Elevation above the floor, degrees.
    pub elevation_deg: f64,
    /// Diffuse intensity: radiance of a white face lit head-on by this light alone.
    pub intensity: f64,
}

/// The camera part of a draw.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CameraDraw {
    /// Orthographic or perspective (with its vertical field of view).
    pub projection: Projection,
    /// Rendered picture size, px.
    pub size_px: [u32; 2],
    /// 1, or 2: the written picture is the rendered one averaged 2 x 2 (thesis Ch. VI).
    pub downsample: u32,
    /// Written picture size, px (`size_px / downsample`).
    pub written_size_px: [u32; 2],
    /// Elevation of every view's camera, degrees (the command's `--elevation`, not drawn).
    pub elevation_deg: f64,
}

/// One light as one view sees it.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ViewLight {
    /// Unit vector from the scene towards the light, world (y up, mm frame of the scene).
    pub towards_light: [f64; 3],
    /// Angle between the light's bearing and the camera's, degrees in 0..=180: 0 the light
    /// comes from the camera's side, 180 from straight behind the blocks.
    pub off_camera_deg: f64,
}

/// The sensor part of a draw: the photo look's sensor plus an exposure gain.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SensorDraw {
    /// Exposure relative to a metered one, 0.6 to 1.6: 1 puts a white face lit head-on by
    /// every light at once at [`METERED_LEVEL`] of the sensor's range.
    pub exposure: f64,
    /// The radiance multiplier applied before the sensor: `exposure * METERED_LEVEL /
    /// (brightest block albedo * (ambient + sum of light intensities))`; what goes over 1
    /// clips to white.
    pub gain: f64,
    /// Gaussian PSF sigma, px (of the rendered picture).
    pub blur_sigma_px: f64,
    /// Electrons at radiance 1 (shot noise).
    pub full_well_e: f64,
    /// Read noise, electrons.
    pub read_noise_e: f64,
    /// Display gamma.
    pub gamma: f64,
    /// Corner light falloff.
    pub vignetting: f64,
}

impl SensorDraw {
    /// The sensor model these values describe.
    pub fn model(&self) -> SensorModel {
        SensorModel {
            blur_sigma_px: self.blur_sigma_px,
            full_well_e: self.full_well_e,
            read_noise_e: self.read_noise_e,
            gamma: self.gamma,
            vignetting: self.vignetting,
        }
    }
}

/// One scene's drawn look: the content of `look.json` (docs/varied-look.md "look.json").
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LookDraw {
    /// [`LOOK_FORMAT`].
    pub format: String,
    /// The scene's seed the draw came from.
    pub seed: u64,
    /// One to three lights, the key light first.
    pub lights: Vec<LightDraw>,
    /// Ambient radiance of a white face (light from everywhere, no shadow).
    pub ambient: f64,
    /// Angular radius of every light seen from the scene, degrees: small = hard shadows.
    pub light_radius_deg: f64,
    /// Radius of the rounded block edges, mm (0 = sharp).
    pub edge_radius_mm: f64,
    /// Albedo of each block, in scene order.
    pub block_albedos: Vec<f64>,
    /// Albedo of the floor.
    pub floor_albedo: f64,
    /// Weight of the specular (Blinn-Phong) highlight on blocks, 0 = matte.
    pub gloss: f64,
    /// Blinn-Phong exponent of the highlight.
    pub shininess: f64,
    /// The camera.
    pub camera: CameraDraw,
    /// The sensor.
    pub sensor: SensorDraw,
    /// Per view name (`ne`, ...): each light as that view sees it, in `lights` order.
    pub views: BTreeMap<String, Vec<ViewLight>>,
    /// Per factor, the bin this draw falls in (docs/varied-look.md "Factors and bins"), for
    /// `bench accuracy`'s per-factor table.
    pub bins: BTreeMap<String, String>,
}

/// Unit vector towards a light at compass `bearing_deg` and `elevation_deg` (the frame of
/// `Camera::frame`: north is -z, east is +x, up is +y).
pub fn towards_bearing(bearing_deg: f64, elevation_deg: f64) -> [f64; 3] {
    let (az, el) = (bearing_deg.to_radians(), elevation_deg.to_radians());
    [el.cos() * az.sin(), el.sin(), -el.cos() * az.cos()]
}

/// The angle between two bearings, degrees in 0..=180.
fn bearing_gap_deg(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(360.0);
    d.min(360.0 - d)
}

impl LightDraw {
    /// The compass bearing of the light in `view` (a camera lamp turns with the camera).
    pub fn bearing_in(&self, view: CornerView) -> f64 {
        match self.placement {
            Placement::Camera => (view.azimuth_deg() + self.bearing_deg).rem_euclid(360.0),
            Placement::Overhead | Placement::Window => self.bearing_deg.rem_euclid(360.0),
        }
    }

    /// This light as `view` sees it.
    pub fn in_view(&self, view: CornerView) -> ViewLight {
        let bearing = self.bearing_in(view);
        ViewLight {
            towards_light: towards_bearing(bearing, self.elevation_deg),
            off_camera_deg: bearing_gap_deg(bearing, view.azimuth_deg()),
        }
    }
}

/// Uniform in `[lo, hi]`.
fn uniform(rng: &mut impl Rng, lo: f64, hi: f64) -> f64 {
    rng.random_range(lo..=hi)
}

/// Log-uniform in `[lo, hi]` (both positive).
fn log_uniform(rng: &mut impl Rng, lo: f64, hi: f64) -> f64 {
    uniform(rng, lo.ln(), hi.ln()).exp()
}

/// Draws one light of `placement` (the key light at full intensity, fill lights dimmer).
fn draw_light(rng: &mut impl Rng, placement: Placement, key: bool) -> LightDraw {
    let (bearing_deg, elevation_deg) = match placement {
        Placement::Camera => (uniform(rng, -75.0, 75.0), uniform(rng, 15.0, 70.0)),
        Placement::Overhead => (uniform(rng, 0.0, 360.0), uniform(rng, 65.0, 88.0)),
        Placement::Window => (uniform(rng, 0.0, 360.0), uniform(rng, 12.0, 45.0)),
    };
    LightDraw {
        placement,
        bearing_deg,
        elevation_deg,
        intensity: if key {
            uniform(rng, 0.55, 0.8)
        } else {
            uniform(rng, 0.1, 0.45)
        },
    }
}

/// Draws a placement: a camera lamp half the time, else overhead or window.
fn draw_placement(rng: &mut impl Rng) -> Placement {
    match rng.random_range(0..4u32) {
        0 | 1 => Placement::Camera,
        2 => Placement::Overhead,
        _ => Placement::Window,
    }
}

/// Draws the camera: orthographic or perspective (15 to 40 degrees), and one of 512 x 480,
/// 256 x 240, or 256 x 240 averaged to the thesis's 128 x 120.
fn draw_camera(rng: &mut impl Rng, elevation_deg: f64) -> CameraDraw {
    let projection = if rng.random_bool(0.5) {
        Projection::Orthographic
    } else {
        Projection::Perspective {
            fov_y_deg: uniform(rng, 15.0, 40.0),
        }
    };
    let (size_px, downsample) = match rng.random_range(0..3u32) {
        0 => ([512, 480], 1),
        1 => ([256, 240], 1),
        _ => ([256, 240], 2),
    };
    CameraDraw {
        projection,
        size_px,
        downsample,
        written_size_px: [size_px[0] / downsample, size_px[1] / downsample],
        elevation_deg,
    }
}

/// Draws the sensor: exposure 0.6 to 1.6 (log-uniform), blur 0.3 to 1.5 px, full well 2,000
/// to 50,000 electrons (log-uniform), read noise 0 to 30 electrons, gamma 1, vignetting 0 to
/// 0.3.
fn draw_sensor(rng: &mut impl Rng) -> SensorDraw {
    SensorDraw {
        exposure: log_uniform(rng, 0.6, 1.6),
        gain: 1.0,
        blur_sigma_px: uniform(rng, 0.3, 1.5),
        full_well_e: log_uniform(rng, 2_000.0, 50_000.0),
        read_noise_e: uniform(rng, 0.0, 30.0),
        gamma: 1.0,
        vignetting: uniform(rng, 0.0, 0.3),
    }
}

/// Draws the albedos: a block shade 0.3 to 0.95 with each block within 0.08 of it, and a floor
/// 0.05 to 0.8, a quarter of the time within 0.12 of the block shade (low contrast).
fn draw_albedos(rng: &mut impl Rng, blocks: usize) -> (Vec<f64>, f64) {
    let shade = uniform(rng, 0.3, 0.95);
    let block_albedos = (0..blocks)
        .map(|_| (shade + uniform(rng, -0.08, 0.08)).clamp(0.05, 1.0))
        .collect();
    let floor = if rng.random_bool(0.25) {
        (shade + uniform(rng, -0.12, 0.12)).clamp(0.05, 0.95)
    } else {
        uniform(rng, 0.05, 0.8)
    };
    (block_albedos, floor)
}

impl LookDraw {
    /// The draw of the scene whose seed is `seed`, with `blocks` blocks, its cameras at
    /// `elevation_deg` (docs/varied-look.md "What is drawn").
    pub fn draw(seed: u64, blocks: usize, elevation_deg: f64) -> LookDraw {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed ^ 0x7661_7279_6C6F_6F6B);
        let count = match rng.random_range(0..10u32) {
            0..=4 => 1,
            5..=7 => 2,
            _ => 3,
        };
        let lights: Vec<LightDraw> = (0..count)
            .map(|k| {
                let placement = draw_placement(&mut rng);
                draw_light(&mut rng, placement, k == 0)
            })
            .collect();
        let ambient = uniform(&mut rng, 0.0, 0.45);
        let light_radius_deg = uniform(&mut rng, 0.5, 25.0);
        let edge_radius_mm = uniform(&mut rng, 0.0, 0.5);
        let (block_albedos, floor_albedo) = draw_albedos(&mut rng, blocks);
        let (gloss, shininess) = if rng.random_bool(0.5) {
            (0.0, 1.0)
        } else {
            (uniform(&mut rng, 0.05, 0.4), uniform(&mut rng, 10.0, 80.0))
        };
        let camera = draw_camera(&mut rng, elevation_deg);
        let mut sensor = draw_sensor(&mut rng);
        let brightest = block_albedos.iter().copied().fold(0.05, f64::max);
        let full_light = ambient + lights.iter().map(|l| l.intensity).sum::<f64>();
        sensor.gain = sensor.exposure * METERED_LEVEL / (brightest * full_light);
        let views = CornerView::ALL
            .iter()
            .map(|v| {
                (
                    v.name().to_string(),
                    lights.iter().map(|l| l.in_view(*v)).collect(),
                )
            })
            .collect();
        let mut draw = LookDraw {
            format: LOOK_FORMAT.to_string(),
            seed,
            lights,
            ambient,
            light_radius_deg,
            edge_radius_mm,
            block_albedos,
            floor_albedo,
            gloss,
            shininess,
            camera,
            sensor,
            views,
            bins: BTreeMap::new(),
        };
        draw.bins = factor_bins(&draw);
        draw
    }

    /// The render options of this draw: `base` with the drawn projection, picture size,
    /// averaging and sensor (its own noise, seed and elevation kept).
    pub fn render_options(&self, base: &RenderOptions) -> RenderOptions {
        RenderOptions {
            camera: CameraOptions {
                projection: self.camera.projection,
                size_px: self.camera.size_px,
                ..base.camera
            },
            downsample: self.camera.downsample,
            photo: PhotoOptions {
                sensor: self.sensor.model(),
                ..base.photo
            },
            ..*base
        }
    }

    /// Every light as `view` sees it, the ambient given to the first only, each with the
    /// drawn angular radius and the light it sends back up off the floor (the shader sums them
    /// through one radiance pass per light).
    pub fn key_lights(&self, view: CornerView) -> Vec<KeyLight> {
        self.lights
            .iter()
            .enumerate()
            .map(|(k, l)| {
                let towards_light = DVec3::from_array(l.in_view(view).towards_light);
                let ambient = if k == 0 { self.ambient } else { 0.0 };
                KeyLight {
                    towards_light,
                    diffuse: l.intensity,
                    ambient,
                    angular_radius_deg: self.light_radius_deg,
                    floor_bounce: self.floor_bounce(l.intensity, towards_light, ambient),
                }
            })
            .collect()
    }

    /// The radiance the floor sends up onto a face turned straight down, per unit albedo of
    /// the face, from one light of `intensity` towards `towards_light` and the `ambient` it
    /// carries: the floor's irradiance (the light's cosine on it plus the sky) times its
    /// albedo, over two, so a side face, which sees half the floor, gets half of it
    /// ([`KeyLight::floor_bounce`]). One bounce off a floor lit evenly all round: the blocks'
    /// own shadows on it and light between blocks are left out. Without it a face turned from
    /// every light is lit by the ambient alone, darker than Cycles draws it over a light floor
    /// (docs/yardstick.md "Where the looks part").
    fn floor_bounce(&self, intensity: f64, towards_light: DVec3, ambient: f64) -> f64 {
        self.floor_albedo * (intensity * towards_light.y.max(0.0) + ambient) / 2.0
    }

    /// The unit vector towards each light as `view` sees it, in `lights` order: what
    /// `look.json` records under `views` (the recognizer's known lights).
    pub fn towards_lights(&self, view: CornerView) -> Vec<DVec3> {
        self.lights
            .iter()
            .map(|l| DVec3::from_array(l.in_view(view).towards_light))
            .collect()
    }

    /// The render mesh's drawn edge profile and floor.
    pub fn mesh_look(&self) -> MeshLook {
        MeshLook {
            edge: EdgeProfile::rounded(self.edge_radius_mm),
            floor_albedo: self.floor_albedo,
        }
    }

    /// The draw as `look.json` text (pretty JSON, a final newline).
    pub fn to_json(&self) -> String {
        crate::io::pretty_json(self)
    }
}

impl RenderOptions {
    /// The varied look's draw for a scene of `blocks` blocks rendered with these options (its
    /// seed is the scene's): `None` unless the look is [`Look::PhotoVaried`].
    pub fn look_draw(&self, blocks: usize) -> Option<LookDraw> {
        (self.look == Look::PhotoVaried)
            .then(|| LookDraw::draw(self.seed, blocks, self.camera.elevation_deg))
    }
}

/// The factors [`factor_bins`] bins a draw by, in table order (docs/varied-look.md "Factors
/// and bins").
pub const FACTORS: [&str; 12] = [
    "key light",
    "backlit views",
    "lights",
    "ambient",
    "shadows",
    "edge radius",
    "contrast",
    "gloss",
    "exposure",
    "noise",
    "camera",
    "size",
];

/// Names a value's bin among `(upper bound, name)` steps; above every bound, `last`.
fn bin(value: f64, steps: &[(f64, &str)], last: &str) -> String {
    steps
        .iter()
        .find(|(hi, _)| value < *hi)
        .map_or(last, |(_, name)| name)
        .to_string()
}

/// The weakest step between the blocks and the floor the draw puts in a picture, gray levels:
/// over the four views and the three block faces each sees (the top and the two sides facing
/// the camera), the smallest difference between the face and the floor, each lit by every
/// light that faces it (Lambert, no cast shadow, no gloss) plus the ambient and the floor's
/// bounce ([`ambient_radiance`]), at the mean block albedo and the floor albedo, through the
/// draw's gain (255 levels, clipped at white). A face lit like the floor beside it draws a
/// faint outline whatever the albedos: a shaded side of a light block on a dark floor can
/// match it. Chapter VI's threshold of 80 on the smoothed Sobel magnitude answers to a step of
/// 20 levels.
pub fn outline_contrast_levels(draw: &LookDraw) -> f64 {
    let mean_block =
        draw.block_albedos.iter().sum::<f64>() / draw.block_albedos.len().max(1) as f64;
    let level = |albedo: f64, normal: DVec3, lights: &[KeyLight]| {
        let lit: f64 = lights
            .iter()
            .map(|l| {
                ambient_radiance(l.ambient, l.floor_bounce, normal)
                    + l.diffuse * normal.dot(l.towards_light).max(0.0)
            })
            .sum();
        255.0 * (draw.sensor.gain * albedo * lit).min(1.0)
    };
    CornerView::ALL
        .iter()
        .filter(|v| draw.views.contains_key(v.name()))
        .filter_map(|&v| {
            let lights = draw.key_lights(v);
            let [x, _, z] = towards_bearing(v.azimuth_deg(), 0.0);
            let faces = [DVec3::Y, DVec3::X * x.signum(), DVec3::Z * z.signum()];
            let floor = level(draw.floor_albedo, DVec3::Y, &lights);
            faces
                .iter()
                .map(|&n| (level(mean_block, n, &lights) - floor).abs())
                .reduce(f64::min)
        })
        .reduce(f64::min)
        .unwrap_or(0.0)
}

/// The bin of every factor of `draw` (docs/varied-look.md "Factors and bins").
pub fn factor_bins(draw: &LookDraw) -> BTreeMap<String, String> {
    let key = draw.lights.first();
    let key_name = match key.map(|l| l.placement) {
        Some(Placement::Camera) => "lamp beside the camera",
        Some(Placement::Overhead) => "overhead",
        Some(Placement::Window) | None => "window",
    };
    let backlit = draw
        .views
        .values()
        .filter(|ls| ls.first().is_some_and(|l| l.off_camera_deg > 100.0))
        .count();
    let contrast = outline_contrast_levels(draw);
    let noise_e = draw
        .sensor
        .full_well_e
        .sqrt()
        .hypot(draw.sensor.read_noise_e);
    let noise_levels = 255.0 * noise_e / draw.sensor.full_well_e;
    let values = [
        key_name.to_string(),
        bin(backlit as f64, &[(0.5, "none"), (2.5, "1-2")], "3-4"),
        draw.lights.len().to_string(),
        bin(draw.ambient, &[(0.1, "none"), (0.3, "some")], "strong"),
        bin(
            draw.light_radius_deg,
            &[(5.0, "hard"), (15.0, "medium")],
            "soft",
        ),
        bin(
            draw.edge_radius_mm,
            &[(0.15, "0-0.15 mm"), (0.35, "0.15-0.35 mm")],
            "0.35-0.5 mm",
        ),
        bin(contrast, &[(10.0, "low"), (25.0, "medium")], "high"),
        bin(draw.gloss, &[(1e-9, "matte")], "glossy"),
        bin(
            draw.sensor.exposure,
            &[(0.8, "under"), (1.25, "normal")],
            "over",
        ),
        bin(noise_levels, &[(1.5, "low"), (3.0, "medium")], "high"),
        match draw.camera.projection {
            Projection::Orthographic => "orthographic".to_string(),
            Projection::Perspective { .. } => "perspective".to_string(),
        },
        format!(
            "{}x{}",
            draw.camera.written_size_px[0], draw.camera.written_size_px[1]
        ),
    ];
    FACTORS
        .iter()
        .zip(values)
        .map(|(f, v)| (f.to_string(), v))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_draw_is_seeded_and_stays_in_its_ranges() {
        let a = LookDraw::draw(33, 4, 35.0);
        assert_eq!(a, LookDraw::draw(33, 4, 35.0));
        assert_ne!(a, LookDraw::draw(34, 4, 35.0));
        for seed in 0..200 {
            let d = LookDraw::draw(seed, 3, 35.0);
            assert!((1..=3).contains(&d.lights.len()));
            assert!(d
                .lights
                .iter()
                .all(|l| (0.0..90.0).contains(&l.elevation_deg)));
            assert!((0.0..=0.5).contains(&d.edge_radius_mm));
            assert!((0.6..=1.6).contains(&d.sensor.exposure));
            assert_eq!(d.block_albedos.len(), 3);
            assert_eq!(d.views.len(), 4);
            assert_eq!(d.bins.len(), FACTORS.len());
            if let Projection::Perspective { fov_y_deg } = d.camera.projection {
                assert!((15.0..=40.0).contains(&fov_y_deg));
            }
        }
    }

    #[test]
    fn a_camera_lamp_turns_with_the_view_and_a_window_stays() {
        let lamp = LightDraw {
            placement: Placement::Camera,
            bearing_deg: 0.0,
            elevation_deg: 30.0,
            intensity: 0.6,
        };
        let window = LightDraw {
            placement: Placement::Window,
            ..lamp
        };
        for v in CornerView::ALL {
            assert!(lamp.in_view(v).off_camera_deg < 1e-9);
        }
        // North window (bearing 0): the ne camera (bearing 45) sees it 45 degrees off, the sw
        // camera (225) from behind the blocks.
        assert!((window.in_view(CornerView::Ne).off_camera_deg - 45.0).abs() < 1e-9);
        assert!((window.in_view(CornerView::Sw).off_camera_deg - 135.0).abs() < 1e-9);
        let [x, y, z] = towards_bearing(90.0, 0.0);
        assert!((x - 1.0).abs() < 1e-12 && y.abs() < 1e-12 && z.abs() < 1e-12);
    }

    /// The contrast bin reads the drawn light, not the albedos alone: a light block on a dark
    /// floor lit from straight above (its sides get the floor's bounce only) draws a faint
    /// outline.
    #[test]
    fn the_outline_contrast_is_the_weakest_face_against_the_floor() {
        let mut d = LookDraw::draw(33, 1, 35.0);
        d.lights.truncate(1);
        d.lights[0].elevation_deg = 90.0;
        d.lights[0].intensity = 0.7;
        d.ambient = 0.0;
        d.block_albedos = vec![0.9];
        d.floor_albedo = 0.1;
        d.sensor.gain = 1.0;
        d.views = CornerView::ALL
            .iter()
            .map(|v| (v.name().to_string(), vec![d.lights[0].in_view(*v)]))
            .collect();
        // Sides lit by the floor's bounce alone (0.9 x 0.1 x 0.7 / 2 = 0.0315) against a
        // floor at 0.07: 9.8175 levels.
        assert!((outline_contrast_levels(&d) - 9.8175).abs() < 1e-6);
        assert_eq!(factor_bins(&d)["contrast"], "low");
        // A lamp beside the camera at 30 degrees lights every visible face brighter.
        d.lights[0].placement = Placement::Camera;
        d.lights[0].bearing_deg = 0.0;
        d.lights[0].elevation_deg = 30.0;
        d.views = CornerView::ALL
            .iter()
            .map(|v| (v.name().to_string(), vec![d.lights[0].in_view(*v)]))
            .collect();
        assert!(
            outline_contrast_levels(&d) > 25.0,
            "{}",
            outline_contrast_levels(&d)
        );
        assert_eq!(factor_bins(&d)["contrast"], "high");
        d.ambient = 0.0;
        d.floor_albedo = 0.9;
        assert_eq!(factor_bins(&d)["contrast"], "low");
    }

    #[test]
    fn look_json_reads_back_as_the_same_draw() {
        let d = LookDraw::draw(3333, 5, 35.26);
        let back: LookDraw = serde_json::from_str(&d.to_json()).unwrap();
        assert_eq!(back, d);
        assert!(d.to_json().contains("\"format\": \"blockworld-look/1\""));
    }
}
