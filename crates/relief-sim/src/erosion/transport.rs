//! Step 3, transport (reference: `transport.cu`, `transportKernel`): each column integrates
//! its net water flux (outflow less the inflow of every pipe that leads to it), evaporates
//! `evaporation clamp(air gap / evaporation_air_gap, 0.01, 1) dt`, takes its velocity
//! `0.5 (R - L, U - D) / cell²` from the net fluxes, moves its sand by slippage and its
//! sediment with the water, and petrifies `petrification dt` of its sand into bedrock.

use super::slots::{neighbours, opposite, par_rows, Slots};
use super::{ErosionParams, ErosionState, StepVolumes};

/// Moves water, sand and sediment along the pipes [`super::pipes::pipes`] computed.
pub(crate) fn transport(state: &mut ErosionState, params: &ErosionParams) -> StepVolumes {
    let (width, height, cells, cs) = (state.width, state.height, state.cells(), state.cell_size);
    let counts = &state.layer_counts;
    let fluxes = &state.fluxes;
    let scratch = &mut state.scratch;
    let (pipes, slippages, scales) =
        (&scratch.pipes, &scratch.slippage, &scratch.sediment_flux_scale);
    let velocities = Slots::new(&mut scratch.velocities);
    let columns = Slots::new(&mut state.columns);
    let sediment = Slots::new(&mut state.sediment);
    let dt = params.dt;
    let scale = dt / (cs * cs);
    par_rows(height, |y| {
        let mut v = StepVolumes::default();
        for x in 0..width {
            let i = x + y * width;
            let near = neighbours(x, y, width, height);
            for k in 0..usize::from(counts[i]) {
                let s = i + k * cells;
                let (out, scale_out, slip_out) = (fluxes[s], scales[s], slippages[s]);
                // Net flux, sediment flux and slippage in direction `d`: the outflow less the
                // inflow of the neighbour's pipes that lead here. Called with constant
                // directions so the four stay in registers.
                let net_to = |d: usize| {
                    let mut flux = out[d];
                    let mut sediment_flux = flux * scale_out;
                    let mut slip = slip_out[d];
                    if let Some(n) = near[d] {
                        let back = opposite(d);
                        for nk in 0..usize::from(counts[n]) {
                            let ns = n + nk * cells;
                            if pipes[ns][back] == k as i8 {
                                flux -= fluxes[ns][back];
                                sediment_flux -= scales[ns] * fluxes[ns][back];
                                slip -= slippages[ns][back];
                            }
                        }
                    }
                    (flux, sediment_flux, slip)
                };
                let nets = [net_to(0), net_to(1), net_to(2), net_to(3)];
                let flux = nets.map(|n| n.0);
                let sediment_flux = nets.map(|n| n.1);
                let slip = nets.map(|n| n.2);
                // SAFETY: slot `s` belongs to cell (x, y) of this row only.
                let (mut c, sed) = unsafe { (columns.get(s), sediment.get(s)) };
                let net: f32 = flux.iter().sum();
                let unclamped = c.water - scale * net;
                let space = (c.ceiling - c.bedrock - c.sand).max(0.0);
                let water = unclamped.max(0.0).min(space);
                v.water_clamped += f64::from(unclamped) - f64::from(water);
                let gap = c.ceiling - c.bedrock - c.sand - water;
                let evaporation_scale = (gap / params.evaporation_air_gap).clamp(0.01, 1.0);
                c.water = (water - params.evaporation * evaporation_scale * dt).max(0.0);
                v.evaporation += f64::from(water) - f64::from(c.water);
                let velocity =
                    [0.5 * (flux[0] - flux[2]) / (cs * cs), 0.5 * (flux[1] - flux[3]) / (cs * cs)];
                if params.slippage {
                    let unclamped = c.sand - slip.iter().sum::<f32>();
                    let room = c.ceiling - c.bedrock - c.water;
                    let sand = unclamped.min(room).max(0.0);
                    v.sand_clamped += f64::from(unclamped) - f64::from(sand);
                    c.sand = sand;
                }
                let petrified = (params.petrification * dt * c.sand).min(c.sand);
                c.bedrock += petrified;
                c.sand -= petrified;
                let unclamped = sed - scale * sediment_flux.iter().sum::<f32>();
                // Below f32's normal range sediment is flushed to 0: subnormal arithmetic is slow.
                let new_sediment = if unclamped < f32::MIN_POSITIVE { 0.0 } else { unclamped };
                v.sediment_clamped += f64::from(new_sediment) - f64::from(unclamped);
                v.fit(&mut c);
                // SAFETY: as above.
                unsafe {
                    columns.set(s, c);
                    sediment.set(s, new_sediment);
                    velocities.set(s, velocity);
                }
            }
        }
        v
    })
}
