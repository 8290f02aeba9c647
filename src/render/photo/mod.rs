//! The photographic look (docs/rendering.md "Photographic look"): pictures as the thesis's CCD camera
//! took them (Ch. VI), not line art. No ink: an edge shows only through shading, on a render
//! mesh whose block edges carry a small bevel and whose touching blocks leave a narrow crack
//! ([`mesh`]); a key light with a shadow map plus ambient, its direction jittered per scene;
//! per-block gray levels; and a sensor model ([`sensor`]) with blur, noise, gamma, vignetting,
//! quantization and the thesis's 2 x 2 averaging.
//!
//! The ground truth (depth, ids, the exact line drawing) is of the sharp catalog solids,
//! whatever the look, in the coordinates of the picture actually written.

pub mod mesh;
pub mod sensor;
pub mod varied;

use super::gpu::photo::PhotoUniforms;
use super::{
    add_sensor_noise, frame_uniforms, noise_seed, RenderError, RenderOptions, RenderedView,
};
use super::{Gray16Image, Renderer};
use crate::camera::{Camera, CornerView};
use crate::drawing::LineDrawing;
use crate::geom::DVec3;
use crate::io::echo_number;
use crate::scene::Scene;
use image::GrayImage;
use sensor::{RadianceImage, SensorModel};

/// How the gray picture looks (docs/rendering.md "Rendering").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Look {
    /// Flat gray faces with a dark seam on every face edge (docs/rendering.md "Rendering"). The default.
    #[default]
    LineArt,
    /// Shading, shadows and a camera sensor, no drawn ink (docs/rendering.md "Photographic look").
    Photo,
    /// The photo look with its light, shadows, edges, albedos, gloss, sensor, picture size and
    /// projection drawn per scene from the scene's seed (docs/varied-look.md "What is drawn").
    #[serde(rename = "photo_varied")]
    PhotoVaried,
}

impl Look {
    /// Whether this is the line-art look (for serde's `skip_serializing_if`).
    pub fn is_line_art(&self) -> bool {
        *self == Look::LineArt
    }

    /// Parses `lineart`, `photo` or `photo_varied` (any case).
    pub fn parse(s: &str) -> Option<Look> {
        match s.trim().to_ascii_lowercase().as_str() {
            "lineart" | "line-art" => Some(Look::LineArt),
            "photo" => Some(Look::Photo),
            "photo_varied" | "photo-varied" => Some(Look::PhotoVaried),
            _ => None,
        }
    }
}

/// Options of the photographic look; each field's doc gives its unit and default.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct PhotoOptions {
    /// Largest change of the key light's direction per scene, degrees, in azimuth and in
    /// elevation (each uniform in `[-jitter, jitter]`, seeded by the scene's seed); default 0.
    pub light_jitter_deg: f64,
    /// Block albedos are drawn uniformly from `[lo, hi]` per block (seeded); default
    /// `[0.8, 1.0]` (light wood of slightly different shades, thesis Figure 6.3).
    pub block_albedo_range: [f64; 2],
    /// The camera sensor.
    pub sensor: SensorModel,
}

impl Default for PhotoOptions {
    fn default() -> Self {
        PhotoOptions {
            light_jitter_deg: 0.0,
            block_albedo_range: [0.8, 1.0],
            sensor: SensorModel::default(),
        }
    }
}

impl PhotoOptions {
    /// Whether these are the defaults (for serde's `skip_serializing_if`).
    pub fn is_default(&self) -> bool {
        *self == PhotoOptions::default()
    }

    /// Checks the options: jitter 0..=45 degrees, albedos within 0.05..=1 with lo <= hi, and
    /// the sensor's own bounds ([`SensorModel::validate`]).
    pub fn validate(&self) -> Result<(), String> {
        if !(0.0..=45.0).contains(&self.light_jitter_deg) {
            return Err(format!(
                "--light-jitter {} is out of range; use 0..=45 degrees",
                echo_number(self.light_jitter_deg)
            ));
        }
        let [lo, hi] = self.block_albedo_range;
        if !(0.05..=1.0).contains(&lo) || !(0.05..=1.0).contains(&hi) || lo > hi {
            return Err(format!(
                "--block-albedo {},{} is invalid; use LO,HI with 0.05 <= LO <= HI <= 1",
                echo_number(lo),
                echo_number(hi)
            ));
        }
        self.sensor.validate()
    }
}

/// Each side of the photo look's radiance target is this many times the picture's, and the
/// sensor pixel integrates the light over its area (a box average of that many squared
/// samples). 1: one sample per pixel, the sensor's blur does the anti-aliasing; 2 (with a
/// 2048 shadow map) gave the same vision scores on the accuracy suite at about five times the
/// cost.
pub const SUPERSAMPLING: u32 = 1;

