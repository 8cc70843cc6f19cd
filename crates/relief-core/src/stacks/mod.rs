//! Material stacks (Löffler et al. 2011): per grid point a stack of layers, each a height
//! interval of one material, with air implied between them.
//!
//! - [`layer`]: one layer ([`StackLayer`]);
//! - [`palette`]: the materials a stacks terrain names ([`StackMaterial`], [`MaterialKind`]),
//!   bedrock, sand and water by default;
//! - [`constructors`]: stacks from their parts (validated), from a height field, from an MLHM;
//! - [`mipmap`]: the LOD mipmap, vertex-centred and nested ([`StacksMipmap`], [`aggregate`]);
//! - [`aggregation`]: the paper's material aggregation heuristic, one coarse stack at a time.

mod aggregation;
mod constructors;
mod layer;
mod mipmap;
mod palette;

pub use layer::StackLayer;
pub use mipmap::{aggregate, StacksMipmap};
pub use palette::{MaterialKind, StackMaterial};

use crate::{CoreError, DVec2};

/// A material-stack terrain: `width x height` stacks on a regular grid, each a list of
/// [`StackLayer`]s bottom to top that neither overlap nor run backwards; air lies between
/// layers and above the top one. Stack `(x, y)` stands on the footprint
/// `[x, x + 1) x [y, y + 1)` grid units as a height field's texel does (row 0 southernmost),
/// its centre at world `origin + ((x + 0.5) * spacing.x, (y + 0.5) * spacing.y)`; heights are
/// absolute, in metres.
///
/// Storage is compressed-row: the layers of stack `x + y * width` are
/// `layers[offsets[i]..offsets[i + 1]]`.
///
/// ```
/// use relief_core::{MaterialStacks, StackLayer, StackMaterial, DVec2};
/// // Two stacks: plain ground, and ground with a rock arch above an air gap.
/// let stacks = MaterialStacks::from_parts(
///     2, 1, DVec2::ONE, DVec2::ZERO, StackMaterial::defaults(),
///     vec![0, 1, 3],
///     vec![
///         StackLayer::new(0.0, 2.0, 0),
///         StackLayer::new(0.0, 2.0, 0),
///         StackLayer::new(5.0, 6.0, 0),
///     ],
/// )?;
/// assert_eq!(stacks.stack(1, 0).len(), 2);
/// assert!(MaterialStacks::from_parts(
///     1, 1, DVec2::ONE, DVec2::ZERO, StackMaterial::defaults(),
///     vec![0, 2],
///     vec![StackLayer::new(0.0, 2.0, 0), StackLayer::new(1.0, 3.0, 1)],
/// ).is_err());
/// # Ok::<(), relief_core::CoreError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct MaterialStacks {
    width: usize,
    height: usize,
    spacing: DVec2,
    origin: DVec2,
    materials: Vec<StackMaterial>,
    offsets: Vec<u32>,
    layers: Vec<StackLayer>,
}

impl MaterialStacks {
    /// Number of stacks along x.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Number of stacks along y.
    pub fn height(&self) -> usize {
        self.height
    }

    /// Distance between neighbouring stacks in metres, along x and y.
    pub fn spacing(&self) -> DVec2 {
        self.spacing
    }

    /// World position of the south-west corner of stack (0, 0)'s footprint.
    pub fn origin(&self) -> DVec2 {
        self.origin
    }

    /// The materials layers refer to by index.
    pub fn materials(&self) -> &[StackMaterial] {
        &self.materials
    }

    /// The layers of stack `(x, y)`, bottom to top.
    ///
    /// # Panics
    /// If `(x, y)` lies outside the grid.
    #[inline]
    pub fn stack(&self, x: usize, y: usize) -> &[StackLayer] {
        assert!(x < self.width && y < self.height, "stack ({x}, {y}) outside the grid");
        let i = x + y * self.width;
        &self.layers[self.offsets[i] as usize..self.offsets[i + 1] as usize]
    }

    /// The compressed-row offsets: `width * height + 1` of them.
    pub fn offsets(&self) -> &[u32] {
        &self.offsets
    }

    /// Every layer, stack after stack.
    pub fn layers(&self) -> &[StackLayer] {
        &self.layers
    }

    /// The lowest layer start and the highest layer end of all stacks, or `None` when every
    /// stack is empty.
    pub fn height_range(&self) -> Option<(f32, f32)> {
        let low = self.layers.iter().map(|l| l.start).reduce(f32::min)?;
        let high = self.layers.iter().map(|l| l.end).reduce(f32::max)?;
        Some((low, high))
    }

    /// Volume in cubic metres of the layers whose material satisfies `keep`.
    pub fn volume(&self, keep: impl Fn(&StackMaterial) -> bool) -> f64 {
        let area = self.spacing.x * self.spacing.y;
        self.layers
            .iter()
            .filter(|l| keep(&self.materials[l.material as usize]))
            .map(|l| (l.end - l.start) as f64 * area)
            .sum()
    }

    /// Bytes the stacks occupy in memory (offsets, layers and materials).
    pub fn memory_bytes(&self) -> usize {
        self.offsets.len() * 4
            + self.layers.len() * std::mem::size_of::<StackLayer>()
            + self.materials.iter().map(|m| m.name.len() + 8).sum::<usize>()
    }

    /// Checks every invariant; the first failure names the stack and the layer:
    /// offsets start at 0, never decrease, never pass the layer count and end at it; every layer's start and
    /// end are finite with `start < end`; a layer starts at or above the end of the layer below;
    /// every material index names a material of the palette.
    pub fn validate(&self) -> Result<(), CoreError> {
        let cells = self.width * self.height;
        if self.offsets.len() != cells + 1
            || self.offsets[0] != 0
            || self.offsets[cells] as usize != self.layers.len()
        {
            return Err(CoreError::Grid(format!(
                "{} stack offsets ending at {} for {cells} stacks of {} layers",
                self.offsets.len(),
                self.offsets.last().copied().unwrap_or(0),
                self.layers.len()
            )));
        }
        for i in 0..cells {
            let (x, y) = (i % self.width, i / self.width);
            let (begin, end) = (self.offsets[i], self.offsets[i + 1]);
            if end < begin {
                return Err(CoreError::Grid(format!(
                    "stack ({x}, {y}): offsets run backwards ({begin} then {end})"
                )));
            }
            if end as usize > self.layers.len() {
                return Err(CoreError::Grid(format!(
                    "stack ({x}, {y}): offset {end} past the {} layers",
                    self.layers.len()
                )));
            }
            let layers = &self.layers[begin as usize..end as usize];
            for (k, layer) in layers.iter().enumerate() {
                let fail = |reason: String| CoreError::StackLayer { x, y, layer: k, reason };
                if !layer.start.is_finite() || !layer.end.is_finite() {
                    return Err(fail(format!(
                        "start {} and end {} must be finite",
                        layer.start, layer.end
                    )));
                }
                if layer.start >= layer.end {
                    return Err(fail(format!(
                        "runs backwards or is empty: start {} is not below end {}",
                        layer.start, layer.end
                    )));
                }
                if layer.material as usize >= self.materials.len() {
                    return Err(fail(format!(
                        "material {} is not one of the {} materials",
                        layer.material,
                        self.materials.len()
                    )));
                }
                if k > 0 && layer.start < layers[k - 1].end {
                    return Err(fail(format!(
                        "overlaps the layer below: starts at {} under its end {}",
                        layer.start,
                        layers[k - 1].end
                    )));
                }
            }
        }
        Ok(())
    }
}
