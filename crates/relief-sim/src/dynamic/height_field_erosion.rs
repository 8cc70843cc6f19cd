//! Hydraulic erosion of a height field: relief's layered erosion ([`ErosionState`]) on one
//! column per cell, its surface written back into the field after every step.

use crate::erosion::{ErosionParams, ErosionState, StepVolumes};
use crate::SimError;
use rayon::prelude::*;
use relief_core::HeightField;

/// The erosion of a height field: the field's samples become the bedrock of a one-column
/// [`ErosionState`] (`ErosionState::from_heights`, no sand, no water), and every
/// [`HeightFieldErosion::step`] runs one step of the layered simulation (rain, virtual pipes,
/// transport, erosion and deposition) and writes the surface, bedrock + sand, back into every
/// sample with [`HeightField::replace_samples`]. Water is simulated but not drawn.
///
/// The state keeps one column per cell, so the erosion never splits columns (no overhangs):
/// the surface is always that column's top. Heights are world heights in the simulation
/// (samples times the z scale) and samples in the field.
///
/// ```
/// use relief_core::{GridGeometry, HeightField};
/// use relief_sim::erosion::ErosionParams;
/// use relief_sim::HeightFieldErosion;
/// let samples: Vec<f32> = (0..32 * 32).map(|i| ((i % 32) as f32 * 0.3).sin() * 4.0).collect();
/// let mut field = HeightField::new(32, 32, samples, GridGeometry::unit()).unwrap();
/// let mut erosion = HeightFieldErosion::new(&field, ErosionParams::default()).unwrap();
/// for _ in 0..5 {
///     erosion.step(&mut field).unwrap();
/// }
/// assert_eq!(erosion.state().step_count(), 5);
/// ```
#[derive(Debug, Clone)]
pub struct HeightFieldErosion {
    state: ErosionState,
    params: ErosionParams,
    seed: u64,
    z_scale: f64,
    /// The buffer the next field is written into (the field's previous samples).
    spare: Vec<f32>,
}

impl HeightFieldErosion {
    /// The erosion of `field` with `params`, rain seeded by 1 (see
    /// [`HeightFieldErosion::with_seed`]).
    ///
    /// Errors: parameters the erosion refuses; a field whose texels are not square (the
    /// simulation's cells are) or that has holes ([`SimError::Mismatch`]); heights that are
    /// not finite in world units.
    pub fn new(field: &HeightField, params: ErosionParams) -> Result<Self, SimError> {
        params.validate()?;
        let g = field.geometry();
        if g.dx != g.dy {
            return Err(SimError::Mismatch(format!(
                "the erosion's cells are square; the field's texels are {} x {}",
                g.dx, g.dy
            )));
        }
        if field.hole_count() > 0 {
            return Err(SimError::Mismatch(format!(
                "the erosion needs a field without holes; this one has {}",
                field.hole_count()
            )));
        }
        let heights: Vec<f32> =
            field.samples().iter().map(|&v| (f64::from(v) * g.z_scale) as f32).collect();
        let state =
            ErosionState::from_heights(field.width(), field.height(), g.dx, &heights, 0.0, 1)?;
        Ok(HeightFieldErosion {
            state,
            params,
            seed: 1,
            z_scale: g.z_scale,
            spare: vec![0.0; field.samples().len()],
        })
    }

    /// The same erosion with rain seeded by `seed`.
    pub fn with_seed(mut self, seed: u64) -> Self {
        self.seed = seed;
        self
    }

    /// The layered state under simulation.
    pub fn state(&self) -> &ErosionState {
        &self.state
    }

    /// The parameters.
    pub fn params(&self) -> &ErosionParams {
        &self.params
    }

    /// The surface of the state as samples of the field: each cell's top column's bedrock +
    /// sand (in f32, as [`relief_core::MlhmColumn::solid_top`]) over the z scale, row-major.
    pub fn surface(&self) -> Vec<f32> {
        let mut out = vec![0.0; self.state.width() * self.state.height()];
        self.write_surface(&mut out);
        out
    }

    /// Runs one erosion step and writes the new surface into every sample of `field`;
    /// returns the volumes the step created or removed by design.
    ///
    /// Errors: a field of another size than the simulation's ([`SimError::Mismatch`]); a
    /// surface the field refuses ([`SimError::Terrain`]).
    pub fn step(&mut self, field: &mut HeightField) -> Result<StepVolumes, SimError> {
        let (w, h) = (self.state.width(), self.state.height());
        if field.width() != w || field.height() != h {
            return Err(SimError::Mismatch(format!(
                "the erosion runs on {w} x {h} cells, the field has {} x {}",
                field.width(),
                field.height()
            )));
        }
        let volumes = self.state.step(&self.params, self.seed)?;
        let mut next = std::mem::take(&mut self.spare);
        next.resize(w * h, 0.0);
        self.write_surface(&mut next);
        match field.replace_samples(next) {
            Ok(old) => {
                self.spare = old;
                Ok(volumes)
            }
            Err(e) => Err(e.into()),
        }
    }

    /// Writes the surface (see [`HeightFieldErosion::surface`]) into `out`.
    fn write_surface(&self, out: &mut [f32]) {
        let cells = self.state.width() * self.state.height();
        let counts = self.state.layer_counts();
        let columns = self.state.columns();
        let z_scale = self.z_scale;
        out.par_chunks_mut(4096).enumerate().for_each(|(chunk, out)| {
            for (k, v) in out.iter_mut().enumerate() {
                let i = chunk * 4096 + k;
                let top = usize::from(counts[i]).max(1) - 1;
                let top = columns[i + top * cells].solid_top();
                *v = if z_scale == 1.0 { top } else { (f64::from(top) / z_scale) as f32 };
            }
        });
    }
}
