//! Seeded material-stack terrains (Löffler et al. 2011) with overhangs, caves, arches, sand and
//! water, at the paper's benchmark size and beyond: [`stacks_terrain`].
//!
//! Per stack, bottom to top:
//! - **bedrock** from 0 up to the ground: the seeded fBm of [`fbm_terrain`] rescaled so that
//!   its relief fills most of the height range (less on small domains: at most a quarter of
//!   the domain's longer side, so that slopes stay plausible);
//! - **overhangs**: where a smooth mask noise exceeds a threshold, an air gap is carved at an
//!   absolute height that varies slowly over the domain (a weak stratum). Inside hills it is a
//!   closed cave; where a hillside crosses it, the rock above it overhangs the gap; where the
//!   ground is too low for a roof, the ground is cut down to the gap's floor (a ledge);
//! - **caves**: where a second mask noise exceeds its threshold, an air gap a smoothly varying
//!   depth below the ground, always under a roof of rock;
//! - **sand** replacing the top of the ground on gentle slopes of the lower half of the
//!   relief, thicker the gentler and the lower;
//! - **arches**: along the zero lines of a third (ridge) noise, where a gate noise allows, a
//!   slab of rock at a deck height above the smoothed ground: merged into the hills it meets
//!   and free above the valleys between them, thinning out where it would hang too high;
//! - **water**: all air below the sea level (the ground height under which
//!   [`StacksTerrainParams::water_fraction`] of the stacks lie), flooded caves included.
//!
//! The gaps' heights and thicknesses follow smooth noise of wavelengths of tens of stacks, and
//! fade to nothing at the masks' edges, so the features are coherent shapes. Layers thinner
//! than [`MIN_LAYER`] are dropped, gaps thinner than it are not carved, and every height is
//! clamped to `[0, max_height]`.

use crate::error::{non_negative, positive};
use crate::gradient_noise::{mix64, CellCache, GradientNoise, NoiseBatch};
use crate::{fbm_terrain, FbmParams, SimError};
use rayon::prelude::*;
use relief_core::{CoreError, DVec2, MaterialStacks, StackLayer, StackMaterial};

/// Thinnest layer (and air gap) kept, in metres.
pub const MIN_LAYER: f32 = 0.05;

/// Samples evaluated together along a row.
const BLOCK: usize = 256;

/// Stacks per band of rows computed by one task (about).
const BAND_STACKS: usize = 1 << 16;

/// Bedrock, sand and water in [`StackMaterial::defaults`].
const BEDROCK: u8 = StackMaterial::BEDROCK;
const SAND: u8 = StackMaterial::SAND;
const WATER: u8 = StackMaterial::WATER;

/// The parameters of [`stacks_terrain`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StacksTerrainParams {
    /// Distance between neighbouring stacks in metres, > 0 [default: 2, the paper's 4 km x
    /// 8 km over 2048 x 4096 stacks].
    pub spacing: f64,
    /// Highest height in metres, > 0 [default: 768, the paper's 512 voxels of 1.5 m].
    pub max_height: f64,
    /// Fraction of the stacks whose ground lies under the sea level, 0 to 1 [default: 0.1].
    pub water_fraction: f64,
    /// Thickness in metres of the sand on flat low ground, thinning to none on slopes of 2 in
    /// 5 and steeper and on the upper half of the relief, >= 0 [default: 3].
    pub sand_thickness: f64,
}

impl Default for StacksTerrainParams {
    fn default() -> Self {
        StacksTerrainParams {
            spacing: 2.0,
            max_height: 768.0,
            water_fraction: 0.1,
            sand_thickness: 3.0,
        }
    }
}

impl StacksTerrainParams {
    /// Checks every field's range; the error names the first field out of range.
    pub fn validate(&self) -> Result<(), SimError> {
        positive("spacing", self.spacing)?;
        positive("max_height", self.max_height)?;
        if !(self.max_height <= f64::from(f32::MAX) / 4.0 && self.spacing <= 1e12) {
            return Err(SimError::parameter("max_height", "spacing or max_height too large"));
        }
        if !(0.0..=1.0).contains(&self.water_fraction) {
            return Err(SimError::parameter(
                "water_fraction",
                format!("{} is not in 0..=1", self.water_fraction),
            ));
        }
        non_negative("sand_thickness", self.sand_thickness)
    }
}

