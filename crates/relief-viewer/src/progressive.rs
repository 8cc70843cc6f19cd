//! The progressive scheduler: which resolution to render next. While the camera moves, the
//! largest reduced resolution whose predicted time fits the frame budget; once it rests,
//! doubling the resolution frame by frame up to full, then the full frame anti-aliased
//! ([`AT_REST_SAMPLES`]² samples a pixel); then nothing, until something changes.

use std::time::Duration;

/// The reductions tried, largest image first: the full size divided by each, per side.
const DIVISORS: [u32; 6] = [1, 2, 3, 4, 6, 8];

/// The samples a side of a pixel of the last frame at rest: the full frame anti-aliased.
pub const AT_REST_SAMPLES: u32 = 2;

/// One frame to render: the view's version and the divisor of its size.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FrameRequest {
    /// The version of the camera and settings it shows.
    pub version: u64,
    /// Its size is the full size divided by this, per side, rounded up.
    pub divisor: u32,
    /// Its width in pixels.
    pub width: u32,
    /// Its height in pixels.
    pub height: u32,
    /// Samples a side of each pixel: 1, or `AT_REST_SAMPLES` (2) for the full frame
    /// anti-aliased at rest (a frame for each offset of the grid, averaged, as `relief render
    /// --aa N` draws it).
    pub samples: u32,
}

/// Decides what to render next.
#[derive(Debug, Clone)]
pub struct ProgressiveScheduler {
    full: (u32, u32),
    budget: Duration,
    version: u64,
    moving: bool,
    /// The last frame shown: (version, divisor, samples).
    shown: Option<(u64, u32, u32)>,
    /// Measured cost per pixel, in seconds (an average that follows changes quickly).
    seconds_per_pixel: Option<f64>,
}

impl ProgressiveScheduler {
    /// For a full image of `full` (width, height) pixels, frames while moving within `budget`.
    pub fn new(full: (u32, u32), budget: Duration) -> Self {
        ProgressiveScheduler {
            full,
            budget,
            version: 0,
            moving: false,
            shown: None,
            seconds_per_pixel: None,
        }
    }

    /// The full image size.
    pub fn full_size(&self) -> (u32, u32) {
        self.full
    }

    /// The full image is now `full` (width, height) pixels (the window was resized): what is
    /// shown is out of date unless it already had that size.
    pub fn resize(&mut self, full: (u32, u32)) {
        let full = (full.0.max(1), full.1.max(1));
        if full != self.full {
            self.full = full;
            self.changed();
        }
    }

    /// The version of the view now (it grows with every change).
    pub fn version(&self) -> u64 {
        self.version
    }

    /// The camera or a setting changed: what is shown is out of date.
    pub fn changed(&mut self) {
        self.version += 1;
    }

    /// Whether the camera is moving (keys held, mouse dragging).
    pub fn set_moving(&mut self, moving: bool) {
        self.moving = moving;
    }

    /// Whether the image shown is the current view at full resolution, anti-aliased.
    pub fn is_complete(&self) -> bool {
        self.shown == Some((self.version, 1, AT_REST_SAMPLES))
    }

    /// The next frame to render, or `None` when the full image of the current view is shown
    /// anti-aliased.
    pub fn next(&self) -> Option<FrameRequest> {
        let fast = self.fast_divisor();
        let (divisor, samples) = match self.shown {
            Some((v, d, samples)) if v == self.version => {
                if self.moving || samples > 1 {
                    return None;
                }
                // At rest: the next larger image, never one smaller than what is shown; after
                // the full one, the full one anti-aliased.
                match DIVISORS.iter().copied().filter(|&k| k < d).max() {
                    Some(larger) => (larger, 1),
                    None => (1, AT_REST_SAMPLES),
                }
            }
            // A new view, moving or not: the largest frame that fits the budget, at once.
            _ => (fast, 1),
        };
        let (width, height) = self.size_for(divisor);
        Some(FrameRequest { version: self.version, divisor, width, height, samples })
    }

    /// The current view at full size, one sample a pixel, whatever is shown: to render it
    /// again (a scripted run that measures frames at rest).
    pub fn full_request(&self) -> FrameRequest {
        let (width, height) = self.full;
        FrameRequest { version: self.version, divisor: 1, width, height, samples: 1 }
    }

