//! Safety shapes on disk: one file per height-field content and options, so a second render
//! of the same terrain skips the precomputation.
//!
//! The file name is a hash of the samples, the grid geometry, the options and the format
//! version; the header repeats all of them but the samples, and an XXH3-64 checksum of all
//! that precedes it ends the file. A file that fails the checksum or whose header does not
//! match exactly is never used: it is rebuilt, and [`CacheOutcome::Rebuilt`] says why.

use super::options::SafetyOptions;
use super::shapes::{Progress, SafetyShapes};
use crate::TraceError;
use relief_core::HeightField;
use std::io::Write;
use std::path::{Path, PathBuf};

const MAGIC: &[u8; 8] = b"RLFSAFE\0";
/// Version 2 added the checksum.
const VERSION: u32 = 2;
/// The checksum's length at the end of the file.
const CHECKSUM_LEN: usize = 8;

/// Whether [`ShapeCache::load_or_build`] found the shapes or computed them.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum CacheOutcome {
    /// Read from this file.
    Loaded(PathBuf),
    /// Computed and written to this file.
    Built(PathBuf),
    /// The file held damaged or foreign data (the reason): computed again and rewritten.
    Rebuilt {
        /// The file, now rewritten.
        path: PathBuf,
        /// What was wrong with what it held.
        reason: String,
    },
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

    /// The cached shapes of `field` with `options`, or `None` if no file holds them. A file
    /// that fails its checksum or was written for another terrain or options is an error,
    /// [`TraceError::CacheFormat`].
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
        match decode(&bytes, key, field, options) {
            Ok(shapes) => Ok(Some(shapes)),
            Err(reason) => Err(TraceError::CacheFormat { path, reason: reason.to_string() }),
        }
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

    /// The shapes from the cache, or built (with progress) and stored; a damaged file is
    /// rebuilt and overwritten.
    pub fn load_or_build(
        &self,
        field: &HeightField,
        options: SafetyOptions,
        progress: Progress,
    ) -> Result<(SafetyShapes, CacheOutcome), TraceError> {
        let damage = match self.load(field, &options) {
            Ok(Some(shapes)) => {
                return Ok((shapes, CacheOutcome::Loaded(self.path(field, &options))));
            }
            Ok(None) => None,
            Err(TraceError::CacheFormat { reason, .. }) => Some(reason),
            Err(other) => return Err(other),
        };
        let shapes = SafetyShapes::build(field, options, progress)?;
        let path = self.store(field, &shapes)?;
        let outcome = match damage {
            None => CacheOutcome::Built(path),
            Some(reason) => CacheOutcome::Rebuilt { path, reason },
        };
        Ok((shapes, outcome))
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
    let checksum = xxhash_rust::xxh3::xxh3_64(&out);
    out.extend_from_slice(&checksum.to_le_bytes());
    out
}

/// Why a cache file's content was not used.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
enum Damage {
    #[error("shorter than a checksum")]
    Short,
    #[error("its checksum does not match its content (the file was changed or cut)")]
    Checksum,
    #[error("written for another terrain, options or version of relief")]
    Foreign,
    #[error("its content does not hold the shapes its header describes")]
    Malformed,
}

/// The shapes in `bytes` if the checksum holds and the header matches `key`, `field` and
/// `options` exactly.
fn decode(
    bytes: &[u8],
    key: u64,
    field: &HeightField,
    options: &SafetyOptions,
) -> Result<SafetyShapes, Damage> {
    let split = bytes.len().checked_sub(CHECKSUM_LEN).ok_or(Damage::Short)?;
    let (content, checksum) = bytes.split_at(split);
    if xxhash_rust::xxh3::xxh3_64(content).to_le_bytes() != checksum {
        return Err(Damage::Checksum);
    }
    let mut r = Reader { bytes: content, at: 0 };
    let foreign = |same: bool| if same { Ok(()) } else { Err(Damage::Foreign) };
    foreign(r.take(8)? == MAGIC && r.u32()? == VERSION && r.u64()? == key)?;
    let (width, height) = (r.u64()? as usize, r.u64()? as usize);
    foreign((width, height) == (field.width(), field.height()))?;
    let name_len = r.u32()? as usize;
    foreign(r.take(name_len)? == options.to_string().as_bytes())?;
    let (slots, cone_slots) = (r.u32()? as usize, r.u32()? as usize);
    let n = width.checked_mul(height).ok_or(Damage::Malformed)?;
    if !(slots == 1 || slots == 4) || !(cone_slots == 0 || cone_slots == slots) {
        return Err(Damage::Malformed);
    }
    let radii = (0..slots)
        .map(|_| (0..n).map(|_| r.take(2).map(|b| u16::from_le_bytes([b[0], b[1]]))).collect())
        .collect::<Result<Vec<Vec<u16>>, Damage>>()?;
    let cones = (0..cone_slots)
        .map(|_| (0..n).map(|_| Ok([r.f32()?, r.f32()?])).collect())
        .collect::<Result<Vec<Vec<[f32; 2]>>, Damage>>()?;
    if r.at != content.len() {
        return Err(Damage::Malformed);
    }
    Ok(SafetyShapes::from_parts(width, height, *options, radii, cones))
}

struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize) -> Result<&'a [u8], Damage> {
        let end = self.at.checked_add(n).ok_or(Damage::Malformed)?;
        let s = self.bytes.get(self.at..end).ok_or(Damage::Malformed)?;
        self.at = end;
        Ok(s)
    }
    fn u32(&mut self) -> Result<u32, Damage> {
        self.take(4).map(|b| u32::from_le_bytes(b.try_into().unwrap()))
    }
    fn u64(&mut self) -> Result<u64, Damage> {
        self.take(8).map(|b| u64::from_le_bytes(b.try_into().unwrap()))
    }
    fn f32(&mut self) -> Result<f32, Damage> {
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
        // A file under the right name whose header says otherwise is not used, but rebuilt.
        std::fs::copy(cache.path(&a, &options), cache.path(&b, &options)).unwrap();
        assert_damaged(cache.load(&b, &options), "another terrain");
        let (rebuilt, outcome) = cache.load_or_build(&b, options, &|_, _| {}).unwrap();
        assert!(matches!(outcome, CacheOutcome::Rebuilt { .. }), "{outcome:?}");
        assert_eq!(cache.load(&b, &options).unwrap(), Some(rebuilt));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    fn assert_damaged(result: Result<Option<SafetyShapes>, TraceError>, needle: &str) {
        match result {
            Err(TraceError::CacheFormat { reason, .. }) => {
                assert!(reason.contains(needle), "{reason}")
            }
            other => panic!("expected a damaged cache file, got {other:?}"),
        }
    }

    #[test]
    fn damaged_files_are_refused_and_rebuilt_to_the_same_shapes() {
        let dir = std::env::temp_dir().join(format!("relief-safety-damage-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let cache = ShapeCache::new(&dir);
        let a = field(0.0);
        let options: SafetyOptions = "cyl_all+cone_all".parse().unwrap();
        let (built, _) = cache.load_or_build(&a, options, &|_, _| {}).unwrap();
        let path = cache.path(&a, &options);
        let good = std::fs::read(&path).unwrap();
        // Every byte changed, one at a time, and every cut: refused, never other shapes.
        for at in (0..good.len()).step_by(7) {
            let mut bad = good.clone();
            bad[at] ^= 0x5a;
            std::fs::write(&path, &bad).unwrap();
            assert_damaged(cache.load(&a, &options), "checksum");
        }
        for cut in [0, 3, good.len() / 2, good.len() - 1] {
            std::fs::write(&path, &good[..cut]).unwrap();
            let needle = if cut < CHECKSUM_LEN { "shorter" } else { "checksum" };
            assert_damaged(cache.load(&a, &options), needle);
        }
        // Overwritten radii (the header intact): rebuilt, with the reason, to the same shapes.
        let mut bad = good.clone();
        let radii_at = 48 + options.to_string().len() + 10;
        bad[radii_at..radii_at + 16].fill(0xff);
        std::fs::write(&path, &bad).unwrap();
        let (rebuilt, outcome) = cache.load_or_build(&a, options, &|_, _| {}).unwrap();
        match outcome {
            CacheOutcome::Rebuilt { reason, .. } => assert!(reason.contains("checksum")),
            other => panic!("expected a rebuild, got {other:?}"),
        }
        assert_eq!(rebuilt, built);
        assert_eq!(std::fs::read(&path).unwrap(), good, "the rewritten file is the first");
        let (_, outcome) = cache.load_or_build(&a, options, &|_, _| {}).unwrap();
        assert!(matches!(outcome, CacheOutcome::Loaded(_)));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
