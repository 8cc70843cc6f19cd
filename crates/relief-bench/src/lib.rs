//! relief-bench: relief's benchmarks in one place.
//!
//! The library holds only what the `relief bench` command and every benchmark share: the
//! fixed [`benchmark_views`] of a height field, so that every measurement of relief (and of
//! Embree beside it) traces the same rays. The benchmark programs live in `benches/`:
//! criterion benchmarks where they time one thing, and programs that print their tables
//! (`harness = false`) where they measure several things at once. Build them all with
//! `cargo bench -p relief-bench --no-run`; run one with
//! `cargo bench -p relief-bench --bench NAME -- ARGS`.
#![deny(missing_docs)]
#![forbid(unsafe_code)]

mod benchmark_views;

pub use benchmark_views::{benchmark_views, BENCHMARK_VIEWS};
