//! The ocean wave simulation of the hybrid-rendering paper (Ammann et al. 2010, section 5.3):
//! a sea level plus a damped 2D wave equation over the grid, rewriting the whole height field
//! every step.

use super::WaveParams;
use crate::erosion::uniform;
use crate::SimError;
use rayon::prelude::*;
use relief_core::HeightField;

/// Rows a parallel task integrates at a time.
const ROWS_PER_TASK: usize = 16;

/// A drop's Gaussian is cut off at this many radii.
const DROP_CUTOFF: f64 = 3.0;

/// The sea over a height field's sea bed.
///
/// The wave `u` (sample units above the sea level) follows `u_tt = c² ∇²u - γ u_t + f`,
/// integrated by leapfrog with second-order central differences,
/// `u' = u + e^{-γ dt} (u - u_prev) + (c dt/dx)² δx²u + (c dt/dy)² δy²u + dt² f`, with the
/// time step from [`WaveParams::courant`]. The wave lives where the sea is, in each row from
/// its first to its last sample below the sea level; it is 0 on the land beyond and outside
/// the grid (walls that reflect it). The forcing `f` is a wind pattern
/// `A sin(k·x - ω t)` travelling at the wave speed; every [`WaveParams::drop_interval`] steps
/// a Gaussian drop lifts the sea at a place drawn from the seed and the step number.
///
/// Each [`WaveSimulation::step`] writes `max(sea bed, sea level + u)` into every sample of the
/// field with [`HeightField::replace_samples`], reusing the buffer it returns. Rows are
/// integrated in parallel, each value by the same operations whatever the thread count, so
/// the bytes do not depend on it.
///
/// ```
/// use relief_core::{GridGeometry, HeightField};
/// use relief_sim::{WaveParams, WaveSimulation};
/// let bed: Vec<f32> = (0..64 * 64).map(|i| (i % 64) as f32 * 0.1).collect();
/// let mut field = HeightField::new(64, 64, bed, GridGeometry::unit()).unwrap();
/// let mut sea = WaveSimulation::new(&field, WaveParams::for_field(&field)).unwrap();
/// for _ in 0..10 {
///     sea.step(&mut field).unwrap();
/// }
/// assert!(field.sample(0, 0) >= 2.2); // the sea covers the low end
/// ```
#[derive(Debug, Clone)]
pub struct WaveSimulation {
    params: WaveParams,
    width: usize,
    height: usize,
    /// The sea bed: the field's samples when the simulation started.
    bed: Vec<f32>,
    /// The wave now, sample units.
    wave: Vec<f32>,
    /// The wave one step ago; overwritten by the next one each step.
    previous: Vec<f32>,
    /// The buffer the next field is written into (the field's previous samples).
    spare: Vec<f32>,
    /// Sea level, sample units.
    sea: f32,
    dt: f64,
    /// Per-step coefficients: memory of the last step, x and y Laplacian weights.
    damping_factor: f32,
    cx: f32,
    cy: f32,
    steps: u64,
    /// Per-column (sin, cos) of the wind's phase along x at the current step, and per-row of
    /// its phase along y (fixed).
    wind_sin: Vec<f32>,
    wind_cos: Vec<f32>,
    wind_rows: Vec<[f32; 2]>,
    /// Per row, the columns from its first to its last sample under the sea level: the
    /// wave lives there and is 0 on the land beyond.
    sea_spans: Vec<[usize; 2]>,
    geometry: relief_core::GridGeometry,
}

impl WaveSimulation {
    /// A calm sea over the samples of `field` as sea bed.
    ///
    /// Errors: parameters [`WaveParams::validate`] refuses.
    pub fn new(field: &HeightField, params: WaveParams) -> Result<Self, SimError> {
        params.validate()?;
        let g = *field.geometry();
        let (width, height) = (field.width(), field.height());
        let cells = width * height;
        let dt = params.courant / (params.wave_speed * (g.dx.powi(-2) + g.dy.powi(-2)).sqrt());
        let cdt = params.wave_speed * dt;
        let sea = (params.sea_level / g.z_scale) as f32;
        if !sea.is_finite() {
            return Err(SimError::parameter("sea level", "is beyond f32's range in sample units"));
        }
        let angle = params.wind_direction_deg.to_radians();
        let k = std::f64::consts::TAU / params.wind_wavelength;
        let ky = k * angle.sin();
        let wind_rows = (0..height)
            .map(|row| {
                let (s, c) = (ky * (g.origin.y + (row as f64 + 0.5) * g.dy)).sin_cos();
                [s as f32, c as f32]
            })
            .collect();
        let mut sim = WaveSimulation {
            params,
            width,
            height,
            bed: field.samples().to_vec(),
            wave: vec![0.0; cells],
            previous: vec![0.0; cells],
            spare: vec![0.0; cells],
            sea,
            dt,
            damping_factor: (-params.damping * dt).exp() as f32,
            cx: ((cdt / g.dx).powi(2)) as f32,
            cy: ((cdt / g.dy).powi(2)) as f32,
            steps: 0,
            wind_sin: vec![0.0; width],
            wind_cos: vec![0.0; width],
            wind_rows,
            sea_spans: sea_spans(field.samples(), width, sea),
            geometry: g,
        };
        sim.update_wind_columns();
        Ok(sim)
    }

