use relief_core::*;
use relief_shade::*;
use relief_trace::*;
use std::sync::Arc;
fn main() {
    let bytes = std::fs::read("/work/shared/data/jacksboro_fault_dem.npy").unwrap();
    let hl = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    let data = &bytes[10 + hl..];
    let (h, w) = (344usize, 403usize);
    let mut s = vec![0f32; w * h];
    for r in 0..h {
        for c in 0..w {
            let k = (c + r * w) * 2;
            s[c + (h - 1 - r) * w] = i16::from_le_bytes([data[k], data[k + 1]]) as f32;
        }
    }
    let g = GridGeometry {
        dx: 75.0,
        dy: 92.0,
        z_scale: 1.0,
        origin: DVec2::new(500000.0, 4000000.0),
    };
    let field = Arc::new(HeightField::new(w, h, s, g).unwrap());
    for surface in [Surface::Triangles] {
        let bounds = field.world_bounds(surface);
        let tracer = build_tracer(field.clone(), surface, TracerKind::Mipmap);
        let args: Vec<String> = std::env::args().collect();
        let az: f64 = args.get(1).map_or(225.0, |a| a.parse().unwrap());
        let el: f64 = args.get(2).map_or(30.0, |a| a.parse().unwrap());
        let z: f64 = args.get(3).map_or(1.0, |a| a.parse().unwrap());
        let _ = z;
        let camera = Camera::frame_from(&bounds, az, el, 45.0, 800, 500).unwrap();
        let t0 = std::time::Instant::now();
        let (gb, st) = render_gbuffer(&*tracer, &camera, &bounds, &|_| {}).unwrap();
        let mut params = ShadingParams::for_terrain(&bounds).unwrap();
        params.sun.elevation_deg = 25.0;
        let (rad, sh) = shade(&gb, &*tracer, &camera, &params).unwrap();
        let rgb = tonemap_to_srgb8(&rad, params.exposure).unwrap();
        eprintln!(
            "{:?} {:?} {:.1} {:?}",
            t0.elapsed(),
            st,
            st.mean_steps(),
            sh
        );
        let mut out = format!("P6\n800 500\n255\n").into_bytes();
        out.extend(rgb);
        std::fs::write(format!("/tmp/demo_{surface}.ppm"), out).unwrap();
    }
}