/// A `width x height` material-stack terrain (palette [`StackMaterial::defaults`], spacing
/// `params.spacing` along both axes, origin 0) seeded with `seed`: fBm bedrock with overhangs,
/// caves and arches, sand and water (see the module documentation).
///
/// The same arguments give the same stacks, bit for bit, whatever the number of threads.
/// Rows are computed in parallel bands straight into the compressed-row storage.
///
/// Errors: [`SimError::Parameter`] for parameters out of range (see
/// [`StacksTerrainParams::validate`]); [`SimError::Terrain`] for an empty grid or one too
/// large to allocate or to index with `u32` offsets.
///
/// ```
/// use relief_sim::{stacks_terrain, StacksTerrainParams};
/// let stacks = stacks_terrain(64, 32, 7, &StacksTerrainParams::default())?;
/// assert_eq!((stacks.width(), stacks.height()), (64, 32));
/// # Ok::<(), relief_sim::SimError>(())
/// ```
pub fn stacks_terrain(
    width: usize,
    height: usize,
    seed: u64,
    params: &StacksTerrainParams,
) -> Result<MaterialStacks, SimError> {
    params.validate()?;
    if width == 0 || height == 0 {
        return Err(CoreError::Grid(format!("{width} x {height} has no stacks")).into());
    }
    let count = width
        .checked_mul(height)
        .filter(|&n| n < u32::MAX as usize / 4)
        .ok_or_else(|| CoreError::Grid(format!("{width} x {height} stacks are too many")))?;
    let world = World::new(width, height, seed, params)?;
    let band_rows = (BAND_STACKS / width).clamp(1, height);
    let mut offsets: Vec<u32> = Vec::new();
    offsets
        .try_reserve_exact(count + 1)
        .map_err(|_| CoreError::Grid(format!("cannot allocate {width} x {height} stacks")))?;
    offsets.resize(count + 1, 0);
    let bands: Vec<Vec<StackLayer>> = offsets[1..]
        .par_chunks_mut(band_rows * width)
        .enumerate()
        .map_init(|| world.worker(), |worker, (b, ends)| worker.band(&world, b * band_rows, ends))
        .collect();
    // Band-local offsets made global; each band's layers moved over and freed in turn.
    let total: usize = bands.iter().map(Vec::len).sum();
    if total > u32::MAX as usize {
        return Err(CoreError::Grid(format!("{total} layers exceed u32 offsets")).into());
    }
    let mut layers: Vec<StackLayer> = Vec::new();
    layers
        .try_reserve_exact(total)
        .map_err(|_| CoreError::Grid(format!("cannot allocate {total} layers")))?;
    for (ends, band) in offsets[1..].chunks_mut(band_rows * width).zip(bands) {
        let base = layers.len() as u32;
        ends.iter_mut().for_each(|e| *e += base);
        layers.extend_from_slice(&band);
    }
    let stacks = MaterialStacks::from_parts(
        width,
        height,
        DVec2::splat(params.spacing),
        DVec2::ZERO,
        StackMaterial::defaults(),
        offsets,
        layers,
    )?;
    Ok(stacks)
}

/// One octave of a noise field.
#[derive(Debug, Clone)]
struct Octave {
    noise: GradientNoise,
    cos: f64,
    sin: f64,
    /// Lattice cells per stack.
    frequency: f64,
    amplitude: f32,
}

/// A sum of rotated gradient-noise octaves (gain 0.5, lacunarity 2), amplitudes summing to 1.
#[derive(Debug, Clone)]
struct Field {
    octaves: Vec<Octave>,
}

/// One thread's working memory for one [`Field`].
#[derive(Default)]
struct FieldScratch {
    caches: Vec<CellCache>,
    batch: NoiseBatch,
    us: Vec<f64>,
    vs: Vec<f64>,
    n: Vec<f32>,
    du: Vec<f32>,
    dv: Vec<f32>,
}

