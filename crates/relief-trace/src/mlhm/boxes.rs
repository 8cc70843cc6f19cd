//! The boxes an MLHM cell stands for in each intersection mode, and the exact 1D slab test of
//! one box over a ray's part inside the cell (Nilles & Müller 2025, sections 4.1 and 4.2).

use relief_core::{Mlhm, MlhmColumn};
use std::fmt;
use std::str::FromStr;

/// What an MLHM ray intersects: which materials count as "inside".
///
/// With `floor(k)` the ceiling of column `k - 1` (for `k = 0` the map's
/// [base](relief_core::Mlhm::base), minus infinity unless set), the boxes of a cell of `n`
/// columns are, closed intervals over the cell's footprint:
///
/// - [`Solids`](MlhmMode::Solids): `[floor(k), bedrock(k) + sand(k)]` for every column `k`
///   (shadow rays, rays that ignore water);
/// - [`SolidsWater`](MlhmMode::SolidsWater): `[floor(k), bedrock(k) + sand(k) + water(k)]`,
///   the visible surface that primary rays and depth output use;
/// - [`SolidsAir`](MlhmMode::SolidsAir): for rays travelling inside water, everything that is
///   not water: `[water_top(k - 1), bedrock(k) + sand(k)]` for every column `k` (the air of
///   column `k - 1`, then the solids of column `k`; `water_top(-1)` is the base), and the
///   air above the top column, `[water_top(n - 1), +inf]`. This is the paper's
///   `[a_min(k-1), s_max(k)]` with the open sky added as one more box.
///
/// A box whose top is not above its bottom (a column of zero height) holds no material and is
/// never hit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum MlhmMode {
    /// Bedrock and sand.
    Solids,
    /// Bedrock, sand and water: the visible surface.
    #[default]
    SolidsWater,
    /// Bedrock, sand and air: where a ray inside water leaves it.
    SolidsAir,
}

impl MlhmMode {
    /// Every mode, in a fixed order.
    pub const ALL: [MlhmMode; 3] = [MlhmMode::Solids, MlhmMode::SolidsWater, MlhmMode::SolidsAir];

    /// The name used in reports and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            MlhmMode::Solids => "solids",
            MlhmMode::SolidsWater => "solids-water",
            MlhmMode::SolidsAir => "solids-air",
        }
    }
}

impl fmt::Display for MlhmMode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(self.name())
    }
}

impl FromStr for MlhmMode {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        MlhmMode::ALL.into_iter().find(|m| m.name() == s).ok_or_else(|| {
            format!("unknown MLHM mode '{s}' (expected solids, solids-water or solids-air)")
        })
    }
}

/// The material of an MLHM at a hit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum MlhmMaterial {
    /// Bedrock: from a column's floor up to its bedrock top.
    Bedrock,
    /// Sand on the bedrock.
    Sand,
    /// Water on the sand (hit only in [`MlhmMode::SolidsWater`]).
    Water,
    /// Air between a water top and the ceiling (hit only in [`MlhmMode::SolidsAir`]).
    Air,
}

/// One material layer of a box: up to `top`, of `material`, belonging to column `column`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Layer {
    pub top: f64,
    pub material: MlhmMaterial,
    pub column: usize,
}

/// One box of a cell in a mode: from `bottom` up through its layers (the last layer's top is
/// the box's top). Only layers thicker than zero are kept.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ColumnBox {
    pub bottom: f64,
    layers: [Layer; 3],
    len: usize,
}

/// Which face of a box a ray enters it through.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum BoxEntry {
    /// Its top (the ray goes down).
    Top,
    /// Its bottom (the ray goes up).
    Bottom,
    /// Where the ray's part in the cell begins: a side of the cell or the ray's start.
    Segment,
}

impl ColumnBox {
    /// A box from `bottom` through `layers` (bottom to top), dropping layers of zero thickness;
    /// `None` when nothing remains.
    fn new(bottom: f64, layers: &[Layer]) -> Option<Self> {
        let placeholder = Layer { top: bottom, material: MlhmMaterial::Bedrock, column: 0 };
        let mut b = ColumnBox { bottom, layers: [placeholder; 3], len: 0 };
        let mut below = bottom;
        for &layer in layers {
            if layer.top > below {
                b.layers[b.len] = layer;
                b.len += 1;
                below = layer.top;
            }
        }
        (b.len > 0).then_some(b)
    }

    /// The box's top.
    #[inline]
    pub fn top(&self) -> f64 {
        self.layers[self.len - 1].top
    }

    /// The kept layers, bottom to top.
    #[inline]
    fn layers(&self) -> &[Layer] {
        &self.layers[..self.len]
    }

    /// The layer hit through `entry` at height `z`: the top layer through the top, the bottom
    /// one through the bottom, else the lowest layer whose top is at or above `z`.
    pub fn layer_at(&self, entry: BoxEntry, z: f64) -> Layer {
        let layers = self.layers();
        match entry {
            BoxEntry::Top => layers[layers.len() - 1],
            BoxEntry::Bottom => layers[0],
            BoxEntry::Segment => {
                *layers.iter().find(|l| z <= l.top).unwrap_or(&layers[layers.len() - 1])
            }
        }
    }

