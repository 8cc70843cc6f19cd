//! The invariants of a simulation state: those of an MLHM ([`Mlhm::validate`]) on every
//! cell's columns, and finite planes (what [`ErosionState::from_mlhm`] accepts back), checked
//! after every step and, in a diagnostic run, after every stage of a step ([`Stage`]).

use super::{ErosionError, ErosionState};
use rayon::prelude::*;
use relief_core::{Mlhm, MlhmColumn};
use std::fmt;

/// A stage of one simulation step, in the order a step runs them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Stage {
    /// Step 1: rain on each cell's top column.
    Rain,
    /// Step 2: virtual pipes and sand slippage (fluxes only).
    Pipes,
    /// Step 3: transport of water, sand and sediment; evaporation; petrification.
    Transport,
    /// Step 4a: horizontal erosion (bedrock beside water into the neighbour's sand).
    HorizontalErosion,
    /// Step 4b: column splits at the windows horizontal erosion exposed.
    ColumnSplit,
    /// Step 5: vertical erosion and deposition, damage recovery.
    VerticalErosion,
    /// Step 6: the support check's passes, and its end with collapses.
    Support,
}

impl Stage {
    /// Every stage, in the order of a step.
    pub const ALL: [Stage; 7] = [
        Stage::Rain,
        Stage::Pipes,
        Stage::Transport,
        Stage::HorizontalErosion,
        Stage::ColumnSplit,
        Stage::VerticalErosion,
        Stage::Support,
    ];
}

impl fmt::Display for Stage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Stage::Rain => "rain",
            Stage::Pipes => "pipes",
            Stage::Transport => "transport",
            Stage::HorizontalErosion => "horizontal erosion",
            Stage::ColumnSplit => "column split",
            Stage::VerticalErosion => "vertical erosion",
            Stage::Support => "support check",
        })
    }
}

/// The text naming where a step broke the invariants, for [`ErosionError::Invariant`].
pub(super) fn after_stage(stage: &Option<Stage>) -> String {
    match stage {
        Some(stage) => format!("after its {stage} stage"),
        None => "after it".into(),
    }
}

impl ErosionState {
    /// Checks the state's invariants: every cell's layer count and columns as
    /// [`Mlhm::validate`] checks them (the ceiling of column `k` at most the bedrock top of
    /// column `k + 1`, water tops under ceilings, ...), finite fluxes, sediment and damage, and
    /// no NaN stability. The first failure in cell order names the cell and the column; the
    /// same with any thread count.
    ///
    /// [`ErosionState::step`] runs this after every step; it costs a small fraction of one.
    pub fn validate(&self) -> Result<(), ErosionError> {
        let rows: Vec<Result<(), ErosionError>> =
            (0..self.height).into_par_iter().map(|y| self.validate_row(y)).collect();
        rows.into_iter().collect()
    }

    /// Checks the cells of row `y`: a quick pass over the row's values, and where it finds
    /// something wrong, the full check that names it.
    fn validate_row(&self, y: usize) -> Result<(), ErosionError> {
        if self.row_is_valid(y) {
            Ok(())
        } else {
            self.find_in_row(y)
        }
    }

    /// Whether row `y` keeps the invariants: the conditions of [`Mlhm::validate_cell`] and of
    /// the planes, as one `&` of comparisons per column (no branch on a value), so that
    /// the check costs a small fraction of a step.
    fn row_is_valid(&self, y: usize) -> bool {
        let (width, cells) = (self.width, self.cells());
        let mut ok = true;
        for x in 0..width {
            let i = x + y * width;
            let n = usize::from(self.layer_counts[i]);
            ok &= (1..=self.max_layers).contains(&n);
            for k in 0..n.min(self.max_layers) {
                let s = i + k * cells;
                let c = self.columns[s];
                let top = k + 1 == n;
                let next = self.columns.get(s + cells).filter(|_| !top);
                let next_bedrock = next.map_or(f32::INFINITY, |c| c.bedrock);
                let [f0, f1, f2, f3] = self.fluxes[s];
                ok &= c.bedrock.is_finite()
                    & c.sand.is_finite()
                    & c.water.is_finite()
                    & (c.sand >= 0.0)
                    & (c.water >= 0.0)
                    & if top { c.ceiling == f32::INFINITY } else { c.ceiling.is_finite() }
                    & (c.water_top() <= c.ceiling)
                    & (c.ceiling <= next_bedrock)
                    & (f0 + f1 + f2 + f3 + self.sediment[s] + self.damage[s]).is_finite()
                    & !self.stability[s].is_nan();
            }
        }
        ok
    }

