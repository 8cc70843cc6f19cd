//! The per-cell choice of the hybrid renderer (Ammann et al. 2010, section 4.2): frustum
//! culling, mesh rasterization where a cell's triangles cover many pixels, else ray casting
//! at a level of precision from the cell's distance, relief and viewing angle.

use super::projection::{project_box, BoxProjection};
use crate::ShadeError;
use rayon::prelude::*;
use relief_core::{Aabb, Camera};
use relief_trace::hybrid::{lop_steps, HybridCells, LopSteps};

/// Fewest and most levels of precision [`HybridParams`] accept.
pub const LEVEL_COUNTS: std::ops::RangeInclusive<usize> = 2..=10;

/// The parameters of the hybrid renderer's heuristic.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HybridParams {
    /// Samples per cell side, n (at least 2; default 64).
    pub cell: usize,
    /// Mesh threshold T: a cell is rasterized when its box's screen area per sample, in
    /// pixels², exceeds it (positive; default 70).
    pub threshold: f64,
    /// Distance factor k: `d_max = k * d_BB` (positive; default 1.3).
    pub k: f64,
    /// Number of levels of precision of the ray casting (2..=10; default 4, see
    /// [`relief_trace::hybrid::lop_steps`]).
    pub levels: usize,
}

impl Default for HybridParams {
    /// The paper's settings of Figure 1 (T = 70, k = 1.3, four levels) with cells of 64².
    fn default() -> Self {
        HybridParams { cell: 64, threshold: 70.0, k: 1.3, levels: 4 }
    }
}

impl HybridParams {
    /// Checks every parameter, naming the first one out of range.
    pub fn validate(&self) -> Result<(), ShadeError> {
        let bad = |msg: String| Err(ShadeError::parameter("hybrid parameters", msg));
        if self.cell < 2 {
            return bad(format!(
                "hybrid cell of {} sample(s) per side: it needs at least 2",
                self.cell
            ));
        }
        if !(self.threshold.is_finite() && self.threshold > 0.0) {
            return bad(format!(
                "hybrid threshold T = {} must be positive and finite",
                self.threshold
            ));
        }
        if !(self.k.is_finite() && self.k > 0.0) {
            return bad(format!(
                "hybrid distance factor k = {} must be positive and finite",
                self.k
            ));
        }
        if self.levels == 0 {
            return bad("hybrid rendering needs at least one level of precision (got 0)".into());
        }
        if !LEVEL_COUNTS.contains(&self.levels) {
            return bad(format!(
                "{} levels of precision: between {} and {} are supported",
                self.levels,
                LEVEL_COUNTS.start(),
                LEVEL_COUNTS.end()
            ));
        }
        Ok(())
    }
}

/// What the heuristic chose for one cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CellChoice {
    /// Wholly outside the view frustum (or without any surface): not drawn.
    Culled,
    /// Rasterized as a mesh at full resolution.
    Mesh,
    /// Ray cast in its proxy box at a level of precision (0 the most precise).
    RayCast {
        /// Index into [`HybridHeuristic::steps`].
        level: u8,
    },
}

/// The heuristic of section 4.2 with validated parameters and its levels' steps.
#[derive(Debug, Clone, PartialEq)]
pub struct HybridHeuristic {
    params: HybridParams,
    steps: Vec<LopSteps>,
}

impl HybridHeuristic {
    /// The heuristic for `params`, checked ([`HybridParams::validate`]).
    pub fn new(params: HybridParams) -> Result<Self, ShadeError> {
        params.validate()?;
        Ok(HybridHeuristic { params, steps: lop_steps(params.levels) })
    }

    /// The parameters.
    pub fn params(&self) -> &HybridParams {
        &self.params
    }

    /// The steps of every level of precision, most precise (level 0) first.
    pub fn steps(&self) -> &[LopSteps] {
        &self.steps
    }

    /// The choice for every cell, in the cells' order (in parallel; the same whatever the
    /// number of threads).
    pub fn choose(&self, cells: &HybridCells, camera: &Camera) -> Vec<CellChoice> {
        let scene = Scene::of(cells);
        (0..cells.len()).into_par_iter().map(|k| self.choose_in(cells, camera, &scene, k)).collect()
    }

    /// The choice for cell `index`:
    ///
    /// 1. `Culled` when the cell has no surface or its proxy box is wholly outside the view
    ///    frustum ([`project_box`]);
    /// 2. `Mesh` when A / S > T, with A the area in pixels² of the bounding rectangle of the
    ///    box's 8 projected corners (infinite for a box crossing the eye's plane) and S the
    ///    number of samples in the cell (n² but for the clipped cells at the grid's edge);
    /// 3. else `RayCast` at the level of L = min(d_b, d_max) / d_max - h cos θ: d_b the
    ///    distance from the eye to the box's centre, d_max = k d_BB with d_BB the diagonal of
    ///    the terrain's bounding box, h the relief of the cell ([`HybridCells::relief`]) over
    ///    the terrain's height range (0 for a flat terrain), θ the angle between the view ray
    ///    to the box's centre and the vertical (|cos θ|, the vertical being a line). With m
    ///    levels, L <= 0 is level 0 and L in [i/m, (i+1)/m) level i, up to m - 1.
    pub fn choose_cell(&self, cells: &HybridCells, camera: &Camera, index: usize) -> CellChoice {
        self.choose_in(cells, camera, &Scene::of(cells), index)
    }

