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

use super::slots::{neighbours, par_rows, Slots};
use super::{ErosionParams, ErosionState, StepVolumes};

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
    let dt = params.dt;
    let area = cs * cs;
    let inverse_range = 1.0 / params.slippage_interpolation_range;
    let flow = dt * params.gravity * cs;
    let taken_scale = dt / area;

    let damping = 1.0 - params.flux_damping * dt;
    let dry = params.dry_talus_angle.to_radians().tan();
    let wet = params.wet_talus_angle.to_radians().tan();
    let eps = f32::EPSILON;
    par_rows(height, |y| {
        for x in 0..width {
            let i = x + y * width;
            let near = neighbours(x, y, width, height);
            for k in 0..usize::from(counts[i]) {
                let s = i + k * cells;
                let c = columns[s];
                let sand = c.solid_top();
                let water = c.water_top();
                // SAFETY: slot `s` belongs to cell (x, y) of this row only.
                let old = unsafe { fluxes.get(s) };
                // The pipe in direction `d`: (flux, slippage, neighbour's layer or -1,
                // neighbour's sand top or this column's). Called with constant directions so
                // the four stay in registers.
                let pipe_to = |d: usize| {
                    if let Some(n) = near[d] {
                        for nk in 0..usize::from(counts[n]) {
                            let nc = columns[n + nk * cells];
                            let n_water = nc.water_top();
                            if c.bedrock < nc.ceiling && n_water + eps < nc.ceiling {
                                let dh = water.min(nc.ceiling) - n_water.max(sand);
                                let mut f = (damping * old[d] + flow * dh).max(0.0);
                                if nc.ceiling.is_finite() {
                                    let free = 0.25 * (nc.ceiling - n_water).max(0.0);
                                    f *= ratio(free, f * taken_scale + eps);
                                }
                                let mean_water = 0.5 * (c.water + nc.water);
                                let t = (mean_water * inverse_range).min(1.0);
                                let talus = dry + (wet - dry) * t;
                                let excess =
                                    params.slippage_rate * (sand - nc.solid_top() - talus * cs);
                                let slip =
                                    excess.max(0.0).min(0.25 * (nc.ceiling - n_water)).max(0.0);
                                return (f, slip, nk as i8, nc.solid_top());
                            }
                        }
                    }
                    (0.0, 0.0, -1, sand)
                };
                let p = [pipe_to(0), pipe_to(1), pipe_to(2), pipe_to(3)];
                let mut flux = p.map(|p| p.0);
                let mut slip = p.map(|p| p.1);
                let pipe = p.map(|p| p.2);
                let tops = p.map(|p| p.3);
                let slope = slope_sine(tops, cs);
                let out = (flux[0] + flux[1] + flux[2] + flux[3]) * dt;
                let scale = ratio(c.water * area, out + eps);
                // A scale of exactly 1 leaves the fluxes as they are: no branch.
                for f in &mut flux {
                    *f *= scale;
                }
                let out = (flux[0] + flux[1] + flux[2] + flux[3]) * dt;
                let sediment_scale = ratio(sediment[s] * area, out + eps);
                let slipped = slip[0] + slip[1] + slip[2] + slip[3];
                let slip_scale = ratio(c.sand, slipped + eps);
                for v in &mut slip {
                    *v *= slip_scale;
                }
                // SAFETY: slot `s` belongs to cell (x, y) of this row only.
                unsafe {
                    fluxes.set(s, flux);
                    pipes.set(s, pipe);
                    slippages.set(s, if params.slippage { slip } else { [0.0; 4] });
                    sediment_scales.set(s, sediment_scale);
                    slopes.set(s, slope);
                }
            }
        }
        StepVolumes::default()
    });
}

/// `min(a / b, 1)` for `b > 0`: exactly 1 when `a >= b`. Divides either way, so the
/// comparison is a select rather than a branch the data makes unpredictable.
#[inline]
fn ratio(a: f32, b: f32) -> f32 {
    let q = a / b;
    if a >= b {
        1.0
    } else {
        q
    }
}

/// sin of the slope of the surface through the four neighbouring sand tops `tops` (right,
/// up, left, down) at spacing `cs`, from the cross product of the two central-difference
/// tangents, as the reference computes it.
fn slope_sine(tops: [f32; 4], cs: f32) -> f32 {
    let a = 2.0 * cs;
    let bx = tops[0] - tops[2];
    let by = tops[1] - tops[3];
    // Tangents (a, bx, 0) and (0, by, a), normalised; the normal's second component is
    // -t0.x * t1.z = -a² / sqrt((a² + bx²)(a² + by²)), and the reference takes
    // sqrt(1 - n.y²) as sin(alpha).
    let a2 = a * a;
    let ny2 = a2 * a2 / ((a2 + bx * bx) * (a2 + by * by));
    (1.0 - ny2).max(0.0).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slope_of_a_plane() {
        assert_eq!(slope_sine([1.0; 4], 1.0), 0.0);
        // 45 degrees along x: sin = 1/sqrt 2.
        let s = slope_sine([1.0, 0.0, -1.0, 0.0], 1.0);
        assert!((s - std::f32::consts::FRAC_1_SQRT_2).abs() < 1e-6, "{s}");
    }
}
