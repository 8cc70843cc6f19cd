//! A material-stack terrain to mesh or draw (Löffler et al. 2011): read from relief's
//! `.stacks` file, made from an MLHM scene (bedrock, sand, water) or from a height file
//! (bedrock), with the mesher's parameters.

use crate::error::RenderError;
use crate::input;
use crate::options::{refuse_shading_normals, SceneOptions};
use relief_core::{Aabb, Camera, DVec3, MaterialStacks, StacksMipmap};
use relief_mesh::{Smoothing, StacksMeshParams, StacksMesher};
use std::path::Path;

/// A stacks terrain opened to mesh or draw.
pub struct StacksScene {
    /// The mesher over the terrain's mipmap.
    pub mesher: StacksMesher,
    /// A finite box holding the terrain.
    pub bounds: Aabb,
    /// What opening it found that the user should know.
    pub warnings: Vec<String>,
}

impl StacksScene {
    /// Reads the input at `path` (`None`: the default fBm terrain) as stacks and builds its
    /// mipmap; the options' sigma is the Gaussian smoothing's standard deviation in metres
    /// (default: one cell).
    pub fn open(path: Option<&Path>, options: &SceneOptions) -> Result<Self, RenderError> {
        options.light.colours.refuse_for("material stacks")?;
        refuse_shading_normals(&options.light, "material stacks")?;
        let mut warnings = Vec::new();
        let stacks = read(path, options, &mut warnings)?;
        let spacing = stacks.spacing().x;
        let smoothing = match options.sigma {
            Some(sigma) => Smoothing::Gaussian { sigma: sigma / spacing },
            None => Smoothing::Gaussian { sigma: 1.0 },
        };
        let bounds = stacks_bounds(&stacks);
        let params = StacksMeshParams {
            smoothing,
            voxel_height: options.mesh.voxel_height,
            ..Default::default()
        };
        let mesher = StacksMesher::new(StacksMipmap::new(stacks)?, params)?;
        Ok(StacksScene { mesher, bounds, warnings })
    }

    /// The scene in a few words.
    pub fn describe(&self) -> String {
        let level0 = &self.mesher.mipmap().levels()[0];
        format!("{}x{} stacks terrain", level0.width(), level0.height())
    }

    /// The warning for a `camera` whose eye is inside the terrain, if it is.
    pub fn camera_warning(&self, camera: &Camera) -> Option<String> {
        crate::warnings::eye_in_stacks(&self.mesher.mipmap().levels()[0], camera)
    }
}

/// The stacks of the input: a `.stacks` file, an MLHM scene, or a height file (or the
/// default fBm terrain) as bedrock; a height file's warnings go to `warnings`.
fn read(
    path: Option<&Path>,
    options: &SceneOptions,
    warnings: &mut Vec<String>,
) -> Result<MaterialStacks, RenderError> {
    match path {
        Some(path) if input::is_stacks_file(path) => Ok(relief_io::read_stacks(path)?),
        Some(path) if input::is_mlhm_scene(path) => {
            let scene = input::load_mlhm(path, &options.terrain.read)?;
            MaterialStacks::from_mlhm(&scene.mlhm)
                .map_err(|source| RenderError::Stacks { path: path.to_path_buf(), source })
        }
        _ => {
            let loaded = input::load(path, &options.terrain)?;
            warnings.extend(loaded.warning);
            Ok(MaterialStacks::from_height_field(&loaded.field)?)
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
