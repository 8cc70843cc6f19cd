//! Material stacks from their parts, from a height field and from a multi-layered height map.

use super::{MaterialStacks, StackLayer, StackMaterial};
use crate::{CoreError, DVec2, HeightField, Mlhm};

impl MaterialStacks {
    /// Stacks from their compressed-row parts (see [`MaterialStacks`]), checked by
    /// [`MaterialStacks::validate`]; fails naming the first bad stack and layer, or when the
    /// grid is empty, the spacing is not finite and positive, the origin is not finite, or the
    /// palette is empty or has more than 256 materials.
    pub fn from_parts(
        width: usize,
        height: usize,
        spacing: DVec2,
        origin: DVec2,
        materials: Vec<StackMaterial>,
        offsets: Vec<u32>,
        layers: Vec<StackLayer>,
    ) -> Result<Self, CoreError> {
        if width == 0 || height == 0 {
            return Err(CoreError::Grid(format!("{width}x{height} stacks: the grid is empty")));
        }
        if !(spacing.x.is_finite() && spacing.y.is_finite() && spacing.x > 0.0 && spacing.y > 0.0) {
            return Err(CoreError::Parameter {
                name: "spacing",
                reason: format!("{spacing} must be finite and positive"),
            });
        }
        if !origin.is_finite() {
            return Err(CoreError::Parameter {
                name: "origin",
                reason: format!("{origin} must be finite"),
            });
        }
        if materials.is_empty() || materials.len() > 256 {
            return Err(CoreError::Parameter {
                name: "materials",
                reason: format!("{} materials: 1 to 256 are allowed", materials.len()),
            });
        }
        if layers.len() > u32::MAX as usize {
            return Err(CoreError::Grid(format!("{} layers exceed u32 offsets", layers.len())));
        }
        let stacks = MaterialStacks { width, height, spacing, origin, materials, offsets, layers };
        stacks.validate()?;
        Ok(stacks)
    }

    /// Stacks from one stack per grid cell, bottom to top, row-major (`x + y * width`): the
    /// compressed-row parts made from nested vectors, then as [`MaterialStacks::from_parts`].
    pub fn from_stacks(
        width: usize,
        height: usize,
        spacing: DVec2,
        origin: DVec2,
        materials: Vec<StackMaterial>,
        stacks: &[Vec<StackLayer>],
    ) -> Result<Self, CoreError> {
        if stacks.len() != width * height {
            return Err(CoreError::Grid(format!(
                "{} stacks for a {width}x{height} grid",
                stacks.len()
            )));
        }
        let mut offsets = Vec::with_capacity(stacks.len() + 1);
        offsets.push(0u32);
        let mut layers = Vec::new();
        for stack in stacks {
            layers.extend_from_slice(stack);
            offsets.push(
                u32::try_from(layers.len())
                    .map_err(|_| CoreError::Grid(format!("more than {} layers", u32::MAX)))?,
            );
        }
        Self::from_parts(width, height, spacing, origin, materials, offsets, layers)
    }

    /// The solid of a height field as stacks of bedrock: each texel's stack runs from the
    /// field's bottom ([`HeightField::min_sample`], scaled) up to its sample, as the tracers'
    /// solid does; a hole, or a sample at the bottom, leaves the stack empty. Spacing and origin
    /// are the field's; the palette is [`StackMaterial::defaults`].
    pub fn from_height_field(field: &HeightField) -> Result<Self, CoreError> {
        let g = field.geometry();
        let bottom = (field.min_sample() as f64 * g.z_scale) as f32;
        let (w, h) = (field.width(), field.height());
        let mut offsets = Vec::with_capacity(w * h + 1);
        offsets.push(0u32);
        let mut layers = Vec::with_capacity(w * h);
        for row in 0..h {
            for col in 0..w {
                let top = (field.sample(col, row) as f64 * g.z_scale) as f32;
                if !field.is_hole(col, row) && top > bottom {
                    layers.push(StackLayer::new(bottom, top, StackMaterial::BEDROCK));
                }
                offsets.push(layers.len() as u32);
            }
        }
        Self::from_parts(
            w,
            h,
            DVec2::new(g.dx, g.dy),
            g.origin,
            StackMaterial::defaults(),
            offsets,
            layers,
        )
    }

