//! Reading and writing an [`Mlhm`]: its dimensions and precision, the heights that bound it
//! ([`MlhmHeights`]), its layer counts and columns in the reference layout, and setting a
//! cell's columns (checked as [`Mlhm::validate`] checks a cell).

use super::invariants::{check_cell, check_layer_count};
use super::precision::is_f16_column;
use super::{Mlhm, MlhmColumn, Precision};
use crate::CoreError;

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

    /// The floor of column `k` of cell `(x, y)`: the ceiling of column `k - 1`, or the map's
    /// [base](Mlhm::base) (minus infinity unless set) for `k = 0`.
    ///
    /// # Panics
    /// As [`Mlhm::column`].
    pub fn floor(&self, x: usize, y: usize, k: usize) -> f32 {
        if k == 0 {
            let _ = self.column(x, y, 0);
            self.base
        } else {
            let _ = self.column(x, y, k);
            self.columns[self.index(x, y, k - 1)].ceiling
        }
    }

    /// The floor of every cell's lowest column, where the solid ends below: minus infinity
    /// (the lowest columns reach down forever) unless [`Mlhm::set_base`] set it. The box
    /// tracers, [`Mlhm::floor`], the volumes ([`Mlhm::material_volumes`],
    /// [`Mlhm::blurred_volumes`]) and so the smooth surface clip the solid there.
    pub fn base(&self) -> f32 {
        self.base
    }

    /// Clips the solid at `base` below: the floor of every cell's lowest column. A base above
    /// the lowest bedrock top is lowered to it (a column is never cut into), as is a NaN
    /// base; minus infinity lifts no clip.
    ///
    /// ```
    /// use relief_core::{Mlhm, MlhmColumn};
    /// let mut map = Mlhm::new(2, 1, 1, 1.0)?;
    /// map.set_cell(0, 0, &[MlhmColumn::new(3.0, 0.0, 0.0, f32::INFINITY)])?;
    /// map.set_cell(1, 0, &[MlhmColumn::new(5.0, 0.0, 0.0, f32::INFINITY)])?;
    /// map.set_base(2.0);
    /// assert_eq!((map.base(), map.floor(1, 0, 0)), (2.0, 2.0));
    /// map.set_base(4.0);
    /// assert_eq!(map.base(), 3.0);
    /// # Ok::<(), relief_core::CoreError>(())
    /// ```
    pub fn set_base(&mut self, base: f32) {
        let lowest = self.heights().bedrock_min as f32;
        self.base = if base <= lowest { base } else { lowest };
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
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mlhm::fixtures::{col, sample};

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
}
