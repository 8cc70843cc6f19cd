//! A material-stack terrain to mesh or draw (Löffler et al. 2011): read from relief's
//! `.stacks` file, made from an MLHM scene (bedrock, sand, water) or from a height file
//! (bedrock), with the mesher's parameters and the starting camera.

use crate::args::SceneArgs;
use crate::{applies, input};
use anyhow::{Context, Result};
use relief_core::{Aabb, Camera, DVec3, MaterialStacks, Ray, StacksMipmap, Surface};
use relief_mesh::{Smoothing, StacksMeshParams, StacksMesher};
use relief_shade::{shade_to_srgb8, Albedo, GBuffer, ShadingParams, Sun};
use relief_trace::{Hit, Tracer};
use std::path::Path;

/// Whether `path` names relief's stacks file, by the extension `.stacks`.
pub fn is_stacks_file(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("stacks"))
}

/// A stacks terrain opened from the command line.
pub struct StacksScene {
    /// The mesher over the terrain's mipmap.
    pub mesher: StacksMesher,
    /// A finite box holding the terrain.
    pub bounds: Aabb,
    /// The camera of the command line, or the framing three-quarter view.
    pub camera: Camera,
}

impl StacksScene {
    /// Reads the input of `args` as stacks and builds its mipmap; `--sigma` is the Gaussian
    /// smoothing's standard deviation in metres (default: one cell).
    /// `here` names the command, for refusals of options that do not apply to it.
    pub fn open(args: &SceneArgs, here: &str) -> Result<Self> {
        refuse_other_options(args, here)?;
        let stacks = read(args)?;
        let spacing = stacks.spacing().x;
        let smoothing = match args.sigma {
            Some(sigma) => Smoothing::Gaussian { sigma: sigma / spacing },
            None => Smoothing::Gaussian { sigma: 1.0 },
        };
        let bounds = stacks_bounds(&stacks);
        let params =
            StacksMeshParams { smoothing, voxel_height: args.voxel_height, ..Default::default() };
        let camera = super::camera(args, &bounds)?;
        if let Some(warning) = crate::warnings::eye_in_stacks(&stacks, &camera) {
            eprintln!("{warning}");
        }
        let mesher = StacksMesher::new(StacksMipmap::new(stacks), params)?;
        Ok(StacksScene { mesher, bounds, camera })
    }
}

/// The stacks of the input: a `.stacks` file, an MLHM scene, or a height file (or the
/// default fBm terrain) as bedrock.
fn read(args: &SceneArgs) -> Result<MaterialStacks> {
    let path = args.input.input.as_deref();
    match path {
        Some(path) if is_stacks_file(path) => {
            applies::check_read_args(&args.input.read, Some(path))?;
            Ok(relief_io::read_stacks(path)?)
        }
        Some(path) if input::is_mlhm_scene(path) => {
            let scene = input::load_mlhm(path, &args.input.read)?;
            MaterialStacks::from_mlhm(&scene.mlhm)
                .with_context(|| format!("stacks of {}", path.display()))
        }
        _ => {
            let field = input::load(&args.input)?;
            Ok(MaterialStacks::from_height_field(&field)?)
        }
    }
}

/// The box of the stacks' footprint and heights.
fn stacks_bounds(stacks: &MaterialStacks) -> Aabb {
    let (low, high) = stacks.height_range().unwrap_or((0.0, 1.0));
    let o = stacks.origin();
    let s = stacks.spacing();
    Aabb::new(
        DVec3::new(o.x, o.y, low as f64),
        DVec3::new(
            o.x + s.x * stacks.width() as f64,
            o.y + s.y * stacks.height() as f64,
            (high as f64).max(low as f64 + 1e-3),
        ),
    )
}

/// Refuses the options of tracers and MLHM rendering that do nothing for a stacks mesh.
fn refuse_other_options(args: &SceneArgs, here: &str) -> Result<()> {
    for (given, option) in [
        (args.tracer.is_some(), "--tracer"),
        (args.surface.is_some(), "--surface"),
        (args.preset.is_some(), "--preset"),
        (args.hierarchy_bounds.is_some(), "--hierarchy-bounds"),
        (args.backtrack.is_some(), "--backtrack"),
        (args.texture.is_some(), "--texture"),
        (args.no_ao, "--no-ao"),
        (applies::safety_option_given(&args.safety).is_some(), "the safety options"),
    ] {
        if given {
            return Err(applies::refuse(option, "the ray-cast renderers", here));
        }
    }
    Ok(())
}

/// Shades a stacks mesh's G-buffer with the deferred pass: the vertex colours as albedo, the
/// sun at `sun` (azimuth, elevation in degrees), `exposure`; no shadow rays (a mesh has no
/// exact tracer for them).
pub fn shade(
    gbuffer: &GBuffer,
    camera: &Camera,
    bounds: &Aabb,
    sun: (f64, f64),
    exposure: f64,
) -> Result<Vec<[u8; 3]>> {
    let mut params = ShadingParams::for_terrain(bounds)?;
    params.sun = Sun { azimuth_deg: sun.0, elevation_deg: sun.1, ..params.sun };
    params.exposure = exposure;
    params.albedo = Albedo::GBufferColour { fallback: [0.3; 3] };
    params.shadows = false;
    Ok(shade_to_srgb8(gbuffer, &NoOccluders, camera, &params)?.0)
}

/// The shadow "tracer" of a mesh drawn without shadows: it meets nothing.
struct NoOccluders;

impl Tracer for NoOccluders {
    fn name(&self) -> &'static str {
        "none"
    }

    fn surface(&self) -> Surface {
        Surface::Triangles
    }

    /// An empty box (min above max): there is no solid.
    fn bounds(&self) -> Aabb {
        Aabb::new(DVec3::INFINITY, DVec3::NEG_INFINITY)
    }

    fn intersect_counted(&self, _ray: &Ray, _steps: &mut u32) -> Option<Hit> {
        None
    }
}