impl Field {
    /// Field `id` of the terrain seeded with `seed`: `octaves` octaves, the first of
    /// `wavelength` stacks.
    fn new(seed: u64, id: u64, wavelength: f64, octaves: u32) -> Self {
        let norm: f64 = (0..octaves).map(|k| 0.5f64.powi(k as i32)).sum();
        let octaves = (0..octaves)
            .map(|k| {
                let index = id * 16 + u64::from(k);
                let angle = 0.7 + index as f64 * 1.3;
                Octave {
                    noise: GradientNoise::new(mix64(
                        seed ^ 0x5bd1_e995_u64.wrapping_mul(index + 1) ^ 0xa076_1d64_78bd_642f,
                    )),
                    cos: angle.cos(),
                    sin: angle.sin(),
                    frequency: 2f64.powi(k as i32) / wavelength,
                    amplitude: (0.5f64.powi(k as i32) / norm) as f32,
                }
            })
            .collect();
        Field { octaves }
    }

    fn scratch(&self) -> FieldScratch {
        FieldScratch {
            caches: vec![CellCache::default(); self.octaves.len()],
            ..Default::default()
        }
    }

    /// The field at the stack centres of row `y` into `out` (one per column).
    fn row(&self, y: usize, out: &mut [f32], s: &mut FieldScratch) {
        out.fill(0.0);
        let yc = y as f64 + 0.5;
        for (octave, cache) in self.octaves.iter().zip(s.caches.iter_mut()) {
            let (c, sn, f) = (octave.cos, octave.sin, octave.frequency);
            for (b, block) in out.chunks_mut(BLOCK).enumerate() {
                let len = block.len();
                s.us.clear();
                s.vs.clear();
                for i in 0..len {
                    let (x, y) = (((b * BLOCK + i) as f64 + 0.5) * f, yc * f);
                    s.us.push(c * x - sn * y);
                    s.vs.push(sn * x + c * y);
                }
                octave.noise.locate(&s.us, &s.vs, cache, &mut s.batch);
                for v in [&mut s.n, &mut s.du, &mut s.dv] {
                    v.resize(len, 0.0);
                }
                s.batch.evaluate(&mut s.n, &mut s.du, &mut s.dv);
                for (o, &n) in block.iter_mut().zip(&s.n[..len]) {
                    *o += octave.amplitude * n;
                }
            }
        }
    }
}

/// Everything computed once for the whole terrain: the ground, its smoothed copy, the sea
/// level, the noise fields and the feature sizes.
struct World {
    width: usize,
    height: usize,
    /// Ground height per stack, metres.
    ground: Vec<f32>,
    /// The ground smoothed over a few hundred metres: the arches' deck below its offset.
    smooth: Vec<f32>,
    sea_level: f32,
    max_height: f32,
    spacing: f32,
    sand: f32,
    /// Overhang stratum: mask, height (0..1 of the relief), thickness modulation.
    overhang: [Field; 3],
    /// Caves: mask, depth.
    cave: [Field; 2],
    /// Arches: ridge (slabs along its zero lines), gate.
    arch: [Field; 2],
    /// Lowest ground, and the ground's relief.
    base: f32,
    relief: f32,
    /// Feature sizes in metres.
    sizes: Sizes,
}

/// Vertical sizes of the features, in metres, scaled down on domains of little relief.
#[derive(Debug, Clone, Copy)]
struct Sizes {
    overhang_gap: f32,
    roof: f32,
    cave_depth: f32,
    cave_depth_range: f32,
    cave_gap: f32,
    slab: f32,
    deck_offset: f32,
    max_clearance: f32,
}

/// Overhang mask threshold and the width of its ramp to the full gap.
const OVERHANG_THRESHOLD: f32 = 0.16;
const OVERHANG_RAMP: f32 = 0.12;
/// Cave mask threshold and ramp.
const CAVE_THRESHOLD: f32 = 0.2;
const CAVE_RAMP: f32 = 0.1;
/// Half-width of the arches' ridge band in noise units, and the gate's threshold.
const ARCH_BAND: f32 = 0.05;
const ARCH_GATE: f32 = 0.14;

