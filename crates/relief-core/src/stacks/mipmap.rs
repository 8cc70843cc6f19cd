//! The LOD mipmap of material stacks ([`StacksMipmap`]): vertex-centred, nested levels, each
//! aggregated from the finer one by the material heuristic ([`aggregate`]).

use super::aggregation::{aggregate_stack, Scratch};
use super::{MaterialStacks, StackLayer};
use crate::CoreError;
use rayon::prelude::*;

/// The LOD mipmap of a stacks terrain: level 0 the stacks themselves (finest), each further
/// level aggregated from the one below by [`aggregate`], down to a level of 1 x 1 stacks.
///
/// The levels are vertex-centred and nested: stack `(i, j)` of level `l + 1` sits where stack
/// `(2i, 2j)` of level `l` does, so a coarse level's stacks coincide with every other stack of
/// the finer one (as the mesher's crack-free stitching needs). Level `l + 1` has
/// `ceil(width_l / 2)` by `ceil(height_l / 2)` stacks at twice the spacing; heights stay
/// absolute and the palette is the same.
///
/// ```
/// use relief_core::{DVec2, MaterialStacks, StackLayer, StackMaterial, StacksMipmap};
/// let slab = vec![vec![StackLayer::new(0.0, 2.0, StackMaterial::BEDROCK)]; 5 * 3];
/// let stacks = MaterialStacks::from_stacks(
///     5, 3, DVec2::ONE, DVec2::ZERO, StackMaterial::defaults(), &slab,
/// )?;
/// let mipmap = StacksMipmap::new(stacks)?;
/// let sizes: Vec<_> = mipmap.levels().iter().map(|l| (l.width(), l.height())).collect();
/// assert_eq!(sizes, [(5, 3), (3, 2), (2, 1), (1, 1)]);
/// assert_eq!(mipmap.level(3).unwrap().stack(0, 0), &[StackLayer::new(0.0, 2.0, 0)]);
/// # Ok::<(), relief_core::CoreError>(())
/// ```
#[derive(Debug, Clone)]
pub struct StacksMipmap {
    levels: Vec<MaterialStacks>,
}

impl StacksMipmap {
    /// The mipmap of `stacks`: `stacks` as level 0, then [`aggregate`] until a level is
    /// 1 x 1.
    ///
    /// Errors: [`CoreError::Grid`] when a level's layers would overflow the `u32` offsets
    /// (over 4 G layers, which no real terrain nears, but a coarse stack may hold more layers
    /// than any of its children, so a level is not bounded by the one below it).
    pub fn new(stacks: MaterialStacks) -> Result<StacksMipmap, CoreError> {
        StacksMipmap::within(stacks, u32::MAX as usize)
    }

    /// As [`StacksMipmap::new`], with levels of at most `max_layers` layers.
    fn within(stacks: MaterialStacks, max_layers: usize) -> Result<StacksMipmap, CoreError> {
        let mut levels = vec![stacks];
        loop {
            let finer = &levels[levels.len() - 1];
            if finer.width == 1 && finer.height == 1 {
                break;
            }
            let coarser = aggregate_within(finer, max_layers)?;
            levels.push(coarser);
        }
        Ok(StacksMipmap { levels })
    }

    /// The levels, finest first.
    pub fn levels(&self) -> &[MaterialStacks] {
        &self.levels
    }

    /// Level `l` (0 the finest), or `None` past the coarsest.
    pub fn level(&self, l: usize) -> Option<&MaterialStacks> {
        self.levels.get(l)
    }

    /// Number of levels, at least 1.
    pub fn level_count(&self) -> usize {
        self.levels.len()
    }

    /// Bytes every level occupies in memory ([`MaterialStacks::memory_bytes`] summed).
    pub fn memory_bytes(&self) -> usize {
        self.levels.iter().map(MaterialStacks::memory_bytes).sum()
    }
}

