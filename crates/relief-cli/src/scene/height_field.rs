//! A height field to draw: the terrain as the command line places it, the surface and tracer
//! it names, the shading fitted to the terrain and the starting camera.

use crate::args::SceneArgs;
use crate::tracers::TracerChoice;
use crate::{applies, input};
use anyhow::{Context, Result};
use relief_core::{Aabb, Camera, HeightField, Surface};
use relief_shade::{sun_direction, Albedo, RgbTexture, ShadingParams, Sun};
use relief_trace::safety::SafetyTracer;
use relief_trace::TracerKind;
use std::sync::Arc;

/// A height field opened from the command line.
pub struct HeightFieldScene {
    /// The terrain, placed in the world.
    pub field: Arc<HeightField>,
    /// The surface to draw (default: triangles).
    pub surface: Surface,
    /// The tracer (default: mipmap).
    pub choice: TracerChoice,
    /// Lights and materials, fitted to the terrain.
    pub params: ShadingParams,
    /// The camera of `--eye`/`--target`, or the framing three-quarter view.
    pub camera: Camera,
}

impl HeightFieldScene {
    /// Reads (or generates) the height field `args` name, refusing the options that do not
    /// apply to it.
    pub fn open(args: &SceneArgs) -> Result<Self> {
        refuse_mlhm_options(args)?;
        let surface = args.surface.unwrap_or(Surface::Triangles);
        let choice = args.tracer.clone().unwrap_or(TracerChoice::Plain(TracerKind::Mipmap));
        if !matches!(choice, TracerChoice::Safety(_)) {
            if let Some(option) = applies::safety_option_given(&args.safety) {
                return Err(applies::refuse(
                    option,
                    "the safety tracer",
                    &format!("the {choice} tracer"),
                ));
            }
        }
        let field = input::load(&args.input)?;
        let camera = super::camera(args, &field.world_bounds(surface))?;
        if let Some(warning) = crate::warnings::eye_in_height_field(&field, surface, &camera) {
            eprintln!("{warning}");
        }
        let params = shading(args, &field.world_bounds(Surface::Boxes))?;
        Ok(HeightFieldScene { field, surface, choice, params, camera })
    }

    /// The box the drawn surface fills.
    pub fn bounds(&self) -> Aabb {
        self.field.world_bounds(self.surface)
    }
}

/// Refuses a view of `camera` that the safety shapes of `safety` were not built for (with
/// shadow rays towards the sun of `params` when it casts shadows).
pub fn check_safety_view(
    safety: &SafetyTracer,
    camera: &Camera,
    params: &ShadingParams,
) -> Result<()> {
    let light =
        params.shadows.then(|| sun_direction(params.sun.azimuth_deg, params.sun.elevation_deg));
    let (w, h) = (camera.width(), camera.height());
    // Every ray with its own origin: an orthographic camera's do not start at its eye.
    let rays = (0..h).flat_map(|j| (0..w).map(move |i| camera.ray(i, j)));
    safety.check_rays(rays, light)?;
    Ok(())
}

/// Lights and materials from the command line, fitted to a terrain within `bounds`.
pub fn shading(args: &SceneArgs, bounds: &Aabb) -> Result<ShadingParams> {
    let mut params = ShadingParams::for_terrain(bounds)?;
    let (azimuth_deg, elevation_deg) = args.sun;
    params.sun = Sun { azimuth_deg, elevation_deg, ..params.sun };
    params.shadows = !args.no_shadows;
    params.exposure = args.exposure;
    if let Some(path) = &args.texture {
        let image = relief_io::read_png_rgb(path)?;
        let rgb: Vec<u8> = image.pixels.iter().flatten().copied().collect();
        let texture = RgbTexture::from_srgb8(image.width as usize, image.height as usize, &rgb)
            .with_context(|| format!("texture {}", path.display()))?;
        params.albedo = Albedo::Texture(texture);
    }
    params.validate()?;
    Ok(params)
}

/// Refuses the options only an MLHM scene takes, for a height field.
fn refuse_mlhm_options(args: &SceneArgs) -> Result<()> {
    let what = if args.tracer == Some(TracerChoice::Hierarchy) {
        "--tracer hierarchy"
    } else if args.mode.is_some() {
        "--mode"
    } else if args.backtrack.is_some() {
        "--backtrack"
    } else if args.preset.is_some() {
        "--preset"
    } else if args.hierarchy_bounds.is_some() {
        "--hierarchy-bounds"
    } else if args.sigma.is_some() {
        "--sigma"
    } else if args.no_ao {
        "--no-ao"
    } else {
        return Ok(());
    };
    let here = applies::input_kind(args.input.input.as_deref());
    Err(applies::refuse(what, "MLHM scenes (.json, .mlhm)", &here))
}
