//! Render options shared by every command that renders (`render`, `demo`, `generate`,
//! `bench ...`), flattened into their clap `Args`.

use anyhow::{bail, Context};
use blockworld::camera::{CameraOptions, CornerView, Projection};
use blockworld::geom::ISOMETRIC_ELEVATION_DEG;
use blockworld::render::photo::sensor::SensorModel;
use blockworld::render::{Backend, Look, PhotoOptions, RenderOptions};

/// How views are rendered (docs/rendering.md "Rendering").
#[derive(Debug, Clone, clap::Args)]
pub struct ViewArgs {
    /// Views to render, comma separated (ne, se, sw, nw).
    #[arg(long, default_value = "ne,se,sw,nw", value_delimiter = ',')]
    pub views: Vec<String>,
    /// Picture size in pixels, WxH (the thesis's digitizer is 512x480).
    #[arg(long, default_value = "512x480")]
    pub size: String,
    /// Camera elevation above the floor in degrees (default: exact isometric, 35.26439).
    #[arg(long)]
    pub elevation: Option<f64>,
    /// orthographic (default) or perspective.
    #[arg(long, default_value = "orthographic")]
    pub projection: String,
    /// Vertical field of view in degrees for --projection perspective.
    #[arg(long, default_value_t = 30.0)]
    pub fov: f64,
    /// Vertical/horizontal pixel size ratio (1.173913 is the thesis's CCD).
    #[arg(long, default_value_t = 1.0)]
    pub pixel_aspect: f64,
    /// Multisample anti-aliasing: 1 (exact gray levels) or 4.
    #[arg(long, default_value_t = 1)]
    pub msaa: u32,
    /// Gaussian sensor noise, standard deviation in gray levels.
    #[arg(long, default_value_t = 0.0)]
    pub noise: f64,
    /// Seed: of the sensor noise for `render`; of the whole dataset for `generate` (each
    /// scene's own seed, noise included, derives from it).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Graphics backend: vulkan (lavapipe, default) or gl (llvmpipe through EGL).
    #[arg(long, default_value = "vulkan")]
    pub backend: String,
    /// Picture look: lineart (flat faces with drawn seams, default), photo (shading, shadows
    /// and a camera sensor; docs/rendering.md "Photographic look") or photo_varied (the photo look with
    /// light, shadows, edges, albedos, sensor, size and projection drawn per scene;
    /// docs/varied-look.md).
    #[arg(long, default_value = "lineart")]
    pub look: String,
    /// Photo look: largest turn of the key light per scene, degrees (seeded).
    #[arg(long, default_value_t = 0.0)]
    pub light_jitter: f64,
    /// Write the picture averaged 2x2 once (2) or twice (4), as the thesis did; 1 = no.
    #[arg(long, default_value_t = 1)]
    pub downsample: u32,
    /// Photo look: block albedo range LO,HI (each block draws one, seeded).
    #[arg(long, default_value = "0.8,1.0")]
    pub block_albedo: String,
    /// Photo sensor: optical blur, Gaussian PSF sigma in px.
    #[arg(long, default_value_t = 0.7)]
    pub sensor_blur: f64,
    /// Photo sensor: electrons at full well (shot noise); 0 = no shot noise.
    #[arg(long, default_value_t = 20_000.0)]
    pub sensor_full_well: f64,
    /// Photo sensor: read noise in electrons.
    #[arg(long, default_value_t = 12.0)]
    pub sensor_read_noise: f64,
    /// Photo sensor: gamma (recorded level = radiance^(1/gamma)).
    #[arg(long, default_value_t = 1.0)]
    pub sensor_gamma: f64,
    /// Photo sensor: share of light lost in the corners.
    #[arg(long, default_value_t = 0.15)]
    pub sensor_vignetting: f64,
}

/// The corner views named by a `--views` list, in its order: an unknown name or a view named
/// twice is an error that says so.
pub fn parse_corner_views<'a>(
    names: impl IntoIterator<Item = &'a String>,
) -> anyhow::Result<Vec<CornerView>> {
    parse_corner_views_of("--views", names)
}

