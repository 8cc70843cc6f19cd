//! Time per call of an MLHM's exact box volumes ([`Mlhm::material_volumes`],
//! [`Mlhm::solid_volume`]) on a 512 x 512 map of 6.25 cm cells, single-column and with 1 to 4
//! columns a cell, for boxes of 9 x 9 and 65 x 65 cells at random places (cold caches) and
//! along a scanline (neighbouring pixels' boxes, half a cell apart). Each benchmark sums the
//! volumes of 4096 boxes; criterion reports the time of those 4096 calls and calls per second.
//!
//! `cargo bench -p relief-bench --bench mlhm_volume [-- FILTER]`

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use relief_core::{DVec3, Mlhm, MlhmColumn};
use std::time::Duration;

/// Cells on a side of the map.
const MAP_CELLS: usize = 512;
/// The cell size, metres.
const CELL_SIZE: f64 = 0.0625;
/// Boxes per benchmark iteration.
const BOXES: usize = 4096;

/// A deterministic stream of numbers in `[0, 1)` (SplitMix64).
struct Stream(u64);

impl Stream {
    fn unit(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A thickness up to `max`, zero a third of the time.
    fn layer(&mut self, max: f64) -> f32 {
        let u = self.unit();
        if u < 1.0 / 3.0 {
            0.0
        } else {
            ((u - 1.0 / 3.0) * 1.5 * max) as f32
        }
    }
}

/// A seeded map of [`MAP_CELLS`]^2 cells with 1 to `max_columns` columns a cell: random
/// bedrock, often empty sand and water, and air gaps between the columns.
fn seeded_map(stream: &mut Stream, max_columns: usize) -> Mlhm {
    let mut map = Mlhm::new(MAP_CELLS, MAP_CELLS, max_columns, CELL_SIZE).expect("a valid map");
    let mut columns = Vec::with_capacity(max_columns);
    for y in 0..MAP_CELLS {
        for x in 0..MAP_CELLS {
            let count = 1 + ((stream.unit() * max_columns as f64) as usize).min(max_columns - 1);
            let mut bedrock = (stream.unit() * 4.0 - 2.0) as f32;
            columns.clear();
            for k in 0..count {
                let (sand, water) = (stream.layer(1.0), stream.layer(1.0));
                let mut column = MlhmColumn::new(bedrock, sand, water, f32::INFINITY);
                if k + 1 < count {
                    column.ceiling = column.water_top() + stream.layer(1.5);
                    bedrock = column.ceiling + stream.layer(1.5);
                }
                columns.push(column);
            }
            map.set_cell(x, y, &columns).expect("columns in order");
        }
    }
    map
}

/// The centres of [`BOXES`] boxes `cells` wide: at random places, or along scanlines half a
/// cell apart.
fn box_centres(stream: &mut Stream, cells: usize, scanline: bool) -> Vec<DVec3> {
    let half = cells as f64 * CELL_SIZE / 2.0;
    let reach = MAP_CELLS as f64 * CELL_SIZE - 2.0 * half;
    (0..BOXES)
        .map(|n| {
            let (x, y) = if scanline {
                ((n % 256) as f64 * 0.5 * CELL_SIZE, (n / 256) as f64 * 8.0 * CELL_SIZE)
            } else {
                (stream.unit() * reach, stream.unit() * reach)
            };
            DVec3::new(half + x, half + y, stream.unit() * 5.0 - 1.0)
        })
        .collect()
}

/// Every combination of columns a cell, box size, placement and volume function.
fn volumes(c: &mut Criterion) {
    let mut stream = Stream(7);
    let mut group = c.benchmark_group("mlhm_volume");
    group.sample_size(20).measurement_time(Duration::from_secs(3));
    group.throughput(Throughput::Elements(BOXES as u64));
    for max_columns in [1, 4] {
        let map = seeded_map(&mut stream, max_columns);
        for cells in [9usize, 65] {
            let half = cells as f64 * CELL_SIZE / 2.0;
            for scanline in [false, true] {
                let centres = box_centres(&mut stream, cells, scanline);
                let place = if scanline { "scanline" } else { "random" };
                let case = format!("1..={max_columns} columns, {cells}x{cells} cells, {place}");
                group.bench_function(BenchmarkId::new("material_volumes", &case), |b| {
                    b.iter(|| {
                        let boxes = centres.iter().map(|&c| (c - half, c + half));
                        boxes.map(|(min, max)| map.material_volumes(min, max).total()).sum::<f64>()
                    })
                });
                group.bench_function(BenchmarkId::new("solid_volume", &case), |b| {
                    b.iter(|| {
                        let boxes = centres.iter().map(|&c| (c - half, c + half));
                        boxes.map(|(min, max)| map.solid_volume(min, max)).sum::<f64>()
                    })
                });
            }
        }
    }
    group.finish();
}

criterion_group!(benches, volumes);
criterion_main!(benches);
