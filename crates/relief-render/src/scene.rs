//! A scene: any input relief takes, opened with its tracer or renderer and its shading, drawn
//! from a camera.

use crate::antialias::{self, Antialiasing};
use crate::camera::{place_camera, CameraOptions, PlacedCamera};
use crate::draw::mesh::StacksDrawing;
use crate::draw::picture::Picture;
use crate::draw::{clipmap, hybrid, mlhm, store, strips};
use crate::error::RenderError;
use crate::input::InputKind;
use crate::options::{RenderMode, SceneOptions};
use crate::progress::Progress;
use crate::scenes::height_field::HeightFieldScene;
use crate::scenes::mlhm::LayeredScene;
use crate::scenes::stacks::StacksScene;
use crate::scenes::store::StoreScene;
use crate::tracer_spec::TracerChoice;
use relief_core::{Aabb, Camera};
use relief_shade::{HeightColourMap, KeptHits, PixelMask};
use std::path::Path;

/// Any input, opened to draw.
pub enum Scene {
    /// A height field (a height file, or the default fBm terrain), drawn by a ray caster, the
    /// hybrid renderer or geometry clipmaps.
    HeightField(HeightFieldScene),
    /// A multi-layered height map, drawn as boxes or its smooth surface.
    Mlhm(LayeredScene),
    /// A material-stack terrain (a .stacks file, or any input in mesh mode), meshed and
    /// rasterized.
    Stacks(Box<StacksDrawing>),
    /// A tile store, its tiles streamed for each picture.
    Store(StoreScene),
}

impl Scene {
    /// Opens the input at `path` (`None`: the default fBm terrain) as `options` say: a tile
    /// store, a material-stacks file (or any input in mesh mode), an MLHM scene, or a height
    /// file.
    pub fn open(path: Option<&Path>, options: &SceneOptions) -> Result<Scene, RenderError> {
        let kind = InputKind::of(path);
        if let (InputKind::TileStore, Some(path)) = (kind, path) {
            return Ok(Scene::Store(StoreScene::open(path, options)?));
        }
        if is_meshed(kind, options) {
            let stacks = StacksScene::open(path, options)?;
            let drawing = StacksDrawing::new(stacks, options.mesh.tau_px, &options.light)?
                .with_node_budget(options.mesh.node_budget);
            return Ok(Scene::Stacks(Box::new(drawing)));
        }
        if let (InputKind::Mlhm, Some(path)) = (kind, path) {
            return Ok(Scene::Mlhm(LayeredScene::open(path, options)?));
        }
        Ok(Scene::HeightField(HeightFieldScene::open(path, options)?))
    }

    /// The colour map over heights in metres that colours the scene, for a legend: `None`
    /// for MLHM scenes and stacks (coloured by their materials) and where a texture or a
    /// store's photo colours the terrain.
    pub fn height_colours(&self) -> Option<HeightColourMap> {
        match self {
            Scene::HeightField(scene) => scene.colours,
            Scene::Store(scene) => scene.colours,
            Scene::Mlhm(_) | Scene::Stacks(_) => None,
        }
    }

    /// The box the drawn surfaces fill.
    pub fn bounds(&self) -> Aabb {
        match self {
            Scene::HeightField(scene) => scene.bounds(),
            Scene::Mlhm(scene) => scene.bounds,
            Scene::Stacks(scene) => scene.bounds,
            Scene::Store(scene) => scene.bounds,
        }
    }

    /// The scene in a few words: "1024x1024 height field", ...
    pub fn describe(&self) -> String {
        match self {
            Scene::HeightField(scene) => scene.describe(),
            Scene::Mlhm(scene) => scene.describe(),
            Scene::Stacks(scene) => scene.describe(),
            Scene::Store(scene) => scene.describe(),
        }
    }

    /// What opening the scene found that the user should know (a DEM read at the wrong
    /// spacing, ...), each a line.
    pub fn warnings(&self) -> &[String] {
        match self {
            Scene::HeightField(scene) => &scene.warnings,
            Scene::Stacks(scene) => scene.warnings(),
            Scene::Mlhm(_) | Scene::Store(_) => &[],
        }
    }

    /// The camera `options` place for this scene, with a note where it changed what was
    /// asked for.
    pub fn camera(&self, options: &CameraOptions) -> Result<PlacedCamera, RenderError> {
        place_camera(options, &self.bounds())
    }

    /// The default camera of a `width x height` picture: the scene framed from the
    /// south-west, 30 degrees up.
    pub fn default_camera(&self, width: u32, height: u32) -> Result<Camera, RenderError> {
        Ok(self.camera(&CameraOptions::framing(width, height))?.camera)
    }

    /// The warning for a `camera` whose eye is inside the terrain (its picture is black), if
    /// it is.
    pub fn camera_warning(&self, camera: &Camera) -> Option<String> {
        match self {
            Scene::HeightField(scene) => scene.camera_warning(camera),
            Scene::Mlhm(scene) => scene.camera_warning(camera),
            Scene::Stacks(scene) => scene.camera_warning(camera),
            Scene::Store(_) => None,
        }
    }

    /// The picture of `camera`, anti-aliased as `aa` says, keeping the depth and normals
    /// `keep` asks for (those of the rays through the pixels' centres); long work is
    /// reported to `progress`.
    pub fn render(
        &self,
        camera: &Camera,
        keep: KeptHits,
        aa: Antialiasing,
        progress: &dyn Progress,
    ) -> Result<Picture, RenderError> {
        // The renderers that rasterize (and the tile store's) draw every pixel of every pass.
        type WholePass<'a> = &'a dyn Fn(&Camera, KeptHits, &dyn Progress) -> PictureResult;
        let whole = |draw: WholePass| {
            let mut pass =
                |camera: &Camera, keep, _: Option<&PixelMask>, progress: &dyn Progress| {
                    draw(camera, keep, progress)
                };
            antialias::draw(camera, keep, aa, progress, &mut pass)
        };
        match self {
            Scene::HeightField(scene) => match scene.choice {
                TracerChoice::Hybrid => whole(&|camera, keep, _| hybrid::draw(scene, camera, keep)),
                TracerChoice::Clipmap => {
                    whole(&|camera, keep, _| clipmap::draw(scene, camera, keep))
                }
                _ => strips::draw(scene, camera, keep, aa, progress),
            },
            Scene::Mlhm(scene) => mlhm::draw(scene, camera, keep, aa, progress),
            Scene::Stacks(scene) => whole(&|camera, keep, progress| {
                progress.begin("meshing", None);
                let picture = scene.draw(camera, keep);
                progress.end();
                picture
            }),
            Scene::Store(scene) => {
                whole(&|camera, keep, progress| store::draw(scene, camera, keep, progress))
            }
        }
    }
}

/// A picture, or why it could not be drawn.
type PictureResult = Result<Picture, RenderError>;

/// Whether an input of `kind` opened with `options` is drawn as a stacks mesh: a .stacks
/// file, or any input but a tile store in mesh mode.
fn is_meshed(kind: InputKind, options: &SceneOptions) -> bool {
    match kind {
        InputKind::Stacks => true,
        InputKind::TileStore => false,
        _ => options.mode == Some(RenderMode::Mesh),
    }
}
