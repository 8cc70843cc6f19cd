//! Filling voids of a raster: nearest valid sample first, then smoothing of the filled area.

use std::collections::VecDeque;

/// Jacobi sweeps of the smoothing pass: enough to relax the fill's terraces over a few dozen
/// samples, bounded so huge voids cost at most this many passes over the voids.
const SMOOTHING_SWEEPS: usize = 64;

/// Replaces every NaN of the row-major `width x height` grid: first with the value of the
/// nearest valid sample (breadth-first over the 4-neighbourhood, ties to the earlier sample),
/// then by averaging each filled sample with its neighbours, valid samples held fixed, so the
/// fill meets its borders smoothly. Deterministic. A grid with no valid sample is left as is.
pub fn fill_voids(width: usize, height: usize, samples: &mut [f32]) {
    let voids: Vec<usize> = (0..samples.len()).filter(|&i| samples[i].is_nan()).collect();
    if voids.is_empty() || voids.len() == samples.len() {
        return;
    }
    let mut queue: VecDeque<usize> = (0..samples.len()).filter(|&i| !samples[i].is_nan()).collect();
    while let Some(i) = queue.pop_front() {
        let value = samples[i];
        for n in neighbours(i, width, height).into_iter().flatten() {
            if samples[n].is_nan() {
                samples[n] = value;
                queue.push_back(n);
            }
        }
    }
    let mut next = vec![0f32; voids.len()];
    for _ in 0..SMOOTHING_SWEEPS {
        for (out, &i) in next.iter_mut().zip(&voids) {
            let (sum, count) = neighbours(i, width, height)
                .into_iter()
                .flatten()
                .fold((0f64, 0u32), |(s, c), n| (s + samples[n] as f64, c + 1));
            *out = (sum / count.max(1) as f64) as f32;
        }
        for (&v, &i) in next.iter().zip(&voids) {
            samples[i] = v;
        }
    }
}

/// The 4-neighbours of sample `i` inside the grid.
fn neighbours(i: usize, width: usize, height: usize) -> [Option<usize>; 4] {
    let (c, r) = (i % width, i / width);
    [
        (c > 0).then(|| i - 1),
        (c + 1 < width).then(|| i + 1),
        (r > 0).then(|| i - width),
        (r + 1 < height).then(|| i + width),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fills_from_the_nearest_valid_sample_and_smooths() {
        // A row 0 .. 10 with the middle missing: the fill lies between its borders.
        let mut s: Vec<f32> =
            (0..11).map(|i| if (3..8).contains(&i) { f32::NAN } else { i as f32 }).collect();
        fill_voids(11, 1, &mut s);
        assert!(s.iter().all(|v| v.is_finite()));
        for (i, v) in s.iter().enumerate().take(8).skip(3) {
            assert!((v - i as f32).abs() < 0.5, "sample {i} is {v}");
        }
        assert_eq!(s[2], 2.0, "valid samples stay");
    }

    #[test]
    fn a_single_valid_sample_spreads_everywhere() {
        let mut s = vec![f32::NAN; 12];
        s[5] = 3.0;
        fill_voids(4, 3, &mut s);
        assert!(s.iter().all(|&v| v == 3.0));
    }

    #[test]
    fn all_void_grid_is_left_alone() {
        let mut s = vec![f32::NAN; 4];
        fill_voids(2, 2, &mut s);
        assert!(s.iter().all(|v| v.is_nan()));
    }
}
