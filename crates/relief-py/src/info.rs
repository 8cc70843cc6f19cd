//! `Scene.info`: what an opened scene is, as a dict: its kind, size, spacing, bounds, CRS
//! where the input names one, and what each kind adds (an MLHM scene's layers and step).

use pyo3::prelude::*;
use pyo3::types::PyDict;
use relief_core::Aabb;
use relief_io::{ReadOptions, RowSource};
use relief_render::Scene;
use std::path::Path;

/// The CRS a height file names.
#[derive(Debug, Clone, PartialEq)]
pub struct Crs {
    /// `"EPSG:<code>"`, or the CRS's name.
    pub name: String,
    /// The EPSG code, if it has one.
    pub epsg: Option<u16>,
}

/// The CRS of the height file at `path` read with `options`, if it names one (read from its
/// header where the format streams, else from the whole file).
pub fn height_file_crs(path: &Path, options: &ReadOptions) -> Option<Crs> {
    let rows: Box<dyn RowSource> = relief_io::open_rows(path, options).ok()?;
    let georeference = rows.info().georeference.as_ref().filter(|g| g.has_crs())?;
    Some(Crs { name: georeference.crs_name(), epsg: georeference.epsg() })
}

/// The name of a scene's kind: `height_field`, `mlhm`, `stacks` or `tile_store`.
pub fn kind(scene: &Scene) -> &'static str {
    match scene {
        Scene::HeightField(_) => "height_field",
        Scene::Mlhm(_) => "mlhm",
        Scene::Stacks(_) => "stacks",
        Scene::Store(_) => "tile_store",
    }
}

/// What `Scene.info` tells of a scene, before it becomes a dict.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneInfo {
    /// The kind's name.
    pub kind: &'static str,
    /// The scene in a few words.
    pub description: String,
    /// The input's path, `None` for the default fBm terrain.
    pub path: Option<String>,
    /// Samples (cells) along x and y, where the scene tells them.
    pub size: Option<(u64, u64)>,
    /// Distance between samples along x and y, world units, where the scene tells it.
    pub spacing: Option<(f64, f64)>,
    /// The box the drawn surfaces fill.
    pub bounds: Aabb,
    /// The CRS the input names.
    pub crs: Option<Crs>,
    /// What opening it found that the user should know.
    pub warnings: Vec<String>,
    /// A height field's surface and tracer, by name.
    pub drawn_with: Option<(String, String)>,
    /// An MLHM scene's layer planes and the steps simulated so far.
    pub layers_and_step: Option<(usize, u64)>,
}

impl SceneInfo {
    /// What `scene` is; `path`, `crs` and `layers_and_step` as the caller knows them.
    pub fn of(
        scene: &Scene,
        path: Option<&Path>,
        crs: Option<Crs>,
        layers_and_step: Option<(usize, u64)>,
    ) -> SceneInfo {
        let (size, spacing, drawn_with) = match scene {
            Scene::HeightField(s) => {
                let (f, g) = (&s.field, s.field.geometry());
                let drawn = (s.surface.to_string(), s.choice.to_string());
                (Some((f.width() as u64, f.height() as u64)), Some((g.dx, g.dy)), Some(drawn))
            }
            Scene::Mlhm(s) => {
                let cell = s.map.cell_size();
                (Some((s.map.width() as u64, s.map.height() as u64)), Some((cell, cell)), None)
            }
            // The drawing keeps its mesher to itself: its size is in its description.
            Scene::Stacks(_) => (None, None, None),
            Scene::Store(s) => {
                let (header, g) = (s.streamer.store().header(), s.streamer.store().geometry());
                (Some((header.width, header.height)), Some((g.dx, g.dy)), None)
            }
        };
        SceneInfo {
            kind: kind(scene),
            description: scene.describe(),
            path: path.map(|p| p.display().to_string()),
            size,
            spacing,
            bounds: scene.bounds(),
            crs,
            warnings: scene.warnings().to_vec(),
            drawn_with,
            layers_and_step,
        }
    }

    /// The dict: `kind`, `description`, `path`, `size` (x, y) and `spacing` (dx, dy) (`None` for a stacks terrain), `bounds`
    /// ((x, y, z) lowest, (x, y, z) highest), `crs` and `epsg` (`None` where unknown),
    /// `warnings`; a height field's `surface` and `tracer`; an MLHM scene's `layers` and
    /// `step`.
    pub fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let dict = PyDict::new(py);
        dict.set_item("kind", self.kind)?;
        dict.set_item("description", &self.description)?;
        dict.set_item("path", &self.path)?;
        dict.set_item("size", self.size)?;
        dict.set_item("spacing", self.spacing)?;
        let (min, max) = (self.bounds.min, self.bounds.max);
        dict.set_item("bounds", ((min.x, min.y, min.z), (max.x, max.y, max.z)))?;
        dict.set_item("crs", self.crs.as_ref().map(|c| c.name.clone()))?;
        dict.set_item("epsg", self.crs.as_ref().and_then(|c| c.epsg))?;
        dict.set_item("warnings", &self.warnings)?;
        if let Some((surface, tracer)) = &self.drawn_with {
            dict.set_item("surface", surface)?;
            dict.set_item("tracer", tracer)?;
        }
        if let Some((layers, step)) = self.layers_and_step {
            dict.set_item("layers", layers)?;
            dict.set_item("step", step)?;
        }
        Ok(dict)
    }
}
