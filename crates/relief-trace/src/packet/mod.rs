//! Coherent ray packets through the max mipmap: [`crate::MipmapTracer`]'s batch traversal.
//!
//! Neighbouring rays (a tile of camera pixels, the shadow rays of a tile) mostly visit the
//! same nodes of the pyramid. A packet of up to 64 rays with the same x and y direction signs
//! walks the pyramid once, depth first and front to back, testing each node against eight
//! rays at a time in `f32` (AVX2 where the processor has it, detected at run time, else
//! portable code). The node tests are conservative, so they never drop a ray that meets the
//! solid; the cells they cannot rule out get [`crate::CellGrid`]'s exact `f64` test, the same
//! one the naive and the single-ray mipmap traversals use, so hits are the same as theirs.

#[cfg(target_arch = "x86_64")]
mod avx2;
mod kernel;
mod ray_packet;
mod traversal;

use crate::cell_grid::CellGrid;
use crate::MaxMipmap;
use kernel::Portable;
use ray_packet::{RayPacket, PACKET_RAYS};
use relief_core::{DVec3, Ray};
use std::cell::RefCell;
use std::fmt;
use std::str::FromStr;
pub(crate) use traversal::{prefetch, prefetch_address};
use traversal::{CellHit, Pending, Terrain, Traversal, STACK};

/// The instructions the packet traversal's node tests run on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Simd {
    /// Eight rays per instruction with AVX2 and FMA (x86-64). Where the processor lacks
    /// them, the portable tests run instead.
    Avx2,
    /// Plain code, one ray at a time, for any processor.
    Portable,
}

impl Simd {
    /// The fastest choice this processor supports.
    pub fn detect() -> Simd {
        if avx2_available() {
            Simd::Avx2
        } else {
            Simd::Portable
        }
    }

    /// The name used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Simd::Avx2 => "avx2",
            Simd::Portable => "portable",
        }
    }

    /// What actually runs for this choice on this processor.
    pub fn effective(self) -> Simd {
        match self {
            Simd::Avx2 if avx2_available() => Simd::Avx2,
            _ => Simd::Portable,
        }
    }
}

impl fmt::Display for Simd {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(self.name())
    }
}

impl FromStr for Simd {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "auto" => Ok(Simd::detect()),
            "avx2" => Ok(Simd::Avx2),
            "portable" => Ok(Simd::Portable),
            other => {
                Err(format!("unknown SIMD choice '{other}' (expected auto, avx2 or portable)"))
            }
        }
    }
}

/// Whether this processor runs AVX2 and FMA instructions.
fn avx2_available() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// The terrain a batch is traced through, and how.
pub(crate) struct PacketTracing<'a> {
    /// The cell grid of the traced surface.
    pub grid: &'a CellGrid,
    /// The height field's samples.
    pub samples: &'a [f32],
    /// The pyramid over the grid's cells.
    pub mipmap: &'a MaxMipmap,
    /// The node tests' instructions.
    pub simd: Simd,
}

