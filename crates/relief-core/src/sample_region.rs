//! A rectangle of a grid's samples: what an edit of a dynamic height field touched.

/// Columns `col0..col1` and rows `row0..row1` of a grid (ends exclusive). Edits return the
/// region they changed, so that renderers update only what lies over it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct SampleRegion {
    /// First column.
    pub col0: usize,
    /// First row.
    pub row0: usize,
    /// One past the last column.
    pub col1: usize,
    /// One past the last row.
    pub row1: usize,
}

impl SampleRegion {
    /// The region of columns `col0..col1` and rows `row0..row1`.
    pub fn new(col0: usize, row0: usize, col1: usize, row1: usize) -> Self {
        SampleRegion { col0, row0, col1, row1 }
    }

    /// Every sample of a `width x height` grid.
    pub fn whole(width: usize, height: usize) -> Self {
        SampleRegion::new(0, 0, width, height)
    }

    /// Whether the region holds no sample.
    pub fn is_empty(&self) -> bool {
        self.col0 >= self.col1 || self.row0 >= self.row1
    }

    /// Number of samples in the region.
    pub fn len(&self) -> usize {
        if self.is_empty() {
            0
        } else {
            (self.col1 - self.col0) * (self.row1 - self.row0)
        }
    }

    /// The smallest region holding both (an empty region adds nothing).
    pub fn union(&self, other: &SampleRegion) -> SampleRegion {
        if self.is_empty() {
            return *other;
        }
        if other.is_empty() {
            return *self;
        }
        SampleRegion::new(
            self.col0.min(other.col0),
            self.row0.min(other.row0),
            self.col1.max(other.col1),
            self.row1.max(other.row1),
        )
    }

    /// The part of the region inside a `width x height` grid.
    pub fn clamped(&self, width: usize, height: usize) -> SampleRegion {
        SampleRegion::new(
            self.col0.min(width),
            self.row0.min(height),
            self.col1.min(width),
            self.row1.min(height),
        )
    }

    /// The region grown by `margin` samples on every side, clamped to a `width x height` grid.
    pub fn grown(&self, margin: usize, width: usize, height: usize) -> SampleRegion {
        if self.is_empty() {
            return *self;
        }
        SampleRegion::new(
            self.col0.saturating_sub(margin),
            self.row0.saturating_sub(margin),
            self.col1.saturating_add(margin),
            self.row1.saturating_add(margin),
        )
        .clamped(width, height)
    }

    /// Whether sample (col, row) lies in the region.
    pub fn contains(&self, col: usize, row: usize) -> bool {
        (self.col0..self.col1).contains(&col) && (self.row0..self.row1).contains(&row)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn union_clamp_and_grow() {
        let a = SampleRegion::new(2, 3, 5, 6);
        let b = SampleRegion::new(4, 1, 9, 4);
        assert_eq!(a.union(&b), SampleRegion::new(2, 1, 9, 6));
        assert_eq!(a.union(&SampleRegion::default()), a);
        assert_eq!(SampleRegion::default().union(&a), a);
        assert_eq!(b.clamped(7, 7), SampleRegion::new(4, 1, 7, 4));
        assert_eq!(a.grown(3, 8, 8), SampleRegion::new(0, 0, 8, 8));
        assert_eq!(a.len(), 9);
        assert!(SampleRegion::new(3, 0, 3, 5).is_empty());
        assert!(a.contains(2, 5) && !a.contains(5, 5));
    }
}
