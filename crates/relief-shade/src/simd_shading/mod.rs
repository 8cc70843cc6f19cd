//! Deferred shading in `f32` lanes: 8 pixels at a time with AVX2, 16 with AVX-512, and a
//! portable path of the same arithmetic that gives the same bytes.
//!
//! The kernel ([`ShadingKernel`]) lights a run of G-buffer pixels of one image row as the
//! `f64` pass of `deferred.rs` does (view ray from the camera, ramp or uniform albedo, sun with
//! the GGX lobe, sky light, fog, exposure, ACES and the sRGB byte table), in structure-of-arrays
//! `f32` lanes. Every lane width runs the same operations in the same order (Rust never fuses
//! a multiply and an add on its own, and the one exponential is a polynomial of this module's),
//! so the widths differ only in speed. The picture stays within one 8-bit step per channel of
//! the `f64` one; `ShadingParams::precise` keeps the `f64` pass.
//!
//! Shadow rays are still traced per tile in `f64` from the same points as before (`strip.rs`),
//! so shadows are the same; only the arithmetic of lighting moves to `f32`.

mod byte_lanes;
mod exp_approx;
mod kernel;
mod lane_width;
mod ramp_lanes;
mod shading_kernel;
mod strip;

pub use lane_width::LaneWidth;
pub use shading_kernel::ShadingKernel;
pub(crate) use strip::shade_strip_in_lanes;
