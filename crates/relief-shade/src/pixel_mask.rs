//! The pixels a pass draws: every one, or those an anti-aliasing pass samples again.

use crate::render::Tile;
use std::ops::Range;

/// A set of an image's pixels: those a masked pass traces and shades, the rest left undrawn
/// (a renderer's masked pass costs about what its marked pixels cost).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PixelMask {
    /// The marks, a row after another.
    marked: Vec<bool>,
    width: usize,
    height: usize,
}

impl PixelMask {
    /// The mask of a `width x height` image marking the pixels of `marked` (a row after
    /// another). Panics when `marked` does not hold `width x height` pixels.
    pub fn new(width: usize, height: usize, marked: Vec<bool>) -> Self {
        assert_eq!(marked.len(), width * height, "one mark a pixel");
        PixelMask { marked, width, height }
    }

    /// The mask of a `width x height` image with the pixels `marked(i, j)` says.
    pub fn from_fn(width: usize, height: usize, marked: impl Fn(usize, usize) -> bool) -> Self {
        let marked = (0..width * height).map(|k| marked(k % width, k / width)).collect();
        PixelMask::new(width, height, marked)
    }

    /// Pixels a row.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Rows.
    pub fn height(&self) -> usize {
        self.height
    }

    /// Whether pixel (i, j) is marked.
    #[inline]
    pub fn contains(&self, i: usize, j: usize) -> bool {
        self.marked[i + j * self.width]
    }

    /// The indices (`i + j * width`) of the marked pixels, in order.
    pub fn indices(&self) -> Vec<usize> {
        (0..self.marked.len()).filter(|&k| self.marked[k]).collect()
    }

    /// The marked pixels' count.
    pub fn count(&self) -> usize {
        self.marked.iter().filter(|&&m| m).count()
    }

    /// Whether a pixel of rows `top..top + rows` is marked.
    pub fn any_in_rows(&self, top: usize, rows: usize) -> bool {
        self.any_in(0..self.width, top..top + rows)
    }

    /// Whether a pixel of `tile` is marked.
    pub fn any_in_tile(&self, tile: Tile) -> bool {
        self.any_in(tile.x..tile.x + tile.cols, tile.y..tile.y + tile.rows)
    }

    /// Whether a pixel of `columns` x `rows` (clipped to the image) is marked.
    fn any_in(&self, columns: Range<usize>, rows: Range<usize>) -> bool {
        let clip = |r: Range<usize>, end: usize| r.start..r.end.min(end).max(r.start);
        let (columns, w) = (clip(columns, self.width), self.width);
        let rows = clip(rows, self.height);
        rows.into_iter().any(|r| self.marked[r * w..][columns.clone()].iter().any(|&m| m))
    }

    /// Whether the mask is of a `width x height` image.
    pub fn fits(&self, width: usize, height: usize) -> bool {
        (self.width, self.height) == (width, height)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_mask_answers_for_its_pixels_rows_and_tiles() {
        let mask = PixelMask::from_fn(40, 20, |i, j| (i, j) == (33, 17));
        assert!(mask.contains(33, 17) && !mask.contains(17, 13));
        assert_eq!(mask.count(), 1);
        assert_eq!(mask.indices(), [33 + 17 * 40]);
        assert!(mask.any_in_rows(16, 16) && !mask.any_in_rows(0, 16));
        assert!(mask.any_in_tile(Tile::new(32, 16, 40, 20)));
        assert!(!mask.any_in_tile(Tile::new(16, 16, 40, 20)));
        assert!(mask.fits(40, 20) && !mask.fits(20, 40));
    }
}
