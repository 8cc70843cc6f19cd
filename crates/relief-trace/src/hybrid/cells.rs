//! The hybrid renderer's cells: square blocks of n x n samples with their height bounds and
//! proxy boxes, updated only where an edit touched them (Ammann et al. 2010, section 3).

use crate::TraceError;
use rayon::prelude::*;
use relief_core::{Aabb, DVec3, GridGeometry, HeightField, SampleRegion, Surface};

/// The samples of one cell: columns `col0..=col1` and rows `row0..=row1` (inclusive).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CellSpan {
    /// First column.
    pub col0: usize,
    /// Last column (inclusive).
    pub col1: usize,
    /// First row.
    pub row0: usize,
    /// Last row (inclusive).
    pub row1: usize,
}

impl CellSpan {
    /// Number of samples in the cell.
    pub fn samples(&self) -> usize {
        (self.col1 - self.col0 + 1) * (self.row1 - self.row0 + 1)
    }
}

/// Height bounds of one cell's samples.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CellBounds {
    /// Lowest sample of the cell, holes aside (+inf when every sample is a hole).
    pub min: f32,
    /// Highest sample of the cell, holes aside (-inf when every sample is a hole).
    pub max: f32,
    /// Whether a wall of the solid stands in the cell (it touches the grid's edge or holds a
    /// hole), so that its proxy box reaches down to the field's lowest sample.
    pub walls: bool,
}

impl CellBounds {
    /// Whether the cell has any surface (not every sample is a hole).
    pub fn has_surface(&self) -> bool {
        self.min <= self.max
    }
}

/// A height field divided into square cells of `n x n` samples for hybrid rendering.
///
/// Neighbouring cells share one row or column of samples (the paper's one-sample overlap), so
/// cell (i, j) holds the columns `i (n-1) ..= i (n-1) + n-1` and the rows likewise, the last
/// cells clipped at the grid's edge. Each cell keeps the lowest and highest of its samples;
/// its proxy box ([`HybridCells::proxy_box`]) bounds every part of the solid the exact
/// tracers see over the cell's footprint:
///
/// - footprint: for `triangles` the sample centres the cell spans (the triangles between its
///   samples, every one of which lies in exactly one cell), for `boxes` the texels' edges
///   (neighbouring cells then overlap by one texel);
/// - heights: from the lowest to the highest sample, but from the field's lowest sample where
///   a wall of the solid stands in the cell: the outer walls at the grid's edge, the walls
///   around a hole (a hole's walls lie in the cell that holds the hole, and for `boxes` any
///   two neighbouring texels share a cell).
///
/// The boxes hold the solid's boundary, not its interior: a ray that starts inside the solid
/// (an eye under the terrain) hits where it starts, in no box; a renderer tests the eye with
/// an exact tracer. The solid's bottom face (at the lowest sample, facing down) is seen only
/// from below that level (a renderer knows its views: relief-shade's `bottom_visible`): for
/// such views let every box reach the floor with [`HybridCells::set_floor_everywhere`]. A cell whose samples are all
/// holes has no surface ([`CellBounds::has_surface`]).
#[derive(Debug, Clone, PartialEq)]
pub struct HybridCells {
    surface: Surface,
    n: usize,
    width: usize,
    height: usize,
    cells_x: usize,
    cells_y: usize,
    bounds: Vec<CellBounds>,
    geometry: GridGeometry,
    field_min: f32,
    field_max: f32,
    floor_everywhere: bool,
}

impl HybridCells {
    /// The cells of `n x n` samples of `field` for `surface` (in parallel). Fails when `n` is
    /// below 2.
    pub fn new(field: &HeightField, surface: Surface, n: usize) -> Result<Self, TraceError> {
        if n < 2 {
            return Err(TraceError::Options(format!(
                "a hybrid cell of {n} sample(s) per side: it needs at least 2"
            )));
        }
        let (width, height) = (field.width(), field.height());
        let count = |samples: usize| (samples.saturating_sub(1)).div_ceil(n - 1).max(1);
        let (cells_x, cells_y) = (count(width), count(height));
        let mut cells = HybridCells {
            surface,
            n,
            width,
            height,
            cells_x,
            cells_y,
            bounds: Vec::new(),
            geometry: *field.geometry(),
            field_min: field.min_sample(),
            field_max: field.max_sample(),
            floor_everywhere: false,
        };
        cells.bounds = (0..cells_x * cells_y)
            .into_par_iter()
            .map(|k| cells.measure(field, k % cells_x, k / cells_x))
            .collect();
        Ok(cells)
    }

