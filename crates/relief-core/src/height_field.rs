//! The height field: a grid of elevation samples placed in the world.

use crate::{Aabb, CoreError, Ray, SampleRegion, Surface};
use glam::{DVec2, DVec3};

/// Where a grid sits in the world: horizontal spacing, origin and vertical scale.
///
/// Texel (col, row) covers `[col, col+1) x [row, row+1)` in grid units; its sample sits at the
/// world point `(origin.x + (col + 0.5) * dx, origin.y + (row + 0.5) * dy, value * z_scale)`.
/// Row 0 is the southernmost row.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridGeometry {
    /// World size of a texel along x (east), > 0.
    pub dx: f64,
    /// World size of a texel along y (north), > 0.
    pub dy: f64,
    /// World z of a sample = value * z_scale; > 0.
    pub z_scale: f64,
    /// World (x, y) of the grid's south-west corner.
    pub origin: DVec2,
}

impl GridGeometry {
    /// Spacing 1, scale 1, origin at zero.
    pub fn unit() -> Self {
        GridGeometry { dx: 1.0, dy: 1.0, z_scale: 1.0, origin: DVec2::ZERO }
    }

    /// Checks that every value is finite and spacings and scale are positive.
    pub fn validate(&self) -> Result<(), CoreError> {
        let positive = |name: &'static str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(CoreError::Parameter {
                    name,
                    reason: format!("{v} is not a finite number > 0"),
                })
            }
        };
        positive("spacing dx", self.dx)?;
        positive("spacing dy", self.dy)?;
        positive("z scale", self.z_scale)?;
        if !self.origin.is_finite() {
            return Err(CoreError::Parameter {
                name: "origin",
                reason: format!("{} is not finite", self.origin),
            });
        }
        Ok(())
    }

    /// Maps a world ray into grid space: x, y in texel units from the grid corner, z in sample
    /// units. The parameter `t` means the same point in both spaces.
    #[inline]
    pub fn ray_to_grid(&self, ray: &Ray) -> Ray {
        self.ray_to_grid_scaled(ray, self.grid_scale())
    }

    /// The world-to-grid scale `1 / (dx, dy, z_scale)`, for [`GridGeometry::ray_to_grid_scaled`].
    pub fn grid_scale(&self) -> DVec3 {
        DVec3::new(1.0 / self.dx, 1.0 / self.dy, 1.0 / self.z_scale)
    }

    /// [`GridGeometry::ray_to_grid`] with the scale from [`GridGeometry::grid_scale`] kept by
    /// the caller: the same numbers without dividing for every ray.
    #[inline]
    pub fn ray_to_grid_scaled(&self, ray: &Ray, scale: DVec3) -> Ray {
        Ray {
            origin: (ray.origin - self.origin.extend(0.0)) * scale,
            dir: ray.dir * scale,
            t_min: ray.t_min,
            t_max: ray.t_max,
        }
    }

    /// Maps a grid-space point to the world.
    #[inline]
    pub fn point_to_world(&self, p: DVec3) -> DVec3 {
        DVec3::new(p.x * self.dx, p.y * self.dy, p.z * self.z_scale) + self.origin.extend(0.0)
    }

    /// Maps a grid-space surface normal to a unit world normal.
    #[inline]
    pub fn normal_to_world(&self, n: DVec3) -> DVec3 {
        DVec3::new(n.x / self.dx, n.y / self.dy, n.z / self.z_scale).normalize()
    }
}

/// A rectangular grid of finite elevation samples, row 0 southernmost, with its geometry.
///
/// Samples are stored as `f32`, row-major (`index = col + row * width`). A field may have
/// holes (voids of the source data kept as empty texels, see [`HeightField::with_holes`]):
/// no surface stands above or around them, and their stored value is the lowest valid sample.
#[derive(Debug, Clone, PartialEq)]
pub struct HeightField {
    width: usize,
    height: usize,
    samples: Vec<f32>,
    holes: Option<Vec<bool>>,
    geometry: GridGeometry,
    min: f32,
    max: f32,
}

