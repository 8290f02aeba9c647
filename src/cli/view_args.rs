//! Render options shared by every command that renders (`render`, `demo`, `generate`,
//! `bench ...`), flattened into their clap `Args`.

use anyhow::{bail, Context};
use blockworld::camera::{CameraOptions, CornerView, Projection};
use blockworld::geom::ISOMETRIC_ELEVATION_DEG;
use blockworld::render::{Backend, RenderOptions};

/// How views are rendered (README "Rendering").
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
}

impl ViewArgs {
    /// The corner views asked for.
    /// A view named twice is an error (it would be rendered and written twice); an empty list
    /// is allowed here (`generate --views ""` writes scene.json only), see
    /// [`ViewArgs::some_corner_views`].
    pub fn corner_views(&self) -> anyhow::Result<Vec<CornerView>> {
        let mut views: Vec<CornerView> = Vec::new();
        for v in self.views.iter().filter(|v| !v.trim().is_empty()) {
            let view = CornerView::parse(v)
                .with_context(|| format!("--views: unknown view {v:?}; use ne, se, sw, nw"))?;
            if views.contains(&view) {
                bail!(
                    "--views: {} is given twice; name each view once",
                    view.name()
                );
            }
            views.push(view);
        }
        Ok(views)
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
        };
        opts.validate()
            .context("--elevation, --fov, --pixel-aspect, --msaa, --noise or --size")?;
        Ok(opts)
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
