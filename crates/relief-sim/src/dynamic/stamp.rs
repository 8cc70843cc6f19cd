//! Terrain stamping: brushes (raise, lower, smooth, flatten) that edit a height field in place
//! and return the samples they touched.

use crate::error::{finite, non_negative, positive};
use crate::SimError;
use relief_core::{DVec2, HeightField, SampleRegion};

/// What a brush does to the samples under it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BrushKind {
    /// Adds `strength` world units of height at the centre, less towards the rim.
    Raise,
    /// Removes `strength` world units of height at the centre, less towards the rim.
    Lower,
    /// Moves each sample towards the mean of its 3 x 3 neighbourhood (holes and samples off
    /// the grid left out) by the fraction `strength` at the centre.
    Smooth,
    /// Moves each sample towards the sample nearest the brush's centre by the fraction
    /// `strength` at the centre.
    Flatten,
}

/// A circular brush in world coordinates.
///
/// A sample at horizontal distance `d` from `centre` is moved by the weight
/// `(1 - d² / radius²)²` for `d < radius` (1 at the centre, falling smoothly to 0 at the rim
/// with a zero slope there) and not at all from the rim outwards.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Brush {
    /// What the brush does.
    pub kind: BrushKind,
    /// World (x, y) of the brush's centre.
    pub centre: DVec2,
    /// World radius, > 0.
    pub radius: f64,
    /// [`BrushKind::Raise`] and [`BrushKind::Lower`]: world height at the centre, >= 0;
    /// [`BrushKind::Smooth`] and [`BrushKind::Flatten`]: the fraction of the way to go at the
    /// centre, 0 to 1.
    pub strength: f64,
}

impl Brush {
    /// Checks that the centre is finite, the radius finite and positive, and the strength in
    /// its kind's range.
    pub fn validate(&self) -> Result<(), SimError> {
        finite("brush centre x", self.centre.x)?;
        finite("brush centre y", self.centre.y)?;
        positive("brush radius", self.radius)?;
        match self.kind {
            BrushKind::Raise | BrushKind::Lower => non_negative("brush strength", self.strength),
            BrushKind::Smooth | BrushKind::Flatten => {
                if (0.0..=1.0).contains(&self.strength) {
                    Ok(())
                } else {
                    Err(SimError::parameter(
                        "brush strength",
                        format!("{} is outside 0..=1 for {:?}", self.strength, self.kind),
                    ))
                }
            }
        }
    }

    /// The brush's weight at squared horizontal distance `d2` from its centre.
    #[inline]
    fn weight(&self, d2: f64) -> f64 {
        let t = 1.0 - d2 / (self.radius * self.radius);
        if t > 0.0 {
            t * t
        } else {
            0.0
        }
    }
}