/// The parts of a photo view besides its radiance that [`Renderer::render_photo_parts`]
/// runs, so that a benchmark can time the look part by part (`bench render --photo-parts`,
/// docs/rendering.md "Photographic look"); the shadows are left out by the setup
/// ([`PhotoSetup::without_shadows`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PhotoParts {
    /// The sensor of thesis Ch. VI ([`SensorModel::expose`], its noise seeded per scene and
    /// view); without it the radiance read back is only quantized to 8 bits
    /// ([`sensor::quantize`] with gamma 1).
    pub sensor: bool,
    /// The ground-truth draw of the sharp solids; without it depth and ids are left blank (0).
    pub truth: bool,
}

impl PhotoParts {
    /// Every part: the photo view as [`Renderer::render_pixels`] renders it.
    pub const ALL: PhotoParts = PhotoParts {
        sensor: true,
        truth: true,
    };
}

/// The CPU side of one photo view: the picture's camera at full size and as written, the key
/// light and the render mesh ([`mesh::photo_mesh`]); plain data, built without the GPU.
#[derive(Debug, Clone)]
pub struct PhotoSetup {
    full: Camera,
    written: Camera,
    light: mesh::KeyLight,
    mesh: mesh::PhotoMesh,
    /// The highlight's weight and Blinn-Phong exponent (weight 0: matte).
    gloss: [f64; 2],
}

impl PhotoSetup {
    /// The setup of `view` of `scene` with `opts` (its light and albedos seeded by
    /// `opts.seed`), as [`Renderer::render_pixels`] builds it for the photo look.
    pub fn new(scene: &Scene, view: CornerView, opts: &RenderOptions) -> PhotoSetup {
        let (full, written) = view_cameras(scene, view, opts);
        let light = mesh::key_light(&full, opts.photo.light_jitter_deg, opts.seed);
        let albedos = mesh::block_albedos(scene, opts.photo.block_albedo_range, opts.seed);
        let reach_mm = BLOCKER_SEARCH_MM + SHADOW_REACH_MARGIN_MM;
        let mesh = mesh::photo_mesh(scene, &full, &albedos, light.towards_light, reach_mm);
        PhotoSetup {
            full,
            written,
            light,
            mesh,
            gloss: [0.0, 0.0],
        }
    }

    /// The setups of `view` for the varied look's `draw`, one per light (`opts` are the draw's
    /// render options, [`varied::LookDraw::render_options`]).
    pub fn varied(
        scene: &Scene,
        view: CornerView,
        opts: &RenderOptions,
        draw: &varied::LookDraw,
    ) -> Vec<PhotoSetup> {
        let (full, written) = view_cameras(scene, view, opts);
        let reach_mm = BLOCKER_SEARCH_MM + SHADOW_REACH_MARGIN_MM;
        let look = draw.mesh_look();
        draw.key_lights(view)
            .into_iter()
            .map(|light| PhotoSetup {
                full,
                written,
                mesh: mesh::photo_mesh_with(
                    scene,
                    &full,
                    &draw.block_albedos,
                    light.towards_light,
                    reach_mm,
                    &look,
                ),
                light,
                gloss: [draw.gloss, draw.shininess],
            })
            .collect()
    }

    /// The same view with its shadows taken out: no shadow casters, and every radiance
    /// triangle shaded without the shadow test ([`mesh::PhotoMesh::without_shadows`]).
    pub fn without_shadows(&self) -> PhotoSetup {
        PhotoSetup {
            mesh: self.mesh.without_shadows(),
            ..self.clone()
        }
    }

    /// Triangles of the render mesh the GPU draws (radiance and shadow passes together).
    pub fn triangles(&self) -> usize {
        self.mesh.vertices.len() / 3
    }
}

/// The camera of `view` at the rendered size, and the camera of the written picture (the
/// same, or averaged down by `opts.downsample`).
fn view_cameras(scene: &Scene, view: CornerView, opts: &RenderOptions) -> (Camera, Camera) {
    let points: Vec<DVec3> = scene.world_vertices();
    let full = Camera::frame(&points, view, &opts.camera);
    let written = full.downsampled(opts.downsample);
    (full, written)
}

