//! The tracer a scene is drawn with, as a front end names it (`--tracer` and the safety
//! options), and building it for a height field: safety shapes with their cache, reported
//! as they are precomputed.

use crate::error::RenderError;
use crate::progress::Progress;
use relief_core::{HeightField, Surface};
use relief_trace::safety::{
    CacheOutcome, FinalTest, SafetyShapes, SafetyTracer, ShapeCache, ShapeLayout,
};
use relief_trace::{build_tracer, MipmapTracer, SafetyOptions, Simd, Tracer, TracerKind};
use std::fmt;
use std::path::PathBuf;
use std::str::FromStr;
use std::sync::Arc;
use std::time::Instant;

/// A tracer or renderer by name: `naive`, `mipmap`, `safety` (the variant the safety
/// settings give), a safety variant by name (`cyl_ext+cone_all`, ...), `hierarchy` (MLHM
/// scenes only; `naive` names the MLHM naive tracer there), `hybrid` or `clipmap`.
#[derive(Debug, Clone, PartialEq)]
pub enum TracerChoice {
    /// A tracer without precomputation.
    Plain(TracerKind),
    /// Safety shapes; `None`: the variant the safety settings name.
    Safety(Option<SafetyOptions>),
    /// The MLHM hierarchy tracer (multi-layered height maps only).
    Hierarchy,
    /// The hybrid renderer of height fields (Ammann et al. 2010): rasterized near field,
    /// ray-cast far field.
    Hybrid,
    /// Geometry clipmaps (Losasso & Hoppe 2004), the hybrid paper's comparison renderer.
    Clipmap,
}

impl FromStr for TracerChoice {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "safety" => Ok(TracerChoice::Safety(None)),
            "hierarchy" => Ok(TracerChoice::Hierarchy),
            "hybrid" => Ok(TracerChoice::Hybrid),
            "clipmap" => Ok(TracerChoice::Clipmap),
            _ if s.starts_with("cyl_") => s.parse().map(|o| TracerChoice::Safety(Some(o))),
            _ => s.parse().map(TracerChoice::Plain).map_err(|_| {
                format!("unknown tracer '{s}' (expected naive, mipmap, safety, a safety variant such as cyl_all+cone_all, hybrid, clipmap, or hierarchy for MLHM scenes)")
            }),
        }
    }
}

impl fmt::Display for TracerChoice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // `pad`, so that widths and alignment in format strings apply.
        match self {
            TracerChoice::Plain(kind) => kind.fmt(f),
            TracerChoice::Safety(None) => f.pad("safety"),
            TracerChoice::Safety(Some(o)) => f.pad(&o.variant()),
            TracerChoice::Hierarchy => f.pad("hierarchy"),
            TracerChoice::Hybrid => f.pad("hybrid"),
            TracerChoice::Clipmap => f.pad("clipmap"),
        }
    }
}

/// The safety tracer's options (Baboud et al. 2011): the shapes' variant and how they are
/// built, the final test, and the shape cache.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SafetySettings {
    /// The shapes' variant [default: cyl_all+cone_all].
    pub variant: Option<SafetyOptions>,
    /// Build the shapes for rays at most this many degrees from horizontal.
    pub phi_max: Option<f64>,
    /// One shape per texel for all four ray classes.
    pub isotropic: bool,
    /// Clamp safety distances to at least one.
    pub positive: bool,
    /// Final test on the view-dependent linear surface instead of the two triangles.
    pub linear_surface: bool,
    /// Farthest step, in texels, a shape may allow [default: 128].
    pub reach: Option<u16>,
    /// Where precomputed shapes are kept [default: the user's cache folder].
    pub cache_dir: Option<PathBuf>,
    /// Neither read nor write the shape cache.
    pub no_cache: bool,
}

impl SafetySettings {
    /// The shapes' options for `variant` (else the settings' own), checked.
    pub fn options(&self, variant: Option<SafetyOptions>) -> Result<SafetyOptions, RenderError> {
        let mut options = variant.or(self.variant).unwrap_or_default();
        options.phi_max_deg = self.phi_max;
        options.layout =
            if self.isotropic { ShapeLayout::Isotropic } else { ShapeLayout::Directional };
        options.strictly_positive = self.positive;
        options.reach = self.reach.unwrap_or(options.reach);
        options.validate().map_err(RenderError::SafetyOptions)?;
        Ok(options)
    }
}

/// A tracer to build for a height field: its name, the surface it traces, the safety options,
/// and how it is built (the shape cache, the memory limit, the mipmap tracer's SIMD).
#[derive(Debug, Clone, PartialEq)]
pub struct TracerSpec {
    /// The tracer.
    pub choice: TracerChoice,
    /// The surface it traces.
    pub surface: Surface,
    /// The safety tracer's options.
    pub safety: SafetySettings,
    /// Whether safety shapes are read from (and stored in) the cache.
    pub use_cache: bool,
    /// Bytes the safety shapes may take.
    pub max_memory: u64,
    /// The instructions the mipmap tracer's packet tests run on.
    pub simd: Simd,
}

/// A built tracer and what building it took.
pub struct BuiltTracer {
    /// The tracer.
    pub tracer: Box<dyn Tracer>,
    /// The safety tracer itself, for view checks.
    pub safety: Option<SafetyTracer>,
    /// Seconds spent building (precomputing), zero when loaded from the cache.
    pub build_s: f64,
    /// A one-line account of the build, e.g. where the shapes came from; empty if none.
    pub note: String,
}

impl TracerSpec {
    /// The tracer `choice` of `surface`, with default safety options, the cache, no memory
    /// limit and the machine's SIMD.
    pub fn new(choice: TracerChoice, surface: Surface) -> Self {
        TracerSpec {
            choice,
            surface,
            safety: SafetySettings::default(),
            use_cache: true,
            max_memory: u64::MAX,
            simd: Simd::detect(),
        }
    }

