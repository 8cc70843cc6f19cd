//! Max-mipmap quadtree traversal of a height field (Dick et al. 2009, section 3.2).

use crate::cell_grid::CellGrid;
use crate::packet::PacketTracing;
use crate::{Hit, MaxMipmap, Simd, Tracer};
use relief_core::{Aabb, CoreError, HeightField, Ray, SampleRegion, Surface};
use std::sync::Arc;

/// Exact ray casting through a [`MaxMipmap`]: the ray skips every node whose maximum it passes
/// above, descends into nodes it may hit, and climbs again only when it leaves the parent node.
///
/// The traversal runs in a mirrored index space where the ray's x and y directions are
/// non-negative (Dick's mirroring), over a grid padded to a power of two. Node and cell bounds
/// come from integer indices, never from accumulated positions, and the final test in a cell is
/// the same exact test the [`crate::NaiveTracer`] uses, so both return the same hits.
///
/// Batches of rays ([`Tracer::intersect_batch`], [`Tracer::occluded_batch`]) are traced in
/// coherent packets instead: up to 64 rays walk the pyramid together, front to back, with
/// their node tests eight at a time in SIMD registers (see [`Simd`]), and the same exact cell
/// test at the end.
#[derive(Debug, Clone)]
pub struct MipmapTracer {
    field: Arc<HeightField>,
    grid: CellGrid,
    mipmap: MaxMipmap,
    /// Slack of the conservative height tests, relative to the heights' magnitude.
    slack: f64,
    /// The instructions of the packets' node tests.
    simd: Simd,
}

impl MipmapTracer {
    /// Builds the max mipmap of `surface` over `field`.
    pub fn new(field: Arc<HeightField>, surface: Surface) -> Self {
        let grid = CellGrid::new(&field, surface);
        let mipmap = MaxMipmap::build(&grid, field.samples());
        let slack = slack_for(&field);
        MipmapTracer { field, grid, mipmap, slack, simd: Simd::detect() }
    }

    /// The same tracer with the packets' node tests on `simd` (by default the fastest this
    /// processor has); the hits do not depend on it.
    pub fn with_simd(mut self, simd: Simd) -> Self {
        self.simd = simd;
        self
    }

    /// The instructions the packets' node tests run on.
    pub fn simd(&self) -> Simd {
        self.simd.effective()
    }

    fn packets(&self) -> PacketTracing<'_> {
        PacketTracing {
            grid: &self.grid,
            samples: self.field.samples(),
            mipmap: &self.mipmap,
            simd: self.simd,
        }
    }

    /// The pyramid this tracer walks.
    pub fn mipmap(&self) -> &MaxMipmap {
        &self.mipmap
    }

    /// The height field this tracer intersects.
    pub fn field(&self) -> &Arc<HeightField> {
        &self.field
    }

    /// Edits the tracer's height field in place and brings the pyramid up to date.
    ///
    /// `edit` changes the field's samples (with [`HeightField::edit_region`] or
    /// [`HeightField::replace_samples`]) and returns the region holding every sample it
    /// changed. The field is shared copy-on-write ([`Arc::make_mut`]): if another owner holds
    /// it, the tracer edits its own copy (see [`MipmapTracer::field`]). Only the pyramid's
    /// nodes above the region are recomputed ([`MaxMipmap::update`]). When the field's value
    /// range changed (the solid's walls now reach another bottom, its bounds another top), the
    /// grid's bounds and the tests' slack are recomputed too, which costs nothing more without
    /// holes (the pyramid does not depend on them: cells over holes hold minus infinity). When
    /// the closure replaced the field by one of another size, geometry or hole mask, or when
    /// it failed, the tracer is rebuilt from its field. Either way it then equals
    /// [`MipmapTracer::new`] over the edited field, bit for bit.
    ///
    /// Returns the closure's result: the edited region, or its error.
    ///
    /// ```
    /// use std::sync::Arc;
    /// use relief_core::{DVec3, GridGeometry, HeightField, Ray, SampleRegion, Surface};
    /// use relief_trace::{MipmapTracer, Tracer};
    /// let field = HeightField::new(4, 4, vec![1.0; 16], GridGeometry::unit()).unwrap();
    /// let mut tracer = MipmapTracer::new(Arc::new(field), Surface::Boxes);
    /// tracer.edit(|f| f.edit_region(SampleRegion::new(1, 1, 2, 2), |_, _, v| v + 2.0)).unwrap();
    /// let hit = tracer.intersect(&Ray::new(DVec3::new(1.5, 1.5, 10.0), -DVec3::Z)).unwrap();
    /// assert_eq!(hit.t, 7.0);
    /// ```
    pub fn edit(
        &mut self,
        edit: impl FnOnce(&mut HeightField) -> Result<SampleRegion, CoreError>,
    ) -> Result<SampleRegion, CoreError> {
        let field = Arc::make_mut(&mut self.field);
        let before = FieldShape::of(field);
        let result = edit(field);
        let field = &*self.field;
        let after = FieldShape::of(field);
        match &result {
            Ok(region) if after.layout == before.layout => {
                if after.range != before.range {
                    self.grid = CellGrid::new(field, self.grid.surface());
                    self.slack = slack_for(field);
                }
                self.mipmap.update(&self.grid, field.samples(), *region)
            }
            _ => self.rebuild(),
        }
        result
    }

    /// Rebuilds the grid, the pyramid and the slack from the field.
    fn rebuild(&mut self) {
        let simd = self.simd;
        *self = MipmapTracer::new(self.field.clone(), self.grid.surface()).with_simd(simd);
    }
}

