//! The material aggregation of Löffler et al. (section 3.1): one coarse stack from its weighted
//! finer children, segment by segment ([`aggregate_stack`]).
//!
//! The height axis is cut at every start and end of the children's layers. Each segment's
//! composition is the weight of every material over it, air (a child with no layer there)
//! counted as a pseudo-material. A strictly heaviest material is chosen; a tie is decided by
//! the nearest dominated segments below and above, by a split between them, or by a widening
//! window of segments, and finally by the lowest material index with air last.

use super::StackLayer;

/// The pseudo-material index of air in a composition (after every real index, 0 to 255).
const AIR: u16 = 256;

/// Segments (and split parts, and merged layers) thinner than this, in metres, are dropped.
pub(crate) const MIN_THICKNESS: f64 = 1e-6;

/// Most children a coarse stack has: its 3 x 3 neighbourhood.
const MAX_CHILDREN: usize = 9;

/// The weight of each material over one segment: at most one entry per child.
#[derive(Debug, Clone, Copy)]
struct Composition {
    /// `(material, weight)`, air as [`AIR`]; only the first `len` are used.
    entries: [(u16, u32); MAX_CHILDREN],
    /// Number of entries used.
    len: usize,
}

impl Composition {
    /// No material at all.
    const EMPTY: Composition = Composition { entries: [(0, 0); MAX_CHILDREN], len: 0 };

    /// Adds `weight` to `material`.
    fn add(&mut self, material: u16, weight: u32) {
        let used = &mut self.entries[..self.len];
        match used.iter_mut().find(|(m, _)| *m == material) {
            Some(entry) => entry.1 += weight,
            None => {
                self.entries[self.len] = (material, weight);
                self.len += 1;
            }
        }
    }

    /// The weight of `material` (0 when absent).
    fn weight(&self, material: u16) -> u32 {
        self.used().iter().find(|(m, _)| *m == material).map_or(0, |e| e.1)
    }

    /// The entries in use.
    fn used(&self) -> &[(u16, u32)] {
        &self.entries[..self.len]
    }

    /// The greatest weight.
    fn max_weight(&self) -> u32 {
        self.used().iter().map(|e| e.1).max().unwrap_or(0)
    }

    /// The material of strictly greatest weight, if one has it (rule 1).
    fn dominant(&self) -> Option<u16> {
        let max = self.max_weight();
        let mut heaviest = self.used().iter().filter(|e| e.1 == max);
        let first = heaviest.next()?;
        heaviest.next().is_none().then_some(first.0)
    }
}

/// One segment of the height axis: its bounds, composition and step-1 dominant material.
#[derive(Debug, Clone, Copy)]
struct Segment {
    start: f32,
    end: f32,
    composition: Composition,
    dominant: Option<u16>,
}

impl Segment {
    /// Thickness in metres.
    fn thickness(&self) -> f64 {
        f64::from(self.end) - f64::from(self.start)
    }
}

/// Reusable buffers of [`aggregate_stack`], one per thread.
#[derive(Debug, Default)]
pub(crate) struct Scratch {
    cuts: Vec<f32>,
    segments: Vec<Segment>,
    pieces: Vec<(f32, f32, u16)>,
    candidates: Vec<u16>,
    scores: Vec<f64>,
}

