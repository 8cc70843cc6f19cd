//! Random terrains and rays for property tests.

use proptest::prelude::*;
use relief_core::{DVec2, DVec3, GridGeometry, HeightField, Ray};

/// The character of a random terrain.
#[derive(Debug, Clone, Copy)]
pub enum Relief {
    Flat,
    Noisy,
    Spiky,
    Cliff,
    Integer,
}

/// A random height field from 1x1 to 64x70 with random geometry.
pub fn terrain() -> impl Strategy<Value = HeightField> {
    let kind = prop_oneof![
        Just(Relief::Flat),
        Just(Relief::Noisy),
        Just(Relief::Spiky),
        Just(Relief::Cliff),
        Just(Relief::Integer)
    ];
    (
        1usize..=64,
        1usize..=70,
        kind,
        any::<u64>(),
        0.25f64..4.0,
        0.25f64..4.0,
        0.1f64..3.0,
        -50.0f64..50.0,
    )
        .prop_map(|(w, h, kind, seed, dx, dy, zs, off)| {
            let mut rng = seed;
            let mut next = move || {
                // splitmix64
                rng = rng.wrapping_add(0x9e3779b97f4a7c15);
                let mut z = rng;
                z = (z ^ (z >> 30)).wrapping_mul(0xbf58476d1ce4e5b9);
                z = (z ^ (z >> 27)).wrapping_mul(0x94d049bb133111eb);
                ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
            };
            let (a, b, c) = (next(), next(), next());
            let samples = (0..w * h)
                .map(|i| {
                    let (x, y) = ((i % w) as f64, (i / w) as f64);
                    let v = match kind {
                        Relief::Flat => 3.0,
                        Relief::Noisy => 10.0 * next(),
                        Relief::Spiky => {
                            if next() < 0.05 {
                                50.0 * next()
                            } else {
                                next() * 0.5
                            }
                        }
                        Relief::Cliff => {
                            let side = (x - a * w as f64) * (b - 0.5) + (y - c * h as f64) * 0.7;
                            next() * 2.0 + if side > 0.0 { 1e4 } else { 0.0 }
                        }
                        Relief::Integer => (next() * 4.0).floor(),
                    };
                    (v + off) as f32
                })
                .collect();
            let geometry =
                GridGeometry { dx, dy, z_scale: zs, origin: DVec2::new(off * 3.0, -off) };
            let field = HeightField::new(w, h, samples, geometry).unwrap();
            // Holes in two cases out of five: scattered texels or a rectangle.
            let (x0, y0) = ((a * w as f64) as usize, (b * h as f64) as usize);
            let (x1, y1) =
                (x0 + 1 + (c * w as f64 / 2.0) as usize, y0 + 1 + (b * h as f64 / 3.0) as usize);
            let holes: Vec<bool> = match seed % 5 {
                0 => (0..w * h).map(|_| next() < 0.15).collect(),
                1 => (0..w * h)
                    .map(|i| (x0..x1).contains(&(i % w)) && (y0..y1).contains(&(i / w)))
                    .collect(),
                _ => return field,
            };
            // Every sample a hole is refused: keep the field whole then.
            field.clone().with_holes(holes).unwrap_or(field)
        })
}

/// Where a random ray starts and how it points.
#[derive(Debug, Clone, Copy)]
pub enum RayKind {
    FromAbove,
    InsideBox,
    BelowSurface,
    Grazing,
    AxisAligned,
    VerticalDown,
    VerticalUp,
    FromOutside,
}

/// A random ray of every kind for `field`, from eight unit-interval numbers.
pub fn ray_for(field: &HeightField, kind: RayKind, u: [f64; 8]) -> Ray {
    let b = field.world_bounds(relief_core::Surface::Boxes);
    let size = b.max - b.min;
    let lerp = |lo: f64, hi: f64, s: f64| lo + (hi - lo) * s;
    let inside = DVec3::new(
        lerp(b.min.x, b.max.x, u[0]),
        lerp(b.min.y, b.max.y, u[1]),
        lerp(b.min.z - 0.5 * size.z - 0.1, b.max.z + 0.5 * size.z + 0.1, u[2]),
    );
    let height = size.z.max(1.0);
    let random_dir = || {
        let z = 2.0 * u[3] - 1.0;
        let phi = u[4] * std::f64::consts::TAU;
        let r = (1.0 - z * z).sqrt();
        DVec3::new(r * phi.cos(), r * phi.sin(), z)
    };
    let (origin, dir) = match kind {
        RayKind::FromAbove => {
            let o = DVec3::new(inside.x, inside.y, b.max.z + height * (0.1 + 2.0 * u[5]));
            let target =
                DVec3::new(lerp(b.min.x, b.max.x, u[6]), lerp(b.min.y, b.max.y, u[7]), b.min.z);
            (o, (target - o).normalize())
        }
        RayKind::InsideBox => (inside, random_dir()),
        RayKind::BelowSurface => {
            let g = field.geometry();
            let c = ((u[0] * field.width() as f64) as usize).min(field.width() - 1);
            let r = ((u[1] * field.height() as f64) as usize).min(field.height() - 1);
            let top = field.sample(c, r) as f64 * g.z_scale;
            let o = DVec3::new(
                g.origin.x + (c as f64 + 0.5 + 0.8 * (u[6] - 0.5)) * g.dx,
                g.origin.y + (r as f64 + 0.5 + 0.8 * (u[7] - 0.5)) * g.dy,
                top - u[2] * height,
            );
            (o, random_dir())
        }
        RayKind::Grazing => {
            let o = DVec3::new(
                b.min.x - size.x * u[5],
                inside.y,
                lerp(b.min.z, b.max.z, 0.5 + 0.5 * u[2]),
            );
            let phi = (u[4] - 0.5) * 1.2;
            (o, DVec3::new(phi.cos(), phi.sin(), (u[3] - 0.5) * 0.02).normalize())
        }
        RayKind::AxisAligned => {
            let dir = [DVec3::X, -DVec3::X, DVec3::Y, -DVec3::Y][(u[5] * 4.0) as usize % 4];
            (inside - dir * size.length() * u[6], dir)
        }
        RayKind::VerticalDown => {
            (DVec3::new(inside.x, inside.y, b.max.z + height * u[5]), -DVec3::Z)
        }
        RayKind::VerticalUp => (DVec3::new(inside.x, inside.y, b.min.z - height * u[5]), DVec3::Z),
        RayKind::FromOutside => {
            let angle = u[5] * std::f64::consts::TAU;
            let c = b.center();
            let r = size.length().max(1.0);
            let o = c + DVec3::new(angle.cos() * r, angle.sin() * r, (u[6] - 0.3) * height * 2.0);
            ((o), (inside - o).normalize())
        }
    };
    Ray::new(origin, dir)
}

pub const ALL_KINDS: [RayKind; 8] = [
    RayKind::FromAbove,
    RayKind::InsideBox,
    RayKind::BelowSurface,
    RayKind::Grazing,
    RayKind::AxisAligned,
    RayKind::VerticalDown,
    RayKind::VerticalUp,
    RayKind::FromOutside,
];

/// Whether two optional hit distances agree to `rel` relative.
pub fn agree(a: Option<f64>, b: Option<f64>, rel: f64) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(x), Some(y)) => (x - y).abs() <= rel * x.abs().max(y.abs()) + 1e-9,
        _ => false,
    }
}
