//! The process's memory: its peak as the operating system reports it, where a budget
//! comes from, and what an image takes while a renderer draws it.

/// Peak resident set size in bytes (`VmHWM` of /proc/self/status), if the system reports it.
pub fn peak_resident_bytes() -> Option<u64> {
    status_bytes("VmHWM:")
}

/// Resident set size now, in bytes (`VmRSS` of /proc/self/status), if the system reports it.
pub fn resident_bytes() -> Option<u64> {
    status_bytes("VmRSS:")
}

/// The figure of the /proc/self/status line starting with `key`, in bytes (it is in KiB).
fn status_bytes(key: &str) -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with(key))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// A memory budget and where it comes from, for messages.
#[derive(Debug, Clone)]
pub struct Budget {
    /// Bytes the work may take.
    pub bytes: u64,
    /// Where the figure comes from: "--max-memory", or the limit the default is half of.
    pub origin: String,
}

/// The budget `--max-memory` gives, or the default one where it gives none.
pub fn budget(max_memory: Option<u64>) -> Budget {
    match max_memory {
        Some(bytes) => Budget { bytes, origin: "--max-memory".into() },
        None => {
            let default = relief_io::default_memory_budget();
            Budget {
                bytes: default.bytes,
                origin: format!("{}; raise it with --max-memory", default.source),
            }
        }
    }
}

/// `bytes` in words for messages: whole MiB from 1 MiB up, else KiB, else bytes (so that a
/// limit of `--max-memory 1K` reads "1 KiB", not "0 MiB").
pub fn format_bytes(bytes: u64) -> String {
    match bytes {
        b if b >= 1 << 20 => format!("{} MiB", b >> 20),
        b if b >= 1 << 10 => match b % (1 << 10) {
            0 => format!("{} KiB", b >> 10),
            _ => format!("{:.1} KiB", b as f64 / 1024.0),
        },
        1 => "1 byte".into(),
        b => format!("{b} bytes"),
    }
}

/// How a renderer holds the picture it draws, which sets the memory an image takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ImageHolding {
    /// Traced and shaded strip by strip (`relief render` with the naive, mipmap and safety
    /// tracers): the 8-bit picture, the depth and normals kept for `--depth` and `--normals`,
    /// and one strip G-buffer a thread.
    Strips {
        /// Whether the depth image is kept (4 bytes a pixel).
        depth: bool,
        /// Whether the normals are kept (12 bytes a pixel).
        normals: bool,
    },
    /// A G-buffer of the whole image, shaded once it is full (tile stores, the hybrid and
    /// clipmap renderers, meshes, the viewer's frames).
    WholeGBuffer,
    /// An MLHM scene's renderer: its G-buffer, the shading's buffers (shadows, ambient
    /// occlusion, water) and the radiance of the whole image.
    Mlhm,
}

/// Bytes an MLHM render holds a pixel: measured 124 (the slope of the peak resident set of
/// the reference scene ngwm24 rendered at 1000x563 and 2000x1125, preset mid).
pub const MLHM_BYTES_PER_PIXEL: u64 = 128;

/// Bytes a whole-image G-buffer renderer holds a pixel: the G-buffer (56), the linear
/// radiance (12) and the 8-bit output (3). Measured: a tile store rendered at 4000x2250 peaks
/// at 60 bytes a pixel.
pub const GBUFFER_BYTES_PER_PIXEL: u64 = 71;

/// Half-bytes the strip renderer holds a pixel of the picture: the 8-bit output (3 bytes) and
/// the PNG encoder's buffers (measured at under half a byte), 3.5 bytes in all.
const STRIP_HALF_BYTES_PER_PIXEL: u64 = 7;

/// Bytes a pixel of a strip G-buffer takes with the shading pass's own buffers: twice the 56
/// of a `relief_shade::GBufferPixel`.
const STRIP_GBUFFER_BYTES_PER_PIXEL: u64 = 112;