    /// `request` was rendered in `elapsed` and is shown.
    pub fn shown(&mut self, request: FrameRequest, elapsed: Duration) {
        let samples = f64::from(request.samples * request.samples);
        let pixels = f64::from(request.width) * f64::from(request.height) * samples;
        let measured = elapsed.as_secs_f64() / pixels;
        self.seconds_per_pixel = Some(match self.seconds_per_pixel {
            Some(old) => 0.5 * old + 0.5 * measured,
            None => measured,
        });
        self.shown = Some((request.version, request.divisor, request.samples));
    }

    /// The size of the image for `divisor`.
    pub fn size_for(&self, divisor: u32) -> (u32, u32) {
        (self.full.0.div_ceil(divisor).max(1), self.full.1.div_ceil(divisor).max(1))
    }

    /// The smallest divisor whose frame is predicted to fit the budget (the largest one
    /// before anything was measured).
    fn fast_divisor(&self) -> u32 {
        let largest = DIVISORS[DIVISORS.len() - 1];
        let Some(cost) = self.seconds_per_pixel else { return largest };
        DIVISORS
            .iter()
            .copied()
            .find(|&d| {
                let (w, h) = self.size_for(d);
                f64::from(w) * f64::from(h) * cost <= self.budget.as_secs_f64()
            })
            .unwrap_or(largest)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_resize_refines_to_the_new_size() {
        let mut s = ProgressiveScheduler::new((640, 360), 40 * MS);
        while let Some(request) = s.next() {
            s.shown(request, MS);
        }
        s.resize((640, 360));
        assert!(s.is_complete(), "the same size changes nothing");
        s.resize((1000, 500));
        let mut last = None;
        while let Some(request) = s.next() {
            s.shown(request, MS);
            last = Some((request.width, request.height));
        }
        assert_eq!(last, Some((1000, 500)));
        s.resize((0, 0));
        assert_eq!(s.full_size(), (1, 1));
    }

    const MS: Duration = Duration::from_millis(1);

    #[test]
    fn at_rest_it_refines_to_full_resolution_and_then_stops() {
        let mut s = ProgressiveScheduler::new((640, 360), 40 * MS);
        let mut sizes = Vec::new();
        while let Some(request) = s.next() {
            sizes.push((request.width, request.height, request.samples));
            s.shown(request, MS); // 1 ms a frame of any size: cheap
        }
        assert_eq!(sizes.first(), Some(&(80, 45, 1)), "nothing measured yet: the fastest first");
        // The full frame, then the full frame anti-aliased.
        assert_eq!(sizes[sizes.len() - 2..], [(640, 360, 1), (640, 360, AT_REST_SAMPLES)]);
        assert!(sizes.windows(2).all(|w| w[0].0 < w[1].0 || w[0].2 < w[1].2), "{sizes:?}");
        assert!(s.is_complete());
        // A change starts again, now straight at the size the budget affords.
        s.changed();
        assert!(!s.is_complete());
        assert_eq!(s.next().map(|r| r.divisor), Some(1));
    }

    #[test]
    fn while_moving_it_keeps_to_the_budget_and_renders_each_view_once() {
        let mut s = ProgressiveScheduler::new((1280, 720), 40 * MS);
        s.set_moving(true);
        let first = s.next().unwrap();
        // Measured: 1 microsecond a pixel, so 40 ms buy 40 000 pixels: 1280x720 / 5^2 would,
        // but the divisors are 1, 2, 3, 4, 6, 8: 6 gives 214x120 = 25 680 pixels.
        s.shown(first, Duration::from_secs_f64(1e-6 * f64::from(first.width * first.height)));
        assert_eq!(s.next(), None, "the same view is not rendered twice while moving");
        s.changed();
        let request = s.next().unwrap();
        assert_eq!((request.divisor, request.width, request.height), (6, 214, 120));
        // Resting after the move: refine from there.
        s.shown(request, Duration::from_secs_f64(1e-6 * 214.0 * 120.0));
        s.set_moving(false);
        assert_eq!(s.next().map(|r| r.divisor), Some(4));
    }

    #[test]
    fn a_frame_shown_for_an_old_view_does_not_count_as_the_current_one() {
        let mut s = ProgressiveScheduler::new((64, 36), 40 * MS);
        let request = s.next().unwrap();
        s.changed();
        s.shown(request, MS);
        assert!(!s.is_complete());
        assert_eq!(s.next().unwrap().version, 1);
        assert_eq!(s.size_for(1000), (1, 1));
    }
}
