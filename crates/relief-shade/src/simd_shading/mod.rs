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
//! Where the picture moves: only where a channel's exposed radiance lies within the `f32`
//! arithmetic's rounding of one of the tone curve's 255 byte steps, since the
//! byte table (`byte_lanes.rs`) is the `f64` pass's own, step for step. On the default
//! 1920x1080 render of a 4096^2 fBm terrain 34 of 6,220,800 channels move by one step (33
//! without shadows; 14 of 2,764,800 at 1280x720), none by more; the tests' random scenes
//! (365,067 channels) move none, and the golden pictures of relief-cli do not move at all.
//!
//! Cost (one thread, 1920x1080, no shadows, `cargo bench -p relief-bench --bench
//! shading_lanes`, medians of 7 alternating rounds): the `f64` pass 99-182 ms a frame by view,
//! the kernel 29-30 ms with AVX-512, 45-49 ms with AVX2 and 65-89 ms portable. A profile puts
//! the kernel's time over its gathers (ramp samples and byte steps), divisions and square
//! roots; the shadow rays' set-up in `f64` stays as it was.

mod byte_lanes;
mod exp_approx;
mod kernel;
mod lane_width;
mod ramp_lanes;
mod shading_kernel;
mod strip;

pub use lane_width::{LaneWidth, LANE_WIDTH_VARIABLE};
pub use shading_kernel::{ShadingKernel, MIN_LANE_ROUGHNESS};
pub(crate) use strip::shade_strip_in_lanes;
