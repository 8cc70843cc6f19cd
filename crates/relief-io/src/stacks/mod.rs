//! relief's own `.stacks` files of material stacks ([`relief_core::MaterialStacks`]): a
//! little-endian binary read by [`read_stacks`] and written by [`write_stacks`].

pub(crate) mod native;

pub use native::{
    has_stacks_magic, is_stacks_path, read_stacks, stacks_from_bytes, stacks_to_bytes,
    write_stacks, STACKS_EXTENSION, STACKS_MAGIC, STACKS_VERSION,
};
