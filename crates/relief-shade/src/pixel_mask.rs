//! The pixels a pass draws: every one, or those an anti-aliasing pass samples again.

use crate::render::Tile;
use std::sync::Arc;

/// A set of an image's pixels: those a masked pass traces and shades, the rest left undrawn
/// (a renderer's masked pass costs about what its marked pixels cost).
///
/// A mask may mark the pixels of an image `n` times finer than the one it was made for
/// ([`PixelMask::finer`]): each marked pixel then marks its `n x n` sub-pixels.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PixelMask {
    /// The marks, a row of `coarse_width` after another.
    marked: Arc<[bool]>,
    coarse_width: usize,
    /// Pixels of the image a side of a mark covers.
    scale: usize,
    width: usize,
    height: usize,
}

impl PixelMask {
    /// The mask of a `width x height` image marking the pixels of `marked` (a row after
    /// another). Panics when `marked` does not hold `width x height` pixels.
    pub fn new(width: usize, height: usize, marked: Vec<bool>) -> Self {
        assert_eq!(marked.len(), width * height, "one mark a pixel");
        PixelMask { marked: marked.into(), coarse_width: width, scale: 1, width, height }
    }

    /// The mask of a `width x height` image with the pixels `marked(i, j)` says.
    pub fn from_fn(width: usize, height: usize, marked: impl Fn(usize, usize) -> bool) -> Self {
        let marked = (0..width * height).map(|k| marked(k % width, k / width)).collect();
        PixelMask::new(width, height, marked)
    }

    /// The same marks over an image `n` times finer across and down: pixel `(i, j)` of it is
    /// marked when pixel `(i / n, j / n)` is marked here.
    pub fn finer(&self, n: usize) -> PixelMask {
        let scale = self.scale * n;
        let (width, height) = (self.width * n, self.height * n);
        PixelMask { marked: self.marked.clone(), scale, width, height, ..*self }
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
        self.marked[i / self.scale + j / self.scale * self.coarse_width]
    }

    /// The marked pixels' count.
    pub fn count(&self) -> usize {
        self.marked.iter().filter(|&&m| m).count() * self.scale * self.scale
    }

    /// Whether a pixel of rows `top..top + rows` is marked.
    pub fn any_in_rows(&self, top: usize, rows: usize) -> bool {
        let rows = top / self.scale..(top + rows).min(self.height).div_ceil(self.scale);
        let w = self.coarse_width;
        rows.into_iter().any(|r| self.marked[r * w..(r + 1) * w].iter().any(|&m| m))
    }

    /// Whether a pixel of `tile` is marked.
    pub fn any_in_tile(&self, tile: Tile) -> bool {
        let s = self.scale;
        let columns = tile.x / s..(tile.x + tile.cols).div_ceil(s);
        let w = self.coarse_width;
        (tile.y / s..(tile.y + tile.rows).div_ceil(s))
            .any(|r| self.marked[r * w..][columns.clone()].iter().any(|&m| m))
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
        assert!(mask.any_in_rows(16, 16) && !mask.any_in_rows(0, 16));
        assert!(mask.any_in_tile(Tile::new(32, 16, 40, 20)));
        assert!(!mask.any_in_tile(Tile::new(16, 16, 40, 20)));
        assert!(mask.fits(40, 20) && !mask.fits(20, 40));
    }

    #[test]
    fn a_finer_mask_marks_the_sub_pixels_of_the_marked_pixels() {
        let coarse = PixelMask::from_fn(21, 11, |i, j| (i + 2 * j) % 7 == 0);
        let fine = coarse.finer(3);
        assert!(fine.fits(63, 33));
        assert_eq!(fine.count(), coarse.count() * 9);
        let dense = PixelMask::from_fn(63, 33, |i, j| coarse.contains(i / 3, j / 3));
        for j in 0..33 {
            for i in 0..63 {
                assert_eq!(fine.contains(i, j), dense.contains(i, j), "({i}, {j})");
            }
            assert_eq!(fine.any_in_rows(j, 5), dense.any_in_rows(j, 5), "rows from {j}");
        }
        for (x, y) in [(0, 0), (16, 16), (48, 32), (32, 0)] {
            let tile = Tile::new(x, y, 63, 33);
            assert_eq!(fine.any_in_tile(tile), dense.any_in_tile(tile), "tile {x}, {y}");
        }
    }
}
