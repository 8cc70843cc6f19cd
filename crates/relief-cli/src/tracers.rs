//! Choosing and building a tracer from the command line, including safety shapes (with their
//! cache and a progress bar while they are precomputed).

use crate::args::SafetyArgs;
use crate::progress;
use anyhow::{bail, Context, Result};
use relief_core::{HeightField, Surface};
use relief_trace::safety::{
    CacheOutcome, FinalTest, SafetyShapes, SafetyTracer, ShapeCache, ShapeLayout,
};
use relief_trace::{build_tracer, MipmapTracer, SafetyOptions, Simd, Tracer, TracerKind};
use std::fmt;
use std::str::FromStr;
use std::sync::Arc;
use std::time::Instant;

/// A tracer named on the command line: `naive`, `mipmap`, `safety` (the variant given by
/// `--safety`), a safety variant by name (`cyl_ext+cone_all`, ...), or `hierarchy` (MLHM
/// scenes only; `naive` names the MLHM naive tracer there).
#[derive(Debug, Clone, PartialEq)]
pub enum TracerChoice {
    /// A tracer without precomputation.
    Plain(TracerKind),
    /// Safety shapes; `None`: the variant `--safety` names.
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

/// A built tracer and what building it took.
pub struct Built {
    /// The tracer.
    pub tracer: Box<dyn Tracer>,
    /// The safety tracer itself, for view checks.
    pub safety: Option<SafetyTracer>,
    /// Seconds spent building (precomputing), zero when loaded from the cache.
    pub build_s: f64,
    /// A one-line account of the build, e.g. where the shapes came from.
    pub note: String,
}

/// The safety options the command line asks for, for `choice`'s variant.
pub fn safety_options(variant: Option<SafetyOptions>, args: &SafetyArgs) -> Result<SafetyOptions> {
    let mut options = variant.or(args.safety).unwrap_or_default();
    options.phi_max_deg = args.phi_max;
    options.layout = if args.isotropic { ShapeLayout::Isotropic } else { ShapeLayout::Directional };
    options.strictly_positive = args.positive;
    options.reach = args.safety_reach.unwrap_or(options.reach);
    options.validate().map_err(anyhow::Error::msg)?;
    Ok(options)
}

/// Builds the chosen tracer for `surface` of `field`. Safety shapes come from the cache when
/// `use_cache` and the cache has them; otherwise they are precomputed (with a progress bar,
/// refused beyond `max_memory`) and, with `use_cache`, stored. The mipmap tracer's packet
/// tests run on `simd`.
pub fn build(
    field: &Arc<HeightField>,
    surface: Surface,
    choice: &TracerChoice,
    args: &SafetyArgs,
    use_cache: bool,
    max_memory: u64,
    simd: Simd,
) -> Result<Built> {
    let started = Instant::now();
    let variant = match choice {
        TracerChoice::Plain(kind) => {
            let tracer = build_plain(field, surface, *kind, simd);
            let build_s = started.elapsed().as_secs_f64();
            return Ok(Built { tracer, safety: None, build_s, note: String::new() });
        }
        TracerChoice::Safety(variant) => *variant,
        TracerChoice::Hierarchy => bail!(
            "the hierarchy tracer renders MLHM scenes (.json, .mlhm) only; height fields take --tracer naive, mipmap or safety"
        ),
        TracerChoice::Hybrid | TracerChoice::Clipmap => bail!(
            "the {choice} renderer draws with relief render and relief bench only; here take --tracer naive, mipmap or safety"
        ),
    };
    if surface != Surface::Triangles {
        bail!("the safety tracer renders the triangles surface only (use --surface triangles)");
    }
    let options = safety_options(variant, args)?;
    let needed = SafetyShapes::memory_estimate(field.width(), field.height(), &options);
    if needed > max_memory {
        bail!(
            "{options} shapes for a {}x{} terrain need about {}, over the {} memory limit \
             (raise it with --max-memory, or use --isotropic or the mipmap tracer)",
            field.width(),
            field.height(),
            crate::memory::format_bytes(needed),
            crate::memory::format_bytes(max_memory)
        );
    }
    let bar = progress::bar((4 * field.width() * field.height()) as u64, "safety shapes");
    let report = |done: usize, _total: usize| bar.set_position(done as u64);
    let cache = (use_cache && !args.no_cache)
        .then(|| args.cache_dir.clone().or_else(ShapeCache::default_dir))
        .flatten()
        .map(ShapeCache::new);
    let (shapes, note) = match &cache {
        Some(cache) => {
            let (shapes, outcome) = cache.load_or_build(field, options, &report)?;
            let note = match outcome {
                CacheOutcome::Loaded(path) => format!("{options} shapes from {}", path.display()),
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
        }
        None => (SafetyShapes::build(field, options, &report)?, format!("{options} shapes")),
    };
    bar.finish_and_clear();
    let build_s = started.elapsed().as_secs_f64();
    let final_test = if args.linear_surface { FinalTest::Linear } else { FinalTest::Triangles };
    let safety =
        SafetyTracer::new(field.clone(), Arc::new(shapes), final_test).context("safety tracer")?;
    Ok(Built { tracer: Box::new(safety.clone()), safety: Some(safety), build_s, note })
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
}
