//! The simulated terrain: an MLHM's columns and the simulator's per-column planes, layer-major
//! as the reference saves them, with conversions from and to [`Mlhm`].

use super::ErosionError;
use relief_core::{Mlhm, MlhmColumn};

/// Stability of a column standing on the ground (the lowest column of a cell), as the
/// reference's `FLT_MAX`.
pub const GROUND_STABILITY: f32 = f32::MAX;

/// The simulator's per-column planes, one value per column slot in layer-major order
/// (index `x + y * width + k * width * height`), as the reference scene format stores them.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SimulationPlanes {
    /// Outflow of the virtual pipes, m³/s: right (+x), up (+y), left, down.
    pub fluxes: Vec<[f32; 4]>,
    /// Stability of the support check, kg of weight the column could still carry.
    pub stability: Vec<f32>,
    /// Suspended sediment, m (volume over the cell area).
    pub sediment: Vec<f32>,
    /// Horizontal-erosion damage, m: bedrock already turned into sand beside the column
    /// and not yet removed from it.
    pub damage: Vec<f32>,
}

impl SimulationPlanes {
    /// All zeros for `slots` column slots: the state of a terrain not yet simulated.
    pub fn zeros(slots: usize) -> Self {
        SimulationPlanes {
            fluxes: vec![[0.0; 4]; slots],
            stability: vec![0.0; slots],
            sediment: vec![0.0; slots],
            damage: vec![0.0; slots],
        }
    }
}

/// Per-slot values one step computes and later kernels of the same step read.
#[derive(Debug, Clone, Default)]
pub(crate) struct Scratch {
    /// Layer of the neighbour column each pipe leads to (-1: none), per direction.
    pub pipes: Vec<[i8; 4]>,
    /// Sand slipping out through each pipe, m.
    pub slippage: Vec<[f32; 4]>,
    /// Fraction of the sediment that moves with the water's outflow.
    pub sediment_flux_scale: Vec<f32>,
    /// sin of the terrain slope.
    pub slopes: Vec<f32>,
    /// Water velocity, m/s (x, y).
    pub velocities: Vec<[f32; 2]>,
    /// Bedrock window exposed to the strongest horizontal erosion: (bottom, top), m.
    pub splits: Vec<[f32; 2]>,
    /// Sand eroded into the neighbour column in each direction, m.
    pub erosions: Vec<[f32; 4]>,
    /// Layer of the neighbour column receiving each erosion (-1: none).
    pub erosion_targets: Vec<[i8; 4]>,
    /// Per row, whether a cell of it has more than one column (the support check's rows).
    pub layered_rows: Vec<bool>,
    /// Per row, whether horizontal erosion's records (`splits`, `erosions`,
    /// `erosion_targets`) of its cells may differ from the defaults (no window, no erosion);
    /// empty for a new state, whose records are all written by the first step.
    pub eroded_rows: Vec<bool>,
    /// Whether the kernels take their one-column paths where the terrain allows (always,
    /// but in the tests that compare them with the general paths).
    pub fast_paths: bool,
}

impl Scratch {
    fn new(slots: usize) -> Self {
        Scratch {
            pipes: vec![[-1; 4]; slots],
            slippage: vec![[0.0; 4]; slots],
            sediment_flux_scale: vec![0.0; slots],
            slopes: vec![0.0; slots],
            velocities: vec![[0.0; 2]; slots],
            splits: vec![[0.0; 2]; slots],
            erosions: vec![[0.0; 4]; slots],
            erosion_targets: vec![[-1; 4]; slots],
            layered_rows: Vec::new(),
            eroded_rows: Vec::new(),
            fast_paths: true,
        }
    }
}

/// The layered terrain under simulation: `width x height` cells of `cell_size` metres, each
/// with 1 to `max_layers` columns, and the simulator's planes ([`SimulationPlanes`]), all
/// layer-major. `step` counts the steps simulated so far: rain's random numbers and the
/// support check's cycle depend on it, so a run resumed from a saved state with its step
/// count continues exactly as an unbroken one.
#[derive(Debug, Clone)]
pub struct ErosionState {
    pub(crate) width: usize,
    pub(crate) height: usize,
    pub(crate) max_layers: usize,
    pub(crate) cell_size: f32,
    pub(crate) step: u64,
    pub(crate) layer_counts: Vec<u8>,
    pub(crate) columns: Vec<MlhmColumn>,
    pub(crate) fluxes: Vec<[f32; 4]>,
    pub(crate) stability: Vec<f32>,
    pub(crate) sediment: Vec<f32>,
    pub(crate) damage: Vec<f32>,
    pub(crate) scratch: Scratch,
}

