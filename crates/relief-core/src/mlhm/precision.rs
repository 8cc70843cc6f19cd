//! The precision an [`Mlhm`]'s values are held at ([`Precision`]) and the conversion to f16,
//! conservative for rendering bounds: values rounded outward, air gaps thinner than f16's
//! resolution closed.

use super::{Mlhm, MlhmColumn};
use crate::CoreError;
use half::f16;

/// The precision an MLHM's values are held at.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Precision {
    /// Any f32 values.
    #[default]
    F32,
    /// Every value is exactly representable as an IEEE half-precision float (f16).
    F16,
}

/// Largest finite f16, as f32.
const F16_MAX: f32 = 65504.0;

impl Mlhm {
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
}

/// Whether every value of `c` is exactly an f16 (infinities included).
pub(super) fn is_f16_column(c: MlhmColumn) -> bool {
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
    use crate::mlhm::fixtures::{col, INF};

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
