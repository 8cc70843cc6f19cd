//! The legend: a colour bar of the height colour map at the picture's bottom right, the low
//! end at the bottom, with round heights in metres beside it.

use relief_core::colour::linear_to_srgb8;
use relief_shade::HeightColourMap;

use super::canvas::{Canvas, INK};
use super::font;
use super::scale_bar::trim;

/// The most height labels a legend carries.
pub const MAX_LABELS: usize = 6;

/// Round heights for labels in `[lo, hi]`: the multiples within it of the smallest step of 1,
/// 2 or 5 x 10^k that gives at most `max_labels` of them (at least one: `lo` itself where the
/// range is empty).
pub fn label_heights(lo: f64, hi: f64, max_labels: usize) -> Vec<f64> {
    let span = hi - lo;
    if span.is_nan() || span <= 0.0 || max_labels == 0 {
        return vec![lo];
    }
    let mut step = 10f64.powf((span / max_labels as f64).log10().floor());
    let mut previous: Vec<f64> = Vec::new();
    loop {
        for m in [1.0, 2.0, 5.0] {
            let s = step * m;
            // A hair of slack, so that a range ending on a round height keeps it.
            let first = (lo / s - 1e-9).ceil() as i64;
            let last = (hi / s + 1e-9).floor() as i64;
            if last < first {
                // The step outgrew the range before the labels were few enough: the one of
                // the last ones nearest the middle.
                let middle = (lo + hi) / 2.0;
                let nearest = previous
                    .iter()
                    .copied()
                    .min_by(|a, b| (a - middle).abs().total_cmp(&(b - middle).abs()));
                return vec![nearest.unwrap_or(lo)];
            }
            let labels: Vec<f64> = (first..=last).map(|k| k as f64 * s).collect();
            if labels.len() <= max_labels {
                return labels;
            }
            previous = labels;
        }
        step *= 10.0;
    }
}

/// A height's label: "1500 m", "-200 m", "0.5 m".
pub fn height_label(metres: f64) -> String {
    format!("{} m", trim(metres))
}

/// Draws the legend of `colours` (heights in metres) at the picture's bottom right, on a
/// light panel below row `top` (where it fits; furniture above takes the rows before it);
/// `unit` is the furniture's pixel scale.
pub(crate) fn draw(canvas: &mut Canvas, colours: &HeightColourMap, unit: u32, top: i64) {
    let u = unit as i64;
    let (lo, hi) = (colours.min_z, colours.max_z);
    let text_h = font::text_height(unit) as i64;
    let (pad, margin, bar_w, tick) = (3 * u, 4 * u, 5 * u, 2 * u);
    let room = canvas.height as i64 - margin - top - 2 * pad - text_h;
    let bar_h = ((canvas.height as f64 * 0.4) as i64).max(4 * text_h).min(room).max(2 * text_h);
    // As many labels as fit with a line of space between them.
    let fit = (bar_h / (text_h + 3 * u)).max(1) as usize;
    let heights = label_heights(lo, hi, fit.min(MAX_LABELS));
    let labels: Vec<String> = heights.iter().map(|&z| height_label(z)).collect();
    let text_w = labels.iter().map(|l| font::text_width(l, unit) as i64).max().unwrap_or(0);
    let panel_w = pad + text_w + 2 * u + tick + bar_w + pad;
    let panel_h = pad + text_h / 2 + bar_h + text_h / 2 + pad;
    let x0 = canvas.width as i64 - margin - panel_w;
    let y0 = canvas.height as i64 - margin - panel_h;
    canvas.panel(x0, y0, panel_w as u32, panel_h as u32);
    let bar_x = x0 + pad + text_w + 2 * u + tick;
    let bar_y = y0 + pad + text_h / 2;
    for row in 0..bar_h {
        let z = hi - (row as f64 + 0.5) / bar_h as f64 * (hi - lo);
        let colour = colours.albedo(z).as_vec3().to_array().map(linear_to_srgb8);
        canvas.fill_rect(bar_x, bar_y + row, bar_w as u32, 1, colour);
    }
    for (z, label) in heights.iter().zip(&labels) {
        let fraction = if hi > lo { (hi - z) / (hi - lo) } else { 1.0 };
        let y = bar_y + (fraction * (bar_h - 1) as f64).round() as i64;
        canvas.fill_rect(bar_x - tick, y - u / 2, tick as u32, unit, INK);
        let w = font::text_width(label, unit) as i64;
        canvas.text(label, bar_x - tick - 2 * u - w, y - text_h / 2, unit, INK);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_are_round_and_within_the_range() {
        assert_eq!(label_heights(-1437.0, 2205.0, 6), vec![-1000.0, 0.0, 1000.0, 2000.0]);
        assert_eq!(label_heights(0.0, 100.0, 6), vec![0.0, 20.0, 40.0, 60.0, 80.0, 100.0]);
        assert_eq!(label_heights(0.0, 100.0, 3), vec![0.0, 50.0, 100.0]);
        let fine = label_heights(3.2, 3.9, 4);
        let want = [3.2, 3.4, 3.6, 3.8];
        assert!(fine.len() == 4 && fine.iter().zip(want).all(|(a, b)| (a - b).abs() < 1e-12));
        assert_eq!(label_heights(5.0, 5.0, 4), vec![5.0]);
        for (lo, hi) in [(-7.3, 12.9), (0.001, 0.009), (120.0, 4810.0)] {
            for n in 1..=6 {
                let labels = label_heights(lo, hi, n);
                assert!(!labels.is_empty() && labels.len() <= n, "{lo}..{hi}, {n}: {labels:?}");
                assert!(labels.iter().all(|&z| z >= lo - 1e-9 && z <= hi + 1e-9), "{labels:?}");
            }
        }
    }

    #[test]
    fn height_labels_read_as_people_write_them() {
        assert_eq!(height_label(1500.0), "1500 m");
        assert_eq!(height_label(-200.0), "-200 m");
        assert_eq!(height_label(0.5), "0.5 m");
        assert_eq!(height_label(-0.0), "0 m");
    }
}