impl PartialEq for ErosionState {
    /// Equal terrain, planes and step count (the per-step scratch is not compared).
    fn eq(&self, other: &Self) -> bool {
        self.width == other.width
            && self.height == other.height
            && self.max_layers == other.max_layers
            && self.cell_size == other.cell_size
            && self.step == other.step
            && self.layer_counts == other.layer_counts
            && self.columns == other.columns
            && self.fluxes == other.fluxes
            && self.stability == other.stability
            && self.sediment == other.sediment
            && self.damage == other.damage
    }
}

impl ErosionState {
    /// The state of `mlhm` with room for `max_layers` columns per cell (at least the map's
    /// own layer planes), the saved `planes` (one value per slot of `mlhm`, zeros when
    /// `None`) and `step` steps simulated so far. Negative fluxes, sediment and damage (as
    /// f32 rounding leaves them in the reference's scenes) are taken as 0, and every cell's
    /// lowest column stands on the ground ([`GROUND_STABILITY`]).
    ///
    /// Errors: a plane of the wrong length, a flux, sediment or damage that is not finite or a
    /// NaN stability (naming cell and column); `max_layers` above 255.
    pub fn from_mlhm(
        mlhm: &Mlhm,
        planes: Option<&SimulationPlanes>,
        max_layers: usize,
        step: u64,
    ) -> Result<Self, ErosionError> {
        let (width, height) = (mlhm.width(), mlhm.height());
        let cells = width * height;
        let src_layers = mlhm.max_layers();
        let max_layers = max_layers.max(src_layers);
        if max_layers > 255 {
            return Err(ErosionError::Parameter {
                name: "max_layers",
                reason: format!("{max_layers} is outside 1..=255"),
            });
        }
        let cell_size = mlhm.cell_size() as f32;
        if !(cell_size.is_finite() && cell_size > 0.0) {
            return Err(ErosionError::Parameter {
                name: "cell_size",
                reason: format!("{} is not a finite f32 > 0", mlhm.cell_size()),
            });
        }
        let src_slots = mlhm.raw_columns().len();
        if let Some(p) = planes {
            check_planes(p, src_slots, width, height)?;
        }
        let slots = cells * max_layers;
        let mut state = ErosionState {
            width,
            height,
            max_layers,
            cell_size,
            step,
            layer_counts: mlhm.layer_counts().to_vec(),
            columns: vec![MlhmColumn::default(); slots],
            fluxes: vec![[0.0; 4]; slots],
            stability: vec![0.0; slots],
            sediment: vec![0.0; slots],
            damage: vec![0.0; slots],
            scratch: Scratch::new(slots),
        };
        for i in 0..cells {
            // A cell's lowest column stands on the ground whatever was saved.
            state.stability[i] = GROUND_STABILITY;
            for k in 1..usize::from(mlhm.layer_counts()[i]) {
                if let Some(p) = planes {
                    state.stability[i + k * cells] = p.stability[i + k * cells];
                }
            }
            for k in 0..usize::from(mlhm.layer_counts()[i]) {
                let s = i + k * cells;
                state.columns[s] = mlhm.raw_columns()[s];
                if let Some(p) = planes {
                    // The reference's f32 arithmetic leaves values a few ulps below zero.
                    state.fluxes[s] = p.fluxes[s].map(|f| f.max(0.0));
                    state.sediment[s] = p.sediment[s].max(0.0);
                    state.damage[s] = p.damage[s].max(0.0);
                }
            }
        }
        Ok(state)
    }

    /// A height field as the one-column case: bedrock `heights[x + y * width]`, `sand` metres
    /// of sand on every cell, no water, room for `max_layers` columns per cell.
    ///
    /// Errors: an empty grid, a height count other than `width * height`, a non-finite
    /// height, a negative or non-finite sand, a bad cell size or layer count.
    pub fn from_heights(
        width: usize,
        height: usize,
        cell_size: f64,
        heights: &[f32],
        sand: f32,
        max_layers: usize,
    ) -> Result<Self, ErosionError> {
        let mut map = Mlhm::new(width, height, max_layers.max(1), cell_size)?;
        if heights.len() != width * height {
            return Err(ErosionError::PlaneLength {
                plane: "heights",
                found: heights.len(),
                expected: width * height,
            });
        }
        for (i, &h) in heights.iter().enumerate() {
            map.set_cell(i % width, i / width, &[MlhmColumn::new(h, sand, 0.0, f32::INFINITY)])?;
        }
        Self::from_mlhm(&map, None, max_layers, 0)
    }

