//! Step 6, the support check (reference: `support.cu`): stability propagates from the ground
//! through bedrock contacts in checkerboard passes; after enough passes to cross
//! `support_distance`, what is unsupported collapses onto the column below as sand.
//!
//! A check starts with every cell's lowest column at [`GROUND_STABILITY`] and the others at 0.
//! A pass updates the columns above the ground of one colour of the checkerboard, reading
//! only the other colour (so the result does not depend on the order or the threads): a
//! column's support is the best over the neighbouring columns whose bedrock overlaps its own
//! (from its floor to its bedrock top) of `min(cell overlap² / thickness bedrock_support,
//! neighbour's stability)`; its stability is `max(support - weight, previous)` with weight
//! `(bedrock_density thickness + sand_density sand + water_density water) cell²`. A wall of
//! the domain supports `cell thickness border_support` (the reference computes this term, then
//! overwrites it).
//!
//! The end of a check visits each cell's columns top down: a column above the ground collapses
//! when its stability is <= 0, its bedrock is at most `min_bedrock_thickness` thick, or the
//! column below leaves less than `0.05 split_damage` between its bedrock and ceiling. What
//! collapses falls onto the next standing column below: bedrock (less the damage it still owes,
//! which is removed) and sand as sand, water as water, sediment as sediment, and that column's
//! ceiling rises to the collapsed one's. A column collapsing onto a column too close beneath
//! merges with it: the lower column's sand becomes bedrock and the fallen bedrock stays bedrock.

use super::slots::{neighbour, par_rows, Slots};
use super::{ErosionParams, ErosionState, StepVolumes, GROUND_STABILITY};
use relief_core::MlhmColumn;

/// Starts a check: ground columns stable, all others not yet supported.
pub fn start_support_check(state: &mut ErosionState) {
    let (width, cells) = (state.width, state.cells());
    let counts = &state.layer_counts;
    let stability = Slots::new(&mut state.stability);
    par_rows(state.height, |y| {
        for x in 0..width {
            let i = x + y * width;
            for k in 0..usize::from(counts[i]) {
                let value = if k == 0 { GROUND_STABILITY } else { 0.0 };
                // SAFETY: slots of cell (x, y) are this row's only.
                unsafe { stability.set(i + k * cells, value) };
            }
        }
        StepVolumes::default()
    });
}

/// One propagation pass: both colours of the checkerboard, one after the other. Only cells
/// with a column above the ground change, so rows without one are skipped.
pub fn support_pass(state: &mut ErosionState, params: &ErosionParams) {
    support_passes(state, params, 1);
}

/// `passes` propagation passes (as [`support_pass`]).
pub(crate) fn support_passes(state: &mut ErosionState, params: &ErosionParams, passes: u32) {
    let width = state.width;
    let mut rows = std::mem::take(&mut state.scratch.layered_rows);
    rows.clear();
    rows.extend(
        state.layer_counts.chunks_exact(width).map(|row| row.iter().fold(0, |m, &n| m.max(n)) > 1),
    );
    if rows.contains(&true) {
        for _ in 0..passes {
            half_pass(state, params, &rows, 0);
            half_pass(state, params, &rows, 1);
        }
    }
    state.scratch.layered_rows = rows;
}

/// Updates the columns of the cells with `(x + y + colour)` even, in the rows `layered` marks.
fn half_pass(state: &mut ErosionState, params: &ErosionParams, layered: &[bool], colour: usize) {
    let (width, height, cells, cs) = (state.width, state.height, state.cells(), state.cell_size);
    let counts = &state.layer_counts;
    let columns = &state.columns;
    let stability = Slots::new(&mut state.stability);
    let area = cs * cs;
    par_rows(height, |y| {
        if !layered[y] {
            return StepVolumes::default();
        }
        for x in ((y + colour) % 2..width).step_by(2) {
            let i = x + y * width;
            let n = usize::from(counts[i]);
            if n < 2 {
                continue;
            }
            let mut own_floor = columns[i].ceiling;
            for k in 1..n {
                let s = i + k * cells;
                let c = columns[s];
                let top = c.bedrock;
                // SAFETY: slot `s` is this cell's; this pass writes no other colour's slots,
                // and reads of neighbours below touch only the other colour.
                let mut previous = unsafe { stability.get(s) };
                if previous == GROUND_STABILITY {
                    previous = 0.0;
                }
                let thickness = top - own_floor;
                let inverse = if thickness > f32::EPSILON { 1.0 / thickness } else { 0.0 };
                let weight = (thickness * params.bedrock_density
                    + c.sand * params.sand_density
                    + c.water * params.water_density)
                    .max(0.0)
                    * area;
                let mut support = 0.0f32;
                for d in 0..4 {
                    let Some(n) = neighbour(x, y, d, width, height) else {
                        support = support.max(cs * thickness.max(0.0) * params.border_support);
                        continue;
                    };
                    let mut n_floor = f32::NEG_INFINITY;
                    for nk in 0..usize::from(counts[n]) {
                        let ns = n + nk * cells;
                        let nc = columns[ns];
                        let overlap = nc.bedrock.min(top) - n_floor.max(own_floor);
                        if overlap > 0.0 {
                            // SAFETY: the neighbour is of the other colour, written by no one
                            // during this pass.
                            let n_stability = unsafe { stability.get(ns) };
                            let carried = cs * overlap * overlap * inverse * params.bedrock_support;
                            support = support.max(carried.min(n_stability));
                        }
                        n_floor = nc.ceiling;
                    }
                }
                // SAFETY: as above.
                unsafe { stability.set(s, (support - weight).max(previous)) };
                own_floor = c.ceiling;
            }
        }
        StepVolumes::default()
    });
}

