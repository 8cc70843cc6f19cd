//! Anti-aliasing against the picture it should converge to: a flat terrain's edge seen
//! straight down, a half-plane whose coverage of every pixel is known exactly.

use relief_core::colour::srgb8_to_linear_table;
use relief_core::{Camera, DVec3, GridGeometry, HeightField, Projection, Surface};
use relief_render::antialias::edges::edge_mask;
use relief_render::scenes::height_field::shading;
use relief_render::{
    Antialiasing, HeightFieldScene, HybridSettings, KeptHits, LightSettings, Picture,
    SafetySettings, Scene, Silent, TracerChoice,
};
use relief_trace::TracerKind;
use std::sync::Arc;

/// The picture's size, pixels a side, and the world size of a pixel, metres.
const SIDE: u32 = 48;
const PIXEL: f64 = 0.25;

/// A flat terrain of 64 x 64 samples a metre apart, and a camera looking straight down at
/// its east edge from above, its image turned by `turn_deg` so the edge runs slanted.
fn edge_scene(turn_deg: f64) -> (Scene, Camera, Edge) {
    let field = HeightField::new(64, 64, vec![10.0; 64 * 64], GridGeometry::unit()).unwrap();
    let field = Arc::new(field);
    let bounds = field.world_bounds(Surface::Triangles);
    let params = shading(&LightSettings::default(), &bounds, 1.0).unwrap();
    let scene = Scene::HeightField(HeightFieldScene {
        field,
        surface: Surface::Triangles,
        choice: TracerChoice::Plain(TracerKind::Mipmap),
        safety: SafetySettings::default(),
        hybrid: HybridSettings::default(),
        max_memory: 1 << 30,
        params,
        normal_style: None,
        colours: None,
        warnings: Vec::new(),
    });
    let edge_x = bounds.max.x;
    let centre = DVec3::new(edge_x + 0.3, 32.0, 10.0);
    let turn = turn_deg.to_radians();
    let up = DVec3::new(turn.sin(), turn.cos(), 0.0);
    let ortho = Projection::Orthographic { height: PIXEL * SIDE as f64 };
    let eye = centre + DVec3::new(0.0, 0.0, 50.0);
    let camera = Camera::new(eye, centre, up, ortho, SIDE, SIDE).unwrap();
    (scene, camera, Edge { x: edge_x, camera })
}

/// The terrain's east edge, `x = x`, as `camera` sees it.
struct Edge {
    x: f64,
    camera: Camera,
}

impl Edge {
    /// The share of pixel (i, j)'s square over the terrain (west of the edge), integrated on
    /// a 256 x 256 grid (to 1/256 of the pixel's side).
    fn coverage(&self, i: u32, j: u32) -> f64 {
        const N: usize = 256;
        let (right, up) = (self.camera.right(), self.camera.image_up());
        let centre = self.camera.ray(i, j).origin;
        let mut inside = 0;
        for s in 0..N * N {
            let u = ((s % N) as f64 + 0.5) / N as f64 - 0.5;
            let v = ((s / N) as f64 + 0.5) / N as f64 - 0.5;
            let p = centre + (u * right + v * up) * PIXEL;
            inside += usize::from(p.x < self.x);
        }
        inside as f64 / (N * N) as f64
    }

    /// The distance from pixel (i, j)'s centre to the edge, in pixels.
    fn distance_px(&self, i: u32, j: u32) -> f64 {
        (self.camera.ray(i, j).origin.x - self.x).abs() / PIXEL
    }
}

fn render(scene: &Scene, camera: &Camera, aa: Antialiasing) -> Picture {
    let keep = KeptHits { depth: true, normals: true };
    scene.render(camera, keep, aa, &Silent).unwrap()
}

/// The linear light of a channel of a pixel.
fn linear(picture: &Picture, i: u32, j: u32, channel: usize) -> f64 {
    let k = (i + j * picture.width) as usize;
    srgb8_to_linear_table()[picture.rgb[k][channel] as usize] as f64
}

