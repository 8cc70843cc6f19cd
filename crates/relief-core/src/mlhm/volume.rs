//! Exact volumes of bedrock, sand and water of an [`Mlhm`] inside an axis-aligned box: the
//! building block of the multi-layered height map's geometric ambient occlusion
//! (`AO = (1 - V_solid / (2a)^3)^2` over the cube of half-size `a` centred at `p + a n`), of
//! material colours blended by volume fractions and of the smooth implicit surface `V(p)`.
//!
//! A column's materials are the half-open height intervals `[floor, bedrock)` (bedrock, from
//! the map's base, minus infinity unless set, for the lowest column), `[bedrock, solid_top)` (sand) and
//! `[solid_top, water_top)` (water), with [`MlhmColumn::solid_top`] and
//! [`MlhmColumn::water_top`] the f32 sums the rest of relief uses, so the intervals never
//! overlap on a valid map. The volume of a material in a box is the sum, over every cell
//! overlapping the box's footprint, of the footprint overlap area times the length of the
//! intersection of the box's height range with each of the cell's intervals of that material.

use crate::{DVec3, Mlhm, MlhmColumn};
use std::ops::{Add, AddAssign, Mul};

/// Volumes of bedrock, sand and water, cubic metres.
///
/// Volumes add and scale, so blending material colours by volume fractions reads naturally:
///
/// ```
/// use relief_core::MaterialVolumes;
/// let v = MaterialVolumes { bedrock: 2.0, sand: 1.0, water: 1.0 };
/// assert_eq!(v.solid(), 3.0);
/// assert_eq!(v.total(), 4.0);
/// assert_eq!((v + v * 0.5).bedrock, 3.0);
/// let [rock, sand, water] = v.fractions().unwrap();
/// assert_eq!((rock, sand, water), (0.5, 0.25, 0.25));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MaterialVolumes {
    /// Volume of bedrock, cubic metres.
    pub bedrock: f64,
    /// Volume of sand, cubic metres.
    pub sand: f64,
    /// Volume of water, cubic metres.
    pub water: f64,
}

impl MaterialVolumes {
    /// No material at all.
    ///
    /// ```
    /// use relief_core::MaterialVolumes;
    /// assert_eq!(MaterialVolumes::ZERO.total(), 0.0);
    /// ```
    pub const ZERO: MaterialVolumes = MaterialVolumes { bedrock: 0.0, sand: 0.0, water: 0.0 };

    /// Volume of the solids: bedrock + sand.
    ///
    /// ```
    /// use relief_core::MaterialVolumes;
    /// assert_eq!(MaterialVolumes { bedrock: 1.5, sand: 0.5, water: 4.0 }.solid(), 2.0);
    /// ```
    #[inline]
    pub fn solid(&self) -> f64 {
        self.bedrock + self.sand
    }

    /// Volume of every material: bedrock + sand + water.
    ///
    /// ```
    /// use relief_core::MaterialVolumes;
    /// assert_eq!(MaterialVolumes { bedrock: 1.5, sand: 0.5, water: 4.0 }.total(), 6.0);
    /// ```
    #[inline]
    pub fn total(&self) -> f64 {
        self.bedrock + self.sand + self.water
    }

    /// The share of each material in [`total`](MaterialVolumes::total), in the order
    /// bedrock, sand, water (the weights for blending material colours); `None` when there
    /// is no material.
    ///
    /// ```
    /// use relief_core::MaterialVolumes;
    /// let v = MaterialVolumes { bedrock: 0.0, sand: 1.0, water: 3.0 };
    /// assert_eq!(v.fractions(), Some([0.0, 0.25, 0.75]));
    /// assert_eq!(MaterialVolumes::ZERO.fractions(), None);
    /// ```
    pub fn fractions(&self) -> Option<[f64; 3]> {
        let total = self.total();
        (total > 0.0).then(|| [self.bedrock / total, self.sand / total, self.water / total])
    }
}

impl Add for MaterialVolumes {
    type Output = MaterialVolumes;

    /// Material by material sum.
    #[inline]
    fn add(self, other: MaterialVolumes) -> MaterialVolumes {
        MaterialVolumes {
            bedrock: self.bedrock + other.bedrock,
            sand: self.sand + other.sand,
            water: self.water + other.water,
        }
    }
}

