//! Warnings of scenes that render without an error but not as the user meant: a camera
//! inside the terrain, a DEM whose heights dwarf its grid at the default spacing.

use relief_core::{
    splits_along_ad, Camera, DVec3, HeightField, MaterialStacks, Mlhm, Projection, Surface,
};

/// A terrain whose relief (highest minus lowest height, after `--z-scale`) is more than this
/// many times its grid's larger side, at a spacing that no one gave, is taken as a DEM read
/// at the wrong spacing. Real terrain's relief stays under its extent (the steepest
/// kilometre of the Alps rises about 1 km); at twice it the mean slope across the whole grid
/// passes 63 degrees and the picture is a needle.
pub const NEEDLE_RELIEF_RATIO: f64 = 2.0;

/// The warning for a height field whose spacing was defaulted (no `--spacing`, no
/// georeference) and whose heights span more than [`NEEDLE_RELIEF_RATIO`] times its grid.
pub fn defaulted_spacing(field: &HeightField) -> Option<String> {
    let g = field.geometry();
    let (low, high) =
        (field.min_sample() as f64 * g.z_scale, field.max_sample() as f64 * g.z_scale);
    let relief = high - low;
    let (w, h) = (field.width() as f64 * g.dx.abs(), field.height() as f64 * g.dy.abs());
    let extent = w.max(h);
    let needle = relief > NEEDLE_RELIEF_RATIO * extent;
    if !needle {
        return None;
    }
    Some(format!(
        "warning: the heights span {} ({} to {}) over a {} x {} grid at the default spacing of \
         {} (the file has no georeference): the terrain is {:.0} times taller than it is wide \
         and renders as a needle. Give the distance between samples in height units with \
         --spacing (e.g. --spacing 30 for a DEM of 30 m cells), or scale the heights with \
         --z-scale",
        round(relief),
        round(low),
        round(high),
        field.width(),
        field.height(),
        round(g.dx),
        relief / extent
    ))
}

/// The warning for a pinhole `camera` whose eye is inside the solid of `field`'s `surface`
/// (under the surface, over the grid): every ray starts inside the terrain and the picture is
/// black.
pub fn eye_in_height_field(
    field: &HeightField,
    surface: Surface,
    camera: &Camera,
) -> Option<String> {
    if !matches!(camera.projection(), Projection::Perspective { .. }) {
        return None;
    }
    let eye = camera.eye();
    let top = surface_height(field, surface, eye.x, eye.y)?;
    (eye.z < top).then(|| eye_inside(eye, top))
}

/// The warning for a pinhole `camera` whose eye is inside the solid (bedrock or sand) of an
/// MLHM.
pub fn eye_in_mlhm(map: &Mlhm, camera: &Camera) -> Option<String> {
    if !matches!(camera.projection(), Projection::Perspective { .. }) {
        return None;
    }
    let eye = camera.eye();
    let s = map.cell_size();
    let (x, y) = ((eye.x / s).floor(), (eye.y / s).floor());
    if !(x >= 0.0 && y >= 0.0 && x < map.width() as f64 && y < map.height() as f64) {
        return None;
    }
    let (x, y) = (x as usize, y as usize);
    let z = eye.z as f32;
    let mut floor = f32::NEG_INFINITY;
    for column in map.cell_columns(x, y) {
        if z >= floor && z < column.ceiling {
            if z >= column.solid_top() {
                return None;
            }
            // The map's solid is clipped at its lowest bedrock top: below it is outside.
            let clip = (0..map.height())
                .flat_map(|y| (0..map.width()).map(move |x| (x, y)))
                .filter_map(|(x, y)| map.cell_columns(x, y).next())
                .map(|c| c.bedrock)
                .fold(f32::INFINITY, f32::min);
            return (z >= clip).then(|| eye_inside(eye, f64::from(column.solid_top())));
        }
        floor = column.ceiling;
    }
    None
}

/// The warning for a pinhole `camera` whose eye is inside a solid layer of a material-stack
/// terrain (a stack's cell covers `[origin + x s, origin + (x + 1) s)` along each axis).
pub fn eye_in_stacks(stacks: &MaterialStacks, camera: &Camera) -> Option<String> {
    if !matches!(camera.projection(), Projection::Perspective { .. }) {
        return None;
    }
    let eye = camera.eye();
    let (o, s) = (stacks.origin(), stacks.spacing());
    let (x, y) = (((eye.x - o.x) / s.x).floor(), ((eye.y - o.y) / s.y).floor());
    if !(x >= 0.0 && y >= 0.0 && x < stacks.width() as f64 && y < stacks.height() as f64) {
        return None;
    }
    let z = eye.z as f32;
    let materials = stacks.materials();
    let solid = |material: u8| materials.get(material as usize).is_none_or(|m| !m.is_liquid());
    let layer = stacks
        .stack(x as usize, y as usize)
        .iter()
        .find(|l| l.start <= z && z < l.end && solid(l.material))?;
    Some(eye_inside(eye, f64::from(layer.end)))
}