    /// The exact first parameter in `[t_enter, t_exit]` at which a ray with height
    /// `oz + t * dz` (`inv_dz = 1 / dz`) is within the box, and the face it enters through.
    #[inline]
    pub fn slab(
        &self,
        oz: f64,
        dz: f64,
        inv_dz: f64,
        t_enter: f64,
        t_exit: f64,
    ) -> Option<(f64, BoxEntry)> {
        let (bottom, top) = (self.bottom, self.top());
        if dz == 0.0 {
            return (bottom <= oz && oz <= top).then_some((t_enter, BoxEntry::Segment));
        }
        let (t_bottom, t_top) = ((bottom - oz) * inv_dz, (top - oz) * inv_dz);
        let (ta, tb, face) = if dz < 0.0 {
            (t_top, t_bottom, BoxEntry::Top)
        } else {
            (t_bottom, t_top, BoxEntry::Bottom)
        };
        let (t0, t1) = (ta.max(t_enter), tb.min(t_exit));
        if t0 <= t1 {
            Some(if ta >= t_enter { (ta, face) } else { (t_enter, BoxEntry::Segment) })
        } else {
            None
        }
    }
}

/// Calls `f` with each box of cell `(x, y)` in `mode`, bottom to top; stops when `f` returns
/// `true`.
pub(crate) fn for_each_box(
    map: &Mlhm,
    x: usize,
    y: usize,
    mode: MlhmMode,
    mut f: impl FnMut(&ColumnBox) -> bool,
) {
    let mut below: Option<MlhmColumn> = None;
    let base = map.base() as f64;
    for (k, c) in map.cell_columns(x, y).enumerate() {
        let layer = |top: f32, material, column| Layer { top: top as f64, material, column };
        let bedrock = layer(c.bedrock, MlhmMaterial::Bedrock, k);
        let sand = layer(c.solid_top(), MlhmMaterial::Sand, k);
        let boxed = match mode {
            MlhmMode::Solids | MlhmMode::SolidsWater => {
                let floor = below.map_or(base, |b| b.ceiling as f64);
                let water = layer(c.water_top(), MlhmMaterial::Water, k);
                let n = if mode == MlhmMode::Solids { 2 } else { 3 };
                ColumnBox::new(floor, &[bedrock, sand, water][..n])
            }
            MlhmMode::SolidsAir => match below {
                None => ColumnBox::new(base, &[bedrock, sand]),
                Some(b) => {
                    let air = layer(b.ceiling, MlhmMaterial::Air, k - 1);
                    ColumnBox::new(b.water_top() as f64, &[air, bedrock, sand])
                }
            },
        };
        if boxed.is_some_and(|b| f(&b)) {
            return;
        }
        below = Some(c);
    }
    if let (MlhmMode::SolidsAir, Some(top)) = (mode, below) {
        let k = map.layer_count(x, y) - 1;
        let sky = Layer { top: f64::INFINITY, material: MlhmMaterial::Air, column: k };
        if let Some(b) = ColumnBox::new(top.water_top() as f64, &[sky]) {
            f(&b);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const INF: f32 = f32::INFINITY;

    fn boxes(map: &Mlhm, mode: MlhmMode) -> Vec<ColumnBox> {
        let mut out = Vec::new();
        for_each_box(map, 0, 0, mode, |b| {
            out.push(*b);
            false
        });
        out
    }

    #[test]
    fn boxes_follow_the_three_modes() {
        let mut map = Mlhm::new(1, 1, 3, 1.0).unwrap();
        map.set_cell(
            0,
            0,
            &[MlhmColumn::new(1.0, 0.5, 0.5, 3.0), MlhmColumn::new(4.0, 0.0, 1.0, INF)],
        )
        .unwrap();
        let spans =
            |mode| boxes(&map, mode).iter().map(|b| (b.bottom, b.top())).collect::<Vec<_>>();
        let ninf = f64::NEG_INFINITY;
        assert_eq!(spans(MlhmMode::Solids), vec![(ninf, 1.5), (3.0, 4.0)]);
        assert_eq!(spans(MlhmMode::SolidsWater), vec![(ninf, 2.0), (3.0, 5.0)]);
        assert_eq!(spans(MlhmMode::SolidsAir), vec![(ninf, 1.5), (2.0, 4.0), (5.0, f64::INFINITY)]);
        let air = boxes(&map, MlhmMode::SolidsAir)[1];
        assert_eq!(air.layer_at(BoxEntry::Bottom, 2.0).material, MlhmMaterial::Air);
        assert_eq!(air.layer_at(BoxEntry::Bottom, 2.0).column, 0);
        assert_eq!(air.layer_at(BoxEntry::Segment, 3.5).material, MlhmMaterial::Bedrock);
        // Zero sand: the top of the second column is bedrock.
        assert_eq!(air.layer_at(BoxEntry::Top, 4.0).material, MlhmMaterial::Bedrock);
    }

    #[test]
    fn slab_enters_through_the_right_face() {
        let b = ColumnBox::new(1.0, &[Layer { top: 2.0, material: MlhmMaterial::Sand, column: 0 }])
            .unwrap();
        assert_eq!(b.slab(5.0, -1.0, -1.0, 0.0, 10.0), Some((3.0, BoxEntry::Top)));
        assert_eq!(b.slab(0.0, 1.0, 1.0, 0.0, 10.0), Some((1.0, BoxEntry::Bottom)));
        assert_eq!(b.slab(1.5, 1.0, 1.0, 0.0, 10.0), Some((0.0, BoxEntry::Segment)));
        assert_eq!(b.slab(1.5, 0.0, f64::INFINITY, 2.0, 3.0), Some((2.0, BoxEntry::Segment)));
        assert_eq!(b.slab(5.0, -1.0, -1.0, 0.0, 2.5), None);
        assert_eq!(b.slab(2.5, 0.0, f64::INFINITY, 0.0, 1.0), None);
    }
}