impl AddAssign for MaterialVolumes {
    /// Material by material sum.
    #[inline]
    fn add_assign(&mut self, other: MaterialVolumes) {
        *self = *self + other;
    }
}

impl Mul<f64> for MaterialVolumes {
    type Output = MaterialVolumes;

    /// Every volume times `factor`.
    #[inline]
    fn mul(self, factor: f64) -> MaterialVolumes {
        MaterialVolumes {
            bedrock: self.bedrock * factor,
            sand: self.sand * factor,
            water: self.water * factor,
        }
    }
}

/// The cells a box's footprint overlaps along one axis, in cell units: cells `first..end`,
/// the first covered over `first_weight` of its width, the last over `last_weight`, the ones
/// between fully (when `end - first == 1`, the single cell's weight is `first_weight`).
#[derive(Debug, Clone, Copy)]
struct AxisCover {
    first: usize,
    end: usize,
    first_weight: f64,
    last_weight: f64,
}

impl AxisCover {
    /// The cover of `[lo, hi]` metres on an axis of `cells` cells of `cell_size` metres;
    /// `None` when the overlap with the grid has no length (NaN bounds included).
    #[inline]
    fn new(lo: f64, hi: f64, cells: usize, cell_size: f64) -> Option<AxisCover> {
        // Before `max` and `min`, which would drop a NaN.
        if !is_interval(lo, hi) {
            return None;
        }
        let lo = lo.max(0.0) / cell_size;
        let hi = hi.min(cells as f64 * cell_size) / cell_size;
        if !is_interval(lo, hi) {
            return None;
        }
        let first = (lo.floor() as usize).min(cells - 1);
        let end = (hi.ceil() as usize).clamp(first + 1, cells);
        let (first_weight, last_weight) = if end - first == 1 {
            (hi - lo, 0.0)
        } else {
            ((first + 1) as f64 - lo, hi - (end - 1) as f64)
        };
        Some(AxisCover { first, end, first_weight, last_weight })
    }

    /// The weight of overlapped cell `cell`: the fraction of its width inside the box.
    #[inline]
    fn weight(&self, cell: usize) -> f64 {
        if cell == self.first {
            self.first_weight
        } else if cell + 1 == self.end {
            self.last_weight
        } else {
            1.0
        }
    }
}

/// Whether `[lo, hi]` has a length: `lo < hi`, false when either is NaN.
#[inline(always)]
fn is_interval(lo: f64, hi: f64) -> bool {
    lo < hi
}

/// Height `z` clamped to the box's height range `[z_min, z_max]`: the length of an interval
/// `[lo, hi]` (`lo <= hi`) inside that range is `clip(hi) - clip(lo)`.
#[inline(always)]
fn clip(z: f32, z_min: f64, z_max: f64) -> f64 {
    f64::from(z).max(z_min).min(z_max)
}

