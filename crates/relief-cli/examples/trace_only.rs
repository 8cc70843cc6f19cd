use relief_core::{Camera, Surface};
use relief_trace::safety::{FinalTest, SafetyShapes, SafetyTracer};
use relief_trace::{MipmapTracer, Tracer};
use std::sync::Arc;
use std::time::Instant;
fn main() {
    let n: usize = std::env::args().nth(1).map(|s| s.parse().unwrap()).unwrap_or(1024);
    let f = relief_sim::fbm_terrain(n, n, 1, &relief_sim::FbmParams::for_size(n, n)).unwrap();
    let f = Arc::new(f);
    let b = f.world_bounds(Surface::Triangles);
    let cams = [
        ("three-quarter", Camera::frame_from(&b, 225.0, 30.0, 45.0, 960, 540).unwrap()),
        ("steep", Camera::frame_from(&b, 225.0, 70.0, 30.0, 960, 540).unwrap()),
    ];
    let shapes =
        Arc::new(SafetyShapes::build(&f, "cyl_all+cone_all".parse().unwrap(), &|_, _| {}).unwrap());
    let s = SafetyTracer::new(f.clone(), shapes, FinalTest::Triangles).unwrap();
    let m = MipmapTracer::new(f.clone(), Surface::Triangles);
    for (name, cam) in &cams {
        for (tn, t) in [("mipmap", &m as &dyn Tracer), ("safety", &s as &dyn Tracer)] {
            let start = Instant::now();
            let mut hits = 0usize;
            let mut acc = 0.0;
            for j in 0..cam.height() {
                for i in 0..cam.width() {
                    if let Some(h) = t.intersect(&cam.ray(i, j)) {
                        hits += 1;
                        acc += h.t;
                    }
                }
            }
            let secs = start.elapsed().as_secs_f64();
            println!(
                "{name} {tn}: {:.2} Mrays/s single thread ({hits} hits, {acc:.1})",
                (cam.width() * cam.height()) as f64 / secs / 1e6
            );
        }
    }
}