    /// The first failure of row `y`, naming the cell and the column (none: `Ok`).
    fn find_in_row(&self, y: usize) -> Result<(), ErosionError> {
        let (width, cells) = (self.width, self.cells());
        let mut columns: Vec<MlhmColumn> = Vec::with_capacity(self.max_layers);
        for x in 0..width {
            let i = x + y * width;
            let n = usize::from(self.layer_counts[i]);
            columns.clear();
            columns.extend((0..n.min(self.max_layers)).map(|k| self.columns[i + k * cells]));
            if n > self.max_layers {
                // Let the MLHM check name the count.
                columns.resize(n, MlhmColumn::default());
            }
            Mlhm::validate_cell(x, y, &columns, self.max_layers)?;
            for k in 0..n {
                let s = i + k * cells;
                let at = |plane, value, reason| ErosionError::PlaneValue {
                    plane,
                    x,
                    y,
                    column: k,
                    value,
                    reason,
                };
                if let Some(&f) = self.fluxes[s].iter().find(|f| !f.is_finite()) {
                    return Err(at("flux", f, "not a finite number"));
                }
                for (plane, v) in [("sediment", self.sediment[s]), ("damage", self.damage[s])] {
                    if !v.is_finite() {
                        return Err(at(plane, v, "not a finite number"));
                    }
                }
                if self.stability[s].is_nan() {
                    return Err(at("stability", self.stability[s], "not a number"));
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn validation_names_the_cell_the_column_and_the_plane() {
        let mut state = ErosionState::from_heights(3, 2, 1.0, &[1.0; 6], 0.5, 4).unwrap();
        state.validate().unwrap();
        // Cell (2, 1) gets an overhang whose ceiling is above the bedrock of the column above.
        let i = 2 + 3;
        state.layer_counts[i] = 2;
        state.columns[i].ceiling = 3.0;
        state.columns[i + 6] = MlhmColumn::new(2.5, 0.0, 0.0, f32::INFINITY);
        let e = state.validate().unwrap_err().to_string();
        assert!(e.contains("cell (2, 1), column 0") && e.contains("bedrock top 2.5"), "{e}");
        state.columns[i + 6].bedrock = 3.0;
        state.validate().unwrap();
        state.sediment[i + 6] = f32::NAN;
        let e = state.validate().unwrap_err().to_string();
        assert!(e.contains("cell (2, 1), column 1") && e.contains("sediment"), "{e}");
    }

    #[test]
    fn the_quick_check_and_the_full_one_agree() {
        let base = {
            let mut s = ErosionState::from_heights(2, 1, 1.0, &[1.0, 2.0], 0.5, 3).unwrap();
            s.layer_counts[1] = 2;
            s.columns[1].ceiling = 3.0;
            s.columns[3] = MlhmColumn::new(4.0, 0.0, 0.0, f32::INFINITY);
            s
        };
        let breaks: [fn(&mut ErosionState); 12] = [
            |s| s.layer_counts[0] = 0,
            |s| s.layer_counts[1] = 4,
            |s| s.columns[0].bedrock = f32::NAN,
            |s| s.columns[1].sand = -1e-7,
            |s| s.columns[3].water = f32::INFINITY,
            |s| s.columns[1].ceiling = 4.5,
            |s| s.columns[1].water = 1.6,
            |s| s.columns[3].ceiling = 9.0,
            |s| s.columns[1].ceiling = f32::INFINITY,
            |s| s.fluxes[3][2] = f32::NAN,
            |s| s.damage[0] = f32::NEG_INFINITY,
            |s| s.stability[3] = f32::NAN,
        ];
        assert!(base.row_is_valid(0));
        base.validate().unwrap();
        for (case, broken) in breaks.iter().enumerate() {
            let mut s = base.clone();
            broken(&mut s);
            assert!(!s.row_is_valid(0), "case {case}");
            assert!(s.find_in_row(0).is_err(), "case {case}");
        }
    }
}
