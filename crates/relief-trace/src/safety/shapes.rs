//! Precomputed safety shapes of a height field: one radius and cone plane per texel and ray
//! class (or one per texel, isotropic), built in parallel and looked up while marching.

use super::frame::{Frame, LocalField, RayClass};
use super::limiting::{LimitingTest, SlopeBound};
use super::options::{ConeMode, SafetyOptions, ShapeLayout};
use super::precompute::{ClassPrecompute, TexelShape};
use crate::TraceError;
use rayon::prelude::*;
use relief_core::HeightField;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Reports precomputation progress: `(texels done, texels in all)`.
pub type Progress<'a> = &'a (dyn Fn(usize, usize) + Sync);

/// The safety shapes of one height field (Baboud et al. 2011, sections 6 and 7).
///
/// For every texel and ray class: a safety radius `r` (an integer number of x-centerlines over
/// which no ray of the class, passing above the texel's centerline segment, can cross the
/// surface twice) and, with cones, a plane `z0 + slope * x` above every limiting triangle past
/// `r`. Stored in grid layout (`col + row * width`), per class or isotropic.
#[derive(Debug, Clone, PartialEq)]
pub struct SafetyShapes {
    width: usize,
    height: usize,
    options: SafetyOptions,
    /// One array per class (four), or one for all (isotropic).
    radii: Vec<Vec<u16>>,
    /// Cone planes `(z0, slope)`, rounded up; one array per entry of `radii`, or none.
    cones: Vec<Vec<[f32; 2]>>,
}

impl SafetyShapes {
    /// Precomputes the shapes of `field`'s `triangles` surface with `options`, in parallel,
    /// reporting progress.
    pub fn build(
        field: &HeightField,
        options: SafetyOptions,
        progress: Progress,
    ) -> Result<Self, TraceError> {
        options.validate().map_err(TraceError::Options)?;
        if field.hole_count() > 0 {
            return Err(TraceError::Unsupported(
                "safety shapes need a height field without voids (fill them: --voids fill)".into(),
            ));
        }
        let (width, height) = (field.width(), field.height());
        let samples = field.samples();
        let geometry = field.geometry();
        let total = 4 * width * height;
        let done = AtomicUsize::new(0);
        let mut per_class: Vec<Vec<TexelShape>> = Vec::with_capacity(4);
        for class in RayClass::ALL {
            let frame = Frame::new(class, width, height);
            let local = LocalField::new(frame, samples);
            let (step_x, step_y) = match class {
                RayClass::XPos | RayClass::XNeg => (geometry.dx, geometry.dy),
                RayClass::YPos | RayClass::YNeg => (geometry.dy, geometry.dx),
            };
            let slope = options.max_slope().map(|max_slope| SlopeBound {
                max_slope,
                step_x,
                step_y,
                z_scale: geometry.z_scale,
            });
            let exterior = options.rays == super::options::RaySet::Exterior;
            let mut shapes = vec![TexelShape::cylinder(options.reach); width * height];
            if width > 1 && height > 1 {
                let pre = ClassPrecompute::new(LimitingTest::new(local, exterior, slope), options);
                let (lw, lh) = (local.width(), local.height());
                let columns: Vec<Vec<TexelShape>> = (0..lw)
                    .into_par_iter()
                    .map(|i| {
                        let column = (0..lh).map(|j| pre.texel(i, j)).collect();
                        progress(done.fetch_add(lh, Ordering::Relaxed) + lh, total);
                        column
                    })
                    .collect();
                for (i, column) in columns.into_iter().enumerate() {
                    for (j, shape) in column.into_iter().enumerate() {
                        shapes[frame.grid_index(i, j)] = shape;
                    }
                }
            } else {
                progress(done.fetch_add(width * height, Ordering::Relaxed), total);
            }
            per_class.push(shapes);
        }
        if options.layout == ShapeLayout::Isotropic {
            per_class = vec![isotropic(&per_class, options.reach)];
        }
        let has_cones = options.cone != ConeMode::None;
        let radii = per_class.iter().map(|c| c.iter().map(|s| s.radius).collect()).collect();
        let cones = if has_cones {
            per_class
                .iter()
                .map(|c| c.iter().map(|s| [round_up(s.z0), round_up(s.slope)]).collect())
                .collect()
        } else {
            Vec::new()
        };
        Ok(SafetyShapes { width, height, options, radii, cones })
    }

    /// The options the shapes were built with.
    pub fn options(&self) -> &SafetyOptions {
        &self.options
    }

    /// Samples along x of the field the shapes belong to.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Samples along y of the field the shapes belong to.
    pub fn height(&self) -> usize {
        self.height
    }

