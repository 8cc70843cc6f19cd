//! Procedural MLHM scenes with real overhangs (arches, a cave, a chasm, overhanging cliffs),
//! carved explicitly so tests and benchmarks have them without an erosion simulator.
//!
//! Every scene covers the same 256 m x 256 m as [`rivers_rain`](crate::rivers_rain): a grid of
//! N x N cells has cells of 256 / N metres, and the geometry is defined in metres, so every
//! resolution shows the same shapes. Each cell is sampled at its centre: the solid there is a
//! union of vertical intervals (the ground from minus infinity, plus rock above air gaps),
//! which becomes one column per interval, bottom to top. Water fills every column whose solid
//! top lies below the scene's water level at that point, up to the level or the ceiling.
//! Ground columns carry 0.5 m of sand (taken from the bedrock, so the surface is unchanged).
//!
//! When a cell needs more columns than the map's layer count allows, its thinnest air gaps
//! are filled with rock until it fits; gaps and rock slivers thinner than 1 cm are closed or
//! dropped. The scenes are deterministic and built row by row in parallel; the result does
//! not depend on the thread count.

use crate::RIVERS_RAIN_EXTENT;
use rayon::prelude::*;
use relief_core::{CoreError, Mlhm, MlhmColumn};
use std::cmp::Ordering;
use std::fmt;
use std::str::FromStr;

/// One of the carved scenes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CarvedScene {
    /// Three natural arches of different spans crossing a north-south valley with a stream.
    Arches,
    /// A hill pierced by a winding east-west tunnel that widens into a cavern with a pool.
    Cave,
    /// A plateau split by a winding gorge whose walls overhang its floor, with a stream and a
    /// boulder wedged between the walls.
    Chasm,
    /// Two-tiered mesas whose cliffs overhang their feet, over ground with ponds.
    Overhangs,
    /// All four at half scale, one per quadrant, flooded in the low parts.
    Combined,
}

impl CarvedScene {
    /// Every scene, in a fixed order.
    pub const ALL: [CarvedScene; 5] = [
        CarvedScene::Arches,
        CarvedScene::Cave,
        CarvedScene::Chasm,
        CarvedScene::Overhangs,
        CarvedScene::Combined,
    ];

    /// The scene's name, as [`CarvedScene::from_str`] parses it.
    pub fn name(self) -> &'static str {
        match self {
            CarvedScene::Arches => "arches",
            CarvedScene::Cave => "cave",
            CarvedScene::Chasm => "chasm",
            CarvedScene::Overhangs => "overhangs",
            CarvedScene::Combined => "combined",
        }
    }
}

impl fmt::Display for CarvedScene {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(self.name())
    }
}

impl FromStr for CarvedScene {
    type Err = CoreError;

    /// Parses a scene name (case-insensitive); the error lists the names.
    fn from_str(s: &str) -> Result<Self, CoreError> {
        CarvedScene::ALL.into_iter().find(|scene| scene.name().eq_ignore_ascii_case(s)).ok_or_else(
            || CoreError::Parameter {
                name: "carved scene",
                reason: format!(
                    "'{s}' is not one of {}",
                    CarvedScene::ALL.map(CarvedScene::name).join(", ")
                ),
            },
        )
    }
}

/// Side of every carved scene in metres (that of RiversRain).
pub const CARVED_EXTENT: f64 = RIVERS_RAIN_EXTENT;

/// Sand on the ground columns, metres.
const SAND: f64 = 0.5;

/// Air gaps and rock slivers thinner than this (metres) are closed or dropped.
const MIN_THICKNESS: f64 = 0.01;

