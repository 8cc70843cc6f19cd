//! A packet of up to [`PACKET_RAYS`] rays laid out in lanes for the SIMD node tests.

use crate::cell_grid::CellRay;
use relief_core::Clip;

/// The children of a node, or the cells of a level-1 node, in the order rays running towards
/// growing x and y meet them (a ray crosses at most one of the middle two); mirrored along the
/// axes the packet runs down.
pub(crate) const ORDER: [(usize, usize); 4] = [(0, 0), (1, 0), (0, 1), (1, 1)];

/// Rays traced together through the pyramid.
pub(crate) const PACKET_RAYS: usize = 64;
/// Rays per SIMD group (one AVX2 register of `f32`).
pub(crate) const LANES: usize = 8;

/// Relative precision of the `f32` node tests: every margin is a multiple of this, far above
/// the rounding of the few operations a test takes (about 2^-22 of the terrain's extent).
const MARGIN: f64 = 1.0 / (1u64 << 20) as f64;

/// Relative margin for the `f64` rounding of the exact tests (about 2^-52 of the coordinates).
const EXACT_MARGIN: f64 = 1.0 / (1u64 << 40) as f64;

/// One `f32` per ray of a packet, aligned for whole-register loads.
#[derive(Debug, Clone, Copy)]
#[repr(C, align(32))]
pub(crate) struct Lanes(pub [f32; PACKET_RAYS]);

/// One step counter per ray of a packet, aligned for whole-register loads.
#[derive(Debug, Clone, Copy)]
#[repr(C, align(32))]
pub(crate) struct StepLanes(pub [i32; PACKET_RAYS]);

/// The four children of a node (or the four cells of a level-1 node) as a packet's rays meet
/// them: `x[0]` is the x boundary the rays enter the node through, `x[1]` its middle, `x[2]`
/// the boundary they leave through, and likewise along y. Child `c` of
/// [`ORDER`], `(i, j)`, spans `x[i]..x[i + 1]` and `y[j]..y[j + 1]`, below
/// `top[c]` (minus infinity for a child outside the grid or over a hole).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Quad {
    /// x boundaries in the order the rays cross them.
    pub x: [f32; 3],
    /// y boundaries in the order the rays cross them.
    pub y: [f32; 3],
    /// The children's highest points.
    pub top: [f32; 4],
}

/// A cell's footprint as a packet's rays meet it: entered through `near_x`, left through
/// `far_x`, and likewise along y.
#[derive(Debug, Clone, Copy)]
pub(crate) struct CellBox {
    /// The x boundary the rays enter through.
    pub near_x: f32,
    /// The x boundary the rays leave through.
    pub far_x: f32,
    /// The y boundary the rays enter through.
    pub near_y: f32,
    /// The y boundary the rays leave through.
    pub far_y: f32,
}

/// A plane `z = p0 + pu * u + pv * v` over a cell, in the cell's local coordinates, in `f32`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Plane {
    /// Height at the cell's lower corner.
    pub p0: f32,
    /// Slope along x.
    pub pu: f32,
    /// Slope along y.
    pub pv: f32,
}

/// Rays whose x and y directions all have the same signs, in `f32` lanes for conservative
/// node tests, with their exact `f64` form for the cell tests.
///
/// In the lanes every ray starts where it enters the terrain's box (`t = 0` there) and ends at
/// `t_end`, where it leaves it. Its crossing times of a node's x boundaries are
/// `near_x * inv_x + enter_x` and `far_x * inv_x + leave_x`: the origins behind `enter_x` and
/// `leave_x` are moved by a margin so that the interval between them holds the true one
/// despite rounding, and `z_low` is the origin's height lowered by a margin, so every test
/// errs on the side of "may hit". The exact test then decides.
pub(crate) struct RayPacket {
    /// `1 / dir.x` (finite: a zero direction is replaced by a tiny one of the packet's sign).
    pub inv_x: Lanes,
    /// `-(origin.x + margin) * inv_x`, for the near x boundary.
    pub enter_x: Lanes,
    /// `-(origin.x - margin) * inv_x`, for the far x boundary.
    pub leave_x: Lanes,
    /// `1 / dir.y`.
    pub inv_y: Lanes,
    /// As `enter_x`, along y.
    pub enter_y: Lanes,
    /// As `leave_x`, along y.
    pub leave_y: Lanes,
    /// Origin x (where the ray enters the box).
    pub ox: Lanes,
    /// Origin y.
    pub oy: Lanes,
    /// Direction x.
    pub dx: Lanes,
    /// Direction y.
    pub dy: Lanes,
    /// Direction z.
    pub dz: Lanes,
    /// Origin z less the height margin.
    pub z_low: Lanes,
    /// Where the ray leaves the box (rounded up). Lanes past `len` hold stale values: every
    /// test masks them out.
    pub t_end: Lanes,
    /// Node tests per ray.
    pub steps: StepLanes,
    /// Margin of the x and y boundaries, in cells.
    pub margin_xy: f32,
    /// The rays in cell space, for the exact tests.
    pub rays: [CellRay; PACKET_RAYS],
    /// Each ray's part inside the terrain's box.
    pub clips: [Clip; PACKET_RAYS],
    /// Which ray of the caller's batch each one is.
    pub source: [usize; PACKET_RAYS],
    /// Rays in the packet.
    pub len: usize,
    /// Whether the rays run towards decreasing x.
    pub negative_x: bool,
    /// Whether the rays run towards decreasing y.
    pub negative_y: bool,
}

