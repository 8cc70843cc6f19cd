//! The rays every tracer is checked with, of every kind that has found bugs in tracers: from
//! above, grazing, vertical, axis-aligned, from inside the solid, from outside the grid, and
//! rays that miss; some with a direction that is not of unit length (`t` is a parameter, not
//! a distance).

use super::seeded::Seeded;
use relief_core::{DVec3, HeightField, Ray, Surface};

/// Where a ray starts and how it points.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RayKind {
    /// From above the terrain towards a point of its footprint at the lowest height.
    FromAbove,
    /// Nearly horizontal, from beside the grid across it.
    Grazing,
    /// Straight down from above.
    VerticalDown,
    /// Straight up from below.
    VerticalUp,
    /// Along +-x or +-y through the terrain's box.
    AxisAligned,
    /// From under a sample, inside the solid, in any direction.
    FromInside,
    /// From anywhere in and around the terrain's box, in any direction.
    Anywhere,
    /// From outside the grid towards a point in its box.
    FromOutside,
    /// Away from the terrain: up from above it, or outwards from beside it.
    Away,
}

/// Every kind, in a fixed order.
pub const RAY_KINDS: [RayKind; 9] = [
    RayKind::FromAbove,
    RayKind::Grazing,
    RayKind::VerticalDown,
    RayKind::VerticalUp,
    RayKind::AxisAligned,
    RayKind::FromInside,
    RayKind::Anywhere,
    RayKind::FromOutside,
    RayKind::Away,
];

/// A ray of `kind` for `field`, drawn from `numbers`; one in four has its direction scaled to
/// a length between 0.25 and 4.
pub fn ray(field: &HeightField, kind: RayKind, numbers: &mut Seeded) -> Ray {
    let b = field.world_bounds(Surface::Boxes);
    let size = b.max - b.min;
    let height = size.z.max(1.0);
    let mut u = [0.0; 8];
    u.iter_mut().for_each(|x| *x = numbers.range(0.001, 0.999));
    let lerp = |lo: f64, hi: f64, s: f64| lo + (hi - lo) * s;
    let point = DVec3::new(
        lerp(b.min.x, b.max.x, u[0]),
        lerp(b.min.y, b.max.y, u[1]),
        lerp(b.min.z - 0.5 * size.z - 0.1, b.max.z + 0.5 * size.z + 0.1, u[2]),
    );
    let any_dir = {
        let z = 2.0 * u[3] - 1.0;
        let phi = u[4] * std::f64::consts::TAU;
        let r = (1.0 - z * z).sqrt();
        DVec3::new(r * phi.cos(), r * phi.sin(), z)
    };
    let (origin, dir) = match kind {
        RayKind::FromAbove => {
            let o = DVec3::new(point.x, point.y, b.max.z + height * (0.1 + 2.0 * u[5]));
            let target =
                DVec3::new(lerp(b.min.x, b.max.x, u[6]), lerp(b.min.y, b.max.y, u[7]), b.min.z);
            (o, (target - o).normalize())
        }
        RayKind::Grazing => {
            let o = DVec3::new(b.min.x - size.x * u[5], point.y, lerp(b.min.z, b.max.z, u[2]));
            let phi = (u[4] - 0.5) * 1.2;
            (o, DVec3::new(phi.cos(), phi.sin(), (u[3] - 0.5) * 0.02).normalize())
        }
        RayKind::VerticalDown => (DVec3::new(point.x, point.y, b.max.z + height * u[5]), -DVec3::Z),
        RayKind::VerticalUp => (DVec3::new(point.x, point.y, b.min.z - height * u[5]), DVec3::Z),
        RayKind::AxisAligned => {
            let dir = [DVec3::X, -DVec3::X, DVec3::Y, -DVec3::Y][(u[5] * 4.0) as usize % 4];
            (point - dir * size.length() * u[6], dir)
        }
        RayKind::FromInside => {
            let g = field.geometry();
            let (c, r) = (numbers.index(field.width()), numbers.index(field.height()));
            let top = field.sample(c, r) as f64 * g.z_scale;
            let o = DVec3::new(
                g.origin.x + (c as f64 + 0.5 + 0.8 * (u[6] - 0.5)) * g.dx,
                g.origin.y + (r as f64 + 0.5 + 0.8 * (u[7] - 0.5)) * g.dy,
                top - u[2] * (top - b.min.z),
            );
            (o, any_dir)
        }
        RayKind::Anywhere => (point, any_dir),
        RayKind::FromOutside => {
            let angle = u[5] * std::f64::consts::TAU;
            let r = size.length().max(1.0);
            let o = b.center()
                + DVec3::new(angle.cos() * r, angle.sin() * r, (u[6] - 0.3) * height * 2.0);
            (o, (point - o).normalize())
        }
        RayKind::Away => {
            if u[5] < 0.5 {
                (DVec3::new(point.x, point.y, b.max.z + 0.1 * height), any_dir.abs())
            } else {
                let out = DVec3::new(u[6] - 0.5, u[7] - 0.5, 0.0).normalize();
                (b.center() + out * size.length(), (out + 0.3 * any_dir).normalize())
            }
        }
    };
    let length = if numbers.unit() < 0.25 { numbers.range(0.25, 4.0) } else { 1.0 };
    Ray::new(origin, dir * length)
}