impl Renderer {
    /// Renders the pixels of one view when the look is photo or the picture is downsampled: the
    /// gray picture at the full size (photo: shaded radiance through the sensor; line art: as
    /// [`Renderer::render_pixels`] draws it), sensor noise, then the 2 x 2 averaging; depth and
    /// ids of the sharp solids drawn at the written size, with the written picture's camera.
    pub(super) fn render_pixels_through_sensor(
        &self,
        scene: &Scene,
        view: CornerView,
        opts: &RenderOptions,
    ) -> Result<RenderedView, RenderError> {
        if opts.look == Look::PhotoVaried {
            return self.render_varied(scene, view, opts);
        }
        if opts.look == Look::Photo {
            let setup = PhotoSetup::new(scene, view, opts);
            return self.render_photo_parts(scene, view, opts, &setup, PhotoParts::ALL);
        }
        let (full, written) = view_cameras(scene, view, opts);
        let truth = self.draw_sharp(scene, &written, 1)?;
        let gray = self.draw_sharp(scene, &full, opts.msaa)?.0;
        Ok(written_view(written, gray, truth, opts, view))
    }

    /// The photo look of `view` from a prepared `setup` (made with the same `scene` and
    /// `opts`), running only the given `parts` besides the radiance: for timing the look part
    /// by part (`bench render --photo-parts`). With [`PhotoParts::ALL`] and
    /// [`PhotoSetup::new`] it gives the pixels [`Renderer::render_pixels`] gives.
    pub fn render_photo_parts(
        &self,
        scene: &Scene,
        view: CornerView,
        opts: &RenderOptions,
        setup: &PhotoSetup,
        parts: PhotoParts,
    ) -> Result<RenderedView, RenderError> {
        self.check_options(opts)?;
        // The photo view is submitted first and read after the truth's draw, whose wait
        // covers both: one wait per view.
        let pending = self.submit_photo(scene, setup)?;
        let truth = if parts.truth {
            self.draw_sharp(scene, &setup.written, 1)?
        } else {
            let [w, h] = setup.written.size_px;
            (
                GrayImage::new(w, h),
                Gray16Image::new(w, h),
                Gray16Image::new(w, h),
            )
        };
        let radiance = pending.radiance()?;
        let gray = if parts.sensor {
            let seed = noise_seed(opts.seed, view) ^ 0x005E_450B;
            opts.photo.sensor.expose(&radiance, seed)
        } else {
            sensor::quantize(&radiance, 1.0)
        };
        Ok(written_view(setup.written, gray, truth, opts, view))
    }

    /// The varied look of `view` (docs/varied-look.md): the scene's draw
    /// ([`RenderOptions::look_draw`]) rendered one light at a time, the radiances summed and
    /// scaled by the drawn exposure, then the drawn sensor; the ground truth as in the photo
    /// look, at the drawn written size.
    fn render_varied(
        &self,
        scene: &Scene,
        view: CornerView,
        opts: &RenderOptions,
    ) -> Result<RenderedView, RenderError> {
        let draw = varied::LookDraw::draw(opts.seed, scene.blocks.len(), opts.camera.elevation_deg);
        let drawn = draw.render_options(opts);
        self.check_options(&drawn)?;
        let setups = PhotoSetup::varied(scene, view, &drawn, &draw);
        let written = setups
            .first()
            .map(|s| s.written)
            .ok_or_else(|| RenderError::Options("the varied look drew no light".into()))?;
        let mut radiance: Option<RadianceImage> = None;
        for setup in &setups {
            let r = self.submit_photo(scene, setup)?.radiance()?;
            radiance = Some(match radiance {
                None => r,
                Some(mut sum) => {
                    sum.values
                        .iter_mut()
                        .zip(&r.values)
                        .for_each(|(s, v)| *s += v);
                    sum
                }
            });
        }
        let mut radiance = radiance.unwrap_or_else(|| RadianceImage::filled(1, 1, 0.0));
        let gain = draw.sensor.gain as f32;
        radiance.values.iter_mut().for_each(|v| *v *= gain);
        let truth = self.draw_sharp(scene, &written, 1)?;
        let seed = noise_seed(opts.seed, view) ^ 0x005E_450B;
        let gray = drawn.photo.sensor.expose(&radiance, seed);
        let mut rendered = written_view(written, gray, truth, &drawn, view);
        rendered.towards_lights = draw.towards_lights(view);
        rendered.edge_radius_mm = draw.edge_radius_mm;
        Ok(rendered)
    }

