//! Safety shapes on disk: one file per height-field content and options, so a second render
//! of the same terrain skips the precomputation.
//!
//! The file name is a hash of the samples, the grid geometry, the options and the format
//! version; the header repeats all of them but the samples, and a file whose header does not
//! match exactly is rebuilt, never used.

use super::options::SafetyOptions;
use super::shapes::{Progress, SafetyShapes};
use crate::TraceError;
use relief_core::HeightField;
use std::io::Write;
use std::path::{Path, PathBuf};

const MAGIC: &[u8; 8] = b"RLFSAFE\0";
const VERSION: u32 = 1;

/// Whether [`ShapeCache::load_or_build`] found the shapes or computed them.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum CacheOutcome {
    /// Read from this file.
    Loaded(PathBuf),
    /// Computed and written to this file.
    Built(PathBuf),
}

/// A directory of precomputed safety shapes.
#[derive(Debug, Clone)]
pub struct ShapeCache {
    dir: PathBuf,
}

impl ShapeCache {
    /// A cache in `dir` (created when first written).
    pub fn new(dir: impl Into<PathBuf>) -> Self {
        ShapeCache { dir: dir.into() }
    }

    /// The usual place: `$RELIEF_CACHE_DIR`, else `$XDG_CACHE_HOME/relief`, else
    /// `$HOME/.cache/relief`.
    pub fn default_dir() -> Option<PathBuf> {
        let var = |name: &str| std::env::var_os(name).filter(|v| !v.is_empty()).map(PathBuf::from);
        var("RELIEF_CACHE_DIR")
            .or_else(|| var("XDG_CACHE_HOME").map(|d| d.join("relief")))
            .or_else(|| var("HOME").map(|d| d.join(".cache").join("relief")))
    }

    /// The directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The key of `field` (samples and geometry) with `options`.
    pub fn key(field: &HeightField, options: &SafetyOptions) -> u64 {
        let mut h = xxhash_rust::xxh3::Xxh3::new();
        h.update(&VERSION.to_le_bytes());
        h.update(&(field.width() as u64).to_le_bytes());
        h.update(&(field.height() as u64).to_le_bytes());
        for s in field.samples() {
            h.update(&s.to_bits().to_le_bytes());
        }
        let g = field.geometry();
        for v in [g.dx, g.dy, g.z_scale] {
            h.update(&v.to_bits().to_le_bytes());
        }
        h.update(options.to_string().as_bytes());
        h.digest()
    }

    /// The file the shapes of `field` with `options` live in.
    pub fn path(&self, field: &HeightField, options: &SafetyOptions) -> PathBuf {
        self.dir.join(format!("{:016x}.safety", Self::key(field, options)))
    }

    /// The cached shapes of `field` with `options`, if a matching file exists.
    pub fn load(
        &self,
        field: &HeightField,
        options: &SafetyOptions,
    ) -> Result<Option<SafetyShapes>, TraceError> {
        let path = self.path(field, options);
        let bytes = match std::fs::read(&path) {
            Ok(b) => b,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(source) => return Err(TraceError::CacheIo { path, source }),
        };
        let key = Self::key(field, options);
        Ok(decode(&bytes, key, field, options))
    }

    /// Writes `shapes` (built for `field`) to the cache, atomically.
    pub fn store(&self, field: &HeightField, shapes: &SafetyShapes) -> Result<PathBuf, TraceError> {
        let path = self.path(field, shapes.options());
        let io = |source| TraceError::CacheIo { path: path.clone(), source };
        std::fs::create_dir_all(&self.dir).map_err(io)?;
        let tmp = path.with_extension(format!("tmp{}", std::process::id()));
        let bytes = encode(shapes, Self::key(field, shapes.options()));
        let written = std::fs::File::create(&tmp).and_then(|mut f| {
            f.write_all(&bytes)?;
            f.sync_all()
        });
        if let Err(e) = written.and_then(|_| std::fs::rename(&tmp, &path)) {
            let _ = std::fs::remove_file(&tmp);
            return Err(io(e));
        }
        Ok(path)
    }

    /// The shapes from the cache, or built (with progress) and stored.
    pub fn load_or_build(
        &self,
        field: &HeightField,
        options: SafetyOptions,
        progress: Progress,
    ) -> Result<(SafetyShapes, CacheOutcome), TraceError> {
        if let Some(shapes) = self.load(field, &options)? {
            return Ok((shapes, CacheOutcome::Loaded(self.path(field, &options))));
        }
        let shapes = SafetyShapes::build(field, options, progress)?;
        let path = self.store(field, &shapes)?;
        Ok((shapes, CacheOutcome::Built(path)))
    }
}

