//! The multi-layered height map (MLHM): a grid of cells holding stacks of columns of bedrock,
//! sand, water and air, in the reference simulator's layer-major layout.
//!
//! - [`column`]: one column of a cell ([`MlhmColumn`]) and its tops;
//! - [`constructors`]: a flat map, and a map from its raw parts (with or without the slack of
//!   f32 arithmetic closed first);
//! - [`access`]: dimensions, bounding heights ([`MlhmHeights`]), layer counts and columns, and
//!   setting a cell;
//! - [`invariants`]: validation, naming the cell and the column, and the closing of slack;
//! - [`precision`]: [`Precision`] and the conservative conversion to f16;
//! - [`volume`]: exact volumes of each material inside a box ([`MaterialVolumes`]);
//! - [`blurred_volume`]: the same weighted by a blurred box ([`BlurredBox`]), smooth in the
//!   box's centre.

mod access;
mod blurred_volume;
mod column;
mod constructors;
mod invariants;
mod precision;
mod volume;

pub use access::MlhmHeights;
pub use blurred_volume::BlurredBox;
pub use column::MlhmColumn;
pub use precision::Precision;
pub use volume::MaterialVolumes;

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
    /// The floor of every cell's lowest column ([`Mlhm::base`]): minus infinity unless set.
    base: f32,
}

/// The maps the unit tests of this module's files share.
#[cfg(test)]
mod fixtures {
    use super::{Mlhm, MlhmColumn};

    pub(super) const INF: f32 = f32::INFINITY;

    pub(super) fn col(b: f32, s: f32, w: f32, c: f32) -> MlhmColumn {
        MlhmColumn::new(b, s, w, c)
    }

    /// A 3 x 2 map whose cell (2, 1) holds three columns.
    pub(super) fn sample() -> Mlhm {
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
}