    /// The precision value L of cell `index` (see [`HybridHeuristic::choose_cell`]); `None`
    /// for a cell without surface.
    pub fn precision_value(
        &self,
        cells: &HybridCells,
        camera: &Camera,
        index: usize,
    ) -> Option<f64> {
        let b = cells.proxy_box(index)?;
        Some(self.l_value(cells, camera, &Scene::of(cells), index, &b))
    }

    /// The level of a precision value L.
    pub fn level_of(&self, l: f64) -> u8 {
        let m = self.steps.len();
        if l.is_nan() || l <= 0.0 {
            return 0;
        }
        ((l * m as f64).floor() as usize).min(m - 1) as u8
    }

    fn choose_in(
        &self,
        cells: &HybridCells,
        camera: &Camera,
        scene: &Scene,
        index: usize,
    ) -> CellChoice {
        let Some(b) = cells.proxy_box(index) else { return CellChoice::Culled };
        let projection = project_box(camera, &b);
        if projection == BoxProjection::Outside {
            return CellChoice::Culled;
        }
        let cells_x = cells.cells().0;
        let span = cells.span(index % cells_x, index / cells_x);
        if projection.area() / span.samples() as f64 > self.params.threshold {
            return CellChoice::Mesh;
        }
        CellChoice::RayCast { level: self.level_of(self.l_value(cells, camera, scene, index, &b)) }
    }

    fn l_value(
        &self,
        cells: &HybridCells,
        camera: &Camera,
        scene: &Scene,
        index: usize,
        b: &Aabb,
    ) -> f64 {
        let to_box = b.center() - camera.eye();
        let d_b = to_box.length();
        let d_max = self.params.k * scene.diagonal;
        let cos_theta = if d_b > 0.0 { to_box.z.abs() / d_b } else { 1.0 };
        let h =
            if scene.height_range > 0.0 { cells.relief(index) / scene.height_range } else { 0.0 };
        d_b.min(d_max) / d_max - h * cos_theta
    }
}

/// What the heuristic needs of the whole terrain.
struct Scene {
    /// d_BB: the diagonal of the terrain's bounding box.
    diagonal: f64,
    /// The terrain's height range in world units.
    height_range: f64,
}

