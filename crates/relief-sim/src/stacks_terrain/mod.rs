//! Seeded material-stack terrains (Löffler et al. 2011) with overhangs, caves, arches, sand and
//! water, at the paper's benchmark size and beyond: [`stacks_terrain`].
//!
//! Per stack, bottom to top:
//! - **bedrock** from 0 up to the ground: the seeded fBm of [`fbm_terrain`](crate::fbm_terrain) rescaled so that
//!   its relief fills most of the height range (less on small domains: at most a quarter of
//!   the domain's longer side, so that slopes stay plausible);
//! - **overhangs**: where a smooth mask noise exceeds a threshold, an air gap is carved at an
//!   absolute height that varies slowly over the domain (a weak stratum). Inside hills it is a
//!   closed cave; where a hillside crosses it, the rock above it overhangs the gap; where the
//!   ground is too low for a roof, the ground is cut down to the gap's floor (a ledge);
//! - **caves**: where a second mask noise exceeds its threshold, an air gap a smoothly varying
//!   depth below the ground, always under a roof of rock;
//! - **sand** replacing the top of the ground on gentle slopes of the lower half of the
//!   relief, thicker the gentler and the lower;
//! - **arches**: along the zero lines of a third (ridge) noise, where a gate noise allows, a
//!   slab of rock at a deck height above the smoothed ground: merged into the hills it meets
//!   and free above the valleys between them, thinning out where it would hang too high;
//! - **water**: all air below the sea level (the ground height under which
//!   [`StacksTerrainParams::water_fraction`] of the stacks lie), flooded caves included.
//!
//! The gaps' heights and thicknesses follow smooth noise of wavelengths of tens of stacks, and
//! fade to nothing at the masks' edges, so the features are coherent shapes. Layers thinner
//! than [`MIN_LAYER`] are dropped, gaps thinner than it are not carved, and every height is
//! clamped to `[0, max_height]`.

mod noise_field;
mod params;
mod stack_layers;
mod world;

pub use params::StacksTerrainParams;
pub use stack_layers::MIN_LAYER;

use crate::SimError;
use rayon::prelude::*;
use relief_core::{CoreError, DVec2, MaterialStacks, StackLayer, StackMaterial};
use stack_layers::Worker;
use world::World;

/// Stacks per band of rows computed by one task (about).
const BAND_STACKS: usize = 1 << 16;

/// A `width x height` material-stack terrain (palette [`StackMaterial::defaults`], spacing
/// `params.spacing` along both axes, origin 0) seeded with `seed`: fBm bedrock with overhangs,
/// caves and arches, sand and water (see the module documentation).
///
/// The same arguments give the same stacks, bit for bit, whatever the number of threads.
/// Rows are computed in parallel bands straight into the compressed-row storage.
///
/// Errors: [`SimError::Parameter`] for parameters out of range (see
/// [`StacksTerrainParams::validate`]); [`SimError::Terrain`] for an empty grid or one too
/// large to allocate or to index with `u32` offsets.
///
/// ```
/// use relief_sim::{stacks_terrain, StacksTerrainParams};
/// let stacks = stacks_terrain(64, 32, 7, &StacksTerrainParams::default())?;
/// assert_eq!((stacks.width(), stacks.height()), (64, 32));
/// # Ok::<(), relief_sim::SimError>(())
/// ```
pub fn stacks_terrain(
    width: usize,
    height: usize,
    seed: u64,
    params: &StacksTerrainParams,
) -> Result<MaterialStacks, SimError> {
    params.validate()?;
    if width == 0 || height == 0 {
        return Err(CoreError::Grid(format!("{width} x {height} has no stacks")).into());
    }
    let count = width
        .checked_mul(height)
        .filter(|&n| n < u32::MAX as usize / 4)
        .ok_or_else(|| CoreError::Grid(format!("{width} x {height} stacks are too many")))?;
    let world = World::new(width, height, seed, params)?;
    let band_rows = (BAND_STACKS / width).clamp(1, height);
    let mut offsets: Vec<u32> = Vec::new();
    offsets
        .try_reserve_exact(count + 1)
        .map_err(|_| CoreError::Grid(format!("cannot allocate {width} x {height} stacks")))?;
    offsets.resize(count + 1, 0);
    let bands: Vec<Vec<StackLayer>> = offsets[1..]
        .par_chunks_mut(band_rows * width)
        .enumerate()
        .map_init(
            || Worker::for_world(&world),
            |worker, (b, ends)| worker.band(&world, b * band_rows, ends),
        )
        .collect();
    // Band-local offsets made global; each band's layers moved over and freed in turn.
    let total: usize = bands.iter().map(Vec::len).sum();
    if total > u32::MAX as usize {
        return Err(CoreError::Grid(format!("{total} layers exceed u32 offsets")).into());
    }
    let mut layers: Vec<StackLayer> = Vec::new();
    layers
        .try_reserve_exact(total)
        .map_err(|_| CoreError::Grid(format!("cannot allocate {total} layers")))?;
    for (ends, band) in offsets[1..].chunks_mut(band_rows * width).zip(bands) {
        let base = layers.len() as u32;
        ends.iter_mut().for_each(|e| *e += base);
        layers.extend_from_slice(&band);
    }
    let stacks = MaterialStacks::from_parts(
        width,
        height,
        DVec2::splat(params.spacing),
        DVec2::ZERO,
        StackMaterial::defaults(),
        offsets,
        layers,
    )?;
    Ok(stacks)
}

