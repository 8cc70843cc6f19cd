//! The 2x2-averaging pyramid of a height field that geometry clipmaps take their levels from.

use relief_core::{HeightField, SampleRegion};

/// Level 0 is the field's samples; level `l` has `ceil(size / 2)` of level `l - 1`'s texels
/// per side, each the mean of the (up to) 2 x 2 texels below it. Texel `k` of level `l`
/// stands for samples `k 2^l .. (k + 1) 2^l` of the field, its value centred among them.
#[derive(Debug, Clone, PartialEq)]
pub struct HeightPyramid {
    /// (width, height, values) of each level, finest first.
    levels: Vec<(usize, usize, Vec<f32>)>,
}

impl HeightPyramid {
    /// The pyramid of `field` with `levels` levels (at least 1).
    pub fn new(field: &HeightField, levels: usize) -> Self {
        let mut pyramid = HeightPyramid {
            levels: vec![(field.width(), field.height(), field.samples().to_vec())],
        };
        for _ in 1..levels.max(1) {
            let (w, h, _) = pyramid.levels[pyramid.levels.len() - 1];
            let (cw, ch) = (w.div_ceil(2), h.div_ceil(2));
            pyramid.levels.push((cw, ch, vec![0.0; cw * ch]));
            let l = pyramid.levels.len() - 1;
            pyramid.refresh(l, SampleRegion::whole(cw, ch));
        }
        pyramid
    }

    /// Takes the samples of `region` from `field` again (after an edit) and updates the
    /// coarser texels above them. The field must have the pyramid's size.
    pub fn update(&mut self, field: &HeightField, region: SampleRegion) {
        let region = region.clamped(field.width(), field.height());
        if region.is_empty() || (field.width(), field.height()) != self.size(0) {
            return;
        }
        let w = field.width();
        for row in region.row0..region.row1 {
            let span = row * w + region.col0..row * w + region.col1;
            self.levels[0].2[span.clone()].copy_from_slice(&field.samples()[span]);
        }
        let mut r = region;
        for l in 1..self.levels.len() {
            r = SampleRegion::new(r.col0 / 2, r.row0 / 2, r.col1.div_ceil(2), r.row1.div_ceil(2));
            self.refresh(l, r);
        }
    }

    /// Recomputes level `l`'s texels in `region` from level `l - 1`.
    fn refresh(&mut self, l: usize, region: SampleRegion) {
        let (below, above) = self.levels.split_at_mut(l);
        let (fw, fh, fine) = &below[l - 1];
        let (cw, _, coarse) = &mut above[0];
        for row in region.row0..region.row1 {
            for col in region.col0..region.col1 {
                let (mut sum, mut count) = (0.0f64, 0.0f64);
                for (c, r) in [
                    (2 * col, 2 * row),
                    (2 * col + 1, 2 * row),
                    (2 * col, 2 * row + 1),
                    (2 * col + 1, 2 * row + 1),
                ] {
                    if c < *fw && r < *fh {
                        sum += fine[c + r * fw] as f64;
                        count += 1.0;
                    }
                }
                coarse[col + row * *cw] = (sum / count) as f32;
            }
        }
    }

    /// Number of levels.
    pub fn level_count(&self) -> usize {
        self.levels.len()
    }

    /// Texels per side of level `l`.
    pub fn size(&self, l: usize) -> (usize, usize) {
        self.levels.get(l).map_or((0, 0), |(w, h, _)| (*w, *h))
    }

    /// Level `l`'s surface at field sample coordinates `(x, y)` (sample (c, r) at `(c, r)`):
    /// bilinear between the texels whose centres surround the point, clamped at the borders.
    pub fn height_at(&self, l: usize, x: f64, y: f64) -> f64 {
        let (w, h, values) = &self.levels[l.min(self.levels.len() - 1)];
        let s = (1u64 << l.min(self.levels.len() - 1)) as f64;
        // Texel k's centre lies at sample coordinate k s + (s - 1) / 2.
        let to_texel = |v: f64, n: usize| ((v - (s - 1.0) / 2.0) / s).clamp(0.0, (n - 1) as f64);
        let (u, v) = (to_texel(x, *w), to_texel(y, *h));
        let (c0, r0) = (u as usize, v as usize);
        let (c1, r1) = ((c0 + 1).min(w - 1), (r0 + 1).min(h - 1));
        let (fu, fv) = (u - c0 as f64, v - r0 as f64);
        let at = |c: usize, r: usize| values[c + r * w] as f64;
        let bottom = at(c0, r0) + fu * (at(c1, r0) - at(c0, r0));
        let top = at(c0, r1) + fu * (at(c1, r1) - at(c0, r1));
        bottom + fv * (top - bottom)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief_core::GridGeometry;

    #[test]
    fn levels_average_and_updates_equal_a_rebuild() {
        let samples: Vec<f32> = (0..25).map(|k| k as f32).collect();
        let mut field = HeightField::new(5, 5, samples, GridGeometry::unit()).unwrap();
        let pyramid = HeightPyramid::new(&field, 3);
        assert_eq!(pyramid.size(1), (3, 3));
        assert_eq!(pyramid.size(2), (2, 2));
        // Texel (0, 0) of level 1 averages samples 0, 1, 5, 6; texel (2, 2) is sample 24 alone.
        assert_eq!(pyramid.height_at(1, 0.5, 0.5), 3.0);
        assert_eq!(pyramid.height_at(1, 4.5, 4.5), 24.0);
        assert_eq!(pyramid.height_at(0, 2.0, 3.0), 17.0);
        let region = field.edit_region(SampleRegion::new(1, 1, 3, 2), |_, _, v| v + 10.0).unwrap();
        let mut updated = pyramid.clone();
        updated.update(&field, region);
        assert_eq!(updated, HeightPyramid::new(&field, 3));
        assert_ne!(updated, pyramid);
    }
}
