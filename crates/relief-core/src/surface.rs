//! The two surfaces a height field can stand for, as relief's conventions define them.

use std::fmt;
use std::str::FromStr;

/// How a height field's samples define a surface.
///
/// - `Boxes` (Dick et al. 2009): texel (col, row) is a flat-topped column over its footprint
///   `[col, col+1) x [row, row+1)`.
/// - `Triangles` (Baboud et al. 2011): vertices at the texel centres; each square between four
///   neighbouring samples is split along the diagonal whose two end heights have the smaller sum
///   (`(c,r)-(c+1,r+1)` on ties).
///
/// Both stand for a solid: the region between the lowest sample and the surface, over the
/// surface's footprint. A tracer returns the first point of a ray inside that solid.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Surface {
    /// Flat-topped columns, one per texel.
    #[default]
    Boxes,
    /// Two triangles per square between four samples, split along the lower diagonal.
    Triangles,
}

impl Surface {
    /// Both surfaces, in a fixed order.
    pub const ALL: [Surface; 2] = [Surface::Boxes, Surface::Triangles];

    /// The name used on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            Surface::Boxes => "boxes",
            Surface::Triangles => "triangles",
        }
    }
}

/// Whether the `triangles` surface splits the square whose corners have the heights `a` at
/// (c, r), `b` at (c+1, r), `c` at (c, r+1) and `d` at (c+1, r+1) along its `a`-`d` diagonal
/// (else along `b`-`c`): the diagonal whose end heights have the smaller sum, `a`-`d` on ties.
/// Every tracer, mesh and shape of the `triangles` surface asks this one function.
#[inline(always)]
pub fn splits_along_ad(a: f64, b: f64, c: f64, d: f64) -> bool {
    a + d <= b + c
}

impl fmt::Display for Surface {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(self.name())
    }
}

impl FromStr for Surface {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "boxes" => Ok(Surface::Boxes),
            "triangles" => Ok(Surface::Triangles),
            other => Err(format!("unknown surface '{other}' (expected boxes or triangles)")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_honour_widths_in_tables() {
        assert_eq!(
            format!("[{:<9}][{:>9}]", Surface::Boxes, Surface::Triangles),
            "[boxes    ][triangles]"
        );
    }
}
