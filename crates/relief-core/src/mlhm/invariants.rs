//! The invariants of an [`Mlhm`]: validation of every cell, the first failure naming the cell
//! and the column, and the closing of the small violations f32 arithmetic leaves in the
//! reference simulator's scenes.

use super::{Mlhm, MlhmColumn};
use crate::CoreError;

impl Mlhm {
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

    /// Checks the invariants of [`Mlhm::validate`] on the columns of one cell `(x, y)`
    /// (bottom to top) of a map with room for `max_layers` columns per cell; the error names
    /// the cell and the column. For code that keeps a map's columns in its own layout (as the
    /// erosion simulation does) and checks them without building an [`Mlhm`].
    pub fn validate_cell(
        x: usize,
        y: usize,
        columns: &[MlhmColumn],
        max_layers: usize,
    ) -> Result<(), CoreError> {
        check_layer_count(x, y, columns.len(), max_layers)?;
        check_cell(x, y, columns)
    }
}

/// Refuses a layer count outside `1..=max`.
pub(super) fn check_layer_count(x: usize, y: usize, n: usize, max: usize) -> Result<(), CoreError> {
    if (1..=max).contains(&n) {
        Ok(())
    } else {
        Err(CoreError::MlhmLayerCount { x, y, count: n, max })
    }
}

/// Checks the invariants of one cell's columns (bottom to top).
pub(super) fn check_cell(x: usize, y: usize, columns: &[MlhmColumn]) -> Result<(), CoreError> {
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
pub(super) fn close_slack(c: &mut MlhmColumn, next_bedrock: f32, slack: f32) -> usize {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mlhm::fixtures::{col, sample, INF};

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
}
