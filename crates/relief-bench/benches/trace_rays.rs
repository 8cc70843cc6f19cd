//! relief's mipmap tracer on premade rays: the "fair on both sides" half of the native Embree
//! anchor (issue 37), tracing exactly the ray files bench/embree_native.c traces, the same
//! way.
//!
//! It builds `MipmapTracer` over the `triangles` surface of a height field (an `.npy`), then
//! runs one command a line read from standard input, as the Embree harness does:
//!
//! - `primary RAYS OUT`: `Tracer::intersect_batch` on batches of 256 consecutive rays (the
//!   files hold them in the renderer's tile order, 16x16 tiles, Morton inside a tile, so a
//!   batch is a tile), writing each ray's distance (`+inf` for a miss) and unit normal (zeros
//!   for a miss);
//! - `shadow RAYS OUT`: `Tracer::occluded_batch` on batches of 256, writing each ray's
//!   occlusion.
//!
//! RAYS is raw float32, six a ray (origin, direction), each ray over `[0, +inf)`. The rays are
//! read and converted and the output buffers allocated and filled before the clock starts;
//! the timed part traces on THREADS rayon threads into those buffers. When OUT is not `-`,
//! the outputs are written after the run to `OUT.distance.f32` and `OUT.normal.f32` (three
//! floats a ray) or `OUT.occluded.u8`. Each command prints one JSON line (kind, rays, wall
//! seconds, CPU seconds of all threads, Mrays/s, hits or blocked rays, peak resident set); the
//! build prints one first.
//!
//! ```sh
//! printf 'primary rays.f32 -\nshadow shadow.f32 -\n' \
//!     | cargo bench -p relief-bench --bench trace_rays -- fbm-4096.npy 2
//! ```

use anyhow::{bail, Context, Result};
use rayon::prelude::*;
use relief_core::{DVec3, Ray, Surface};
use relief_trace::{Hit, MipmapTracer, Tracer};
use std::io::BufRead;
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

#[path = "common/args.rs"]
mod args;
#[path = "common/process_clock.rs"]
mod process_clock;
#[path = "common/raw_files.rs"]
mod raw_files;

/// Rays a batch: a 16x16 tile, as the renderer passes them.
const BATCH: usize = 256;

/// What one command traces.
#[derive(Clone, Copy, PartialEq)]
enum Kind {
    Primary,
    Shadow,
}

/// The outputs of one run, allocated and filled before it.
struct Outputs {
    distance: Vec<f32>,
    normal: Vec<[f32; 3]>,
    occluded: Vec<u8>,
}

/// The rays of a raw float32 file, six values a ray.
fn read_rays(path: &Path) -> Result<Vec<Ray>> {
    let values = raw_files::read_f32s(path)?;
    if values.len() % 6 != 0 {
        bail!("{}: {} floats is not six a ray", path.display(), values.len());
    }
    let vector = |v: &[f32]| DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64);
    Ok(values.chunks_exact(6).map(|r| Ray::new(vector(&r[..3]), vector(&r[3..]))).collect())
}

/// Traces `rays` as `kind` says into `out`, batch by batch in parallel.
fn trace(tracer: &MipmapTracer, kind: Kind, rays: &[Ray], out: &mut Outputs) {
    let scratch = || (vec![None::<Hit>; BATCH], vec![0u32; BATCH], vec![false; BATCH]);
    if kind == Kind::Shadow {
        rays.par_chunks(BATCH).zip(out.occluded.par_chunks_mut(BATCH)).for_each_init(
            scratch,
            |(_, steps, blocked), (batch, occluded)| {
                let n = batch.len();
                tracer.occluded_batch(batch, &mut blocked[..n], &mut steps[..n]);
                for (o, &b) in occluded.iter_mut().zip(blocked.iter()) {
                    *o = u8::from(b);
                }
            },
        );
        return;
    }
    let outputs = out.distance.par_chunks_mut(BATCH).zip(out.normal.par_chunks_mut(BATCH));
    rays.par_chunks(BATCH).zip(outputs).for_each_init(
        scratch,
        |(hits, steps, _), (batch, (distance, normal))| {
            let n = batch.len();
            tracer.intersect_batch(batch, &mut hits[..n], &mut steps[..n]);
            for ((hit, d), m) in hits.iter().zip(distance.iter_mut()).zip(normal.iter_mut()) {
                (*d, *m) = match hit {
                    Some(hit) => (hit.t as f32, hit.normal.as_vec3().to_array()),
                    None => (f32::INFINITY, [0.0; 3]),
                };
            }
        },
    );
}