impl HeightField {
    /// Builds a height field, checking that the grid is non-empty, the sample count matches,
    /// every sample is finite and the geometry is valid.
    pub fn new(
        width: usize,
        height: usize,
        samples: Vec<f32>,
        geometry: GridGeometry,
    ) -> Result<Self, CoreError> {
        if width == 0 || height == 0 {
            return Err(CoreError::Grid(format!("{width} x {height} has no samples")));
        }
        if width.checked_mul(height) != Some(samples.len()) {
            return Err(CoreError::Grid(format!(
                "{width} x {height} needs {} samples, got {}",
                width as u128 * height as u128,
                samples.len()
            )));
        }
        geometry.validate()?;
        let (mut min, mut max) = (f32::INFINITY, f32::NEG_INFINITY);
        for (i, &v) in samples.iter().enumerate() {
            if !v.is_finite() {
                return Err(CoreError::NonFiniteSample {
                    col: i % width,
                    row: i / width,
                    value: v,
                });
            }
            min = min.min(v);
            max = max.max(v);
        }
        Ok(HeightField { width, height, samples, holes: None, geometry, min, max })
    }

    /// The same field with the texels flagged in `holes` (row-major, one flag per sample) kept
    /// empty. The value range then covers the other samples only. Fails when the mask's length
    /// does not match or when every sample is a hole.
    pub fn with_holes(mut self, holes: Vec<bool>) -> Result<Self, CoreError> {
        if holes.len() != self.samples.len() {
            return Err(CoreError::Grid(format!(
                "hole mask has {} flags for {} samples",
                holes.len(),
                self.samples.len()
            )));
        }
        let valid = || self.samples.iter().zip(&holes).filter(|(_, &h)| !h).map(|(&v, _)| v);
        let min = valid().fold(f32::INFINITY, f32::min);
        let max = valid().fold(f32::NEG_INFINITY, f32::max);
        if min > max {
            return Err(CoreError::Grid("every sample is a hole".into()));
        }
        for (v, _) in self.samples.iter_mut().zip(&holes).filter(|(_, &h)| h) {
            *v = min;
        }
        self.holes = holes.contains(&true).then_some(holes);
        self.min = min;
        self.max = max;
        Ok(self)
    }

    /// The same field standing on a solid that reaches down to `floor` instead of its lowest
    /// sample: a piece of a larger terrain (a tile of relief-tiles) keeps the whole terrain's
    /// bottom, so that the pieces' solids join into the whole one. [`HeightField::min_sample`]
    /// is then `floor`. Fails when `floor` is not finite or lies above the lowest sample.
    pub fn with_floor(mut self, floor: f32) -> Result<Self, CoreError> {
        if !floor.is_finite() || floor > self.min {
            return Err(CoreError::Grid(format!(
                "floor {floor} must be finite and at most the lowest sample {}",
                self.min
            )));
        }
        self.min = floor;
        Ok(self)
    }

    /// Whether texel (col, row) is a hole. Panics if out of range.
    #[inline]
    pub fn is_hole(&self, col: usize, row: usize) -> bool {
        self.holes.as_ref().is_some_and(|h| h[col + row * self.width])
    }

    /// The hole flags, row-major, or `None` when the field has no holes.
    pub fn holes(&self) -> Option<&[bool]> {
        self.holes.as_deref()
    }

    /// Number of holes.
    pub fn hole_count(&self) -> usize {
        self.holes.as_ref().map_or(0, |h| h.iter().filter(|&&x| x).count())
    }

    /// Number of columns.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Number of rows.
    pub fn height(&self) -> usize {
        self.height
    }

    /// The sample at (col, row). Panics if out of range.
    #[inline]
    pub fn sample(&self, col: usize, row: usize) -> f32 {
        self.samples[col + row * self.width]
    }

    /// All samples, row-major, row 0 southernmost.
    pub fn samples(&self) -> &[f32] {
        &self.samples
    }

