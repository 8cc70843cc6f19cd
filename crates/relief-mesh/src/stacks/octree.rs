//! The octree over the stacks mipmap (section 3.3): nodes of `n^3` cells of one level, chosen
//! for a camera by their screen-space extent (equation 1) against τ, then balanced so that
//! neighbours (across faces, edges and corners) differ by at most one level.

use rustc_hash::FxHashSet;
use std::collections::{BTreeMap, BTreeSet};

/// An octree node: its level (0 finest) and its position in nodes of that level; its own
/// lattice points are `[key * n, key * n + n)` along each axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct NodeKey {
    /// Level of the mipmap, 0 finest.
    pub level: u8,
    /// Node position along x, y, z.
    pub at: [i32; 3],
}

impl NodeKey {
    /// The node one level coarser that contains this one.
    pub fn parent(&self) -> NodeKey {
        NodeKey { level: self.level + 1, at: self.at.map(|c| c.div_euclid(2)) }
    }

    /// The eight nodes one level finer inside this one.
    pub fn children(&self) -> impl Iterator<Item = NodeKey> + '_ {
        (0..8).map(move |c| NodeKey {
            level: self.level - 1,
            at: std::array::from_fn(|a| 2 * self.at[a] + ((c >> a) & 1)),
        })
    }

    /// The node's first own lattice point.
    pub fn origin(&self, n: i32) -> [i32; 3] {
        self.at.map(|c| c * n)
    }
}

/// A set of leaves that partitions space: every point lies in exactly one leaf.
#[derive(Debug, Clone, Default)]
pub(crate) struct Leaves {
    set: FxHashSet<NodeKey>,
    /// Per level, which nodes are leaves and which are split into finer ones (the leaves'
    /// ancestors): the lookups of balancing, an array index each.
    marks: Vec<LevelMarks>,
    max_level: u8,
    /// The smallest and largest root positions: no leaf lies outside the roots.
    roots: ([i32; 3], [i32; 3]),
}

/// What a node is in a [`Leaves`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Mark {
    /// Neither a leaf nor split: inside a coarser leaf, or outside the roots.
    None = 0,
    Leaf = 1,
    Split = 2,
}

/// The marks of one level's nodes in a box of node positions (a node outside it is
/// [`Mark::None`]).
#[derive(Debug, Clone, Default)]
struct LevelMarks {
    low: [i32; 3],
    size: [usize; 3],
    marks: Vec<u8>,
}

impl LevelMarks {
    /// The marks of nodes `low..=high` (every one [`Mark::None`]).
    fn new(low: [i32; 3], high: [i32; 3]) -> Self {
        let size = std::array::from_fn(|a| (high[a] as i64 - low[a] as i64 + 1).max(0) as usize);
        LevelMarks { low, size, marks: vec![Mark::None as u8; size.iter().product()] }
    }

    fn index(&self, at: [i32; 3]) -> Option<usize> {
        let mut index = 0;
        for a in (0..3).rev() {
            let offset = at[a].wrapping_sub(self.low[a]) as u32 as usize;
            if offset >= self.size[a] {
                return None;
            }
            index = index * self.size[a] + offset;
        }
        Some(index)
    }

    fn get(&self, at: [i32; 3]) -> Mark {
        match self.index(at).map(|i| self.marks[i]) {
            Some(1) => Mark::Leaf,
            Some(2) => Mark::Split,
            _ => Mark::None,
        }
    }

