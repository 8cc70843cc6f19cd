//! Anti-aliasing: several rays through each pixel, their colours averaged in linear light.
//!
//! `--aa N` samples every pixel at the N x N points of a stratified grid (the centres of its
//! N x N equal sub-squares: deterministic, so a picture is the same from run to run). The
//! default, [`Antialiasing::Adaptive`], traces one ray a pixel first, then samples again, on
//! a grid of [`ADAPTIVE_GRID`] x [`ADAPTIVE_GRID`], only the pixels whose depth, normal or
//! colour differs from a neighbour's ([`edges::edge_mask`]): silhouettes, box edges, creases,
//! shadow and material boundaries.
//!
//! Each sample of the grid is a pass of the camera sampling every pixel off its centre by the
//! same offset ([`Camera::with_pixel_offset`]), so memory stays that of one picture whatever
//! `N`. A renderer that traces rays draws only the marked pixels of an adaptive pass
//! ([`relief_shade::PixelMask`]); the rasterizing renderers and tile stores draw it whole.
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

/// The pixel offsets of an `n x n` stratified grid: the centres of the pixel's `n x n`
/// sub-squares, a row of them after another from the top left, each in `(-0.5, 0.5)`.
pub fn grid_offsets(n: u32) -> Vec<[f64; 2]> {
    let at = |k: u32| (k as f64 + 0.5) / n as f64 - 0.5;
    (0..n * n).map(|k| [at(k % n), at(k / n)]).collect()
}

/// The colours of `camera`'s picture sampled on an `n x n` grid: `draw` gives the colours of
/// the camera offset to each point of the grid in turn ([`grid_offsets`]), and they are
/// averaged in linear light. What `relief render --aa N` and `relief view` at rest draw.
pub fn grid_mean<E>(
    camera: &Camera,
    n: u32,
    mut draw: impl FnMut(&Camera) -> Result<Vec<[u8; 3]>, E>,
) -> Result<Vec<[u8; 3]>, E> {
    let offsets = grid_offsets(n);
    let mut sum = LinearSum::new(camera.width() as usize * camera.height() as usize);
    for &[dx, dy] in &offsets {
        let offset = camera.with_pixel_offset(dx, dy).expect("a grid's points lie in the pixel");
        sum.add_all(&draw(&offset)?);
    }
    Ok(sum.means(offsets.len()))
}

/// Every pixel sampled on an `n x n` grid: a pass for each offset of the grid (a pass of the
/// centres too, for the depth and normals, where they are asked for and the grid has no
/// centre), their colours averaged in linear light.
fn draw_grid(
    camera: &Camera,
    keep: KeptHits,
    n: u32,
    progress: &dyn Progress,
    pass: &mut Pass,
) -> Result<Picture, RenderError> {
    let offsets = grid_offsets(n);
    let has_centre = offsets.contains(&[0.0, 0.0]);
    let wants_centre = keep.depth || keep.normals;
    // The picture whose statistics, depth and normals are kept: the centre pass's where there
    // is one, else the first pass's.
    let mut kept =
        if wants_centre && !has_centre { Some(pass(camera, keep, None, progress)?) } else { None };
    let started = Instant::now();
    progress.begin("anti-aliasing", Some(offsets.len() as u64));
    let rgb: Result<_, RenderError> = grid_mean(camera, n, |offset_camera| {
        let is_centre = offset_camera.pixel_offset() == [0.0, 0.0];
        let asked = if is_centre { keep } else { KeptHits::default() };
        let mut sample = pass(offset_camera, asked, None, &Silent)?;
        progress.advance(1);
        let rgb = std::mem::take(&mut sample.rgb);
        if is_centre || kept.is_none() {
            kept = Some(sample);
        }
        Ok(rgb)
    });
    progress.end();
    let rgb = rgb?;
    let mut picture = kept.expect("a grid has a pass");
    picture.rgb = rgb;
    let samples = picture.rgb.len() as u64 * offsets.len() as u64;
    record(&mut picture, Antialiasing::Grid(n), samples, ms_since(started), None);
    Ok(picture)
}

/// One ray a pixel, then a pass for each offset of the 2 x 2 grid, of the pixels on an edge
/// only, whose four samples replace their colour.
fn draw_adaptive(
    camera: &Camera,
    keep: KeptHits,
    progress: &dyn Progress,
    pass: &mut Pass,
) -> Result<Picture, RenderError> {
    let mut picture = pass(camera, KeptHits { depth: true, normals: true }, None, progress)?;
    let started = Instant::now();
    let edges = edges::edge_mask(&picture);
    let marked = edges.indices();
    if !marked.is_empty() {
        let offsets = grid_offsets(ADAPTIVE_GRID);
        // The sums of the marked pixels only, the m-th at m.
        let mut sum = LinearSum::new(marked.len());
        progress.begin("anti-aliasing", Some(offsets.len() as u64));
        for &[dx, dy] in &offsets {
            let camera = camera.with_pixel_offset(dx, dy)?;
            let sample = pass(&camera, KeptHits::default(), Some(&edges), &Silent)?;
            marked.iter().enumerate().for_each(|(m, &k)| sum.add(m, sample.rgb[k]));
            progress.advance(1);
        }
        progress.end();
        for (m, &k) in marked.iter().enumerate() {
            picture.rgb[k] = sum.mean(m, offsets.len());
        }
    }
    picture.depth = picture.depth.filter(|_| keep.depth);
    picture.normals = picture.normals.filter(|_| keep.normals);
    let samples = (marked.len() as u64) * u64::from(ADAPTIVE_GRID * ADAPTIVE_GRID);
    let share = marked.len() as f64 / picture.rgb.len() as f64;
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

/// Sums of pixels' colours in linear light, over the passes of a picture.
struct LinearSum {
    sums: Vec<[f32; 3]>,
}

impl LinearSum {
    /// Sums of `pixels` pixels, all zero.
    fn new(pixels: usize) -> Self {
        LinearSum { sums: vec![[0.0; 3]; pixels] }
    }

    /// Adds the sRGB colour `rgb` to pixel `k`'s sum.
    #[inline]
    fn add(&mut self, k: usize, rgb: [u8; 3]) {
        let linear = srgb8_to_linear_table();
        (0..3).for_each(|c| self.sums[k][c] += linear[rgb[c] as usize]);
    }

    /// Adds a pass's colours, pixel by pixel.
    fn add_all(&mut self, rgb: &[[u8; 3]]) {
        let linear = srgb8_to_linear_table();
        self.sums.par_iter_mut().zip(rgb).for_each(|(sum, p)| {
            (0..3).for_each(|c| sum[c] += linear[p[c] as usize]);
        });
    }

    /// The mean of `n` colours summed at pixel `k`, in sRGB.
    #[inline]
    fn mean(&self, k: usize, n: usize) -> [u8; 3] {
        self.sums[k].map(|s| linear_to_srgb8(s / n as f32))
    }

    /// The means of `n` colours summed at every pixel, in sRGB.
    fn means(&self, n: usize) -> Vec<[u8; 3]> {
        self.sums.par_iter().map(|s| s.map(|s| linear_to_srgb8(s / n as f32))).collect()
    }
}
