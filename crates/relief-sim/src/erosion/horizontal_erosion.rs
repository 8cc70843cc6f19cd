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

use super::lanes::{avx2_dispatch, load, load2, map4, store, Column, LaneMask, Lanes, Real, LANES};
use super::one_column::{along_row, neighbourhood_run};
use super::slots::{fit_column, neighbours, opposite, par_rows, smoothstep, Slots, OFFSETS};
use super::{ErosionParams, ErosionState, StepVolumes};
use relief_core::MlhmColumn;
use std::ops::Range;

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

/// The step's constants of horizontal erosion.
struct Constants {
    cs: f32,
    /// `dt / cell²`.
    integration: f32,
    /// `rise² > steep` (with `rise > 0`) exactly when `sin(atan2(rise, cs))` exceeds the
    /// minimum slope `m`: `steep = m² cs² / (1 - m²)`.
    steep: f32,
    min_slope: f32,
    strength: f32,
}

impl Constants {
    fn new(params: &ErosionParams, cs: f32) -> Self {
        let m = params.min_horizontal_erosion_slope;
        Constants {
            cs,
            integration: params.dt / (cs * cs),
            steep: m * m * cs * cs / (1.0 - m * m),
            min_slope: m,
            strength: params.horizontal_erosion_strength,
        }
    }

    /// Whether bedrock rising `rise` above the neighbour's sand is steep enough to erode.
    #[inline(always)]
    fn steep<R: Real>(&self, rise: R) -> R::Mask {
        R::and(rise.gt(R::splat(0.0)), (rise * rise).gt(R::splat(self.steep)))
    }

    /// The erosion of bedrock top `bedrock` in direction `d` into the window
    /// `[bottom, top]` beside the neighbour column `nc` (ceiling `n_ceiling`, water velocity
    /// `velocity`): 0 where the bedrock does not rise steeply enough above `nc`'s sand.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn erosion<R: Real>(
        &self,
        bedrock: R,
        nc: Column<R>,
        n_ceiling: R,
        [bottom, top]: [R; 2],
        [vx, vy]: [R; 2],
        d: usize,
    ) -> R {
        let splat = R::splat;
        let rise = bedrock - nc.solid_top();
        let steep = self.steep(rise);
        let sine = rise / (rise * rise + splat(self.cs * self.cs)).sqrt();
        let slope_scale = smoothstep(self.min_slope, 1.0, sine) * sine;
        let speed = (vx * vx + vy * vy).sqrt();
        let (ox, oy) = OFFSETS[d];
        let along = (splat(ox as f32) * vx + splat(oy as f32) * vy) / (speed + splat(f32::EPSILON));
        let attenuation = splat(0.5) - splat(0.5) * along;
        let area = (top - bottom) * splat(self.cs);
        let e = splat(self.strength)
            * slope_scale
            * speed
            * attenuation
            * area
            * splat(self.integration);
        let e = e.min(splat(0.25) * (n_ceiling - nc.water_top())).max(splat(0.0));
        R::select(steep, e, splat(0.0))
    }
}

/// Limits `erosions` so the damage `damage` does not outgrow the window `split`; returns
/// them and the new damage.
#[inline(always)]
fn limit<R: Real>(erosions: [R; 4], split: [R; 2], damage: R) -> ([R; 4], R) {
    let sum = |e: [R; 4]| e[0] + e[1] + e[2] + e[3];
    let total = sum(erosions);
    let limit = ((split[1] - split[0] - damage) / (total + R::splat(f32::EPSILON))).clamp(0.0, 1.0);
    let erosions = map4(erosions, |e| e * limit);
    (erosions, damage + sum(erosions))
}

/// A row's records: whether they are written (see `record_erosions`), and whether a column
/// of the row eroded.
struct RowRecords {
    write: bool,
    eroded: bool,
}

