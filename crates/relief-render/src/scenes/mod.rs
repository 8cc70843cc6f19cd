//! The scenes an input opens as, one kind of input a file.

pub mod height_field;
pub mod mlhm;
pub mod stacks;
pub mod store;
