//! Step 2, virtual pipes and sand slippage (reference: `transport.cu`, `pipeKernel`).
//!
//! Each column connects, in each of the four directions, to the first column of the
//! neighbouring cell (bottom up) whose ceiling is above this column's bedrock and that is not
//! full of water. Its outflow through that pipe follows the head difference
//! `dh = min(own water top, neighbour ceiling) - max(neighbour water top, own sand top)`:
//! `f = max((1 - damping dt) f + dt g A dh / l, 0)` with `A = cell²` and `l = cell`. Into a
//! column under a ceiling, each pipe carries at most a quarter of that column's free space
//! per step (the reference allows each pipe the whole space and deletes what overflows; a
//! quarter per pipe keeps water conserved). Then all outflows are scaled so they carry at most
//! the column's water. Beyond the domain's edges are walls: no pipe, no flux.
//!
//! Sand slips through the same pipes: `rate (sand-top difference - tan(talus) cell)`, the
//! talus angle going from dry to wet over `slippage_interpolation_range` of mean water depth,
//! at most a quarter of the neighbour's free space, scaled to the column's sand. The slope
//! (sin) for erosion comes from the sand tops the pipes reach (central differences).

use super::lanes::{avx2_dispatch, load, load4, map4, store, store4, Column, Lanes, Real, LANES};
use super::one_column::{along_row, neighbourhood_run};
use super::slots::{neighbours, par_rows, Slots};
use super::{ErosionParams, ErosionState, StepVolumes};
use relief_core::MlhmColumn;
use std::ops::Range;

/// The step's constants of the pipes.
struct PipeConstants {
    dt: f32,
    cs: f32,
    area: f32,
    /// `1 / slippage_interpolation_range`.
    inverse_range: f32,
    /// `dt g cell`: flux per metre of head.
    flow: f32,
    /// `dt / cell²`: height per flux.
    taken_scale: f32,
    /// `1 - flux_damping dt`.
    damping: f32,
    /// tan of the dry and wet talus angles.
    dry: f32,
    wet: f32,
    slippage_rate: f32,
    slippage: bool,
}

impl PipeConstants {
    fn new(params: &ErosionParams, cs: f32) -> Self {
        let dt = params.dt;
        PipeConstants {
            dt,
            cs,
            area: cs * cs,
            inverse_range: 1.0 / params.slippage_interpolation_range,
            flow: dt * params.gravity * cs,
            taken_scale: dt / (cs * cs),
            damping: 1.0 - params.flux_damping * dt,
            dry: params.dry_talus_angle.to_radians().tan(),
            wet: params.wet_talus_angle.to_radians().tan(),
            slippage_rate: params.slippage_rate,
            slippage: params.slippage,
        }
    }

    /// The flux and the sand slippage of the pipe from `c` into `nc` (whose ceiling is
    /// `n_ceiling`), whose flux was `old`. Without `CEILING`, `nc`'s ceiling must be `+inf`:
    /// the terms it bounds are then left out, which gives the same values.
    #[inline(always)]
    fn pipe<R: Real, const CEILING: bool>(
        &self,
        c: Column<R>,
        nc: Column<R>,
        n_ceiling: R,
        old: R,
    ) -> (R, R) {
        let splat = R::splat;
        let (sand, water) = (c.solid_top(), c.water_top());
        let n_water = nc.water_top();
        let reach = if CEILING { water.min(n_ceiling) } else { water };
        let dh = reach - n_water.max(sand);
        let mut f = (splat(self.damping) * old + splat(self.flow) * dh).max(splat(0.0));
        if CEILING {
            // Under an infinite ceiling the ratio is exactly 1.
            let free = splat(0.25) * (n_ceiling - n_water).max(splat(0.0));
            f = f * ratio(free, f * splat(self.taken_scale) + splat(f32::EPSILON));
        }
        let mean_water = splat(0.5) * (c.water + nc.water);
        let t = (mean_water * splat(self.inverse_range)).min(splat(1.0));
        let talus = splat(self.dry) + splat(self.wet - self.dry) * t;
        let excess = splat(self.slippage_rate) * (sand - nc.solid_top() - talus * splat(self.cs));
        let slip = if CEILING {
            excess.max(splat(0.0)).min(splat(0.25) * (n_ceiling - n_water)).max(splat(0.0))
        } else {
            excess.max(splat(0.0))
        };
        (f, slip)
    }