    /// The time step, seconds.
    pub fn time_step(&self) -> f64 {
        self.dt
    }

    /// Steps simulated so far.
    pub fn step_count(&self) -> u64 {
        self.steps
    }

    /// The wave now, row-major, in sample units above the sea level.
    pub fn wave(&self) -> &[f32] {
        &self.wave
    }

    /// The sea bed, row-major, in sample units.
    pub fn sea_bed(&self) -> &[f32] {
        &self.bed
    }

    /// The parameters.
    pub fn params(&self) -> &WaveParams {
        &self.params
    }

    /// Advances the sea by one time step and writes `max(sea bed, sea level + wave)` into
    /// every sample of `field`.
    ///
    /// Errors: a field of another size than the simulation's ([`SimError::Mismatch`]); a
    /// value the field refuses ([`SimError::Terrain`]). The field is then unchanged.
    pub fn step(&mut self, field: &mut HeightField) -> Result<(), SimError> {
        if field.width() != self.width || field.height() != self.height {
            return Err(SimError::Mismatch(format!(
                "the wave simulation runs on {} x {} samples, the field has {} x {}",
                self.width,
                self.height,
                field.width(),
                field.height()
            )));
        }
        self.drop_if_due();
        self.integrate();
        std::mem::swap(&mut self.wave, &mut self.previous);
        self.steps += 1;
        self.update_wind_columns();
        let next = std::mem::take(&mut self.spare);
        match field.replace_samples(next) {
            Ok(old) => {
                self.spare = old;
                Ok(())
            }
            Err(e) => {
                self.spare = vec![0.0; self.bed.len()];
                Err(e.into())
            }
        }
    }

    /// Lifts the sea by a Gaussian drop when this step is due one.
    fn drop_if_due(&mut self) {
        let p = &self.params;
        if p.drop_interval == 0 || !self.steps.is_multiple_of(u64::from(p.drop_interval)) {
            return;
        }
        let g = &self.geometry;
        let (w, h) = (self.width as f64, self.height as f64);
        let x = f64::from(uniform(p.seed, self.steps, 0)) * w * g.dx;
        let y = f64::from(uniform(p.seed, self.steps, 1)) * h * g.dy;
        let reach = DROP_CUTOFF * p.drop_radius;
        let span = |centre: f64, spacing: f64, n: f64| {
            let lo = ((centre - reach) / spacing - 0.5).floor().clamp(0.0, n) as usize;
            let hi = ((centre + reach) / spacing + 0.5).ceil().clamp(0.0, n) as usize;
            lo..hi
        };
        let amplitude = p.drop_amplitude / g.z_scale;
        let inv_r2 = 1.0 / (p.drop_radius * p.drop_radius);
        for row in span(y, g.dy, h) {
            let dy = (row as f64 + 0.5) * g.dy - y;
            for col in span(x, g.dx, w) {
                let dx = (col as f64 + 0.5) * g.dx - x;
                let [c0, c1] = self.sea_spans[row];
                if !(c0..c1).contains(&col) {
                    continue;
                }
                let lift = amplitude * (-(dx * dx + dy * dy) * 0.5 * inv_r2).exp();
                self.wave[col + row * self.width] += lift as f32;
            }
        }
    }

    /// The wind's phase along x at the current step, per column.
    fn update_wind_columns(&mut self) {
        let g = &self.geometry;
        let p = &self.params;
        let k = std::f64::consts::TAU / p.wind_wavelength;
        let kx = k * p.wind_direction_deg.to_radians().cos();
        let omega = k * p.wave_speed;
        let t = self.steps as f64 * self.dt;
        for (col, (ws, wc)) in self.wind_sin.iter_mut().zip(&mut self.wind_cos).enumerate() {
            let (s, c) = (kx * (g.origin.x + (col as f64 + 0.5) * g.dx) - omega * t).sin_cos();
            (*ws, *wc) = (s as f32, c as f32);
        }
    }

    /// One leapfrog step: the next wave into `previous`, the next field into `spare`.
    fn integrate(&mut self) {
        let w = self.width;
        let h = self.height;
        let zero_row = vec![0.0f32; w];
        let kernel = RowKernel {
            damping_factor: self.damping_factor,
            cx: self.cx,
            cy: self.cy,
            forcing: (self.dt * self.dt * self.params.wind_amplitude / self.geometry.z_scale)
                as f32,
            sea: self.sea,
            wind_sin: &self.wind_sin,
            wind_cos: &self.wind_cos,
        };
        let wave = &self.wave;
        let bed = &self.bed;
        let rows = &self.wind_rows;
        let spans = &self.sea_spans;
        self.previous
            .par_chunks_mut(w * ROWS_PER_TASK)
            .zip(self.spare.par_chunks_mut(w * ROWS_PER_TASK))
            .enumerate()
            .for_each(|(task, (previous, out))| {
                let first = task * ROWS_PER_TASK;
                for (k, (prev_row, out_row)) in
                    previous.chunks_exact_mut(w).zip(out.chunks_exact_mut(w)).enumerate()
                {
                    let row = first + k;
                    let at = |r: usize| &wave[r * w..(r + 1) * w];
                    let below = if row == 0 { &zero_row[..] } else { at(row - 1) };
                    let above = if row + 1 == h { &zero_row[..] } else { at(row + 1) };
                    let neighbours = Neighbours { below, here: at(row), above };
                    kernel.row(
                        &neighbours,
                        rows[row],
                        spans[row],
                        &bed[row * w..(row + 1) * w],
                        prev_row,
                        out_row,
                    );
                }
            });
    }
}

