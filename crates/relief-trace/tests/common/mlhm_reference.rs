//! An independent brute-force MLHM tracer: a world-space slab test of every material layer of
//! every column of every cell, keeping the smallest `t`; and random MLHMs and rays for tests.

use relief_core::{DVec2, DVec3, Mlhm, MlhmColumn, Ray};
use relief_trace::{MlhmMaterial, MlhmMode};

/// The material layers `(bottom, top, material)` of column `k` of a cell that `mode` counts as
/// inside, bottom to top, including zero-thickness ones; the lowest column's solid begins at
/// the map's `base` (minus infinity unless the map is clipped, `Mlhm::set_base`).
fn layers(
    columns: &[MlhmColumn],
    k: usize,
    mode: MlhmMode,
    base: f64,
) -> Vec<(f64, f64, MlhmMaterial)> {
    let c = columns[k];
    let floor = if k == 0 { base } else { columns[k - 1].ceiling as f64 };
    let (bedrock, solid, water) = (c.bedrock as f64, c.solid_top() as f64, c.water_top() as f64);
    let mut out =
        vec![(floor, bedrock, MlhmMaterial::Bedrock), (bedrock, solid, MlhmMaterial::Sand)];
    match mode {
        MlhmMode::Solids => {}
        MlhmMode::SolidsWater => out.push((solid, water, MlhmMaterial::Water)),
        MlhmMode::SolidsAir => out.push((water, c.ceiling as f64, MlhmMaterial::Air)),
    }
    out
}

/// The parameter range of `ray` inside the closed box `[lo, hi]`, within its own range.
pub fn clip(ray: &Ray, lo: DVec3, hi: DVec3) -> Option<(f64, f64)> {
    let (mut t0, mut t1) = (ray.t_min, ray.t_max);
    for axis in 0..3 {
        let (o, d) = (ray.origin[axis], ray.dir[axis]);
        if d == 0.0 {
            if o < lo[axis] || o > hi[axis] {
                return None;
            }
        } else {
            let (a, b) = ((lo[axis] - o) / d, (hi[axis] - o) / d);
            t0 = t0.max(a.min(b));
            t1 = t1.min(a.max(b));
        }
    }
    (t0 <= t1).then_some((t0, t1))
}

/// Where `ray` enters the closed box `[lo, hi]` within its own range.
fn slab(ray: &Ray, lo: DVec3, hi: DVec3) -> Option<f64> {
    clip(ray, lo, hi).map(|(t0, _)| t0)
}

/// The first hit of `ray` with the material layers of `mode` of `map` placed with its
/// south-west corner at `origin`: its parameter and material. Layers of zero thickness hold
/// nothing; ties go to the first layer found (cells in index order, layers bottom up).
pub fn first_hit(
    map: &Mlhm,
    origin: DVec2,
    mode: MlhmMode,
    ray: &Ray,
) -> Option<(f64, MlhmMaterial)> {
    let s = map.cell_size();
    let mut best: Option<(f64, MlhmMaterial)> = None;
    for y in 0..map.height() {
        for x in 0..map.width() {
            let columns: Vec<MlhmColumn> = map.cell_columns(x, y).collect();
            let (x0, y0) = (origin.x + x as f64 * s, origin.y + y as f64 * s);
            for k in 0..columns.len() {
                for (bottom, top, material) in layers(&columns, k, mode, map.base() as f64) {
                    if top <= bottom {
                        continue;
                    }
                    let lo = DVec3::new(x0, y0, bottom);
                    let hi = DVec3::new(x0 + s, y0 + s, top);
                    if let Some(t) = slab(ray, lo, hi) {
                        if best.is_none_or(|(b, _)| t < b) {
                            best = Some((t, material));
                        }
                    }
                }
            }
        }
    }
    best
}

/// A small deterministic generator (SplitMix64), so a map or ray is a function of its seed.
#[derive(Debug, Clone)]
pub struct Rng(u64);

impl Rng {
    /// A generator from a seed.
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `[lo, hi)`.
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// True with probability `p`.
    pub fn chance(&mut self, p: f64) -> bool {
        self.range(0.0, 1.0) < p
    }

    /// Uniform in `0..n` (n > 0).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }

    /// A random unit vector.
    pub fn unit(&mut self) -> DVec3 {
        loop {
            let v = DVec3::new(self.range(-1.0, 1.0), self.range(-1.0, 1.0), self.range(-1.0, 1.0));
            let l = v.length();
            if l > 0.05 && l <= 1.0 {
                return v / l;
            }
        }
    }
}

/// A random map of `width x height` cells of `cell_size` with 1 to `max_columns` columns per
/// cell: random bedrock thickness, sand, water and air gaps, each sometimes exactly zero.
pub fn random_mlhm(
    rng: &mut Rng,
    width: usize,
    height: usize,
    max_columns: usize,
    cell_size: f64,
) -> Mlhm {
    let mut map = Mlhm::new(width, height, max_columns, cell_size).unwrap();
    for y in 0..height {
        for x in 0..width {
            let n = 1 + rng.below(max_columns);
            let mut columns = Vec::with_capacity(n);
            let mut floor = rng.range(-2.0, 2.0) as f32;
            for k in 0..n {
                let rock = if k == 0 || rng.chance(0.8) { rng.range(0.0, 1.5) } else { 0.0 };
                let bedrock = floor + rock as f32;
                let sand = if rng.chance(0.6) { rng.range(0.0, 1.0) as f32 } else { 0.0 };
                let water = if rng.chance(0.5) { rng.range(0.0, 1.0) as f32 } else { 0.0 };
                let mut c = MlhmColumn::new(bedrock, sand, water, f32::INFINITY);
                if k + 1 < n {
                    let gap = if rng.chance(0.85) { rng.range(0.05, 2.0) as f32 } else { 0.0 };
                    c.ceiling = c.water_top() + gap;
                    floor = c.ceiling;
                }
                columns.push(c);
            }
            map.set_cell(x, y, &columns).unwrap();
        }
    }
    map
}