    /// The pipe of `c` (whose flux was `old`) to the neighbouring cell `near` (of `counts`
    /// columns in the planes of `cells` slots of `columns`): (flux, slippage, neighbour's
    /// layer or -1, neighbour's sand top or this column's). A function, not a closure, so
    /// that it is always inlined and the four directions stay in registers.
    #[inline(always)]
    fn pipe_to(
        &self,
        c: MlhmColumn,
        near: Option<usize>,
        old: f32,
        (counts, columns, cells): (&[u8], &[MlhmColumn], usize),
    ) -> (f32, f32, i8, f32) {
        if let Some(n) = near {
            for nk in 0..usize::from(counts[n]) {
                let nc = columns[n + nk * cells];
                if c.bedrock < nc.ceiling && nc.water_top() + f32::EPSILON < nc.ceiling {
                    let (cf, nf) = (c.into(), nc.into());
                    // Under an infinite ceiling both give the same values.
                    let (f, slip) = if nc.ceiling.is_finite() {
                        self.pipe::<f32, true>(cf, nf, nc.ceiling, old)
                    } else {
                        self.pipe::<f32, false>(cf, nf, nc.ceiling, old)
                    };
                    return (f, slip, nk as i8, nc.solid_top());
                }
            }
        }
        (0.0, 0.0, -1, c.solid_top())
    }

    /// Scales the pipes of `c` (`flux`, `slip`, with the sand tops `tops` they reach) to the
    /// water and sand it has; returns the fluxes, slippages, sediment flux scale and slope.
    #[inline(always)]
    fn scale<R: Real>(
        &self,
        c: Column<R>,
        sediment: R,
        flux: [R; 4],
        slip: [R; 4],
        tops: [R; 4],
    ) -> ([R; 4], [R; 4], R, R) {
        let splat = R::splat;
        let eps = splat(f32::EPSILON);
        let slope = slope_sine(tops, self.cs);
        let out = (flux[0] + flux[1] + flux[2] + flux[3]) * splat(self.dt);
        let scale = ratio(c.water * splat(self.area), out + eps);
        // A scale of exactly 1 leaves the fluxes as they are: no branch.
        let flux = map4(flux, |f| f * scale);
        let out = (flux[0] + flux[1] + flux[2] + flux[3]) * splat(self.dt);
        let sediment_scale = ratio(sediment * splat(self.area), out + eps);
        let slipped = slip[0] + slip[1] + slip[2] + slip[3];
        let slip_scale = ratio(c.sand, slipped + eps);
        let slip = if self.slippage { map4(slip, |v| v * slip_scale) } else { [splat(0.0); 4] };
        (flux, slip, sediment_scale, slope)
    }
}

/// Computes fluxes, pipes, slippage, sediment flux scales and slopes for every column.
pub(crate) fn pipes(state: &mut ErosionState, params: &ErosionParams) {
    let (width, height, cells, cs) = (state.width, state.height, state.cells(), state.cell_size);
    let counts = &state.layer_counts;
    let columns = &state.columns;
    let sediment = &state.sediment;
    let fluxes = Slots::new(&mut state.fluxes);
    let pipes = Slots::new(&mut state.scratch.pipes);
    let slippages = Slots::new(&mut state.scratch.slippage);
    let sediment_scales = Slots::new(&mut state.scratch.sediment_flux_scale);
    let slopes = Slots::new(&mut state.scratch.slopes);
    let k = PipeConstants::new(params, cs);
    let fast = state.scratch.fast_paths;
    par_rows(height, |y| {
        let cell = |x: usize| {
            let i = x + y * width;
            let near = neighbours(x, y, width, height);
            for layer in 0..usize::from(counts[i]) {
                let s = i + layer * cells;
                let c = columns[s];
                // SAFETY: slot `s` belongs to cell (x, y) of this row only.
                let old = unsafe { fluxes.get(s) };
                let terrain = (&counts[..], &columns[..], cells);
                let p = [
                    k.pipe_to(c, near[0], old[0], terrain),
                    k.pipe_to(c, near[1], old[1], terrain),
                    k.pipe_to(c, near[2], old[2], terrain),
                    k.pipe_to(c, near[3], old[3], terrain),
                ];
                let (flux, slip, scale, slope) = k.scale(
                    c.into(),
                    sediment[s],
                    map4(p, |p| p.0),
                    map4(p, |p| p.1),
                    map4(p, |p| p.3),
                );
                // SAFETY: slot `s` belongs to cell (x, y) of this row only.
                unsafe {
                    fluxes.set(s, flux);
                    pipes.set(s, map4(p, |p| p.2));
                    slippages.set(s, slip);
                    sediment_scales.set(s, scale);
                    slopes.set(s, slope);
                }
            }
        };
        let row = y * width;
        let run = |x| if fast { neighbourhood_run(counts, width, height, y, x) } else { 0 };
        let lanes = |_: &mut (), cells| {
            // SAFETY: the slots of row `y`'s lowest columns belong to this row only.
            let out = unsafe {
                OneColumnRow {
                    fluxes: fluxes.row(row, width),
                    pipes: pipes.row(row, width),
                    slippages: slippages.row(row, width),
                    sediment_scales: sediment_scales.row(row, width),
                    slopes: slopes.row(row, width),
                }
            };
            let band = &columns[row - width..row + 2 * width];
            one_column_pipes(&k, band, &sediment[row..row + width], out, cells);
        };
        along_row(width, &mut (), run, lanes, |_, x| cell(x));
        StepVolumes::default()
    });
}

