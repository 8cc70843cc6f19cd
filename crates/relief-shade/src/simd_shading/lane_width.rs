//! How many pixels the shading kernel lights at once, and which widths this processor runs.

use std::sync::OnceLock;

/// The lane width of the `f32` shading kernel: the same bytes at every width.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LaneWidth {
    /// 8 lanes in plain Rust, compiled for the baseline processor: runs everywhere.
    Portable,
    /// 8 lanes compiled for AVX2 and FMA (x86-64).
    Avx2,
    /// 16 lanes compiled for AVX-512 (x86-64 with AVX-512 F, VL, DQ and BW).
    Avx512,
}

/// The environment variable that forces a lane width for the whole process (`portable`,
/// `avx2` or `avx512`), to compare them; a width the processor lacks is ignored.
pub const LANE_WIDTH_VARIABLE: &str = "RELIEF_SHADING_LANES";

impl LaneWidth {
    /// Every width, narrowest first.
    pub const ALL: [LaneWidth; 3] = [LaneWidth::Portable, LaneWidth::Avx2, LaneWidth::Avx512];

    /// Pixels lit at once.
    pub fn lanes(self) -> usize {
        match self {
            LaneWidth::Portable | LaneWidth::Avx2 => 8,
            LaneWidth::Avx512 => 16,
        }
    }

    /// The width's name, as [`LANE_WIDTH_VARIABLE`] takes it.
    pub fn name(self) -> &'static str {
        match self {
            LaneWidth::Portable => "portable",
            LaneWidth::Avx2 => "avx2",
            LaneWidth::Avx512 => "avx512",
        }
    }

    /// Whether this processor runs the width.
    pub fn is_available(self) -> bool {
        match self {
            LaneWidth::Portable => true,
            #[cfg(target_arch = "x86_64")]
            LaneWidth::Avx2 => is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma"),
            #[cfg(target_arch = "x86_64")]
            LaneWidth::Avx512 => {
                LaneWidth::Avx2.is_available()
                    && is_x86_feature_detected!("avx512f")
                    && is_x86_feature_detected!("avx512vl")
                    && is_x86_feature_detected!("avx512dq")
                    && is_x86_feature_detected!("avx512bw")
            }
            #[cfg(not(target_arch = "x86_64"))]
            LaneWidth::Avx2 | LaneWidth::Avx512 => false,
        }
    }

    /// The width the kernel uses unless told otherwise: [`LANE_WIDTH_VARIABLE`] when it names
    /// a width this processor runs, else the widest that pays (see [`LaneWidth::widest`]).
    /// Decided once per process.
    pub fn detect() -> LaneWidth {
        static CHOSEN: OnceLock<LaneWidth> = OnceLock::new();
        *CHOSEN.get_or_init(|| {
            let forced = std::env::var(LANE_WIDTH_VARIABLE).ok().and_then(|name| {
                LaneWidth::ALL.into_iter().find(|w| w.name() == name.trim() && w.is_available())
            });
            forced.unwrap_or_else(LaneWidth::widest)
        })
    }

    /// The widest width this processor runs: it pays where there is one (AVX-512 shades a
    /// frame in about 0.65 of AVX2's time on an AMD EPYC with AVX-512, AVX2 in 0.7 of the
    /// portable path's; `cargo bench -p relief-bench --bench shading_lanes`).
    pub fn widest() -> LaneWidth {
        LaneWidth::ALL.into_iter().rev().find(|w| w.is_available()).unwrap_or(LaneWidth::Portable)
    }
}