/// The memory an image of `width x height` takes while `holding` draws it with `threads`
/// threads (the terrain and the tracer's structures are counted apart).
///
/// The strip renderer's model against the peak resident set of `relief render g.npy` (a
/// 1201 x 1201 fBm terrain, mipmap tracer, 2 threads), less the 15.7 MB that a 16x9 render of
/// the same terrain peaks at (the program, the terrain and its pyramid): 4000x2250, model
/// 45.8 MB, measured 40.7 MB; 8000x4500, model 154.7 MB, measured 137.7 MB; 16000x9000, model
/// 561 MB, measured 497.5 MB; 32768x32768 (refused at 72704 MiB by the former flat 71 bytes
/// a pixel), model 3876 MB, measured 3384 MB.
pub fn image_bytes(width: u32, height: u32, holding: ImageHolding, threads: usize) -> u64 {
    let (w, pixels) = (u64::from(width), u64::from(width) * u64::from(height));
    match holding {
        ImageHolding::WholeGBuffer => pixels * GBUFFER_BYTES_PER_PIXEL,
        ImageHolding::Mlhm => pixels * MLHM_BYTES_PER_PIXEL,
        ImageHolding::Strips { depth, normals } => {
            let picture = pixels * STRIP_HALF_BYTES_PER_PIXEL / 2;
            let kept = pixels * (4 * u64::from(depth) + 12 * u64::from(normals));
            let strip_rows = (relief_shade::TILE_SIZE as u64).min(u64::from(height));
            let strips = threads as u64 * strip_rows * w * STRIP_GBUFFER_BYTES_PER_PIXEL;
            picture + kept + strips
        }
    }
}

/// The memory anti-aliasing adds to an image of `width x height` drawn with `aa`, beside what
/// its renderer holds for one picture ([`image_bytes`]): adaptive, the depth and normals of
/// the centre rays (16 bytes a pixel), the comparisons and the mask (3) and a pass's picture
/// (3); a grid, the sums of its samples in linear light (12) and a pass's picture beside the
/// kept one (3).
pub fn antialiasing_bytes(width: u32, height: u32, aa: crate::Antialiasing) -> u64 {
    let pixels = u64::from(width) * u64::from(height);
    match aa {
        crate::Antialiasing::Off | crate::Antialiasing::Grid(1) => 0,
        crate::Antialiasing::Adaptive => pixels * 22,
        crate::Antialiasing::Grid(_) => pixels * 15,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_read_in_the_unit_that_fits() {
        assert_eq!(format_bytes(1024), "1 KiB");
        assert_eq!(format_bytes(1536), "1.5 KiB");
        assert_eq!(format_bytes(100), "100 bytes");
        assert_eq!(format_bytes(12052 << 20), "12052 MiB");
    }

    #[test]
    fn strips_take_a_few_bytes_a_pixel_and_g_buffers_many() {
        let strips = ImageHolding::Strips { depth: false, normals: false };
        let big = image_bytes(32768, 32768, strips, 2);
        assert!(big < 4 << 30, "{big}");
        let both = ImageHolding::Strips { depth: true, normals: true };
        assert!(image_bytes(100, 100, both, 1) > image_bytes(100, 100, strips, 1));
        assert_eq!(image_bytes(10, 10, ImageHolding::WholeGBuffer, 8), 7100);
        assert_eq!(antialiasing_bytes(10, 10, crate::Antialiasing::Off), 0);
        assert!(antialiasing_bytes(10, 10, crate::Antialiasing::Adaptive) > 0);
    }

    #[test]
    fn the_default_budget_says_which_limit_applied() {
        let default = budget(None);
        assert_eq!(default.bytes, relief_io::default_memory_budget().bytes);
        assert!(default.origin.contains(&relief_io::default_memory_budget().source));
        assert!(default.origin.ends_with("raise it with --max-memory"), "{}", default.origin);
        assert_eq!(budget(Some(5)).origin, "--max-memory");
    }
}