    /// Rewrites the samples of `region` (clamped to the grid): sample (col, row) becomes
    /// `edit(col, row, old)`. Holes stay holes and keep their value. The new values are checked
    /// before any is written, so a non-finite one fails the edit and leaves the field as it was.
    /// Returns the region actually changed (the clamped one); the value range follows the edit.
    pub fn edit_region(
        &mut self,
        region: SampleRegion,
        mut edit: impl FnMut(usize, usize, f32) -> f32,
    ) -> Result<SampleRegion, CoreError> {
        let region = region.clamped(self.width, self.height);
        let mut values = Vec::with_capacity(region.len());
        // The range of the valid samples before and after, over the region.
        let (mut old_range, mut new_range) =
            ((f32::INFINITY, f32::NEG_INFINITY), (f32::INFINITY, f32::NEG_INFINITY));
        for row in region.row0..region.row1 {
            for col in region.col0..region.col1 {
                let old = self.sample(col, row);
                if self.is_hole(col, row) {
                    values.push(old);
                    continue;
                }
                let new = edit(col, row, old);
                if !new.is_finite() {
                    return Err(CoreError::NonFiniteSample { col, row, value: new });
                }
                old_range = (old_range.0.min(old), old_range.1.max(old));
                new_range = (new_range.0.min(new), new_range.1.max(new));
                values.push(new);
            }
        }
        let mut values = values.into_iter();
        for row in region.row0..region.row1 {
            let start = region.col0 + row * self.width;
            let end = region.col1 + row * self.width;
            self.samples[start..end].iter_mut().for_each(|v| *v = values.next().unwrap_or(*v));
        }
        if old_range.0 > self.min && old_range.1 < self.max {
            // The range's ends lie outside the region: only the new values can move them.
            let lowest = self.min;
            self.min = self.min.min(new_range.0);
            self.max = self.max.max(new_range.1);
            if let Some(holes) = self.holes.as_ref().filter(|_| self.min != lowest) {
                let min = self.min;
                for (v, _) in self.samples.iter_mut().zip(holes).filter(|(_, &h)| h) {
                    *v = min;
                }
            }
        } else {
            self.update_range();
        }
        Ok(region)
    }

    /// Replaces every sample at once (a simulation step that rewrites the whole field) and
    /// returns the previous samples, so that a caller can write the next step into them.
    /// Fails, leaving the field unchanged, when the count does not match or a value is not
    /// finite. Holes stay holes: their new values are replaced by the lowest valid sample.
    pub fn replace_samples(&mut self, mut samples: Vec<f32>) -> Result<Vec<f32>, CoreError> {
        if samples.len() != self.samples.len() {
            return Err(CoreError::Grid(format!(
                "{} x {} needs {} samples, got {}",
                self.width,
                self.height,
                self.samples.len(),
                samples.len()
            )));
        }
        let range = finite_range(&samples);
        if range.is_none() {
            if let Some(i) = samples.iter().position(|v| !v.is_finite()) {
                let (col, row) = (i % self.width, i / self.width);
                return Err(CoreError::NonFiniteSample { col, row, value: samples[i] });
            }
        }
        std::mem::swap(&mut self.samples, &mut samples);
        match (range, &self.holes) {
            (Some((min, max)), None) => (self.min, self.max) = (min, max),
            _ => self.update_range(),
        }
        Ok(samples)
    }

    /// Recomputes the value range after samples changed, and sets holes to its minimum.
    fn update_range(&mut self) {
        let (mut min, mut max) = (f32::INFINITY, f32::NEG_INFINITY);
        match &self.holes {
            None => {
                for &v in &self.samples {
                    min = min.min(v);
                    max = max.max(v);
                }
            }
            Some(holes) => {
                for (&v, _) in self.samples.iter().zip(holes).filter(|(_, &h)| !h) {
                    min = min.min(v);
                    max = max.max(v);
                }
                for (v, _) in self.samples.iter_mut().zip(holes).filter(|(_, &h)| h) {
                    *v = min;
                }
            }
        }
        self.min = min;
        self.max = max;
    }

    /// The grid's placement in the world.
    pub fn geometry(&self) -> &GridGeometry {
        &self.geometry
    }

    /// The same samples placed with another geometry.
    pub fn with_geometry(mut self, geometry: GridGeometry) -> Result<Self, CoreError> {
        geometry.validate()?;
        self.geometry = geometry;
        Ok(self)
    }

    /// The same grid with its rows in reverse order: turns a north-up array (row 0 north)
    /// into relief's convention (row 0 south).
    pub fn flip_rows(mut self) -> Self {
        let w = self.width;
        let rows: Vec<&[f32]> = self.samples.chunks_exact(w).rev().collect();
        self.samples = rows.concat();
        if let Some(holes) = &self.holes {
            let rows: Vec<&[bool]> = holes.chunks_exact(w).rev().collect();
            self.holes = Some(rows.concat());
        }
        self
    }

    /// Smallest sample value (holes aside), or the floor set by [`HeightField::with_floor`]:
    /// the bottom of the solid.
    pub fn min_sample(&self) -> f32 {
        self.min
    }