/// Appends to `out` the layers of the coarse stack aggregated from `children`, each a finer
/// stack (valid: sorted, non-overlapping) with its weight. Children left out of the list (out
/// of the grid) count for nothing; a child with no layer over a segment gives its weight to air.
///
/// Per segment between consecutive cuts (every layer start and end), thinner segments than
/// [`MIN_THICKNESS`] left out:
/// 1. a material (air included) of strictly greatest weight is chosen;
/// 2. on a tie between candidates, with `B` and `A` the dominant materials of the nearest
///    segments below and above that have one (none past the stack's ends):
///    a. if exactly one candidate is among `B` and `A` (or both are the same candidate), it is
///    chosen;
///    b. if `B` and `A` are different candidates, the segment is split: `B` below, `A` above,
///    at the point dividing it in the ratio of their weights (the midpoint, as they tie);
///    c. otherwise, for `r = 2, 3, ...`, the candidates are scored over the segments
///    `k - r ..= k + r` (clamped to the stack) by weight times thickness, and a strict winner
///    is chosen; once the window covers the whole stack, the tied best candidates fall back to
///    the lowest material index, air after every material.
///
/// Consecutive pieces of one material are then merged (across left-out thin segments), air is
/// dropped, and so are layers thinner than [`MIN_THICKNESS`].
pub(crate) fn aggregate_stack(
    children: &[(&[StackLayer], u32)],
    scratch: &mut Scratch,
    out: &mut Vec<StackLayer>,
) {
    debug_assert!(children.len() <= MAX_CHILDREN);
    cut_segments(children, scratch);
    let Scratch { segments, pieces, candidates, scores, .. } = scratch;
    pieces.clear();
    for k in 0..segments.len() {
        let segment = segments[k];
        if let Some(material) = segment.dominant {
            pieces.push((segment.start, segment.end, material));
            continue;
        }
        let max = segment.composition.max_weight();
        candidates.clear();
        candidates.extend(segment.composition.used().iter().filter(|e| e.1 == max).map(|e| e.0));
        candidates.sort_unstable();
        let is_candidate = |m: &u16| candidates.contains(m);
        let below = segments[..k].iter().rev().find_map(|s| s.dominant).filter(is_candidate);
        let above = segments[k + 1..].iter().find_map(|s| s.dominant).filter(is_candidate);
        match (below, above) {
            (Some(b), Some(a)) if a != b => {
                let (wb, wa) = (segment.composition.weight(b), segment.composition.weight(a));
                let ratio = f64::from(wb) / f64::from(wb + wa);
                let split = (f64::from(segment.start) + segment.thickness() * ratio) as f32;
                pieces.push((segment.start, split, b));
                pieces.push((split, segment.end, a));
            }
            (Some(m), _) | (None, Some(m)) => pieces.push((segment.start, segment.end, m)),
            (None, None) => {
                let material = widen(segments, k, candidates, scores);
                pieces.push((segment.start, segment.end, material));
            }
        }
    }
    merge_pieces(pieces, out);
}

/// Cuts the height axis of `children` into `scratch.segments`, with their compositions and
/// step-1 dominant materials.
fn cut_segments(children: &[(&[StackLayer], u32)], scratch: &mut Scratch) {
    let Scratch { cuts, segments, .. } = scratch;
    cuts.clear();
    segments.clear();
    for (layers, _) in children {
        for layer in layers.iter() {
            cuts.push(layer.start);
            cuts.push(layer.end);
        }
    }
    cuts.sort_unstable_by(f32::total_cmp);
    cuts.dedup();
    // Per child, the first layer that may still cover a segment (segments ascend).
    let mut next = [0usize; MAX_CHILDREN];
    for pair in cuts.windows(2) {
        let (start, end) = (pair[0], pair[1]);
        if f64::from(end) - f64::from(start) < MIN_THICKNESS {
            continue;
        }
        let mut composition = Composition::EMPTY;
        for (c, (layers, weight)) in children.iter().enumerate() {
            while next[c] < layers.len() && layers[next[c]].end <= start {
                next[c] += 1;
            }
            // Layer bounds are cuts: a layer starting at or below `start` covers the segment.
            let material = match layers.get(next[c]) {
                Some(layer) if layer.start <= start => u16::from(layer.material),
                _ => AIR,
            };
            composition.add(material, *weight);
        }
        let dominant = composition.dominant();
        segments.push(Segment { start, end, composition, dominant });
    }
}

/// Rule 2c for the tied segment `k` among `candidates` (sorted): the candidate of strictly
/// greatest weight times thickness over a widening window, else the lowest index (air last).
fn widen(segments: &[Segment], k: usize, candidates: &[u16], scores: &mut Vec<f64>) -> u16 {
    let last = segments.len() - 1;
    let mut r = 2;
    loop {
        let (lo, hi) = (k.saturating_sub(r), (k + r).min(last));
        scores.clear();
        scores.extend(candidates.iter().map(|&m| {
            segments[lo..=hi]
                .iter()
                .map(|s| f64::from(s.composition.weight(m)) * s.thickness())
                .sum::<f64>()
        }));
        let best = scores.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let mut winners = candidates.iter().zip(scores.iter()).filter(|(_, &s)| s == best);
        let first = winners.next().map_or(candidates[0], |(&m, _)| m);
        if winners.next().is_none() || (lo == 0 && hi == last) {
            // A strict winner, or the fallback: candidates are sorted, air (256) last.
            return first;
        }
        r += 1;
    }
}

