//! Anti-aliasing: several rays through each pixel, their colours averaged in linear light.
//!
//! `--aa N` samples every pixel at the N x N points of a stratified grid (the centres of its
//! N x N equal sub-squares: deterministic, so a picture is the same from run to run). The
//! default, [`Antialiasing::Adaptive`], traces one ray a pixel first, then samples again, on
//! a grid of [`ADAPTIVE_GRID`] x [`ADAPTIVE_GRID`], only the pixels whose depth, normal or
//! colour differs from a neighbour's ([`edges::edge_mask`]): silhouettes, box edges, creases,
//! shadow and material boundaries.
//!
//! The samples of a grid are the pixels of one camera `N` times finer (its pixel `(N i + a,
//! N j + b)` looks through the centre of sub-square `(a, b)` of pixel `(i, j)`), drawn in one
//! pass, so that a pixel's samples are traced together. A renderer that traces rays draws
//! only the marked pixels of that pass ([`relief_shade::PixelMask`]); the rasterizing
//! renderers draw it whole.
//!
//! The depth and normals a picture keeps are always those of the ray through each pixel's
//! centre, so they stay exact.

pub mod edges;

use crate::draw::picture::{ms_since, Picture};
use crate::error::RenderError;
use crate::progress::{Progress, Silent};
use rayon::prelude::*;
use relief_core::colour::{linear_to_srgb8, srgb8_to_linear_table};
use relief_core::Camera;
use relief_shade::{KeptHits, PixelMask};
use serde_json::json;
use std::fmt;
use std::str::FromStr;
use std::time::Instant;

/// The side of the grid of samples the adaptive default takes in a pixel on an edge.
pub const ADAPTIVE_GRID: u32 = 2;

/// The largest `N` of `--aa N`.
pub const MAX_GRID: u32 = 8;

/// How a picture's pixels are sampled.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Antialiasing {
    /// One ray through each pixel's centre (`--aa off`, or `--aa 1`).
    Off,
    /// `N x N` rays through every pixel, at the centres of its `N x N` sub-squares (`--aa N`).
    Grid(u32),
    /// One ray through each pixel's centre, then [`ADAPTIVE_GRID`]² through each pixel whose
    /// depth, normal or colour differs from a neighbour's, which they replace (`--aa
    /// adaptive`, the default).
    #[default]
    Adaptive,
}

impl FromStr for Antialiasing {
    type Err = String;

    /// `off`, `adaptive`, or the side `N` of the sample grid, 1 to [`MAX_GRID`] (1 is off).
    fn from_str(text: &str) -> Result<Self, String> {
        match text.trim() {
            "off" => Ok(Antialiasing::Off),
            "adaptive" => Ok(Antialiasing::Adaptive),
            n => match n.parse::<u32>() {
                Ok(1) => Ok(Antialiasing::Off),
                Ok(n) if (2..=MAX_GRID).contains(&n) => Ok(Antialiasing::Grid(n)),
                _ => Err(format!(
                    "anti-aliasing '{text}' is none of off, adaptive, or a grid side N from 1 \
                     to {MAX_GRID} (N x N samples a pixel)"
                )),
            },
        }
    }
}

impl fmt::Display for Antialiasing {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Antialiasing::Off => write!(f, "off"),
            Antialiasing::Grid(n) => write!(f, "{n}x{n} samples a pixel"),
            Antialiasing::Adaptive => {
                write!(f, "adaptive (4 samples a pixel at edges)")
            }
        }
    }
}

/// A renderer's pass: the picture of a camera, keeping the depth and normals asked for, of
/// the marked pixels only where a mask is given and the renderer can draw so, reporting its
/// progress to the given [`Progress`].
pub(crate) type Pass<'a> = dyn FnMut(&Camera, KeptHits, Option<&PixelMask>, &dyn Progress) -> Result<Picture, RenderError>
    + 'a;

/// The picture of `camera` anti-aliased as `aa` says, each of its passes drawn by `pass`.
/// The depth and normals `keep` asks for are the centre rays'. The picture's statistics tell
/// the samples taken and the time the extra passes took.
pub(crate) fn draw(
    camera: &Camera,
    keep: KeptHits,
    aa: Antialiasing,
    progress: &dyn Progress,
    pass: &mut Pass,
) -> Result<Picture, RenderError> {
    match aa {
        Antialiasing::Off | Antialiasing::Grid(1) => {
            let mut picture = pass(camera, keep, None, progress)?;
            record(&mut picture, aa, 0, 0.0, None);
            Ok(picture)
        }
        Antialiasing::Grid(n) => draw_grid(camera, keep, n, progress, pass),
        Antialiasing::Adaptive => draw_adaptive(camera, keep, progress, pass),
    }
}