    /// Marks node `at`, the box grown to hold it where it does not (balancing can split a
    /// leaf whose children lie outside the box chosen before it).
    fn set(&mut self, at: [i32; 3], mark: Mark) {
        if self.index(at).is_none() {
            let (low, high) = if self.marks.is_empty() {
                (at, at)
            } else {
                (
                    std::array::from_fn(|a| self.low[a].min(at[a])),
                    std::array::from_fn(|a| (self.low[a] + self.size[a] as i32 - 1).max(at[a])),
                )
            };
            let mut grown = LevelMarks::new(low, high);
            for (i, &m) in self.marks.iter().enumerate().filter(|(_, &m)| m != 0) {
                let (x, y, z) = (
                    i % self.size[0],
                    i / self.size[0] % self.size[1],
                    i / self.size[0] / self.size[1],
                );
                let at = [x, y, z].map(|c| c as i32);
                let at = std::array::from_fn(|a| at[a] + self.low[a]);
                let j = grown.index(at).expect("the grown box holds the old one");
                grown.marks[j] = m;
            }
            *self = grown;
        }
        let i = self.index(at).expect("the box holds the node");
        self.marks[i] = mark as u8;
    }
}

impl Leaves {
    /// Leaves chosen from `roots` (nodes of `max_level`) by `split`, which is asked about every
    /// node above level 0.
    pub fn select(roots: &[NodeKey], mut split: impl FnMut(&NodeKey) -> bool) -> Self {
        let max_level = roots.first().map_or(0, |r| r.level);
        let mut range = ([i32::MAX; 3], [i32::MIN; 3]);
        for root in roots {
            for a in 0..3 {
                range.0[a] = range.0[a].min(root.at[a]);
                range.1[a] = range.1[a].max(root.at[a]);
            }
        }
        let (mut set, mut interior) = (FxHashSet::default(), Vec::new());
        let mut stack: Vec<NodeKey> = roots.to_vec();
        while let Some(node) = stack.pop() {
            if node.level > 0 && split(&node) {
                interior.push(node);
                stack.extend(node.children());
            } else {
                set.insert(node);
            }
        }
        // Every node but a root is a child of a node one level up, and balancing only splits
        // leaves: a level's box is the one over the children of the level above's nodes.
        let mut boxes = vec![([i32::MAX; 3], [i32::MIN; 3]); max_level as usize + 1];
        boxes[max_level as usize] = range;
        for node in set.iter().chain(&interior).filter(|n| n.level > 0) {
            let (low, high) = &mut boxes[node.level as usize - 1];
            for a in 0..3 {
                low[a] = low[a].min(2 * node.at[a]);
                high[a] = high[a].max(2 * node.at[a] + 1);
            }
        }
        let mut marks: Vec<LevelMarks> =
            boxes.into_iter().map(|(low, high)| LevelMarks::new(low, high)).collect();
        for node in &set {
            marks[node.level as usize].set(node.at, Mark::Leaf);
        }
        for node in &interior {
            marks[node.level as usize].set(node.at, Mark::Split);
        }
        let mut leaves = Leaves { set, marks, max_level, roots: range };
        leaves.balance();
        leaves
    }

    /// What node `key` is.
    fn mark(&self, key: &NodeKey) -> Mark {
        self.marks.get(key.level as usize).map_or(Mark::None, |m| m.get(key.at))
    }

    /// The leaf covering the region of node `key` or a coarser leaf containing it, if any.
    fn covering(&self, key: &NodeKey) -> Option<NodeKey> {
        // Outside the roots nothing covers it.
        let up = u32::from(self.max_level.saturating_sub(key.level)).min(31);
        let top = key.at.map(|c| c >> up);
        if (0..3).any(|a| top[a] < self.roots.0[a] || top[a] > self.roots.1[a]) {
            return None;
        }
        let mut k = *key;
        loop {
            match self.mark(&k) {
                Mark::Leaf => return Some(k),
                // A split node's region is covered by finer leaves, and so is any node's
                // inside it.
                Mark::Split => return None,
                Mark::None if k.level >= self.max_level => return None,
                Mark::None => k = k.parent(),
            }
        }
    }

