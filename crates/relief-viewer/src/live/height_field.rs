//! A height field drawn live: the tracers (built when first asked for, then kept), the
//! deferred shading with the viewer's sun, exposure and shadows.

use super::drawing::Drawing;
use super::tracer_cache::TracerCache;
use super::view_shading::{apply_view_settings, position};
use crate::{Cancel, Frame, FrameStats, SceneChoices, ViewSettings};
use relief_core::{Camera, Surface};
use relief_render::scenes::height_field::check_safety_view;
use relief_render::tracer_spec::build_plain;
use relief_render::{HeightFieldScene, Progress, RenderError, TracerChoice};
use relief_shade::{render_to_srgb8, sun_shadow_sweep, KeptHits, ShadingParams};
use relief_trace::adapters::Interruptible;
use relief_trace::safety::SafetyTracer;
use relief_trace::{Simd, SunShadows, Tracer, TracerKind};
use std::collections::HashMap;
use std::sync::{Arc, Mutex};

/// How many frames a kept shadow sweep is counted to serve when deciding whether it pays: the
/// viewer redraws while the camera moves and refines at rest, all under one sun.
const FRAMES_UNDER_ONE_SUN: usize = 16;

/// The surfaces a height field offers, in the order the viewer cycles them.
const SURFACES: [Surface; 2] = [Surface::Triangles, Surface::Boxes];

/// A height field and the tracers drawing it.
pub struct LiveHeightField {
    scene: HeightFieldScene,
    /// The tracers offered, in the order the viewer cycles them.
    choices: Vec<TracerChoice>,
    /// The safety tracer, when one was asked for (built before the window opens).
    safety: Option<SafetyTracer>,
    /// The tracers built so far, by choice index and surface.
    built: TracerCache<(usize, Surface), dyn Tracer>,
    /// The scene's shading, the viewer's settings applied frame by frame.
    params: Mutex<ShadingParams>,
    /// The sun's shadow sweep of the last frame that had one, kept for the frames after it
    /// while its tracer, surface and sun stay.
    sweep: Mutex<Option<KeptSweep>>,
}

/// A shadow sweep and what it was built for: the tracer's choice index, the surface and the
/// direction towards the sun, bit for bit.
struct KeptSweep {
    built_for: (usize, Surface, [u64; 3]),
    sweep: Arc<SunShadows<Arc<dyn Tracer>>>,
}

impl LiveHeightField {
    /// Draws `scene`: the mipmap and naive tracers, and the safety tracer too when the scene
    /// names it (its shapes built, or read from the cache, now, reported to `progress`). Also
    /// returns where the shapes came from, if it built them.
    pub fn new(
        scene: HeightFieldScene,
        progress: &dyn Progress,
    ) -> Result<(Self, Option<String>), RenderError> {
        let mut choices =
            vec![TracerChoice::Plain(TracerKind::Mipmap), TracerChoice::Plain(TracerKind::Naive)];
        let mut built = HashMap::new();
        let (mut safety, mut note) = (None, None);
        if matches!(scene.choice, TracerChoice::Safety(_)) {
            let spec = scene.tracer_spec(&scene.choice, Surface::Triangles);
            let made = spec.build_reporting(&scene.field, progress)?;
            note = Some(made.note).filter(|n| !n.is_empty());
            choices.push(scene.choice.clone());
            built.insert((choices.len() - 1, Surface::Triangles), Arc::from(made.tracer));
            safety = made.safety;
        }
        let params = Mutex::new(scene.params.clone());
        let live = LiveHeightField {
            scene,
            choices,
            safety,
            built: TracerCache::new(built),
            params,
            sweep: Mutex::new(None),
        };
        Ok((live, note))
    }

    /// The viewer's starting settings: the scene's tracer, surface, sun, exposure and shadows.
    pub fn settings(&self) -> ViewSettings {
        let names = SceneChoices {
            tracers: self.choices.iter().map(ToString::to_string).collect(),
            surfaces: SURFACES.iter().map(ToString::to_string).collect(),
            ..SceneChoices::default()
        };
        let params = &self.scene.params;
        let sun = (params.sun.azimuth_deg, params.sun.elevation_deg);
        let mut settings = ViewSettings::new(names, sun, params.exposure, params.shadows);
        settings.tracer = position(&settings.choices.tracers, &self.scene.choice.to_string());
        settings.surface = position(&settings.choices.surfaces, &self.scene.surface.to_string());
        settings
    }

