//! The multi-layered height map (MLHM): a grid of cells holding stacks of columns of bedrock,
//! sand, water and air, in the reference simulator's layer-major layout.

mod volume;

use crate::CoreError;
use half::f16;

pub use volume::MaterialVolumes;

/// One column of an MLHM cell: four values in the reference order.
///
/// The column spans from its floor (the ceiling of the column below, or minus infinity for the
/// lowest column) up to [`water_top`](MlhmColumn::water_top): bedrock up to `bedrock`, then
/// `sand` metres of sand, then `water` metres of water; air from there up to `ceiling`, where
/// the bedrock of the next column begins. The topmost column's ceiling is `+inf`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[repr(C)]
pub struct MlhmColumn {
    /// Absolute height of the bedrock's top, metres.
    pub bedrock: f32,
    /// Thickness of the sand on the bedrock, metres, >= 0.
    pub sand: f32,
    /// Thickness of the water on the sand, metres, >= 0.
    pub water: f32,
    /// Absolute height where this column's air ends (the floor of the column above); `+inf`
    /// for the topmost column.
    pub ceiling: f32,
}

impl MlhmColumn {
    /// A column with these four values.
    pub const fn new(bedrock: f32, sand: f32, water: f32, ceiling: f32) -> Self {
        MlhmColumn { bedrock, sand, water, ceiling }
    }

    /// Absolute height of the top of the solids: `bedrock + sand` (computed in f32).
    #[inline]
    pub fn solid_top(&self) -> f32 {
        self.bedrock + self.sand
    }

    /// Absolute height of the top of the water: `bedrock + sand + water` (computed in f32,
    /// left to right).
    #[inline]
    pub fn water_top(&self) -> f32 {
        self.bedrock + self.sand + self.water
    }

    /// The four values in the reference order (bedrock, sand, water, ceiling).
    #[inline]
    pub fn to_array(self) -> [f32; 4] {
        [self.bedrock, self.sand, self.water, self.ceiling]
    }

    /// A column from four values in the reference order (bedrock, sand, water, ceiling).
    #[inline]
    pub fn from_array(v: [f32; 4]) -> Self {
        MlhmColumn { bedrock: v[0], sand: v[1], water: v[2], ceiling: v[3] }
    }
}

/// The precision an MLHM's values are held at.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Precision {
    /// Any f32 values.
    #[default]
    F32,
    /// Every value is exactly representable as an IEEE half-precision float (f16).
    F16,
}

/// A multi-layered height map: `width x height` cells of `cell_size` metres, each holding
/// 1 to `max_layers` columns stacked bottom to top (see [`MlhmColumn`]).
///
/// Storage follows the reference simulator: one layer count per cell, and the columns
/// layer-major, column `k` of cell `(x, y)` at index `x + y * width + k * width * height`.
/// Only the first `layer_count(x, y)` layers of a cell are meaningful; the other slots hold
/// whatever the source held (zeros after [`Mlhm::set_cell`]). Cell `(x, y)` covers
/// `[x, x + 1) x [y, y + 1)` cell units, row 0 southernmost, as a height field's texel.
///
/// Every constructor and [`Mlhm::set_cell`] keep the invariants of [`Mlhm::validate`].
///
/// ```
/// use relief_core::{Mlhm, MlhmColumn};
/// let mut map = Mlhm::new(2, 1, 2, 1.0)?;
/// // An overhang in cell (1, 0): ground at 1 m, a 1 m air gap, rock from 2 m to 3 m.
/// map.set_cell(1, 0, &[
///     MlhmColumn::new(1.0, 0.0, 0.0, 2.0),
///     MlhmColumn::new(3.0, 0.0, 0.0, f32::INFINITY),
/// ])?;
/// assert_eq!(map.layer_count(1, 0), 2);
/// assert_eq!(map.floor(1, 0, 1), 2.0);
/// assert_eq!(map.column(1, 0, 1).solid_top(), 3.0);
/// # Ok::<(), relief_core::CoreError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Mlhm {
    width: usize,
    height: usize,
    max_layers: usize,
    cell_size: f64,
    layer_counts: Vec<u8>,
    columns: Vec<MlhmColumn>,
    precision: Precision,
}

