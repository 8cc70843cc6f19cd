//! What `relief flythrough` reports of its frames: one line a frame, a closing line of
//! medians, and the JSON of `--stats` (every frame's figures and a summary).

use super::args::FlythroughArgs;
use super::flight_plan::FlightPlan;
use crate::commands::simulate::frames::median;
use crate::memory;
use relief_tiles::FrameStats;
use serde_json::{json, Value};

/// What drawing and writing one frame took.
pub(super) struct FlightFrame {
    /// The frame's number, from 0 (its file is `frame-NNNNN.png`).
    pub frame: u32,
    /// Its time on the camera path, seconds.
    pub time_s: f64,
    /// Milliseconds to draw it: choosing and loading tiles (stores), tracing and shading.
    pub time_ms: f64,
    /// Milliseconds to write its PNG.
    pub write_ms: f64,
    /// The process's resident memory after drawing it, bytes (where the system says).
    pub rss_bytes: Option<u64>,
    /// A tile store's figures of the frame: tiles wanted, drawn and standing in, the cache's
    /// bytes, the wait for IO and the error bound used.
    pub tiles: Option<FrameStats>,
    /// What the renderer did other than asked, if anything.
    pub note: Option<String>,
}

/// Mebibytes of `bytes`, for lines.
fn mib(bytes: u64) -> f64 {
    bytes as f64 / f64::from(1u32 << 20)
}

impl FlightFrame {
    /// The frame's line: number, path time, frame time, tiles (stores), RSS, IO wait (stores).
    pub fn line(&self) -> String {
        let mut line =
            format!("frame {} (t {:.3} s): {:.1} ms", self.frame, self.time_s, self.time_ms);
        if let Some(tiles) = &self.tiles {
            line += &format!(
                "; {} tiles drawn, {} standing in, {:.1} MiB of tiles resident",
                tiles.tiles_drawn,
                tiles.tiles_standing_in,
                mib(tiles.resident_bytes)
            );
        }
        match self.rss_bytes {
            Some(bytes) => line += &format!("; RSS {:.1} MiB", mib(bytes)),
            None => line += "; RSS unknown",
        }
        if let Some(tiles) = &self.tiles {
            line += &format!("; IO wait {:.1} ms", tiles.io_wait_ms);
        }
        if let Some(note) = &self.note {
            line += &format!(" ({note})");
        }
        line
    }

    /// The frame's `--stats` entry; the tile figures only for stores, and a note only where
    /// the renderer left one.
    fn to_json(&self) -> Value {
        let mut entry = json!({
            "frame": self.frame,
            "time_s": self.time_s,
            "time_ms": self.time_ms,
            "write_ms": self.write_ms,
            "rss_bytes": self.rss_bytes,
        });
        let Some(all) = entry.as_object_mut() else { return entry };
        if let Some(tiles) = &self.tiles {
            let figures = json!({
                "tiles_drawn": tiles.tiles_drawn,
                "tiles_standing_in": tiles.tiles_standing_in,
                "tiles_wanted": tiles.tiles_wanted,
                "resident_bytes": tiles.resident_bytes,
                "io_wait_ms": tiles.io_wait_ms,
                "max_error_px": tiles.max_error_px,
            });
            if let Value::Object(figures) = figures {
                all.extend(figures);
            }
        }
        if let Some(note) = &self.note {
            all.insert("note".into(), json!(note));
        }
        entry
    }
}

/// The frames of a flight, as they are drawn.
pub(super) struct FlightLog {
    /// The input in a few words.
    scene: String,
    /// Whether the input is a tile store.
    store: bool,
    frames: Vec<FlightFrame>,
}

impl FlightLog {
    /// An empty log of the flight over `scene` (a tile store when `store`).
    pub fn new(scene: String, store: bool) -> Self {
        FlightLog { scene, store, frames: Vec::new() }
    }

    /// Adds a frame drawn.
    pub fn push(&mut self, frame: FlightFrame) {
        self.frames.push(frame);
    }