/// The message for an eye under the surface whose top is at `top` over it.
fn eye_inside(eye: DVec3, top: f64) -> String {
    let above = top + (top.abs() * 0.1).max(10.0);
    format!(
        "warning: the camera's eye ({}, {}, {}) is inside the terrain, whose surface is at \
         height {} there: every ray starts in the solid and the picture will be black. Raise \
         the eye above the surface (e.g. --eye {},{},{}), or leave out --eye and --target for \
         the default view",
        round(eye.x),
        round(eye.y),
        round(eye.z),
        round(top),
        round(eye.x),
        round(eye.y),
        round(above)
    )
}

/// The height of `field`'s `surface` over world `(x, y)`; `None` off the surface's
/// footprint or over a hole.
fn surface_height(field: &HeightField, surface: Surface, x: f64, y: f64) -> Option<f64> {
    let g = field.geometry();
    let (col, row) = ((x - g.origin.x) / g.dx, (y - g.origin.y) / g.dy);
    let (w, h) = (field.width(), field.height());
    if !(col >= 0.0 && row >= 0.0 && col < w as f64 && row < h as f64) {
        return None;
    }
    let value = match surface {
        Surface::Boxes => {
            let (c, r) = (col as usize, row as usize);
            if field.is_hole(c, r) {
                return None;
            }
            f64::from(field.sample(c, r))
        }
        Surface::Triangles => {
            // Vertices at the samples (texel centres); the footprint ends at the border ones.
            let (u, v) = (col - 0.5, row - 0.5);
            if !(u >= 0.0 && v >= 0.0 && u <= (w - 1) as f64 && v <= (h - 1) as f64) {
                return None;
            }
            let (c, r) =
                ((u as usize).min(w.saturating_sub(2)), (v as usize).min(h.saturating_sub(2)));
            if w < 2 || h < 2 {
                return Some(f64::from(field.sample(0, 0)) * g.z_scale);
            }
            let corners = [(c, r), (c + 1, r), (c, r + 1), (c + 1, r + 1)];
            if corners.iter().any(|&(c, r)| field.is_hole(c, r)) {
                return None;
            }
            let [h00, h10, h01, h11] = corners.map(|(c, r)| f64::from(field.sample(c, r)));
            triangle_height([h00, h10, h01, h11], u - c as f64, v - r as f64)
        }
    };
    Some(value * g.z_scale)
}

/// The height at `(fu, fv)` in [0, 1]^2 of the two triangles over four samples `[h00, h10,
/// h01, h11]`, split along the diagonal every tracer of the surface takes
/// ([`splits_along_ad`]).
fn triangle_height([h00, h10, h01, h11]: [f64; 4], fu: f64, fv: f64) -> f64 {
    if splits_along_ad(h00, h10, h01, h11) {
        // Diagonal (0,0)-(1,1).
        if fu >= fv {
            h00 + fu * (h10 - h00) + fv * (h11 - h10)
        } else {
            h00 + fv * (h01 - h00) + fu * (h11 - h01)
        }
    } else if fu + fv <= 1.0 {
        // Diagonal (1,0)-(0,1).
        h00 + fu * (h10 - h00) + fv * (h01 - h00)
    } else {
        h11 + (1.0 - fu) * (h01 - h11) + (1.0 - fv) * (h10 - h11)
    }
}

/// `v` with at most one decimal, for messages.
fn round(v: f64) -> String {
    let r = (v * 10.0).round() / 10.0;
    match r == r.trunc() {
        true => format!("{r:.0}"),
        false => format!("{r:.1}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn triangles_interpolate_their_corners() {
        let q = [0.0, 1.0, 2.0, 3.0];
        assert_eq!(triangle_height(q, 0.0, 0.0), 0.0);
        assert_eq!(triangle_height(q, 1.0, 1.0), 3.0);
        assert_eq!(triangle_height(q, 1.0, 0.0), 1.0);
        assert_eq!(triangle_height(q, 0.0, 1.0), 2.0);
        assert_eq!(triangle_height(q, 0.5, 0.5), 1.5);
    }

    #[test]
    fn numbers_read_short() {
        assert_eq!(round(120.0), "120");
        assert_eq!(round(143.26), "143.3");
    }
}