impl World {
    fn new(
        width: usize,
        height: usize,
        seed: u64,
        params: &StacksTerrainParams,
    ) -> Result<Self, SimError> {
        let side = width.max(height) as f64;
        let field = fbm_terrain(width, height, seed, &FbmParams::for_size(width, height))?;
        let top = f64::from(field.max_sample()).max(f64::MIN_POSITIVE);
        let max_height = params.max_height;
        // Relief: most of the height range, but no steeper than a quarter of the extent.
        let relief = (0.85 * max_height).min(0.25 * side * params.spacing);
        let base = 0.04 * max_height;
        let scale = relief / top;
        let ground: Vec<f32> = field
            .samples()
            .par_iter()
            .map(|&h| (base + f64::from(h) * scale).clamp(0.0, max_height) as f32)
            .collect();
        drop(field);
        let sea_level = sea_level(&ground, max_height as f32, params.water_fraction);
        // Wavelengths in metres, at most 2/5 of the longer side so that small domains have
        // features too.
        let stacks = |metres: f64| (metres / params.spacing).min(side / 2.5).max(2.0);
        let radius = ((160.0 / params.spacing).min(side / 6.0) as usize).max(1);
        let smooth = box_blur(&ground, width, height, radius);
        let r = relief as f32;
        let sizes = Sizes {
            overhang_gap: (0.25 * r).min(14.0),
            roof: (0.06 * r).clamp(0.5, 4.0),
            cave_depth: (0.1 * r).clamp(0.6, 6.0),
            cave_depth_range: (0.3 * r).min(30.0),
            cave_gap: (0.2 * r).min(9.0),
            slab: (0.12 * r).min(9.0),
            deck_offset: (0.08 * r).min(25.0),
            max_clearance: (0.5 * r).min(120.0),
        };
        Ok(World {
            width,
            height,
            ground,
            smooth,
            sea_level,
            max_height: max_height as f32,
            spacing: params.spacing as f32,
            sand: params.sand_thickness as f32,
            overhang: [
                Field::new(seed, 1, stacks(180.0), 2),
                Field::new(seed, 2, stacks(900.0), 1),
                Field::new(seed, 3, stacks(90.0), 1),
            ],
            cave: [Field::new(seed, 4, stacks(140.0), 2), Field::new(seed, 5, stacks(220.0), 1)],
            arch: [Field::new(seed, 6, stacks(260.0), 1), Field::new(seed, 7, stacks(700.0), 1)],
            base: base as f32,
            relief: r,
            sizes,
        })
    }

    fn worker(&self) -> Worker {
        let fields = self.overhang.iter().chain(&self.cave).chain(&self.arch);
        Worker {
            scratch: fields.map(Field::scratch).collect(),
            rows: vec![vec![0.0; self.width]; 7],
            solid: Vec::new(),
        }
    }
}

/// The ground height under which `fraction` of `ground` lies, from a histogram of 4096 bins
/// over `[0, max_height]` (exact enough, and independent of the order of the samples).
fn sea_level(ground: &[f32], max_height: f32, fraction: f64) -> f32 {
    const BINS: usize = 4096;
    if fraction <= 0.0 {
        return 0.0;
    }
    let bin = |h: f32| ((h / max_height * BINS as f32) as usize).min(BINS - 1);
    let histogram = ground
        .par_chunks(1 << 16)
        .map(|chunk| {
            let mut counts = vec![0u64; BINS];
            chunk.iter().for_each(|&h| counts[bin(h)] += 1);
            counts
        })
        .reduce(
            || vec![0u64; BINS],
            |mut a, b| {
                a.iter_mut().zip(b).for_each(|(x, y)| *x += y);
                a
            },
        );
    let wanted = (fraction * ground.len() as f64).ceil() as u64;
    let mut below = 0;
    for (k, count) in histogram.iter().enumerate() {
        below += count;
        if below >= wanted {
            return (k + 1) as f32 / BINS as f32 * max_height;
        }
    }
    max_height
}

