//! Step 4a, horizontal erosion (reference: `erosion.cu`, `horizontalErosionKernel`): water
//! flowing past a column's bedrock wears it sideways. For each direction, the topmost column
//! of the neighbouring cell whose water overlaps this column's bedrock (above its floor)
//! exposes the window `[max(floor, neighbour sand top), min(bedrock, neighbour water top)]`;
//! it erodes `strength s(slope) |v| (1 - v̂·n)/2 window cell dt / cell²` metres, with
//! `s = smoothstep(min slope, 1, sin) sin` of the bedrock's height over the neighbour's sand.
//! The eroded bedrock becomes sand in the neighbour column at once, and the column records it
//! as damage (bedrock owed) until damage recovery or a split removes it. Erosion stops when
//! the damage reaches the window, and (unlike the reference) each erosion is at most a quarter
//! of the receiving column's free space, so the sand fits.
//!
//! The reference adds the sand with atomics; here each column first records its erosion per
//! direction, then each column gathers what its neighbours sent it, in a fixed order.

use super::slots::{fit_column, neighbours, opposite, par_rows, smoothstep, Slots, OFFSETS};
use super::{ErosionParams, ErosionState, StepVolumes};

/// Erodes bedrock sideways into neighbouring water; returns the sand created and whether
/// any column has a window to split at.
pub(crate) fn horizontal_erosion(
    state: &mut ErosionState,
    params: &ErosionParams,
) -> (StepVolumes, bool) {
    let mut volumes = record_erosions(state, params);
    // `splits` counts the columns with a window here; the split kernel counts splits.
    let windows = volumes.splits > 0;
    volumes.splits = 0;
    if volumes.horizontal_erosion_sand > 0.0 {
        volumes.add(&gather_sand(state));
    }
    (volumes, windows)
}