/// What an edit of the samples may change and what not: the layout (size, geometry and hole
/// mask, by address) stays, the value range (as bits) may move. While the layout stays, the
/// pyramid changes only above the edit.
#[derive(Debug, Clone, Copy, PartialEq)]
struct FieldShape {
    layout: (usize, usize, relief_core::GridGeometry, Option<*const bool>),
    range: (u32, u32),
}

impl FieldShape {
    fn of(field: &HeightField) -> Self {
        FieldShape {
            layout: (
                field.width(),
                field.height(),
                *field.geometry(),
                field.holes().map(|h| h.as_ptr()),
            ),
            range: (field.min_sample().to_bits(), field.max_sample().to_bits()),
        }
    }
}

/// Slack of the conservative height tests for `field`, relative to its heights' magnitude.
fn slack_for(field: &HeightField) -> f64 {
    let magnitude = field.min_sample().abs().max(field.max_sample().abs()) as f64;
    1e-9 * (1.0 + magnitude)
}

/// One horizontal axis of a ray in the pyramid's mirrored index space, where the ray runs
/// towards growing coordinates (Dick's mirroring): the grid is padded to a power of two and
/// flipped along the axes the ray runs down, so every step is "+1" and every crossing time is
/// one subtraction and one multiplication, without branches.
#[derive(Clone, Copy)]
struct MirroredAxis {
    /// The ray's origin along the axis, in mirrored coordinates.
    origin: f64,
    /// `1 / |direction|` (infinite when the ray does not move along the axis).
    inv_dir: f64,
    /// Whether the ray moves along the axis at all.
    moves: bool,
    /// All ones when flipped, else zero: mirrored index `m` of a level of `n` nodes is original
    /// index `m ^ (flip & (n - 1))`.
    flip: usize,
    /// The padded grid size, a power of two.
    padded: usize,
}

impl MirroredAxis {
    fn new(origin: f64, dir: f64, inv_dir: f64, padded: usize) -> Self {
        let flipped = dir < 0.0;
        MirroredAxis {
            origin: if flipped { padded as f64 - origin } else { origin },
            inv_dir: inv_dir.abs(),
            moves: dir != 0.0,
            flip: if flipped { usize::MAX } else { 0 },
            padded,
        }
    }

    /// The original index of mirrored node `m` of `level` (the map is its own inverse). An
    /// index past the padded grid maps past it too, where lookups refuse it.
    #[inline]
    fn original(self, m: usize, level: usize) -> usize {
        m ^ (self.flip & ((self.padded >> level) - 1))
    }

    /// When the ray reaches the mirrored boundary `m << level`.
    #[inline]
    fn time_to(self, m: usize, level: usize) -> f64 {
        if self.moves {
            ((m << level) as f64 - self.origin) * self.inv_dir
        } else {
            f64::INFINITY
        }
    }

    /// The child at `level` of mirrored node `m` (one level up) that holds the ray's point at
    /// `t`: the upper one once the ray has reached the boundary between the two.
    #[inline]
    fn child(self, m: usize, level: usize, t: f64) -> usize {
        let upper = 2 * m + 1;
        let reached = if self.moves {
            t >= self.time_to(upper, level)
        } else {
            self.origin >= (upper << level) as f64
        };
        upper - !reached as usize
    }
}

impl Tracer for MipmapTracer {
    fn name(&self) -> &'static str {
        "mipmap"
    }

    fn max_mipmap(&self) -> Option<&MaxMipmap> {
        Some(&self.mipmap)
    }

    fn surface(&self) -> Surface {
        self.grid.surface()
    }

    fn bounds(&self) -> Aabb {
        self.grid.world_bounds()
    }

    fn intersect_counted(&self, world_ray: &Ray, steps: &mut u32) -> Option<Hit> {
        let mut count = 0;
        let hit = self.traverse(world_ray, &mut count);
        *steps += count;
        hit
    }

    /// Traces the rays in packets (see the type's documentation); `steps` counts node tests.
    fn intersect_batch(&self, rays: &[Ray], hits: &mut [Option<Hit>], steps: &mut [u32]) {
        assert!(rays.len() == hits.len() && rays.len() == steps.len(), "batch slices differ");
        hits.fill(None);
        self.packets().trace(rays, steps, |k, t, normal| {
            hits[k] = Some(self.grid.world_hit(&rays[k], t, normal));
        });
    }

    /// Traces the rays in packets; `steps` counts node tests.
    fn occluded_batch(&self, rays: &[Ray], occluded: &mut [bool], steps: &mut [u32]) {
        assert!(rays.len() == occluded.len() && rays.len() == steps.len(), "batch slices differ");
        occluded.fill(false);
        self.packets().trace(rays, steps, |k, _, _| occluded[k] = true);
    }
}

