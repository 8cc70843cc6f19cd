//! Shared test support: an independent brute-force tracer and random terrains and rays.
#![allow(dead_code)]

pub mod hierarchy_checks;
pub mod mlhm_reference;
pub mod reference;
pub mod scenes;