/// Stamps `brush` on `field` in place through [`HeightField::edit_region`]: only samples
/// strictly within `brush.radius` of its centre change (holes never do). Returns the region of
/// samples the edit covered, which holds every changed sample (empty when the brush lies off
/// the grid). Deterministic: a smoothing brush reads the samples as they were before the
/// stamp, whatever the order it writes them in.
///
/// Errors: a brush [`Brush::validate`] refuses, or a result that is not a finite f32
/// ([`SimError::Terrain`]); the field is then unchanged.
///
/// ```
/// use relief_core::{DVec2, GridGeometry, HeightField};
/// use relief_sim::{stamp, Brush, BrushKind};
/// let mut field = HeightField::new(16, 16, vec![0.0; 256], GridGeometry::unit()).unwrap();
/// let brush = Brush { kind: BrushKind::Raise, centre: DVec2::new(8.0, 8.0), radius: 3.0, strength: 2.0 };
/// let region = stamp(&mut field, &brush).unwrap();
/// assert!(region.contains(7, 7) && !region.contains(0, 0));
/// assert!(field.sample(7, 7) > 1.5 && field.sample(0, 0) == 0.0);
/// ```
pub fn stamp(field: &mut HeightField, brush: &Brush) -> Result<SampleRegion, SimError> {
    brush.validate()?;
    let region = brush_region(field, brush);
    if region.is_empty() {
        return Ok(region);
    }
    let g = *field.geometry();
    let (width, height) = (field.width(), field.height());
    let distance2 = move |col: usize, row: usize| {
        let x = g.origin.x + (col as f64 + 0.5) * g.dx - brush.centre.x;
        let y = g.origin.y + (row as f64 + 0.5) * g.dy - brush.centre.y;
        x * x + y * y
    };
    let changed = match brush.kind {
        BrushKind::Raise | BrushKind::Lower => {
            let sign = if brush.kind == BrushKind::Raise { 1.0 } else { -1.0 };
            let scale = sign * brush.strength / g.z_scale;
            field.edit_region(region, |col, row, old| {
                (f64::from(old) + scale * brush.weight(distance2(col, row))) as f32
            })?
        }
        BrushKind::Flatten => {
            let col = nearest_index(brush.centre.x, g.origin.x, g.dx, width);
            let row = nearest_index(brush.centre.y, g.origin.y, g.dy, height);
            let target = f64::from(field.sample(col, row));
            field.edit_region(region, |col, row, old| {
                let w = brush.strength * brush.weight(distance2(col, row));
                (f64::from(old) + w * (target - f64::from(old))) as f32
            })?
        }
        BrushKind::Smooth => {
            let before = RegionCopy::new(field, region.grown(1, width, height));
            field.edit_region(region, |col, row, old| {
                let w = brush.strength * brush.weight(distance2(col, row));
                if w == 0.0 {
                    return old;
                }
                let mean = before.neighbourhood_mean(col, row);
                (f64::from(old) + w * (mean - f64::from(old))) as f32
            })?
        }
    };
    Ok(changed)
}

/// The samples whose centres may lie within the brush's radius, clamped to the grid.
fn brush_region(field: &HeightField, brush: &Brush) -> SampleRegion {
    let g = field.geometry();
    let span = |centre: f64, origin: f64, spacing: f64, n: usize| {
        // Sample k sits at origin + (k + 0.5) * spacing: the ones within the radius.
        let lo = ((centre - brush.radius - origin) / spacing - 0.5).floor();
        let hi = ((centre + brush.radius - origin) / spacing - 0.5).floor() + 1.0;
        let clamp = |v: f64| v.clamp(0.0, n as f64) as usize;
        (clamp(lo), clamp(hi))
    };
    let (col0, col1) = span(brush.centre.x, g.origin.x, g.dx, field.width());
    let (row0, row1) = span(brush.centre.y, g.origin.y, g.dy, field.height());
    SampleRegion::new(col0, row0, col1, row1)
}

/// The index of the sample nearest world coordinate `x` along one axis, clamped to the grid.
fn nearest_index(x: f64, origin: f64, spacing: f64, n: usize) -> usize {
    ((x - origin) / spacing).floor().clamp(0.0, (n - 1) as f64) as usize
}

/// The samples and hole flags of a region, copied before an edit changes them.
struct RegionCopy {
    region: SampleRegion,
    samples: Vec<f32>,
    holes: Vec<bool>,
}

impl RegionCopy {
    /// Copies `region` (inside the grid) of `field`.
    fn new(field: &HeightField, region: SampleRegion) -> Self {
        let mut samples = Vec::with_capacity(region.len());
        let mut holes = Vec::with_capacity(region.len());
        for row in region.row0..region.row1 {
            for col in region.col0..region.col1 {
                samples.push(field.sample(col, row));
                holes.push(field.is_hole(col, row));
            }
        }
        RegionCopy { region, samples, holes }
    }

