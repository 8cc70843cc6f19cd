//! The node meshes kept across frames, and the amortisation of node meshing over frames
//! (Löffler et al. 2011, section 4: "in each frame we can update ≈ 40 nodes"): with a budget
//! of node meshes a frame, the nodes a frame wants but has no mesh for yet are drawn by what
//! the last frame drew over their place (the same node's mesh next to other neighbours, a
//! coarser ancestor's mesh, or finer descendants' meshes), until their turn comes: the
//! budget's nodes are made ahead, in the background once the frame that chose them is drawn,
//! for the next frame. Once a camera stays put long enough, every wanted node has its own
//! mesh and the frame is the one drawn without a budget.

use super::node_mesh::NodeMesh;
use super::octree::NodeKey;
use rayon::prelude::*;
use rustc_hash::{FxHashMap, FxHashSet};
use std::collections::HashMap;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, OnceLock};

/// How many levels coarser than a node its stand-in may be: a node whose nearest drawn
/// ancestor is coarser still is meshed in its frame (cells of at most `4 τ` pixels on screen).
const MAX_STAND_IN_LEVELS: u8 = 2;

/// A node as a frame wants it: its key and the coarser leaves next to it (they decide its
/// stitching, so they are part of what its mesh is).
pub(crate) type WantedNode = (NodeKey, Vec<NodeKey>);

/// The node meshes of recent frames.
#[derive(Debug, Default)]
pub(crate) struct NodeCache {
    /// Meshes by node and coarser neighbours: each exactly what meshing that node there makes.
    exact: HashMap<WantedNode, Arc<NodeMesh>>,
    /// What the last frame drew over each node's place: the node's own mesh or a stand-in.
    drawn: FxHashMap<NodeKey, Arc<NodeMesh>>,
    /// Node meshes made a frame at most, past those no stand-in covers; `None`: every node.
    budget: Option<usize>,
    /// The node meshes the last frame chose to make ahead of the next.
    ahead: Option<Ahead>,
}

/// The meshes a frame draws and how it came by them.
#[derive(Debug, Default)]
pub(crate) struct FrameMeshes {
    /// The meshes to draw, in the order of the wanted nodes (a stand-in where the first node
    /// it stands in for is).
    pub meshes: Vec<Arc<NodeMesh>>,
    /// Node meshes made for this frame.
    pub meshed: usize,
    /// Wanted nodes drawn by a stand-in, their own meshes still to make.
    pub waiting: usize,
}

/// What stands in for a wanted node that has no mesh of its own yet.
#[derive(Debug, Clone)]
enum StandIn {
    /// Nothing the last frame drew covers it: it must be meshed now.
    None,
    /// The same node's mesh next to other neighbours (only the stitching differs).
    SameNode(NodeKey),
    /// A coarser node's mesh (the node's region is part of it).
    Ancestor(NodeKey),
    /// Finer nodes' meshes (the parts of the node's region the last frame drew).
    Descendants(Vec<NodeKey>),
}

impl StandIn {
    /// The order in which the nodes of `level` get their own meshes: those nothing stands in
    /// for, then those drawn coarser than they should be (the coarser, the sooner), then finer,
    /// then those whose neighbours changed.
    fn rank(&self, level: u8) -> u8 {
        match self {
            StandIn::None => 0,
            StandIn::Ancestor(up) => 1 + MAX_STAND_IN_LEVELS - (up.level - level),
            StandIn::Descendants(_) => 2 + MAX_STAND_IN_LEVELS,
            StandIn::SameNode(_) => 3 + MAX_STAND_IN_LEVELS,
        }
    }
}

impl NodeCache {
    /// Sets the budget: at most `budget` node meshes made a frame beyond those nothing stands
    /// in for (`None`: every wanted node meshed in its frame).
    pub fn set_budget(&mut self, budget: Option<usize>) {
        self.budget = budget;
    }

    /// The budget of node meshes a frame.
    pub fn budget(&self) -> Option<usize> {
        self.budget
    }

