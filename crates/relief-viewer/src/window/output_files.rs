//! Where the viewer writes what it saves: numbered files in the output folder, so that a new
//! run does not overwrite an earlier one's.

use crate::frame::Frame;
use crate::ViewerError;
use std::path::{Path, PathBuf};

/// Writes `frame` (without the overlay) to `path`, or to the next free `relief-view-NNN.png`
/// of `output_dir`; returns where it went.
pub(crate) fn save_screenshot(
    frame: &Frame,
    path: Option<&Path>,
    output_dir: &Path,
) -> Result<PathBuf, ViewerError> {
    let path = match path {
        Some(p) => p.to_path_buf(),
        None => next_free(output_dir, "relief-view", "png"),
    };
    let rgb: Vec<u8> = frame.rgb.iter().flatten().copied().collect();
    relief_io::write_png_rgb8(&path, frame.width, frame.height, &rgb)?;
    eprintln!("saved {} ({}x{})", path.display(), frame.width, frame.height);
    Ok(path)
}

/// `dir/PREFIX-NNN.EXT` with the smallest number from 001 that names no file yet, so that
/// a new run does not overwrite the screenshots and paths of an earlier one.
pub(crate) fn next_free(dir: &Path, prefix: &str, extension: &str) -> PathBuf {
    (1u32..)
        .map(|n| dir.join(format!("{prefix}-{n:03}.{extension}")))
        .find(|path| !path.exists())
        .expect("a free number")
}
