//! The four ray classes of Baboud et al. (5.2.2) and the frame in which each becomes `x+`.
//!
//! A ray belongs to `x+` when `dx >= |dy|`, to `x-` when `-dx >= |dy|`, and to `y+`/`y-`
//! likewise. Each class has a *local frame*: the sample grid mirrored and/or transposed so that
//! the class's rays run along local `+x`. Precomputation and marching are written once, for
//! `x+`, and read the field through a frame. The triangulation (lower diagonal of each square)
//! is the same surface in every frame, since mirroring and transposing keep diagonal sums.

use relief_core::DVec3;

/// One of the four ray classes, named by the axis and sign its rays mainly follow.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RayClass {
    /// `dx >= |dy|`.
    XPos,
    /// `-dx >= |dy|`.
    XNeg,
    /// `dy > |dx|`.
    YPos,
    /// `-dy > |dx|`.
    YNeg,
}

impl RayClass {
    /// The classes in storage order.
    pub const ALL: [RayClass; 4] = [RayClass::XPos, RayClass::XNeg, RayClass::YPos, RayClass::YNeg];

    /// Index of the class in [`RayClass::ALL`].
    pub fn index(self) -> usize {
        self as usize
    }

    /// The class of a direction (only its x and y matter); `None` for a vertical direction.
    pub fn of(dir: DVec3) -> Option<RayClass> {
        let (ax, ay) = (dir.x.abs(), dir.y.abs());
        if ax == 0.0 && ay == 0.0 {
            None
        } else if ax >= ay {
            Some(if dir.x > 0.0 { RayClass::XPos } else { RayClass::XNeg })
        } else {
            Some(if dir.y > 0.0 { RayClass::YPos } else { RayClass::YNeg })
        }
    }

    /// Short name, as in the paper: `x+`, `x-`, `y+`, `y-`.
    pub fn name(self) -> &'static str {
        ["x+", "x-", "y+", "y-"][self.index()]
    }
}

/// A class's view of a `width x height` sample grid: local coordinates in which the class's
/// rays run along `+x`. Local sample `(i, j)` is grid sample [`Frame::to_grid`]`(i, j)`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Frame {
    /// The ray class this frame serves.
    pub class: RayClass,
    /// Samples along the grid's x.
    pub grid_width: usize,
    /// Samples along the grid's y.
    pub grid_height: usize,
    /// Samples along local x and y.
    local_width: usize,
    local_height: usize,
    /// Grid index of local sample (0, 0), and its steps along local x and y.
    base: isize,
    step_i: isize,
    step_j: isize,
}

impl Frame {
    /// The frame of `class` over a grid of `grid_width x grid_height` samples.
    pub fn new(class: RayClass, grid_width: usize, grid_height: usize) -> Self {
        let (w, h) = (grid_width as isize, grid_height as isize);
        let (base, step_i, step_j) = match class {
            RayClass::XPos => (0, 1, w),
            RayClass::XNeg => (w - 1, -1, w),
            RayClass::YPos => (0, w, 1),
            RayClass::YNeg => ((h - 1) * w, -w, 1),
        };
        let (local_width, local_height) = match class {
            RayClass::XPos | RayClass::XNeg => (grid_width, grid_height),
            RayClass::YPos | RayClass::YNeg => (grid_height, grid_width),
        };
        Frame { class, grid_width, grid_height, local_width, local_height, base, step_i, step_j }
    }

    /// Samples along local x.
    #[inline]
    pub fn width(&self) -> usize {
        self.local_width
    }

    /// Samples along local y.
    #[inline]
    pub fn height(&self) -> usize {
        self.local_height
    }

    /// Grid (column, row) of local sample (i, j).
    #[inline]
    pub fn to_grid(&self, i: usize, j: usize) -> (usize, usize) {
        match self.class {
            RayClass::XPos => (i, j),
            RayClass::XNeg => (self.grid_width - 1 - i, j),
            RayClass::YPos => (j, i),
            RayClass::YNeg => (j, self.grid_height - 1 - i),
        }
    }

    /// Row-major grid index of local sample (i, j).
    #[inline]
    pub fn grid_index(&self, i: usize, j: usize) -> usize {
        (self.base + i as isize * self.step_i + j as isize * self.step_j) as usize
    }

    /// Grid cell (between samples) of the local cell whose lower-left local sample is (i, j).
    #[inline]
    pub fn cell_to_grid(&self, i: usize, j: usize) -> (usize, usize) {
        match self.class {
            RayClass::XPos => (i, j),
            RayClass::XNeg => (self.grid_width - 2 - i, j),
            RayClass::YPos => (j, i),
            RayClass::YNeg => (j, self.grid_height - 2 - i),
        }
    }

    /// A point of sample space (samples at integer coordinates) in local coordinates.
    #[inline]
    pub fn point_to_local(&self, p: DVec3) -> DVec3 {
        let (w, h) = ((self.grid_width - 1) as f64, (self.grid_height - 1) as f64);
        match self.class {
            RayClass::XPos => p,
            RayClass::XNeg => DVec3::new(w - p.x, p.y, p.z),
            RayClass::YPos => DVec3::new(p.y, p.x, p.z),
            RayClass::YNeg => DVec3::new(h - p.y, p.x, p.z),
        }
    }

    /// A direction of sample space in local coordinates.
    #[inline]
    pub fn dir_to_local(&self, d: DVec3) -> DVec3 {
        match self.class {
            RayClass::XPos => d,
            RayClass::XNeg => DVec3::new(-d.x, d.y, d.z),
            RayClass::YPos | RayClass::YNeg => {
                let x = if self.class == RayClass::YPos { d.y } else { -d.y };
                DVec3::new(x, d.x, d.z)
            }
        }
    }
}

