//! Step 5, vertical erosion and deposition (reference: `erosion.cu`, `sedimentKernel`).
//!
//! Per column with water: slope factor `min + (max - min) sin a (1 - smoothstep(fade, 1,
//! sin a))`, speed factor `min_speed + (1 - min_speed) |v|`, water factor
//! `1 - tanh(2 depth / erosion_water_max_height)`. The sediment capacity is
//! `sediment_capacity` times the three; bedrock under less than `sand_threshold` of sand
//! dissolves into sand at `bedrock_dissolving` times the three; water within
//! `top_erosion_distance` of the ceiling wears the ceiling (the bedrock of the column above)
//! into sand. Below capacity, sand dissolves into sediment at `sand_dissolving (capacity -
//! sediment)`; above, sediment deposits as sand at `deposition (sediment - capacity)`, at
//! most the free space. A dry column erodes nothing and deposits its sediment. Then damage
//! recovers at `damage_recovery`, lowering the bedrock as much.

use super::slots::{par_rows, smoothstep, Slots};
use super::{ErosionParams, ErosionState, StepVolumes};

/// Erodes and deposits vertically in every column; recovers damage.
pub(crate) fn vertical_erosion(state: &mut ErosionState, params: &ErosionParams) -> StepVolumes {
    let (width, height, cells) = (state.width, state.height, state.cells());
    let counts = &state.layer_counts;
    let slopes = &state.scratch.slopes;
    let velocities = &state.scratch.velocities;
    let columns = Slots::new(&mut state.columns);
    let sediments = Slots::new(&mut state.sediment);
    let damages = Slots::new(&mut state.damage);
    let dt = params.dt;
    let water_scale = 2.0 / params.erosion_water_max_height;
    par_rows(height, |y| {
        let mut v = StepVolumes::default();
        for x in 0..width {
            let i = x + y * width;
            let n = usize::from(counts[i]);
            let mut floor = f32::NEG_INFINITY;
            for k in 0..n {
                let s = i + k * cells;
                // SAFETY (every access below): slots of cell (x, y) are this row's only.
                let (mut c, mut sed, mut damage) =
                    unsafe { (columns.get(s), sediments.get(s), damages.get(s)) };
                let wet = c.water > 0.0;
                if !wet && sed == 0.0 && damage == 0.0 {
                    // Nothing to erode, deposit or recover.
                    floor = c.ceiling;
                    continue;
                }
                let capacity = if wet {
                    let sine = slopes[s];
                    let fade = smoothstep(params.slope_fade_start, 1.0, sine);
                    let slope_factor = params.min_slope_erosion_scale
                        + (params.max_slope_erosion_scale - params.min_slope_erosion_scale)
                            * sine
                            * (1.0 - fade);
                    let [vx, vy] = velocities[s];
                    let speed = (vx * vx + vy * vy).sqrt();
                    let speed_factor = params.min_speed_erosion_scale
                        + (1.0 - params.min_speed_erosion_scale) * speed;
                    let water_factor = (1.0 - (c.water * water_scale).tanh()).clamp(0.0, 1.0);
                    if params.vertical_erosion {
                        if k + 1 < n {
                            let gap = c.ceiling - c.water_top();
                            let top_factor =
                                (1.0 - (gap / params.top_erosion_distance).max(0.0)).max(0.0);
                            let top_rate = params.bedrock_dissolving
                                * speed
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
                        let sand_cover = (1.0 - c.sand / params.sand_threshold).max(0.0);
                        let bedrock_rate = sand_cover
                            * params.bedrock_dissolving
                            * slope_factor
                            * speed_factor
                            * water_factor;
                        let dissolved = (bedrock_rate * dt).min((c.bedrock - floor).max(0.0));
                        if dissolved > 0.0 {
                            let bedrock = (c.bedrock - dissolved).max(floor);
                            c.sand += c.bedrock - bedrock;
                            c.bedrock = bedrock;
                        }
                    }
                    params.sediment_capacity * slope_factor * speed_factor * water_factor
                } else {
                    0.0
                };
                // Both outcomes, then a select: whether the water is below capacity is
                // unpredictable.
                let (eroded_sand, eroded_sed) = if params.vertical_erosion {
                    let taken = (params.sand_dissolving * (capacity - sed) * dt).min(c.sand);
                    (c.sand - taken, sed + taken)
                } else {
                    (c.sand, sed)
                };
                let settled = (params.deposition * (sed - capacity) * dt)
                    .min(c.ceiling - c.water_top())
                    .min(sed - capacity)
                    .max(0.0);
                let (settled_sand, settled_sed) = (c.sand + settled, sed - settled);
                (c.sand, sed) = if capacity > sed {
                    (eroded_sand, eroded_sed)
                } else {
                    (settled_sand, settled_sed)
                };
                let recovered =
                    (params.damage_recovery * dt).min(damage.min(c.bedrock - floor)).max(0.0);
                if recovered > 0.0 {
                    let bedrock = (c.bedrock - recovered).max(floor);
                    v.damage_recovery += f64::from(c.bedrock) - f64::from(bedrock);
                    damage -= recovered;
                    c.bedrock = bedrock;
                }
                v.fit(&mut c);
                unsafe {
                    columns.set(s, c);
                    sediments.set(s, sed);
                    damages.set(s, damage);
                }
                floor = c.ceiling;
            }
        }
        v
    })
}