/// Largest finite f16, as f32.
const F16_MAX: f32 = 65504.0;

/// The heights that bound an [`Mlhm`] (see [`Mlhm::heights`]), in metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MlhmHeights {
    /// Lowest bedrock top of any cell's lowest column.
    pub bedrock_min: f64,
    /// Highest solid (bedrock + sand) top.
    pub solid_max: f64,
    /// Highest water top.
    pub water_max: f64,
}

impl Mlhm {
    /// A flat map: every cell one column with bedrock, sand and water 0 and ceiling `+inf`.
    ///
    /// Fails when a dimension is 0, `max_layers` is outside `1..=255`, the cell size is not a
    /// finite number > 0 or the storage would not fit in memory's address space.
    pub fn new(
        width: usize,
        height: usize,
        max_layers: usize,
        cell_size: f64,
    ) -> Result<Self, CoreError> {
        let slots = Self::check_shape(width, height, max_layers, cell_size)?;
        let mut columns = vec![MlhmColumn::default(); slots];
        for c in &mut columns[..width * height] {
            c.ceiling = f32::INFINITY;
        }
        Ok(Mlhm {
            width,
            height,
            max_layers,
            cell_size,
            layer_counts: vec![1; width * height],
            columns,
            precision: Precision::F32,
        })
    }

    /// A map from its raw parts in the reference layout: `width * height` layer counts and
    /// `width * height * max_layers` columns, layer-major. Checks the lengths and every
    /// invariant of [`Mlhm::validate`].
    pub fn from_parts(
        width: usize,
        height: usize,
        max_layers: usize,
        cell_size: f64,
        layer_counts: Vec<u8>,
        columns: Vec<MlhmColumn>,
    ) -> Result<Self, CoreError> {
        let slots = Self::check_shape(width, height, max_layers, cell_size)?;
        if layer_counts.len() != width * height || columns.len() != slots {
            return Err(CoreError::Grid(format!(
                "an MLHM of {width} x {height} cells and {max_layers} layers needs {} layer \
                 counts and {slots} columns, got {} and {}",
                width * height,
                layer_counts.len(),
                columns.len()
            )));
        }
        let map = Mlhm {
            width,
            height,
            max_layers,
            cell_size,
            layer_counts,
            columns,
            precision: Precision::F32,
        };
        map.validate()?;
        Ok(map)
    }

    /// As [`Mlhm::from_parts`], after closing violations of the ordering invariants no larger
    /// than `slack` metres, as f32 arithmetic leaves them in the reference simulator's scenes
    /// (a water top one ulp above its ceiling, a ceiling a fraction of a millimetre above the
    /// next bedrock). For every column `k` below a cell's top, in this order:
    ///
    /// - a ceiling above the next column's bedrock by at most `slack` is lowered to it;
    /// - a water top above the ceiling by at most `slack` raises the ceiling to the water top
    ///   when that stays at or below the next bedrock, else lowers the water (to the ceiling
    ///   minus the solid top, then ulp by ulp while the f32 sum still exceeds the ceiling).
    ///
    /// Larger violations are left for [`Mlhm::validate`] to refuse. Returns the map and the
    /// number of values changed.
    pub fn from_parts_with_slack(
        width: usize,
        height: usize,
        max_layers: usize,
        cell_size: f64,
        layer_counts: Vec<u8>,
        mut columns: Vec<MlhmColumn>,
        slack: f32,
    ) -> Result<(Self, usize), CoreError> {
        let cells = width.saturating_mul(height);
        let mut changed = 0;
        if layer_counts.len() == cells && columns.len() == cells.saturating_mul(max_layers) {
            for (i, &n) in layer_counts.iter().enumerate() {
                let n = usize::from(n).min(max_layers);
                for k in 0..n.saturating_sub(1) {
                    let next_bedrock = columns[i + (k + 1) * cells].bedrock;
                    changed += close_slack(&mut columns[i + k * cells], next_bedrock, slack);
                }
            }
        }
        let map = Self::from_parts(width, height, max_layers, cell_size, layer_counts, columns)?;
        Ok((map, changed))
    }

