//! Step 5, vertical erosion and deposition (reference: `erosion.cu`, `sedimentKernel`).
//!
//! Per column with water: slope factor `min + (max - min) sin a (1 - smoothstep(fade, 1,
//! sin a))`, speed factor `min_speed + (1 - min_speed) |v|`, water factor
//! `1 - tanh(2 depth / erosion_water_max_height)` (as `2 / (e^2y + 1)`). The sediment capacity is
//! `sediment_capacity` times the three; bedrock under less than `sand_threshold` of sand
//! dissolves into sand at `bedrock_dissolving` times the three; water within
//! `top_erosion_distance` of the ceiling wears the ceiling (the bedrock of the column above)
//! into sand. Below capacity, sand dissolves into sediment at `sand_dissolving (capacity -
//! sediment)`; above, sediment deposits as sand at `deposition (sediment - capacity)`, at
//! most the free space. A dry column erodes nothing and deposits its sediment. Then damage
//! recovers at `damage_recovery`, lowering the bedrock as much.

use super::lanes::{avx2_dispatch, exp, load, load2, store, Column, LaneMask, Lanes, Real, LANES};
use super::one_column::{along_row, row_run};
use super::slots::{par_rows, smoothstep, Slots};
use super::{ErosionParams, ErosionState, StepVolumes};
use relief_core::MlhmColumn;
use std::ops::Range;

/// The erosion factors of a column with water.
struct Factors<R> {
    slope: R,
    speed: R,
    speed_factor: R,
    water: R,
}

impl<R: Real> Factors<R> {
    /// The factors for slope sine `sine`, water velocity `velocity` and depth `water`.
    #[inline(always)]
    fn new(params: &ErosionParams, sine: R, velocity: [R; 2], water: R) -> Self {
        let splat = R::splat;
        let fade = smoothstep(params.slope_fade_start, 1.0, sine);
        let slope = splat(params.min_slope_erosion_scale)
            + splat(params.max_slope_erosion_scale - params.min_slope_erosion_scale)
                * sine
                * (splat(1.0) - fade);
        let [vx, vy] = velocity;
        let speed = (vx * vx + vy * vy).sqrt();
        let speed_factor = splat(params.min_speed_erosion_scale)
            + splat(1.0 - params.min_speed_erosion_scale) * speed;
        let water_scale = 2.0 / params.erosion_water_max_height;
        // 1 - tanh(y) = 2 / (e^2y + 1) for the depth's y >= 0.
        let y = water * splat(water_scale);
        let water = splat(2.0) / (exp(splat(2.0) * y) + splat(1.0));
        Factors { slope, speed, speed_factor, water }
    }

    /// The sediment the water can carry.
    #[inline(always)]
    fn capacity(&self, params: &ErosionParams) -> R {
        R::splat(params.sediment_capacity) * self.slope * self.speed_factor * self.water
    }
}

/// Dissolves the bedrock of `c` (above its floor `floor`) into sand, the less the more sand
/// covers it.
#[inline(always)]
fn dissolve_bedrock<R: Real>(
    params: &ErosionParams,
    c: Column<R>,
    floor: R,
    f: &Factors<R>,
) -> Column<R> {
    let splat = R::splat;
    let sand_cover = (splat(1.0) - c.sand / splat(params.sand_threshold)).max(splat(0.0));
    let rate = sand_cover * splat(params.bedrock_dissolving) * f.slope * f.speed_factor * f.water;
    let dissolved = (rate * splat(params.dt)).min((c.bedrock - floor).max(splat(0.0)));
    let bedrock = (c.bedrock - dissolved).max(floor);
    let some = dissolved.gt(splat(0.0));
    Column {
        bedrock: R::select(some, bedrock, c.bedrock),
        sand: R::select(some, c.sand + (c.bedrock - bedrock), c.sand),
        water: c.water,
    }
}

