//! The `f32` shading kernel's public face: what it covers, and one row at a chosen width.

use relief_core::{Camera, Projection};

use super::byte_lanes::ByteLanes;
use super::kernel::{shade_row_lanes, LaneAlbedo, LaneConstants, RowPixels};
use super::lane_width::LaneWidth;
use super::ramp_lanes::RampLanes;
use crate::colour_ramp::rock_linear;
use crate::{Albedo, ShadeError, ShadingParams};

/// Smallest GGX roughness the kernel lights: below it the lobe's peak is too sharp for `f32`
/// to stay within one 8-bit step of the `f64` pass, which then shades instead.
pub const MIN_LANE_ROUGHNESS: f64 = 0.2;

/// The deferred shading of one camera's picture in `f32` lanes, for the parameters it covers:
/// a pinhole or orthographic camera, uniform, hypsometric, colour-mapped or per-pixel
/// ([`Albedo::GBufferColour`]) albedo, any sun and
/// sky, GGX of roughness at least [`MIN_LANE_ROUGHNESS`] or none, fog, exposure;
/// `ShadingParams::precise` off.
///
/// A pixel's bytes are within one 8-bit step per channel of the `f64` pass's
/// ([`crate::shade_to_srgb8`] with `precise`), and the same at every [`LaneWidth`].
#[derive(Clone)]
pub struct ShadingKernel {
    constants: LaneConstants,
    screen_x: Vec<f32>,
    screen_y: Vec<f32>,
    /// [`Camera::screen_x`] of every column, for the shadow rays made in `f64`.
    pub(crate) screen_x_f64: Vec<f64>,
    /// [`Camera::screen_y`] of every row.
    pub(crate) screen_y_f64: Vec<f64>,
    width: LaneWidth,
}

impl ShadingKernel {
    /// The kernel for `camera`'s picture shaded with `params` (which must be valid), at the
    /// width [`LaneWidth::detect`] picks; `None` where the kernel does not cover the
    /// parameters (see [`ShadingKernel`]), which the `f64` pass then shades.
    pub fn new(camera: &Camera, params: &ShadingParams) -> Option<ShadingKernel> {
        if params.precise {
            return None;
        }
        if params.specular.is_some_and(|s| s.roughness < MIN_LANE_ROUGHNESS) {
            return None;
        }
        let albedo = match &params.albedo {
            Albedo::Uniform(rgb) => LaneAlbedo::Uniform(*rgb),
            Albedo::Hypsometric(ramp) => {
                let extent = ramp.max_z - ramp.min_z;
                let (t_eye, t_per_unit) = if extent > 0.0 {
                    ((camera.eye().z - ramp.min_z) / extent, 1.0 / extent)
                } else {
                    (0.0, 0.0)
                };
                LaneAlbedo::Ramp {
                    t_eye: t_eye as f32,
                    t_per_unit: t_per_unit as f32,
                    steep_rock: ramp.steep_rock,
                    rock: rock_linear().as_vec3().to_array(),
                    table: RampLanes::get(),
                }
            }
            Albedo::Mapped(map) => {
                let pieces = map.pieces();
                LaneAlbedo::Mapped {
                    h_eye: (camera.eye().z - pieces.pivot_z) as f32,
                    pivot_u: pieces.pivot_u as f32,
                    below: pieces.below as f32,
                    above: pieces.above as f32,
                    table: map.map.table(),
                }
            }
            Albedo::GBufferColour { fallback } => LaneAlbedo::PerPixel { fallback: *fallback },
            _ => return None,
        };
        let lights = params.sun.is_up() && params.sun.irradiance > 0.0;
        let constants = LaneConstants {
            orthographic: matches!(camera.projection(), Projection::Orthographic { .. }),
            forward: camera.forward().as_vec3().to_array(),
            right: camera.right().as_vec3().to_array(),
            up: camera.image_up().as_vec3().to_array(),
            to_sun: params.sun.direction().as_vec3().to_array(),
            irradiance: if lights { params.sun.irradiance as f32 } else { 0.0 },
            zenith: params.sky.zenith,
            horizon: params.sky.horizon,
            ambient: params.sky.ambient,
            albedo,
            specular: params.specular.map(|s| {
                let alpha = (s.roughness * s.roughness).max(1e-3);
                ((alpha * alpha) as f32, s.f0 as f32)
            }),
            fog_density: params.fog_density as f32,
            exposure: params.exposure as f32,
            steps: ByteLanes::tone_curve(),
        };
        let screen_x_f64: Vec<f64> = (0..camera.width()).map(|i| camera.screen_x(i)).collect();
        let screen_y_f64: Vec<f64> = (0..camera.height()).map(|j| camera.screen_y(j)).collect();
        Some(ShadingKernel {
            constants,
            screen_x: screen_x_f64.iter().map(|&x| x as f32).collect(),
            screen_y: screen_y_f64.iter().map(|&y| y as f32).collect(),
            screen_x_f64,
            screen_y_f64,
            width: LaneWidth::detect(),
        })
    }

