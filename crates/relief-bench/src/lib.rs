//! relief-bench: relief's benchmarks in one place.
//!
//! The library holds what the `relief bench` command and the benchmarks share: the fixed
//! [`benchmark_views`] of a height field, so that every measurement of relief (and of Embree
//! beside it) traces the same rays, and the measurement machinery of `relief bench` (the
//! command parses its options, shows progress and prints the results): [`measure`] builds a
//! tracer or a renderer (through relief-render's `TracerSpec`), traces a view and the sun's
//! shadow rays, times them and summarises them as a [`Measurement`]; [`DynamicBench`] times
//! the hybrid renderer drawing a field that changes every frame. The benchmark programs live
//! in `benches/`: criterion benchmarks where they time one thing, and programs that print
//! their tables (`harness = false`) where they measure several things at once. Build them all
//! with `cargo bench -p relief-bench --no-run`; run one with
//! `cargo bench -p relief-bench --bench NAME -- ARGS`.
#![deny(missing_docs)]
#![forbid(unsafe_code)]

mod benchmark_views;
mod drawn;
mod dynamic;
mod error;
mod tracer_measurement;

pub use benchmark_views::{benchmark_views, BENCHMARK_VIEWS};
pub use drawn::{Drawn, DrawnSettings};
pub use dynamic::{ChangeKind, DynamicBench, FrameTimes};
pub use error::BenchError;
pub use tracer_measurement::{
    measure, MeasureSettings, Measurement, SweepMeasurement, BENCHMARK_SUN,
};
