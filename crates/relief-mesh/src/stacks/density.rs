//! Stacks to density (section 3.2.1) and smoothing (section 3.2.2): the coverage of each
//! lattice point's voxel by a level's layers, in channels, then a separable low-pass filter.

use super::lattice::{Block, Lattice};
use relief_core::{MaterialKind, MaterialStacks};

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
        Channels { of_material, count, materials }
    }
}

/// The smoothed density of one level over a block of lattice points, channel-major
/// (`values[channel][block index]`).
#[derive(Debug, Clone)]
pub(crate) struct Density {
    /// The points the values cover.
    pub block: Block,
    /// One grid of values per channel.
    pub channels: Vec<Vec<f32>>,
}

impl Density {
    /// The density of `stacks` (one level, on `lattice`) over `block`, smoothed by `kernel`.
    pub fn new(
        stacks: &MaterialStacks,
        lattice: &Lattice,
        channels: &Channels,
        block: Block,
        kernel: &[f32],
    ) -> Self {
        let r = (kernel.len() / 2) as i32;
        let wide = block.grown(r);
        let mut values = vec![vec![0f32; wide.len()]; channels.count];
        let [nx, ny, nz] = wide.size;
        let (z_lo, z_hi) = (wide.min[2], wide.min[2] + nz as i32);
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
                let column = wide.index([x, y, 0]);
                for layer in stacks.stack(gx as usize, gy as usize) {
                    let (total, own) = channels.of_material[layer.material as usize];
                    let (start, end) = (lattice.to_k(layer.start), lattice.to_k(layer.end));
                    // Voxel k covers [k - 0.5, k + 0.5] in lattice units.
                    let first = ((start + 0.5).floor() as i32).max(z_lo);
                    let last = ((end + 0.5).ceil() as i32 - 1).min(z_hi - 1);
                    for k in first..=last {
                        let kf = k as f64;
                        let cover = (end.min(kf + 0.5) - start.max(kf - 0.5)).max(0.0) as f32;
                        let i = column + (k - z_lo) as usize * nx * ny;
                        values[total][i] += cover;
                        if let Some(own) = own {
                            values[own][i] += cover;
                        }
                    }
                }
            }
        }
        // The solid and liquid densities are smoothed; the materials' coverage, which only
        // colours the vertices, is taken as it is.
        let channels = values
            .into_iter()
            .enumerate()
            .map(
                |(c, v)| if c < 2 { smooth(v, wide, block, kernel) } else { crop(&v, wide, block) },
            )
            .collect();
        Density { block, channels }
    }

    /// The value of `channel` at lattice point `p` (which must lie in the block).
    #[inline]
    pub fn at(&self, channel: usize, p: [i32; 3]) -> f32 {
        self.channels[channel][self.block.index_of(p)]
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

/// `values` over `wide` filtered along x, y and z by `kernel` and cut to `inner`: each output
/// sums its neighbours in a fixed order, so a point gets the same value in every block. A
/// channel with no coverage stays zero without filtering.
fn smooth(values: Vec<f32>, wide: Block, inner: Block, kernel: &[f32]) -> Vec<f32> {
    if values.iter().all(|&v| v == 0.0) {
        return vec![0.0; inner.len()];
    }
    let r = kernel.len() / 2;
    let mut current = values;
    let mut size = wide.size;
    for axis in 0..3 {
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
