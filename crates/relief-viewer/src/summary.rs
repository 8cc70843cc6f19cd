//! What a viewer run showed: every frame's size and timing (written by `--stats`), and a
//! summary of the frame times while moving and at rest.

use serde::Serialize;

/// One frame shown.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FrameRecord {
    /// Its width.
    pub width: u32,
    /// Its height.
    pub height: u32,
    /// Whether the camera was moving when it was asked for.
    pub moving: bool,
    /// Rendering it took, milliseconds.
    pub render_ms: f64,
    /// Time since the frame before was shown, milliseconds (none for the first).
    pub interval_ms: Option<f64>,
    /// Rays cast.
    pub rays: u64,
}

/// How a run ended.
#[derive(Debug, Clone, Default)]
pub struct ViewerSummary {
    /// Frames shown.
    pub frames: Vec<FrameRecord>,
    /// The screenshot written at the end of a `frames` run.
    pub screenshot: Option<std::path::PathBuf>,
}

impl ViewerSummary {
    /// One line each for the frames shown while moving and at full size: how many, at what
    /// size, the median render time and, while moving, the median time from one frame shown
    /// to the next and the frames per second that is.
    pub fn report(&self) -> Vec<String> {
        let pixels = |f: &FrameRecord| u64::from(f.width) * u64::from(f.height);
        let full = self.frames.iter().map(pixels).max();
        let moving: Vec<&FrameRecord> = self.frames.iter().filter(|f| f.moving).collect();
        let at_rest: Vec<&FrameRecord> =
            self.frames.iter().filter(|f| !f.moving && Some(pixels(f)) == full).collect();
        let mut lines = vec![format!("{} frames shown", self.frames.len())];
        for (label, frames) in [("while moving", moving), ("at full size", at_rest)] {
            let Some(render) = median(frames.iter().map(|f| f.render_ms)) else { continue };
            let mut line = format!(
                "{label}: {} frames at {}, median {render:.1} ms to render",
                frames.len(),
                sizes(&frames)
            );
            if label == "while moving" {
                if let Some(interval) = median(frames.iter().filter_map(|f| f.interval_ms)) {
                    let fps = 1e3 / interval.max(1e-6);
                    line += &format!(", shown every {interval:.1} ms ({fps:.1} frames/s)");
                }
            }
            lines.push(line);
        }
        lines
    }
}

/// The median of `values`, if there are any.
fn median(values: impl Iterator<Item = f64>) -> Option<f64> {
    let mut sorted: Vec<f64> = values.collect();
    sorted.sort_by(f64::total_cmp);
    sorted.get(sorted.len() / 2).copied()
}

/// The size most of `frames` have, and how many others there are: "160x90", or "160x90 and
/// 2 other sizes".
fn sizes(frames: &[&FrameRecord]) -> String {
    let mut counts: Vec<((u32, u32), usize)> = Vec::new();
    for f in frames {
        match counts.iter_mut().find(|(s, _)| *s == (f.width, f.height)) {
            Some((_, n)) => *n += 1,
            None => counts.push(((f.width, f.height), 1)),
        }
    }
    // Stable: of sizes as frequent, the first shown.
    counts.sort_by_key(|&(_, n)| std::cmp::Reverse(n));
    let ((w, h), _) = counts[0];
    match counts.len() - 1 {
        0 => format!("{w}x{h}"),
        1 => format!("{w}x{h} and 1 other size"),
        n => format!("{w}x{h} and {n} other sizes"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(width: u32, moving: bool, render_ms: f64, interval_ms: f64) -> FrameRecord {
        let height = width / 2;
        FrameRecord { width, height, moving, render_ms, interval_ms: Some(interval_ms), rays: 0 }
    }

    #[test]
    fn the_report_splits_moving_frames_from_full_ones() {
        let summary = ViewerSummary {
            frames: vec![
                frame(100, true, 10.0, 40.0),
                frame(100, true, 30.0, 50.0),
                frame(50, true, 20.0, 25.0),
                frame(200, false, 80.0, 90.0),
                frame(400, false, 200.0, 210.0),
            ],
            screenshot: None,
        };
        let report = summary.report();
        assert_eq!(report[0], "5 frames shown");
        assert_eq!(
            report[1],
            "while moving: 3 frames at 100x50 and 1 other size, median 20.0 ms to render, shown every \
             40.0 ms (25.0 frames/s)"
        );
        assert_eq!(report[2], "at full size: 1 frames at 400x200, median 200.0 ms to render");
    }
}