impl Mlhm {
    /// The exact volumes of bedrock, sand and water inside the axis-aligned box from `min` to
    /// `max`, in grid-local metres: x and y from the grid's south-west corner (cell `(x, y)`
    /// covers `[x s, (x + 1) s) x [y s, (y + 1) s)`, `s` the [cell size](Mlhm::cell_size)), z
    /// absolute height.
    ///
    /// The volume of a material is the sum, over every cell the box's footprint overlaps, of
    /// the overlap area times the length of the box's height range inside the cell's
    /// intervals of that material. Each column contributes the intervals `[floor, bedrock)`
    /// of bedrock, `[bedrock, solid_top)` of sand and `[solid_top, water_top)` of water,
    /// with [`MlhmColumn::solid_top`] and [`MlhmColumn::water_top`] the f32 sums the rest of
    /// relief uses, so that they never overlap. The lowest column's bedrock reaches down to
    /// the map's [base](Mlhm::base) (minus infinity unless set), clipped to the box; parts
    /// of the box outside the grid hold nothing. A box with a NaN bound or without volume
    /// (`min >= max` on an axis) holds nothing; a box reaching down to minus infinity over
    /// a grid without a base holds infinite bedrock.
    ///
    /// Runs in time proportional to the overlapped cells times the columns visited per cell,
    /// which stop at the first column whose floor is at or above `max.z`; allocates nothing.
    ///
    /// ```
    /// use relief_core::{DVec3, Mlhm, MlhmColumn};
    /// let mut map = Mlhm::new(2, 2, 2, 0.5)?;
    /// // Cell (1, 0): bedrock up to 1 m, 0.5 m of sand, 0.25 m of water under a roof at 2 m.
    /// map.set_cell(1, 0, &[
    ///     MlhmColumn::new(1.0, 0.5, 0.25, 2.0),
    ///     MlhmColumn::new(3.0, 0.0, 0.0, f32::INFINITY),
    /// ])?;
    /// let v = map.material_volumes(DVec3::new(0.5, 0.0, 0.0), DVec3::new(1.0, 0.5, 4.0));
    /// let area = 0.25;
    /// assert_eq!(v.bedrock, area * (1.0 + 1.0));
    /// assert_eq!(v.sand, area * 0.5);
    /// assert_eq!(v.water, area * 0.25);
    /// // Outside the grid there is nothing; the flat cells are bedrock below 0 m.
    /// let v = map.material_volumes(DVec3::new(-1.0, 0.0, -2.0), DVec3::new(0.5, 0.5, 0.0));
    /// assert_eq!(v.bedrock, 0.25 * 2.0);
    /// # Ok::<(), relief_core::CoreError>(())
    /// ```
    pub fn material_volumes(&self, min: DVec3, max: DVec3) -> MaterialVolumes {
        let (z_min, z_max) = (min.z, max.z);
        if !is_interval(z_min, z_max) {
            return MaterialVolumes::ZERO;
        }
        self.integrate(min, max, |column, floor| {
            let bedrock_top = clip(column.bedrock, z_min, z_max);
            let solid_top = clip(column.solid_top(), z_min, z_max);
            MaterialVolumes {
                bedrock: bedrock_top - floor,
                sand: solid_top - bedrock_top,
                water: clip(column.water_top(), z_min, z_max) - solid_top,
            }
        })
    }

    /// The exact volume of solids (bedrock and sand) inside the box from `min` to `max`:
    /// [`material_volumes`](Mlhm::material_volumes)`(min, max).solid()`, computed faster.
    ///
    /// ```
    /// use relief_core::{DVec3, Mlhm, MlhmColumn};
    /// let mut map = Mlhm::new(4, 4, 1, 0.25)?;
    /// map.set_cell(2, 2, &[MlhmColumn::new(1.0, 1.0, 1.0, f32::INFINITY)])?;
    /// // Geometric ambient occlusion over a cube of half-size 0.5 m centred at p + 0.5 n.
    /// let (p, normal, a) = (DVec3::new(0.5, 0.5, 0.0), DVec3::Z, 0.5);
    /// let centre = p + a * normal;
    /// let solid = map.solid_volume(centre - a, centre + a);
    /// let ambient_occlusion = (1.0 - solid / (2.0 * a).powi(3)).powi(2);
    /// assert_eq!(solid, 0.0625 * 1.0);
    /// assert!((ambient_occlusion - (1.0 - 0.0625f64).powi(2)).abs() < 1e-12);
    /// # Ok::<(), relief_core::CoreError>(())
    /// ```
    pub fn solid_volume(&self, min: DVec3, max: DVec3) -> f64 {
        let (z_min, z_max) = (min.z, max.z);
        if !is_interval(z_min, z_max) {
            return 0.0;
        }
        self.integrate(min, max, |column, floor| clip(column.solid_top(), z_min, z_max) - floor)
    }