/// The carved `scene` on a `size x size` grid (cells of 256 / `size` metres) with room for
/// `max_layers` columns per cell (the scenes need up to 4; fewer fills the thinnest gaps).
///
/// Fails when `size` is 0, `max_layers` is outside `1..=255` or the map would not fit in the
/// address space.
///
/// ```
/// use relief_sim::{carved_scene, CarvedScene};
/// let map = carved_scene(CarvedScene::Arches, 64, 4)?;
/// assert_eq!((map.width(), map.cell_size()), (64, 4.0));
/// assert!(map.layer_counts().iter().any(|&n| n >= 2));
/// # Ok::<(), relief_core::CoreError>(())
/// ```
pub fn carved_scene(scene: CarvedScene, size: usize, max_layers: usize) -> Result<Mlhm, CoreError> {
    if size == 0 {
        return Err(CoreError::Grid(format!("a {scene} scene of 0 x 0 cells is empty")));
    }
    let cell_size = CARVED_EXTENT / size as f64;
    // Checks the shape before the large allocations below.
    Mlhm::new(1, 1, max_layers, cell_size)?;
    let cells = size
        .checked_mul(size)
        .and_then(|cells| cells.checked_mul(max_layers).map(|_| cells))
        .ok_or_else(|| {
            CoreError::Grid(format!("a {scene} scene of {size} x {size} cells is too large"))
        })?;
    let mut counts = vec![0u8; cells];
    let mut columns = vec![MlhmColumn::default(); cells * max_layers];
    // rows[y][k]: row y of layer plane k.
    let mut rows: Vec<Vec<&mut [MlhmColumn]>> = (0..size).map(|_| Vec::new()).collect();
    for plane in columns.chunks_mut(cells) {
        for (row, chunk) in rows.iter_mut().zip(plane.chunks_mut(size)) {
            row.push(chunk);
        }
    }
    rows.into_par_iter().zip(counts.par_chunks_mut(size)).enumerate().for_each_init(
        CellWork::default,
        |work, (y, (mut planes, counts))| {
            let v = (y as f64 + 0.5) * cell_size;
            for (x, count) in counts.iter_mut().enumerate() {
                let u = (x as f64 + 0.5) * cell_size;
                let cell = work.cell(scene, u, v, max_layers);
                *count = cell.len() as u8;
                for (plane, column) in planes.iter_mut().zip(cell) {
                    plane[x] = *column;
                }
            }
        },
    );
    Mlhm::from_parts(size, size, max_layers, cell_size, counts, columns)
}

/// A cell's solid as sorted, disjoint vertical intervals `(bottom, top)`; the first starts at
/// minus infinity (the ground).
type Intervals = Vec<(f64, f64)>;

/// One thread's scratch memory for a cell.
#[derive(Default)]
struct CellWork {
    solid: Intervals,
    scratch: Intervals,
    columns: Vec<MlhmColumn>,
}

impl CellWork {
    /// The columns of the cell centred at `(u, v)` metres, at most `max_layers` of them.
    fn cell(&mut self, scene: CarvedScene, u: f64, v: f64, max_layers: usize) -> &[MlhmColumn] {
        let water = shape(scene, u, v, self);
        tidy(&mut self.solid, max_layers);
        self.columns.clear();
        let n = self.solid.len();
        for (k, &(_, top)) in self.solid.iter().enumerate() {
            let ceiling = if k + 1 < n { self.solid[k + 1].0 as f32 } else { f32::INFINITY };
            let sand = if k == 0 { SAND } else { 0.0 };
            let (bedrock, sand) = ((top - sand) as f32, sand as f32);
            let solid_top = bedrock + sand;
            let mut depth = match water {
                Some(level) if level > f64::from(solid_top) => {
                    (level.min(f64::from(ceiling)) - f64::from(solid_top)) as f32
                }
                _ => 0.0,
            };
            // f32 sums may round the water top a few ulps past the ceiling.
            while depth > 0.0 && solid_top + depth > ceiling {
                depth = f32::from_bits(depth.to_bits() - 1);
            }
            self.columns.push(MlhmColumn::new(bedrock, sand, depth.max(0.0), ceiling));
        }
        &self.columns
    }

    /// Starts the cell's solid as the ground up to `height`.
    fn ground(&mut self, height: f64) {
        self.solid.clear();
        self.solid.push((f64::NEG_INFINITY, height));
    }

    /// Adds rock from `bottom` to `top` (nothing when empty).
    fn add(&mut self, bottom: f64, top: f64) {
        if bottom.partial_cmp(&top) != Some(Ordering::Less) {
            return;
        }
        self.scratch.clear();
        let mut new = (bottom, top);
        for &(b, t) in &self.solid {
            if t < new.0 || b > new.1 {
                self.scratch.push((b, t));
            } else {
                new = (new.0.min(b), new.1.max(t));
            }
        }
        self.scratch.push(new);
        self.scratch.sort_by(|a, b| a.0.total_cmp(&b.0));
        std::mem::swap(&mut self.solid, &mut self.scratch);
    }

    /// Removes rock from `bottom` to `top` (nothing when empty).
    fn carve(&mut self, bottom: f64, top: f64) {
        if bottom.partial_cmp(&top) != Some(Ordering::Less) {
            return;
        }
        self.scratch.clear();
        for &(b, t) in &self.solid {
            if t <= bottom || b >= top {
                self.scratch.push((b, t));
                continue;
            }
            if b < bottom {
                self.scratch.push((b, bottom));
            }
            if t > top {
                self.scratch.push((top, t));
            }
        }
        std::mem::swap(&mut self.solid, &mut self.scratch);
    }
}