    /// The mean of the copied 3 x 3 neighbourhood of (col, row), holes and samples outside
    /// the copy left out; the sample itself is never a hole, so the mean always exists.
    fn neighbourhood_mean(&self, col: usize, row: usize) -> f64 {
        let r = &self.region;
        let width = r.col1 - r.col0;
        let (mut sum, mut count) = (0.0f64, 0u32);
        for y in row.saturating_sub(1).max(r.row0)..(row + 2).min(r.row1) {
            for x in col.saturating_sub(1).max(r.col0)..(col + 2).min(r.col1) {
                let i = (x - r.col0) + (y - r.row0) * width;
                if !self.holes[i] {
                    sum += f64::from(self.samples[i]);
                    count += 1;
                }
            }
        }
        if count == 0 {
            0.0
        } else {
            sum / f64::from(count)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief_core::GridGeometry;

    fn ramp(width: usize, height: usize) -> HeightField {
        let samples = (0..width * height).map(|i| ((i * 37) % 11) as f32 * 0.5).collect();
        let g = GridGeometry { dx: 2.0, dy: 1.5, z_scale: 0.5, origin: DVec2::new(-3.0, 4.0) };
        HeightField::new(width, height, samples, g).unwrap()
    }

    #[test]
    fn raise_adds_strength_at_the_centre_in_world_units() {
        let mut field = ramp(9, 9);
        // Sample (4, 4) sits at (-3 + 4.5 * 2, 4 + 4.5 * 1.5) = (6, 10.75).
        let brush = Brush {
            kind: BrushKind::Raise,
            centre: DVec2::new(6.0, 10.75),
            radius: 5.0,
            strength: 1.0,
        };
        let before = field.sample(4, 4);
        stamp(&mut field, &brush).unwrap();
        // One world unit is two sample units at z scale 0.5.
        assert_eq!(field.sample(4, 4), before + 2.0);
    }

    #[test]
    fn flatten_pulls_to_the_centre_sample() {
        let mut field = ramp(9, 9);
        let brush = Brush {
            kind: BrushKind::Flatten,
            centre: DVec2::new(6.0, 10.75),
            radius: 30.0,
            strength: 1.0,
        };
        let target = field.sample(4, 4);
        stamp(&mut field, &brush).unwrap();
        assert_eq!(field.sample(4, 4), target);
        // Every sample moved towards the target, none past it.
        let fresh = ramp(9, 9);
        for row in 0..9 {
            for col in 0..9 {
                let (a, b) = (fresh.sample(col, row), field.sample(col, row));
                assert!((b - target).abs() <= (a - target).abs() + 1e-6);
            }
        }
    }

    #[test]
    fn bad_brushes_are_refused() {
        let mut field = ramp(4, 4);
        let good =
            Brush { kind: BrushKind::Smooth, centre: DVec2::ZERO, radius: 1.0, strength: 0.5 };
        for bad in [
            Brush { radius: 0.0, ..good },
            Brush { radius: f64::NAN, ..good },
            Brush { strength: 1.5, ..good },
            Brush { kind: BrushKind::Lower, strength: -1.0, ..good },
            Brush { centre: DVec2::new(f64::INFINITY, 0.0), ..good },
        ] {
            assert!(stamp(&mut field, &bad).is_err(), "{bad:?}");
        }
        let huge = Brush { kind: BrushKind::Raise, strength: 1e300, radius: 100.0, ..good };
        let before = field.clone();
        assert!(matches!(stamp(&mut field, &huge), Err(SimError::Terrain(_))));
        assert_eq!(field, before);
    }

    #[test]
    fn a_brush_off_the_grid_touches_nothing() {
        let mut field = ramp(4, 4);
        let before = field.clone();
        let brush = Brush {
            kind: BrushKind::Raise,
            centre: DVec2::new(1e6, -1e6),
            radius: 3.0,
            strength: 1.0,
        };
        assert!(stamp(&mut field, &brush).unwrap().is_empty());
        assert_eq!(field, before);
    }
}