impl Scene {
    fn of(cells: &HybridCells) -> Self {
        let bounds = cells.world_bounds();
        Scene { diagonal: bounds.diagonal(), height_range: bounds.max.z - bounds.min.z }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief_core::{DVec3, GridGeometry, HeightField, Surface};

    /// 9 x 9 samples in cells of 5 (2 x 2 cells), all 0 but sample (6, 6) at 2: cell (1, 1)
    /// has the relief, [4.5, 8.5]² x [0, 2] for triangles; the others are flat at 0.
    fn scene() -> HybridCells {
        let mut samples = vec![0.0f32; 81];
        samples[6 + 6 * 9] = 2.0;
        let field = HeightField::new(9, 9, samples, GridGeometry::unit()).unwrap();
        HybridCells::new(&field, Surface::Triangles, 5).unwrap()
    }

    fn heuristic(threshold: f64, k: f64) -> HybridHeuristic {
        HybridHeuristic::new(HybridParams { cell: 5, threshold, k, levels: 4 }).unwrap()
    }

    /// Straight down from 100 above (2.5, 2.5), 90 degrees, 100 x 100 pixels: right is x, up
    /// is y, and a point at depth z projects to pixel (50 (1 + x/z), 50 (1 - y/z)).
    fn top_down() -> Camera {
        let eye = DVec3::new(2.5, 2.5, 100.0);
        Camera::look_at(eye, DVec3::new(2.5, 2.5, 0.0), DVec3::Y, 90.0, 100, 100).unwrap()
    }

    #[test]
    fn choices_equal_hand_computed_cases() {
        let (cells, camera) = (scene(), top_down());
        // d_BB = |(8, 8, 2)| = sqrt(132). Cell (0, 0): d_b = 100, h = 0.
        let d_bb = 132f64.sqrt();
        // k = 1.3: d_max < d_b, L = 1: the least precise level.
        let h = heuristic(70.0, 1.3);
        assert_eq!(h.choose_cell(&cells, &camera, 0), CellChoice::RayCast { level: 3 });
        // k = 20: L = 100 / (20 d_BB) = 0.435, level floor(4 L) = 1.
        let h = heuristic(70.0, 20.0);
        let l = h.precision_value(&cells, &camera, 0).unwrap();
        assert!((l - 100.0 / (20.0 * d_bb)).abs() < 1e-12);
        assert_eq!(h.choose_cell(&cells, &camera, 0), CellChoice::RayCast { level: 1 });
        // Cell (1, 1): centre (6.5, 6.5, 1), d_b = sqrt(9833), cos θ = 99 / d_b, h = 1:
        // L = 0.4316 - 0.9984 < 0, the most precise level.
        let d_b = 9833f64.sqrt();
        let l = h.precision_value(&cells, &camera, 3).unwrap();
        assert!((l - (d_b / (20.0 * d_bb) - 99.0 / d_b)).abs() < 1e-12);
        assert_eq!(h.choose_cell(&cells, &camera, 3), CellChoice::RayCast { level: 0 });
        // Mesh by area: A / S is 4 / 25 = 0.16 for cell (0, 0) and 0.170 for cell (1, 1).
        let h = heuristic(0.165, 20.0);
        assert_eq!(h.choose_cell(&cells, &camera, 0), CellChoice::RayCast { level: 1 });
        assert_eq!(h.choose_cell(&cells, &camera, 3), CellChoice::Mesh);
        let all = heuristic(0.1, 20.0).choose(&cells, &camera);
        assert_eq!(all, vec![CellChoice::Mesh; 4]);
    }

    #[test]
    fn boxes_behind_or_beside_the_view_are_culled_and_boxes_around_the_eye_meshed() {
        let cells = scene();
        let h = heuristic(70.0, 1.3);
        // The eye inside cell (1, 1)'s box, looking towards (8, 8, 0): cell (0, 0) is behind.
        let inside = Camera::look_at(
            DVec3::new(6.5, 6.5, 1.0),
            DVec3::new(8.0, 8.0, 0.0),
            DVec3::Z,
            60.0,
            64,
            64,
        )
        .unwrap();
        assert_eq!(project_box(&inside, &cells.proxy_box(3).unwrap()), BoxProjection::Unbounded);
        assert_eq!(h.choose_cell(&cells, &inside, 3), CellChoice::Mesh);
        assert_eq!(h.choose_cell(&cells, &inside, 0), CellChoice::Culled);
        // From the south at z = 0, looking north along x = 2.5 with 5 degrees: at depth 24.5
        // the view is 1.07 wide on each side, short of x = 4.5 where the eastern cells begin.
        // (From z = 1 the flat western cells would lie below the view and be culled too.)
        let narrow = Camera::look_at(
            DVec3::new(2.5, -20.0, 0.0),
            DVec3::new(2.5, 0.0, 0.0),
            DVec3::Z,
            5.0,
            100,
            100,
        )
        .unwrap();
        let choices = h.choose(&cells, &narrow);
        assert_eq!(choices[1], CellChoice::Culled);
        assert_eq!(choices[3], CellChoice::Culled);
        assert!(matches!(choices[0], CellChoice::RayCast { .. }));
        assert!(matches!(choices[2], CellChoice::RayCast { .. }));
        // Looking away from the terrain: everything culled.
        let away = Camera::look_at(
            DVec3::new(4.5, 4.5, 50.0),
            DVec3::new(4.5, 4.5, 60.0),
            DVec3::Y,
            60.0,
            64,
            64,
        )
        .unwrap();
        assert!(h.choose(&cells, &away).iter().all(|&c| c == CellChoice::Culled));
    }

    #[test]
    fn precision_values_fall_into_their_levels() {
        let h = heuristic(70.0, 1.3);
        assert_eq!(
            [h.level_of(-0.5), h.level_of(0.0), h.level_of(0.2499), h.level_of(0.25)],
            [0, 0, 0, 1]
        );
        assert_eq!([h.level_of(0.74), h.level_of(0.75), h.level_of(1.0)], [2, 3, 3]);
    }

    #[test]
    fn parameters_out_of_range_are_refused_by_name() {
        let ok = HybridParams::default();
        assert_eq!((ok.cell, ok.threshold, ok.k, ok.levels), (64, 70.0, 1.3, 4));
        assert!(ok.validate().is_ok());
        let cases: [(HybridParams, &str); 8] = [
            (HybridParams { cell: 0, ..ok }, "cell"),
            (HybridParams { cell: 1, ..ok }, "cell"),
            (HybridParams { threshold: 0.0, ..ok }, "threshold"),
            (HybridParams { threshold: f64::NAN, ..ok }, "threshold"),
            (HybridParams { k: -1.0, ..ok }, "k ="),
            (HybridParams { levels: 0, ..ok }, "at least one level"),
            (HybridParams { levels: 1, ..ok }, "between 2 and 10"),
            (HybridParams { levels: 11, ..ok }, "between 2 and 10"),
        ];
        for (params, word) in cases {
            let err = HybridHeuristic::new(params).unwrap_err().to_string();
            assert!(err.contains(word), "{params:?}: {err}");
        }
    }
}