/// Drops rock slivers (but never the ground), closes thin gaps and fills the thinnest gaps
/// until at most `max_layers` intervals remain.
fn tidy(solid: &mut Intervals, max_layers: usize) {
    if solid.is_empty() || solid[0].0 != f64::NEG_INFINITY {
        // Everything at the bottom was carved away: the ground starts at the lowest rock, or
        // at 0 m when no rock is left.
        let top = solid.first().map_or(0.0, |first| first.1);
        if solid.is_empty() {
            solid.push((f64::NEG_INFINITY, top));
        } else {
            solid[0].0 = f64::NEG_INFINITY;
        }
    }
    solid.retain(|&(b, t)| b == f64::NEG_INFINITY || t - b >= MIN_THICKNESS);
    let mut k = 1;
    while k < solid.len() {
        if solid[k].0 - solid[k - 1].1 < MIN_THICKNESS {
            solid[k - 1].1 = solid[k].1;
            solid.remove(k);
        } else {
            k += 1;
        }
    }
    while solid.len() > max_layers {
        let k = (1..solid.len())
            .min_by(|&i, &j| {
                let gap = |k: usize| solid[k].0 - solid[k - 1].1;
                gap(i).total_cmp(&gap(j))
            })
            .unwrap_or(1);
        solid[k - 1].1 = solid[k].1;
        solid.remove(k);
    }
}

/// Fills `work.solid` with the scene's solid at `(u, v)` metres; returns the water level there.
fn shape(scene: CarvedScene, u: f64, v: f64, work: &mut CellWork) -> Option<f64> {
    match scene {
        CarvedScene::Arches => arches(u, v, 1.0, work),
        CarvedScene::Cave => cave(u, v, 1.0, work),
        CarvedScene::Chasm => chasm(u, v, 1.0, work),
        CarvedScene::Overhangs => overhangs(u, v, 1.0, work),
        CarvedScene::Combined => combined(u, v, work),
    }
}

/// Gentle undulation of the ground, +-`amplitude` metres.
fn undulation(u: f64, v: f64, amplitude: f64) -> f64 {
    amplitude * (u / 17.0).sin() * (v / 23.0 + 1.0).cos()
}

/// Scales the solid's heights and a water level by `scale`.
fn scaled(work: &mut CellWork, water: Option<f64>, scale: f64) -> Option<f64> {
    if scale != 1.0 {
        for interval in &mut work.solid {
            *interval = (interval.0 * scale, interval.1 * scale);
        }
    }
    water.map(|level| level * scale)
}

/// A valley along y between 30 m plateaus, a stream in its floor, crossed by three arches.
fn arches(u: f64, v: f64, scale: f64, work: &mut CellWork) -> Option<f64> {
    const FLOOR: f64 = 4.0;
    const PLATEAU: f64 = 30.0;
    let du = (u - 128.0).abs();
    // Floor 48 m to each side of the axis, walls rising over 24 m, a 1.5 m deep stream bed.
    let wall = ((du - 48.0) / 24.0).clamp(0.0, 1.0);
    let wall = wall * wall * (3.0 - 2.0 * wall);
    let bed = 1.5 * (1.0 - (du / 6.0).powi(2)).max(0.0);
    work.ground(FLOOR + (PLATEAU - FLOOR) * wall - bed + undulation(u, v, 0.5));
    // (position along y, inner radius, rock thickness, depth along y)
    for (centre, inner, thickness, depth) in
        [(56.0, 40.0, 12.0, 7.0), (128.0, 30.0, 8.0, 5.0), (200.0, 46.0, 10.0, 9.0)]
    {
        let dv = (v - centre) / depth;
        if dv.abs() >= 1.0 {
            continue;
        }
        // A ring in the x-z plane whose rock tapers to an edge at the faces, like a torus.
        let half = 0.5 * thickness * (1.0 - dv * dv).sqrt();
        let mid = inner + 0.5 * thickness;
        let (ri, ro) = (mid - half, mid + half);
        if du >= ro {
            continue;
        }
        let top = FLOOR + (ro * ro - du * du).sqrt();
        let bottom = if du < ri { FLOOR + (ri * ri - du * du).sqrt() } else { f64::NEG_INFINITY };
        work.add(bottom, top);
    }
    // The stream fills the bed to 1 m; the undulating floor around it stays dry.
    let water = (du < 48.0).then_some(FLOOR - 0.5);
    scaled(work, water, scale)
}

