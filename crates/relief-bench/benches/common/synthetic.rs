//! The benchmarks' input: a deterministic synthetic terrain and a CPU-time clock.

use relief_core::{GridGeometry, HeightField};

/// A deterministic fractal terrain: octaves of hashed value noise, heights in metres.
pub fn synthetic_field(n: usize) -> HeightField {
    let hash = |x: i64, y: i64, o: i64| {
        let mut h = (x.wrapping_mul(374_761_393)
            ^ y.wrapping_mul(668_265_263)
            ^ o.wrapping_mul(2_147_483_647)) as u64;
        h = (h ^ (h >> 13)).wrapping_mul(1_274_126_177);
        ((h ^ (h >> 16)) & 0xffff) as f64 / 65535.0
    };
    let noise = |x: f64, y: f64, o: i64| {
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (sx, sy) = (fx * fx * (3.0 - 2.0 * fx), fy * fy * (3.0 - 2.0 * fy));
        let (xi, yi) = (x0 as i64, y0 as i64);
        let a = hash(xi, yi, o) + sx * (hash(xi + 1, yi, o) - hash(xi, yi, o));
        let b = hash(xi, yi + 1, o) + sx * (hash(xi + 1, yi + 1, o) - hash(xi, yi + 1, o));
        a + sy * (b - a)
    };
    let samples = (0..n * n)
        .map(|k| {
            let (x, y) = ((k % n) as f64 / 256.0, (k / n) as f64 / 256.0);
            let mut h = 0.0;
            for octave in 0..8 {
                let f = (1 << octave) as f64;
                h += noise(x * f, y * f, octave) * 300.0 / f;
            }
            h as f32
        })
        .collect();
    HeightField::new(n, n, samples, GridGeometry::unit()).expect("a valid synthetic field")
}

/// CPU seconds (user + system) this process has used, from /proc (0 where there is none):
/// on a shared machine the wall time of a parallel draw depends on the other load.
pub fn cpu_seconds() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let fields: Vec<&str> = stat.rsplit(')').next().unwrap_or("").split_whitespace().collect();
    let ticks = |k: usize| fields.get(k).and_then(|v| v.parse::<f64>().ok()).unwrap_or(0.0);
    (ticks(11) + ticks(12)) / 100.0
}
