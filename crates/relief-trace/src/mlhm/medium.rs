//! Which medium (air, water or solid) a point of an MLHM scene lies in, and how deep under
//! the water's surface: resolved in the one cell below the point, since water lies in columns.

use relief_core::{DVec2, DVec3, Mlhm};

/// What fills the space at a point of an MLHM scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Medium {
    /// Open air (also everything outside the grid's footprint).
    Air,
    /// Water, `depth` metres below its surface straight above.
    Water {
        /// Distance straight up to the water surface.
        depth: f64,
    },
    /// Inside bedrock or sand.
    Solid,
}

/// The medium at world point `p` of `map`, whose south-west corner is at world `origin`:
/// resolved within the one cell below `p`, since water in an MLHM lies in columns; air below
/// the map's [base](Mlhm::base).
pub fn medium_at(map: &Mlhm, origin: DVec2, p: DVec3) -> Medium {
    let s = map.cell_size();
    let (fx, fy) = ((p.x - origin.x) / s, (p.y - origin.y) / s);
    if !(fx >= 0.0 && fy >= 0.0 && fx < map.width() as f64 && fy < map.height() as f64) {
        return Medium::Air;
    }
    let (x, y) = (fx as usize, fy as usize);
    let z = p.z;
    // Below the base the solid has ended.
    if z < map.base() as f64 {
        return Medium::Air;
    }
    let n = map.layer_count(x, y);
    for (k, c) in map.cell_columns(x, y).enumerate() {
        if z >= c.ceiling as f64 && k + 1 < n {
            continue;
        }
        let (solid, water) = (c.solid_top() as f64, c.water_top() as f64);
        return if z < solid {
            Medium::Solid
        } else if z < water {
            Medium::Water { depth: water - z }
        } else {
            Medium::Air
        };
    }
    Medium::Air
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief_core::MlhmColumn;

    #[test]
    fn media_of_a_flooded_cave() {
        // Ground: bedrock to 1 m, sand 0.5 m, water 1 m, air to the cave roof at 4 m; above it a
        // rock slab to 5 m under a 0.5 m pond.
        let mut map = Mlhm::new(1, 1, 2, 2.0).unwrap();
        let cave =
            [MlhmColumn::new(1.0, 0.5, 1.0, 4.0), MlhmColumn::new(5.0, 0.0, 0.5, f32::INFINITY)];
        map.set_cell(0, 0, &cave).unwrap();
        let at = |x: f64, z: f64| medium_at(&map, DVec2::new(10.0, 0.0), DVec3::new(x, 1.0, z));
        assert_eq!(at(11.0, 0.0), Medium::Solid);
        assert_eq!(at(11.0, 1.25), Medium::Solid);
        assert_eq!(at(11.0, 2.0), Medium::Water { depth: 0.5 });
        assert_eq!(at(11.0, 3.0), Medium::Air);
        assert_eq!(at(11.0, 4.5), Medium::Solid);
        assert_eq!(at(11.0, 5.25), Medium::Water { depth: 0.25 });
        assert_eq!(at(11.0, 9.0), Medium::Air);
        assert_eq!(at(9.0, 2.0), Medium::Air, "outside the footprint");
        assert_eq!(at(f64::NAN, 2.0), Medium::Air);
    }
}