/// Heights of a sample grid read through a class frame, as `f64`.
#[derive(Debug, Clone, Copy)]
pub struct LocalField<'a> {
    /// The frame.
    pub frame: Frame,
    samples: &'a [f32],
}

impl<'a> LocalField<'a> {
    /// `samples` (row-major, `grid_width x grid_height`) seen through `frame`.
    pub fn new(frame: Frame, samples: &'a [f32]) -> Self {
        LocalField { frame, samples }
    }

    /// Samples along local x.
    #[inline]
    pub fn width(&self) -> usize {
        self.frame.width()
    }

    /// Samples along local y.
    #[inline]
    pub fn height(&self) -> usize {
        self.frame.height()
    }

    /// Height of local sample (i, j).
    #[inline]
    pub fn h(&self, i: usize, j: usize) -> f64 {
        self.samples[self.frame.grid_index(i, j)] as f64
    }

    /// Height of the surface on the x-centerline `i` at local `y` (linear between samples;
    /// `y` is clamped into the grid).
    #[inline]
    pub fn centerline_height(&self, i: usize, y: f64) -> f64 {
        let top = self.height() - 1;
        if top == 0 {
            return self.h(i, 0);
        }
        let y = y.clamp(0.0, top as f64);
        let j = (y as usize).min(top - 1);
        let f = y - j as f64;
        let k = self.frame.grid_index(i, j);
        let (a, b) = (
            self.samples[k] as f64,
            self.samples[(k as isize + self.frame.step_j) as usize] as f64,
        );
        a + (b - a) * f
    }

    /// Height of the triangulated surface at any local point of the grid (clamped into it).
    pub fn surface_height(&self, x: f64, y: f64) -> f64 {
        let (wx, wy) = (self.width() - 1, self.height() - 1);
        if wx == 0 || wy == 0 {
            return if wx == 0 { self.centerline_height(0, y) } else { self.h(0, 0) };
        }
        let (x, y) = (x.clamp(0.0, wx as f64), y.clamp(0.0, wy as f64));
        let (i, j) = ((x as usize).min(wx - 1), (y as usize).min(wy - 1));
        let (u, v) = (x - i as f64, y - j as f64);
        let [a, b, c, d] = self.cell_corners(i, j);
        // The larger of the two planes of the lower-diagonal split.
        if relief_core::splits_along_ad(a, b, c, d) {
            (a + (b - a) * u + (d - b) * v).max(a + (d - c) * u + (c - a) * v)
        } else {
            (a + (b - a) * u + (c - a) * v).max(b + c - d + (d - c) * u + (d - b) * v)
        }
    }

    /// Heights of the corners of local cell (i, j): (i,j), (i+1,j), (i,j+1), (i+1,j+1).
    #[inline]
    pub fn cell_corners(&self, i: usize, j: usize) -> [f64; 4] {
        [self.h(i, j), self.h(i + 1, j), self.h(i, j + 1), self.h(i + 1, j + 1)]
    }

    /// The two triangles of local cell (i, j) (lower diagonal), as vertices (x, y, z).
    #[inline]
    pub fn cell_triangles(&self, i: usize, j: usize) -> [[DVec3; 3]; 2] {
        let [a, b, c, d] = self.cell_corners(i, j);
        let (x, y) = (i as f64, j as f64);
        let pa = DVec3::new(x, y, a);
        let pb = DVec3::new(x + 1.0, y, b);
        let pc = DVec3::new(x, y + 1.0, c);
        let pd = DVec3::new(x + 1.0, y + 1.0, d);
        if relief_core::splits_along_ad(a, b, c, d) {
            [[pa, pb, pd], [pa, pd, pc]]
        } else {
            [[pa, pb, pc], [pb, pd, pc]]
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_map_samples_points_and_cells_consistently() {
        let (w, h) = (5usize, 3usize);
        let samples: Vec<f32> = (0..w * h).map(|k| (k * k % 7) as f32).collect();
        for class in RayClass::ALL {
            let frame = Frame::new(class, w, h);
            let local = LocalField::new(frame, &samples);
            for i in 0..frame.width() {
                for j in 0..frame.height() {
                    let (c, r) = frame.to_grid(i, j);
                    let p = frame.point_to_local(DVec3::new(c as f64, r as f64, 0.0));
                    assert_eq!((p.x, p.y), (i as f64, j as f64), "{class:?}");
                    assert_eq!(frame.grid_index(i, j), c + r * w);
                    assert_eq!(local.h(i, j), samples[c + r * w] as f64);
                }
            }
            // A class's own direction runs along local +x.
            let d = match class {
                RayClass::XPos => DVec3::X,
                RayClass::XNeg => -DVec3::X,
                RayClass::YPos => DVec3::Y,
                RayClass::YNeg => -DVec3::Y,
            };
            assert_eq!(RayClass::of(d), Some(class));
            assert_eq!(frame.dir_to_local(d), DVec3::X);
            // Local cell (0, 0) has local sample (0, 0) among the grid cell's corners.
            let (gc, gr) = frame.cell_to_grid(0, 0);
            let (c0, r0) = frame.to_grid(0, 0);
            assert!(c0.abs_diff(gc) <= 1 && r0.abs_diff(gr) <= 1 && c0 >= gc && r0 >= gr);
        }
    }

    #[test]
    fn surface_height_matches_the_centerlines() {
        let samples = [0.0f32, 3.0, 1.0, 5.0, 2.0, 4.0];
        let local = LocalField::new(Frame::new(RayClass::XPos, 3, 2), &samples);
        for k in 0..=10 {
            let y = k as f64 / 10.0;
            for i in 0..3 {
                let a = local.centerline_height(i, y);
                assert!((a - local.surface_height(i as f64, y)).abs() < 1e-12);
            }
        }
    }
}
