//! One stack's density along its column of lattice points: the signed vertical distance to
//! the nearest boundary of a channel's material, so that the iso-surface crosses every
//! vertical lattice edge exactly where a layer starts or ends, and layers thinner than the
//! lattice keep their thickness.
//!
//! A channel's layers (the solids, or the liquids) are merged into *runs*, maximal intervals
//! of that channel. A point at lattice height `k` takes `0.5 + d`, `d` the distance from `k`
//! to the nearest boundary of a run, positive inside, clamped to `[-BAND, BAND]`: along a
//! column, linear interpolation of the values between two points then finds a run's end at
//! its exact height.
//!
//! A run that holds at most one lattice point strictly inside (and does not start at the
//! terrain's bottom) is *pinned*: one point cannot carry the distances to both its ends, so it
//! takes `d = BAND` (as deep inside as a thick run's points, so that smoothing across the
//! columns treats a sheet's rim as it treats a thick layer's) and its two neighbours the
//! values that make interpolation cross at the run's two ends, `BAND (1 - 1 / a)`, `a` the
//! distance from the inside point to that end (floored where the columns are smoothed, see
//! [`THIN_FLOOR_SMOOTHED`]). A run that holds one point stays where it is. A *thin* run, one
//! that holds none, is first moved, its thickness kept, by the least shift that puts the
//! lattice point nearest its top a quarter step inside it (a quarter of its thickness for a
//! thinner run): its top moves by less than half a step plus a quarter of its thickness (half
//! its thickness when it was centred on that point), and a run that holds a point keeps its
//! place, so the sheets of one flat water surface stay near it, whatever their depth. The
//! mesh then keeps a thin sand cover, a water sheet or a ledge as a slab of its thickness,
//! less than a lattice step from where it is. Runs thinner than `min_thickness` are left
//! out.
//!
//! Measured with `bench/stacks_fidelity.py` and the property test's scenes (200 random 96 x 96
//! shelf scenes) when pinning replaced moving every run that holds at most one point so that
//! it was centred on the point nearest its top: the water at the finest level, on the
//! benchmark's six scenes, from -1.78, -2.23, -4.28, -1.94, -1.03, -4.15 % of the stacks' to
//! the figures of docs/stacks.md; on the shelf scenes from -10.8 .. -0.8 % to -3.1 .. +4.0 %
//! (at the camera's levels from -7.6 .. -0.5 % to -4.0 .. +2.6 %).

use relief_core::{StackLayer, StackMaterial};

/// How far from a run's boundary, lattice steps, the distance is kept before it is clamped.
pub(crate) const BAND: f64 = 1.0;

/// The lowest value a pinned run's neighbours take where the columns are smoothed: below it, a
/// very thin sheet's steep values would outweigh its neighbours' in the filter's sums and
/// lower thick water beside it (measured with `bench/stacks_fidelity.py` while it was added:
/// the shelf scenes' water at the finest level went from -5.1 %, -15.2 %, -14.6 % without it
/// to -5.0 %, -4.4 %, -6.0 % with it). It makes a pinned run whose end lies less than a
/// quarter step from its point a little thicker.
pub(crate) const THIN_FLOOR_SMOOTHED: f64 = -3.0 * BAND;

/// The value below the terrain's bottom under a run that starts there (a *grounded* run): so
/// low that the bottom face lies a thousandth of a step under the bottom, while the point at
/// the bottom takes the distance to the run's top, as a thick run's points do. A ground
/// thinner than a step then keeps its top where it is, at every level.
const BELOW_GROUND: f64 = -1000.0 * BAND;

/// A maximal interval of one channel's material in a column, lattice units.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Run {
    /// Bottom.
    start: f64,
    /// Top.
    end: f64,
    /// The first layer of the stack the run was made of (index into the stack).
    first_layer: usize,
    /// The last one.
    last_layer: usize,
    /// Whether it is *pinned* (see the module's docs): it holds one lattice point inside,
    /// which takes the full depth, its two neighbours the values that put both ends where
    /// the run's are.
    pinned: bool,
    /// Whether it starts at the terrain's bottom (lattice height 0).
    grounded: bool,
}

/// The values one column gives its lattice points for one channel: the density, and the
/// material each point shows (the layer at the nearest boundary within the band, else the
/// layer holding the point). Reused from column to column, so that a node allocates once.
#[derive(Debug, Default)]
pub(crate) struct ColumnValues {
    /// `0.5 + d` per point.
    pub density: Vec<f32>,
    /// `0.5 + d` per point, a pinned run's neighbours not floored: the exact crossings.
    pub exact: Vec<f32>,
    /// The material index each point shows, or `None` (air away from any run).
    pub material: Vec<Option<u8>>,
    /// The distances, before they become densities.
    best: Vec<f64>,
    /// The same, not floored.
    best_exact: Vec<f64>,
    /// The channel's runs in the column.
    runs: Vec<Run>,
}

