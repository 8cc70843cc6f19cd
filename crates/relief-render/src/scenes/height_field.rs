//! A height field to draw: the terrain as the options place it, the surface and tracer they
//! name, and the shading fitted to the terrain.

use crate::error::RenderError;
use crate::input;
use crate::memory;
use crate::options::{HybridSettings, LightSettings, SceneOptions};
use crate::tracer_spec::{SafetySettings, TracerChoice, TracerSpec};
use relief_core::{Aabb, Camera, HeightField, Surface};
use relief_shade::{
    sun_direction, Albedo, HeightColourMap, NormalStyle, RgbTexture, ShadingNormals, ShadingParams,
    Sun,
};
use relief_trace::safety::SafetyTracer;
use relief_trace::{Simd, TracerKind};
use std::path::Path;
use std::sync::Arc;

/// A height field opened as a scene.
pub struct HeightFieldScene {
    /// The terrain, placed in the world.
    pub field: Arc<HeightField>,
    /// The surface to draw (default: triangles).
    pub surface: Surface,
    /// The tracer or renderer (default: mipmap).
    pub choice: TracerChoice,
    /// The safety tracer's options.
    pub safety: SafetySettings,
    /// The hybrid renderer's options.
    pub hybrid: HybridSettings,
    /// Bytes the safety shapes may take.
    pub max_memory: u64,
    /// Lights and materials, fitted to the terrain, with the normals of [`Self::surface`]
    /// ([`HeightFieldScene::normals`]).
    pub params: ShadingParams,
    /// The shading normals asked for (`None`: the surface's default).
    pub normal_style: Option<NormalStyle>,
    /// The colour map over heights in metres, for a legend; `None` where a texture colours
    /// the terrain.
    pub colours: Option<HeightColourMap>,
    /// What opening it found that the user should know (a DEM read at the wrong spacing).
    pub warnings: Vec<String>,
}

impl HeightFieldScene {
    /// Reads the height file at `path` (or generates the default fBm terrain) as `options`
    /// say.
    pub fn open(path: Option<&Path>, options: &SceneOptions) -> Result<Self, RenderError> {
        let surface = options.surface.unwrap_or(Surface::Triangles);
        let choice = options.tracer.clone().unwrap_or(TracerChoice::Plain(TracerKind::Mipmap));
        let loaded = input::load(path, &options.terrain)?;
        let field = Arc::new(loaded.field);
        let bounds = field.world_bounds(Surface::Boxes);
        let z_scale = options.terrain.z_scale;
        let mut params = shading(&options.light, &bounds, z_scale)?;
        let normal_style = options.light.shading_normals;
        params.normals = shading_normals(normal_style, surface, &field)?;
        let colours = legend_colours(&options.light, &bounds, z_scale)?;
        Ok(HeightFieldScene {
            field,
            surface,
            choice,
            safety: options.safety.clone(),
            hybrid: options.hybrid.clone(),
            max_memory: memory::budget(options.terrain.read.max_memory).bytes,
            params,
            normal_style,
            colours,
            warnings: loaded.warning.into_iter().collect(),
        })
    }

    /// The normals that light `surface` of the scene's field (the viewer switches surfaces):
    /// as [`shading_normals`] gives them for the style asked, except that `boxes` are
    /// faceted whatever was asked.
    pub fn normals(&self, surface: Surface) -> ShadingNormals {
        let style = if surface == Surface::Boxes { None } else { self.normal_style };
        shading_normals(style, surface, &self.field).unwrap_or_default()
    }

    /// The box the drawn surface fills.
    pub fn bounds(&self) -> Aabb {
        self.field.world_bounds(self.surface)
    }

    /// The scene in a few words.
    pub fn describe(&self) -> String {
        format!("{}x{} height field", self.field.width(), self.field.height())
    }

    /// The warning for a `camera` whose eye is inside the terrain, if it is.
    pub fn camera_warning(&self, camera: &Camera) -> Option<String> {
        crate::warnings::eye_in_height_field(&self.field, self.surface, camera)
    }