    /// Cells along x.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Cells along y.
    pub fn height(&self) -> usize {
        self.height
    }

    /// Room for columns per cell (the number of layer planes).
    pub fn max_layers(&self) -> usize {
        self.max_layers
    }

    /// Horizontal size of a cell, metres.
    pub fn cell_size(&self) -> f32 {
        self.cell_size
    }

    /// Steps simulated so far.
    pub fn step_count(&self) -> u64 {
        self.step
    }

    /// Number of columns of each cell, index `x + y * width`.
    pub fn layer_counts(&self) -> &[u8] {
        &self.layer_counts
    }

    /// All column slots, layer-major; slots above a cell's layer count are zero.
    pub fn columns(&self) -> &[MlhmColumn] {
        &self.columns
    }

    /// The column at slot `x + y * width + k * width * height`, if cell `(x, y)` has a column
    /// `k`.
    pub fn column(&self, x: usize, y: usize, k: usize) -> Option<MlhmColumn> {
        if x >= self.width
            || y >= self.height
            || k >= usize::from(self.layer_counts[x + y * self.width])
        {
            return None;
        }
        Some(self.columns[x + y * self.width + k * self.width * self.height])
    }

    /// Suspended sediment per slot, m.
    pub fn sediment(&self) -> &[f32] {
        &self.sediment
    }

    /// Damage per slot, m.
    pub fn damage(&self) -> &[f32] {
        &self.damage
    }

    /// Stability per slot.
    pub fn stability(&self) -> &[f32] {
        &self.stability
    }

    /// Pipe outflow per slot, m³/s (right, up, left, down).
    pub fn fluxes(&self) -> &[[f32; 4]] {
        &self.fluxes
    }

    /// The terrain as an [`Mlhm`] of `max_layers` layer planes (checked by
    /// [`Mlhm::validate`]).
    pub fn to_mlhm(&self) -> Result<Mlhm, ErosionError> {
        self.to_mlhm_with_layers(self.max_layers)
    }

    /// The simulator's planes, one value per slot of [`ErosionState::to_mlhm`]'s map.
    pub fn planes(&self) -> SimulationPlanes {
        self.planes_with_layers(self.max_layers)
    }

    /// The largest number of columns any cell holds.
    pub fn used_layers(&self) -> usize {
        self.layer_counts.iter().map(|&n| usize::from(n)).max().unwrap_or(1)
    }

    /// The terrain as an [`Mlhm`] of `layers` layer planes, at least
    /// [`ErosionState::used_layers`] (else an error naming `layers`).
    pub fn to_mlhm_with_layers(&self, layers: usize) -> Result<Mlhm, ErosionError> {
        let slots = self.check_layers(layers)?;
        Ok(Mlhm::from_parts(
            self.width,
            self.height,
            layers,
            f64::from(self.cell_size),
            self.layer_counts.clone(),
            (0..slots).map(|s| self.slot(&self.columns, s)).collect(),
        )?)
    }

    /// The simulator's planes for `layers` layer planes (as [`ErosionState::to_mlhm_with_layers`]);
    /// slots beyond the state's own planes are zero.
    pub fn planes_with_layers(&self, layers: usize) -> SimulationPlanes {
        let slots = self.cells() * layers;
        SimulationPlanes {
            fluxes: (0..slots).map(|s| self.slot(&self.fluxes, s)).collect(),
            stability: (0..slots).map(|s| self.slot(&self.stability, s)).collect(),
            sediment: (0..slots).map(|s| self.slot(&self.sediment, s)).collect(),
            damage: (0..slots).map(|s| self.slot(&self.damage, s)).collect(),
        }
    }

    /// The value at slot `s` of `plane`, the default beyond it.
    fn slot<T: Copy + Default>(&self, plane: &[T], s: usize) -> T {
        plane.get(s).copied().unwrap_or_default()
    }

    /// Checks that `layers` planes hold every cell's columns; returns their slot count.
    fn check_layers(&self, layers: usize) -> Result<usize, ErosionError> {
        let used = self.used_layers();
        if layers < used || layers > 255 {
            return Err(ErosionError::Parameter {
                name: "layers",
                reason: format!("{layers} planes cannot hold cells of up to {used} columns"),
            });
        }
        Ok(self.cells() * layers)
    }