    /// Recomputes the cells holding a sample of `region` (and the field's range, on which the
    /// boxes with walls depend) after the samples there changed; every other cell is left
    /// alone. Afterwards the cells equal [`HybridCells::new`] over the edited field, bit for
    /// bit, provided `region` holds every changed sample and the field kept its size and
    /// holes. A field of another size is measured from scratch; a new geometry is taken as
    /// it is (the boxes are placed in the world when asked for).
    pub fn update(&mut self, field: &HeightField, region: SampleRegion) {
        if (field.width(), field.height()) != (self.width, self.height) {
            if let Ok(fresh) = HybridCells::new(field, self.surface, self.n) {
                *self = fresh;
            }
            return;
        }
        self.geometry = *field.geometry();
        self.field_min = field.min_sample();
        self.field_max = field.max_sample();
        let region = region.clamped(self.width, self.height);
        if region.is_empty() {
            return;
        }
        // A sample on a shared line belongs to the cells on both sides.
        let stride = self.n - 1;
        let first = |s: usize| s.saturating_sub(1) / stride;
        let last = |s: usize, cells: usize| (s / stride).min(cells - 1);
        let (i0, i1) = (first(region.col0), last(region.col1 - 1, self.cells_x));
        let (j0, j1) = (first(region.row0), last(region.row1 - 1, self.cells_y));
        let (cells_x, columns) = (self.cells_x, i1 - i0 + 1);
        // In parallel, row by row of cells, when there are many.
        let measured: Vec<CellBounds> = if columns * (j1 - j0 + 1) >= 64 {
            (0..columns * (j1 - j0 + 1))
                .into_par_iter()
                .map(|k| self.measure(field, i0 + k % columns, j0 + k / columns))
                .collect()
        } else {
            (0..columns * (j1 - j0 + 1))
                .map(|k| self.measure(field, i0 + k % columns, j0 + k / columns))
                .collect()
        };
        for (k, b) in measured.into_iter().enumerate() {
            self.bounds[i0 + k % columns + (j0 + k / columns) * cells_x] = b;
        }
    }

    /// The bounds of cell (i, j) read from the field.
    fn measure(&self, field: &HeightField, i: usize, j: usize) -> CellBounds {
        let span = self.span(i, j);
        let samples = field.samples();
        let (mut min, mut max, mut hole) = (f32::INFINITY, f32::NEG_INFINITY, false);
        for row in span.row0..=span.row1 {
            let line = row * self.width + span.col0..=row * self.width + span.col1;
            match field.holes() {
                None => {
                    let (lo, hi) = range_of(&samples[line]);
                    min = min.min(lo);
                    max = max.max(hi);
                }
                Some(holes) => {
                    for (&v, &h) in samples[line.clone()].iter().zip(&holes[line]) {
                        hole |= h;
                        if !h {
                            min = min.min(v);
                            max = max.max(v);
                        }
                    }
                }
            }
        }
        let edge = span.col0 == 0
            || span.row0 == 0
            || span.col1 + 1 == self.width
            || span.row1 + 1 == self.height;
        CellBounds { min, max, walls: edge || hole }
    }

    /// Whether every proxy box reaches down to the field's lowest sample (for views from below
    /// it, which see the solid's bottom face), or only those of cells with walls (the default).
    pub fn set_floor_everywhere(&mut self, on: bool) {
        self.floor_everywhere = on;
    }

    /// The surface the boxes are built for.
    pub fn surface(&self) -> Surface {
        self.surface
    }

    /// Samples per cell side, `n`.
    pub fn cell_samples(&self) -> usize {
        self.n
    }

    /// Number of cells along x and y.
    pub fn cells(&self) -> (usize, usize) {
        (self.cells_x, self.cells_y)
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.bounds.len()
    }

    /// Whether there is no cell (never: a field has at least one sample).
    pub fn is_empty(&self) -> bool {
        self.bounds.is_empty()
    }

    /// Index of cell (i, j) in [`HybridCells::bounds`]: `i + j * cells_x`.
    pub fn index(&self, i: usize, j: usize) -> usize {
        i + j * self.cells_x
    }

    /// The field's lowest and highest samples when the cells were last measured.
    pub fn field_range(&self) -> (f32, f32) {
        (self.field_min, self.field_max)
    }

