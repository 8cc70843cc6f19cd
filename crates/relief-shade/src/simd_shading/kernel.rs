//! The lane arithmetic of the `f32` shading kernel: one image row's run of pixels, `N` at a
//! time, written once and compiled for every lane width.

use std::f32::consts::FRAC_1_PI;

use super::byte_lanes::ByteLanes;
use super::exp_approx::exp_non_positive;
use super::ramp_lanes::RampLanes;
use crate::colour_maps::MapTable;

/// Smallest cosine of the view angle the GGX lobe uses (as `shading.rs`).
const MIN_COS_VIEW: f32 = 1e-4;

/// Where the kernel's albedo comes from.
#[derive(Clone, Copy)]
pub(crate) enum LaneAlbedo {
    /// The same reflectance everywhere.
    Uniform([f32; 3]),
    /// The hypsometric ramp: elevation fraction `t = t_eye + (origin.z - eye.z) * t_per_unit
    /// + dir.z * distance * t_per_unit`.
    Ramp {
        /// The eye's elevation fraction.
        t_eye: f32,
        /// Elevation fraction per world unit of height.
        t_per_unit: f32,
        /// Whether steep slopes turn to rock.
        steep_rock: bool,
        /// The rock's linear colour.
        rock: [f32; 3],
        /// The ramp's table.
        table: &'static RampLanes,
    },
    /// A named colour map over heights: the height above the pivot `h = h_eye + (origin.z -
    /// eye.z) + dir.z * distance`, the map's position `u = pivot_u + h * (below if h < 0 else
    /// above)`.
    Mapped {
        /// The eye's height above the pivot.
        h_eye: f32,
        /// The position at the pivot.
        pivot_u: f32,
        /// Position per unit of height below the pivot.
        below: f32,
        /// Position per unit of height above it.
        above: f32,
        /// The map's table.
        table: &'static MapTable,
    },
    /// Each pixel's own linear RGB colour (the G-buffer's first three material weights),
    /// `fallback` where a row comes without colours.
    PerPixel {
        /// The albedo of a row shaded without colours.
        fallback: [f32; 3],
    },
}

/// The per-pass constants of the kernel, in `f32`.
#[derive(Clone)]
pub(crate) struct LaneConstants {
    /// Whether the camera is orthographic: rays along `forward` from `eye + sx right + sy up`
    /// (else from the eye through the pixel).
    pub orthographic: bool,
    /// The camera's unit viewing direction.
    pub forward: [f32; 3],
    /// The camera's unit right vector.
    pub right: [f32; 3],
    /// The camera's unit image-up vector.
    pub up: [f32; 3],
    /// Unit direction to the sun.
    pub to_sun: [f32; 3],
    /// The sun's irradiance.
    pub irradiance: f32,
    /// Sky radiance straight up.
    pub zenith: [f32; 3],
    /// Sky radiance at the horizon.
    pub horizon: [f32; 3],
    /// Ambient sky radiance.
    pub ambient: [f32; 3],
    /// The albedo.
    pub albedo: LaneAlbedo,
    /// The GGX lobe: `alpha^2` and F0, or `None`.
    pub specular: Option<(f32, f32)>,
    /// Fog density per world unit.
    pub fog_density: f32,
    /// Exposure.
    pub exposure: f32,
    /// The tone curve's byte steps.
    pub steps: &'static ByteLanes,
}

/// One run of up to `N` pixels of a row, structure of arrays.
pub(crate) struct Lanes<const N: usize> {
    /// Screen x of each pixel's column.
    pub sx: [f32; N],
    /// Distance to the hit (`+inf` for a miss).
    pub distance: [f32; N],
    /// The stored normal, by component.
    pub normal: [[f32; N]; 3],
    /// The sun's visibility (0 or 1).
    pub visibility: [f32; N],
    /// Each pixel's own albedo, by channel (zeros when the row has none).
    pub colour: [[f32; N]; 3],
}

impl<const N: usize> Lanes<N> {
    /// The first `N` pixels of the slices (each holds at least `N`), loaded whole so that the
    /// loads are vector loads.
    #[inline(always)]
    fn whole(row: &RowPixels, start: usize) -> Self {
        let first = |v: &[f32]| -> [f32; N] { v[start..start + N].try_into().expect("N values") };
        let normals: &[[f32; 3]; N] = row.normal[start..start + N].try_into().expect("N normals");
        let mut by_axis = [[0.0f32; N]; 3];
        for l in 0..N {
            by_axis[0][l] = normals[l][0];
            by_axis[1][l] = normals[l][1];
            by_axis[2][l] = normals[l][2];
        }
        let mut colour = [[0.0f32; N]; 3];
        if let Some(colours) = row.colour {
            let colours: &[[f32; 4]; N] = colours[start..start + N].try_into().expect("N colours");
            for l in 0..N {
                colour[0][l] = colours[l][0];
                colour[1][l] = colours[l][1];
                colour[2][l] = colours[l][2];
            }
        }
        Lanes {
            sx: first(row.sx),
            distance: first(row.distance),
            normal: by_axis,
            visibility: first(row.visibility),
            colour,
        }
    }