/// The next coarser level of `finer`: `ceil(width / 2)` by `ceil(height / 2)` stacks at twice
/// the spacing, stack `(i, j)` aggregating the finer stacks `(2i + a, 2j + b)`,
/// `a, b in {-1, 0, 1}`, with tent weights `(2 - |a|)(2 - |b|)` (4 at the centre, 2 at an edge,
/// 1 at a corner); finer stacks outside the grid are left out, not counted as air. The origin
/// moves to `origin - spacing / 2`, so that stack `(i, j)`'s centre is finer stack
/// `(2i, 2j)`'s. The palette is copied; rows are aggregated in parallel, with the same result
/// whatever the thread count.
///
/// Each coarse stack follows Löffler et al.'s heuristic (section 3.1), made precise: the
/// height axis is cut at every start and end of its children's layers into segments (those
/// thinner than 1e-6 m left out), each with its composition, the weight of every material over
/// it and of air where a child has no layer;
/// 1. a material (air included) of strictly greatest weight is chosen;
/// 2. on a tie, with `B` and `A` the strictly dominant materials of the nearest segments below
///    and above that have one:
///    a. if exactly one of the tied candidates is among `B` and `A`, it is chosen;
///    b. if `B` and `A` are two different candidates, the segment is split, `B` below and `A`
///    above, in the ratio of their weights (the midpoint: they tie);
///    c. otherwise the candidates are scored by weight times thickness over the segments
///    `k - r ..= k + r` for `r = 2, 3, ...` until one strictly wins; if none does once the
///    window covers the whole stack, the lowest material index is chosen, air after every
///    material.
///
/// Consecutive segments of one material are then merged, air dropped, and layers thinner
/// than 1e-6 m dropped.
///
/// Errors: [`CoreError::Grid`] when the coarse level would have more than `u32::MAX` layers.
pub fn aggregate(finer: &MaterialStacks) -> Result<MaterialStacks, CoreError> {
    aggregate_within(finer, u32::MAX as usize)
}