    /// The median of `figure` over the frames.
    fn median_of(&self, figure: impl Fn(&FlightFrame) -> f64) -> f64 {
        median(self.frames.iter().map(figure).collect())
    }

    /// The median of a tile figure over the frames (0 for inputs other than stores).
    fn median_tiles(&self, figure: impl Fn(&FrameStats) -> f64) -> f64 {
        median(self.frames.iter().filter_map(|f| f.tiles.as_ref()).map(figure).collect())
    }

    /// The closing line's figures: the median frame time and, for stores, tiles and IO wait.
    pub fn summary_line(&self) -> String {
        let mut line = format!(
            "median {:.1} ms a frame, slowest {:.1} ms",
            self.median_of(|f| f.time_ms),
            self.frames.iter().map(|f| f.time_ms).fold(0.0, f64::max)
        );
        if self.store {
            let standing = self.frames_with_stand_ins();
            line += &format!(
                ", median {:.0} tiles drawn, {standing} frame(s) with stand-ins, median IO wait \
                 {:.1} ms",
                self.median_tiles(|t| t.tiles_drawn as f64),
                self.median_tiles(|t| t.io_wait_ms)
            );
        }
        line
    }

    /// Frames in which coarser tiles stood in for some still loading.
    fn frames_with_stand_ins(&self) -> usize {
        let standing = |f: &&FlightFrame| f.tiles.is_some_and(|t| t.tiles_standing_in > 0);
        self.frames.iter().filter(standing).count()
    }

    /// The `--stats` JSON: what was flown, every frame, and a summary (`load_ms` opening the
    /// input, `build_ms` building its tracer, medians and extremes of the frames, `total_ms`).
    pub fn to_json(
        &self,
        args: &FlythroughArgs,
        plan: &FlightPlan,
        load_ms: f64,
        build_ms: f64,
        total_ms: f64,
    ) -> Value {
        let times: Vec<f64> = self.frames.iter().map(|f| f.time_ms).collect();
        let mean = times.iter().sum::<f64>() / times.len().max(1) as f64;
        let mut summary = json!({
            "frames": self.frames.len(),
            "median_time_ms": self.median_of(|f| f.time_ms),
            "mean_time_ms": mean,
            "max_time_ms": times.iter().copied().fold(0.0, f64::max),
            "median_write_ms": self.median_of(|f| f.write_ms),
            "load_ms": load_ms,
            "build_ms": build_ms,
            "total_ms": total_ms,
            "max_rss_bytes": self.frames.iter().filter_map(|f| f.rss_bytes).max(),
            "peak_rss_bytes": memory::peak_resident_bytes(),
        });
        if self.store {
            let tiles = || self.frames.iter().filter_map(|f| f.tiles.as_ref());
            let store = json!({
                "wait": args.wait,
                "median_io_wait_ms": self.median_tiles(|t| t.io_wait_ms),
                "total_io_wait_ms": tiles().map(|t| t.io_wait_ms).sum::<f64>(),
                "median_tiles_drawn": self.median_tiles(|t| t.tiles_drawn as f64),
                "frames_with_stand_ins": self.frames_with_stand_ins(),
                "max_resident_bytes": tiles().map(|t| t.resident_bytes).max(),
                "max_error_px": tiles().map(|t| t.max_error_px).fold(0.0, f64::max),
            });
            if let (Some(all), Value::Object(store)) = (summary.as_object_mut(), store) {
                all.extend(store);
            }
        }
        let input = match &args.scene.input.input {
            Some(path) => json!(path.display().to_string()),
            None => json!("fbm"),
        };
        json!({
            "input": input,
            "scene": self.scene,
            "kind": if self.store { "tile store" } else { "scene" },
            "camera_path": plan.path.display().to_string(),
            "path_span_s": [plan.span.0, plan.span.1],
            "width": args.scene.size.0,
            "height": args.scene.size.1,
            "threads": rayon::current_num_threads(),
            "frames": self.frames.iter().map(FlightFrame::to_json).collect::<Vec<_>>(),
            "summary": summary,
        })
    }
}