/// Computes each column's erosions, their receivers, its damage and its split window;
/// returns the sand the erosions create, and in `splits` the number of columns with a window.
fn record_erosions(state: &mut ErosionState, params: &ErosionParams) -> StepVolumes {
    let (width, height, cells, cs) = (state.width, state.height, state.cells(), state.cell_size);
    let counts = &state.layer_counts;
    let columns = &state.columns;
    let scratch = &mut state.scratch;
    let velocities = &scratch.velocities;
    let damages = Slots::new(&mut state.damage);
    let splits = Slots::new(&mut scratch.splits);
    let erosions_out = Slots::new(&mut scratch.erosions);
    let targets_out = Slots::new(&mut scratch.erosion_targets);
    if scratch.eroded_rows.len() != height {
        // A new state: every row's records are written.
        scratch.eroded_rows = vec![true; height];
    }
    let eroded_rows = Slots::new(&mut scratch.eroded_rows);
    let integration = params.dt / (cs * cs);
    let eps = f32::EPSILON;
    // sin(atan2(rise, cs)) > m exactly when rise > 0 and rise² > m² cs² / (1 - m²).
    let m = params.min_horizontal_erosion_slope;
    let steep = m * m * cs * cs / (1.0 - m * m);
    par_rows(height, |y| {
        let mut v = StepVolumes::default();
        // A row whose columns erode nothing (no window) leaves its records at their defaults
        // (no erosion, no window), written once when the row stops eroding: the kernels that
        // read the records see the same values, and most rows skip the writes.
        // SAFETY (eroded_rows): entry `y` is this row's only.
        let mut write = unsafe { eroded_rows.get(y) };
        // SAFETY: slot `s` belongs to a cell of this row.
        let clear = |s: usize| unsafe {
            splits.set(s, [f32::NAN; 2]);
            erosions_out.set(s, [0.0; 4]);
            targets_out.set(s, [-1; 4]);
        };
        let mut eroded = false;
        for x in 0..width {
            let i = x + y * width;
            let near = neighbours(x, y, width, height);
            let mut floor = f32::NEG_INFINITY;
            for k in 0..usize::from(counts[i]) {
                let s = i + k * cells;
                let c = columns[s];
                let mut erosions = [0.0f32; 4];
                let mut targets = [-1i8; 4];
                let mut strongest = 0.0f32;
                let mut split = [floor, c.bedrock];
                for d in 0..4 {
                    let Some(n) = near[d] else { continue };
                    for nk in (0..usize::from(counts[n])).rev() {
                        let ns = n + nk * cells;
                        let nc = columns[ns];
                        let bottom = floor.max(nc.solid_top());
                        let top = c.bedrock.min(nc.water_top());
                        if top - bottom > 0.0 {
                            let rise = c.bedrock - nc.solid_top();
                            targets[d] = nk as i8;
                            if rise <= 0.0 || rise * rise <= steep {
                                break;
                            }
                            let sine = rise / (rise * rise + cs * cs).sqrt();
                            let slope_scale =
                                smoothstep(params.min_horizontal_erosion_slope, 1.0, sine) * sine;
                            let [vx, vy] = velocities[ns];
                            let speed = (vx * vx + vy * vy).sqrt();
                            let (ox, oy) = OFFSETS[d];
                            let along = (ox as f32 * vx + oy as f32 * vy) / (speed + eps);
                            let attenuation = 0.5 - 0.5 * along;
                            let area = (top - bottom) * cs;
                            let e = params.horizontal_erosion_strength
                                * slope_scale
                                * speed
                                * attenuation
                                * area
                                * integration;
                            let e = e.min(0.25 * (nc.ceiling - nc.water_top())).max(0.0);
                            erosions[d] = e;
                            if e > strongest {
                                strongest = e;
                                split = [bottom, top];
                            }
                            break;
                        }
                    }
                }
                // SAFETY: slot `s` belongs to cell (x, y) of this row only.
                let mut damage = unsafe { damages.get(s) };
                let total: f32 = erosions.iter().sum();
                let limit = ((split[1] - split[0] - damage) / (total + eps)).clamp(0.0, 1.0);
                for e in &mut erosions {
                    *e *= limit;
                }
                damage += erosions.iter().sum::<f32>();
                v.horizontal_erosion_sand += erosions.iter().map(|&e| f64::from(e)).sum::<f64>();
                if strongest <= 0.0 {
                    // Nothing eroded: no window to split at.
                    split = [f32::NAN; 2];
                } else {
                    v.splits += 1;
                    if !write {
                        // The row's earlier columns eroded nothing: their defaults.
                        write = true;
                        for (j, &count) in counts.iter().enumerate().take(i).skip(y * width) {
                            for jk in 0..usize::from(count) {
                                clear(j + jk * cells);
                            }
                        }
                        for jk in 0..k {
                            clear(i + jk * cells);
                        }
                    }
                    eroded = true;
                }
                // SAFETY: as above.
                unsafe {
                    damages.set(s, damage);
                    if write {
                        splits.set(s, split);
                        erosions_out.set(s, erosions);
                        targets_out.set(s, targets);
                    }
                }
                floor = c.ceiling;
            }
        }
        // SAFETY: as above.
        unsafe { eroded_rows.set(y, eroded) };
        v
    })
}

/// Adds to each column the sand its neighbours eroded into it.
fn gather_sand(state: &mut ErosionState) -> StepVolumes {
    let (width, height, cells) = (state.width, state.height, state.cells());
    let counts = &state.layer_counts;
    let erosions = &state.scratch.erosions;
    let targets = &state.scratch.erosion_targets;
    let columns = Slots::new(&mut state.columns);
    par_rows(height, |y| {
        let mut v = StepVolumes::default();
        for x in 0..width {
            let i = x + y * width;
            let near = neighbours(x, y, width, height);
            for k in 0..usize::from(counts[i]) {
                let s = i + k * cells;
                let mut received = 0.0f32;
                for (d, &n) in near.iter().enumerate() {
                    let Some(n) = n else { continue };
                    let back = opposite(d);
                    for nk in 0..usize::from(counts[n]) {
                        let ns = n + nk * cells;
                        if targets[ns][back] == k as i8 {
                            received += erosions[ns][back];
                        }
                    }
                }
                if received > 0.0 {
                    // SAFETY: slot `s` belongs to cell (x, y) of this row only.
                    let mut c = unsafe { columns.get(s) };
                    let before = c.sand;
                    c.sand += received;
                    let (water, sand) = fit_column(&mut c);
                    let exact = f64::from(before) + f64::from(received);

                    v.water_clamped += f64::from(water);
                    // What f32 rounding of the sum lost counts as clamped.
                    v.sand_clamped += f64::from(sand) + exact - f64::from(before + received);
                    // SAFETY: as above.
                    unsafe { columns.set(s, c) };
                }
            }
        }
        v
    })
}
