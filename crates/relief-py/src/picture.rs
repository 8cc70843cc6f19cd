//! A picture the scene layer drew, handed to Python: the RGB image and its depth as NumPy
//! arrays; and the memory check an image passes before it is drawn.

use crate::arrays::{image_f32, image_rgb8};
use crate::errors::invalid;
use numpy::{PyArray2, PyArray3};
use pyo3::prelude::*;
use relief_render::memory::{self, format_bytes, ImageHolding};
use relief_render::{Antialiasing, Picture};

/// What a render returns: the RGB image and its depth.
pub type Rendered<'py> = (Bound<'py, PyArray3<u8>>, Bound<'py, PyArray2<f32>>);

/// `picture` as `(rgb, depth)`: uint8 (height, width, 3) and float32 (height, width), row 0
/// the top row; the depth +inf where nothing was hit.
pub fn arrays(py: Python<'_>, picture: Picture) -> PyResult<Rendered<'_>> {
    let (w, h) = (picture.width as usize, picture.height as usize);
    let depth = picture.depth.unwrap_or_else(|| vec![f32::INFINITY; w * h]);
    let rgb = picture.rgb.into_flattened();
    Ok((image_rgb8(py, h, w, rgb)?, image_f32(py, h, w, depth)?))
}

/// Refuses an image of `width x height` pixels that `holding` would draw, anti-aliased as `aa`
/// says, over the memory budget `max_memory` gives (default: half the machine's memory), with
/// the command line's message; `raise_with` names the option that raises the budget, if the
/// caller has one.
pub fn check_image(
    width: u32,
    height: u32,
    holding: ImageHolding,
    aa: Antialiasing,
    max_memory: Option<u64>,
    raise_with: Option<&str>,
) -> PyResult<()> {
    let budget = memory::budget(max_memory);
    let threads = rayon::current_num_threads();
    let needed = memory::image_bytes(width, height, holding, threads)
        + memory::antialiasing_bytes(width, height, aa);
    if needed > budget.bytes {
        return Err(invalid(format!(
            "a {width}x{height} image needs {}, over the {} memory limit ({})",
            format_bytes(needed),
            format_bytes(budget.bytes),
            match raise_with {
                Some(option) => budget.origin.replace("--max-memory", option),
                None => budget.origin.replace("; raise it with --max-memory", ""),
            }
        )));
    }
    Ok(())
}
