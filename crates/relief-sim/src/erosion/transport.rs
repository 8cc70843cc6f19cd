//! Step 3, transport (reference: `transport.cu`, `transportKernel`): each column integrates
//! its net water flux (outflow less the inflow of every pipe that leads to it), evaporates
//! `evaporation clamp(air gap / evaporation_air_gap, 0.01, 1) dt`, takes its velocity
//! `0.5 (R - L, U - D) / cell²` from the net fluxes, moves its sand by slippage and its
//! sediment with the water, and petrifies `petrification dt` of its sand into bedrock.

use super::lanes::{avx2_dispatch, load, load4, map4, store, store2, Column, Lanes, Real, LANES};
use super::one_column::{along_row, neighbourhood_run};
use super::slots::{neighbours, opposite, par_rows, Slots};
use super::{ErosionParams, ErosionState, StepVolumes};
use relief_core::MlhmColumn;
use std::ops::Range;

/// A column after transport, with the values before its clamps (for the volumes).
struct Transported<R> {
    column: Column<R>,
    sediment: R,
    velocity: [R; 2],
    /// The water after the net flux, before and after clamping to `[0, space]`.
    water_unclamped: R,
    water_clamped: R,
    /// The sand after slippage, before and after clamping to the room under the ceiling.
    sand_unclamped: R,
    sand_clamped: R,
    /// The sediment before flushing what is below f32's normal range to 0.
    sediment_unclamped: R,
}

/// Transport of one column (or lanes of columns) with ceiling `ceiling`, sediment `sed`, and
/// in each direction the net water flux, sediment flux and slippage out of it.
#[inline(always)]
fn transport_column<R: Real>(
    params: &ErosionParams,
    cs: f32,
    c: Column<R>,
    ceiling: R,
    sed: R,
    [flux, sediment_flux, slip]: [[R; 4]; 3],
) -> Transported<R> {
    let splat = R::splat;
    let dt = params.dt;
    let scale = splat(dt / (cs * cs));
    let sum = |v: [R; 4]| v[0] + v[1] + v[2] + v[3];
    let mut c = c;
    let water_unclamped = c.water - scale * sum(flux);
    let space = (ceiling - c.bedrock - c.sand).max(splat(0.0));
    let water = water_unclamped.max(splat(0.0)).min(space);
    let gap = ceiling - c.bedrock - c.sand - water;
    let evaporation_scale = (gap / splat(params.evaporation_air_gap)).clamp(0.01, 1.0);
    c.water = (water - splat(params.evaporation) * evaporation_scale * splat(dt)).max(splat(0.0));
    let area = splat(cs * cs);
    let velocity =
        [splat(0.5) * (flux[0] - flux[2]) / area, splat(0.5) * (flux[1] - flux[3]) / area];
    let sand_unclamped = c.sand - sum(slip);
    if params.slippage {
        let room = ceiling - c.bedrock - c.water;
        c.sand = sand_unclamped.min(room).max(splat(0.0));
    }
    let sand_clamped = c.sand;
    let petrified = (splat(params.petrification * dt) * c.sand).min(c.sand);
    c.bedrock = c.bedrock + petrified;
    c.sand = c.sand - petrified;
    let sediment_unclamped = sed - scale * sum(sediment_flux);
    // Below f32's normal range sediment is flushed to 0: subnormal arithmetic is slow.
    let normal = sediment_unclamped.ge(splat(f32::MIN_POSITIVE));
    let sediment = R::select(normal, sediment_unclamped, splat(0.0));
    Transported {
        column: c,
        sediment,
        velocity,
        water_unclamped,
        water_clamped: water,
        sand_unclamped,
        sand_clamped,
        sediment_unclamped,
    }
}

impl Transported<f32> {
    /// Counts the clamps in `v` and returns the column, fitted under `ceiling`.
    #[inline(always)]
    fn account(&self, v: &mut StepVolumes, ceiling: f32, slippage: bool) -> MlhmColumn {
        let f = f64::from;
        v.water_clamped += f(self.water_unclamped) - f(self.water_clamped);
        v.evaporation += f(self.water_clamped) - f(self.column.water);
        if slippage {
            v.sand_clamped += f(self.sand_unclamped) - f(self.sand_clamped);
        }
        v.sediment_clamped += f(self.sediment) - f(self.sediment_unclamped);
        let c = self.column;
        let mut c = MlhmColumn::new(c.bedrock, c.sand, c.water, ceiling);
        v.fit(&mut c);
        c
    }
}