/// `values` (`width x height`, row-major) averaged over the `(2r + 1)^2` square around each
/// point, the edges repeated outwards: a horizontal then a vertical running sum.
fn box_blur(values: &[f32], width: usize, height: usize, r: usize) -> Vec<f32> {
    let n = (2 * r + 1) as f64;
    let mut rows = vec![0f32; values.len()];
    rows.par_chunks_mut(width).zip(values.par_chunks(width)).for_each(|(out, row)| {
        let at = |i: isize| f64::from(row[i.clamp(0, width as isize - 1) as usize]);
        let mut sum: f64 = (-(r as isize)..=r as isize).map(at).sum();
        for (x, o) in out.iter_mut().enumerate() {
            *o = (sum / n) as f32;
            let x = x as isize;
            sum += at(x + r as isize + 1) - at(x - r as isize);
        }
    });
    let mut out = vec![0f32; values.len()];
    let row = |y: isize| &rows[y.clamp(0, height as isize - 1) as usize * width..][..width];
    let mut sum = vec![0f64; width];
    for y in -(r as isize)..=r as isize {
        sum.iter_mut().zip(row(y)).for_each(|(s, &v)| *s += f64::from(v));
    }
    for (y, o) in out.chunks_mut(width).enumerate() {
        o.iter_mut().zip(&sum).for_each(|(o, &s)| *o = (s / n) as f32);
        let y = y as isize;
        let (add, remove) = (row(y + r as isize + 1), row(y - r as isize));
        for ((s, &a), &b) in sum.iter_mut().zip(add).zip(remove) {
            *s += f64::from(a) - f64::from(b);
        }
    }
    out
}

/// Slope (rise over run) from which no sand lies.
const SAND_SLOPE: f32 = 0.4;

