//! Output files: each is written in the format its extension names, and every output of a
//! command is checked before any work (its folder, its format, and that no two outputs, nor
//! an output and an input, are one file).

use crate::applies::extension;
use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};

/// The picture formats `-o` of `relief render` writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PictureFormat {
    /// 8-bit RGB PNG.
    Png,
    /// Baseline JPEG at [`relief_io::JPEG_QUALITY`].
    Jpeg,
}

/// The picture format `path` names by its extension; anything else is refused.
pub fn picture_format(option: &str, path: &Path) -> Result<PictureFormat> {
    match extension(path).as_deref() {
        Some("png") => Ok(PictureFormat::Png),
        Some("jpg" | "jpeg") => Ok(PictureFormat::Jpeg),
        _ => bail!("{option} {}: a picture is written as .png or .jpg (.jpeg)", path.display()),
    }
}

/// Writes the `width x height` RGB picture `rgb` to `path` in the format its extension names,
/// a PNG compressed as `png` says.
pub fn write_picture(
    path: &Path,
    width: u32,
    height: u32,
    rgb: &[u8],
    png: relief_io::PngCompression,
) -> Result<()> {
    match picture_format("-o", path)? {
        PictureFormat::Png => relief_io::write_png_rgb8_compressed(path, width, height, rgb, png)?,
        PictureFormat::Jpeg => relief_io::write_jpeg_rgb8(path, width, height, rgb)?,
    }
    Ok(())
}

/// Refuses an array output (`--depth`, `--normals`) that is not a `.npy` file.
pub fn check_npy(option: &str, path: &Path) -> Result<()> {
    if extension(path).as_deref() != Some("npy") {
        bail!(
            "{option} {}: it is written as a NumPy array, so its name must end in .npy",
            path.display()
        );
    }
    Ok(())
}

/// Refuses a height-file output whose extension names no format relief writes, or, for a grid
/// of `size` (width, height) where it is known, an SRTM tile of a size other than 1201 or
/// 3601 samples a side.
pub fn check_height_file(path: &Path, size: Option<(usize, usize)>) -> Result<()> {
    match (extension(path).as_deref(), size) {
        (Some("tif" | "tiff" | "asc" | "png" | "npy"), _) | (Some("hgt"), None) => Ok(()),
        (Some("hgt"), Some((width, height)))
            if width == height && (width == 1201 || width == 3601) =>
        {
            Ok(())
        }
        (Some("hgt"), Some((width, height))) => bail!(
            "output {}: an SRTM .hgt tile has 1201 x 1201 or 3601 x 3601 samples, not \
             {width} x {height}",
            path.display()
        ),
        (_, _) => bail!(
            "output {}: a height file is written as .tif/.tiff (float32 GeoTIFF), .asc, .png \
             (16-bit grey), .hgt or .npy",
            path.display()
        ),
    }
}

/// Refuses a `--stats` output that is not a `.json` file in an existing folder.
pub fn check_stats(path: &Path) -> Result<()> {
    check_writable(path)?;
    if extension(path).as_deref() != Some("json") {
        bail!("--stats {}: the statistics are written as .json", path.display());
    }
    Ok(())
}

/// Writes `stats` (stage timings as `*_ms` keys and counts) to `path` as pretty JSON: what
/// every command's `--stats` writes, after its work succeeded.
pub fn write_stats(path: &Path, stats: &serde_json::Value) -> Result<()> {
    let text = serde_json::to_string_pretty(stats).context("writing the stats")?;
    std::fs::write(path, text + "\n").with_context(|| format!("cannot write {}", path.display()))
}

/// Milliseconds since `start`.
pub fn ms_since(start: std::time::Instant) -> f64 {
    start.elapsed().as_secs_f64() * 1e3
}

/// Refuses an output path whose folder does not exist or that names a folder.
pub fn check_writable(path: &Path) -> Result<()> {
    if path.is_dir() {
        bail!("output {} is a directory", path.display());
    }
    let parent = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    if !parent.is_dir() {
        bail!("output folder {} does not exist", parent.display());
    }
    Ok(())
}

/// Refuses two of `outputs` (option, path) that name one file, and an output that is one of
/// `inputs`.
pub fn check_distinct(outputs: &[(&str, &Path)], inputs: &[&Path]) -> Result<()> {
    for (k, (option, path)) in outputs.iter().enumerate() {
        let key = identity(path);
        if let Some((other, _)) = outputs[..k].iter().find(|(_, p)| identity(p) == key) {
            bail!("{other} and {option} both write {}: give each its own file", path.display());
        }
        if inputs.iter().any(|input| identity(input) == key) {
            bail!("{option} {} would overwrite the input", path.display());
        }
    }
    Ok(())
}

/// The file `path` names, as one path however it is spelt (`./a.png`, `a.png`, a symlinked
/// folder): its folder resolved where it exists.
fn identity(path: &Path) -> PathBuf {
    let absolute = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    if let Ok(resolved) = absolute.canonicalize() {
        return resolved;
    }
    match (absolute.parent(), absolute.file_name()) {
        (Some(parent), Some(name)) => {
            parent.canonicalize().unwrap_or_else(|_| parent.to_path_buf()).join(name)
        }
        _ => absolute,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_follow_extensions() {
        assert_eq!(picture_format("-o", Path::new("a.PNG")).unwrap(), PictureFormat::Png);
        assert_eq!(picture_format("-o", Path::new("a.jpeg")).unwrap(), PictureFormat::Jpeg);
        assert!(picture_format("-o", Path::new("a.tif")).is_err());
        assert!(check_npy("--depth", Path::new("d.npy")).is_ok());
        assert!(check_npy("--depth", Path::new("d.png")).is_err());
        assert!(check_height_file(Path::new("N36W085.hgt"), Some((1201, 1201))).is_ok());
        assert!(check_height_file(Path::new("x.hgt"), Some((1024, 1024))).is_err());
        assert!(check_height_file(Path::new("x.hgt"), None).is_ok());
        assert!(check_height_file(Path::new("x.jpg"), None).is_err());
    }

    #[test]
    fn one_file_spelt_two_ways_is_one_output() {
        let a = Path::new("y.png");
        let b = Path::new("./y.png");
        let err = check_distinct(&[("-o", a), ("--depth", b)], &[]).unwrap_err().to_string();
        assert!(err.contains("-o and --depth"), "{err}");
        assert!(check_distinct(&[("-o", a)], &[b]).is_err());
        assert!(check_distinct(&[("-o", a), ("--depth", Path::new("y.npy"))], &[]).is_ok());
    }
}
