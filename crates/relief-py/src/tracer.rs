//! The tracer a call traces with, built once per call as the command line builds it.

use relief_core::{HeightField, Surface};
use relief_trace::{build_tracer, MipmapTracer, Simd, Tracer, TracerKind};
use std::sync::Arc;

/// The tracer `kind` for `surface` of `field`; the mipmap tracer's packet tests run on the
/// fastest instructions this processor has, as `relief render`'s do.
pub fn tracer(field: &Arc<HeightField>, surface: Surface, kind: TracerKind) -> Box<dyn Tracer> {
    match kind {
        TracerKind::Mipmap => {
            Box::new(MipmapTracer::new(field.clone(), surface).with_simd(Simd::detect()))
        }
        _ => build_tracer(field.clone(), surface, kind),
    }
}