/// The peak resident set of this process so far, in MiB (from /proc; 0 where unknown).
fn peak_rss_mib() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let line = status.lines().find(|l| l.starts_with("VmHWM:")).unwrap_or("VmHWM: 0 kB");
    let kib: f64 = line.split_whitespace().nth(1).and_then(|v| v.parse().ok()).unwrap_or(0.0);
    kib / 1024.0
}

/// Runs one command line: traces, prints its JSON line, writes the outputs.
fn run(tracer: &MipmapTracer, pool: &rayon::ThreadPool, line: &str) -> Result<()> {
    let words: Vec<&str> = line.split_whitespace().collect();
    let [kind, rays_path, out_prefix] = words[..] else {
        bail!("expected 'primary|shadow RAYS OUT', got '{line}'");
    };
    let kind = match kind {
        "primary" => Kind::Primary,
        "shadow" => Kind::Shadow,
        other => bail!("unknown command '{other}' (primary or shadow)"),
    };
    let rays = read_rays(rays_path.as_ref())?;
    let n = rays.len();
    let mut out = Outputs {
        distance: vec![f32::INFINITY; if kind == Kind::Primary { n } else { 0 }],
        normal: vec![[0.0; 3]; if kind == Kind::Primary { n } else { 0 }],
        occluded: vec![0; if kind == Kind::Shadow { n } else { 0 }],
    };
    let cpu_started = process_clock::cpu_seconds();
    let started = Instant::now();
    pool.install(|| trace(tracer, kind, &rays, &mut out));
    let seconds = started.elapsed().as_secs_f64();
    let cpu = process_clock::cpu_seconds() - cpu_started;
    let (name, found_key, found) = match kind {
        Kind::Primary => ("primary", "hits", out.distance.iter().filter(|d| d.is_finite()).count()),
        Kind::Shadow => ("shadow", "blocked", out.occluded.iter().filter(|&&o| o != 0).count()),
    };
    println!(
        "{{\"kind\": \"{name}\", \"rays\": {n}, \"seconds\": {seconds:.6}, \
         \"cpu_seconds\": {cpu:.6}, \"mrays_s\": {:.3}, \"{found_key}\": {found}, \
         \"peak_mib\": {:.1}}}",
        n as f64 / seconds / 1e6,
        peak_rss_mib()
    );
    if out_prefix != "-" {
        if kind == Kind::Shadow {
            let path = format!("{out_prefix}.occluded.u8");
            std::fs::write(&path, &out.occluded).with_context(|| format!("writing {path}"))?;
        } else {
            let flat: Vec<f32> = out.normal.iter().flatten().copied().collect();
            raw_files::write_f32s(format!("{out_prefix}.distance.f32").as_ref(), &out.distance)?;
            raw_files::write_f32s(format!("{out_prefix}.normal.f32").as_ref(), &flat)?;
        }
    }
    Ok(())
}

fn main() -> Result<()> {
    let args = args::program_args();
    let [terrain, threads] = &args[..] else {
        bail!("usage: trace_rays TERRAIN.npy THREADS < commands");
    };
    let threads: usize = threads.parse().with_context(|| format!("THREADS '{threads}'"))?;
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build()?;
    let field = Arc::new(relief_io::read_npy_height_field(terrain.as_ref())?);
    let started = Instant::now();
    let tracer = pool.install(|| MipmapTracer::new(field, Surface::Triangles));
    println!(
        "{{\"kind\": \"build\", \"seconds\": {:.3}, \"threads\": {threads}, \"peak_mib\": {:.1}}}",
        started.elapsed().as_secs_f64(),
        peak_rss_mib()
    );
    for line in std::io::stdin().lock().lines() {
        let line = line?;
        if !line.trim().is_empty() {
            run(&tracer, &pool, &line)?;
        }
    }
    Ok(())
}