/// `camera` with `n` times its pixels across and down: its pixel `(n i + a, n j + b)` looks
/// through the centre of sub-square `(a, b)` of the `n x n` sub-squares of `camera`'s pixel
/// `(i, j)`, so a pass of it is a pass of `camera` on the stratified grid.
fn finer(camera: &Camera, n: u32) -> Result<Camera, RenderError> {
    let (width, height) = (camera.width() * n, camera.height() * n);
    let (eye, target, up) = (camera.eye(), camera.target(), camera.up());
    Ok(Camera::new(eye, target, up, camera.projection(), width, height)?)
}

/// Every pixel sampled on an `n x n` grid (one pass of the camera `n` times finer, averaged
/// down); the depth and normals come from a pass of the centre rays, where they are asked for.
fn draw_grid(
    camera: &Camera,
    keep: KeptHits,
    n: u32,
    progress: &dyn Progress,
    pass: &mut Pass,
) -> Result<Picture, RenderError> {
    let wants_centre = keep.depth || keep.normals;
    let centre = if wants_centre { Some(pass(camera, keep, None, progress)?) } else { None };
    let started = Instant::now();
    progress.begin("anti-aliasing", None);
    let fine = pass(&finer(camera, n)?, KeptHits::default(), None, &Silent);
    progress.end();
    let fine = fine?;
    let (w, h) = (camera.width() as usize, camera.height() as usize);
    let mut picture = centre.unwrap_or_else(|| {
        // The statistics of the finer pass, of this picture's size.
        let mut picture = Picture { width: w as u32, height: h as u32, ..fine.clone() };
        picture.stats.insert("width".into(), json!(w));
        picture.stats.insert("height".into(), json!(h));
        picture
    });
    let side = n as usize;
    let mean = |k| sub_pixel_mean(&fine.rgb, w, side, k);
    picture.rgb = (0..w * h).into_par_iter().map(mean).collect();
    let samples = fine.rgb.len() as u64;
    let ms = ms_since(started);
    record(&mut picture, Antialiasing::Grid(n), samples, ms, None);
    Ok(picture)
}

/// One ray a pixel, then the 2 x 2 grid of each pixel on an edge, which replaces it (one
/// pass of the camera twice as fine, of the sub-pixels of the edge pixels only).
fn draw_adaptive(
    camera: &Camera,
    keep: KeptHits,
    progress: &dyn Progress,
    pass: &mut Pass,
) -> Result<Picture, RenderError> {
    let mut picture = pass(camera, KeptHits { depth: true, normals: true }, None, progress)?;
    let started = Instant::now();
    let edges = edges::edge_mask(&picture);
    let marked = edges.count();
    if marked > 0 {
        let (w, n) = (picture.width as usize, ADAPTIVE_GRID as usize);
        progress.begin("anti-aliasing", None);
        let fine_camera = finer(camera, ADAPTIVE_GRID)?;
        let fine = pass(&fine_camera, KeptHits::default(), Some(&edges.finer(n)), &Silent);
        progress.end();
        let fine = fine?;
        picture.rgb.par_iter_mut().enumerate().for_each(|(k, rgb)| {
            if edges.contains(k % w, k / w) {
                *rgb = sub_pixel_mean(&fine.rgb, w, n, k);
            }
        });
    }
    picture.depth = picture.depth.filter(|_| keep.depth);
    picture.normals = picture.normals.filter(|_| keep.normals);
    let samples = marked as u64 * u64::from(ADAPTIVE_GRID * ADAPTIVE_GRID);
    let share = marked as f64 / picture.rgb.len() as f64;
    record(&mut picture, Antialiasing::Adaptive, samples, ms_since(started), Some(share));
    Ok(picture)
}

/// Notes in `picture`'s statistics how it was anti-aliased: the mode, the extra samples, the
/// time they took and, for the adaptive mode, the share of pixels sampled again.
fn record(picture: &mut Picture, aa: Antialiasing, samples: u64, ms: f64, share: Option<f64>) {
    let stats = &mut picture.stats;
    stats.insert("antialiasing".into(), json!(aa.to_string()));
    stats.insert("aa_samples".into(), json!(samples));
    stats.insert("aa_ms".into(), json!(ms));
    if let Some(share) = share {
        stats.insert("aa_edge_share".into(), json!(share));
    }
}

/// The mean colour, in linear light, of the `n x n` sub-pixels of pixel `k` of a picture
/// `width` pixels wide, in the picture `fine` of its camera `n` times finer.
fn sub_pixel_mean(fine: &[[u8; 3]], width: usize, n: usize, k: usize) -> [u8; 3] {
    let linear = srgb8_to_linear_table();
    let (i, j) = (k % width * n, k / width * n);
    let mut sum = [0.0f32; 3];
    for s in 0..n * n {
        let rgb = fine[i + s % n + (j + s / n) * width * n];
        (0..3).for_each(|c| sum[c] += linear[rgb[c] as usize]);
    }
    sum.map(|v| linear_to_srgb8(v / (n * n) as f32))
}