    /// Checks dimensions, layer count and cell size; returns the number of column slots.
    fn check_shape(
        width: usize,
        height: usize,
        max_layers: usize,
        cell_size: f64,
    ) -> Result<usize, CoreError> {
        if width == 0 || height == 0 {
            return Err(CoreError::Grid(format!("an MLHM of {width} x {height} cells is empty")));
        }
        if !(1..=255).contains(&max_layers) {
            return Err(CoreError::Parameter {
                name: "MLHM max layer count",
                reason: format!("{max_layers} is outside 1..=255"),
            });
        }
        if !(cell_size.is_finite() && cell_size > 0.0) {
            return Err(CoreError::Parameter {
                name: "MLHM cell size",
                reason: format!("{cell_size} is not a finite number > 0"),
            });
        }
        width
            .checked_mul(height)
            .and_then(|n| n.checked_mul(max_layers))
            .filter(|&n| n.checked_mul(std::mem::size_of::<MlhmColumn>()).is_some())
            .ok_or_else(|| {
                CoreError::Grid(format!(
                    "an MLHM of {width} x {height} cells and {max_layers} layers is too large"
                ))
            })
    }

    /// Cells along x.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Cells along y.
    pub fn height(&self) -> usize {
        self.height
    }

    /// Largest number of columns a cell may hold (L), the number of stored layer planes.
    pub fn max_layers(&self) -> usize {
        self.max_layers
    }

    /// Horizontal size of a cell, metres.
    pub fn cell_size(&self) -> f64 {
        self.cell_size
    }

    /// The precision the values are held at.
    pub fn precision(&self) -> Precision {
        self.precision
    }

    /// The heights that bound the map: the lowest bedrock top of any cell's lowest column, and
    /// the highest solid and water tops (infinite for a map with no cells).
    pub fn heights(&self) -> MlhmHeights {
        let mut heights = MlhmHeights {
            bedrock_min: f64::INFINITY,
            solid_max: f64::NEG_INFINITY,
            water_max: f64::NEG_INFINITY,
        };
        for y in 0..self.height {
            for x in 0..self.width {
                for (k, c) in self.cell_columns(x, y).enumerate() {
                    if k == 0 {
                        heights.bedrock_min = heights.bedrock_min.min(c.bedrock as f64);
                    }
                    heights.solid_max = heights.solid_max.max(c.solid_top() as f64);
                    heights.water_max = heights.water_max.max(c.water_top() as f64);
                }
            }
        }
        heights
    }

    /// The per-cell layer counts, index `x + y * width`.
    pub fn layer_counts(&self) -> &[u8] {
        &self.layer_counts
    }

    /// All column slots, layer-major (index `x + y * width + k * width * height`), including
    /// the unused slots above each cell's layer count.
    pub fn raw_columns(&self) -> &[MlhmColumn] {
        &self.columns
    }

    /// Index of column `k` of cell `(x, y)` in [`Mlhm::raw_columns`].
    #[inline]
    pub fn index(&self, x: usize, y: usize, k: usize) -> usize {
        x + y * self.width + k * self.width * self.height
    }

    /// Number of columns of cell `(x, y)`.
    ///
    /// # Panics
    /// When `(x, y)` is outside the grid.
    #[inline]
    pub fn layer_count(&self, x: usize, y: usize) -> usize {
        assert!(x < self.width && y < self.height, "cell ({x}, {y}) outside the grid");
        usize::from(self.layer_counts[x + y * self.width])
    }

    /// Column `k` of cell `(x, y)`.
    ///
    /// # Panics
    /// When `(x, y)` is outside the grid or `k >= layer_count(x, y)`.
    #[inline]
    pub fn column(&self, x: usize, y: usize, k: usize) -> MlhmColumn {
        let n = self.layer_count(x, y);
        assert!(k < n, "column {k} of cell ({x}, {y}), which has {n}");
        self.columns[self.index(x, y, k)]
    }