/// As [`aggregate`], failing when the coarse level would have more than `max_layers` layers
/// (at most `u32::MAX`, what the offsets hold).
fn aggregate_within(
    finer: &MaterialStacks,
    max_layers: usize,
) -> Result<MaterialStacks, CoreError> {
    debug_assert!(max_layers <= u32::MAX as usize);
    let (fw, fh) = (finer.width, finer.height);
    let (width, height) = ((fw - 1) / 2 + 1, (fh - 1) / 2 + 1);
    let rows: Vec<(Vec<u32>, Vec<StackLayer>)> = (0..height)
        .into_par_iter()
        .map_init(Scratch::default, |scratch, j| {
            let mut counts = Vec::with_capacity(width);
            let mut layers = Vec::new();
            let mut children: Vec<(&[StackLayer], u32)> = Vec::with_capacity(9);
            for i in 0..width {
                children.clear();
                for b in -1i64..=1 {
                    let y = 2 * j as i64 + b;
                    if y < 0 || y >= fh as i64 {
                        continue;
                    }
                    for a in -1i64..=1 {
                        let x = 2 * i as i64 + a;
                        if x < 0 || x >= fw as i64 {
                            continue;
                        }
                        let weight = ((2 - a.abs()) * (2 - b.abs())) as u32;
                        children.push((finer.stack(x as usize, y as usize), weight));
                    }
                }
                let before = layers.len();
                aggregate_stack(&children, scratch, &mut layers);
                counts.push((layers.len() - before) as u32);
            }
            (counts, layers)
        })
        .collect();

    let total: usize = rows.iter().map(|(_, layers)| layers.len()).sum();
    if total > max_layers {
        return Err(CoreError::Grid(format!(
            "the {width}x{height} level would have {total} layers, more than {max_layers} \
             (what its u32 offsets hold)"
        )));
    }
    let mut offsets = Vec::with_capacity(width * height + 1);
    offsets.push(0u32);
    let mut layers = Vec::with_capacity(total);
    for (counts, row_layers) in rows {
        for count in counts {
            let last = offsets[offsets.len() - 1];
            offsets.push(last + count);
        }
        layers.extend(row_layers);
    }
    Ok(MaterialStacks {
        width,
        height,
        spacing: finer.spacing * 2.0,
        origin: finer.origin - finer.spacing * 0.5,
        materials: finer.materials.clone(),
        offsets,
        layers,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{DVec2, StackMaterial};
    use proptest::prelude::*;

    const BEDROCK: u8 = StackMaterial::BEDROCK;
    const SAND: u8 = StackMaterial::SAND;

    fn stacks(width: usize, height: usize, columns: &[Vec<StackLayer>]) -> MaterialStacks {
        MaterialStacks::from_stacks(
            width,
            height,
            DVec2::new(2.0, 3.0),
            DVec2::new(10.0, -5.0),
            StackMaterial::defaults(),
            columns,
        )
        .unwrap()
    }

    fn centre(stacks: &MaterialStacks, x: usize, y: usize) -> DVec2 {
        stacks.origin() + (DVec2::new(x as f64, y as f64) + 0.5) * stacks.spacing()
    }

    #[test]
    fn level_sizes_halve_rounding_up_down_to_one_by_one() {
        let mipmap = StacksMipmap::new(stacks(5, 3, &vec![vec![]; 15])).unwrap();
        let sizes: Vec<_> = mipmap.levels().iter().map(|l| (l.width(), l.height())).collect();
        assert_eq!(sizes, [(5, 3), (3, 2), (2, 1), (1, 1)]);
        assert_eq!(mipmap.level_count(), 4);
        assert!(mipmap.level(4).is_none());
        let one = StacksMipmap::new(stacks(1, 1, &[vec![]])).unwrap();
        assert_eq!(one.level_count(), 1);
        let tall = StacksMipmap::new(stacks(1, 4, &vec![vec![]; 4])).unwrap();
        let sizes: Vec<_> = tall.levels().iter().map(|l| (l.width(), l.height())).collect();
        assert_eq!(sizes, [(1, 4), (1, 2), (1, 1)]);
    }

    #[test]
    fn a_coarse_stack_is_centred_on_the_finer_stack_at_twice_its_index() {
        let mipmap = StacksMipmap::new(stacks(9, 6, &vec![vec![]; 54])).unwrap();
        for pair in mipmap.levels().windows(2) {
            let (fine, coarse) = (&pair[0], &pair[1]);
            assert_eq!(coarse.spacing(), fine.spacing() * 2.0);
            for j in 0..coarse.height() {
                for i in 0..coarse.width() {
                    let d = centre(coarse, i, j) - centre(fine, 2 * i, 2 * j);
                    assert!(d.length() < 1e-9, "level {i}, {j}: off by {d}");
                }
            }
        }
    }

    #[test]
    fn a_level_with_more_layers_than_its_offsets_hold_is_an_error_not_the_end() {
        // Levels of 35, 12, 4 and 1 layers: the second one is the largest coarse level.
        let slab = vec![vec![StackLayer::new(0.0, 2.0, BEDROCK)]; 7 * 5];
        let whole = StacksMipmap::within(stacks(7, 5, &slab), 12).unwrap();
        assert_eq!(whole.level_count(), 4);
        match StacksMipmap::within(stacks(7, 5, &slab), 11) {
            Err(CoreError::Grid(message)) => {
                assert!(message.contains("4x3 level would have 12 layers"), "{message}")
            }
            other => panic!("a mipmap ended early or built: {other:?}"),
        }
    }

    #[test]
    fn a_flat_slab_stays_the_same_at_every_level() {
        let slab = vec![vec![StackLayer::new(0.0, 2.0, BEDROCK)]; 7 * 5];
        let mipmap = StacksMipmap::new(stacks(7, 5, &slab)).unwrap();
        for level in mipmap.levels() {
            assert!(level.layers().iter().all(|&l| l == StackLayer::new(0.0, 2.0, BEDROCK)));
            assert_eq!(level.layers().len(), level.width() * level.height());
            assert_eq!(level.materials(), StackMaterial::defaults());
        }
        let total: usize = mipmap.levels().iter().map(MaterialStacks::memory_bytes).sum();
        assert_eq!(mipmap.memory_bytes(), total);
    }

    #[test]
    fn children_outside_the_grid_are_absent_not_air() {
        // A 3 x 1 row: coarse stack 0 sees fine 0 (weight 4) and fine 1 (weight 2); counting
        // the five missing children as air would make air win.
        let fine = stacks(
            3,
            1,
            &[
                vec![StackLayer::new(0.0, 1.0, BEDROCK)],
                vec![],
                vec![StackLayer::new(0.0, 1.0, SAND)],
            ],
        );
        let coarse = aggregate(&fine).unwrap();
        assert_eq!((coarse.width(), coarse.height()), (2, 1));
        assert_eq!(coarse.stack(0, 0), &[StackLayer::new(0.0, 1.0, BEDROCK)]);
        assert_eq!(coarse.stack(1, 0), &[StackLayer::new(0.0, 1.0, SAND)]);
    }

    #[test]
    fn tent_weights_favour_the_centre_over_edges_and_corners() {
        // Coarse stack (1, 1) of a 5 x 5 grid aggregates fine (1..=3, 1..=3). The centre
        // (weight 4) is sand, the corners (1 each) rock: the empty edges' air (8) wins. With
        // rock on the edges too, rock weighs 4 + 8 = 12 against sand's 4.
        let mut columns = vec![vec![]; 25];
        let rock = vec![StackLayer::new(0.0, 1.0, BEDROCK)];
        columns[2 + 2 * 5] = vec![StackLayer::new(0.0, 1.0, SAND)];
        for (x, y) in [(1, 1), (3, 1), (1, 3), (3, 3)] {
            columns[x + y * 5] = rock.clone();
        }
        let coarse = aggregate(&stacks(5, 5, &columns)).unwrap();
        assert!(coarse.stack(1, 1).is_empty(), "air 8 beats sand 4 and rock 4");
        for (x, y) in [(2, 1), (1, 2), (3, 2), (2, 3)] {
            columns[x + y * 5] = rock.clone();
        }
        let coarse = aggregate(&stacks(5, 5, &columns)).unwrap();
        assert_eq!(coarse.stack(1, 1), rock.as_slice());
    }

    #[test]
    fn aggregation_is_deterministic_across_thread_counts() {
        let columns: Vec<Vec<StackLayer>> = (0..40 * 30)
            .map(|i| {
                let h = (i * 7919 % 13) as f32 * 0.5;
                vec![StackLayer::new(0.0, 1.0 + h, (i % 3) as u8)]
            })
            .collect();
        let fine = stacks(40, 30, &columns);
        let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
        let serial = one.install(|| StacksMipmap::new(fine.clone()).unwrap());
        let parallel = StacksMipmap::new(fine).unwrap();
        assert_eq!(serial.levels(), parallel.levels());
    }

    /// A random stack: up to 4 layers of materials 0 to 2 with gaps, bottom to top.
    fn random_stack() -> impl Strategy<Value = Vec<StackLayer>> {
        prop::collection::vec((0u8..4, 1u8..4, 0u8..3), 0..4).prop_map(|parts| {
            let mut z = -2.0f32;
            parts
                .into_iter()
                .map(|(gap, thickness, material)| {
                    let start = z + f32::from(gap) * 0.5;
                    z = start + f32::from(thickness) * 0.5;
                    StackLayer::new(start, z, material)
                })
                .collect()
        })
    }

    proptest! {
        #[test]
        fn every_level_of_random_stacks_validates(
            (width, height, columns) in (1usize..7, 1usize..7).prop_flat_map(|(w, h)| {
                (Just(w), Just(h), prop::collection::vec(random_stack(), w * h))
            })
        ) {
            let mipmap = StacksMipmap::new(stacks(width, height, &columns)).unwrap();
            let last = &mipmap.levels()[mipmap.level_count() - 1];
            prop_assert_eq!((last.width(), last.height()), (1, 1));
            for level in mipmap.levels() {
                prop_assert!(level.validate().is_ok(), "{:?}", level.validate());
                if let (Some((lo, hi)), Some((flo, fhi))) =
                    (level.height_range(), mipmap.levels()[0].height_range())
                {
                    prop_assert!(lo >= flo && hi <= fhi, "heights stay within the input's");
                }
            }
        }
    }
}