/// The net flux, sediment flux and slippage out of column `k` of a cell through one pipe,
/// whose outflow is `out` (flux, sediment flux scale, slippage): the outflow less the inflow of
/// the neighbouring cell `near`'s pipes in direction `back` that lead to column `k`. A
/// function, not a closure, so that it is always inlined and the four directions stay in
/// registers.
#[inline(always)]
fn net_inflow(
    (flux, scale_out, slip): (f32, f32, f32),
    near: Option<usize>,
    back: usize,
    k: usize,
    (counts, cells): (&[u8], usize),
    pipes: &Pipes,
) -> (f32, f32, f32) {
    let (mut flux, mut sediment_flux, mut slip) = (flux, flux * scale_out, slip);
    if let Some(n) = near {
        for nk in 0..usize::from(counts[n]) {
            let ns = n + nk * cells;
            if pipes.layers[ns][back] == k as i8 {
                flux -= pipes.fluxes[ns][back];
                sediment_flux -= pipes.scales[ns] * pipes.fluxes[ns][back];
                slip -= pipes.slippages[ns][back];
            }
        }
    }
    (flux, sediment_flux, slip)
}

/// Moves water, sand and sediment along the pipes [`super::pipes::pipes`] computed.
pub(crate) fn transport(state: &mut ErosionState, params: &ErosionParams) -> StepVolumes {
    let (width, height, cells, cs) = (state.width, state.height, state.cells(), state.cell_size);
    let counts = &state.layer_counts;
    let fluxes = &state.fluxes;
    let scratch = &mut state.scratch;
    let fast = scratch.fast_paths;
    let (pipes, slippages, scales) =
        (&scratch.pipes, &scratch.slippage, &scratch.sediment_flux_scale);
    let all = Pipes { fluxes, scales, slippages, layers: pipes };
    let layers = (&counts[..], cells);
    let velocities = Slots::new(&mut scratch.velocities);
    let columns = Slots::new(&mut state.columns);
    let sediment = Slots::new(&mut state.sediment);
    par_rows(height, |y| {
        let mut v = StepVolumes::default();
        let cell = |x: usize, v: &mut StepVolumes| {
            let i = x + y * width;
            let near = neighbours(x, y, width, height);
            for k in 0..usize::from(counts[i]) {
                let s = i + k * cells;
                let (out, scale_out, slip_out) = (fluxes[s], scales[s], slippages[s]);
                let out = |d: usize| (out[d], scale_out, slip_out[d]);
                let nets = [
                    net_inflow(out(0), near[0], opposite(0), k, layers, &all),
                    net_inflow(out(1), near[1], opposite(1), k, layers, &all),
                    net_inflow(out(2), near[2], opposite(2), k, layers, &all),
                    net_inflow(out(3), near[3], opposite(3), k, layers, &all),
                ];
                let nets = [map4(nets, |n| n.0), map4(nets, |n| n.1), map4(nets, |n| n.2)];
                // SAFETY: slot `s` belongs to cell (x, y) of this row only.
                let (c, sed) = unsafe { (columns.get(s), sediment.get(s)) };
                let t = transport_column(params, cs, c.into(), c.ceiling, sed, nets);
                let c = t.account(v, c.ceiling, params.slippage);
                // SAFETY: as above.
                unsafe {
                    columns.set(s, c);
                    sediment.set(s, t.sediment);
                    velocities.set(s, t.velocity);
                }
            }
        };
        let row = y * width;
        let run = |x| if fast { neighbourhood_run(counts, width, height, y, x) } else { 0 };
        let lanes = |v: &mut StepVolumes, cells| {
            // Lanes are never in the first or last row.
            let band = all.rows(row - width..row + 2 * width);
            // SAFETY: the slots of row `y`'s lowest columns belong to this row only.
            let out = unsafe {
                OneColumnRow {
                    columns: columns.row(row, width),
                    sediment: sediment.row(row, width),
                    velocities: velocities.row(row, width),
                }
            };
            one_column_transport(params, cs, band, out, cells, v);
        };
        along_row(width, &mut v, run, lanes, |v, x| cell(x, v));
        v
    })
}