    /// The pixels of the row from `start` on (fewer than `N`), the other lanes misses.
    #[inline(always)]
    fn part(row: &RowPixels, start: usize) -> Self {
        let mut lanes = Lanes {
            sx: [0.0; N],
            distance: [f32::INFINITY; N],
            normal: [[0.0; N]; 3],
            visibility: [0.0; N],
            colour: [[0.0; N]; 3],
        };
        for l in 0..(row.sx.len() - start).min(N) {
            let k = start + l;
            lanes.sx[l] = row.sx[k];
            lanes.distance[l] = row.distance[k];
            for (axis, value) in lanes.normal.iter_mut().zip(row.normal[k]) {
                axis[l] = value;
            }
            lanes.visibility[l] = row.visibility[k];
            if let Some(colours) = row.colour {
                for (channel, value) in lanes.colour.iter_mut().zip(colours[k]) {
                    channel[l] = value;
                }
            }
        }
        lanes
    }
}

/// A run of pixels of one image row as the kernel reads them: the row's screen y, and one
/// entry a pixel of each slice (screen x, G-buffer distance and normal, the sun's visibility).
#[derive(Clone, Copy)]
pub(crate) struct RowPixels<'a> {
    /// [`relief_core::Camera::screen_y`] of the row.
    pub sy: f32,
    /// [`relief_core::Camera::screen_x`] of each pixel's column.
    pub sx: &'a [f32],
    /// Distance to the hit (`+inf` for a miss).
    pub distance: &'a [f32],
    /// The hit's normal.
    pub normal: &'a [[f32; 3]],
    /// The sun's visibility (0 or 1).
    pub visibility: &'a [f32],
    /// Each pixel's G-buffer material weights, the first three its linear RGB albedo, for
    /// [`LaneAlbedo::PerPixel`]; `None`: the fallback albedo.
    pub colour: Option<&'a [[f32; 4]]>,
}

/// Shades `row`, `N` pixels at a time, one byte triple a pixel into `out`.
#[inline(always)]
pub(crate) fn shade_row_lanes<const N: usize>(
    c: &LaneConstants,
    row: &RowPixels,
    out: &mut [[u8; 3]],
) {
    let sy = row.sy;
    let mut start = 0;
    while start < out.len() {
        let m = N.min(out.len() - start);
        let lanes =
            if m == N { Lanes::<N>::whole(row, start) } else { Lanes::<N>::part(row, start) };
        let radiance = radiance_lanes(c, sy, &lanes, row.colour.is_some());
        // No closures here (`array::map`): they would be compiled apart from the lane width's
        // target features.
        let (red, green, blue) =
            (c.steps.bytes(&radiance[0]), c.steps.bytes(&radiance[1]), c.steps.bytes(&radiance[2]));
        for (l, pixel) in out[start..start + m].iter_mut().enumerate() {
            *pixel = [red[l] as u8, green[l] as u8, blue[l] as u8];
        }
        start += m;
    }
}

