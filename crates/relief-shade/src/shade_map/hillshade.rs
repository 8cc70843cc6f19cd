//! The Lambert hillshade of a height field: its slope towards a sun, the way GIS tools compute
//! it (Horn's 3x3 gradient, as `gdaldem hillshade`), with no shadows.

use relief_core::{DVec3, HeightField};

/// The unit upward normal at sample (`col`, `row`) of `field` from Horn's gradient: the
/// height differences across the 3x3 neighbourhood, the nearer neighbours weighted twice, over
/// 8 spacings, in world units (`dx`, `dy`, `z_scale`). A neighbour outside the grid or in
/// `void` (when given, indexed like the samples) counts as the centre sample's height, so the
/// edges and the rims of voids are shaded too.
pub fn horn_normal(field: &HeightField, void: Option<&[bool]>, col: usize, row: usize) -> DVec3 {
    let (w, h) = (field.width() as isize, field.height() as isize);
    let centre = field.sample(col, row) as f64;
    let z = |dc: isize, dr: isize| -> f64 {
        let (c, r) = (col as isize + dc, row as isize + dr);
        if c < 0 || r < 0 || c >= w || r >= h {
            return centre;
        }
        let (c, r) = (c as usize, r as usize);
        if void.is_some_and(|v| v[c + r * field.width()]) || field.is_hole(c, r) {
            centre
        } else {
            field.sample(c, r) as f64
        }
    };
    let g = field.geometry();
    // Row 0 is south: dr = +1 is the northern neighbour.
    let east = z(1, 1) + 2.0 * z(1, 0) + z(1, -1);
    let west = z(-1, 1) + 2.0 * z(-1, 0) + z(-1, -1);
    let north = z(-1, 1) + 2.0 * z(0, 1) + z(1, 1);
    let south = z(-1, -1) + 2.0 * z(0, -1) + z(1, -1);
    let dz_dx = (east - west) * g.z_scale / (8.0 * g.dx);
    let dz_dy = (north - south) * g.z_scale / (8.0 * g.dy);
    DVec3::new(-dz_dx, -dz_dy, 1.0).normalize()
}

/// Lambert's cosine of a surface with unit `normal` lit from the unit direction `towards_sun`,
/// clamped at 0 (a slope facing away is dark): `gdaldem hillshade`'s value divided by 255.
pub fn lambert(normal: DVec3, towards_sun: DVec3) -> f64 {
    normal.dot(towards_sun).max(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sun_direction;
    use relief_core::GridGeometry;

    fn plane(slope_east: f64, slope_north: f64, dx: f64) -> HeightField {
        let samples = (0..25)
            .map(|k| ((k % 5) as f64 * slope_east * dx + (k / 5) as f64 * slope_north * dx) as f32)
            .collect();
        let geometry = GridGeometry { dx, dy: dx, ..GridGeometry::unit() };
        HeightField::new(5, 5, samples, geometry).unwrap()
    }

    #[test]
    fn a_plane_facing_the_sun_is_fully_lit_everywhere() {
        // Down towards the east at 45°: its normal points east and up, at the sun of azimuth 90°,
        // elevation 45°. The edges count missing neighbours as the centre: the gradient there
        // is half as steep (one-sided over two spacings), so test the inner samples.
        let field = plane(-1.0, 0.0, 30.0);
        let sun = sun_direction(90.0, 45.0);
        for row in 1..4 {
            for col in 1..4 {
                let n = horn_normal(&field, None, col, row);
                assert!((lambert(n, sun) - 1.0).abs() < 1e-6, "{col},{row}: {n}");
            }
        }
        // The sun in the west lights it at grazing angle 0.
        assert_eq!(lambert(horn_normal(&field, None, 2, 2), sun_direction(270.0, 45.0)), 0.0);
    }

    #[test]
    fn north_is_the_rising_row() {
        // Rising towards the north (+y): it faces south.
        let field = plane(0.0, 0.5, 10.0);
        let n = horn_normal(&field, None, 2, 2);
        assert!(n.y < 0.0 && n.x.abs() < 1e-12, "{n}");
        let flat = horn_normal(&plane(0.0, 0.0, 10.0), None, 0, 0);
        assert_eq!(flat, DVec3::Z);
    }

    #[test]
    fn void_neighbours_count_as_the_centre() {
        let field = plane(-1.0, 0.0, 30.0);
        let mut void = vec![false; 25];
        void[3 + 2 * 5] = true; // the eastern neighbour of (2, 2)
        let with = horn_normal(&field, Some(&void), 2, 2);
        let without = horn_normal(&field, None, 2, 2);
        assert!(with.x < without.x, "{with} {without}");
    }
}
