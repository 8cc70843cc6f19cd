//! Shading terms of box faces filtered over a pixel's footprint: the shading normal (the
//! mean normal of the boxes' surface near the hit) and the sun's visibility (the lit share of
//! the footprint as the sun sees it). Box terrain is a staircase of steps far thinner than a
//! pixel; point-sampled, their side faces and the shadow slivers they cast show as stipple,
//! moiré rings and, where pixel centres fall exactly on cell edges, lines.

use relief_core::{DVec3, Mlhm};

/// The side of the cube a shading normal is filtered over, in pixel footprints.
pub const NORMAL_FILTER_FOOTPRINTS: f64 = 2.0;

/// Bisection steps of the filtered sun visibility: its resolution is `2^-6` of full light.
pub const VISIBILITY_BISECTIONS: u32 = 5;

/// Gradient components below this share of the gradient's length are rounding: set to 0, so
/// that a flat face's normal is exactly its own.
const ROUNDING: f64 = 1e-9;

/// The normal of the surface of `map`'s solids (and water, where `water`) at grid-local point
/// `p` (exact face normal `exact`) filtered over a pixel `footprint` metres wide: `-grad V`
/// by central differences of spacing `r`, with `V` the volume of solids (and water) in the
/// cube of half-size `r` around the point and `r` half of [`NORMAL_FILTER_FOOTPRINTS`]
/// footprints. By the divergence theorem
/// `-grad V` is the area-weighted mean of the surface's normals near `p`, so a face larger
/// than the footprint keeps its own normal (exactly: the differences across a flat face
/// cancel) and steps far thinner than a pixel lean it only by their share of the area.
///
/// Returns `exact` when the footprint is not a positive length or the filtered normal is
/// degenerate or faces away from the face (a sliver thinner than the footprint).
pub fn filtered_normal(map: &Mlhm, p: DVec3, exact: DVec3, footprint: f64, water: bool) -> DVec3 {
    let r = 0.5 * NORMAL_FILTER_FOOTPRINTS * footprint;
    if !(r.is_finite() && r > 0.0) {
        return exact;
    }
    let volume = |c: DVec3| match water {
        false => map.solid_volume(c - r, c + r),
        true => map.material_volumes(c - r, c + r).total(),
    };
    let mut g = DVec3::ZERO;
    for axis in 0..3 {
        let mut d = DVec3::ZERO;
        d[axis] = r;
        g[axis] = volume(p - d) - volume(p + d);
    }
    let length = g.length();
    if !(length.is_finite() && length > 0.0) {
        return exact;
    }
    for axis in 0..3 {
        if g[axis].abs() < ROUNDING * length {
            g[axis] = 0.0;
        }
    }
    let n = g.normalize();
    if n.dot(exact) > 0.0 {
        n
    } else {
        exact
    }
}

