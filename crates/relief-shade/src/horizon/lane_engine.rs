//! The horizon engine of a height field without holes over a flat earth: every direction's
//! stencil and its line family's band pyramid made once, then the samples' horizons found
//! [`LANES`] at a time.

use super::band_pyramid::BandPyramid;
use super::far_field::{FarContext, FarField, FarLanes, FarLine, Patch};
use super::lane_frame::{LaneFrame, LANES};
use super::lanes::{angle_of, LaneDirection, LaneGroup};
use super::march::unit_steps;
use super::stencil::{Stencil, StencilLine};
use super::{Facing, HorizonParams};
use rayon::prelude::*;
use relief_core::HeightField;
use std::collections::HashMap;
use std::ops::Range;
use std::sync::Arc;

/// The lanes engine of one height field seen one way up.
pub(crate) struct LaneEngine {
    /// The samples in rows as they are, and with rows and columns swapped (where a direction
    /// runs more along y than along x), each if a direction needs it.
    frames: [Option<LaneFrame>; 2],
    /// Per direction, its stencil and maxima (none where its angles are not wanted).
    directions: Vec<Option<LaneDirection>>,
    /// Per direction, its line past the window through the whole raster, where the height
    /// field is a window of a larger raster (none where its angles are not wanted).
    far_lines: Vec<Option<FarLine>>,
    width: usize,
    height: usize,
    upside_down: bool,
    z_scale: f32,
    observer_height: f32,
}

impl LaneEngine {
    /// The engine of `field` (which has no holes, at least 2 x 2 samples) seen `facing` up,
    /// for the directions of `params` marked in `wanted`, its observer height and radius (its
    /// curvature is not this engine's); with `far`, `field` is a window of the raster `far`
    /// reads, and the lines go on past the window to the raster's edge (without a radius).
    pub(crate) fn new(
        field: &HeightField,
        params: &HorizonParams,
        facing: Facing,
        wanted: &[bool],
        far: Option<&FarField>,
    ) -> LaneEngine {
        let (width, height) = (field.width(), field.height());
        let g = field.geometry();
        let sign = if facing == Facing::Up { 1.0 } else { -1.0 };
        // Per direction: whether its frame is transposed, and its line's step in that frame.
        let lines: Vec<(bool, isize, f64, f64)> = (0..params.azimuths as usize)
            .map(|k| {
                let (a, b) = unit_steps(params.azimuth_deg(k), g.dx, g.dy);
                let transposed = b.abs() > a.abs();
                let (along, across) = if transposed { (b, a) } else { (a, b) };
                (
                    transposed,
                    if along > 0.0 { 1 } else { -1 },
                    across / along.abs(),
                    1.0 / along.abs(),
                )
            })
            .collect();
        let needs = |t: bool| lines.iter().zip(wanted).any(|(l, &w)| w && l.0 == t);
        let frame =
            |t: bool| needs(t).then(|| LaneFrame::new(field.samples(), width, height, sign, t));
        let (rows, columns) = rayon::join(|| frame(false), || frame(true));
        let frames = [rows, columns];
        // One pyramid per line family: a direction and its opposite share one.
        let family = |&(transposed, step_x, rows_per_step, _): &(bool, isize, f64, f64)| {
            (transposed, (rows_per_step * step_x as f64).to_bits())
        };
        let mut families: Vec<(bool, u64)> =
            lines.iter().zip(wanted).filter(|(_, &w)| w).map(|(l, _)| family(l)).collect();
        families.sort_unstable();
        families.dedup();
        // The pyramids share the quarter byte a sample and direction the estimate allows.
        let wanted_count = wanted.iter().filter(|&&w| w).count().max(1);
        let pyramid_bytes = wanted_count as f64 / (4.0 * families.len().max(1) as f64);
        let pyramids: HashMap<(bool, u64), Arc<BandPyramid>> = [false, true]
            .into_par_iter()
            .flat_map(|t| {
                let Some(frame) = frames[t as usize].as_ref() else {
                    return Vec::new();
                };
                let windows = frame.band_windows();
                families
                    .par_iter()
                    .filter(|f| f.0 == t)
                    .map(|&(t, slope)| {
                        let pyramid =
                            BandPyramid::new(frame, &windows, f64::from_bits(slope), pyramid_bytes);
                        ((t, slope), Arc::new(pyramid))
                    })
                    .collect::<Vec<_>>()
            })
            .collect();
        let directions = lines
            .into_par_iter()
            .zip(wanted)
            .map(|(l, &wanted)| {
                if !wanted {
                    return None;
                }
                let (transposed, step_x, rows_per_step, metres_per_step) = l;
                let frame = frames[transposed as usize].as_ref().expect("built when needed");
                let line = StencilLine {
                    step_x,
                    rows_per_step,
                    metres_per_step,
                    stride: frame.stride,
                    column_major: true,
                    radius_steps: params.radius.map(|r| r / metres_per_step),
                    z_scale: g.z_scale,
                    observer_height: params.observer_height,
                    height_range: f64::from(field.max_sample()) - f64::from(field.min_sample()),
                };
                let stencil = Stencil::new(&line, frame.width.saturating_sub(1).max(1));
                let pyramid = pyramids[&family(&l)].clone();
                let far = far
                    .filter(|_| params.radius.is_none())
                    .map(|far| FarLine::new(&line, transposed, sign, far, width, height));
                Some((LaneDirection { transposed, stencil, pyramid }, far))
            })
            .collect::<Vec<_>>();
        let (directions, far_lines) = directions
            .into_iter()
            .map(|d| d.map_or((None, None), |(direction, far)| (Some(direction), far)))
            .unzip();
        LaneEngine {
            frames,
            directions,
            far_lines,
            width,
            height,
            upside_down: facing == Facing::Down,
            z_scale: g.z_scale as f32,
            observer_height: params.observer_height as f32,
        }
    }