    /// The tracer `choice` for `surface`, with the scene's safety options and memory limit,
    /// the shape cache and the machine's SIMD.
    pub fn tracer_spec(&self, choice: &TracerChoice, surface: Surface) -> TracerSpec {
        TracerSpec {
            choice: choice.clone(),
            surface,
            safety: self.safety.clone(),
            use_cache: true,
            max_memory: self.max_memory,
            simd: Simd::detect(),
        }
    }
}

/// Refuses a view of `camera` that the safety shapes of `safety` were not built for (with
/// shadow rays towards the sun of `params` when it casts shadows).
pub fn check_safety_view(
    safety: &SafetyTracer,
    camera: &Camera,
    params: &ShadingParams,
) -> Result<(), RenderError> {
    let light =
        params.shadows.then(|| sun_direction(params.sun.azimuth_deg, params.sun.elevation_deg));
    let (w, h) = (camera.width(), camera.height());
    // Every ray with its own origin: an orthographic camera's do not start at its eye.
    let rays = (0..h).flat_map(|j| (0..w).map(move |i| camera.ray(i, j)));
    safety.check_rays(rays, light)?;
    Ok(())
}

/// The normals that light `surface` of `field` in the `style` asked: smooth (from the field's
/// gradients, [`relief_core::HeightField::smooth_normal_at`]) or faceted; by default smooth
/// for `triangles` and faceted for `boxes`, whose flat tops have no smooth normals to give.
///
/// Fails when smooth normals are asked for the `boxes` surface.
pub fn shading_normals(
    style: Option<NormalStyle>,
    surface: Surface,
    field: &Arc<HeightField>,
) -> Result<ShadingNormals, RenderError> {
    match (style, surface) {
        (Some(NormalStyle::Smooth), Surface::Boxes) => Err(RenderError::Unsupported(
            "smooth shading normals are for the triangles surface: boxes are always faceted".into(),
        )),
        (Some(NormalStyle::Faceted), _) | (None, Surface::Boxes) => Ok(ShadingNormals::Faceted),
        (_, Surface::Triangles) => Ok(ShadingNormals::smooth(field.clone())),
    }
}

/// Lights and materials as `light` says, fitted to a terrain within `bounds`, whose world
/// heights are `z_scale` times its metres (`--z-scale`).
pub fn shading(
    light: &LightSettings,
    bounds: &Aabb,
    z_scale: f64,
) -> Result<ShadingParams, RenderError> {
    let mut params = ShadingParams::for_terrain(bounds)?;
    if light.colours.given() {
        if light.texture.is_some() {
            return Err(RenderError::Colours(
                "a colour map and a texture both colour the terrain: give one".into(),
            ));
        }
        params.albedo = light.colours.albedo(bounds, z_scale)?;
    }
    let (azimuth_deg, elevation_deg) = light.sun;
    params.sun = Sun { azimuth_deg, elevation_deg, ..params.sun };
    params.shadows = !light.no_shadows;
    params.exposure = light.exposure;
    if let Some(path) = &light.texture {
        let image = relief_io::read_png_rgb(path)?;
        let rgb: Vec<u8> = image.pixels.iter().flatten().copied().collect();
        let texture = RgbTexture::from_srgb8(image.width as usize, image.height as usize, &rgb)
            .map_err(|source| RenderError::Texture { path: path.clone(), source })?;
        params.albedo = Albedo::Texture(texture);
    }
    params.validate()?;
    Ok(params)
}

/// The colour map over heights in metres that `light` lays over a terrain within `bounds`
/// (world heights `z_scale` times the metres), for a legend; `None` where a texture colours
/// it.
pub fn legend_colours(
    light: &LightSettings,
    bounds: &Aabb,
    z_scale: f64,
) -> Result<Option<HeightColourMap>, RenderError> {
    match &light.texture {
        Some(_) => Ok(None),
        None => light.colours.in_metres(bounds, z_scale).map(Some),
    }
}
