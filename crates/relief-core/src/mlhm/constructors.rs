//! Building an [`Mlhm`]: a flat map, a map from its raw parts in the reference layout
//! (checked against every invariant), the same with the slack of f32 arithmetic closed first,
//! and an empty map of another's shape.

use super::invariants::close_slack;
use super::{Mlhm, MlhmColumn, Precision};
use crate::CoreError;

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
            base: f32::NEG_INFINITY,
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
            base: f32::NEG_INFINITY,
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

    /// An empty map of this one's shape (no storage), to be completed by the caller.
    pub(super) fn clone_shape(&self) -> Mlhm {
        Mlhm {
            width: self.width,
            height: self.height,
            max_layers: self.max_layers,
            cell_size: self.cell_size,
            layer_counts: Vec::new(),
            columns: Vec::new(),
            precision: self.precision,
            base: self.base,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mlhm::fixtures::sample;

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
}