/// Computes each column's erosions, their receivers, its damage and its split window;
/// returns the sand the erosions create, and in `splits` the number of columns with a window.
fn record_erosions(state: &mut ErosionState, params: &ErosionParams) -> StepVolumes {
    let (width, height, cells, cs) = (state.width, state.height, state.cells(), state.cell_size);
    let counts = &state.layer_counts;
    let columns = &state.columns;
    let scratch = &mut state.scratch;
    let fast = scratch.fast_paths;
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
    let k = Constants::new(params, cs);
    par_rows(height, |y| {
        let v = StepVolumes::default();
        // A row whose columns erode nothing (no window) leaves its records at their defaults
        // (no erosion, no window), written once when the row stops eroding: the kernels that
        // read the records see the same values, and most rows skip the writes.
        // SAFETY (eroded_rows): entry `y` is this row's only.
        let write = unsafe { eroded_rows.get(y) };
        // SAFETY: slot `s` belongs to a cell of this row.
        let clear = |s: usize| unsafe {
            splits.set(s, [f32::NAN; 2]);
            erosions_out.set(s, [0.0; 4]);
            targets_out.set(s, [-1; 4]);
        };
        // The records of all columns of cells `cells` (of this row) to their defaults.
        let clear_cells = |cells_of_row: Range<usize>| {
            for j in cells_of_row {
                for jk in 0..usize::from(counts[j]) {
                    clear(j + jk * cells);
                }
            }
        };
        let cell = |(row, v): &mut (RowRecords, StepVolumes), x: usize| {
            let i = x + y * width;
            let near = neighbours(x, y, width, height);
            let mut floor = f32::NEG_INFINITY;
            for layer in 0..usize::from(counts[i]) {
                let s = i + layer * cells;
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
                            targets[d] = nk as i8;
                            let window = [bottom, top];
                            if !k.steep(c.bedrock - nc.solid_top()) {
                                // No erosion: skip the formula that would give 0.
                                break;
                            }
                            let e = k.erosion(
                                c.bedrock,
                                nc.into(),
                                nc.ceiling,
                                window,
                                velocities[ns],
                                d,
                            );
                            erosions[d] = e;
                            if e > strongest {
                                strongest = e;
                                split = window;
                            }
                            break;
                        }
                    }
                }
                // SAFETY: slot `s` belongs to cell (x, y) of this row only.
                let (erosions, damage) = limit(erosions, split, unsafe { damages.get(s) });
                v.horizontal_erosion_sand += erosions.iter().map(|&e| f64::from(e)).sum::<f64>();
                if strongest <= 0.0 {
                    // Nothing eroded: no window to split at.
                    split = [f32::NAN; 2];
                } else {
                    v.splits += 1;
                    if !row.write {
                        // The row's earlier columns eroded nothing: their defaults.
                        row.write = true;
                        clear_cells(y * width..i);
                        for jk in 0..layer {
                            clear(i + jk * cells);
                        }
                    }
                    row.eroded = true;
                }
                // SAFETY: as above.
                unsafe {
                    damages.set(s, damage);
                    if row.write {
                        splits.set(s, split);
                        erosions_out.set(s, erosions);
                        targets_out.set(s, targets);
                    }
                }
                floor = c.ceiling;
            }
        };
        let start = y * width;
        let run = |x| if fast { neighbourhood_run(counts, width, height, y, x) } else { 0 };
        let lanes = |(row, v): &mut (RowRecords, StepVolumes), cells: Range<usize>| {
            // Lanes are never in the first or last row.
            let band = start - width..start + 2 * width;
            // SAFETY: the slots of row `y`'s lowest columns belong to this row only.
            let out = unsafe {
                OneColumnRow {
                    damage: damages.row(start, width),
                    splits: splits.row(start, width),
                    erosions: erosions_out.row(start, width),
                    targets: targets_out.row(start, width),
                }
            };
            let near =
                Near { columns: &columns[band.clone()], velocities: &velocities[band.clone()] };
            if let Some(x) = one_column_erosions(&k, near, out, cells, row, v) {
                clear_cells(start..start + x);
            }
        };
        let mut state = (RowRecords { write, eroded: false }, v);
        along_row(width, &mut state, run, lanes, cell);
        let (row, v) = state;
        // SAFETY: as above.
        unsafe { eroded_rows.set(y, row.eroded) };
        v
    })
}

/// The lowest columns and water velocities of the rows below, at and above a row.
struct Near<'a> {
    columns: &'a [MlhmColumn],
    velocities: &'a [[f32; 2]],
}

