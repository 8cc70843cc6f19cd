//! A rendered picture: its pixels, the depth and normals where asked for, what it took.

use relief_shade::{GBuffer, KeptHits};
use serde_json::{Map, Value};
use std::time::Instant;

/// A scene rendered from one camera.
#[derive(Debug, Clone, PartialEq)]
pub struct Picture {
    /// Pixels a row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// 8-bit sRGB pixels, row-major from the top.
    pub rgb: Vec<[u8; 3]>,
    /// The distance to each pixel's first hit (+inf on a miss), where asked for.
    pub depth: Option<Vec<f32>>,
    /// Each pixel's unit world normal (zero on a miss), where asked for.
    pub normals: Option<Vec<[f32; 3]>>,
    /// What drew it, in a few words: "triangles mipmap tracer", ...
    pub summary: String,
    /// What the user should know of how it was drawn (where safety shapes came from, ...).
    pub notes: Vec<String>,
    /// Counts and stage timings (`*_ms`): the tracer, rays, hits, build, trace and shade.
    pub stats: Map<String, Value>,
}

impl Picture {
    /// The picture's pixels as one slice of bytes.
    pub fn rgb_bytes(&self) -> &[u8] {
        self.rgb.as_flattened()
    }

    /// Writes the picture to `path` as an 8-bit RGB PNG.
    pub fn write_png(&self, path: &std::path::Path) -> Result<(), crate::RenderError> {
        Ok(relief_io::write_png_rgb8(path, self.width, self.height, self.rgb_bytes())?)
    }
}

/// The depth and normals of `gbuffer` that `keep` asks for, taken out of it.
pub(crate) fn kept_arrays(
    gbuffer: &mut GBuffer,
    keep: KeptHits,
) -> (Option<Vec<f32>>, Option<Vec<[f32; 3]>>) {
    let depth = keep.depth.then(|| std::mem::take(&mut gbuffer.distance));
    let normals = keep.normals.then(|| std::mem::take(&mut gbuffer.normal));
    (depth, normals)
}

/// Milliseconds since `start`.
pub(crate) fn ms_since(start: Instant) -> f64 {
    start.elapsed().as_secs_f64() * 1e3
}

/// `value` as a JSON object's map (empty for anything else).
pub(crate) fn object(value: Value) -> Map<String, Value> {
    match value {
        Value::Object(map) => map,
        _ => Map::new(),
    }
}
