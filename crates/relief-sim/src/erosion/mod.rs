//! The layered hydraulic erosion simulation of the reference MLHM simulator, on the CPU:
//! parallel (rayon) and deterministic, for MLHMs, a height field being the one-column case.
//!
//! One [`ErosionState::step`] runs, in the reference's order: rain (`rain.rs`), virtual pipes
//! with sand slippage (`pipes.rs`), transport (`transport.rs`: water, evaporation, velocity,
//! sediment, petrification), horizontal erosion (`horizontal_erosion.rs`) with column splits
//! (`column_split.rs`), vertical erosion and deposition (`vertical_erosion.rs`), and the
//! support check with collapse (`support.rs`). The domain's edges are walls: no water, sand or
//! sediment leaves the grid.
//!
//! Material is created or removed by design only where [`StepVolumes`] says: horizontal erosion
//! turns bedrock into sand beside it at once and removes the bedrock later (damage recovery or
//! a split, whose gap is partly filled with sand); a collapsing column drops the bedrock its
//! damage still owes; f32 rounding clamps are counted too. Water changes only by rain,
//! evaporation and rounding clamps.
//!
//! Where this differs from the reference: each pipe into a column under a ceiling carries at
//! most a quarter of its free space (the reference deletes the overflow), a direction with no
//! pipe has no flux (the reference keeps a stale flux whose water vanishes), horizontal
//! erosion is gathered instead of added with atomics and limited by the receiver's free space,
//! walls support in the support check, and dry columns do not erode.

mod column_split;
mod error;
mod horizontal_erosion;
mod invariants;
mod lanes;
mod one_column;
mod params;
mod pipes;
mod rain;
mod random;
mod slots;
mod state;
mod step;
mod support;
mod transport;
mod vertical_erosion;
mod volumes;

pub use error::ErosionError;
pub use invariants::Stage;
pub use params::ErosionParams;
pub use random::uniform;
pub use state::{ErosionState, SimulationPlanes, GROUND_STABILITY};
pub use support::{end_support_check, start_support_check, support_pass};
pub use volumes::{StepVolumes, TerrainTotals};