    /// The samples of cell (i, j).
    pub fn span(&self, i: usize, j: usize) -> CellSpan {
        let stride = self.n - 1;
        let (col0, row0) = (i * stride, j * stride);
        CellSpan {
            col0,
            row0,
            col1: (col0 + stride).min(self.width - 1),
            row1: (row0 + stride).min(self.height - 1),
        }
    }

    /// Height bounds of every cell, row-major (index `i + j * cells_x`).
    pub fn bounds(&self) -> &[CellBounds] {
        &self.bounds
    }

    /// The proxy box of cell `index` in grid space (x, y in texel units from the grid's
    /// corner, z in sample units), or `None` when the cell has no surface. See the type's
    /// documentation for what it holds.
    pub fn grid_box(&self, index: usize) -> Option<Aabb> {
        let b = self.bounds[index];
        if !b.has_surface() {
            return None;
        }
        let span = self.span(index % self.cells_x, index / self.cells_x);
        let (lo, hi) = match self.surface {
            Surface::Triangles => (0.5, 0.5),
            Surface::Boxes => (0.0, 1.0),
        };
        let z_min = if b.walls || self.floor_everywhere { self.field_min } else { b.min };
        Some(Aabb::new(
            DVec3::new(span.col0 as f64 + lo, span.row0 as f64 + lo, z_min as f64),
            DVec3::new(span.col1 as f64 + hi, span.row1 as f64 + hi, b.max as f64),
        ))
    }

    /// The proxy box of cell `index` in world space, or `None` when it has no surface.
    pub fn proxy_box(&self, index: usize) -> Option<Aabb> {
        let b = self.grid_box(index)?;
        Some(Aabb::new(self.geometry.point_to_world(b.min), self.geometry.point_to_world(b.max)))
    }

    /// The height of cell `index`'s samples in world units, `(max - min) * z_scale` (0 when
    /// it has no surface): the relief amplitude the heuristic weighs, without the extension
    /// of the box down to the walls' bottom.
    pub fn relief(&self, index: usize) -> f64 {
        let b = self.bounds[index];
        if b.has_surface() {
            (b.max as f64 - b.min as f64) * self.geometry.z_scale
        } else {
            0.0
        }
    }

    /// The field's bounding box in world space (that of the exact tracers' solid).
    pub fn world_bounds(&self) -> Aabb {
        let inset = match self.surface {
            Surface::Boxes => 0.0,
            Surface::Triangles => 0.5,
        };
        let min = DVec3::new(inset, inset, self.field_min as f64);
        let max = DVec3::new(
            self.width as f64 - inset,
            self.height as f64 - inset,
            self.field_max as f64,
        );
        Aabb::new(self.geometry.point_to_world(min), self.geometry.point_to_world(max))
    }
}

