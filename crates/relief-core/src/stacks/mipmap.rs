//! The LOD mipmap of material stacks (to be written).

use super::MaterialStacks;

/// The LOD mipmap of a stacks terrain: level 0 the stacks themselves, each further level
/// aggregated from the one below by the material heuristic of Löffler et al. (section 3.1).
#[derive(Debug, Clone)]
pub struct StacksMipmap {
    levels: Vec<MaterialStacks>,
}

impl StacksMipmap {
    /// The levels, finest first.
    pub fn levels(&self) -> &[MaterialStacks] {
        &self.levels
    }
}