    /// The line-art draw of the sharp solids seen by `camera`: gray, depth and ids.
    fn draw_sharp(
        &self,
        scene: &Scene,
        camera: &Camera,
        msaa: u32,
    ) -> Result<(GrayImage, Gray16Image, Gray16Image), RenderError> {
        let vertices = super::mesh::scene_vertices(scene, camera).map_err(|e| {
            RenderError::Options(format!(
                "block {} face {} has {} edges; the renderer draws faces of at most {} edges",
                e.block,
                e.face,
                e.edges,
                super::mesh::MAX_FACE_EDGES
            ))
        })?;
        let [w, h] = camera.size_px;
        let request = super::gpu::FrameRequest {
            vertices: &vertices,
            uniforms: frame_uniforms(camera),
            floor: super::mesh::floor_fill(scene, camera),
        };
        let frame = self
            .gpu
            .draw_many(&[request], [w, h], msaa)?
            .pop()
            .ok_or_else(|| RenderError::Gpu("the renderer returned no frame".into()))?;
        let wrong = |what: &str| RenderError::Gpu(format!("{what} readback has the wrong size"));
        Ok((
            GrayImage::from_raw(w, h, frame.gray).ok_or_else(|| wrong("gray"))?,
            Gray16Image::from_raw(w, h, frame.depth).ok_or_else(|| wrong("depth"))?,
            Gray16Image::from_raw(w, h, frame.ids).ok_or_else(|| wrong("ids"))?,
        ))
    }

    /// Submits the photo look's picture at the setup's full size: the bevelled, cracked render
    /// mesh shaded on the GPU with the scene's key light and shadow map (the soft shadow test
    /// only where a shadow can reach, [`mesh::photo_mesh`]); [`PendingExposure::radiance`] reads
    /// it back.
    fn submit_photo(
        &self,
        scene: &Scene,
        setup: &PhotoSetup,
    ) -> Result<PendingExposure<'_>, RenderError> {
        let uniforms = photo_uniforms(scene, &setup.full, &setup.light, setup.gloss);
        let [w, h] = setup.full.size_px;
        let size = [w * SUPERSAMPLING, h * SUPERSAMPLING];
        let pending = self
            .gpu
            .submit_photo(&self.photo, &setup.mesh, &uniforms, size)?;
        Ok(PendingExposure { pending, size })
    }
}

/// The written view: sensor noise on `gray` (seeded per scene and view), the 2 x 2 averaging
/// of `opts.downsample`, and the ground truth drawn at the written size.
fn written_view(
    written: Camera,
    mut gray: GrayImage,
    truth: (GrayImage, Gray16Image, Gray16Image),
    opts: &RenderOptions,
    view: CornerView,
) -> RenderedView {
    add_sensor_noise(&mut gray, opts.noise_sigma, noise_seed(opts.seed, view));
    RenderedView {
        camera: written,
        gray: sensor::downsample(&gray, opts.downsample),
        depth: truth.1,
        ids: truth.2,
        lines: LineDrawing::default(),
        towards_lights: Vec::new(),
        edge_radius_mm: 0.0,
    }
}

/// A photo view on the GPU ([`Renderer::submit_photo`]) and the size of its radiance target.
struct PendingExposure<'a> {
    pending: super::gpu::photo::PendingPhoto<'a>,
    size: [u32; 2],
}

impl PendingExposure<'_> {
    /// Waits for the view and reads its radiance back, its `SUPERSAMPLING`^2 samples per
    /// pixel averaged.
    fn radiance(self) -> Result<RadianceImage, RenderError> {
        let samples = self.pending.read()?;
        Ok(box_average(samples, self.size, SUPERSAMPLING))
    }
}