/// The lowest and highest of finite values (eight lanes at a time, which compilers turn
/// into vector instructions); (+inf, -inf) for none.
fn range_of(values: &[f32]) -> (f32, f32) {
    let (mut lo, mut hi) = ([f32::INFINITY; 8], [f32::NEG_INFINITY; 8]);
    let mut chunks = values.chunks_exact(8);
    for chunk in &mut chunks {
        for k in 0..8 {
            lo[k] = if chunk[k] < lo[k] { chunk[k] } else { lo[k] };
            hi[k] = if chunk[k] > hi[k] { chunk[k] } else { hi[k] };
        }
    }
    let (mut min, mut max) = (f32::INFINITY, f32::NEG_INFINITY);
    for &v in lo.iter().chain(chunks.remainder()) {
        min = min.min(v);
    }
    for &v in hi.iter().chain(chunks.remainder()) {
        max = max.max(v);
    }
    (min, max)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn field(w: usize, h: usize) -> HeightField {
        let samples = (0..w * h).map(|k| ((k * 37) % 11) as f32).collect();
        HeightField::new(w, h, samples, GridGeometry::unit()).unwrap()
    }

    #[test]
    fn every_box_reaches_the_floor_when_asked() {
        let mut samples = vec![5.0f32; 100];
        samples[0] = 1.0;
        let f = HeightField::new(10, 10, samples, GridGeometry::unit()).unwrap();
        let mut cells = HybridCells::new(&f, Surface::Triangles, 4).unwrap();
        let inner = cells.index(1, 1);
        assert_eq!(cells.grid_box(inner).unwrap().min.z, 5.0);
        cells.set_floor_everywhere(true);
        assert_eq!(cells.grid_box(inner).unwrap().min.z, 1.0);
    }

    #[test]
    fn lane_ranges_equal_a_plain_fold() {
        for n in [0, 1, 7, 8, 9, 17, 64, 70] {
            let values: Vec<f32> = (0..n).map(|k| ((k * 7919) % 101) as f32 - 50.0).collect();
            let min = values.iter().copied().fold(f32::INFINITY, f32::min);
            let max = values.iter().copied().fold(f32::NEG_INFINITY, f32::max);
            assert_eq!(range_of(&values), (min, max), "{n} values");
        }
    }

    #[test]
    fn cells_share_one_line_of_samples_and_clip_at_the_edge() {
        let f = field(10, 5);
        let cells = HybridCells::new(&f, Surface::Triangles, 4).unwrap();
        assert_eq!(cells.cells(), (3, 2));
        assert_eq!(cells.span(0, 0), CellSpan { col0: 0, col1: 3, row0: 0, row1: 3 });
        assert_eq!(cells.span(2, 1), CellSpan { col0: 6, col1: 9, row0: 3, row1: 4 });
        let one = HybridCells::new(&field(1, 1), Surface::Boxes, 64).unwrap();
        assert_eq!((one.cells(), one.span(0, 0).samples()), ((1, 1), 1));
        assert!(HybridCells::new(&f, Surface::Boxes, 1).is_err());
        assert!(HybridCells::new(&f, Surface::Boxes, 0).is_err());
        assert_eq!(HybridCells::new(&field(7, 7), Surface::Boxes, 4).unwrap().cells(), (2, 2));
        assert_eq!(HybridCells::new(&field(8, 7), Surface::Boxes, 4).unwrap().cells(), (3, 2));
    }

    #[test]
    fn boxes_hold_the_cells_samples_and_reach_the_floor_at_walls() {
        // 7 x 7 samples, cells of 4: an inner corner sample high, one low sample far away.
        let mut samples = vec![5.0f32; 49];
        samples[3 + 3 * 7] = 9.0; // shared by all four cells
        samples[6 + 6 * 7] = 1.0; // the field's lowest, in cell (1, 1) only
        let f = HeightField::new(7, 7, samples, GridGeometry::unit()).unwrap();
        let tri = HybridCells::new(&f, Surface::Triangles, 4).unwrap();
        let b = tri.grid_box(0).unwrap();
        assert_eq!((b.min, b.max), (DVec3::new(0.5, 0.5, 1.0), DVec3::new(3.5, 3.5, 9.0)));
        assert_eq!(tri.bounds()[0], CellBounds { min: 5.0, max: 9.0, walls: true });
        assert_eq!(tri.bounds()[3].min, 1.0);
        let boxes = HybridCells::new(&f, Surface::Boxes, 4).unwrap();
        let b = boxes.grid_box(3).unwrap();
        assert_eq!((b.min, b.max), (DVec3::new(3.0, 3.0, 1.0), DVec3::new(7.0, 7.0, 9.0)));
        assert_eq!(boxes.relief(3), 8.0);
    }

    #[test]
    fn inner_cells_stop_at_their_lowest_sample_unless_they_hold_a_hole() {
        let mut samples = vec![4.0f32; 100];
        samples[5 + 5 * 10] = 6.0;
        samples[0] = 0.0;
        let f = HeightField::new(10, 10, samples, GridGeometry::unit()).unwrap();
        let cells = HybridCells::new(&f, Surface::Triangles, 4).unwrap();
        // Cell (1, 1) spans samples 3..=6: inside the grid, no hole.
        let inner = cells.grid_box(cells.index(1, 1)).unwrap();
        assert_eq!((inner.min.z, inner.max.z), (4.0, 6.0));
        let mut holes = vec![false; 100];
        holes[4 + 4 * 10] = true;
        let f = f.with_holes(holes).unwrap();
        let cells = HybridCells::new(&f, Surface::Triangles, 4).unwrap();
        let inner = cells.grid_box(cells.index(1, 1)).unwrap();
        assert_eq!((inner.min.z, inner.max.z), (0.0, 6.0));
        let all = HeightField::new(3, 3, vec![1.0; 9], GridGeometry::unit()).unwrap();
        let mut holes = vec![true; 9];
        holes[0] = false;
        let all = all.with_holes(holes).unwrap();
        let cells = HybridCells::new(&all, Surface::Boxes, 2).unwrap();
        assert!(cells.grid_box(cells.index(1, 1)).is_none());
        assert!(cells.grid_box(0).is_some());
    }
}