#[test]
fn a_grid_of_samples_converges_to_the_edge_s_area_coverage() {
    let (scene, camera, edge) = edge_scene(23.0);
    let off = render(&scene, &camera, Antialiasing::Off);
    // The colours of a pixel wholly over the terrain and of one wholly beside it.
    let pure = |want: f64| {
        let (i, j) = (0..SIDE * SIDE)
            .map(|k| (k % SIDE, k / SIDE))
            .find(|&(i, j)| edge.coverage(i, j) == want && edge.distance_px(i, j) > 2.0)
            .expect("a pure pixel");
        [0, 1, 2].map(|c| linear(&off, i, j, c))
    };
    let (terrain, beside) = (pure(1.0), pure(0.0));
    let channel = (0..3)
        .max_by(|&a, &b| (terrain[a] - beside[a]).abs().total_cmp(&(terrain[b] - beside[b]).abs()));
    let c = channel.unwrap();
    assert!((terrain[c] - beside[c]).abs() > 0.1, "the terrain stands out: {terrain:?} {beside:?}");
    // Each pixel's coverage as the picture shows it, against the exact one.
    let mean_error = |picture: &Picture| {
        let mut sum = 0.0;
        let mut n = 0;
        for j in 0..SIDE {
            for i in 0..SIDE {
                if edge.distance_px(i, j) < 1.0 {
                    let shown = (linear(picture, i, j, c) - beside[c]) / (terrain[c] - beside[c]);
                    sum += (shown - edge.coverage(i, j)).abs();
                    n += 1;
                }
            }
        }
        sum / n as f64
    };
    let errors: Vec<f64> = [1, 2, 4, 8]
        .map(|n| {
            let aa = if n == 1 { Antialiasing::Off } else { Antialiasing::Grid(n) };
            mean_error(&render(&scene, &camera, aa))
        })
        .to_vec();
    eprintln!("mean coverage error at 1, 2, 4, 8 samples a side: {errors:?}");
    assert!(errors.windows(2).all(|e| e[1] < e[0]), "the error falls: {errors:?}");
    // A stratified grid of n x n samples comes within about 1 / n² of a straight edge's
    // coverage on average.
    assert!(errors[0] > 0.08, "one sample a pixel shows 0 or 1: {errors:?}");
    assert!(errors[3] < 0.01, "8 x 8 samples give the coverage: {errors:?}");
}

#[test]
fn the_adaptive_pass_samples_again_only_the_pixels_along_the_edge() {
    let (scene, camera, edge) = edge_scene(31.0);
    let off = render(&scene, &camera, Antialiasing::Off);
    let adaptive = render(&scene, &camera, Antialiasing::Adaptive);
    let marks = edge_mask(&off);
    for j in 0..SIDE {
        for i in 0..SIDE {
            let k = (i + j * SIDE) as usize;
            let (marked, coverage) = (marks.contains(i as usize, j as usize), edge.coverage(i, j));
            // A pixel the edge crosses is marked; one more than a pixel and a half from it
            // (a diagonal neighbour's reach) is not, and keeps its aliased colour.
            if coverage > 0.02 && coverage < 0.98 {
                assert!(marked, "pixel ({i}, {j}) of coverage {coverage} is not marked");
            }
            if edge.distance_px(i, j) > 1.5 * std::f64::consts::SQRT_2 {
                assert!(!marked, "pixel ({i}, {j}) far from the edge is marked");
            }
            if !marked {
                assert_eq!(adaptive.rgb[k], off.rgb[k], "pixel ({i}, {j}) changed");
            }
        }
    }
    assert!(marks.count() > 0);
    assert_eq!(adaptive.stats["aa_samples"], marks.count() as u64 * 4);
}

#[test]
fn depth_and_normals_stay_those_of_the_centre_rays() {
    let (scene, camera, _) = edge_scene(17.0);
    let off = render(&scene, &camera, Antialiasing::Off);
    for aa in [Antialiasing::Adaptive, Antialiasing::Grid(2), Antialiasing::Grid(3)] {
        let picture = render(&scene, &camera, aa);
        assert_eq!(picture.depth, off.depth, "{aa}");
        assert_eq!(picture.normals, off.normals, "{aa}");
        assert_ne!(picture.rgb, off.rgb, "{aa} smooths the edge");
        assert_eq!((picture.width, picture.height), (SIDE, SIDE));
    }
}

#[test]
fn the_modes_read_as_the_command_line_writes_them() {
    let parse = |s: &str| s.parse::<Antialiasing>();
    assert_eq!(parse("adaptive"), Ok(Antialiasing::Adaptive));
    assert_eq!(parse("off"), Ok(Antialiasing::Off));
    assert_eq!(parse("1"), Ok(Antialiasing::Off));
    assert_eq!(parse("4"), Ok(Antialiasing::Grid(4)));
    for bad in ["0", "9", "-2", "fast", ""] {
        let message = parse(bad).unwrap_err();
        assert!(message.contains("off, adaptive"), "{bad}: {message}");
    }
    assert_eq!(Antialiasing::default(), Antialiasing::Adaptive);
}