/// The sun's visibility filtered over a footprint: the lit share of a strip `width` wide
/// across the sun's rays, from a point whose shadow ray is `occluded(0)` and whose shadow
/// rays shifted by `lift` across the sun's rays, away from the surface, are `occluded(lift)`.
///
/// 1 when the point's own ray is clear; 0 when even the ray shifted by the whole width is
/// blocked; in between, the shift at which the rays clear (found by
/// [`VISIBILITY_BISECTIONS`] bisections) gives `1 - shift / width`: an occluder whose shadow
/// covers a sliver of the footprint darkens it by that sliver's share, and a shadow's edge
/// fades over one footprint. Shadow rays are only traced where the point's own is blocked.
pub fn lit_share(width: f64, mut occluded: impl FnMut(f64) -> bool) -> f64 {
    if !occluded(0.0) {
        return 1.0;
    }
    if !(width.is_finite() && width > 0.0) || occluded(width) {
        return 0.0;
    }
    // Blocked at `lo`, clear at `hi`.
    let (mut lo, mut hi) = (0.0, width);
    for _ in 0..VISIBILITY_BISECTIONS {
        let mid = 0.5 * (lo + hi);
        if occluded(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    1.0 - 0.5 * (lo + hi) / width
}

/// The direction in which to shift a shadow ray of direction `to_sun` (unit) off a surface of
/// (shading) normal `n`: across the sun's rays, away from the surface (`n` without its part
/// along the rays), or, for light straight along the normal, any direction across the rays.
pub fn lift_direction(n: DVec3, to_sun: DVec3) -> DVec3 {
    let across = n - n.dot(to_sun) * to_sun;
    if across.length() > 1e-6 {
        return across.normalize();
    }
    let helper = if to_sun.z.abs() < 0.9 { DVec3::Z } else { DVec3::X };
    (helper - helper.dot(to_sun) * to_sun).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief_core::MlhmColumn;

    const INF: f32 = f32::INFINITY;

    /// 8 x 8 cells of 1 m, flat at 2 m, the western half (x < 4) raised by `step`.
    fn stepped(step: f32) -> Mlhm {
        let mut map = Mlhm::new(8, 8, 1, 1.0).unwrap();
        for y in 0..8 {
            for x in 0..8 {
                let top = if x < 4 { 2.0 + step } else { 2.0 };
                map.set_cell(x, y, &[MlhmColumn::new(top, 0.0, 0.0, INF)]).unwrap();
            }
        }
        map
    }

    #[test]
    fn flat_faces_keep_their_normal_exactly() {
        let map = stepped(0.0);
        for x in [1.5, 3.0, 4.0, 4.37, 6.2] {
            let p = DVec3::new(x, 4.25, 2.0);
            assert_eq!(filtered_normal(&map, p, DVec3::Z, 0.6, false), DVec3::Z, "x = {x}");
        }
        // Far from the step, a stepped map's faces keep theirs too.
        let map = stepped(1.0);
        assert_eq!(
            filtered_normal(&map, DVec3::new(6.0, 4.0, 2.0), DVec3::Z, 0.5, false),
            DVec3::Z
        );
        assert_eq!(filtered_normal(&map, DVec3::new(6.0, 4.0, 2.0), DVec3::Z, 0.0, true), DVec3::Z);
    }

    #[test]
    fn a_thin_step_leans_the_normal_by_its_share_of_the_area() {
        // A 2 cm riser facing east at x = 4, seen from a footprint of 0.5 m.
        let map = stepped(0.02);
        let riser = filtered_normal(&map, DVec3::new(4.0, 4.0, 2.01), DVec3::X, 0.5, false);
        assert!(riser.z > 0.99 && riser.x > 0.0, "{riser}");
        let tread = filtered_normal(&map, DVec3::new(4.0, 4.0, 2.0), DVec3::Z, 0.5, true);
        assert!((tread - riser).length() < 0.03, "{tread} {riser}");
    }

    #[test]
    fn the_lit_share_fades_over_the_width() {
        assert_eq!(lit_share(1.0, |_| false), 1.0);
        assert_eq!(lit_share(1.0, |_| true), 0.0);
        assert_eq!(lit_share(0.0, |lift| lift == 0.0), 0.0);
        // Clear from a shift of 0.25 on: three quarters lit, to the bisection's resolution.
        let share = lit_share(1.0, |lift| lift < 0.25);
        assert!((share - 0.75).abs() <= 0.5f64.powi(VISIBILITY_BISECTIONS as i32), "{share}");
    }

    #[test]
    fn lifts_go_across_the_rays_and_off_the_surface() {
        let l = DVec3::new(-1.0, 1.0, 1.0).normalize();
        let m = lift_direction(DVec3::Z, l);
        assert!(m.dot(l).abs() < 1e-12 && m.z > 0.0);
        let m = lift_direction(l, l);
        assert!(m.dot(l).abs() < 1e-12 && (m.length() - 1.0).abs() < 1e-12);
    }
}