/// Merges consecutive `pieces` of one material, drops air and layers thinner than
/// [`MIN_THICKNESS`], and appends the rest to `out`.
fn merge_pieces(pieces: &[(f32, f32, u16)], out: &mut Vec<StackLayer>) {
    let mut k = 0;
    while k < pieces.len() {
        let (start, mut end, material) = pieces[k];
        k += 1;
        while k < pieces.len() && pieces[k].2 == material {
            end = pieces[k].1;
            k += 1;
        }
        if material != AIR && f64::from(end) - f64::from(start) >= MIN_THICKNESS {
            out.push(StackLayer::new(start, end, material as u8));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::StackMaterial;

    const BEDROCK: u8 = StackMaterial::BEDROCK;
    const SAND: u8 = StackMaterial::SAND;
    const WATER: u8 = StackMaterial::WATER;

    fn l(start: f32, end: f32, material: u8) -> StackLayer {
        StackLayer::new(start, end, material)
    }

    /// The coarse stack of `children`, each with its weight.
    fn aggregate(children: &[(Vec<StackLayer>, u32)]) -> Vec<StackLayer> {
        let children: Vec<(&[StackLayer], u32)> =
            children.iter().map(|(layers, w)| (layers.as_slice(), *w)).collect();
        let mut out = Vec::new();
        aggregate_stack(&children, &mut Scratch::default(), &mut out);
        out
    }

    #[test]
    fn rule_1_three_of_four_make_the_dominant_material() {
        let rock = vec![l(0.0, 1.0, BEDROCK)];
        let coarse = aggregate(&[
            (rock.clone(), 1),
            (rock.clone(), 1),
            (rock, 1),
            (vec![l(0.0, 1.0, SAND)], 1),
        ]);
        assert_eq!(coarse, vec![l(0.0, 1.0, BEDROCK)]);
    }

    #[test]
    fn rule_1_weights_count_not_children() {
        // One centre child (weight 4) of sand outweighs three corners (weight 1) of rock.
        let rock = vec![l(0.0, 1.0, BEDROCK)];
        let coarse = aggregate(&[
            (vec![l(0.0, 1.0, SAND)], 4),
            (rock.clone(), 1),
            (rock.clone(), 1),
            (rock, 1),
        ]);
        assert_eq!(coarse, vec![l(0.0, 1.0, SAND)]);
    }

    #[test]
    fn air_is_a_material_and_a_dominant_air_leaves_a_gap() {
        // Over [1, 2] three children of four have nothing: air wins, the arch's gap stays.
        let coarse = aggregate(&[
            (vec![l(0.0, 1.0, BEDROCK), l(2.0, 3.0, BEDROCK)], 1),
            (vec![l(0.0, 1.0, BEDROCK), l(2.0, 3.0, BEDROCK)], 1),
            (vec![l(0.0, 1.0, BEDROCK), l(2.0, 3.0, BEDROCK)], 1),
            (vec![l(0.0, 3.0, BEDROCK)], 1),
        ]);
        assert_eq!(coarse, vec![l(0.0, 1.0, BEDROCK), l(2.0, 3.0, BEDROCK)]);
    }

    #[test]
    fn rule_2a_a_tie_takes_the_candidate_dominating_below() {
        // [1, 2]: sand 1, water 1; below, sand dominates; above is nothing.
        let coarse = aggregate(&[
            (vec![l(0.0, 2.0, SAND)], 1),
            (vec![l(0.0, 1.0, SAND), l(1.0, 2.0, WATER)], 1),
        ]);
        assert_eq!(coarse, vec![l(0.0, 2.0, SAND)]);
    }

    #[test]
    fn rule_2a_a_tie_takes_the_one_candidate_among_the_neighbours() {
        // [1, 2]: sand 1, water 1; below bedrock (not a candidate), above water.
        let coarse = aggregate(&[
            (vec![l(0.0, 1.0, BEDROCK), l(1.0, 2.0, SAND), l(2.0, 3.0, WATER)], 1),
            (vec![l(0.0, 1.0, BEDROCK), l(1.0, 3.0, WATER)], 1),
        ]);
        assert_eq!(coarse, vec![l(0.0, 1.0, BEDROCK), l(1.0, 3.0, WATER)]);
    }

    #[test]
    fn rule_2_looks_past_tied_neighbours() {
        // [1, 2] and [2, 3] both tie sand 2 against water 2; for each, the nearest dominated
        // segments are [0, 1] (sand) below and [3, 4] (water) above: both are split.
        let coarse = aggregate(&[
            (vec![l(0.0, 3.0, SAND)], 2),
            (vec![l(0.0, 1.0, SAND), l(1.0, 2.0, WATER), l(2.0, 4.0, WATER)], 2),
            (vec![l(3.0, 4.0, WATER)], 1),
        ]);
        assert_eq!(
            coarse,
            vec![l(0.0, 1.5, SAND), l(1.5, 2.0, WATER), l(2.0, 2.5, SAND), l(2.5, 4.0, WATER)]
        );
    }

    #[test]
    fn rule_2b_a_tie_between_two_dominated_neighbours_is_split_at_its_middle() {
        // [1, 2]: bedrock 1, sand 1; bedrock dominates below, sand above.
        let coarse = aggregate(&[
            (vec![l(0.0, 1.0, BEDROCK), l(1.0, 3.0, SAND)], 1),
            (vec![l(0.0, 2.0, BEDROCK), l(2.0, 3.0, SAND)], 1),
        ]);
        assert_eq!(coarse, vec![l(0.0, 1.5, BEDROCK), l(1.5, 3.0, SAND)]);
    }

    #[test]
    fn rule_2c_a_wider_window_decides_when_the_neighbours_are_no_candidates() {
        // Segments [0,1] .. [4,5]; [2, 3] ties sand 2 against bedrock 2, its neighbours are
        // water; over [0, 5] sand weighs 3 + 2 + 2 = 7 against bedrock's 1 + 1 + 2 + 1 = 5.
        let sandy = vec![
            l(0.0, 1.0, SAND),
            l(1.0, 2.0, WATER),
            l(2.0, 3.0, SAND),
            l(3.0, 4.0, WATER),
            l(4.0, 5.0, SAND),
        ];
        let coarse = aggregate(&[
            (sandy.clone(), 1),
            (sandy.clone(), 1),
            (
                vec![
                    l(0.0, 1.0, SAND),
                    l(1.0, 2.0, WATER),
                    l(2.0, 3.0, BEDROCK),
                    l(3.0, 4.0, WATER),
                    l(4.0, 5.0, BEDROCK),
                ],
                1,
            ),
            (vec![l(0.0, 3.0, BEDROCK), l(3.0, 4.0, WATER)], 1),
        ]);
        assert_eq!(coarse, sandy);
    }

    #[test]
    fn rule_2c_weighs_thickness() {
        // [1, 2] ties sand against bedrock between water; over the window [-4, 3.5] bedrock
        // scores 3 x 4 + 2 = 14 against sand's 1 x 4 + 1 + 2 + 4 x 0.5 = 9 (by weight alone,
        // sand would win 8 to 5).
        let upper = [l(2.0, 3.0, WATER), l(3.0, 3.5, SAND)];
        let child = |low: u8, middle: u8| {
            let mut layers = vec![l(-4.0, 0.0, low), l(0.0, 1.0, WATER), l(1.0, 2.0, middle)];
            layers.extend(upper);
            layers
        };
        let mut sandy = vec![l(-4.0, 1.0, SAND), l(1.0, 2.0, BEDROCK)];
        sandy.extend(upper);
        let coarse = aggregate(&[
            (child(BEDROCK, SAND), 1),
            (child(BEDROCK, SAND), 1),
            (child(BEDROCK, BEDROCK), 1),
            (sandy, 1),
        ]);
        assert_eq!(coarse, child(BEDROCK, BEDROCK));
    }

    #[test]
    fn fallback_takes_the_lowest_material_and_air_last() {
        let coarse = aggregate(&[(vec![l(0.0, 1.0, SAND)], 1), (vec![l(0.0, 1.0, BEDROCK)], 1)]);
        assert_eq!(coarse, vec![l(0.0, 1.0, BEDROCK)]);
        let coarse = aggregate(&[(vec![l(0.0, 1.0, WATER)], 1), (vec![], 1)]);
        assert_eq!(coarse, vec![l(0.0, 1.0, WATER)]);
    }

    #[test]
    fn segments_thinner_than_a_micrometre_are_dropped() {
        let top = 1.0f32.next_up();
        let coarse = aggregate(&[(vec![l(0.0, 1.0, BEDROCK)], 1), (vec![l(0.0, top, BEDROCK)], 1)]);
        // Kept, [1, top] would tie bedrock against air and take bedrock from below.
        assert_eq!(coarse, vec![l(0.0, 1.0, BEDROCK)]);
    }

    #[test]
    fn no_children_or_empty_children_make_an_empty_stack() {
        assert!(aggregate(&[]).is_empty());
        assert!(aggregate(&[(vec![], 4), (vec![], 2)]).is_empty());
    }
}
