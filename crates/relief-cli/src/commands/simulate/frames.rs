//! `relief simulate --render-every K --frames DIR`: every K steps, the state converted to an
//! MLHM, the hierarchy rebuilt in the storage of the previous frame's, and a frame rendered
//! with the MLHM renderer at a preset from a camera fixed over the run, each stage timed.

use super::args::SimulateArgs;
use crate::{applies, outputs};
use anyhow::{bail, Context, Result};
use relief_core::{Camera, DVec2, Mlhm};
use relief_render::draw::mlhm::mlhm_frame;
use relief_render::scenes::mlhm::{mlhm_base, mlhm_bounds};
use relief_render::{place_camera, CameraOptions};
use relief_shade::mlhm::{MlhmPreset, MlhmShading};
use relief_shade::Sun;
use relief_sim::erosion::ErosionState;
use relief_trace::{MlhmHierarchy, MlhmHierarchyTracer};
use serde_json::{json, Value};
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

/// The scene has no georeference: cell (x, y) covers [x s, (x + 1) s) x [y s, (y + 1) s).
const ORIGIN: DVec2 = DVec2::ZERO;

/// The frame size without `--size`, as `relief render`'s.
const DEFAULT_SIZE: (u32, u32) = (1280, 720);

/// Refuses the frame options given without the others they need, and a frame folder that
/// cannot be created; creates it.
pub fn check(args: &SimulateArgs) -> Result<()> {
    match (&args.render_every, &args.frames) {
        (Some(_), None) => bail!("--render-every needs --frames DIR, the folder the frames go to"),
        (None, Some(_)) => bail!("--frames needs --render-every K, the steps between frames"),
        (None, None) => {
            let given = [
                ("--preset", args.preset.is_some()),
                ("--size", args.size.is_some()),
                ("--view", args.view.is_some()),
            ];
            if let Some((option, _)) = given.iter().find(|(_, given)| *given) {
                return Err(applies::refuse(option, "--frames", "a run without frames"));
            }
            return Ok(());
        }
        (Some(_), Some(dir)) => {
            if dir.exists() && !dir.is_dir() {
                bail!("--frames {}: not a folder", dir.display());
            }
            std::fs::create_dir_all(dir)
                .with_context(|| format!("--frames {}: cannot create the folder", dir.display()))?;
        }
    }
    Ok(())
}

/// Where the run's frames go and how they are drawn.
pub struct Frames {
    every: u64,
    dir: PathBuf,
    shading: MlhmShading,
    preset: MlhmPreset,
    camera: Camera,
    /// The map's layer planes: the initial map's, grown as columns split.
    layers: usize,
    /// Where the solid ends below ([`mlhm_base`] of the initial map), in every frame.
    base: f32,
    hierarchy: Option<MlhmHierarchy>,
    /// Milliseconds of the steps since the last frame.
    pending_steps_ms: f64,
    pending_steps: u64,
    times: Vec<FrameTimes>,
    /// Digits of the frame numbers: 5, more when the run's frames need them.
    digits: usize,
}

/// One frame's stages, milliseconds.
struct FrameTimes {
    simulate: f64,
    convert: f64,
    rebuild: f64,
    render: f64,
    write: f64,
}

impl Frames {
    /// The frames `args` ask for (None without `--frames`), the camera framing `map` as
    /// `relief render` frames it.
    pub fn new(args: &SimulateArgs, map: &Arc<Mlhm>) -> Result<Option<Frames>> {
        let (Some(every), Some(dir)) = (args.render_every, &args.frames) else {
            return Ok(None);
        };
        let preset = args.preset.unwrap_or(MlhmPreset::Low);
        let mut shading = MlhmShading::new(preset);
        // `relief render`'s default sun.
        shading.sun = Sun { azimuth_deg: 315.0, elevation_deg: 35.0, ..shading.sun };
        shading.validate()?;
        let (w, h) = args.size.unwrap_or(DEFAULT_SIZE);
        let bounds = mlhm_bounds(map)?;
        let options = CameraOptions { view: args.view, ..CameraOptions::framing(w, h) };
        let camera = place_camera(&options, &bounds)?.camera;
        Ok(Some(Frames {
            every,
            dir: dir.clone(),
            shading,
            preset,
            camera,
            layers: map.max_layers(),
            base: mlhm_base(map),
            hierarchy: None,
            pending_steps_ms: 0.0,
            pending_steps: 0,
            times: Vec::new(),
            digits: (args.steps / every).saturating_sub(1).to_string().len().max(5),
        }))
    }