/// The outputs of the pipes for one row's lowest columns.
struct OneColumnRow<'a> {
    fluxes: &'a mut [[f32; 4]],
    pipes: &'a mut [[i8; 4]],
    slippages: &'a mut [[f32; 4]],
    sediment_scales: &'a mut [f32],
    slopes: &'a mut [f32],
}

avx2_dispatch! {
/// The pipes of the cells `cells` of a row, [`LANES`] at a time, where they and their
/// neighbours hold one column each ([`neighbourhood_run`]): `columns` holds the rows below, at
/// and above the row, `sediment` the row's own. Every pipe leads to the neighbour's only
/// column, whose ceiling is `+inf`.
fn one_column_pipes(
    k: &PipeConstants,
    columns: &[MlhmColumn],
    sediment: &[f32],
    out: OneColumnRow,
    cells: Range<usize>,
) {
    let width = sediment.len();
    let (below, rest) = columns.split_at(width);
    let (row, above) = rest.split_at(width);
    for x in cells.step_by(LANES) {
        let c = Column::load(&row[x..]);
        let near = [
            Column::load(&row[x + 1..]),
            Column::load(&above[x..]),
            Column::load(&row[x - 1..]),
            Column::load(&below[x..]),
        ];
        let old = load4(&out.fluxes[x..]);
        let p = map4([0, 1, 2, 3], |d| {
            k.pipe::<Lanes, false>(c, near[d], Lanes::splat(f32::INFINITY), old[d])
        });
        let tops = map4(near, |n| n.solid_top());
        let (flux, slip, scale, slope) =
            k.scale(c, load(&sediment[x..]), map4(p, |p| p.0), map4(p, |p| p.1), tops);
        store4(&mut out.fluxes[x..], flux);
        out.pipes[x..x + LANES].fill([0; 4]);
        store4(&mut out.slippages[x..], slip);
        store(&mut out.sediment_scales[x..], scale);
        store(&mut out.slopes[x..], slope);
    }
}
}

/// `min(a / b, 1)` for `b > 0`: exactly 1 when `a >= b`. Divides either way, so the
/// comparison is a select rather than a branch the data makes unpredictable.
#[inline]
fn ratio<R: Real>(a: R, b: R) -> R {
    R::select(a.ge(b), R::splat(1.0), a / b)
}

/// sin of the slope of the surface through the four neighbouring sand tops `tops` (right,
/// up, left, down) at spacing `cs`, from the cross product of the two central-difference
/// tangents, as the reference computes it.
#[inline(always)]
fn slope_sine<R: Real>(tops: [R; 4], cs: f32) -> R {
    let a = 2.0 * cs;
    let bx = tops[0] - tops[2];
    let by = tops[1] - tops[3];
    // Tangents (a, bx, 0) and (0, by, a), normalised; the normal's second component is
    // -t0.x * t1.z = -a² / sqrt((a² + bx²)(a² + by²)), and the reference takes
    // sqrt(1 - n.y²) as sin(alpha).
    let a2 = a * a;
    let ny2 = R::splat(a2 * a2) / ((R::splat(a2) + bx * bx) * (R::splat(a2) + by * by));
    (R::splat(1.0) - ny2).max(R::splat(0.0)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slope_of_a_plane() {
        assert_eq!(slope_sine([1.0f32; 4], 1.0), 0.0);
        // 45 degrees along x: sin = 1/sqrt 2.
        let s = slope_sine([1.0f32, 0.0, -1.0, 0.0], 1.0);
        assert!((s - std::f32::consts::FRAC_1_SQRT_2).abs() < 1e-6, "{s}");
    }
}