    /// The meshes of a frame that wants `wanted` (each node once, in a fixed order): nodes
    /// meshed before (same node, same coarser neighbours) from the cache, with those the last
    /// frame chose to make ahead; of the others, those nothing the last frame drew covers made
    /// now by `mesh` in parallel, and, when `amortised`, the most needed within the budget
    /// chosen to make ahead for the next frame ([`NodeCache::begin_ahead`]; else all of them
    /// made now); the rest drawn by stand-ins. The cache then keeps this frame's meshes.
    pub fn frame(
        &mut self,
        wanted: &[WantedNode],
        amortised: bool,
        mesh: &NodeMaking,
    ) -> FrameMeshes {
        let mut meshed = self.join_ahead(mesh.as_ref());
        let missing: Vec<usize> =
            (0..wanted.len()).filter(|&w| !self.exact.contains_key(&wanted[w])).collect();
        let budget = if amortised { self.budget } else { None };
        let (to_mesh, ahead, stand_ins) = match budget {
            Some(budget) => self.choose(wanted, &missing, budget),
            None => (missing, Vec::new(), FxHashMap::default()),
        };
        let made: Vec<Arc<NodeMesh>> =
            to_mesh.par_iter().map(|&w| Arc::new(mesh(&wanted[w].0, &wanted[w].1))).collect();
        meshed += made.len();
        for (&w, m) in to_mesh.iter().zip(made) {
            self.exact.insert(wanted[w].clone(), m);
        }
        if !ahead.is_empty() {
            let nodes = ahead.iter().map(|&w| wanted[w].clone()).collect();
            self.ahead = Some(Ahead::new(nodes));
        }

        let mut frame = FrameMeshes { meshed, ..FrameMeshes::default() };
        let mut drawn = FxHashMap::default();
        for (w, node) in wanted.iter().enumerate() {
            if let Some(m) = self.exact.get(node) {
                frame.meshes.push(m.clone());
                drawn.insert(node.0, m.clone());
                continue;
            }
            frame.waiting += 1;
            let keys = match &stand_ins[&w] {
                StandIn::SameNode(key) | StandIn::Ancestor(key) => std::slice::from_ref(key),
                StandIn::Descendants(keys) => keys.as_slice(),
                StandIn::None => unreachable!("a node nothing stands in for is meshed"),
            };
            for key in keys {
                if !drawn.contains_key(key) {
                    let m = self.drawn[key].clone();
                    frame.meshes.push(m.clone());
                    drawn.insert(*key, m);
                }
            }
        }
        let keep: FxHashSet<&WantedNode> = wanted.iter().collect();
        self.exact.retain(|k, _| keep.contains(k));
        self.drawn = drawn;
        frame
    }

    /// Of the missing nodes, which to mesh now (indices into `wanted`): those nothing stands
    /// in for; which to begin ahead: up to `budget` more by [`StandIn::rank`], coarser levels
    /// first, then in `wanted`'s order; and what stands in for every node not meshed now.
    fn choose(
        &self,
        wanted: &[WantedNode],
        missing: &[usize],
        budget: usize,
    ) -> (Vec<usize>, Vec<usize>, FxHashMap<usize, StandIn>) {
        let mut stand_ins: FxHashMap<usize, StandIn> =
            missing.iter().map(|&w| (w, self.stand_in(&wanted[w].0))).collect();
        // Nodes that only finer meshes the last frame drew can stand in for.
        let open: FxHashMap<NodeKey, usize> = missing
            .iter()
            .filter(|w| matches!(stand_ins[w], StandIn::None))
            .map(|&w| (wanted[w].0, w))
            .collect();
        if !open.is_empty() {
            let mut finer: Vec<(NodeKey, usize)> = Vec::new();
            for key in self.drawn.keys() {
                let mut up = *key;
                for _ in 0..MAX_STAND_IN_LEVELS {
                    up = up.parent();
                    if let Some(&w) = open.get(&up) {
                        finer.push((*key, w));
                        break;
                    }
                }
            }
            finer.sort();
            for (key, w) in finer {
                match stand_ins.get_mut(&w) {
                    Some(StandIn::Descendants(keys)) => keys.push(key),
                    Some(s) => *s = StandIn::Descendants(vec![key]),
                    None => {}
                }
            }
        }
        let mut order: Vec<usize> = missing.to_vec();
        order.sort_by_key(|&w| {
            let level = wanted[w].0.level;
            (stand_ins[&w].rank(level), std::cmp::Reverse(level), w)
        });
        let now = order.iter().filter(|w| matches!(stand_ins[w], StandIn::None)).count();
        let mut to_mesh: Vec<usize> = order[..now].to_vec();
        to_mesh.sort_unstable();
        for w in &to_mesh {
            stand_ins.remove(w);
        }
        let mut ahead: Vec<usize> = order[now..(now + budget).min(order.len())].to_vec();
        ahead.sort_unstable();
        (to_mesh, ahead, stand_ins)
    }

    /// Begins making, on a thread of its own, the node meshes the last frame chose to make
    /// ahead (if it has not yet): they overlap what the caller does until the next frame,
    /// which makes what is left.
    pub fn begin_ahead(&mut self, mesh: &NodeMaking) {
        if let Some(ahead) = &mut self.ahead {
            ahead.begin(mesh.clone());
        }
    }