/// The kinds of rays the property tests draw.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MlhmRayKind {
    /// From above the highest water top, going down.
    FromAbove,
    /// From anywhere in (a margin around) the scene, any direction.
    InsideBox,
    /// From an air gap under an overhang or in a cave, any direction.
    UnderOverhang,
    /// Horizontal, from anywhere.
    Horizontal,
    /// Straight up or down.
    Vertical,
    /// Along +-x or +-y.
    AxisAligned,
    /// From outside the footprint, aimed at a point of the scene.
    FromOutside,
    /// From inside some water, any direction.
    InWater,
}

/// Every ray kind.
pub const MLHM_RAY_KINDS: [MlhmRayKind; 8] = [
    MlhmRayKind::FromAbove,
    MlhmRayKind::InsideBox,
    MlhmRayKind::UnderOverhang,
    MlhmRayKind::Horizontal,
    MlhmRayKind::Vertical,
    MlhmRayKind::AxisAligned,
    MlhmRayKind::FromOutside,
    MlhmRayKind::InWater,
];

/// Lowest floor-free height and highest water top of the map.
fn z_range(map: &Mlhm) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for y in 0..map.height() {
        for x in 0..map.width() {
            for c in map.cell_columns(x, y) {
                lo = lo.min(c.bedrock as f64);
                hi = hi.max(c.water_top() as f64);
            }
        }
    }
    (lo, hi)
}

/// A random ray of `kind` for `map` placed at `origin` (unit direction, range `[0, inf)`).
pub fn random_ray(rng: &mut Rng, map: &Mlhm, origin: DVec2, kind: MlhmRayKind) -> Ray {
    let s = map.cell_size();
    let size = DVec2::new(map.width() as f64, map.height() as f64) * s;
    let (z_lo, z_hi) = z_range(map);
    let footprint = |rng: &mut Rng, margin: f64| {
        origin
            + DVec2::new(rng.range(-margin, size.x + margin), rng.range(-margin, size.y + margin))
    };
    let p = footprint(rng, 0.2 * s);
    let z = rng.range(z_lo - 1.0, z_hi + 1.0);
    let cell_point = |rng: &mut Rng, x: usize, y: usize, z: f64| {
        let (u, v) = (rng.range(0.01, 0.99), rng.range(0.01, 0.99));
        DVec3::new(origin.x + (x as f64 + u) * s, origin.y + (y as f64 + v) * s, z)
    };
    match kind {
        MlhmRayKind::FromAbove => {
            let mut d = rng.unit();
            d.z = -d.z.abs().max(0.05);
            let o = p.extend(z_hi + rng.range(0.5, 5.0));
            Ray::new(o, d.normalize())
        }
        MlhmRayKind::InsideBox => Ray::new(p.extend(z), rng.unit()),
        MlhmRayKind::Horizontal => {
            let a = rng.range(0.0, std::f64::consts::TAU);
            Ray::new(p.extend(z), DVec3::new(a.cos(), a.sin(), 0.0))
        }
        MlhmRayKind::Vertical => {
            let d = if rng.chance(0.5) { DVec3::Z } else { -DVec3::Z };
            Ray::new(p.extend(z), d)
        }
        MlhmRayKind::AxisAligned => {
            let d = [DVec3::X, -DVec3::X, DVec3::Y, -DVec3::Y][rng.below(4)];
            Ray::new(p.extend(z), d)
        }
        MlhmRayKind::FromOutside => {
            let a = rng.range(0.0, std::f64::consts::TAU);
            let centre = origin + 0.5 * size;
            let far = centre + DVec2::new(a.cos(), a.sin()) * (size.length() + s);
            let o = far.extend(rng.range(z_lo - 1.0, z_hi + 3.0));
            let target = footprint(rng, 0.0).extend(rng.range(z_lo - 0.5, z_hi + 0.5));
            Ray::new(o, (target - o).normalize())
        }
        MlhmRayKind::UnderOverhang | MlhmRayKind::InWater => {
            // Gather the spans: air gaps under a column, or water bodies.
            let mut spans = Vec::new();
            for y in 0..map.height() {
                for x in 0..map.width() {
                    let columns: Vec<MlhmColumn> = map.cell_columns(x, y).collect();
                    for (k, c) in columns.iter().enumerate() {
                        let (lo, hi) = if kind == MlhmRayKind::InWater {
                            (c.solid_top(), c.water_top())
                        } else if k + 1 < columns.len() {
                            (c.water_top(), c.ceiling)
                        } else {
                            continue;
                        };
                        if hi > lo {
                            spans.push((x, y, lo as f64, hi as f64));
                        }
                    }
                }
            }
            if spans.is_empty() {
                return Ray::new(p.extend(z), rng.unit());
            }
            let (x, y, lo, hi) = spans[rng.below(spans.len())];
            let z = rng.range(lo, hi);
            let o = cell_point(rng, x, y, if z > lo && z < hi { z } else { 0.5 * (lo + hi) });
            Ray::new(o, rng.unit())
        }
    }
}

/// Whether two optional distances agree to `rel` relative (with a 1e-9 absolute floor).
pub fn agree(a: Option<f64>, b: Option<f64>, rel: f64) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(x), Some(y)) => (x - y).abs() <= rel * x.abs().max(y.abs()) + 1e-9,
        _ => false,
    }
}