    /// Splits leaves until no two neighbours (26-connected) differ by more than one level.
    fn balance(&mut self) {
        // Splitting a node only makes covers finer, so a leaf whose neighbours' covers were
        // fine stays fine: after the first pass over every leaf, only the leaves a split made
        // and those that saw a cover too coarse (it may still be, one level finer) are checked.
        let mut work: Vec<NodeKey> = self.set.iter().copied().collect();
        while !work.is_empty() {
            let mut to_split = BTreeSet::new();
            let mut again = Vec::new();
            for leaf in &work {
                let mut violated = false;
                for d in neighbour_offsets() {
                    let at = std::array::from_fn(|a| leaf.at[a] + d[a]);
                    if let Some(cover) = self.covering(&NodeKey { level: leaf.level, at }) {
                        if cover.level > leaf.level + 1 {
                            to_split.insert(cover);
                            violated = true;
                        }
                    }
                }
                if violated {
                    again.push(*leaf);
                }
            }
            work = again;
            for node in to_split {
                self.set.remove(&node);
                self.marks[node.level as usize].set(node.at, Mark::Split);
                for child in node.children() {
                    self.set.insert(child);
                    self.marks[child.level as usize].set(child.at, Mark::Leaf);
                    work.push(child);
                }
            }
            // A leaf split in this round is no leaf to check.
            work.retain(|k| self.set.contains(k));
        }
    }

    /// For each leaf `keep` keeps, the coarser leaves among its 26 neighbours (one level up,
    /// by balance).
    pub fn coarser_neighbours(
        &self,
        keep: impl Fn(&NodeKey) -> bool,
    ) -> BTreeMap<NodeKey, Vec<NodeKey>> {
        let mut out = BTreeMap::new();
        for leaf in self.set.iter().filter(|leaf| keep(leaf)) {
            let mut coarser = Vec::new();
            for d in neighbour_offsets() {
                let at = std::array::from_fn(|a| leaf.at[a] + d[a]);
                if let Some(cover) = self.covering(&NodeKey { level: leaf.level, at }) {
                    if cover.level > leaf.level && !coarser.contains(&cover) {
                        coarser.push(cover);
                    }
                }
            }
            coarser.sort();
            out.insert(*leaf, coarser);
        }
        out
    }
}