    /// The stacks of a multi-layered height map: per cell and column, bedrock from the
    /// column's floor (for the lowest column, the map's lowest bedrock top, where relief's
    /// tracers clip the solid) to its bedrock top, then its sand and its water; layers of no
    /// thickness are left out. Cell `(x, y)` becomes stack `(x, y)`, spacing the cell size,
    /// origin zero; the palette is [`StackMaterial::defaults`].
    pub fn from_mlhm(map: &Mlhm) -> Result<Self, CoreError> {
        let bottom = map.heights().bedrock_min as f32;
        let (w, h) = (map.width(), map.height());
        let mut offsets = Vec::with_capacity(w * h + 1);
        offsets.push(0u32);
        let mut layers = Vec::with_capacity(w * h * 3);
        for y in 0..h {
            for x in 0..w {
                let mut floor = bottom;
                for column in map.cell_columns(x, y) {
                    let solid_top = column.solid_top();
                    let water_top = column.water_top();
                    let parts = [
                        (floor, column.bedrock, StackMaterial::BEDROCK),
                        (column.bedrock.max(floor), solid_top, StackMaterial::SAND),
                        (solid_top.max(floor), water_top, StackMaterial::WATER),
                    ];
                    for (start, end, material) in parts {
                        if end > start {
                            layers.push(StackLayer::new(start, end, material));
                        }
                    }
                    floor = column.ceiling;
                }
                offsets.push(layers.len() as u32);
            }
        }
        let size = map.cell_size();
        Self::from_parts(
            w,
            h,
            DVec2::splat(size),
            DVec2::ZERO,
            StackMaterial::defaults(),
            offsets,
            layers,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{GridGeometry, MlhmColumn};

    #[test]
    fn a_height_field_becomes_bedrock_from_its_lowest_sample() {
        let field = HeightField::new(2, 1, vec![1.0, 3.0], GridGeometry::unit()).unwrap();
        let stacks = MaterialStacks::from_height_field(&field).unwrap();
        assert!(stacks.stack(0, 0).is_empty());
        assert_eq!(stacks.stack(1, 0), &[StackLayer::new(1.0, 3.0, StackMaterial::BEDROCK)]);
        assert_eq!(stacks.volume(|m| !m.is_liquid()), 2.0);
    }

    #[test]
    fn an_mlhm_overhang_becomes_bedrock_sand_water_and_a_second_rock_layer() {
        let mut map = Mlhm::new(2, 1, 2, 1.0).unwrap();
        map.set_cell(0, 0, &[MlhmColumn::new(0.5, 0.0, 0.0, f32::INFINITY)]).unwrap();
        map.set_cell(
            1,
            0,
            &[MlhmColumn::new(1.0, 0.5, 0.25, 3.0), MlhmColumn::new(4.0, 0.0, 0.0, f32::INFINITY)],
        )
        .unwrap();
        let stacks = MaterialStacks::from_mlhm(&map).unwrap();
        assert!(stacks.stack(0, 0).is_empty(), "the lowest bedrock top is the bottom");
        assert_eq!(
            stacks.stack(1, 0),
            &[
                StackLayer::new(0.5, 1.0, StackMaterial::BEDROCK),
                StackLayer::new(1.0, 1.5, StackMaterial::SAND),
                StackLayer::new(1.5, 1.75, StackMaterial::WATER),
                StackLayer::new(3.0, 4.0, StackMaterial::BEDROCK),
            ]
        );
    }

    #[test]
    fn overlapping_or_backward_layers_are_refused_naming_the_stack_and_layer() {
        let make = |layers: Vec<StackLayer>| {
            let n = layers.len() as u32;
            MaterialStacks::from_parts(
                2,
                1,
                DVec2::ONE,
                DVec2::ZERO,
                StackMaterial::defaults(),
                vec![0, 0, n],
                layers,
            )
        };
        let err = make(vec![StackLayer::new(0.0, 2.0, 0), StackLayer::new(1.0, 3.0, 1)])
            .unwrap_err()
            .to_string();
        assert!(err.contains("stack (1, 0), layer 1") && err.contains("overlaps"), "{err}");
        let err = make(vec![StackLayer::new(2.0, 1.0, 0)]).unwrap_err().to_string();
        assert!(err.contains("stack (1, 0), layer 0") && err.contains("backwards"), "{err}");
        assert!(make(vec![StackLayer::new(0.0, 1.0, 7)]).is_err());
        assert!(make(vec![StackLayer::new(0.0, f32::NAN, 0)]).is_err());
    }
}