    /// Builds the tracer for `field`.
    pub fn build(&self, field: &Arc<HeightField>) -> Result<Box<dyn Tracer>, RenderError> {
        Ok(self.build_reporting(field, &crate::progress::Silent)?.tracer)
    }

    /// Builds the tracer for `field`. Safety shapes come from the cache when it is used and
    /// has them; otherwise they are precomputed (reported to `progress`, refused beyond the
    /// memory limit) and, with the cache, stored.
    pub fn build_reporting(
        &self,
        field: &Arc<HeightField>,
        progress: &dyn Progress,
    ) -> Result<BuiltTracer, RenderError> {
        let started = Instant::now();
        let (surface, choice) = (self.surface, &self.choice);
        let variant = match choice {
            TracerChoice::Plain(kind) => {
                let tracer = build_plain(field, surface, *kind, self.simd);
                let build_s = started.elapsed().as_secs_f64();
                return Ok(BuiltTracer { tracer, safety: None, build_s, note: String::new() });
            }
            TracerChoice::Safety(variant) => *variant,
            TracerChoice::Hierarchy => return Err(RenderError::Unsupported(
                "the hierarchy tracer renders MLHM scenes (.json, .mlhm) only; height fields take --tracer naive, mipmap or safety".into()
            )),
            TracerChoice::Hybrid | TracerChoice::Clipmap => return Err(RenderError::Unsupported(format!(
                "the {choice} renderer draws with relief render and relief bench only; here take --tracer naive, mipmap or safety"
            ))),
        };
        if surface != Surface::Triangles {
            return Err(RenderError::Unsupported(
                "the safety tracer renders the triangles surface only (use --surface triangles)"
                    .into(),
            ));
        }
        let options = self.safety.options(variant)?;
        let needed = SafetyShapes::memory_estimate(field.width(), field.height(), &options);
        if needed > self.max_memory {
            return Err(RenderError::ShapesOverBudget {
                options: options.to_string(),
                width: field.width(),
                height: field.height(),
                needed,
                limit: self.max_memory,
            });
        }
        progress.begin("safety shapes", Some((4 * field.width() * field.height()) as u64));
        let report = |done: usize, _total: usize| progress.set(done as u64);
        let cache = (self.use_cache && !self.safety.no_cache)
            .then(|| self.safety.cache_dir.clone().or_else(ShapeCache::default_dir))
            .flatten()
            .map(ShapeCache::new);
        let built = match &cache {
            Some(cache) => cache.load_or_build(field, options, &report).map(|(shapes, outcome)| {
                let note = match outcome {
                    CacheOutcome::Loaded(path) => {
                        format!("{options} shapes from {}", path.display())
                    }
                    CacheOutcome::Built(path) => {
                        format!("{options} shapes cached in {}", path.display())
                    }
                    CacheOutcome::Rebuilt { path, reason } => format!(
                        "warning: the cached {options} shapes in {} were not used: {reason}; \
                         built again and rewritten",
                        path.display()
                    ),
                };
                (shapes, note)
            }),
            None => SafetyShapes::build(field, options, &report)
                .map(|shapes| (shapes, format!("{options} shapes"))),
        };
        progress.end();
        let (shapes, note) = built?;
        let build_s = started.elapsed().as_secs_f64();
        let final_test =
            if self.safety.linear_surface { FinalTest::Linear } else { FinalTest::Triangles };
        let safety = SafetyTracer::new(field.clone(), Arc::new(shapes), final_test)
            .map_err(RenderError::SafetyTracer)?;
        Ok(BuiltTracer { tracer: Box::new(safety.clone()), safety: Some(safety), build_s, note })
    }
}

/// Builds the tracer `kind`, which needs no precomputation, for `surface` of `field`; the
/// mipmap tracer's packet tests run on `simd`.
pub fn build_plain(
    field: &Arc<HeightField>,
    surface: Surface,
    kind: TracerKind,
    simd: Simd,
) -> Box<dyn Tracer> {
    match kind {
        TracerKind::Mipmap => Box::new(MipmapTracer::new(field.clone(), surface).with_simd(simd)),
        _ => build_tracer(field.clone(), surface, kind),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_safety_variant_is_the_documented_one() {
        let documented: SafetyOptions = "cyl_all+cone_all".parse().unwrap();
        assert_eq!(documented, SafetyOptions::default());
    }

    #[test]
    fn names_honour_widths() {
        let mipmap = TracerChoice::Plain(TracerKind::Mipmap);
        assert_eq!(
            format!("[{mipmap:<8}][{:>8}]", TracerChoice::Hierarchy),
            "[mipmap  ][hierarchy]"
        );
        assert_eq!(format!("[{:<8}]", TracerChoice::Safety(None)), "[safety  ]");
    }

    #[test]
    fn a_plain_tracer_builds_and_a_hierarchy_is_refused_for_a_height_field() {
        let samples = (0..8 * 8).map(|k| (k % 3) as f32).collect();
        let grid = relief_core::GridGeometry::unit();
        let field = Arc::new(HeightField::new(8, 8, samples, grid).unwrap());
        let spec = TracerSpec::new(TracerChoice::Plain(TracerKind::Naive), Surface::Boxes);
        assert_eq!(spec.build(&field).unwrap().surface(), Surface::Boxes);
        let hierarchy = TracerSpec::new(TracerChoice::Hierarchy, Surface::Boxes);
        let err = hierarchy.build(&field).err().unwrap().to_string();
        assert!(err.contains("MLHM scenes"), "{err}");
    }
}