    /// The tracer of choice `index` for `surface`, built now if it was not yet.
    fn tracer(&self, index: usize, surface: Surface) -> Result<Arc<dyn Tracer>, RenderError> {
        self.built.get_or_build((index, surface), || {
            let TracerChoice::Plain(kind) = self.choices[index] else {
                return Err(RenderError::Unsupported(
                    "the safety tracer draws the triangles surface only".into(),
                ));
            };
            Ok(Arc::from(build_plain(&self.scene.field, surface, kind, Simd::detect())))
        })
    }

    /// The sun's shadow sweep for a frame of `pixels` pixels drawn by `tracer` (choice `index`)
    /// over `surface` with `params`: the kept one when it was built for the same, else built
    /// now ([`sun_shadow_sweep`]) and kept; `None` where it would not pay.
    fn sweep(
        &self,
        index: usize,
        surface: Surface,
        tracer: &Arc<dyn Tracer>,
        params: &ShadingParams,
        pixels: usize,
    ) -> Option<Arc<SunShadows<Arc<dyn Tracer>>>> {
        if !params.traces_shadow_rays() {
            return None;
        }
        let built_for = (index, surface, params.sun.direction().to_array().map(f64::to_bits));
        let mut kept = self.sweep.lock().expect("no render panicked");
        if let Some(kept) = kept.as_ref().filter(|k| k.built_for == built_for) {
            return Some(kept.sweep.clone());
        }
        let field = &self.scene.field;
        // The sweep is kept for every frame drawn under the same sun, so its build (a pass over
        // the field, a few milliseconds at 4096^2) pays for the shadow rays of all of them, not
        // of this frame alone: it pays whenever it would for their sum.
        let rays_while_kept = pixels.saturating_mul(FRAMES_UNDER_ONE_SUN);
        let sweep = sun_shadow_sweep(tracer.clone(), field, surface, params, rays_while_kept)?;
        let sweep = Arc::new(sweep);
        *kept = Some(KeptSweep { built_for, sweep: sweep.clone() });
        Some(sweep)
    }
}

impl Drawing for LiveHeightField {
    fn describe(&self) -> String {
        self.scene.describe()
    }

    fn scene_size(&self) -> f64 {
        let bounds = self.scene.bounds();
        (bounds.max - bounds.min).length()
    }

    fn draw(
        &self,
        camera: &Camera,
        settings: &ViewSettings,
        cancel: &Cancel,
    ) -> Result<Frame, RenderError> {
        let surface = SURFACES[settings.surface.min(SURFACES.len() - 1)];
        let mut index = settings.tracer.min(self.choices.len() - 1);
        let mut params = self.params.lock().expect("no render panicked");
        apply_view_settings(&mut params, settings);
        // The scene's shading normals for the surface shown: boxes are always faceted.
        params.normals = self.scene.normals(surface);
        let mut note = None;
        if let (TracerChoice::Safety(_), Some(safety)) = (&self.choices[index], &self.safety) {
            let refused = if surface != Surface::Triangles {
                Some("the safety tracer draws triangles only".to_string())
            } else {
                check_safety_view(safety, camera, &params).err().map(|e| e.to_string())
            };
            if let Some(why) = refused {
                note = Some(format!("{why}: drawn by the mipmap tracer"));
                index = 0;
            }
        }
        let built = self.tracer(index, surface)?;
        let pixels = camera.width() as usize * camera.height() as usize;
        let sweep = self.sweep(index, surface, &built, &params, pixels);
        let tracer = Interruptible { inner: built.as_ref(), stop: cancel.flag() };
        let shadow_tracer: &dyn Tracer = match &sweep {
            Some(sweep) => sweep.as_ref(),
            None => built.as_ref(),
        };
        let shadow_tracer = Interruptible { inner: shadow_tracer, stop: cancel.flag() };
        let bounds = self.scene.field.world_bounds(surface);
        let keep = KeptHits::default();
        let drawn =
            render_to_srgb8(&tracer, &shadow_tracer, camera, &bounds, &params, keep, &|_| {})?;
        let (traced, shaded) = (drawn.stats.primary, drawn.stats.shadow);
        let stats = FrameStats {
            rays: traced.rays + shaded.rays,
            steps_per_ray: Some(traced.mean_steps()),
        };
        Ok(Frame { width: camera.width(), height: camera.height(), rgb: drawn.rgb, stats, note })
    }
}