/// The shader constants of one photo view: the picture's camera, and an orthographic shadow
/// camera looking along the key light that frames every block (what lies outside its frame
/// is never shadowed: nothing there casts a shadow), deep enough to reach the floor.
fn photo_uniforms(
    scene: &Scene,
    camera: &Camera,
    light: &mesh::KeyLight,
    [gloss, shininess]: [f64; 2],
) -> PhotoUniforms {
    let points: Vec<DVec3> = scene.world_vertices();
    let (lo, hi) = crate::geom::bounds3(points.iter().copied())
        .unwrap_or((DVec3::splat(-10.0), DVec3::splat(10.0)));
    let centre = (lo + hi) / 2.0;
    let radius = ((hi - lo).length() / 2.0).max(1.0);
    let distance = 4.0 * radius + 100.0;
    let up = if light.towards_light.y.abs() > 0.99 {
        DVec3::Z
    } else {
        DVec3::Y
    };
    let view = crate::camera::look_at(centre + light.towards_light * distance, centre, up);
    let (vlo, vhi) = crate::geom::bounds3(points.iter().map(|p| view.transform_point3(*p)))
        .unwrap_or((DVec3::splat(-radius), DVec3::splat(radius)));
    let pad = 0.02 * radius + 1.0;
    let (near, far) = (1.0, 2.0 * distance + 20.0 * radius + 2000.0);
    let proj = glam::dcamera::rh::proj::directx::orthographic(
        vlo.x - pad,
        vhi.x + pad,
        vlo.y - pad,
        vhi.y + pad,
        near,
        far,
    );
    let texel_mm = (vhi.x - vlo.x + 2.0 * pad).max(vhi.y - vlo.y + 2.0 * pad)
        / f64::from(super::gpu::photo::SHADOW_MAP_PX);
    PhotoUniforms {
        clip_from_world: camera.clip_from_world().as_mat4().to_cols_array(),
        light_clip_from_world: (proj * view).as_mat4().to_cols_array(),
        light_clip_normal: glam::DMat4::from_mat3(
            glam::DMat3::from_mat4(proj * view).inverse().transpose(),
        )
        .as_mat4()
        .to_cols_array(),
        towards_light: light
            .towards_light
            .extend(light.diffuse)
            .as_vec4()
            .to_array(),
        params: [
            light.ambient as f32,
            SHADOW_BIAS_MM as f32,
            (1.5 * texel_mm) as f32,
            texel_mm as f32,
        ],
        soft: [
            light.angular_radius_deg.to_radians().tan() as f32,
            (far - near) as f32,
            BLOCKER_SEARCH_MM as f32,
            MAX_PENUMBRA_MM as f32,
        ],
        soft_min: [
            MIN_PENUMBRA_MM as f32,
            gloss as f32,
            shininess as f32,
            light.floor_bounce as f32,
        ],
        eye: if camera.is_orthographic() {
            camera.towards_eye().extend(0.0)
        } else {
            camera.eye().extend(1.0)
        }
        .as_vec4()
        .to_array(),
    }
}

/// Radius around a shaded point searched for occluders, mm (the widest penumbra a block of
/// the catalog casts on its neighbours is about this).
const BLOCKER_SEARCH_MM: f64 = 8.0;

/// Added to the blocker search radius for [`mesh::photo_mesh`]'s reach of a shadow, mm: covers
/// the receiver's offset along its normal and the shadow map's texels.
const SHADOW_REACH_MARGIN_MM: f64 = 1.0;

/// Smallest penumbra radius, mm: where a shadow touches its occluder (a block on another's
/// top) a hard shadow edge would draw a line no block has.
const MIN_PENUMBRA_MM: f64 = 0.05;

/// Largest penumbra radius, mm.
const MAX_PENUMBRA_MM: f64 = 12.0;

/// Depth bias of the shadow test, mm along the light: far below the crack's width.
const SHADOW_BIAS_MM: f64 = 0.02;

/// Averages `factor` x `factor` blocks of a `size` radiance buffer (rows top to bottom); a
/// factor of 1 hands the buffer over as it is.
fn box_average(samples: Vec<f32>, [w, h]: [u32; 2], factor: u32) -> RadianceImage {
    if factor <= 1 {
        return RadianceImage {
            width: w,
            height: h,
            values: samples,
        };
    }
    let (ow, oh) = (w / factor, h / factor);
    let mut out = RadianceImage::filled(ow, oh, 0.0);
    let scale = 1.0 / (factor * factor) as f32;
    for y in 0..oh as usize {
        for x in 0..ow as usize {
            let mut acc = 0.0;
            for dy in 0..factor as usize {
                let row = (y * factor as usize + dy) * w as usize;
                for dx in 0..factor as usize {
                    acc += samples[row + x * factor as usize + dx];
                }
            }
            out.values[y * ow as usize + x] = acc * scale;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_average_of_a_4x2_buffer_is_two_means() {
        let s = [0.0, 1.0, 0.5, 0.5, 1.0, 0.0, 0.25, 0.75];
        let r = box_average(s.to_vec(), [4, 2], 2);
        assert_eq!((r.width, r.height), (2, 1));
        assert_eq!(r.values, vec![0.5, 0.5]);
    }

    #[test]
    fn looks_parse_and_options_are_checked() {
        assert_eq!(Look::parse("Photo"), Some(Look::Photo));
        assert_eq!(Look::parse("lineart"), Some(Look::LineArt));
        assert_eq!(Look::parse("ink"), None);
        assert!(PhotoOptions::default().validate().is_ok());
        let bad = PhotoOptions {
            block_albedo_range: [0.9, 0.5],
            ..PhotoOptions::default()
        };
        assert!(bad.validate().unwrap_err().contains("albedo"));
        let bad = PhotoOptions {
            light_jitter_deg: 90.0,
            ..PhotoOptions::default()
        };
        assert!(bad.validate().unwrap_err().contains("jitter"));
    }
}