    /// The same kernel at lane width `width`; fails when this processor does not run it.
    pub fn with_width(self, width: LaneWidth) -> Result<ShadingKernel, ShadeError> {
        if !width.is_available() {
            return Err(ShadeError::parameter(
                "shading lane width",
                format!("this processor does not run {}", width.name()),
            ));
        }
        Ok(ShadingKernel { width, ..self })
    }

    /// The lane width the kernel runs at.
    pub fn width(&self) -> LaneWidth {
        self.width
    }

    /// Shades the pixels of image row `row` from column `first_column` on into `out`, one per
    /// entry: each pixel's G-buffer `distance` (`+inf` for a miss) and `normal`, and the sun's
    /// `visibility` (0 or 1; 0 where the `f64` pass finds the surface facing away from the
    /// sun, as it does not trace a shadow ray there).
    ///
    /// Panics when the slices differ in length or the pixels lie outside the picture.
    pub fn shade_row(
        &self,
        row: usize,
        first_column: usize,
        distance: &[f32],
        normal: &[[f32; 3]],
        visibility: &[f32],
        out: &mut [[u8; 3]],
    ) {
        let n = out.len();
        assert!(
            distance.len() == n && normal.len() == n && visibility.len() == n,
            "one distance, normal and visibility per pixel"
        );
        let sx = &self.screen_x[first_column..first_column + n];
        let pixels =
            RowPixels { sy: self.screen_y[row], sx, distance, normal, visibility, colour: None };
        self.shade_pixels(&pixels, out);
    }

    /// The pixels of image row `row` from column `first_column` on, as [`RowPixels`] holds
    /// them, with each pixel's G-buffer material weights in `colour` (read when the albedo is
    /// [`Albedo::GBufferColour`]).
    pub(crate) fn row_pixels<'a>(
        &'a self,
        row: usize,
        first_column: usize,
        (distance, normal): (&'a [f32], &'a [[f32; 3]]),
        colour: Option<&'a [[f32; 4]]>,
        visibility: &'a [f32],
    ) -> RowPixels<'a> {
        let sx = &self.screen_x[first_column..first_column + distance.len()];
        RowPixels { sy: self.screen_y[row], sx, distance, normal, visibility, colour }
    }

    /// Shades `pixels` into `out`, one per entry.
    ///
    /// Panics when the slices differ in length.
    #[allow(unsafe_code)]
    pub(crate) fn shade_pixels(&self, pixels: &RowPixels, out: &mut [[u8; 3]]) {
        let n = out.len();
        assert!(
            pixels.sx.len() == n
                && pixels.distance.len() == n
                && pixels.normal.len() == n
                && pixels.visibility.len() == n
                && pixels.colour.is_none_or(|c| c.len() == n),
            "one distance, normal, visibility and colour per pixel"
        );
        let c = &self.constants;
        match self.width {
            LaneWidth::Portable => shade_row_portable(c, pixels, out),
            #[cfg(target_arch = "x86_64")]
            // SAFETY: a kernel holds a width only once `is_available` found it on this
            // processor (`detect` and `with_width` check it).
            LaneWidth::Avx2 => unsafe { shade_row_avx2(c, pixels, out) },
            #[cfg(target_arch = "x86_64")]
            // SAFETY: as above.
            LaneWidth::Avx512 => unsafe { shade_row_avx512(c, pixels, out) },
            #[cfg(not(target_arch = "x86_64"))]
            LaneWidth::Avx2 | LaneWidth::Avx512 => shade_row_portable(c, pixels, out),
        }
    }
}

/// The kernel, 8 lanes, compiled for the baseline processor.
fn shade_row_portable(c: &LaneConstants, pixels: &RowPixels, out: &mut [[u8; 3]]) {
    shade_row_lanes::<8>(c, pixels, out)
}

/// The kernel, 8 lanes, compiled for AVX2 and FMA (no multiply-add is fused: Rust never
/// contracts one).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn shade_row_avx2(c: &LaneConstants, pixels: &RowPixels, out: &mut [[u8; 3]]) {
    shade_row_lanes::<8>(c, pixels, out)
}

/// The kernel, 16 lanes, compiled for AVX-512.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512vl,avx512dq,avx512bw,avx2,fma")]
fn shade_row_avx512(c: &LaneConstants, pixels: &RowPixels, out: &mut [[u8; 3]]) {
    shade_row_lanes::<16>(c, pixels, out)
}