    /// The columns of cell `(x, y)`, bottom to top.
    ///
    /// # Panics
    /// When `(x, y)` is outside the grid.
    pub fn cell_columns(
        &self,
        x: usize,
        y: usize,
    ) -> impl ExactSizeIterator<Item = MlhmColumn> + '_ {
        let n = self.layer_count(x, y);
        (0..n).map(move |k| self.columns[self.index(x, y, k)])
    }

    /// The floor of column `k` of cell `(x, y)`: the ceiling of column `k - 1`, or minus
    /// infinity for `k = 0`.
    ///
    /// # Panics
    /// As [`Mlhm::column`].
    pub fn floor(&self, x: usize, y: usize, k: usize) -> f32 {
        if k == 0 {
            let _ = self.column(x, y, 0);
            f32::NEG_INFINITY
        } else {
            let _ = self.column(x, y, k);
            self.columns[self.index(x, y, k - 1)].ceiling
        }
    }

    /// Replaces the columns of cell `(x, y)` by `columns` (bottom to top); the slots above
    /// are zeroed. The columns are checked as [`Mlhm::validate`] checks a cell, and the map is
    /// left unchanged when they fail. Setting a cell makes the map's precision
    /// [`Precision::F32`] unless every value is an f16 and the map was [`Precision::F16`].
    pub fn set_cell(
        &mut self,
        x: usize,
        y: usize,
        columns: &[MlhmColumn],
    ) -> Result<(), CoreError> {
        if x >= self.width || y >= self.height {
            return Err(CoreError::Parameter {
                name: "MLHM cell",
                reason: format!("({x}, {y}) is outside the {} x {} grid", self.width, self.height),
            });
        }
        check_layer_count(x, y, columns.len(), self.max_layers)?;
        check_cell(x, y, columns)?;
        self.layer_counts[x + y * self.width] = columns.len() as u8;
        for k in 0..self.max_layers {
            let i = self.index(x, y, k);
            self.columns[i] = columns.get(k).copied().unwrap_or_default();
        }
        if self.precision == Precision::F16 && !columns.iter().all(|c| is_f16_column(*c)) {
            self.precision = Precision::F32;
        }
        Ok(())
    }

    /// Checks every invariant; the first failure names the cell `(x, y)` and the column:
    ///
    /// - each layer count lies in `1..=max_layers`;
    /// - bedrock, sand and water are finite, and so is the ceiling of every column but the top;
    /// - sand and water are >= 0;
    /// - the water top (`bedrock + sand + water`) is <= the column's ceiling;
    /// - the ceiling of column `k` is <= the bedrock top of column `k + 1`;
    /// - the topmost column's ceiling is `+inf`.
    pub fn validate(&self) -> Result<(), CoreError> {
        let mut cell = Vec::with_capacity(self.max_layers);
        for y in 0..self.height {
            for x in 0..self.width {
                let n = usize::from(self.layer_counts[x + y * self.width]);
                check_layer_count(x, y, n, self.max_layers)?;
                cell.clear();
                cell.extend((0..n).map(|k| self.columns[self.index(x, y, k)]));
                check_cell(x, y, &cell)?;
            }
        }
        Ok(())
    }

    /// This map at `precision`. [`Precision::F32`], or a map already at [`Precision::F16`],
    /// returns it as it is. [`Precision::F16`]
    /// rounds every value to an f16, conservatively for rendering bounds:
    ///
    /// - bedrock, sand and water are rounded up, so each column's solid top and water top
    ///   (f32 sums of the rounded values) are >= the original ones;
    /// - ceilings below the top are rounded down, so each column's floor is <= the original;
    /// - where rounding closes an air gap (the rounded water top of column `k` exceeds its
    ///   rounded ceiling, i.e. the gap was thinner than f16's resolution there), columns `k`
    ///   and `k + 1` are merged: the merged column keeps column `k`'s floor and column `k + 1`'s
    ///   rounded values, so column `k`'s sand, water and the gap become bedrock.
    ///
    /// Hence every point that is solid in this map is solid in the rounded one, and every point
    /// that is solid or water here is solid or water there: water may become solid and air may
    /// become water or solid, never the reverse. Boxes and hierarchy bounds for the solids and
    /// solids + water modes computed from the rounded map enclose this map's. Bounds of air
    /// (the start of air used for rays inside water) are *not* conservative this way. The
    /// rounded map satisfies every invariant of [`Mlhm::validate`]; a cell may lose columns.
    ///
    /// Fails when a finite value lies outside f16's range (+-65504), naming cell and column.
    pub fn to_precision(&self, precision: Precision) -> Result<Mlhm, CoreError> {
        if precision == Precision::F32 || self.precision == Precision::F16 {
            return Ok(self.clone());
        }
        let cells = self.width * self.height;
        let mut columns = vec![MlhmColumn::default(); self.columns.len()];
        let mut layer_counts = self.layer_counts.clone();
        for (i, count) in layer_counts.iter_mut().enumerate() {
            let (x, y, n) = (i % self.width, i / self.width, usize::from(*count));
            let (mut k, mut kept) = (0, 0);
            while k < n {
                let mut r = round_column(self.columns[i + k * cells], x, y, k)?;
                // The top column's ceiling is +inf, so this ends.
                while r.water_top() > r.ceiling && k + 1 < n {
                    k += 1;
                    r = round_column(self.columns[i + k * cells], x, y, k)?;
                }
                columns[i + kept * cells] = r;
                kept += 1;
                k += 1;
            }
            *count = kept as u8;
        }
        let out = Mlhm { columns, layer_counts, precision: Precision::F16, ..self.clone_shape() };
        debug_assert_eq!(out.validate(), Ok(()));
        Ok(out)
    }

    /// An empty map of this one's shape (no storage), to be completed by the caller.
    fn clone_shape(&self) -> Mlhm {
        Mlhm {
            width: self.width,
            height: self.height,
            max_layers: self.max_layers,
            cell_size: self.cell_size,
            layer_counts: Vec::new(),
            columns: Vec::new(),
            precision: self.precision,
        }
    }
}