#[cfg(test)]
mod tests {
    use super::stack_layers::{SAND, WATER};
    use super::*;

    fn terrain(width: usize, height: usize, seed: u64) -> MaterialStacks {
        stacks_terrain(width, height, seed, &StacksTerrainParams::default()).unwrap()
    }

    /// Whether the stack has two solid runs with air between them.
    fn overhangs(layers: &[StackLayer]) -> bool {
        layers.windows(2).any(|p| p[1].start > p[0].end && p[1].material != WATER)
    }

    #[test]
    fn layers_are_valid_and_within_the_height_range() {
        for (w, h, seed) in [(64, 32, 1), (200, 150, 2), (1, 1, 3), (7, 300, 4)] {
            let stacks = terrain(w, h, seed);
            stacks.validate().unwrap();
            let (low, high) = stacks.height_range().unwrap();
            assert!(low >= 0.0 && high <= 768.0, "{w}x{h}: {low}..{high}");
            assert!(stacks.layers().iter().all(|l| l.thickness() >= MIN_LAYER));
        }
    }

    #[test]
    fn same_seed_same_stacks_other_seed_other_stacks() {
        let a = terrain(150, 90, 11);
        assert_eq!(a, terrain(150, 90, 11));
        assert_ne!(a, terrain(150, 90, 12));
    }

    #[test]
    fn has_overhangs_sand_and_water() {
        for (w, h) in [(64, 32), (400, 300)] {
            let stacks = terrain(w, h, 5);
            let cells = w * h;
            let layered = (0..cells).filter(|i| overhangs(stacks.stack(i % w, i / w))).count();
            assert!(layered > cells / 100, "{w}x{h}: {layered} stacks with overhangs");
            let count = |m: u8| stacks.layers().iter().filter(|l| l.material == m).count();
            assert!(count(SAND) > cells / 25, "{w}x{h}: {} sand layers", count(SAND));
            assert!(count(WATER) > cells / 50, "{w}x{h}: {} water layers", count(WATER));
        }
    }

    #[test]
    fn features_are_coherent_not_speckle() {
        // Stacks with overhangs mostly have a neighbour with one too.
        let (w, h) = (300, 200);
        let stacks = terrain(w, h, 9);
        let has = |x: usize, y: usize| overhangs(stacks.stack(x, y));
        let (mut layered, mut lonely) = (0, 0);
        for y in 1..h - 1 {
            for x in 1..w - 1 {
                if has(x, y) {
                    layered += 1;
                    if !(has(x - 1, y) || has(x + 1, y) || has(x, y - 1) || has(x, y + 1)) {
                        lonely += 1;
                    }
                }
            }
        }
        assert!(layered > 0 && lonely * 50 < layered, "{lonely} of {layered} alone");
    }

    #[test]
    fn bad_parameters_are_refused() {
        let good = StacksTerrainParams::default();
        for (name, params) in [
            ("spacing", StacksTerrainParams { spacing: 0.0, ..good }),
            ("max_height", StacksTerrainParams { max_height: f64::NAN, ..good }),
            ("water_fraction", StacksTerrainParams { water_fraction: 1.5, ..good }),
            ("sand_thickness", StacksTerrainParams { sand_thickness: -1.0, ..good }),
        ] {
            match stacks_terrain(8, 8, 1, &params) {
                Err(SimError::Parameter { name: found, .. }) => assert_eq!(found, name),
                other => panic!("{params:?}: {other:?}"),
            }
        }
        assert!(matches!(stacks_terrain(0, 8, 1, &good), Err(SimError::Terrain(_))));
    }
}