    /// Drops what direction `k`'s far line made (its steps over the whole raster).
    pub(crate) fn release_far(&self, k: usize) {
        if let Some(Some(line)) = self.far_lines.get(k) {
            line.release();
        }
    }

    /// Samples a row of the height field.
    pub(crate) fn width(&self) -> usize {
        self.width
    }

    /// Per direction, the horizon angles in radians of the samples of columns `cols` of
    /// `rows`, row by row (NaN where `void` says so; none in a direction not wanted); with
    /// `at_least_level`, `max(angle, 0)`. With `far` (the far field the engine was made for),
    /// the lines go on to the raster's edge. With `only`, that direction alone (the others
    /// have no angles).
    pub(crate) fn band(
        &self,
        rows: Range<usize>,
        cols: Range<usize>,
        void: Option<&[bool]>,
        at_least_level: bool,
        far: Option<&FarContext>,
        only: Option<usize>,
    ) -> Vec<Vec<f32>> {
        let (width, count) = (self.width, rows.len() * cols.len());
        let out_width = cols.len();
        debug_assert!(rows.end <= self.height && cols.end <= width);
        let is_void = |col: usize, row: usize| void.is_some_and(|v| v[col + row * width]);
        let mut patch = Patch::default();
        self.directions
            .iter()
            .zip(&self.far_lines)
            .enumerate()
            .map(|(k, (direction, far_line))| {
                let Some(direction) = direction.as_ref().filter(|_| only.is_none_or(|o| o == k))
                else {
                    return Vec::new();
                };
                let far = far.zip(far_line.as_ref()).map(|(far, line)| (far, line, line.stencil()));
                let frame = self.frames[direction.transposed as usize].as_ref().unwrap();
                let mut out = vec![f32::NAN; count];
                let mut group = LaneGroup {
                    frame,
                    direction,
                    u: 0,
                    v: usize::MAX,
                    wanted: [false; LANES],
                    upside_down: self.upside_down,
                    z_scale: self.z_scale,
                    observer_height: self.observer_height,
                    lowest: if at_least_level { 0.0 } else { f32::NEG_INFINITY },
                    hints: [0; LANES],
                };
                let step_x = direction.stencil.step_x;
                // Each group of lanes: its frame column, its first frame row, its frame rows'
                // end, and where its samples are in `out` (the first and the step between).
                let mut run = |u: usize, first: usize, end: usize, at: usize, step: usize| {
                    group.wanted = std::array::from_fn(|i| {
                        let v = first + i;
                        v < end && !if direction.transposed { is_void(v, u) } else { is_void(u, v) }
                    });
                    if group.v != first || group.u + 1 != u {
                        group.hints = [0; LANES];
                    }
                    (group.u, group.v) = (u, first);
                    if group.wanted.iter().any(|&w| w) {
                        let mut slopes = group.exact_slopes();
                        if let Some((far, line, stencil)) = &far {
                            let base = frame.index(u, first);
                            let z0 = frame.z[base..base + LANES].try_into().expect("16 lanes");
                            let (wanted, hints) = (&group.wanted, &group.hints);
                            let lanes = FarLanes { x: u, y: first, z0, wanted, hints };
                            let far_steps = far.raise_lanes(
                                line,
                                stencil,
                                &mut patch,
                                &lanes,
                                &mut slopes.slopes,
                            );
                            // A step of the far walk set the horizon where it is not 0.
                            for (step, far_step) in slopes.steps.iter_mut().zip(far_steps) {
                                if far_step != 0 {
                                    *step = far_step;
                                }
                            }
                        }
                        for (i, &slope) in slopes.slopes.iter().enumerate().take(end - first) {
                            out[at + i * step] = angle_of(slope);
                        }
                        // The next group is one column on: the same points one step nearer
                        // (forwards) or farther.
                        group.hints = slopes.steps.map(|j| {
                            if j == 0 {
                                0
                            } else {
                                j.saturating_add_signed(-step_x as i32)
                            }
                        });
                    } else {
                        group.hints = [0; LANES];
                    }
                };
                // Column after column: the lines of one group and the next lie side by side,
                // read the same samples and have their horizons at about the same points.
                if direction.transposed {
                    for first in cols.clone().step_by(LANES) {
                        for u in rows.clone() {
                            let at = (u - rows.start) * out_width + first - cols.start;
                            run(u, first, cols.end, at, 1);
                        }
                    }
                } else {
                    for first in rows.clone().step_by(LANES) {
                        for u in cols.clone() {
                            let at = (first - rows.start) * out_width + u - cols.start;
                            run(u, first, rows.end, at, out_width);
                        }
                    }
                }
                out
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::super::far_field::{FarError, FarSamples};
    use super::*;
    use relief_core::GridGeometry;

    /// A window's horizons, its lines walked past it through the whole raster, are the whole
    /// raster's bit for bit, on plain arrays and in the widest vectors the processor has.
    #[test]
    fn a_window_and_its_far_walks_give_the_whole_raster_s_bits() {
        let (w, h) = (150, 110);
        let samples: Vec<f32> = (0..w * h)
            .map(|k| {
                let (c, r) = ((k % w) as f32, (k / w) as f32);
                (c * 0.13).sin() * 7.0 + (r * 0.11 - c * 0.03).cos() * 6.0 + (k % 11) as f32 * 0.2
            })
            .collect();
        let geometry = GridGeometry { dx: 1.5, dy: 0.8, z_scale: 2.0, ..GridGeometry::unit() };
        let whole = HeightField::new(w, h, samples.clone(), geometry).unwrap();
        let (col0, row0, ww, wh) = (40, 30, 60, 50);
        let window_samples =
            (row0..row0 + wh).flat_map(|r| samples[r * w + col0..r * w + col0 + ww].to_vec());
        let window = HeightField::new(ww, wh, window_samples.collect(), geometry).unwrap();
        let terrain = FarSamples::new(Arc::new(samples), w, h);
        let far = FarField { terrain: &terrain, col0, row0 };
        let params = HorizonParams { azimuths: 24, ..HorizonParams::default() };
        let bits =
            |v: &Vec<Vec<f32>>| -> Vec<u32> { v.iter().flatten().map(|a| a.to_bits()).collect() };
        for facing in [Facing::Up, Facing::Down] {
            let engine = LaneEngine::new(&whole, &params, facing, &[true; 24], None);
            let expected = engine.band(row0..row0 + wh, col0..col0 + ww, None, false, None, None);
            let engine = LaneEngine::new(&window, &params, facing, &[true; 24], Some(&far));
            let context = FarContext { field: far, error: FarError::default() };
            let fast = engine.band(0..wh, 0..ww, None, false, Some(&context), None);
            super::super::lanes::tests::PORTABLE_ONLY.set(true);
            let portable = engine.band(0..wh, 0..ww, None, false, Some(&context), None);
            super::super::lanes::tests::PORTABLE_ONLY.set(false);
            assert!(context.error.take().is_none());
            assert_eq!(bits(&fast), bits(&expected), "{facing:?}");
            assert_eq!(bits(&portable), bits(&expected), "{facing:?}");
        }
    }

    /// The lanes on plain arrays and in the widest vectors the processor has give the same
    /// bits, in every direction, both ways up, above the horizontal or not, with a radius.
    #[test]
    fn every_processor_path_gives_the_same_bits() {
        let (w, h) = (83, 61);
        let samples = (0..w * h)
            .map(|k| {
                let (c, r) = ((k % w) as f32, (k / w) as f32);
                (c * 0.21).sin() * 9.0 + (r * 0.17 + c * 0.05).cos() * 5.0 + (k % 7) as f32 * 0.3
            })
            .collect();
        let geometry = GridGeometry { dx: 1.5, dy: 0.8, z_scale: 2.0, ..GridGeometry::unit() };
        let field = HeightField::new(w, h, samples, geometry).unwrap();
        for radius in [None, Some(25.0)] {
            let params = HorizonParams { azimuths: 24, radius, ..HorizonParams::default() };
            for facing in [Facing::Up, Facing::Down] {
                let engine = LaneEngine::new(&field, &params, facing, &[true; 24], None);
                for level in [false, true] {
                    let fast = engine.band(0..h, 0..w, None, level, None, None);
                    super::super::lanes::tests::PORTABLE_ONLY.set(true);
                    let portable = engine.band(0..h, 0..w, None, level, None, None);
                    super::super::lanes::tests::PORTABLE_ONLY.set(false);
                    let bits = |v: &Vec<Vec<f32>>| -> Vec<u32> {
                        v.iter().flatten().map(|a| a.to_bits()).collect()
                    };
                    assert_eq!(bits(&fast), bits(&portable), "{radius:?} {facing:?} {level}");
                }
            }
        }
    }
}