/// Cubic smoothstep of `t` clamped to [0, 1].
#[inline]
fn smooth01(t: f32) -> f32 {
    let t = t.clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// One thread's working memory: the noise rows and one stack's solid intervals.
struct Worker {
    scratch: Vec<FieldScratch>,
    /// Noise rows: overhang mask, height, thickness; cave mask, depth; ridge, gate.
    rows: Vec<Vec<f32>>,
    /// `(start, end, material)` of one stack, bottom to top.
    solid: Vec<(f32, f32, u8)>,
}

impl Worker {
    /// Rows from `first` on, as many as `ends` holds (`ends.len() / width`): fills `ends` with
    /// the band-local end offset of each stack and returns the band's layers.
    fn band(&mut self, world: &World, first: usize, ends: &mut [u32]) -> Vec<StackLayer> {
        let width = world.width;
        let mut layers = Vec::with_capacity(ends.len() * 2);
        for (k, row_ends) in ends.chunks_mut(width).enumerate() {
            let y = first + k;
            let fields = world.overhang.iter().chain(&world.cave).chain(&world.arch);
            for ((field, out), scratch) in fields.zip(&mut self.rows).zip(&mut self.scratch) {
                field.row(y, out, scratch);
            }
            for (x, end) in row_ends.iter_mut().enumerate() {
                self.stack(world, x, y);
                for &(start, stop, material) in &self.solid {
                    if stop - start >= MIN_LAYER {
                        layers.push(StackLayer::new(start, stop, material));
                    }
                }
                *end = layers.len() as u32;
            }
        }
        layers
    }

    /// The layers of stack `(x, y)` into `self.solid`, valid and clamped.
    fn stack(&mut self, w: &World, x: usize, y: usize) {
        let i = x + y * w.width;
        let s = w.sizes;
        let ground = w.ground[i];
        let solid = &mut self.solid;
        solid.clear();
        let mut top = ground;
        if top >= MIN_LAYER {
            solid.push((0.0, top, BEDROCK));
        }
        // Overhang stratum: an absolute height, carved inside the rock, cutting the ground
        // down to its floor where the roof would be too thin.
        let mask = self.rows[0][x];
        let thickness = s.overhang_gap * smooth01((mask - OVERHANG_THRESHOLD) / OVERHANG_RAMP) * {
            0.55 + 0.9 * (self.rows[2][x] + 0.5).clamp(0.0, 1.0)
        };
        if thickness >= MIN_LAYER {
            let centre = w.base + w.relief * (0.15 + 0.7 * (self.rows[1][x] + 0.5).clamp(0.0, 1.0));
            let (low, high) = ((centre - 0.5 * thickness).max(MIN_LAYER), centre + 0.5 * thickness);
            if high + s.roof <= top {
                carve(solid, low, high);
            } else if low < top {
                carve(solid, low, top);
            }
            top = solid.last().map_or(0.0, |l| l.1);
        }
        // Caves: a gap under a roof that follows the ground.
        let mask = self.rows[3][x];
        let thickness = s.cave_gap * smooth01((mask - CAVE_THRESHOLD) / CAVE_RAMP);
        if thickness >= MIN_LAYER {
            let depth = s.cave_depth + s.cave_depth_range * (self.rows[4][x] + 0.5).clamp(0.0, 1.0);
            let high = ground - depth;
            let low = (high - thickness).max(MIN_LAYER);
            if high - low >= MIN_LAYER && high <= top - s.roof {
                carve(solid, low, high);
            }
        }
        // Sand: the top of the ground, thicker on gentler slopes.
        if let Some(last) = solid.last_mut() {
            let slope = slope(w, x, y);
            let altitude = (last.1 - w.base) / w.relief;
            let depth = w.sand
                * (1.0 - slope / SAND_SLOPE).clamp(0.0, 1.0)
                * (1.0 - smooth01((altitude - 0.4) / 0.2));
            if depth >= MIN_LAYER && last.1 - last.0 >= 2.0 * MIN_LAYER {
                let split = (last.1 - depth).max(last.0 + MIN_LAYER);
                let end = last.1;
                last.1 = split;
                solid.push((split, end, SAND));
            }
        }
        // Arches: a slab along the ridge lines where the gate allows.
        let ridge = self.rows[5][x].abs();
        let gate = smooth01((self.rows[6][x] - ARCH_GATE) / 0.06);
        if ridge < ARCH_BAND && gate > 0.0 {
            let profile = 1.0 - (ridge / ARCH_BAND).powi(2);
            let deck = w.smooth[i] + s.deck_offset;
            let mut slab = s.slab * profile * gate;
            let bottom = deck - 0.6 * slab;
            let clearance = bottom - top;
            slab *= 1.0 - smooth01((clearance - 0.6 * s.max_clearance) / (0.4 * s.max_clearance));
            let (bottom, high) = (deck - 0.6 * slab, (deck + 0.4 * slab).min(w.max_height));
            if high - bottom >= MIN_LAYER && high > top {
                if bottom - top >= MIN_LAYER {
                    solid.push((bottom, high, BEDROCK));
                } else {
                    solid.push((top, high, BEDROCK));
                }
            }
        }
        // Water: all air below the sea level.
        let sea = w.sea_level;
        let mut below = 0.0f32;
        let mut k = 0;
        loop {
            let high = solid.get(k).map_or(f32::INFINITY, |l| l.0).min(sea);
            if high - below >= MIN_LAYER {
                solid.insert(k, (below, high, WATER));
                k += 1;
            }
            match solid.get(k) {
                Some(l) if l.1 < sea => below = l.1,
                _ => break,
            }
            k += 1;
        }
        for l in solid.iter_mut() {
            l.0 = l.0.clamp(0.0, w.max_height);
            l.1 = l.1.clamp(0.0, w.max_height);
        }
    }
}

/// Removes `[low, high]` from the solid intervals.
fn carve(solid: &mut Vec<(f32, f32, u8)>, low: f32, high: f32) {
    if high - low < MIN_LAYER {
        return;
    }
    let mut k = 0;
    while k < solid.len() {
        let (start, end, material) = solid[k];
        if end <= low || start >= high {
            k += 1;
            continue;
        }
        let below = (start, low.max(start), material);
        let above = (high.min(end), end, material);
        solid.remove(k);
        if above.1 - above.0 >= MIN_LAYER {
            solid.insert(k, above);
        }
        if below.1 - below.0 >= MIN_LAYER {
            solid.insert(k, below);
            k += 1;
        }
        if above.1 - above.0 >= MIN_LAYER {
            k += 1;
        }
    }
}

/// The ground's slope (rise over run) at stack `(x, y)`, by central differences.
fn slope(w: &World, x: usize, y: usize) -> f32 {
    let at = |x: usize, y: usize| w.ground[x + y * w.width];
    let (x0, x1) = (x.saturating_sub(1), (x + 1).min(w.width - 1));
    let (y0, y1) = (y.saturating_sub(1), (y + 1).min(w.height - 1));
    let gx = (at(x1, y) - at(x0, y)) / (((x1 - x0).max(1)) as f32 * w.spacing);
    let gy = (at(x, y1) - at(x, y0)) / (((y1 - y0).max(1)) as f32 * w.spacing);
    (gx * gx + gy * gy).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn terrain(width: usize, height: usize, seed: u64) -> MaterialStacks {
        stacks_terrain(width, height, seed, &StacksTerrainParams::default()).unwrap()
    }

    /// Whether the stack has two solid runs with air between them.
    fn overhangs(layers: &[StackLayer]) -> bool {
        layers.windows(2).any(|p| p[1].start > p[0].end && p[1].material != WATER)
    }

    #[test]
    fn layers_are_valid_and_within_the_height_range() {
        for (w, h, seed) in [(64, 32, 1), (200, 150, 2), (1, 1, 3), (7, 300, 4)] {
            let stacks = terrain(w, h, seed);
            stacks.validate().unwrap();
            let (low, high) = stacks.height_range().unwrap();
            assert!(low >= 0.0 && high <= 768.0, "{w}x{h}: {low}..{high}");
            assert!(stacks.layers().iter().all(|l| l.thickness() >= MIN_LAYER));
        }
    }

    #[test]
    fn same_seed_same_stacks_other_seed_other_stacks() {
        let a = terrain(150, 90, 11);
        assert_eq!(a, terrain(150, 90, 11));
        assert_ne!(a, terrain(150, 90, 12));
    }

    #[test]
    fn has_overhangs_sand_and_water() {
        for (w, h) in [(64, 32), (400, 300)] {
            let stacks = terrain(w, h, 5);
            let cells = w * h;
            let layered = (0..cells).filter(|i| overhangs(stacks.stack(i % w, i / w))).count();
            assert!(layered > cells / 100, "{w}x{h}: {layered} stacks with overhangs");
            let count = |m: u8| stacks.layers().iter().filter(|l| l.material == m).count();
            assert!(count(SAND) > cells / 25, "{w}x{h}: {} sand layers", count(SAND));
            assert!(count(WATER) > cells / 50, "{w}x{h}: {} water layers", count(WATER));
        }
    }

    #[test]
    fn features_are_coherent_not_speckle() {
        // Stacks with overhangs mostly have a neighbour with one too.
        let (w, h) = (300, 200);
        let stacks = terrain(w, h, 9);
        let has = |x: usize, y: usize| overhangs(stacks.stack(x, y));
        let (mut layered, mut lonely) = (0, 0);
        for y in 1..h - 1 {
            for x in 1..w - 1 {
                if has(x, y) {
                    layered += 1;
                    if !(has(x - 1, y) || has(x + 1, y) || has(x, y - 1) || has(x, y + 1)) {
                        lonely += 1;
                    }
                }
            }
        }
        assert!(layered > 0 && lonely * 50 < layered, "{lonely} of {layered} alone");
    }

    #[test]
    fn bad_parameters_are_refused() {
        let good = StacksTerrainParams::default();
        for (name, params) in [
            ("spacing", StacksTerrainParams { spacing: 0.0, ..good }),
            ("max_height", StacksTerrainParams { max_height: f64::NAN, ..good }),
            ("water_fraction", StacksTerrainParams { water_fraction: 1.5, ..good }),
            ("sand_thickness", StacksTerrainParams { sand_thickness: -1.0, ..good }),
        ] {
            match stacks_terrain(8, 8, 1, &params) {
                Err(SimError::Parameter { name: found, .. }) => assert_eq!(found, name),
                other => panic!("{params:?}: {other:?}"),
            }
        }
        assert!(matches!(stacks_terrain(0, 8, 1, &good), Err(SimError::Terrain(_))));
    }

    #[test]
    fn carve_splits_and_drops_slivers() {
        let mut solid = vec![(0.0, 10.0, BEDROCK)];
        carve(&mut solid, 4.0, 6.0);
        assert_eq!(solid, vec![(0.0, 4.0, BEDROCK), (6.0, 10.0, BEDROCK)]);
        carve(&mut solid, 3.98, 9.99);
        assert_eq!(solid, vec![(0.0, 3.98, BEDROCK)]);
    }
}