    /// Counts a step of `ms` milliseconds; renders a frame of `state` when it is the K-th.
    /// `log` prints the frame's line.
    pub fn after_step(&mut self, state: &ErosionState, ms: f64, log: &dyn Fn(&str)) -> Result<()> {
        self.pending_steps_ms += ms;
        self.pending_steps += 1;
        if self.pending_steps < self.every {
            return Ok(());
        }
        let started = Instant::now();
        self.layers = self.layers.max(state.used_layers());
        let mut map = state.to_mlhm_with_layers(self.layers)?;
        map.set_base(self.base);
        let map = Arc::new(map);
        let convert = ms_since(started);

        let started = Instant::now();
        match &mut self.hierarchy {
            Some(hierarchy) => hierarchy.rebuild(&map),
            None => self.hierarchy = Some(MlhmHierarchy::build(&map)),
        }
        let rebuild = ms_since(started);

        let started = Instant::now();
        // The tracer owns its hierarchy: it gets a copy, the rebuilt storage stays here.
        let hierarchy = self.hierarchy.clone().context("the hierarchy")?;
        let tracer = MlhmHierarchyTracer::with_hierarchy(map, hierarchy, ORIGIN);
        let frame_rgb = mlhm_frame(&tracer, &self.camera, &self.shading)?;
        let render = ms_since(started);

        let started = Instant::now();
        // Numbered from 0, as `relief flythrough` numbers its frames.
        let frame = self.times.len();
        let digits = self.digits;
        let path = self.dir.join(format!("frame-{frame:0digits$}.png"));
        let (w, h) = (self.camera.width(), self.camera.height());
        let rgb = frame_rgb.rgb.as_flattened();
        outputs::write_picture(&path, w, h, rgb, relief_io::PngCompression::Fast)
            .with_context(|| format!("writing {}", path.display()))?;
        let write = ms_since(started);

        log(&format!(
            "frame {frame} (step {}): simulate {:.1} ms ({} steps), convert {convert:.1} ms, \
             rebuild {rebuild:.1} ms, render {render:.1} ms, write {write:.1} ms: {}",
            state.step_count(),
            self.pending_steps_ms,
            self.pending_steps,
            path.display()
        ));
        self.times.push(FrameTimes {
            simulate: self.pending_steps_ms,
            convert,
            rebuild,
            render,
            write,
        });
        (self.pending_steps_ms, self.pending_steps) = (0.0, 0);
        Ok(())
    }

    /// One line about the frames written.
    pub fn summary(&self) -> String {
        let median = |f: fn(&FrameTimes) -> f64| median(self.times.iter().map(f).collect());
        format!(
            "{} frames ({}x{}, preset {}) in {}: median rebuild {:.1} ms, render {:.1} ms",
            self.times.len(),
            self.camera.width(),
            self.camera.height(),
            self.preset,
            self.dir.display(),
            median(|t| t.rebuild),
            median(|t| t.render)
        )
    }

    /// The `--stats` keys of the frames: medians over the frames and per-frame arrays.
    pub fn stats(&self) -> Vec<(&'static str, Value)> {
        let column = |f: fn(&FrameTimes) -> f64| self.times.iter().map(f).collect::<Vec<f64>>();
        let (simulate, convert, rebuild, render, write) = (
            column(|t| t.simulate),
            column(|t| t.convert),
            column(|t| t.rebuild),
            column(|t| t.render),
            column(|t| t.write),
        );
        vec![
            ("frames", json!(self.times.len())),
            ("render_every", json!(self.every)),
            ("frame_size", json!([self.camera.width(), self.camera.height()])),
            ("preset", json!(self.preset.name())),
            ("rebuild_ms", json!(median(rebuild.clone()))),
            ("render_ms", json!(median(render.clone()))),
            ("convert_ms", json!(median(convert.clone()))),
            ("write_ms", json!(median(write.clone()))),
            ("frame_simulate_ms_each", json!(simulate)),
            ("convert_ms_each", json!(convert)),
            ("rebuild_ms_each", json!(rebuild)),
            ("render_ms_each", json!(render)),
            ("write_ms_each", json!(write)),
        ]
    }
}

/// Milliseconds since `start`.
fn ms_since(start: Instant) -> f64 {
    start.elapsed().as_secs_f64() * 1e3
}

/// The median of `values` (0 for none).
pub fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values.get(values.len() / 2).copied().unwrap_or(0.0)
}