fn encode(shapes: &SafetyShapes, key: u64) -> Vec<u8> {
    let (radii, cones) = shapes.parts();
    let options = shapes.options().to_string();
    let mut out = Vec::new();
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&VERSION.to_le_bytes());
    out.extend_from_slice(&key.to_le_bytes());
    out.extend_from_slice(&(shapes.width() as u64).to_le_bytes());
    out.extend_from_slice(&(shapes.height() as u64).to_le_bytes());
    out.extend_from_slice(&(options.len() as u32).to_le_bytes());
    out.extend_from_slice(options.as_bytes());
    out.extend_from_slice(&(radii.len() as u32).to_le_bytes());
    out.extend_from_slice(&(cones.len() as u32).to_le_bytes());
    for r in radii.iter().flatten() {
        out.extend_from_slice(&r.to_le_bytes());
    }
    for c in cones.iter().flatten().flatten() {
        out.extend_from_slice(&c.to_le_bytes());
    }
    out
}

/// The shapes in `bytes` if the header matches `key`, `field` and `options` exactly.
fn decode(
    bytes: &[u8],
    key: u64,
    field: &HeightField,
    options: &SafetyOptions,
) -> Option<SafetyShapes> {
    let mut r = Reader { bytes, at: 0 };
    if r.take(8)? != MAGIC || r.u32()? != VERSION || r.u64()? != key {
        return None;
    }
    let (width, height) = (r.u64()? as usize, r.u64()? as usize);
    if (width, height) != (field.width(), field.height()) {
        return None;
    }
    let name_len = r.u32()? as usize;
    if r.take(name_len)? != options.to_string().as_bytes() {
        return None;
    }
    let (slots, cone_slots) = (r.u32()? as usize, r.u32()? as usize);
    let n = width.checked_mul(height)?;
    if !(slots == 1 || slots == 4) || !(cone_slots == 0 || cone_slots == slots) {
        return None;
    }
    let radii = (0..slots)
        .map(|_| (0..n).map(|_| r.take(2).map(|b| u16::from_le_bytes([b[0], b[1]]))).collect())
        .collect::<Option<Vec<Vec<u16>>>>()?;
    let cones = (0..cone_slots)
        .map(|_| (0..n).map(|_| Some([r.f32()?, r.f32()?])).collect())
        .collect::<Option<Vec<Vec<[f32; 2]>>>>()?;
    (r.at == bytes.len()).then(|| SafetyShapes::from_parts(width, height, *options, radii, cones))
}

struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize) -> Option<&'a [u8]> {
        let s = self.bytes.get(self.at..self.at.checked_add(n)?)?;
        self.at += n;
        Some(s)
    }
    fn u32(&mut self) -> Option<u32> {
        self.take(4).map(|b| u32::from_le_bytes(b.try_into().unwrap()))
    }
    fn u64(&mut self) -> Option<u64> {
        self.take(8).map(|b| u64::from_le_bytes(b.try_into().unwrap()))
    }
    fn f32(&mut self) -> Option<f32> {
        self.take(4).map(|b| f32::from_le_bytes(b.try_into().unwrap()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief_core::GridGeometry;

    fn field(bump: f32) -> HeightField {
        let samples =
            (0..12 * 9).map(|k| ((k * 7) % 5) as f32 + if k == 40 { bump } else { 0.0 }).collect();
        HeightField::new(12, 9, samples, GridGeometry::unit()).unwrap()
    }

    #[test]
    fn shapes_come_back_only_for_the_same_field_and_options() {
        let dir = std::env::temp_dir().join(format!("relief-safety-cache-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let cache = ShapeCache::new(&dir);
        let (a, b) = (field(0.0), field(0.5));
        let options: SafetyOptions = "cyl_all+cone_all".parse().unwrap();
        let (built, outcome) = cache.load_or_build(&a, options, &|_, _| {}).unwrap();
        assert!(matches!(outcome, CacheOutcome::Built(_)));
        assert_eq!(cache.load(&a, &options).unwrap(), Some(built.clone()));
        // Another field, other options: nothing to reuse.
        assert_eq!(cache.load(&b, &options).unwrap(), None);
        let other = SafetyOptions { strictly_positive: true, ..options };
        assert_eq!(cache.load(&a, &other).unwrap(), None);
        // A file under the right name whose header says otherwise is not used.
        std::fs::copy(cache.path(&a, &options), cache.path(&b, &options)).unwrap();
        assert_eq!(cache.load(&b, &options).unwrap(), None);
        // Nor is a truncated one.
        let path = cache.path(&a, &options);
        let bytes = std::fs::read(&path).unwrap();
        std::fs::write(&path, &bytes[..bytes.len() - 3]).unwrap();
        assert_eq!(cache.load(&a, &options).unwrap(), None);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