    /// Takes in the node meshes the last frame chose to make ahead, those not made yet made
    /// now on every core; returns how many.
    fn join_ahead(&mut self, mesh: &MakeNode) -> usize {
        let Some(ahead) = self.ahead.take() else { return 0 };
        let job = ahead.finish(mesh);
        let count = job.nodes.len();
        for (node, made) in job.nodes.iter().zip(&job.made) {
            let made = made.get().expect("every node of a finished job is made");
            self.exact.insert(node.clone(), made.clone());
        }
        count
    }

    /// What the last frame drew that stands in for node `key`: the same node, else its
    /// nearest drawn ancestor at most [`MAX_STAND_IN_LEVELS`] coarser, else nothing
    /// (descendants are found by [`NodeCache::choose`]).
    fn stand_in(&self, key: &NodeKey) -> StandIn {
        if self.drawn.contains_key(key) {
            return StandIn::SameNode(*key);
        }
        let mut up = *key;
        for _ in 0..MAX_STAND_IN_LEVELS {
            up = up.parent();
            if self.drawn.contains_key(&up) {
                return StandIn::Ancestor(up);
            }
        }
        StandIn::None
    }
}

/// How a node is meshed: the node and its coarser neighbours to its mesh.
pub(crate) type MakeNode = dyn Fn(&NodeKey, &[NodeKey]) -> NodeMesh + Send + Sync;

/// [`MakeNode`], shared with the thread that meshes ahead.
pub(crate) type NodeMaking = Arc<MakeNode>;

/// Node meshes made ahead of the frame that draws them: begun by a thread of low priority
/// once the frame that chose them is drawn (it takes what the caller leaves of the
/// processors until the next frame), the next frame making the rest (`finish`). The same
/// meshes whoever makes them, so frames do not depend on timing.
#[derive(Debug)]
struct Ahead {
    job: Arc<AheadJob>,
    /// Whether a thread works on it.
    begun: bool,
}

/// The nodes to mesh ahead and their meshes, each made by whoever takes it first.
#[derive(Debug)]
struct AheadJob {
    nodes: Vec<WantedNode>,
    /// The first node no one has taken yet.
    next: AtomicUsize,
    made: Vec<OnceLock<Arc<NodeMesh>>>,
}

impl AheadJob {
    /// Takes nodes and meshes them with `mesh` until none is left.
    fn work(&self, mesh: &MakeNode) {
        loop {
            let i = self.next.fetch_add(1, Ordering::Relaxed);
            let Some((key, coarser)) = self.nodes.get(i) else { return };
            let _ = self.made[i].set(Arc::new(mesh(key, coarser)));
        }
    }
}

impl Ahead {
    /// `nodes` to mesh ahead, not begun.
    fn new(nodes: Vec<WantedNode>) -> Ahead {
        let made = (0..nodes.len()).map(|_| OnceLock::new()).collect();
        Ahead { job: Arc::new(AheadJob { nodes, next: AtomicUsize::new(0), made }), begun: false }
    }

    /// Begins meshing the nodes with `mesh` on a thread of low priority, unless begun.
    fn begin(&mut self, mesh: NodeMaking) {
        if std::mem::replace(&mut self.begun, true) {
            return;
        }
        let job = self.job.clone();
        std::thread::spawn(move || {
            background_priority();
            job.work(mesh.as_ref());
        });
    }

    /// The job done on every core: the nodes no one has taken yet, then any the thread took
    /// and has not finished, made again rather than waited for (at its priority, a busy
    /// machine could keep it waiting long; the mesh is the same, and the thread's copy is
    /// dropped when it is done).
    fn finish(self, mesh: &MakeNode) -> Arc<AheadJob> {
        let job = self.job;
        (0..rayon::current_num_threads()).into_par_iter().for_each(|_| job.work(mesh));
        job.made.par_iter().zip(&job.nodes).for_each(|(made, (key, coarser))| {
            made.get_or_init(|| Arc::new(mesh(key, coarser)));
        });
        job
    }
}

impl Drop for NodeCache {
    /// Stops the meshing ahead after the node its thread is making.
    fn drop(&mut self) {
        if let Some(ahead) = &self.ahead {
            ahead.job.next.store(usize::MAX / 2, Ordering::Relaxed);
        }
    }
}

/// Lowers the calling thread's priority to the lowest (Linux's `SCHED_IDLE`: it runs only on
/// what the frame's threads leave idle). Where the system has no such call, the thread keeps
/// its priority.
fn background_priority() {
    #[cfg(target_os = "linux")]
    #[allow(unsafe_code)]
    // SAFETY: a system call on the calling thread (0) with a parameter that outlives it.
    unsafe {
        let param = libc::sched_param { sched_priority: 0 };
        libc::sched_setscheduler(0, libc::SCHED_IDLE, &param);
    }
}
