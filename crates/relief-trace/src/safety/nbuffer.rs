//! N-buffers (Décoret 2005) along local y: the highest sample of any window of a local column
//! in two lookups, for the conservative cone slopes of Baboud et al. (6.3.2).

use super::frame::LocalField;

/// Level `l` holds, for every local sample (i, j), the maximum of `h(i, j .. j + 2^l)`.
pub struct NBuffer {
    height: usize,
    /// Levels 0.. stored column-major (`j + i * height`) so a window is contiguous.
    levels: Vec<Vec<f32>>,
}

impl NBuffer {
    /// The N-buffer of a class's local field.
    pub fn new(field: &LocalField) -> Self {
        let (w, h) = (field.width(), field.height());
        let mut level: Vec<f32> = (0..w)
            .flat_map(|i| (0..h).map(move |j| (i, j)))
            .map(|(i, j)| field.h(i, j) as f32)
            .collect();
        let mut levels = Vec::new();
        let mut span = 1;
        loop {
            let next_span = span * 2;
            let next = (next_span <= h).then(|| {
                let mut next = level.clone();
                for i in 0..w {
                    let col = &level[i * h..(i + 1) * h];
                    for j in 0..h - span {
                        next[i * h + j] = col[j].max(col[j + span]);
                    }
                }
                next
            });
            levels.push(level);
            match next {
                Some(n) => level = n,
                None => break,
            }
            span = next_span;
        }
        NBuffer { height: h, levels }
    }

    /// The highest sample of local column `i` over rows `j0..=j1` (clamped into the grid).
    #[inline]
    pub fn window_max(&self, i: usize, j0: isize, j1: isize) -> f32 {
        if j1 < 0 {
            return f32::NEG_INFINITY;
        }
        let j0 = j0.max(0) as usize;
        let j1 = (j1.max(0) as usize).min(self.height - 1);
        if j0 > j1 {
            return f32::NEG_INFINITY;
        }
        let len = j1 - j0 + 1;
        let l = (usize::BITS - 1 - len.leading_zeros()) as usize;
        let level = &self.levels[l];
        let base = i * self.height;
        level[base + j0].max(level[base + j1 + 1 - (1 << l)])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::safety::frame::{Frame, RayClass};

    #[test]
    fn windows_match_a_direct_maximum() {
        let (w, h) = (3usize, 11usize);
        let samples: Vec<f32> = (0..w * h).map(|k| ((k * 37) % 17) as f32).collect();
        for class in RayClass::ALL {
            let field = LocalField::new(Frame::new(class, w, h), &samples);
            let nb = NBuffer::new(&field);
            for i in 0..field.width() {
                for j0 in -2..field.height() as isize + 1 {
                    for j1 in j0..field.height() as isize + 2 {
                        let direct = (j0.max(0)..=j1.min(field.height() as isize - 1))
                            .map(|j| field.h(i, j as usize) as f32)
                            .fold(f32::NEG_INFINITY, f32::max);
                        assert_eq!(nb.window_max(i, j0, j1), direct, "{class:?} {i} {j0}..{j1}");
                    }
                }
            }
        }
    }
}