/// The smallest direction component the lanes use: small enough that the ray moves less than
/// a rounding error over any terrain, large enough that its reciprocal is finite.
const TINY: f32 = 1e-20;

impl RayPacket {
    /// An empty packet; [`RayPacket::clear`] readies it for a sign class and a grid.
    pub fn new() -> Box<Self> {
        let zero = Lanes([0.0; PACKET_RAYS]);
        let ray = CellRay {
            ray: relief_core::Ray::new(Default::default(), Default::default()),
            inv_dir: Default::default(),
        };
        let clip = Clip { t_enter: 0.0, t_exit: 0.0, face: relief_core::BoxFace::Inside };
        Box::new(RayPacket {
            inv_x: zero,
            enter_x: zero,
            leave_x: zero,
            inv_y: zero,
            enter_y: zero,
            leave_y: zero,
            ox: zero,
            oy: zero,
            dx: zero,
            dy: zero,
            dz: zero,
            z_low: zero,
            t_end: zero,
            steps: StepLanes([0; PACKET_RAYS]),
            margin_xy: 0.0,
            rays: [ray; PACKET_RAYS],
            clips: [clip; PACKET_RAYS],
            source: [0; PACKET_RAYS],
            len: 0,
            negative_x: false,
            negative_y: false,
        })
    }

    /// Empties the packet for rays of the given signs over a grid of `cells` cells along x
    /// plus y.
    pub fn clear(&mut self, negative_x: bool, negative_y: bool, cells: usize) {
        self.steps.0[..self.len].fill(0);
        self.len = 0;
        self.negative_x = negative_x;
        self.negative_y = negative_y;
        self.margin_xy = (MARGIN * (cells as f64 + 2.0)) as f32;
    }

    /// Whether the packet holds [`PACKET_RAYS`] rays.
    pub fn is_full(&self) -> bool {
        self.len == PACKET_RAYS
    }

    /// Adds a ray whose direction signs are the packet's, clipped to the box as `clip`;
    /// `z_extent` is the largest absolute height in the box plus its height range.
    ///
    /// The height margin covers the `f32` rounding of heights within the box and, far below
    /// that, the `f64` rounding of the exact tests' heights along the ray from its origin.
    pub fn push(&mut self, ray: CellRay, clip: Clip, source: usize, z_extent: f64) {
        let k = self.len;
        debug_assert!(k < PACKET_RAYS);
        debug_assert_eq!((ray.dir.x < 0.0, ray.dir.y < 0.0), (self.negative_x, self.negative_y));
        let origin = ray.origin + ray.dir * clip.t_enter;
        let direction = |d: f64, negative: bool| {
            let d = d as f32;
            if d.abs() >= TINY {
                d
            } else if negative {
                -TINY
            } else {
                TINY
            }
        };
        let (dx, dy) =
            (direction(ray.dir.x, self.negative_x), direction(ray.dir.y, self.negative_y));
        let margin = self.margin_xy as f64;
        let (inv_x, inv_y) = (1.0 / dx, 1.0 / dy);
        // Moving the origin forwards by the margin moves the near boundary back, and the far
        // boundary forwards when moved backwards: the interval only grows.
        let (sx, sy) = (dx.signum() as f64, dy.signum() as f64);
        self.inv_x.0[k] = inv_x;
        self.enter_x.0[k] = (-(origin.x + sx * margin) * inv_x as f64) as f32;
        self.leave_x.0[k] = (-(origin.x - sx * margin) * inv_x as f64) as f32;
        self.inv_y.0[k] = inv_y;
        self.enter_y.0[k] = (-(origin.y + sy * margin) * inv_y as f64) as f32;
        self.leave_y.0[k] = (-(origin.y - sy * margin) * inv_y as f64) as f32;
        self.ox.0[k] = origin.x as f32;
        self.oy.0[k] = origin.y as f32;
        self.dx.0[k] = dx;
        self.dy.0[k] = dy;
        self.dz.0[k] = ray.dir.z as f32;
        let exact_rounding = EXACT_MARGIN * (ray.origin.z.abs() + (clip.t_enter * ray.dir.z).abs());
        self.z_low.0[k] = (origin.z - MARGIN * z_extent - exact_rounding) as f32;
        self.t_end.0[k] = ((clip.t_exit - clip.t_enter) * (1.0 + MARGIN)) as f32;
        self.rays[k] = ray;
        self.clips[k] = clip;
        self.source[k] = source;
        self.len += 1;
    }

    /// The bit mask of the packet's rays.
    pub fn all(&self) -> u64 {
        if self.len == PACKET_RAYS {
            u64::MAX
        } else {
            (1u64 << self.len) - 1
        }
    }

    /// The slack of a plane test over a cell whose corner heights sum in magnitude to
    /// `corner_magnitude`: the plane's slopes times the boundary margin, plus the rounding of
    /// its heights.
    pub fn plane_slack(&self, plane: &Plane, corner_magnitude: f32) -> f32 {
        (plane.pu.abs() + plane.pv.abs()) * self.margin_xy
            + (4.0 * MARGIN) as f32 * corner_magnitude
    }
}
