//! How a walk through an MLHM hierarchy climbs back to coarser levels ([`MlhmBacktrack`]).

use std::fmt;
use std::str::FromStr;

/// How the hierarchical traversal climbs back to coarser levels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum MlhmBacktrack {
    /// A per-level array of the distances at which the ray leaves each node it descended
    /// from: after a step, climb while the step reached the parent's exit.
    #[default]
    ExitStack,
    /// A miss counter: climb one level after 8 missed nodes in a row (16 on level 0).
    MissCounter,
}

impl MlhmBacktrack {
    /// Both variants, in a fixed order.
    pub const ALL: [MlhmBacktrack; 2] = [MlhmBacktrack::ExitStack, MlhmBacktrack::MissCounter];

    /// The name used in reports and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            MlhmBacktrack::ExitStack => "stack",
            MlhmBacktrack::MissCounter => "miss",
        }
    }
}

impl fmt::Display for MlhmBacktrack {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(self.name())
    }
}

impl FromStr for MlhmBacktrack {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        MlhmBacktrack::ALL
            .into_iter()
            .find(|b| b.name() == s)
            .ok_or_else(|| format!("unknown backtracking '{s}' (expected stack or miss)"))
    }
}