/// The smaller of two numbers that are never NaN (cheaper than `f64::min`).
#[inline(always)]
fn min(a: f64, b: f64) -> f64 {
    if a < b {
        a
    } else {
        b
    }
}

impl MipmapTracer {
    /// The traversal, counting steps into a local counter.
    #[inline(always)]
    fn traverse(&self, world_ray: &Ray, steps: &mut u32) -> Option<Hit> {
        let ray = self.grid.to_cell_space(world_ray);
        let clip = self.grid.clip(&ray)?;
        let samples = self.field.samples();
        let top = self.mipmap.top_level();
        let padded = 1usize << top;
        let mx = MirroredAxis::new(ray.origin.x, ray.dir.x, ray.inv_dir.x, padded);
        let my = MirroredAxis::new(ray.origin.y, ray.dir.y, ray.inv_dir.y, padded);
        let (cx, cy) = self.grid.cell_at(&ray, clip.t_enter);
        let (mcx, mcy) = (mx.original(cx, 0), my.original(cy, 0));
        let mut t = clip.t_enter;
        // Skip the descent the loop would make through every node whose maximum the start point
        // is already below (a shadow ray leaving the surface goes all the way down): one lookup
        // a level instead of a full step. The loop then continues exactly as it would have.
        let z_start = ray.origin.z + t * ray.dir.z;
        let mut level = top;
        while level > 0 {
            let (nx, ny) = (mcx >> level, mcy >> level);
            match self.mipmap.get(level, mx.original(nx, level), my.original(ny, level)) {
                Some(node_max) if z_start <= node_max as f64 => level -= 1,
                _ => break,
            }
        }
        let mut nx = mcx >> level;
        let mut ny = mcy >> level;
        loop {
            *steps += 1;
            let tx = mx.time_to(nx + 1, level);
            let ty = my.time_to(ny + 1, level);
            let t_leave = min(min(tx, ty), clip.t_exit);
            let (ox, oy) = (mx.original(nx, level), my.original(ny, level));
            if level == 0 {
                if ox >= self.grid.cells_x() || oy >= self.grid.cells_y() {
                    return None;
                }
                // Cheap rejection first: the ray passes above the cell's highest point. (Before
                // `t` it cannot hit: the parent's test or its advance to the parent's maximum
                // ruled that out.) Otherwise the exact test, shared with the naive tracer.
                let cell_max = self.grid.cell_max(samples, ox, oy) as f64;
                let z_low = min(ray.origin.z + t * ray.dir.z, ray.origin.z + t_leave * ray.dir.z);
                if z_low <= cell_max + self.slack {
                    let seg = self.grid.segment(&ray, &clip, ox, oy);
                    if let Some((t_hit, n)) = self.grid.intersect_cell(samples, &ray, ox, oy, &seg)
                    {
                        return Some(self.grid.world_hit(world_ray, t_hit, n));
                    }
                }
            } else {
                let node_max = self.mipmap.get(level, ox, oy)? as f64;
                let z_in = ray.origin.z + t * ray.dir.z;
                let z_out = ray.origin.z + t_leave * ray.dir.z;
                // A hair of slack keeps the coarse test conservative; level 0 decides exactly.
                if min(z_in, z_out) <= node_max + self.slack {
                    if ray.dir.z < 0.0 && z_in > node_max {
                        // Not `clamp`: rounding may put `t_leave` an ulp before `t`.
                        let reach = (node_max - ray.origin.z) * ray.inv_dir.z;
                        t = reach.min(t_leave).max(t);
                    }
                    level -= 1;
                    nx = mx.child(nx, level, t);
                    ny = my.child(ny, level, t);
                    // At the grid's edge, rounding between the clip (original coordinates) and
                    // mirrored boundaries may pick the child outside the grid: take its sibling.
                    let (nodes_x, nodes_y) = self.mipmap.nodes(level);
                    nx ^= (mx.original(nx, level) >= nodes_x) as usize;
                    ny ^= (my.original(ny, level) >= nodes_y) as usize;
                    continue;
                }
            }
            if t_leave >= clip.t_exit {
                return None;
            }
            t = t_leave;
            let (mut cross_x, mut cross_y) = (tx == t_leave, ty == t_leave);
            nx += cross_x as usize;
            ny += cross_y as usize;
            // Climb while the step left the parent node as well.
            while level < top {
                let (leave_x, leave_y) =
                    (cross_x && nx.is_multiple_of(2), cross_y && ny.is_multiple_of(2));
                if !(leave_x || leave_y) {
                    break;
                }
                (cross_x, cross_y) = (leave_x, leave_y);
                level += 1;
                nx >>= 1;
                ny >>= 1;
            }
        }
    }
}