/// The pipes' outputs: for all cells, or for the rows below, at and above a row.
struct Pipes<'a> {
    fluxes: &'a [[f32; 4]],
    scales: &'a [f32],
    slippages: &'a [[f32; 4]],
    /// The layer of the neighbour each pipe leads to (-1: none).
    layers: &'a [[i8; 4]],
}

impl<'a> Pipes<'a> {
    /// The outputs of the slots `slots`.
    fn rows(&self, slots: Range<usize>) -> Pipes<'a> {
        Pipes {
            fluxes: &self.fluxes[slots.clone()],
            scales: &self.scales[slots.clone()],
            slippages: &self.slippages[slots.clone()],
            layers: &self.layers[slots],
        }
    }
}

/// The state of one row's lowest columns that transport changes.
struct OneColumnRow<'a> {
    columns: &'a mut [MlhmColumn],
    sediment: &'a mut [f32],
    velocities: &'a mut [[f32; 2]],
}

avx2_dispatch! {
/// Transport in the cells `cells` of a row, [`LANES`] at a time, where they and their
/// neighbours hold one column each ([`neighbourhood_run`]): every neighbour's pipe back leads
/// to the cell's only column, whose ceiling is `+inf`.
fn one_column_transport(
    params: &ErosionParams,
    cs: f32,
    pipes: Pipes,
    out: OneColumnRow,
    cells: Range<usize>,
    v: &mut StepVolumes,
) {
    let mut volumes = LaneVolumes::default();
    let width = out.columns.len();
    let (row, above) = (width, 2 * width);
    for x in cells.step_by(LANES) {
        let flux_out = load4(&pipes.fluxes[row + x..]);
        let scale_out = load(&pipes.scales[row + x..]);
        let slip_out = load4(&pipes.slippages[row + x..]);
        // The neighbour in direction d, and the direction of its pipe back here.
        let back = [(row + x + 1, 2), (above + x, 3), (row + x - 1, 0), (x, 1)];
        let mut nets = [[Lanes::splat(0.0); 4]; 3];
        for (d, (n, b)) in back.into_iter().enumerate() {
            let flux_in = load4(&pipes.fluxes[n..])[b];
            let scale_in = load(&pipes.scales[n..]);
            let slip_in = load4(&pipes.slippages[n..])[b];
            nets[0][d] = flux_out[d] - flux_in;
            nets[1][d] = flux_out[d] * scale_out - scale_in * flux_in;
            nets[2][d] = slip_out[d] - slip_in;
        }
        let cells = &mut out.columns[x..x + LANES];
        let c = Column::load(cells);
        let sed = load(&out.sediment[x..]);
        let t = transport_column(params, cs, c, Lanes::splat(f32::INFINITY), sed, nets);
        // Under an infinite ceiling the water and sand, both >= 0, fit: nothing to fit.
        t.column.store(cells, f32::INFINITY);
        store(&mut out.sediment[x..], t.sediment);
        store2(&mut out.velocities[x..], t.velocity);
        volumes.add(&t, params.slippage);
    }
    volumes.add_to(v);
}
}

/// The volumes of [`Transported::account`], summed per lane in f64.
#[derive(Default)]
struct LaneVolumes {
    water_clamped: [f64; LANES],
    evaporation: [f64; LANES],
    sand_clamped: [f64; LANES],
    sediment_clamped: [f64; LANES],
}

impl LaneVolumes {
    /// Adds the clamps and the evaporation of `t`.
    #[inline(always)]
    fn add(&mut self, t: &Transported<Lanes>, slippage: bool) {
        let f = f64::from;
        for l in 0..LANES {
            self.water_clamped[l] += f(t.water_unclamped.0[l]) - f(t.water_clamped.0[l]);
            self.evaporation[l] += f(t.water_clamped.0[l]) - f(t.column.water.0[l]);
            if slippage {
                self.sand_clamped[l] += f(t.sand_unclamped.0[l]) - f(t.sand_clamped.0[l]);
            }
            self.sediment_clamped[l] += f(t.sediment.0[l]) - f(t.sediment_unclamped.0[l]);
        }
    }

    /// Adds the lanes' sums, in lane order, to `v`.
    fn add_to(&self, v: &mut StepVolumes) {
        for l in 0..LANES {
            v.water_clamped += self.water_clamped[l];
            v.evaporation += self.evaporation[l];
            v.sand_clamped += self.sand_clamped[l];
            v.sediment_clamped += self.sediment_clamped[l];
        }
    }
}