/// A hill with a winding tunnel through it along x and a cavern with a pool at its heart.
fn cave(u: f64, v: f64, scale: f64, work: &mut CellWork) -> Option<f64> {
    const CENTRE: (f64, f64) = (128.0, 128.0);
    let r = (u - CENTRE.0).hypot(v - CENTRE.1);
    let hill = 58.0 * (0.5 + 0.5 * (std::f64::consts::PI * (r / 110.0).min(1.0)).cos());
    work.ground(2.0 + hill + undulation(u, v, 0.8));
    // The tunnel: an elliptic section 12 m wide and 10 m high, its floor 11 m up.
    let axis = CENTRE.1 + 18.0 * (u / 40.0).sin();
    let dy = (v - axis) / 6.0;
    if dy.abs() < 1.0 {
        let h = 5.0 * (1.0 - dy * dy).sqrt();
        work.carve(16.0 - h, 16.0 + h);
    }
    // The cavern: an ellipsoid 56 m across and 26 m high, its floor 6 m up.
    let (dx, dy) = ((u - CENTRE.0) / 28.0, (v - axis) / 28.0);
    let d2 = dx * dx + dy * dy;
    let mut water = None;
    if d2 < 1.0 {
        let h = 13.0 * (1.0 - d2).sqrt();
        work.carve(19.0 - h, 19.0 + h);
        water = Some(9.0);
    }
    // A pillar of rock from the cavern's floor to its roof.
    if (u - 140.0).hypot(v - axis - 6.0) < 4.0 {
        work.add(0.0, 40.0);
    }
    scaled(work, water, scale)
}

/// A 40 m plateau cut by a winding gorge, 8 m wide at the top and 20 m at the floor.
fn chasm(u: f64, v: f64, scale: f64, work: &mut CellWork) -> Option<f64> {
    const FLOOR: f64 = 6.0;
    const TOP: f64 = 40.0;
    // The gorge runs south-west to north-east, winding.
    let (s, t) = ((u + v) / std::f64::consts::SQRT_2, (v - u) / std::f64::consts::SQRT_2);
    let d = (t - 14.0 * (s / 30.0).sin()).abs();
    work.ground(TOP + undulation(u, v, 1.0));
    let (top_half, floor_half) = (4.0, 10.0);
    let mut water = None;
    if d < floor_half {
        // Air where d < half width(z), the width shrinking linearly from floor to top.
        let z = if d <= top_half {
            f64::INFINITY
        } else {
            FLOOR + (floor_half - d) / (floor_half - top_half) * (TOP - FLOOR)
        };
        work.carve(FLOOR, z);
        water = Some(FLOOR + 1.0);
    }
    // A boulder wedged between the walls.
    let along = |s0: f64| (s - s0).hypot(t - 14.0 * (s0 / 30.0).sin());
    let boulder = along(190.0);
    if boulder < 9.0 {
        let h = (81.0 - boulder * boulder).sqrt() * 0.6;
        work.add(26.0 - h, 26.0 + h);
    }
    scaled(work, water, scale)
}

/// Two-tiered mesas whose cliffs lean out over their feet, on undulating ground with ponds.
fn overhangs(u: f64, v: f64, scale: f64, work: &mut CellWork) -> Option<f64> {
    const GROUND: f64 = 5.0;
    work.ground(GROUND + undulation(u, v, 1.5));
    // (centre, foot radius of the lower tier, of the upper tier)
    for (cx, cy, r1, r2) in [(80.0, 84.0, 52.0, 44.0), (184.0, 176.0, 40.0, 30.0)] {
        let r = (u - cx).hypot(v - cy);
        // Lower tier from the ground to 20 m, overhanging by 10 m at its top.
        add_leaning_tier(work, r, r1, 10.0, GROUND - 2.0, 20.0);
        // Upper tier from 20 m to 36 m, overhanging by 12 m.
        add_leaning_tier(work, r, r2, 12.0, 20.0, 36.0);
    }
    scaled(work, Some(GROUND - 0.5), scale)
}

