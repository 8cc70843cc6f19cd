//! Stacks to density (section 3.2.1) and smoothing (section 3.2.2): each lattice point's
//! vertical distance to the nearest boundary of a level's layers, in channels, then a
//! separable low-pass filter across the columns.

use super::column_field::{column_values, ColumnValues, BAND, THIN_FLOOR_SMOOTHED};
use super::lattice::{Block, Lattice};
use super::node_mesh::ISO;
use relief_core::{MaterialKind, MaterialStacks};

/// How far above the iso-value a point inside a layer stays when the filter would carve it
/// out.
const KEPT_INSIDE: f32 = 0.05;

/// The low-pass filter applied to the density before contouring, separable along x, y, z, in
/// lattice units of the level being meshed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Smoothing {
    /// No smoothing: the blocky coverage itself.
    None,
    /// A box of `2 * radius + 1` lattice points.
    Box {
        /// Half the box's width, lattice points.
        radius: usize,
    },
    /// A Gaussian of standard deviation `sigma` lattice points, cut at `ceil(2 sigma)`.
    Gaussian {
        /// Standard deviation, lattice points (> 0).
        sigma: f64,
    },
}

impl Smoothing {
    /// The same filter at level `level` of the mipmap, whose cells are `2^level` finest cells
    /// across: its width in metres kept (a Gaussian's sigma and a box's radius halved per
    /// level; a box of radius 0, or a Gaussian narrower than 0.3 cells, whose side weights are below 0.4 %, filters nothing).
    pub fn at_level(&self, level: usize) -> Smoothing {
        let scale = (1u64 << level.min(62)) as f64;
        match *self {
            Smoothing::None => Smoothing::None,
            Smoothing::Box { radius } => Smoothing::Box { radius: radius >> level.min(63) },
            Smoothing::Gaussian { sigma } if sigma / scale < 0.3 => Smoothing::None,
            Smoothing::Gaussian { sigma } => Smoothing::Gaussian { sigma: sigma / scale },
        }
    }

    /// The normalized kernel weights, `2 * radius + 1` of them.
    pub fn kernel(&self) -> Vec<f32> {
        let weights: Vec<f64> = match *self {
            Smoothing::None => vec![1.0],
            Smoothing::Box { radius } => vec![1.0; 2 * radius + 1],
            Smoothing::Gaussian { sigma } => {
                let radius = (2.0 * sigma).ceil() as i64;
                (-radius..=radius)
                    .map(|t| (-(t * t) as f64 / (2.0 * sigma * sigma)).exp())
                    .collect()
            }
        };
        let sum: f64 = weights.iter().sum();
        weights.iter().map(|w| (w / sum) as f32).collect()
    }
}

/// What each density channel accumulates: channel 0 the solids, channel 1 the liquids, then
/// one channel per solid material for the vertex colours.
#[derive(Debug, Clone)]
pub(crate) struct Channels {
    /// For every material of the palette: its channels (solid or liquid total, and its own).
    pub of_material: Vec<(usize, Option<usize>)>,
    /// Number of channels.
    pub count: usize,
    /// The material each per-material channel (from 2 on) stands for.
    pub materials: Vec<u8>,
    /// Layers (runs of one channel) thinner than this, metres, are left out at every level: a
    /// tenth of the finest spacing.
    pub min_thickness: f64,
}

impl Channels {
    /// The channels of a palette.
    pub fn new(stacks: &MaterialStacks) -> Self {
        let mut count = 2;
        let mut materials = Vec::new();
        let of_material = stacks
            .materials()
            .iter()
            .enumerate()
            .map(|(m, material)| match material.kind {
                MaterialKind::Liquid => (1, None),
                MaterialKind::Solid => {
                    count += 1;
                    materials.push(m as u8);
                    (0, Some(count - 1))
                }
            })
            .collect();
        let spacing = stacks.spacing();
        Channels { of_material, count, materials, min_thickness: 0.1 * spacing.x.min(spacing.y) }
    }
}

/// The smoothed density of one level over a block of lattice points, channel-major
/// (`values[channel][block index]`), then the liquid unfiltered ([`Density::raw_liquid`]).
#[derive(Debug, Clone)]
pub(crate) struct Density {
    /// The points the values cover.
    pub block: Block,
    /// One grid of values per channel.
    pub channels: Vec<Vec<f32>>,
}