/// The column of `stack` for the channel whose layers `belongs` picks, over the lattice points
/// `points` (heights `k`); `to_k` maps a height to lattice units; runs thinner than
/// `min_thickness` lattice units are left out; a pinned run's neighbours take at least
/// `thin_floor` (see [`THIN_FLOOR_SMOOTHED`]).
#[allow(clippy::too_many_arguments)] // One column's inputs, each of its own kind.
pub(crate) fn column_values(
    out: &mut ColumnValues,
    stack: &[StackLayer],
    materials: &[StackMaterial],
    belongs: impl Fn(&StackMaterial) -> bool,
    to_k: impl Fn(f32) -> f64,
    min_thickness: f64,
    thin_floor: f64,
    points: std::ops::Range<i32>,
) {
    let (z_lo, len) = (points.start, points.len());
    runs_of(&mut out.runs, stack, materials, &belongs, &to_k, min_thickness);
    let (best, material) = (&mut out.best, &mut out.material);
    best.clear();
    best.resize(len, f64::NEG_INFINITY);
    out.best_exact.clear();
    out.best_exact.resize(len, f64::NEG_INFINITY);
    material.clear();
    material.resize(len, None);
    let z_hi = z_lo + len as i32;
    for run in &out.runs {
        // A pinned run sets its point and the two beside it; a thick one the band around it.
        let (first, last) = if run.pinned {
            let inside = run.start.floor() as i32 + 1;
            (inside - 1, inside + 1)
        } else if run.grounded {
            (-2, (run.end + BAND).ceil() as i32)
        } else {
            ((run.start - BAND).floor() as i32, (run.end + BAND).ceil() as i32)
        };
        let (first, last) = (first.max(z_lo), last.min(z_hi - 1));
        for k in first..=last {
            let kf = k as f64;
            let exact = if run.pinned {
                let inside = run.start.floor() + 1.0;
                if kf < inside {
                    BAND * (1.0 - 1.0 / (inside - run.start))
                } else if kf > inside {
                    BAND * (1.0 - 1.0 / (run.end - inside))
                } else {
                    BAND
                }
            } else {
                f64::NAN
            };
            let d = if run.pinned {
                exact.max(thin_floor)
            } else if run.grounded {
                if k < 0 {
                    BELOW_GROUND
                } else {
                    (run.end - kf).clamp(-BAND, BAND)
                }
            } else {
                (kf - run.start).min(run.end - kf).clamp(-BAND, BAND)
            };
            let i = (k - z_lo) as usize;
            if d > best[i] || (d == best[i] && material[i].is_none()) {
                best[i] = d;
                out.best_exact[i] = if run.pinned { exact } else { d };
                let near_top = run.end - kf <= kf - run.start;
                let layer = if run.pinned || (d > -BAND && d < BAND) {
                    if near_top {
                        run.last_layer
                    } else {
                        run.first_layer
                    }
                } else if d >= BAND {
                    holding_layer(stack, run, &to_k, kf)
                } else {
                    continue;
                };
                material[i] = Some(stack[layer].material);
            }
        }
    }
    // Points no run reaches are air, a band's width from any boundary.
    let density = |d: f64| (0.5 + if d.is_finite() { d } else { -BAND }) as f32;
    out.density.clear();
    out.density.extend(best.iter().map(|&d| density(d)));
    out.exact.clear();
    out.exact.extend(out.best_exact.iter().map(|&d| density(d)));
}

/// The runs of the channel `belongs` picks in `stack`, lattice units, those holding at most
/// one lattice point pinned (thin ones moved onto the point nearest their top), overlapping
/// ones merged; bottom to top.
fn runs_of(
    runs: &mut Vec<Run>,
    stack: &[StackLayer],
    materials: &[StackMaterial],
    belongs: &impl Fn(&StackMaterial) -> bool,
    to_k: &impl Fn(f32) -> f64,
    min_thickness: f64,
) {
    runs.clear();
    for (i, layer) in stack.iter().enumerate() {
        if !belongs(&materials[layer.material as usize]) {
            continue;
        }
        let (start, end) = (to_k(layer.start), to_k(layer.end));
        match runs.last_mut() {
            Some(run) if run.last_layer + 1 == i && start <= run.end => {
                run.end = end;
                run.last_layer = i;
            }
            _ => runs.push(Run {
                start,
                end,
                first_layer: i,
                last_layer: i,
                pinned: false,
                grounded: start <= 0.0,
            }),
        }
    }
    runs.retain(|run| run.end - run.start >= min_thickness);
    for run in runs.iter_mut() {
        // Points strictly inside: floor(start) + 1 ..= ceil(end) - 1.
        let inside = run.end.ceil() - run.start.floor() - 1.0;
        if inside > 1.0 || run.grounded {
            continue;
        }
        run.pinned = true;
        if inside < 1.0 {
            // No point inside: moved onto the point nearest its top, as little as holding it
            // a quarter step (a quarter of its thickness) inside allows.
            let thickness = run.end - run.start;
            let point = run.end.round();
            let margin = (0.25f64).min(0.25 * thickness);
            run.end = run.end.clamp(point + margin, point + thickness - margin);
            run.start = run.end - thickness;
        }
    }
    // Merge the runs moving made overlap, in place.
    let mut kept = 0;
    for i in 0..runs.len() {
        let run = runs[i];
        if kept > 0 && run.start <= runs[kept - 1].end {
            let last = &mut runs[kept - 1];
            last.end = last.end.max(run.end);
            last.last_layer = run.last_layer;
            last.pinned = false;
        } else {
            runs[kept] = run;
            kept += 1;
        }
    }
    runs.truncate(kept);
}