/// The exposed linear radiance of `N` pixels, by channel.
#[inline(always)]
fn radiance_lanes<const N: usize>(
    c: &LaneConstants,
    sy: f32,
    p: &Lanes<N>,
    has_colours: bool,
) -> [[f32; N]; 3] {
    // The view ray, as `Camera::ray_through` makes it: normalize(forward + sx right + sy up)
    // (times the reciprocal of the length, as glam normalizes),
    // or `forward` for an orthographic camera.
    let mut dir = [[0.0f32; N]; 3];
    let mut unit_normal = [[0.0f32; N]; 3];
    let mut sky = [[0.0f32; N]; 3];
    for l in 0..N {
        let mut d = [0.0f32; 3];
        for (a, d) in d.iter_mut().enumerate() {
            *d = c.forward[a] + p.sx[l] * c.right[a] + sy * c.up[a];
        }
        let inverse_length = 1.0 / (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        for a in 0..3 {
            dir[a][l] = if c.orthographic { c.forward[a] } else { d[a] * inverse_length };
        }
        let n = [p.normal[0][l], p.normal[1][l], p.normal[2][l]];
        let squared = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
        let inverse = if squared > 0.0 { 1.0 / squared.sqrt() } else { 0.0 };
        for a in 0..3 {
            unit_normal[a][l] = n[a] * inverse;
        }
        let z = dir[2][l];
        let rise = if z > 0.0 { z.min(1.0).sqrt() } else { 0.0 };
        for (ch, sky) in sky.iter_mut().enumerate() {
            sky[l] = c.horizon[ch] + (c.zenith[ch] - c.horizon[ch]) * rise;
        }
    }
    let albedo = albedo_lanes(c, sy, p, &dir, &unit_normal, has_colours);
    let mut out = [[0.0f32; N]; 3];
    for l in 0..N {
        let n = [unit_normal[0][l], unit_normal[1][l], unit_normal[2][l]];
        let v = [-dir[0][l], -dir[1][l], -dir[2][l]];
        let n_l = n[0] * c.to_sun[0] + n[1] * c.to_sun[1] + n[2] * c.to_sun[2];
        let specular = match c.specular {
            Some((a2, f0)) => ggx(a2, f0, n, v, c.to_sun, n_l),
            None => 0.0,
        };
        let lit = n_l > 0.0 && p.visibility[l] > 0.0;
        let sun = if lit { c.irradiance * n_l * p.visibility[l] } else { 0.0 };
        let sky_light = 0.5 + 0.5 * n[2].clamp(-1.0, 1.0);
        let distance = p.distance[l];
        let transmittance = exp_non_positive(-c.fog_density * distance);
        let hit = distance < f32::INFINITY;
        for ch in 0..3 {
            let a = albedo[ch][l];
            let surface = (a * FRAC_1_PI + specular) * sun + a * c.ambient[ch] * sky_light;
            let fogged = surface * transmittance + sky[ch][l] * (1.0 - transmittance);
            out[ch][l] = (if hit { fogged } else { sky[ch][l] }) * c.exposure;
        }
    }
    out
}

/// The albedo of `N` pixels, by channel (`has_colours`: the lanes hold each pixel's own).
#[inline(always)]
fn albedo_lanes<const N: usize>(
    c: &LaneConstants,
    sy: f32,
    p: &Lanes<N>,
    dir: &[[f32; N]; 3],
    normal: &[[f32; N]; 3],
    has_colours: bool,
) -> [[f32; N]; 3] {
    match c.albedo {
        LaneAlbedo::Uniform(rgb) => [[rgb[0]; N], [rgb[1]; N], [rgb[2]; N]],
        LaneAlbedo::Ramp { t_eye, t_per_unit, steep_rock, rock, table } => {
            let mut t = [0.0f32; N];
            for l in 0..N {
                // The ray's origin above the eye: none for a pinhole.
                let rise = if c.orthographic { p.sx[l] * c.right[2] + sy * c.up[2] } else { 0.0 };
                t[l] = t_eye + rise * t_per_unit + dir[2][l] * (p.distance[l] * t_per_unit);
            }
            let mut albedo = table.colour_lanes(&t);
            if steep_rock {
                for l in 0..N {
                    // smoothstep(0.18, 0.5, 1 - n.z), as `HypsometricRamp::albedo` has it.
                    let steepness = 1.0 - normal[2][l].clamp(0.0, 1.0);
                    let s = ((steepness - 0.18) * (1.0 / (0.5 - 0.18))).clamp(0.0, 1.0);
                    let s = s * s * (3.0 - 2.0 * s);
                    for ch in 0..3 {
                        albedo[ch][l] = albedo[ch][l] * (1.0 - s) + rock[ch] * s;
                    }
                }
            }
            albedo
        }
        LaneAlbedo::Mapped { h_eye, pivot_u, below, above, table } => {
            let mut u = [0.0f32; N];
            for l in 0..N {
                let rise = if c.orthographic { p.sx[l] * c.right[2] + sy * c.up[2] } else { 0.0 };
                let h = h_eye + rise + dir[2][l] * p.distance[l];
                u[l] = pivot_u + h * if h < 0.0 { below } else { above };
            }
            table.colour_lanes(&u)
        }
        LaneAlbedo::PerPixel { .. } if has_colours => p.colour,
        LaneAlbedo::PerPixel { fallback } => [[fallback[0]; N], [fallback[1]; N], [fallback[2]; N]],
    }
}

/// `GgxSpecular::brdf` in `f32` for unit `n`, `v` (to the eye) and `l` (to the light), with
/// `n_l = n.l`; 0 when the light is behind the surface.
#[inline(always)]
fn ggx(a2: f32, f0: f32, n: [f32; 3], v: [f32; 3], l: [f32; 3], n_l: f32) -> f32 {
    let n_v_signed = n[0] * v[0] + n[1] * v[1] + n[2] * v[2];
    let n_v = n_v_signed.max(MIN_COS_VIEW);
    let v_l = v[0] * l[0] + v[1] * l[1] + v[2] * l[2];
    let sum_squared = 2.0 + 2.0 * v_l;
    let half_exists = sum_squared > 0.0;
    let n_h = (n_v_signed + n_l).max(0.0);
    let n_h2 = if half_exists { n_h * n_h / sum_squared } else { 0.0 };
    let v_h = if half_exists { (0.5 * sum_squared.max(0.0).sqrt()).clamp(0.0, 1.0) } else { 0.0 };
    let d_denom = n_h2 * (a2 - 1.0) + 1.0;
    let n_l_pos = n_l.max(0.0);
    let smith = n_l_pos * (n_v * n_v * (1.0 - a2) + a2).sqrt()
        + n_v * (n_l_pos * n_l_pos * (1.0 - a2) + a2).sqrt();
    let grazing = 1.0 - v_h;
    let grazing2 = grazing * grazing;
    let fresnel = f0 + (1.0 - f0) * (grazing2 * grazing2 * grazing);
    let value = a2 * fresnel / (2.0 * std::f32::consts::PI * d_denom * d_denom * smith);
    if n_l > 0.0 {
        value
    } else {
        0.0
    }
}