    /// Number of cells.
    pub(crate) fn cells(&self) -> usize {
        self.width * self.height
    }
}

/// Checks the planes' lengths and values.
fn check_planes(
    p: &SimulationPlanes,
    slots: usize,
    width: usize,
    height: usize,
) -> Result<(), ErosionError> {
    let lengths = [
        ("fluxes", p.fluxes.len()),
        ("stability", p.stability.len()),
        ("sediment", p.sediment.len()),
        ("damage", p.damage.len()),
    ];
    for (plane, found) in lengths {
        if found != slots {
            return Err(ErosionError::PlaneLength { plane, found, expected: slots });
        }
    }
    let cells = width * height;
    let at = |plane, s: usize, value, reason| ErosionError::PlaneValue {
        plane,
        x: s % cells % width,
        y: s % cells / width,
        column: s / cells,
        value,
        reason,
    };
    for s in 0..slots {
        for &f in &p.fluxes[s] {
            if !f.is_finite() {
                return Err(at("flux", s, f, "not a finite number"));
            }
        }
        for (plane, v) in [("sediment", p.sediment[s]), ("damage", p.damage[s])] {
            if !v.is_finite() {
                return Err(at(plane, s, v, "not a finite number"));
            }
        }
        if p.stability[s].is_nan() {
            return Err(at("stability", s, p.stability[s], "not a number"));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_keeps_terrain_and_planes() {
        let mut map = Mlhm::new(2, 1, 2, 1.0).unwrap();
        map.set_cell(
            1,
            0,
            &[MlhmColumn::new(1.0, 0.5, 0.0, 3.0), MlhmColumn::new(5.0, 0.0, 1.0, f32::INFINITY)],
        )
        .unwrap();
        let mut planes = SimulationPlanes::zeros(4);
        planes.sediment[1] = 0.25;
        planes.damage[3] = 0.5;
        let state = ErosionState::from_mlhm(&map, Some(&planes), 2, 7).unwrap();
        assert_eq!(state.to_mlhm().unwrap(), map);
        planes.stability[0] = GROUND_STABILITY;
        planes.stability[1] = GROUND_STABILITY;
        assert_eq!(state.planes(), planes);
        assert_eq!(state.step_count(), 7);
    }

    #[test]
    fn output_planes_hold_the_used_layers() {
        let mut map = Mlhm::new(2, 1, 2, 1.0).unwrap();
        map.set_cell(
            1,
            0,
            &[MlhmColumn::new(1.0, 0.5, 0.0, 3.0), MlhmColumn::new(5.0, 0.0, 1.0, f32::INFINITY)],
        )
        .unwrap();
        let state = ErosionState::from_mlhm(&map, None, 8, 0).unwrap();
        assert_eq!((state.max_layers(), state.used_layers()), (8, 2));
        assert_eq!(state.to_mlhm_with_layers(2).unwrap(), map);
        assert_eq!(state.planes_with_layers(3).damage.len(), 6);
        assert!(matches!(
            state.to_mlhm_with_layers(1),
            Err(ErosionError::Parameter { name: "layers", .. })
        ));
    }

    #[test]
    fn bad_planes_are_refused_with_their_cell() {
        let map = Mlhm::new(2, 2, 1, 1.0).unwrap();
        let short = SimulationPlanes::zeros(3);
        assert!(matches!(
            ErosionState::from_mlhm(&map, Some(&short), 1, 0),
            Err(ErosionError::PlaneLength { plane: "fluxes", found: 3, expected: 4 })
        ));
        let mut bad = SimulationPlanes::zeros(4);
        bad.sediment[3] = f32::INFINITY;
        let e = ErosionState::from_mlhm(&map, Some(&bad), 1, 0).unwrap_err();
        assert!(matches!(e, ErosionError::PlaneValue { plane: "sediment", x: 1, y: 1, .. }), "{e}");
    }

    #[test]
    fn height_field_is_one_column_per_cell() {
        let s = ErosionState::from_heights(2, 2, 0.5, &[1.0, 2.0, 3.0, 4.0], 0.5, 4).unwrap();
        assert_eq!(s.max_layers(), 4);
        assert_eq!(s.column(1, 1, 0), Some(MlhmColumn::new(4.0, 0.5, 0.0, f32::INFINITY)));
        assert_eq!(s.column(1, 1, 1), None);
        assert!(ErosionState::from_heights(2, 2, 0.5, &[1.0], 0.0, 1).is_err());
    }
}