/// Per row of `bed` (`width` samples a row), the columns `[first, last + 1)` of its samples
/// below `sea` (`[0, 0]` for a row of land).
fn sea_spans(bed: &[f32], width: usize, sea: f32) -> Vec<[usize; 2]> {
    bed.chunks_exact(width)
        .map(|row| match row.iter().position(|&b| b < sea) {
            Some(first) => {
                let last = row.iter().rposition(|&b| b < sea).unwrap_or(first);
                [first, last + 1]
            }
            None => [0, 0],
        })
        .collect()
}

/// The field's sample: the sea's `level` where it is above the `bed`, else the bed. (Both are
/// finite: a plain comparison, which vectorises, where `f32::max` would handle NaN.)
#[inline]
fn surface(bed: f32, level: f32) -> f32 {
    if level > bed {
        level
    } else {
        bed
    }
}

/// The wave's rows around the row being integrated.
struct Neighbours<'a> {
    below: &'a [f32],
    here: &'a [f32],
    above: &'a [f32],
}

/// The per-step constants of the leapfrog update.
struct RowKernel<'a> {
    damping_factor: f32,
    cx: f32,
    cy: f32,
    /// `dt²` times the wind's peak acceleration, sample units.
    forcing: f32,
    sea: f32,
    wind_sin: &'a [f32],
    wind_cos: &'a [f32],
}

impl RowKernel<'_> {
    /// Integrates one row: `previous` (the wave one step ago) becomes the next wave, `out`
    /// the next field.
    #[inline]
    fn row(
        &self,
        u: &Neighbours,
        wind_row: [f32; 2],
        span: [usize; 2],
        bed: &[f32],
        previous: &mut [f32],
        out: &mut [f32],
    ) {
        // Land outside the row's sea span: the bed, and a wave that stays 0.
        let [c0, c1] = span;
        out[..c0].copy_from_slice(&bed[..c0]);
        out[c1..].copy_from_slice(&bed[c1..]);
        if c0 == c1 {
            return;
        }
        let n = c1 - c0;
        let (below, here, above) = (&u.below[c0..c1], &u.here[c0..c1], &u.above[c0..c1]);
        let (bed, previous, out) = (&bed[c0..c1], &mut previous[c0..c1], &mut out[c0..c1]);
        let (ws, wc) = (&self.wind_sin[c0..c1], &self.wind_cos[c0..c1]);
        let [sb, cb] = wind_row;
        let (fs, fc) = (self.forcing * cb, self.forcing * sb);
        let interior = n.saturating_sub(2);
        let step = |uc: f32, l: f32, r: f32, d: f32, a: f32, p: f32, sa: f32, ca: f32| {
            uc + self.damping_factor * (uc - p)
                + self.cx * (l + r - 2.0 * uc)
                + self.cy * (d + a - 2.0 * uc)
                + (sa * fs + ca * fc)
        };
        if n == 1 {
            let next = step(here[0], 0.0, 0.0, below[0], above[0], previous[0], ws[0], wc[0]);
            previous[0] = next;
            out[0] = surface(bed[0], self.sea + next);
            return;
        }
        let first = step(here[0], 0.0, here[1], below[0], above[0], previous[0], ws[0], wc[0]);
        let last_c = n - 1;
        let last = step(
            here[last_c],
            here[last_c - 1],
            0.0,
            below[last_c],
            above[last_c],
            previous[last_c],
            ws[last_c],
            wc[last_c],
        );
        // The interior, as zipped slices of one length so that the loop vectorises.
        let (p_in, o_in) = (&mut previous[1..1 + interior], &mut out[1..1 + interior]);
        let (b_in, s_in, k_in) =
            (&bed[1..1 + interior], &ws[1..1 + interior], &wc[1..1 + interior]);
        let (d_in, a_in) = (&below[1..1 + interior], &above[1..1 + interior]);
        let (l_in, c_in, r_in) =
            (&here[..interior], &here[1..1 + interior], &here[2..2 + interior]);
        for k in 0..interior {
            let next = step(c_in[k], l_in[k], r_in[k], d_in[k], a_in[k], p_in[k], s_in[k], k_in[k]);
            p_in[k] = next;
            o_in[k] = surface(b_in[k], self.sea + next);
        }
        previous[0] = first;
        out[0] = surface(bed[0], self.sea + first);
        previous[last_c] = last;
        out[last_c] = surface(bed[last_c], self.sea + last);
    }
}