/// The 26 offsets to a node's neighbours.
fn neighbour_offsets() -> impl Iterator<Item = [i32; 3]> {
    (0..27).filter(|&i| i != 13).map(|i| [i % 3 - 1, (i / 3) % 3 - 1, i / 9 - 1])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn balancing_keeps_neighbours_within_one_level() {
        let roots: Vec<NodeKey> =
            (0..2).flat_map(|x| (0..2).map(move |y| NodeKey { level: 3, at: [x, y, 0] })).collect();
        // Refine only towards the corner (0, 0, 0).
        let leaves = Leaves::select(&roots, |k| k.at == [0, 0, 0]);
        assert!(leaves.coarser_neighbours(|_| true).keys().any(|k| k.level == 0));
        for (leaf, coarser) in leaves.coarser_neighbours(|_| true) {
            for c in coarser {
                assert_eq!(c.level, leaf.level + 1, "{leaf:?} next to {c:?}");
            }
        }
    }

    #[test]
    fn levels_without_nodes_are_no_trouble() {
        // No split: the levels below the roots hold no node.
        let roots = [NodeKey { level: 4, at: [0, 0, 0] }, NodeKey { level: 4, at: [1, 0, 0] }];
        let leaves = Leaves::select(&roots, |_| false);
        let mut got: Vec<NodeKey> = leaves.set.iter().copied().collect();
        got.sort();
        assert_eq!(got, roots);
        // One chain of splits down to level 0 beside an unsplit root: balancing splits the
        // root level by level, into levels that held nothing before.
        let leaves = Leaves::select(&roots, |k| k.at == [1 << (4 - k.level), 0, 0]);
        for (leaf, coarser) in leaves.coarser_neighbours(|_| true) {
            assert!(coarser.iter().all(|c| c.level == leaf.level + 1), "{leaf:?}");
        }
    }

    /// Balancing by full passes over every leaf until nothing splits, covers found by walking
    /// up to the roots: the plain algorithm the balance above must agree with.
    fn balanced_by_full_passes(
        roots: &[NodeKey],
        split: impl Fn(&NodeKey) -> bool,
    ) -> Vec<NodeKey> {
        let max_level = roots[0].level;
        let mut set: FxHashSet<NodeKey> = FxHashSet::default();
        let mut stack = roots.to_vec();
        while let Some(node) = stack.pop() {
            if node.level > 0 && split(&node) {
                stack.extend(node.children());
            } else {
                set.insert(node);
            }
        }
        let covering = |set: &FxHashSet<NodeKey>, key: &NodeKey| {
            let mut k = *key;
            loop {
                if set.contains(&k) {
                    return Some(k);
                }
                if k.level >= max_level {
                    return None;
                }
                k = k.parent();
            }
        };
        loop {
            let mut to_split = BTreeSet::new();
            for leaf in &set {
                for d in neighbour_offsets() {
                    let at = std::array::from_fn(|a| leaf.at[a] + d[a]);
                    if let Some(cover) = covering(&set, &NodeKey { level: leaf.level, at }) {
                        if cover.level > leaf.level + 1 {
                            to_split.insert(cover);
                        }
                    }
                }
            }
            if to_split.is_empty() {
                let mut leaves: Vec<NodeKey> = set.into_iter().collect();
                leaves.sort();
                return leaves;
            }
            for node in to_split {
                set.remove(&node);
                set.extend(node.children());
            }
        }
    }

    #[test]
    fn balancing_agrees_with_full_passes() {
        // Roots with gaps (empty roots left out), refined towards a few random points.
        let mut seed = 12345u64;
        let mut next = move || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 33) as i32
        };
        for case in 0..20 {
            let roots: Vec<NodeKey> = (0..4)
                .flat_map(|x| (0..3).flat_map(move |y| (0..2).map(move |z| [x, y, z])))
                .filter(|_| next() % 5 != 0)
                .map(|at| NodeKey { level: 5, at })
                .collect();
            // Random points, and one on the corner of roots: its finest leaves touch roots
            // five levels coarser, which balancing splits level by level.
            let mut targets: Vec<[i32; 3]> =
                (0..3).map(|_| [next() % 128, next() % 96, next() % 64]).collect();
            if case % 2 == 0 {
                targets = vec![[32, 32, 32]];
            }
            // Split while a target lies within a node's size of the node.
            let split = |k: &NodeKey| {
                let size = 1i32 << k.level;
                let reach = if case % 2 == 0 { 0 } else { size };
                targets.iter().any(|t| {
                    (0..3).all(|a| {
                        let lo = k.at[a] * size;
                        t[a] >= lo - reach && t[a] < lo + size + reach
                    })
                }) && k.level > (case % 3) as u8
            };
            let leaves = Leaves::select(&roots, split);
            let mut got: Vec<NodeKey> = leaves.set.iter().copied().collect();
            got.sort();
            assert_eq!(got, balanced_by_full_passes(&roots, split), "case {case}");
            // The coarser neighbours by walking up from each neighbour to the roots.
            let set: FxHashSet<NodeKey> = got.iter().copied().collect();
            let walk = |key: &NodeKey| {
                let mut k = *key;
                loop {
                    if set.contains(&k) {
                        return Some(k);
                    }
                    if k.level >= 5 {
                        return None;
                    }
                    k = k.parent();
                }
            };
            for (leaf, coarser) in leaves.coarser_neighbours(|_| true) {
                let mut want = Vec::new();
                for d in neighbour_offsets() {
                    let at = std::array::from_fn(|a| leaf.at[a] + d[a]);
                    if let Some(cover) = walk(&NodeKey { level: leaf.level, at }) {
                        if cover.level > leaf.level && !want.contains(&cover) {
                            want.push(cover);
                        }
                    }
                }
                want.sort();
                assert_eq!(coarser, want, "case {case}, {leaf:?}");
            }
        }
    }
}