impl Density {
    /// The density of `stacks` (one level, on `lattice`) over `block`, smoothed along x and
    /// y by `kernels[0]` (the solids and the materials) and `kernels[1]` (the liquids).
    ///
    /// Channels 0 (the solids) and 1 (the liquids) hold `0.5 +` the vertical distance to the
    /// nearest boundary of that material in each stack (see [`super::column_field`]); each
    /// material's channel holds 1 where the point shows that material (the layer at the
    /// nearest boundary, or the layer holding the point) and 0 elsewhere.
    pub fn new(
        stacks: &MaterialStacks,
        lattice: &Lattice,
        channels: &Channels,
        block: Block,
        kernels: [&[f32]; 2],
    ) -> Self {
        let r = kernels.iter().map(|k| k.len() / 2).max().unwrap_or(0) as i32;
        let wide = across(block, r);
        let air = (0.5 - BAND) as f32;
        let thin_floor =
            |c: usize| if kernels[c].len() > 1 { THIN_FLOOR_SMOOTHED } else { f64::NEG_INFINITY };
        let mut values: Vec<Vec<f32>> =
            (0..channels.count).map(|c| vec![if c < 2 { air } else { 0.0 }; wide.len()]).collect();
        let [nx, ny, nz] = wide.size;
        let materials = stacks.materials();
        let mut column_out = ColumnValues::default();
        // Which channels any column wrote to.
        let mut touched = vec![false; channels.count];
        let mut exact_liquid = vec![air; wide.len()];
        for y in 0..ny {
            let gy = wide.min[1] + y as i32;
            if gy < 0 || gy as usize >= stacks.height() {
                continue;
            }
            for x in 0..nx {
                let gx = wide.min[0] + x as i32;
                if gx < 0 || gx as usize >= stacks.width() {
                    continue;
                }
                let stack = stacks.stack(gx as usize, gy as usize);
                if stack.is_empty() {
                    continue;
                }
                let column = wide.index([x, y, 0]);
                for (total, liquid) in [(0, false), (1, true)] {
                    if !stack.iter().any(|l| materials[l.material as usize].is_liquid() == liquid) {
                        continue;
                    }
                    touched[total] = true;
                    let c = &mut column_out;
                    column_values(
                        c,
                        stack,
                        materials,
                        |m| m.is_liquid() == liquid,
                        |z| lattice.to_k(z),
                        channels.min_thickness / lattice.step.z,
                        thin_floor(total),
                        wide.min[2]..wide.min[2] + nz as i32,
                    );
                    for k in 0..nz {
                        let i = column + k * nx * ny;
                        values[total][i] = c.density[k];
                        if liquid {
                            exact_liquid[i] = c.exact[k];
                        }
                        if let Some(own) =
                            c.material[k].and_then(|m| channels.of_material[m as usize].1)
                        {
                            values[own][i] = 1.0;
                            touched[own] = true;
                        }
                    }
                }
            }
        }
        // The filter rounds the surfaces; it may not carve a point that is inside the solid out
        // of it (a rim, a ridge, a thin arch): there the value stays just inside. The liquid's
        // smallest puddles may go (measured on the reference scene: kept too, its water's
        // faces went from 183 009 to 324 326 at the finest level, past the face budget).
        // The liquid before the filter, after the other channels: where it crosses an edge the
        // filtered liquid crosses too, its exact crossing places the vertex (see
        // `VertexTable::crossing_of`).
        let raw_liquid = crop(&exact_liquid, wide, block);
        let mut channels: Vec<Vec<f32>> = values
            .into_iter()
            .enumerate()
            .map(|(c, v)| {
                // A material no column wrote is 0 everywhere, smoothed or not. (The solid and
                // the liquid are always filtered: a constant filtered is not always the same
                // float, and a point must get the same value in every node.)
                if c >= 2 && !touched[c] {
                    return vec![0.0; block.len()];
                }
                let kernel = kernels[usize::from(c == 1)];
                let r = (kernel.len() / 2) as i32;
                let grown = across(block, r);
                let smoothed = smooth_across(crop(&v, wide, grown), grown, block, kernel);
                if c >= 1 {
                    return smoothed;
                }
                let original = crop(&v, wide, block);
                smoothed
                    .into_iter()
                    .zip(original)
                    .map(|(s, o)| if o > ISO { s.max(ISO + KEPT_INSIDE) } else { s })
                    .collect()
            })
            .collect();
        channels.push(raw_liquid);
        Density { block, channels }
    }

    /// The channel of the liquid before the filter.
    pub fn raw_liquid(&self) -> usize {
        self.channels.len() - 1
    }

    /// The value of `channel` at lattice point `p` (which must lie in the block).
    #[inline]
    pub fn at(&self, channel: usize, p: [i32; 3]) -> f32 {
        self.channels[channel][self.block.index_of(p)]
    }
}

/// `block` grown by `r` points along x and y.
fn across(block: Block, r: i32) -> Block {
    Block {
        min: [block.min[0] - r, block.min[1] - r, block.min[2]],
        size: [block.size[0] + 2 * r as usize, block.size[1] + 2 * r as usize, block.size[2]],
    }
}

/// `values` over `wide` cut to `inner`, row by row.
fn crop(values: &[f32], wide: Block, inner: Block) -> Vec<f32> {
    let mut out = Vec::with_capacity(inner.len());
    let [nx, ny, nz] = inner.size;
    for z in 0..nz {
        for y in 0..ny {
            let start =
                wide.index_of([inner.min[0], inner.min[1] + y as i32, inner.min[2] + z as i32]);
            out.extend_from_slice(&values[start..start + nx]);
        }
    }
    out
}

/// `values` over `wide` filtered along x and y by `kernel` and cut to `inner` (`wide` is
/// `inner` grown by the kernel's half-width along x and y): each output sums its neighbours
/// in a fixed order, so a point gets the same value in every block. The stacks are exact
/// along z, so the filter leaves z alone: a layer keeps its height and its thickness.
fn smooth_across(values: Vec<f32>, wide: Block, inner: Block, kernel: &[f32]) -> Vec<f32> {
    let r = kernel.len() / 2;
    if r == 0 {
        return values;
    }
    let mut current = values;
    let mut size = wide.size;
    for axis in 0..2 {
        let mut to = size;
        to[axis] -= 2 * r;
        let stride = match axis {
            0 => 1,
            1 => size[0],
            _ => size[0] * size[1],
        };
        let mut out = vec![0f32; to[0] * to[1] * to[2]];
        // Row by row, each tap added over the whole row: contiguous, so it vectorizes; every
        // output still sums its taps in the kernel's order.
        for (row, out_row) in out.chunks_exact_mut(to[0]).enumerate() {
            let (y, z) = (row % to[1], row / to[1]);
            let start = (z * size[1] + y) * size[0];
            for (t, &w) in kernel.iter().enumerate() {
                let src = &current[start + t * stride..start + t * stride + to[0]];
                for (o, &v) in out_row.iter_mut().zip(src) {
                    *o += w * v;
                }
            }
        }
        current = out;
        size = to;
    }
    debug_assert_eq!(size, inner.size);
    current
}
