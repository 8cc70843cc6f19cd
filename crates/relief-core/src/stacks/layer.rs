//! One layer of a material stack ([`StackLayer`]).

/// One layer of a material stack: the material with index `material` from height `start` up to
/// height `end` (absolute, metres, `start < end`).
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C)]
pub struct StackLayer {
    /// Height of the layer's bottom.
    pub start: f32,
    /// Height of the layer's top.
    pub end: f32,
    /// Index of the layer's material in the stacks' palette.
    pub material: u8,
}

impl StackLayer {
    /// The layer of `material` from `start` to `end`.
    pub const fn new(start: f32, end: f32, material: u8) -> Self {
        StackLayer { start, end, material }
    }

    /// Thickness `end - start`.
    #[inline]
    pub fn thickness(&self) -> f32 {
        self.end - self.start
    }
}