/// [`parse_corner_views`] for the list given to `flag`, which the errors name.
pub fn parse_corner_views_of<'a>(
    flag: &str,
    names: impl IntoIterator<Item = &'a String>,
) -> anyhow::Result<Vec<CornerView>> {
    let mut views: Vec<CornerView> = Vec::new();
    for v in names {
        let view = CornerView::parse(v)
            .with_context(|| format!("{flag}: unknown view {v:?}; use ne, se, sw, nw"))?;
        if views.contains(&view) {
            bail!(
                "{flag}: {} is given twice; name each view once",
                view.name()
            );
        }
        views.push(view);
    }
    Ok(views)
}

impl ViewArgs {
    /// The corner views asked for.
    /// A view named twice is an error (it would be rendered and written twice); an empty list
    /// is allowed here (`generate --views ""` writes scene.json only), see
    /// [`ViewArgs::some_corner_views`].
    pub fn corner_views(&self) -> anyhow::Result<Vec<CornerView>> {
        parse_corner_views(self.views.iter().filter(|v| !v.trim().is_empty()))
    }

    /// The corner views asked for, at least one (for commands whose only output is views).
    pub fn some_corner_views(&self) -> anyhow::Result<Vec<CornerView>> {
        let views = self.corner_views()?;
        if views.is_empty() {
            bail!("--views: no view given; name one or more of ne, se, sw, nw");
        }
        Ok(views)
    }

    /// The backend asked for.
    pub fn backend(&self) -> anyhow::Result<Backend> {
        parse_backend(&self.backend)
    }

    /// Checked render options.
    pub fn render_options(&self) -> anyhow::Result<RenderOptions> {
        let (w, h) = self
            .size
            .split_once(['x', 'X'])
            .and_then(|(w, h)| Some((w.trim().parse::<u32>().ok()?, h.trim().parse::<u32>().ok()?)))
            .with_context(|| {
                format!("--size: expected WxH such as 512x480, got {:?}", self.size)
            })?;
        if !(8..=8192).contains(&w) || !(8..=8192).contains(&h) {
            bail!("--size: {w}x{h} is out of range; each side must be 8..=8192 pixels");
        }
        let projection = match self.projection.to_ascii_lowercase().as_str() {
            "orthographic" | "ortho" => Projection::Orthographic,
            "perspective" => Projection::Perspective {
                fov_y_deg: self.fov,
            },
            other => bail!("--projection: unknown {other:?}; use orthographic or perspective"),
        };
        let elevation_deg = self.elevation.unwrap_or(ISOMETRIC_ELEVATION_DEG);
        let opts = RenderOptions {
            camera: CameraOptions {
                size_px: [w, h],
                elevation_deg,
                projection,
                pixel_aspect: self.pixel_aspect,
                ..CameraOptions::default()
            },
            msaa: self.msaa,
            noise_sigma: self.noise,
            seed: self.seed,
            look: Look::parse(&self.look).with_context(|| {
                format!(
                    "--look: unknown {:?}; use lineart, photo or photo_varied",
                    self.look
                )
            })?,
            downsample: self.downsample,
            photo: self.photo_options()?,
        };
        opts.validate()?;
        Ok(opts)
    }

    /// The photo look's options from `--light-jitter`, `--block-albedo` and `--sensor-*`.
    fn photo_options(&self) -> anyhow::Result<PhotoOptions> {
        let range = self
            .block_albedo
            .split_once(',')
            .and_then(|(a, b)| Some([a.trim().parse::<f64>().ok()?, b.trim().parse::<f64>().ok()?]))
            .with_context(|| {
                format!(
                    "--block-albedo: expected LO,HI such as 0.8,1.0, got {:?}",
                    self.block_albedo
                )
            })?;
        Ok(PhotoOptions {
            light_jitter_deg: self.light_jitter,
            block_albedo_range: range,
            sensor: SensorModel {
                blur_sigma_px: self.sensor_blur,
                full_well_e: self.sensor_full_well,
                read_noise_e: self.sensor_read_noise,
                gamma: self.sensor_gamma,
                vignetting: self.sensor_vignetting,
            },
        })
    }
}

/// Parses a `--backend` value: `vulkan` (or `vk`) and `gl` (or `gles`), any case.
pub fn parse_backend(name: &str) -> anyhow::Result<Backend> {
    match name.to_ascii_lowercase().as_str() {
        "vulkan" | "vk" => Ok(Backend::Vulkan),
        "gl" | "gles" => Ok(Backend::Gl),
        other => bail!("--backend: unknown backend {other:?}; use vulkan or gl"),
    }
}