    /// Bytes that building shapes with `options` for a `width x height` field takes at its
    /// peak: the shapes themselves and one class's working data (N-buffer, per-texel results).
    /// Exterior visibility keeps a few line sets per triangle on top of this.
    pub fn memory_estimate(width: usize, height: usize, options: &SafetyOptions) -> u64 {
        let texels = (width * height) as u64;
        let slots = if options.layout == ShapeLayout::Isotropic { 1 } else { 4 };
        let per_texel = if options.cone == ConeMode::None { 2 } else { 10 };
        let levels = usize::BITS as u64 - width.max(height).leading_zeros() as u64;
        let nbuffer = if options.cone == ConeMode::None { 0 } else { 4 * levels * texels };
        let working = 4 * 24 * texels + nbuffer;
        slots * per_texel * texels + working
    }

    /// Bytes the shapes occupy.
    pub fn memory_bytes(&self) -> usize {
        self.radii.iter().map(|r| r.len() * 2).sum::<usize>()
            + self.cones.iter().map(|c| c.len() * 8).sum::<usize>()
    }

    /// The mean safety radius over all texels and classes (a summary for reports).
    pub fn mean_radius(&self) -> f64 {
        let n: usize = self.radii.iter().map(Vec::len).sum();
        let sum: u64 = self.radii.iter().flatten().map(|&r| r as u64).sum();
        sum as f64 / n.max(1) as f64
    }

    /// How many x-centerlines a ray of `class` may advance from texel `grid_index`, where it is
    /// at height `z` (sample units) and climbs `dz` per centerline.
    #[inline]
    pub fn step(&self, class: RayClass, grid_index: usize, z: f64, dz: f64) -> u32 {
        let slot = if self.radii.len() == 1 { 0 } else { class.index() };
        let radius = self.radii[slot][grid_index] as u32;
        let Some(cones) = self.cones.get(slot) else { return radius };
        let [z0, slope] = cones[grid_index].map(f64::from);
        let reach = self.options.reach as u32;
        if z <= z0 {
            // Not above the cone's plane: only the cylinder is safe.
            return radius;
        }
        if slope <= dz {
            // Above the plane and climbing at least as fast: it stays above within the reach.
            return reach;
        }
        // Above the plane for `steps` more centerlines.
        let steps = (z - z0) / (slope - dz);
        if steps >= reach as f64 {
            reach
        } else if steps > 0.0 {
            (steps as u32).max(radius)
        } else {
            radius
        }
    }

    /// The raw parts, for serialisation: radii and cone planes per class slot.
    pub(crate) fn parts(&self) -> (&[Vec<u16>], &[Vec<[f32; 2]>]) {
        (&self.radii, &self.cones)
    }

    /// Reassembles shapes from their parts (see [`SafetyShapes::parts`]).
    pub(crate) fn from_parts(
        width: usize,
        height: usize,
        options: SafetyOptions,
        radii: Vec<Vec<u16>>,
        cones: Vec<Vec<[f32; 2]>>,
    ) -> Self {
        SafetyShapes { width, height, options, radii, cones }
    }
}

/// One shape per texel safe for every class (Fig. 28 a, b): the smallest radius, and a plane
/// above every class's plane wherever that class's plane matters (past its own radius).
fn isotropic(per_class: &[Vec<TexelShape>], reach: u16) -> Vec<TexelShape> {
    (0..per_class[0].len())
        .map(|k| {
            let shapes = per_class.iter().map(|c| c[k]);
            let radius = shapes.clone().map(|s| s.radius).min().unwrap_or(reach);
            // Classes with a real cone constrain it; the others have no limiting triangle
            // within the reach (radius = reach) or nothing past their radius (slope -inf).
            let coned = shapes.filter(|s| s.radius < reach && s.slope.is_finite());
            let slope = coned.clone().map(|s| s.slope).fold(f64::NEG_INFINITY, f64::max);
            let z0 = coned
                .map(|s| s.z0 + (s.slope - slope) * s.radius as f64)
                .fold(f64::NEG_INFINITY, f64::max);
            if radius == reach {
                TexelShape::cylinder(reach)
            } else {
                TexelShape { radius, z0, slope }
            }
        })
        .collect()
}

/// The smallest `f32` at least `x` (infinities stay infinite).
fn round_up(x: f64) -> f32 {
    let f = x as f32;
    if (f as f64) < x {
        f32::from_bits(if f >= 0.0 { f.to_bits() + 1 } else { f.to_bits() - 1 })
    } else {
        f
    }
}