/// Whether lanes of bedrock tops `bedrock` have a window in direction `d` (towards the lanes
/// of one-column cells from `n` on in `near`), their erosion (0 without a window) and the
/// window.
#[inline(always)]
fn towards(
    k: &Constants,
    near: &Near,
    bedrock: Lanes,
    d: usize,
    n: usize,
) -> (LaneMask, Lanes, [Lanes; 2]) {
    let nc = Column::load(&near.columns[n..]);
    // Below the lowest column the floor is -inf: the window starts at the sand top.
    let window = [nc.solid_top(), bedrock.min(nc.water_top())];
    let open = (window[1] - window[0]).gt(Lanes::splat(0.0));
    let infinity = Lanes::splat(f32::INFINITY);
    let e = k.erosion(bedrock, nc, infinity, window, load2(&near.velocities[n..]), d);
    (open, Lanes::select(open, e, Lanes::splat(0.0)), window)
}

/// The damage and the records of one row's lowest columns.
struct OneColumnRow<'a> {
    damage: &'a mut [f32],
    splits: &'a mut [[f32; 2]],
    erosions: &'a mut [[f32; 4]],
    targets: &'a mut [[i8; 4]],
}

avx2_dispatch! {
/// Horizontal erosion's records for the cells `cells` of a row, [`LANES`] at a time, where
/// they and their neighbours hold one column each ([`neighbourhood_run`]): every neighbour
/// has one column, under a `+inf` ceiling. Returns the cell (of the row) from which on it
/// started writing the row's records (see `record_erosions`): the records of the cells
/// before it are for the caller to set to their defaults.
fn one_column_erosions(
    k: &Constants,
    near: Near,
    out: OneColumnRow,
    cells: Range<usize>,
    row: &mut RowRecords,
    v: &mut StepVolumes,
) -> Option<usize> {
    let width = out.damage.len();
    let (at, above) = (width, 2 * width);
    let mut started = None;
    for x in cells.step_by(LANES) {
        let c = Column::load(&near.columns[at + x..]);
        let found = [
            towards(k, &near, c.bedrock, 0, at + x + 1),
            towards(k, &near, c.bedrock, 1, above + x),
            towards(k, &near, c.bedrock, 2, at + x - 1),
            towards(k, &near, c.bedrock, 3, x),
        ];
        let mut strongest = Lanes::splat(0.0);
        let mut split = [Lanes::splat(f32::NEG_INFINITY), c.bedrock];
        for (_, e, window) in found {
            let stronger = e.gt(strongest);
            strongest = Lanes::select(stronger, e, strongest);
            split = [
                Lanes::select(stronger, window[0], split[0]),
                Lanes::select(stronger, window[1], split[1]),
            ];
        }
        let erosions = map4(found, |f| f.1);
        let windows = map4(found, |f| f.0);
        let (erosions, damage) = limit(erosions, split, load(&out.damage[x..]));
        store(&mut out.damage[x..], damage);
        if !row.write && strongest.0.iter().all(|&e| e <= 0.0) {
            // Nothing eroded (every erosion is 0) and no record to write: the common case.
            continue;
        }
        for l in 0..LANES {
            let e = map4(erosions, |e| e.0[l]);
            v.horizontal_erosion_sand += e.iter().map(|&e| f64::from(e)).sum::<f64>();
            let eroded = strongest.0[l] > 0.0;
            if eroded {
                v.splits += 1;
                if !row.write {
                    // The row's earlier columns eroded nothing: their defaults (those before
                    // these lanes by the caller, who knows all their columns).
                    row.write = true;
                    started = Some(x);
                    out.splits[x..x + l].fill([f32::NAN; 2]);
                    out.erosions[x..x + l].fill([0.0; 4]);
                    out.targets[x..x + l].fill([-1; 4]);
                }
                row.eroded = true;
            }
            if row.write {
                let s = x + l;
                out.splits[s] = if eroded { [split[0].0[l], split[1].0[l]] } else { [f32::NAN; 2] };
                out.erosions[s] = e;
                out.targets[s] = map4(windows, |w| if w.get(l) { 0 } else { -1 });
            }
        }
    }
    started
}
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