impl PacketTracing<'_> {
    /// Traces `rays` (world space) in packets, adding each ray's node visits to `steps` and
    /// calling `found(k, t, normal)` for every ray `k` that hits, with its parameter and
    /// grid-space normal (zero: the ray starts inside). Rays that miss the terrain's box
    /// take no step.
    pub fn trace(&self, rays: &[Ray], steps: &mut [u32], mut found: impl FnMut(usize, f64, DVec3)) {
        SCRATCH.with(|scratch| {
            let mut scratch = scratch.borrow_mut();
            let scratch = scratch.get_or_insert_with(Scratch::new);
            self.trace_with(scratch, rays, steps, &mut found);
        });
    }

    fn trace_with(
        &self,
        scratch: &mut Scratch,
        rays: &[Ray],
        steps: &mut [u32],
        found: &mut impl FnMut(usize, f64, DVec3),
    ) {
        let bounds = self.grid.bounds();
        let z_extent =
            bounds.min.z.abs().max(bounds.max.z.abs()) + (bounds.max.z - bounds.min.z) + 1e-30;
        let cells = self.grid.cells_x() + self.grid.cells_y();
        // The packet each sign class is filling, if any; full packets wait in `ready` until
        // INTERLEAVED of them can be traced together.
        let mut filling: [Option<usize>; 4] = [None; 4];
        for (k, world_ray) in rays.iter().enumerate() {
            let ray = self.grid.to_cell_space(world_ray);
            let Some(clip) = self.grid.clip(&ray) else { continue };
            let class = (ray.dir.x < 0.0) as usize + 2 * (ray.dir.y < 0.0) as usize;
            let slot = *filling[class].get_or_insert_with(|| {
                let slot = scratch.free.pop().expect("a free packet for every class");
                scratch.packets[slot].clear(class & 1 == 1, class & 2 == 2, cells);
                slot
            });
            let packet = &mut scratch.packets[slot];
            packet.push(ray, clip, k, z_extent);
            if packet.is_full() {
                filling[class] = None;
                scratch.ready.push(slot);
                if scratch.ready.len() == INTERLEAVED {
                    self.flush(scratch, steps, found);
                }
            }
        }
        scratch.ready.extend(filling.into_iter().flatten());
        while !scratch.ready.is_empty() {
            self.flush(scratch, steps, found);
        }
    }

    /// Traces up to [`INTERLEAVED`] waiting packets together, reports their rays and frees them
    /// (a packet is cleared when it is next taken).
    fn flush(
        &self,
        scratch: &mut Scratch,
        steps: &mut [u32],
        found: &mut impl FnMut(usize, f64, DVec3),
    ) {
        let terrain = Terrain { grid: self.grid, samples: self.samples, mipmap: self.mipmap };
        let take = scratch.ready.len().min(INTERLEAVED);
        let slots: Vec<usize> = scratch.ready.drain(..take).collect();
        let mut walks: Vec<Traversal> = scratch
            .packets
            .iter_mut()
            .zip(scratch.hits.iter_mut())
            .zip(scratch.stacks.iter_mut())
            .enumerate()
            .filter(|(slot, _)| slots.contains(slot))
            .map(|(_, ((packet, hits), stack))| {
                hits[..packet.len].fill(None);
                Traversal::new(&terrain, packet, hits, stack)
            })
            .collect();
        match self.simd.effective() {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: `effective` returns Avx2 only when the processor has AVX2 and FMA.
            Simd::Avx2 => unsafe { trace_avx2(&terrain, &mut walks) },
            _ => traversal::trace::<Portable>(&terrain, &mut walks),
        }
        for walk in walks {
            let p = walk.packet;
            for k in 0..p.len {
                let source = p.source[k];
                steps[source] += p.steps.0[k] as u32;
                if let Some((t, normal)) = walk.hits[k] {
                    found(source, t, normal);
                }
            }
        }
        scratch.free.extend(slots);
    }
}

/// Packets traced together, a node of each in turn: their work is independent, so the
/// processor can overlap it (3-17% faster than one at a time, docs/performance.md).
const INTERLEAVED: usize = 4;

/// A thread's packets and traversal stacks, kept between batches: enough for every sign class
/// to be filling one while [`INTERLEAVED`] wait.
struct Scratch {
    packets: Vec<Box<RayPacket>>,
    hits: Vec<[CellHit; PACKET_RAYS]>,
    stacks: Vec<[Pending; STACK]>,
    /// Packets not in use.
    free: Vec<usize>,
    /// Full packets waiting to be traced.
    ready: Vec<usize>,
}

impl Scratch {
    fn new() -> Self {
        let n = INTERLEAVED + 4;
        Scratch {
            packets: (0..n).map(|_| RayPacket::new()).collect(),
            hits: vec![[None; PACKET_RAYS]; n],
            stacks: vec![[Pending::default(); STACK]; n],
            free: (0..n).rev().collect(),
            ready: Vec::with_capacity(n),
        }
    }
}

thread_local! {
    static SCRATCH: RefCell<Option<Scratch>> = const { RefCell::new(None) };
}

/// The traversal compiled for AVX2 and FMA.
///
/// # Safety
/// The processor must support AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn trace_avx2(terrain: &Terrain, walks: &mut [Traversal]) {
    traversal::trace::<avx2::Avx2>(terrain, walks)
}