/// A column after the exchange of sand and sediment and the damage recovery.
struct Exchanged<R> {
    column: Column<R>,
    sediment: R,
    damage: R,
    /// The bedrock before the damage recovery lowered it.
    bedrock_before_recovery: R,
}

/// Below `capacity`, sand dissolves into the sediment `sed`; above, sediment settles as sand
/// (within the room under `ceiling`); then damage recovers, lowering the bedrock down to at
/// most the floor.
#[inline(always)]
fn exchange<R: Real>(
    params: &ErosionParams,
    mut c: Column<R>,
    [ceiling, floor]: [R; 2],
    sed: R,
    damage: R,
    capacity: R,
) -> Exchanged<R> {
    let splat = R::splat;
    let dt = splat(params.dt);
    // Both outcomes, then a select: whether the water is below capacity is unpredictable.
    let (eroded_sand, eroded_sed) = if params.vertical_erosion {
        let taken = (splat(params.sand_dissolving) * (capacity - sed) * dt).min(c.sand);
        (c.sand - taken, sed + taken)
    } else {
        (c.sand, sed)
    };
    let settled = (splat(params.deposition) * (sed - capacity) * dt)
        .min(ceiling - c.water_top())
        .min(sed - capacity)
        .max(splat(0.0));
    let erode = capacity.gt(sed);
    c.sand = R::select(erode, eroded_sand, c.sand + settled);
    let sediment = R::select(erode, eroded_sed, sed - settled);
    let recovered = splat(params.damage_recovery * params.dt)
        .min(damage.min(c.bedrock - floor))
        .max(splat(0.0));
    let recover = recovered.gt(splat(0.0));
    let before = c.bedrock;
    c.bedrock = R::select(recover, (c.bedrock - recovered).max(floor), c.bedrock);
    let damage = R::select(recover, damage - recovered, damage);
    Exchanged { column: c, sediment, damage, bedrock_before_recovery: before }
}

/// Erodes and deposits vertically in every column; recovers damage.
pub(crate) fn vertical_erosion(state: &mut ErosionState, params: &ErosionParams) -> StepVolumes {
    let (width, height, cells) = (state.width, state.height, state.cells());
    let counts = &state.layer_counts;
    let fast = state.scratch.fast_paths;
    let slopes = &state.scratch.slopes;
    let velocities = &state.scratch.velocities;
    let columns = Slots::new(&mut state.columns);
    let sediments = Slots::new(&mut state.sediment);
    let damages = Slots::new(&mut state.damage);
    let dt = params.dt;
    par_rows(height, |y| {
        let mut v = StepVolumes::default();
        let row = y * width..(y + 1) * width;
        let run = |x| if fast { row_run(counts, width, y, x) } else { 0 };
        let lanes = |v: &mut StepVolumes, cells| {
            // SAFETY: the slots of row `y`'s lowest columns belong to this row only.
            let out = unsafe {
                OneColumnRow {
                    columns: columns.row(row.start, width),
                    sediment: sediments.row(row.start, width),
                    damage: damages.row(row.start, width),
                }
            };
            let (slopes, velocities) = (&slopes[row.clone()], &velocities[row.clone()]);
            one_column_vertical(params, slopes, velocities, out, cells, v);
        };
        let cell = |v: &mut StepVolumes, x: usize| {
            let i = x + y * width;
            let n = usize::from(counts[i]);
            let mut floor = f32::NEG_INFINITY;
            for k in 0..n {
                let s = i + k * cells;
                // SAFETY (every access below): slots of cell (x, y) are this row's only.
                let (mut c, sed, damage) =
                    unsafe { (columns.get(s), sediments.get(s), damages.get(s)) };
                let wet = c.water > 0.0;
                if !wet && sed == 0.0 && damage == 0.0 {
                    // Nothing to erode, deposit or recover.
                    floor = c.ceiling;
                    continue;
                }
                let capacity = if wet {
                    let f = Factors::new(params, slopes[s], velocities[s], c.water);
                    if params.vertical_erosion {
                        if k + 1 < n {
                            let gap = c.ceiling - c.water_top();
                            let top_factor =
                                (1.0 - (gap / params.top_erosion_distance).max(0.0)).max(0.0);
                            let top_rate = params.bedrock_dissolving
                                * f.speed
                                * top_factor
                                * params.min_slope_erosion_scale;
                            let next_bedrock = unsafe { columns.get(s + cells) }.bedrock;
                            let worn = (top_rate * dt).min((next_bedrock - c.ceiling).max(0.0));
                            if worn > 0.0 {
                                let ceiling = (c.ceiling + worn).min(next_bedrock);
                                c.sand += ceiling - c.ceiling;
                                c.ceiling = ceiling;
                            }
                        }
                        let d = dissolve_bedrock(params, c.into(), floor, &f);
                        (c.bedrock, c.sand) = (d.bedrock, d.sand);
                    }
                    f.capacity(params)
                } else {
                    0.0
                };
                let e = exchange(params, c.into(), [c.ceiling, floor], sed, damage, capacity);
                v.damage_recovery +=
                    f64::from(e.bedrock_before_recovery) - f64::from(e.column.bedrock);
                let mut c = MlhmColumn::new(e.column.bedrock, e.column.sand, c.water, c.ceiling);
                v.fit(&mut c);
                unsafe {
                    columns.set(s, c);
                    sediments.set(s, e.sediment);
                    damages.set(s, e.damage);
                }
                floor = c.ceiling;
            }
        };
        along_row(width, &mut v, run, lanes, cell);
        v
    })
}