/// Refuses a layer count outside `1..=max`.
fn check_layer_count(x: usize, y: usize, n: usize, max: usize) -> Result<(), CoreError> {
    if (1..=max).contains(&n) {
        Ok(())
    } else {
        Err(CoreError::MlhmLayerCount { x, y, count: n, max })
    }
}

/// Checks the invariants of one cell's columns (bottom to top).
fn check_cell(x: usize, y: usize, columns: &[MlhmColumn]) -> Result<(), CoreError> {
    let bad = |k: usize, reason: String| CoreError::MlhmColumn { x, y, column: k, reason };
    for (k, c) in columns.iter().enumerate() {
        let top = k + 1 == columns.len();
        for (name, v) in [("bedrock", c.bedrock), ("sand", c.sand), ("water", c.water)] {
            if !v.is_finite() {
                return Err(bad(k, format!("{name} is {v}")));
            }
        }
        if c.sand < 0.0 {
            return Err(bad(k, format!("sand thickness {} is negative", c.sand)));
        }
        if c.water < 0.0 {
            return Err(bad(k, format!("water thickness {} is negative", c.water)));
        }
        if top {
            if c.ceiling != f32::INFINITY {
                return Err(bad(k, format!("the top column's ceiling is {}, not +inf", c.ceiling)));
            }
        } else if !c.ceiling.is_finite() {
            return Err(bad(k, format!("ceiling is {} below the top column", c.ceiling)));
        }
        if c.water_top() > c.ceiling {
            return Err(bad(
                k,
                format!("water top {} is above the ceiling {}", c.water_top(), c.ceiling),
            ));
        }
        if let Some(next) = columns.get(k + 1) {
            if c.ceiling > next.bedrock {
                return Err(bad(
                    k,
                    format!(
                        "ceiling {} is above the bedrock top {} of column {}",
                        c.ceiling,
                        next.bedrock,
                        k + 1
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// Closes the slack of column `c` below a column whose bedrock top is `next_bedrock` (see
/// [`Mlhm::from_parts_with_slack`]); returns the number of values changed.
fn close_slack(c: &mut MlhmColumn, next_bedrock: f32, slack: f32) -> usize {
    let within = |excess: f32| excess > 0.0 && excess <= slack;
    let mut changed = 0;
    if within(c.ceiling - next_bedrock) {
        c.ceiling = next_bedrock;
        changed += 1;
    }
    if within(c.water_top() - c.ceiling) {
        changed += 1;
        if c.water_top() <= next_bedrock {
            c.ceiling = c.water_top();
        } else {
            c.water = (c.ceiling - c.solid_top()).max(0.0);
            while c.water > 0.0 && c.water_top() > c.ceiling {
                c.water = f32::from_bits(c.water.to_bits() - 1);
            }
        }
    }
    changed
}

/// Whether every value of `c` is exactly an f16 (infinities included).
fn is_f16_column(c: MlhmColumn) -> bool {
    c.to_array().iter().all(|&v| f16::from_f32(v).to_f32() == v)
}

/// `c` rounded to f16: bedrock, sand and water up, a finite ceiling down, +inf kept.
fn round_column(c: MlhmColumn, x: usize, y: usize, k: usize) -> Result<MlhmColumn, CoreError> {
    for v in c.to_array() {
        if v.is_finite() && v.abs() > F16_MAX {
            return Err(CoreError::MlhmColumn {
                x,
                y,
                column: k,
                reason: format!("{v} is outside the f16 range +-65504"),
            });
        }
    }
    let ceiling = if c.ceiling.is_finite() { f16_down(c.ceiling) } else { c.ceiling };
    Ok(MlhmColumn::new(f16_up(c.bedrock), f16_up(c.sand), f16_up(c.water), ceiling))
}

/// The smallest f16 >= `v` (finite `v` within f16's range), as f32.
fn f16_up(v: f32) -> f32 {
    let h = f16::from_f32(v);
    if h.to_f32() < v {
        next_up(h).to_f32()
    } else {
        h.to_f32()
    }
}

/// The largest f16 <= `v` (finite `v` within f16's range), as f32.
fn f16_down(v: f32) -> f32 {
    -f16_up(-v)
}

/// The next f16 above a finite `h`.
fn next_up(h: f16) -> f16 {
    let bits = h.to_bits();
    if bits & 0x7fff == 0 {
        f16::from_bits(1)
    } else if bits & 0x8000 == 0 {
        f16::from_bits(bits + 1)
    } else {
        f16::from_bits(bits - 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const INF: f32 = f32::INFINITY;

    fn col(b: f32, s: f32, w: f32, c: f32) -> MlhmColumn {
        MlhmColumn::new(b, s, w, c)
    }

    /// A 3 x 2 map whose cell (2, 1) holds three columns.
    fn sample() -> Mlhm {
        let mut map = Mlhm::new(3, 2, 4, 0.5).unwrap();
        for y in 0..2 {
            for x in 0..3 {
                map.set_cell(x, y, &[col(x as f32, 0.5, 0.25 * y as f32, INF)]).unwrap();
            }
        }
        map.set_cell(
            2,
            1,
            &[col(1.0, 0.5, 0.5, 3.0), col(4.0, 0.0, 1.0, 6.0), col(7.0, 1.0, 0.0, INF)],
        )
        .unwrap();
        map
    }

    #[test]
    fn layout_is_layer_major_as_the_reference() {
        let map = sample();
        assert_eq!(map.index(2, 1, 2), 2 + 3 + 2 * 6);
        assert_eq!(map.raw_columns().len(), 3 * 2 * 4);
        assert_eq!(map.raw_columns()[2 + 3 + 6], col(4.0, 0.0, 1.0, 6.0));
        assert_eq!(map.layer_counts(), &[1, 1, 1, 1, 1, 3]);
        assert_eq!(map.raw_columns()[2 + 3 + 3 * 6], MlhmColumn::default());
    }

    #[test]
    fn accessors_give_tops_and_floors() {
        let map = sample();
        assert_eq!(map.layer_count(2, 1), 3);
        let c = map.column(2, 1, 0);
        assert_eq!((c.solid_top(), c.water_top()), (1.5, 2.0));
        assert_eq!(map.floor(2, 1, 0), f32::NEG_INFINITY);
        assert_eq!(map.floor(2, 1, 2), 6.0);
        let cols: Vec<_> = map.cell_columns(2, 1).collect();
        assert_eq!(cols.len(), 3);
        assert_eq!(cols[1].ceiling, 6.0);
        assert_eq!(map.cell_columns(0, 0).len(), 1);
        map.validate().unwrap();
    }

    #[test]
    fn from_parts_round_trips_and_checks_lengths() {
        let map = sample();
        let back =
            Mlhm::from_parts(3, 2, 4, 0.5, map.layer_counts().to_vec(), map.raw_columns().to_vec())
                .unwrap();
        assert_eq!(back, map);
        let err = Mlhm::from_parts(3, 2, 4, 0.5, vec![1; 6], vec![]).unwrap_err();
        assert!(matches!(err, CoreError::Grid(_)), "{err}");
        assert!(Mlhm::new(0, 2, 4, 1.0).is_err());
        assert!(Mlhm::new(2, 2, 0, 1.0).is_err());
        assert!(Mlhm::new(2, 2, 256, 1.0).is_err());
        assert!(Mlhm::new(2, 2, 4, f64::NAN).is_err());
        assert!(Mlhm::new(usize::MAX, 2, 4, 1.0).is_err());
    }

    /// The error of setting cell (2, 1) to `columns`, which must be refused.
    fn refused(columns: &[MlhmColumn]) -> String {
        let mut map = sample();
        let before = map.clone();
        let err = map.set_cell(2, 1, columns).unwrap_err();
        assert_eq!(map, before, "a refused cell must leave the map unchanged");
        err.to_string()
    }

    #[test]
    fn validation_errors_name_the_cell_and_the_column() {
        let cases: [(&[MlhmColumn], &str, &str); 7] = [
            (&[col(f32::NAN, 0.0, 0.0, INF)], "column 0", "bedrock is NaN"),
            (&[col(0.0, 0.0, 0.0, 2.0), col(3.0, -1.0, 0.0, INF)], "column 1", "sand"),
            (&[col(0.0, 0.0, -0.5, INF)], "column 0", "water thickness -0.5"),
            (&[col(0.0, 1.0, 1.5, 2.0), col(3.0, 0.0, 0.0, INF)], "column 0", "water top 2.5"),
            (&[col(0.0, 0.0, 0.0, 4.0), col(3.0, 0.0, 0.0, INF)], "column 0", "bedrock top 3"),
            (&[col(0.0, 0.0, 0.0, 5.0)], "column 0", "not +inf"),
            (&[col(0.0, 0.0, 0.0, INF), col(3.0, 0.0, 0.0, INF)], "column 0", "ceiling is inf"),
        ];
        for (columns, column, reason) in cases {
            let msg = refused(columns);
            assert!(msg.contains("cell (2, 1)"), "{msg}");
            assert!(msg.contains(column), "{msg}");
            assert!(msg.contains(reason), "{msg}");
        }
        let msg = refused(&[]);
        assert!(msg.contains("cell (2, 1)") && msg.contains("0 columns"), "{msg}");
        let msg = refused(&[col(0.0, 0.0, 0.0, 1.0); 5]);
        assert!(msg.contains("5 columns") && msg.contains("1..=4"), "{msg}");
        assert!(sample().set_cell(3, 0, &[col(0.0, 0.0, 0.0, INF)]).is_err());
    }

    #[test]
    fn validate_finds_bad_raw_data() {
        let map = sample();
        let mut columns = map.raw_columns().to_vec();
        columns[map.index(1, 1, 0)].water = f32::INFINITY;
        let err = Mlhm::from_parts(3, 2, 4, 0.5, map.layer_counts().to_vec(), columns)
            .unwrap_err()
            .to_string();
        assert!(err.contains("cell (1, 1)") && err.contains("column 0"), "{err}");
        let mut counts = map.layer_counts().to_vec();
        counts[1] = 0;
        let err = Mlhm::from_parts(3, 2, 4, 0.5, counts, map.raw_columns().to_vec())
            .unwrap_err()
            .to_string();
        assert!(err.contains("cell (1, 0)"), "{err}");
    }

    #[test]
    fn f16_rounding_is_conservative_and_keeps_the_invariants() {
        let mut map = Mlhm::new(2, 1, 3, 1.0).unwrap();
        let original = [col(10.001, 0.3337, 0.1, 20.003), col(30.0007, 1.0001, 2.2, INF)];
        map.set_cell(0, 0, &original).unwrap();
        // An air gap far thinner than f16's resolution at 1000 m (0.5 m).
        map.set_cell(1, 0, &[col(1000.1, 0.0, 0.0, 1000.2), col(1000.3, 0.1, 0.0, INF)]).unwrap();
        let rounded = map.to_precision(Precision::F16).unwrap();
        assert_eq!(rounded.precision(), Precision::F16);
        rounded.validate().unwrap();
        for (k, c) in original.iter().enumerate() {
            let r = rounded.column(0, 0, k);
            assert!(r.to_array().iter().all(|&v| f16::from_f32(v).to_f32() == v));
            assert!(r.solid_top() >= c.solid_top() && r.water_top() >= c.water_top());
            assert!(r.ceiling <= c.ceiling);
        }
        assert_eq!(rounded.column(0, 0, 0).ceiling, 20.0);
        // The closed gap merged the two columns into one covering both.
        assert_eq!(rounded.layer_count(1, 0), 1);
        let merged = rounded.column(1, 0, 0);
        assert!(merged.solid_top() >= 1000.4 && merged.ceiling == INF);
        // Already f16: unchanged.
        assert_eq!(rounded.to_precision(Precision::F16).unwrap(), rounded);
        assert_eq!(map.to_precision(Precision::F32).unwrap(), map);
    }

    #[test]
    fn slack_of_f32_arithmetic_is_closed_and_larger_violations_refused() {
        let water_top = 12.617576f32 + 0.0111233 + 2.3297486;
        let below = f32::from_bits(water_top.to_bits() - 1);
        let cells = |first: MlhmColumn, second: MlhmColumn| {
            let columns = vec![first, second];
            Mlhm::from_parts_with_slack(1, 1, 2, 1.0, vec![2], columns, 1e-3)
        };
        let top = col(23.3, 0.0, 0.5, INF);
        let (map, changed) = cells(col(12.617576, 0.0111233, 2.3297486, below), top).unwrap();
        assert_eq!((changed, map.column(0, 0, 0).ceiling), (1, water_top));
        let (map, changed) = cells(col(22.5, 0.0, 0.0, 23.3003), top).unwrap();
        assert_eq!((changed, map.column(0, 0, 0).ceiling), (1, 23.3));
        let (map, changed) = cells(col(22.5, 0.0, 0.80001, 23.3), top).unwrap();
        let c = map.column(0, 0, 0);
        assert!(changed == 1 && c.water_top() <= c.ceiling && c.water > 0.79);
        let err = cells(col(22.5, 0.0, 0.9, 23.3), top).unwrap_err().to_string();
        assert!(err.contains("cell (0, 0), column 0"), "{err}");
    }

    #[test]
    fn f16_rounding_refuses_values_beyond_its_range() {
        let mut map = Mlhm::new(1, 2, 1, 1.0).unwrap();
        map.set_cell(0, 1, &[col(7e4, 0.0, 0.0, INF)]).unwrap();
        let err = map.to_precision(Precision::F16).unwrap_err().to_string();
        assert!(err.contains("cell (0, 1)") && err.contains("column 0"), "{err}");
    }

    #[test]
    fn rounding_helpers_bracket_values() {
        for v in [0.0, -0.0, 1e-9, -1e-9, 0.1, -0.1, 1000.1, -1000.1, 65504.0, -65504.0] {
            let (up, down) = (f16_up(v), f16_down(v));
            assert!(down <= v && v <= up, "{v}: {down} {up}");
            assert_eq!(f16::from_f32(up).to_f32(), up);
            assert_eq!(f16::from_f32(down).to_f32(), down);
        }
        assert_eq!(f16_up(1.0), 1.0);
    }
}