/// Ends a check: collapses what is unsupported, too thin or too close; returns the damage
/// removed with collapsing columns and the number of collapses.
pub fn end_support_check(state: &mut ErosionState, params: &ErosionParams) -> StepVolumes {
    let (width, height, cells, max_layers) =
        (state.width, state.height, state.cells(), state.max_layers);
    let counts = Slots::new(&mut state.layer_counts);
    let columns = Slots::new(&mut state.columns);
    let fluxes = Slots::new(&mut state.fluxes);
    let stability = Slots::new(&mut state.stability);
    let sediments = Slots::new(&mut state.sediment);
    let damages = Slots::new(&mut state.damage);
    let too_close_gap = 0.05 * params.split_damage;
    par_rows(height, |y| {
        let mut v = StepVolumes::default();
        let mut cell: Vec<(MlhmColumn, [f32; 4], f32, f32, f32)> = Vec::with_capacity(max_layers);
        for x in 0..width {
            let i = x + y * width;
            // SAFETY (every access below): slots of cell (x, y) are this row's only.
            let n = usize::from(unsafe { counts.get(i) });
            if n < 2 {
                continue;
            }
            cell.clear();
            for k in 0..n {
                let s = i + k * cells;
                unsafe {
                    cell.push((
                        columns.get(s),
                        fluxes.get(s),
                        stability.get(s),
                        sediments.get(s),
                        damages.get(s),
                    ));
                }
            }
            let mut keep = vec![true; n];
            // Material falling from the columns above: bedrock, sand, water, sediment.
            let (mut fall_bedrock, mut fall_sand, mut fall_water, mut fall_sediment) =
                (0.0f32, 0.0, 0.0, 0.0);
            let mut fallen_ceiling: Option<f32> = None;
            let mut merge = false;
            for k in (0..n).rev() {
                let (below_ceiling, below_bedrock) = if k > 0 {
                    (cell[k - 1].0.ceiling, cell[k - 1].0.bedrock)
                } else {
                    (f32::NEG_INFINITY, f32::NEG_INFINITY)
                };
                let (c, _, stab, sed, damage) = &mut cell[k];
                if merge {
                    c.bedrock += c.sand + fall_bedrock;
                    c.sand = fall_sand;
                } else {
                    c.sand += fall_bedrock + fall_sand;
                }
                c.water += fall_water;
                *sed += fall_sediment;
                if let Some(ceiling) = fallen_ceiling.take() {
                    c.ceiling = ceiling;
                }
                (fall_bedrock, fall_sand, fall_water, fall_sediment) = (0.0, 0.0, 0.0, 0.0);
                merge = false;
                if k == 0 {
                    break;
                }
                let too_close = below_ceiling - below_bedrock < too_close_gap;
                let too_thin = c.bedrock - below_ceiling <= params.min_bedrock_thickness;
                if too_thin || too_close || *stab <= 0.0 {
                    let bedrock = (c.bedrock - below_ceiling).max(0.0);
                    let owed = damage.min(bedrock);
                    v.collapse_damage += f64::from(owed);
                    fall_bedrock = bedrock - owed;
                    fall_sand = c.sand;
                    fall_water = c.water;
                    fall_sediment = *sed;
                    fallen_ceiling = Some(c.ceiling);
                    merge = too_close;
                    keep[k] = false;
                    v.collapses += 1;
                }
            }
            let mut kept = 0;
            for k in 0..n {
                if !keep[k] {
                    continue;
                }
                let (mut c, flux, stab, sed, damage) = cell[k];
                v.fit(&mut c);
                let s = i + kept * cells;
                unsafe {
                    columns.set(s, c);
                    fluxes.set(s, flux);
                    stability.set(s, stab);
                    sediments.set(s, sed);
                    damages.set(s, damage);
                }
                kept += 1;
            }
            for k in kept..n {
                let s = i + k * cells;
                unsafe {
                    columns.set(s, MlhmColumn::default());
                    fluxes.set(s, [0.0; 4]);
                    stability.set(s, 0.0);
                    sediments.set(s, 0.0);
                    damages.set(s, 0.0);
                }
            }
            unsafe { counts.set(i, kept as u8) };
        }
        v
    })
}