/// The layer of `run` that holds lattice height `k` (the nearest one where moving a thin run
/// left none).
fn holding_layer(stack: &[StackLayer], run: &Run, to_k: &impl Fn(f32) -> f64, k: f64) -> usize {
    (run.first_layer..=run.last_layer).find(|&l| to_k(stack[l].end) > k).unwrap_or(run.last_layer)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn solid_column(layers: &[(f32, f32, u8)], z_lo: i32, len: usize) -> ColumnValues {
        let stack: Vec<StackLayer> =
            layers.iter().map(|&(s, e, m)| StackLayer::new(s, e, m)).collect();
        let mut out = ColumnValues::default();
        column_values(
            &mut out,
            &stack,
            &StackMaterial::defaults(),
            |m| !m.is_liquid(),
            |z| z as f64,
            0.0,
            f64::NEG_INFINITY,
            z_lo..z_lo + len as i32,
        );
        out
    }

    /// Where linear interpolation of the column's values crosses the iso-value 1/2.
    fn crossings(values: &[f32], z_lo: i32) -> Vec<f64> {
        let mut out = Vec::new();
        for k in 0..values.len() - 1 {
            let (a, b) = (values[k] as f64, values[k + 1] as f64);
            if (a > 0.5) != (b > 0.5) {
                out.push(z_lo as f64 + k as f64 + (0.5 - a) / (b - a));
            }
        }
        out
    }

    #[test]
    fn thick_layers_cross_at_their_exact_ends() {
        let c = solid_column(&[(1.25, 4.5, 0), (4.5, 4.75, 1)], -2, 12);
        let x = crossings(&c.density, -2);
        assert_eq!(x.len(), 2);
        assert!((x[0] - 1.25).abs() < 1e-6 && (x[1] - 4.75).abs() < 1e-6, "{x:?}");
        // The top shows the sand cover, the bottom the bedrock.
        assert_eq!(c.material[(5 + 2) as usize], Some(1));
        assert_eq!(c.material[(2 + 2) as usize], Some(0));
    }

    #[test]
    fn a_thin_layer_keeps_its_thickness_within_a_step() {
        for (start, end) in [(3.1f32, 3.4f32), (2.7, 3.2), (0.2, 0.5), (3.6, 4.5)] {
            let c = solid_column(&[(start, end, 1)], -3, 12);
            let x = crossings(&c.density, -3);
            assert_eq!(x.len(), 2, "{start}..{end}: {x:?}");
            let thickness = (end - start) as f64;
            assert!((x[1] - x[0] - thickness).abs() < 1e-6, "{start}..{end}: {x:?}");
            let centre = 0.5 * (start + end) as f64;
            assert!((0.5 * (x[0] + x[1]) - centre).abs() < 1.0, "{x:?}");
        }
    }

    #[test]
    fn a_layer_holding_one_point_keeps_both_ends() {
        for (start, end) in [(2.06f32, 3.18f32), (2.7, 3.2), (3.6, 4.5), (1.9, 3.7)] {
            let c = solid_column(&[(start, end, 1)], -3, 12);
            let x = crossings(&c.density, -3);
            assert_eq!(x.len(), 2, "{start}..{end}: {x:?}");
            assert!((x[0] - start as f64).abs() < 1e-6, "{start}..{end}: {x:?}");
            assert!((x[1] - end as f64).abs() < 1e-6, "{start}..{end}: {x:?}");
        }
    }

    #[test]
    fn a_thin_ground_keeps_its_top_and_its_bottom() {
        let c = solid_column(&[(0.0, 0.3, 0)], -3, 8);
        let x = crossings(&c.density, -3);
        assert_eq!(x.len(), 2, "{x:?}");
        assert!(x[0] < 0.0 && x[0] > -1e-3, "bottom {}", x[0]);
        assert!((x[1] - 0.3).abs() < 1e-6, "top {}", x[1]);
    }

    #[test]
    fn the_liquid_channel_sees_only_the_water() {
        let stack = [StackLayer::new(0.0, 2.0, 0), StackLayer::new(2.0, 2.3, 2)];
        let mut c = ColumnValues::default();
        column_values(
            &mut c,
            &stack,
            &StackMaterial::defaults(),
            |m| m.is_liquid(),
            |z| z as f64,
            0.0,
            f64::NEG_INFINITY,
            -1..5,
        );
        assert_eq!(c.density.iter().filter(|&&v| v > 0.5).count(), 1);
    }
}