    /// Sums `per_column(column, floor)` over the columns of every cell the footprint of the
    /// box from `min` to `max` overlaps, from the lowest up to the first whose ceiling is at
    /// or above `max.z`, weighted by the cell's overlap with the footprint, times the cell's
    /// area. `floor` is the column's floor clamped to `[min.z, max.z]`. The caller checks
    /// `min.z < max.z`.
    ///
    /// The lowest columns of a row are contiguous and read as a slice; the layer counts are
    /// not read: a column whose ceiling lies below `max.z` is finite, so not the topmost (whose
    /// ceiling is `+inf`, an invariant of every map), and a column lies above it.
    #[inline(always)]
    fn integrate<V, F>(&self, min: DVec3, max: DVec3, per_column: F) -> V
    where
        V: Copy + Default + AddAssign + Mul<f64, Output = V>,
        F: Fn(MlhmColumn, f64) -> V,
    {
        let s = self.cell_size();
        let (Some(xs), Some(ys)) = (
            AxisCover::new(min.x, max.x, self.width(), s),
            AxisCover::new(min.y, max.y, self.height(), s),
        ) else {
            return V::default();
        };
        let (z_min, z_max) = (min.z, max.z);
        let layer_stride = self.width() * self.height();
        let columns = self.raw_columns();
        // The sum over the cell whose lowest column, `lowest`, is at index `i`.
        // The lowest columns end at the base (minus infinity unless set).
        let base = clip(self.base(), z_min, z_max);
        let cell = |i: usize, lowest: MlhmColumn| {
            let mut sum = per_column(lowest, base);
            let (mut below, mut i) = (lowest, i);
            while f64::from(below.ceiling) < z_max {
                i += layer_stride;
                let column = columns[i];
                sum += per_column(column, f64::from(below.ceiling).max(z_min));
                below = column;
            }
            sum
        };
        let mut total = V::default();
        for y in ys.first..ys.end {
            let row = y * self.width();
            let (first, last) = (row + xs.first, row + xs.end - 1);
            let mut row_sum = cell(first, columns[first]) * xs.first_weight;
            if last > first {
                for (i, &lowest) in (first + 1..).zip(&columns[first + 1..last]) {
                    row_sum += cell(i, lowest);
                }
                row_sum += cell(last, columns[last]) * xs.last_weight;
            }
            total += row_sum * ys.weight(y);
        }
        total * (s * s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `(first, end, first_weight, last_weight)` of the cover of `[lo, hi]` on 4 unit cells.
    fn cover(lo: f64, hi: f64) -> Option<(usize, usize, f64, f64)> {
        AxisCover::new(lo, hi, 4, 1.0).map(|c| (c.first, c.end, c.first_weight, c.last_weight))
    }

    #[test]
    fn axis_covers_weigh_the_border_cells_by_their_overlap() {
        assert_eq!(cover(0.5, 2.5), Some((0, 3, 0.5, 0.5)));
        assert_eq!(cover(1.0, 2.0), Some((1, 2, 1.0, 0.0)));
        assert_eq!(cover(1.0, 3.0), Some((1, 3, 1.0, 1.0)));
        assert_eq!(cover(1.25, 1.5), Some((1, 2, 0.25, 0.0)));
        assert_eq!(cover(-5.0, 10.0), Some((0, 4, 1.0, 1.0)));
        assert_eq!(cover(f64::NEG_INFINITY, f64::INFINITY), Some((0, 4, 1.0, 1.0)));
        assert_eq!(cover(3.5, 1e300), Some((3, 4, 0.5, 0.0)));
        let weights = AxisCover::new(0.5, 3.25, 4, 1.0).unwrap();
        let all: Vec<_> = (weights.first..weights.end).map(|i| weights.weight(i)).collect();
        assert_eq!(all, [0.5, 1.0, 1.0, 0.25]);
    }

    #[test]
    fn axis_covers_of_nothing_are_none() {
        for (lo, hi) in [
            (4.0, 5.0),
            (-1.0, 0.0),
            (2.0, 2.0),
            (3.0, 1.0),
            (f64::NAN, 1.0),
            (1.0, f64::NAN),
            (f64::INFINITY, f64::INFINITY),
        ] {
            assert_eq!(cover(lo, hi), None, "[{lo}, {hi}]");
        }
    }

    #[test]
    fn volumes_add_and_scale_material_by_material() {
        let a = MaterialVolumes { bedrock: 1.0, sand: 2.0, water: 3.0 };
        let mut b = a * 2.0;
        assert_eq!(b, MaterialVolumes { bedrock: 2.0, sand: 4.0, water: 6.0 });
        b += a;
        assert_eq!(b, a * 3.0);
        assert_eq!((a + a).total(), 12.0);
        assert_eq!(MaterialVolumes::default(), MaterialVolumes::ZERO);
    }
}