/// Adds a tier of rock at distance `r` from its centre: a cliff from `bottom` to `top` whose
/// foot is at radius `foot` and which leans out by `lean` metres at the top (quadratically).
fn add_leaning_tier(work: &mut CellWork, r: f64, foot: f64, lean: f64, bottom: f64, top: f64) {
    let out = r - foot;
    if out >= lean {
        return;
    }
    let start = if out <= 0.0 { bottom } else { bottom + (top - bottom) * (out / lean).sqrt() };
    work.add(start, top);
}

/// The four scenes at half scale, one per quadrant, with water up to 3.5 m everywhere.
fn combined(u: f64, v: f64, work: &mut CellWork) -> Option<f64> {
    const HALF: f64 = CARVED_EXTENT / 2.0;
    let (qu, qv) = (u >= HALF, v >= HALF);
    let (lu, lv) =
        (2.0 * (u - if qu { HALF } else { 0.0 }), 2.0 * (v - if qv { HALF } else { 0.0 }));
    let local = match (qu, qv) {
        (false, false) => arches(lu, lv, 0.5, work),
        (true, false) => cave(lu, lv, 0.5, work),
        (false, true) => chasm(lu, lv, 0.5, work),
        (true, true) => overhangs(lu, lv, 0.5, work),
    };
    Some(local.map_or(3.5, |level| level.max(3.5)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_back_and_unknown_names_are_refused() {
        for scene in CarvedScene::ALL {
            assert_eq!(scene.name().parse::<CarvedScene>().unwrap(), scene);
            assert_eq!(scene.to_string(), scene.name());
        }
        assert_eq!("CAVE".parse::<CarvedScene>().unwrap(), CarvedScene::Cave);
        let err = "volcano".parse::<CarvedScene>().unwrap_err().to_string();
        assert!(err.contains("volcano") && err.contains("arches, cave"), "{err}");
    }

    #[test]
    fn every_scene_is_valid_with_overhangs_at_several_sizes() {
        for scene in CarvedScene::ALL {
            for size in [16, 64, 200] {
                let map = carved_scene(scene, size, 4).unwrap();
                map.validate().unwrap();
                assert_eq!((map.width(), map.height()), (size, size));
                assert_eq!(map.cell_size(), 256.0 / size as f64);
                let layered = map.layer_counts().iter().filter(|&&n| n >= 2).count();
                assert!(layered > 0, "{scene} at {size}: no cell with 2 columns");
            }
        }
    }

    #[test]
    fn builds_are_identical() {
        for scene in CarvedScene::ALL {
            assert_eq!(carved_scene(scene, 96, 4).unwrap(), carved_scene(scene, 96, 4).unwrap());
        }
    }

    /// Whether some column of the map holds water under a ceiling (inside a cave).
    fn water_under_rock(map: &Mlhm) -> bool {
        (0..map.height()).any(|y| {
            (0..map.width()).any(|x| {
                let n = map.layer_count(x, y);
                (0..n - 1).any(|k| map.column(x, y, k).water > 0.0)
            })
        })
    }

    #[test]
    fn the_cave_has_water_inside() {
        for size in [16, 64, 200] {
            assert!(water_under_rock(&carved_scene(CarvedScene::Cave, size, 4).unwrap()));
        }
        assert!(water_under_rock(&carved_scene(CarvedScene::Combined, 128, 4).unwrap()));
    }

    #[test]
    fn scenes_use_up_to_four_columns_and_fit_fewer_layers() {
        let map = carved_scene(CarvedScene::Combined, 256, 4).unwrap();
        let most = map.layer_counts().iter().copied().max().unwrap();
        assert!(most >= 3, "{most}");
        for layers in [1, 2] {
            let map = carved_scene(CarvedScene::Combined, 64, layers).unwrap();
            map.validate().unwrap();
            assert!(map.layer_counts().iter().all(|&n| usize::from(n) <= layers));
        }
        assert!(carved_scene(CarvedScene::Arches, 0, 4).is_err());
        assert!(carved_scene(CarvedScene::Arches, 8, 0).is_err());
    }

    #[test]
    fn arches_span_the_valley_with_air_beneath() {
        let map = carved_scene(CarvedScene::Arches, 256, 4).unwrap();
        // Cell (128, 56) lies on the valley axis under the first arch.
        let columns: Vec<_> = map.cell_columns(128, 56).collect();
        assert_eq!(columns.len(), 2, "{columns:?}");
        let (ground, arch) = (columns[0], columns[1]);
        assert!(ground.solid_top() < 5.0 && ground.ceiling > 40.0, "{columns:?}");
        assert!(arch.solid_top() > 50.0 && arch.ceiling == f32::INFINITY, "{columns:?}");
    }
}