    /// Largest sample value (holes aside).
    pub fn max_sample(&self) -> f32 {
        self.max
    }

    /// The solid's bounds in grid space for a surface: x, y in texel units, z in sample units.
    ///
    /// `boxes` span the whole grid; `triangles` span the sample centres, from 0.5 to size - 0.5.
    pub fn grid_bounds(&self, surface: Surface) -> Aabb {
        let inset = match surface {
            Surface::Boxes => 0.0,
            Surface::Triangles => 0.5,
        };
        Aabb::new(
            DVec3::new(inset, inset, self.min as f64),
            DVec3::new(self.width as f64 - inset, self.height as f64 - inset, self.max as f64),
        )
    }

    /// The solid's bounds in world coordinates for a surface.
    pub fn world_bounds(&self, surface: Surface) -> Aabb {
        let b = self.grid_bounds(surface);
        Aabb::new(self.geometry.point_to_world(b.min), self.geometry.point_to_world(b.max))
    }
}

/// The smallest and largest of `samples`, or `None` when one is not finite (or there are
/// none): one pass in lanes the compiler vectorises, as a simulation rewrites a whole field
/// every step.
fn finite_range(samples: &[f32]) -> Option<(f32, f32)> {
    const LANES: usize = 16;
    const EXPONENT: u32 = 0x7f80_0000;
    let mut lo = [f32::INFINITY; LANES];
    let mut hi = [f32::NEG_INFINITY; LANES];
    let mut non_finite = [0u32; LANES];
    let chunks = samples.chunks_exact(LANES);
    let rest = chunks.remainder();
    for chunk in chunks {
        for k in 0..LANES {
            let v = chunk[k];
            non_finite[k] |= u32::from(v.to_bits() & EXPONENT == EXPONENT);
            lo[k] = if v < lo[k] { v } else { lo[k] };
            hi[k] = if v > hi[k] { v } else { hi[k] };
        }
    }
    let mut bad = non_finite.iter().any(|&b| b != 0);
    let (mut min, mut max) = (f32::INFINITY, f32::NEG_INFINITY);
    for k in 0..LANES {
        min = min.min(lo[k]);
        max = max.max(hi[k]);
    }
    for &v in rest {
        bad |= !v.is_finite();
        min = min.min(v);
        max = max.max(v);
    }
    (!bad && min <= max).then_some((min, max))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edits_keep_the_range_and_refuse_non_finite_values() {
        let g = GridGeometry::unit();
        let mut f = HeightField::new(3, 2, vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0], g).unwrap();
        let changed = f.edit_region(SampleRegion::new(1, 0, 9, 1), |c, _, v| v + c as f32).unwrap();
        assert_eq!(changed, SampleRegion::new(1, 0, 3, 1));
        assert_eq!(f.samples(), &[1.0, 3.0, 5.0, 4.0, 5.0, 6.0]);
        assert_eq!((f.min_sample(), f.max_sample()), (1.0, 6.0));
        let before = f.clone();
        let bad =
            f.edit_region(SampleRegion::whole(3, 2), |_, r, v| if r == 1 { f32::NAN } else { v });
        assert!(matches!(bad, Err(CoreError::NonFiniteSample { col: 0, row: 1, .. })));
        assert_eq!(f, before);
        let old = f.replace_samples(vec![-2.0; 6]).unwrap();
        assert_eq!(old, before.samples());
        assert_eq!((f.min_sample(), f.max_sample()), (-2.0, -2.0));
        assert!(f.replace_samples(vec![0.0; 5]).is_err());
        assert!(f.replace_samples(vec![f32::INFINITY; 6]).is_err());
        assert_eq!(f.samples(), &[-2.0; 6]);
    }

    #[test]
    fn replace_samples_ranges_like_new_in_every_lane() {
        let g = GridGeometry::unit();
        let values: Vec<f32> = (0..37).map(|i| ((i * 7919) % 101) as f32 - 50.0).collect();
        let mut f = HeightField::new(37, 1, vec![0.0; 37], g).unwrap();
        f.replace_samples(values.clone()).unwrap();
        let fresh = HeightField::new(37, 1, values.clone(), g).unwrap();
        assert_eq!((f.min_sample(), f.max_sample()), (fresh.min_sample(), fresh.max_sample()));
        // A non-finite value in a lane, in the remainder, or an infinity is refused by place.
        for (i, bad) in [(5, f32::NAN), (35, f32::NAN), (16, f32::NEG_INFINITY)] {
            let mut v = values.clone();
            v[i] = bad;
            let err = f.replace_samples(v).unwrap_err();
            assert!(matches!(err, CoreError::NonFiniteSample { col, row: 0, .. } if col == i));
        }
    }

    #[test]
    fn an_edit_keeps_the_range_exact_inside_and_outside_the_region() {
        let g = GridGeometry::unit();
        let mut f = HeightField::new(4, 1, vec![0.0, 5.0, 2.0, 3.0], g).unwrap();
        // Inside the range, away from its ends: no rescan needed.
        f.edit_region(SampleRegion::new(2, 0, 3, 1), |_, _, _| 4.0).unwrap();
        assert_eq!((f.min_sample(), f.max_sample()), (0.0, 5.0));
        // Past an end.
        f.edit_region(SampleRegion::new(3, 0, 4, 1), |_, _, _| -1.0).unwrap();
        assert_eq!((f.min_sample(), f.max_sample()), (-1.0, 5.0));
        // Lowering the sample that held the maximum: the range shrinks.
        f.edit_region(SampleRegion::new(1, 0, 2, 1), |_, _, _| 1.0).unwrap();
        assert_eq!((f.min_sample(), f.max_sample()), (-1.0, 4.0));
        // With a hole: it keeps the lowest valid value.
        let mut f = HeightField::new(3, 1, vec![1.0, 2.0, 3.0], g)
            .unwrap()
            .with_holes(vec![false, false, true])
            .unwrap();
        f.edit_region(SampleRegion::new(1, 0, 2, 1), |_, _, _| -2.0).unwrap();
        assert_eq!(f.samples(), &[1.0, -2.0, -2.0]);
        assert_eq!((f.min_sample(), f.max_sample()), (-2.0, 1.0));
    }

    #[test]
    fn refuses_bad_grids() {
        let g = GridGeometry::unit();
        assert!(HeightField::new(0, 3, vec![], g).is_err());
        assert!(HeightField::new(2, 2, vec![0.0; 3], g).is_err());
        let nan = HeightField::new(2, 1, vec![0.0, f32::NAN], g).unwrap_err();
        assert!(matches!(nan, CoreError::NonFiniteSample { col: 1, row: 0, .. }));
        let bad = GridGeometry { dx: 0.0, ..g };
        assert!(HeightField::new(1, 1, vec![0.0], bad).is_err());
    }

    #[test]
    fn holes_are_left_out_of_the_range() {
        let f = HeightField::new(2, 2, vec![5.0, 1.0, 2.0, 9.0], GridGeometry::unit()).unwrap();
        let f = f.with_holes(vec![false, true, false, false]).unwrap();
        assert_eq!((f.min_sample(), f.max_sample(), f.hole_count()), (2.0, 9.0, 1));
        assert!(f.is_hole(1, 0) && !f.is_hole(0, 1));
        assert_eq!(f.sample(1, 0), 2.0);
        let flipped = f.clone().flip_rows();
        assert!(flipped.is_hole(1, 1) && !flipped.is_hole(1, 0));
        let all = HeightField::new(1, 1, vec![0.0], GridGeometry::unit()).unwrap();
        assert!(all.with_holes(vec![true]).is_err());
        let none = HeightField::new(1, 1, vec![0.0], GridGeometry::unit()).unwrap();
        assert!(none.with_holes(vec![false]).unwrap().holes().is_none());
    }

    #[test]
    fn flipping_rows_reverses_them() {
        let f = HeightField::new(2, 3, vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0], GridGeometry::unit());
        let f = f.unwrap().flip_rows();
        assert_eq!(f.samples(), &[4.0, 5.0, 2.0, 3.0, 0.0, 1.0]);
    }

    #[test]
    fn grid_and_world_spaces_agree() {
        let g = GridGeometry { dx: 2.0, dy: 3.0, z_scale: 0.5, origin: DVec2::new(10.0, 20.0) };
        let ray = Ray::new(DVec3::new(12.0, 26.0, 4.0), DVec3::new(1.0, 1.0, 1.0));
        let grid = g.ray_to_grid(&ray);
        assert_eq!(grid.origin, DVec3::new(1.0, 2.0, 8.0));
        let p = grid.at(2.0);
        assert!((g.point_to_world(p) - ray.at(2.0)).length() < 1e-12);
    }
}
