//! Tracers that wrap or stand in for another: stopped by a flag ([`Interruptible`]), meeting
//! nothing ([`NoOccluders`]), or seen one ray at a time ([`OneRayAtATime`]).

mod interruptible;
mod no_occluders;
mod one_ray_at_a_time;

pub use interruptible::Interruptible;
pub use no_occluders::NoOccluders;
pub use one_ray_at_a_time::OneRayAtATime;