/// The state of one row's lowest columns that vertical erosion changes.
struct OneColumnRow<'a> {
    columns: &'a mut [MlhmColumn],
    sediment: &'a mut [f32],
    damage: &'a mut [f32],
}

avx2_dispatch! {
/// Vertical erosion in the one-column cells `cells` of a row ([`row_run`]), [`LANES`] at a
/// time.
fn one_column_vertical(
    params: &ErosionParams,
    slopes: &[f32],
    velocities: &[[f32; 2]],
    out: OneColumnRow,
    cells: Range<usize>,
    v: &mut StepVolumes,
) {
    let mut recovered = [0.0f64; LANES];
    for x in cells.step_by(LANES) {
        let cells = &mut out.columns[x..x + LANES];
        let c = Column::load(cells);
        let (sed, damage) = (load(&out.sediment[x..]), load(&out.damage[x..]));
        let wet = c.water.gt(Lanes::splat(0.0));
        let f = Factors::new(params, load(&slopes[x..]), load2(&velocities[x..]), c.water);
        let floor = Lanes::splat(f32::NEG_INFINITY);
        let eroding = if params.vertical_erosion {
            Column::select(wet, dissolve_bedrock(params, c, floor, &f), c)
        } else {
            c
        };
        let capacity = Lanes::select(wet, f.capacity(params), Lanes::splat(0.0));
        let ceiling = Lanes::splat(f32::INFINITY);
        let e = exchange(params, eroding, [ceiling, floor], sed, damage, capacity);
        // A dry column without sediment or damage keeps its values (as the general path,
        // which skips it).
        let idle = LaneMask::from_fn(|l| !wet.get(l) && sed.0[l] == 0.0 && damage.0[l] == 0.0);
        // Under an infinite ceiling the sand, >= 0, fits: nothing to fit.
        Column::select(idle, c, e.column).store(cells, f32::INFINITY);
        store(&mut out.sediment[x..], Lanes::select(idle, sed, e.sediment));
        store(&mut out.damage[x..], Lanes::select(idle, damage, e.damage));
        for (l, sum) in recovered.iter_mut().enumerate() {
            if !idle.get(l) {
                *sum +=
                    f64::from(e.bedrock_before_recovery.0[l]) - f64::from(e.column.bedrock.0[l]);
            }
        }
    }
    v.damage_recovery += recovered.iter().sum::<f64>();
}
}
