//! The error metrics of the hybrid-rendering paper's section 4.1 (Ammann et al. 2010)
//! between a reference depth image and a test depth image: per-pixel distance error, PSNR,
//! wrong pixels and the largest relative error.

use crate::ShadeError;

/// A depth image as relief writes it: `width x height` distances, row-major, +inf where the
/// ray hit nothing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DepthImage<'a> {
    /// Pixels per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// The distances, `width * height` of them, each >= 0 or +inf.
    pub depth: &'a [f32],
}

impl DepthImage<'_> {
    /// Checks the length and that every value is a distance (>= 0, finite or +inf), naming
    /// the first that is not.
    fn validate(&self, name: &'static str) -> Result<(), ShadeError> {
        if self.width.checked_mul(self.height) != Some(self.depth.len()) {
            return Err(ShadeError::Mismatch(format!(
                "{name} depth image of {} x {} pixels holds {} values",
                self.width,
                self.height,
                self.depth.len()
            )));
        }
        if let Some(i) = self.depth.iter().position(|d| d.is_nan() || *d < 0.0) {
            return Err(ShadeError::parameter(
                name,
                format!(
                    "pixel ({}, {}) has depth {}, not a distance >= 0 or +inf",
                    i % self.width.max(1),
                    i / self.width.max(1),
                    self.depth[i]
                ),
            ));
        }
        Ok(())
    }
}

/// The scale of the comparison: the PSNR's peak `R` and the cell size that tells a hit
/// slightly off from a wrong one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DepthScale {
    /// `R` of the PSNR: the terrain's bounding-box diagonal, world units, > 0.
    pub diagonal: f64,
    /// A hit more than this far (world units, along the ray) from the reference's is a
    /// wrong pixel: the terrain's grid spacing, > 0.
    pub cell: f64,
}

/// How far a test depth image is from its reference (section 4.1).
///
/// A pixel is *rendered* when both images hit terrain there; its error is the distance
/// between the two hits along the ray, `|test - reference|`. A pixel is *wrong* when one image
/// sees terrain and the other sky, or when both hit more than [`DepthScale::cell`] apart.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DepthMetrics {
    /// Pixels compared.
    pub pixels: usize,
    /// Pixels where both images hit terrain.
    pub rendered: usize,
    /// Pixels where the reference hits terrain and the test sees sky.
    pub reference_only: usize,
    /// Pixels where the test hits terrain and the reference sees sky.
    pub test_only: usize,
    /// Rendered pixels whose hits lie more than a cell apart.
    pub off_by_more_than_a_cell: usize,
    /// Wrong pixels: `reference_only + test_only + off_by_more_than_a_cell`.
    pub wrong: usize,
    /// `wrong / pixels` (0 for an image without pixels).
    pub wrong_pixel_fraction: f64,
    /// `10 log10(R² / MSE)`, the mean over the rendered pixels of the squared error, in dB;
    /// +inf when no rendered pixel has an error (identical images) or none is rendered.
    pub psnr_db: f64,
    /// Root of the MSE, world units (0 when no pixel is rendered).
    pub rms_error: f64,
    /// Largest error of a rendered pixel, world units.
    pub max_abs_error: f64,
    /// Largest `error / reference depth` over the rendered pixels whose reference depth is
    /// above 0 (0 when there are none).
    pub max_rel_error: f64,
}

/// The per-pixel distance error between two depth images of one shape: `|test - reference|`
/// where both hit terrain, 0 where both see sky, +inf where one sees terrain and the other sky.
///
/// Errors: images of different shapes ([`ShadeError::Mismatch`]), a value that is not a
/// distance ([`ShadeError::Parameter`]).
pub fn depth_errors(reference: &DepthImage, test: &DepthImage) -> Result<Vec<f32>, ShadeError> {
    check_pair(reference, test)?;
    Ok(reference
        .depth
        .iter()
        .zip(test.depth)
        .map(|(&r, &t)| match (r.is_finite(), t.is_finite()) {
            (true, true) => (f64::from(t) - f64::from(r)).abs() as f32,
            (false, false) => 0.0,
            _ => f32::INFINITY,
        })
        .collect())
}

/// The metrics of `test` against `reference` at `scale` (see [`DepthMetrics`]). The sums run
/// in f64 in pixel order, so the result does not depend on threads.
///
/// Errors: images of different shapes ([`ShadeError::Mismatch`]), a value that is not a
/// distance, or a scale that is not finite and positive ([`ShadeError::Parameter`]).
///
/// ```
/// use relief_shade::{depth_metrics, DepthImage, DepthScale};
/// let reference = [10.0, 20.0, f32::INFINITY, 40.0];
/// let test = [10.0, 21.0, 30.0, 40.0];
/// let image = |depth| DepthImage { width: 2, height: 2, depth };
/// let scale = DepthScale { diagonal: 100.0, cell: 2.0 };
/// let m = depth_metrics(&image(&reference), &image(&test), scale).unwrap();
/// assert_eq!((m.rendered, m.test_only, m.wrong), (3, 1, 1));
/// assert_eq!(m.wrong_pixel_fraction, 0.25);
/// // MSE = 1/3: PSNR = 10 log10(100² · 3).
/// assert!((m.psnr_db - 10.0 * 30000f64.log10()).abs() < 1e-9);
/// assert_eq!(m.max_rel_error, 0.05);
/// ```
pub fn depth_metrics(
    reference: &DepthImage,
    test: &DepthImage,
    scale: DepthScale,
) -> Result<DepthMetrics, ShadeError> {
    for (name, v) in [("PSNR diagonal", scale.diagonal), ("cell size", scale.cell)] {
        if !(v.is_finite() && v > 0.0) {
            return Err(ShadeError::parameter(name, format!("{v} is not a finite number > 0")));
        }
    }
    check_pair(reference, test)?;
    let mut m = DepthMetrics {
        pixels: reference.depth.len(),
        rendered: 0,
        reference_only: 0,
        test_only: 0,
        off_by_more_than_a_cell: 0,
        wrong: 0,
        wrong_pixel_fraction: 0.0,
        psnr_db: f64::INFINITY,
        rms_error: 0.0,
        max_abs_error: 0.0,
        max_rel_error: 0.0,
    };
    let mut squares = 0.0f64;
    for (&r, &t) in reference.depth.iter().zip(test.depth) {
        match (r.is_finite(), t.is_finite()) {
            (true, true) => {
                let (r, t) = (f64::from(r), f64::from(t));
                let e = (t - r).abs();
                m.rendered += 1;
                squares += e * e;
                m.max_abs_error = m.max_abs_error.max(e);
                if r > 0.0 {
                    m.max_rel_error = m.max_rel_error.max(e / r);
                }
                if e > scale.cell {
                    m.off_by_more_than_a_cell += 1;
                }
            }
            (true, false) => m.reference_only += 1,
            (false, true) => m.test_only += 1,
            (false, false) => {}
        }
    }
    m.wrong = m.reference_only + m.test_only + m.off_by_more_than_a_cell;
    if m.pixels > 0 {
        m.wrong_pixel_fraction = m.wrong as f64 / m.pixels as f64;
    }
    if m.rendered > 0 {
        let mse = squares / m.rendered as f64;
        m.rms_error = mse.sqrt();
        if mse > 0.0 {
            m.psnr_db = 10.0 * (scale.diagonal * scale.diagonal / mse).log10();
        }
    }
    Ok(m)
}

/// Checks both images and that they have one shape.
fn check_pair(reference: &DepthImage, test: &DepthImage) -> Result<(), ShadeError> {
    reference.validate("reference")?;
    test.validate("test")?;
    if (reference.width, reference.height) != (test.width, test.height) {
        return Err(ShadeError::Mismatch(format!(
            "the reference depth image is {} x {} pixels, the test {} x {}",
            reference.width, reference.height, test.width, test.height
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const INF: f32 = f32::INFINITY;

    fn image(width: usize, height: usize, depth: &[f32]) -> DepthImage<'_> {
        DepthImage { width, height, depth }
    }

    #[test]
    fn identical_images_have_infinite_psnr_and_no_wrong_pixel() {
        let d = [1.0, 2.0, INF, 0.0, 5.5, INF];
        let scale = DepthScale { diagonal: 10.0, cell: 1.0 };
        let m = depth_metrics(&image(3, 2, &d), &image(3, 2, &d), scale).unwrap();
        assert_eq!(m.psnr_db, f64::INFINITY);
        assert_eq!((m.pixels, m.rendered, m.wrong), (6, 4, 0));
        assert_eq!((m.wrong_pixel_fraction, m.max_rel_error, m.rms_error), (0.0, 0.0, 0.0));
    }

    #[test]
    fn hand_computed_case() {
        // Errors on rendered pixels: 0.5, 3 (more than a cell of 2), 0; one sky against
        // terrain each way.
        let reference = [10.0, 6.0, 4.0, INF, 8.0, INF];
        let test = [10.5, 9.0, 4.0, 7.0, INF, INF];
        let scale = DepthScale { diagonal: 50.0, cell: 2.0 };
        let m = depth_metrics(&image(2, 3, &reference), &image(2, 3, &test), scale).unwrap();
        assert_eq!((m.rendered, m.reference_only, m.test_only), (3, 1, 1));
        assert_eq!((m.off_by_more_than_a_cell, m.wrong), (1, 3));
        assert_eq!(m.wrong_pixel_fraction, 0.5);
        // MSE = (0.25 + 9 + 0) / 3 = 3.0833...; PSNR = 10 log10(2500 / MSE) = 29.0892...
        let mse: f64 = 9.25 / 3.0;
        assert!((m.psnr_db - 10.0 * (2500.0 / mse).log10()).abs() < 1e-12);
        assert!((m.psnr_db - 29.0892).abs() < 1e-4, "{}", m.psnr_db);
        assert!((m.rms_error - mse.sqrt()).abs() < 1e-12);
        assert_eq!(m.max_abs_error, 3.0);
        assert_eq!(m.max_rel_error, 0.5); // 3 / 6
        let errors = depth_errors(&image(2, 3, &reference), &image(2, 3, &test)).unwrap();
        assert_eq!(errors, vec![0.5, 3.0, 0.0, INF, INF, 0.0]);
    }

    #[test]
    fn exactly_one_cell_off_is_not_wrong() {
        let scale = DepthScale { diagonal: 1.0, cell: 1.0 };
        let m = depth_metrics(&image(2, 1, &[5.0, 5.0]), &image(2, 1, &[6.0, 6.5]), scale).unwrap();
        assert_eq!(m.off_by_more_than_a_cell, 1);
    }

    #[test]
    fn shapes_values_and_scales_are_checked() {
        let scale = DepthScale { diagonal: 1.0, cell: 1.0 };
        let a = [1.0; 6];
        let shape = depth_metrics(&image(3, 2, &a), &image(2, 3, &a), scale);
        assert!(matches!(shape, Err(ShadeError::Mismatch(_))));
        let short = depth_metrics(&image(3, 2, &a), &image(3, 2, &a[..5]), scale);
        assert!(matches!(short, Err(ShadeError::Mismatch(_))));
        for bad in [f32::NAN, -1.0, f32::NEG_INFINITY] {
            let b = [1.0, bad, 1.0, 1.0, 1.0, 1.0];
            let err = depth_metrics(&image(3, 2, &a), &image(3, 2, &b), scale).unwrap_err();
            assert!(err.to_string().contains("pixel (1, 0)"), "{err}");
        }
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let s = DepthScale { diagonal: bad, cell: 1.0 };
            assert!(depth_metrics(&image(3, 2, &a), &image(3, 2, &a), s).is_err());
            let s = DepthScale { diagonal: 1.0, cell: bad };
            assert!(depth_metrics(&image(3, 2, &a), &image(3, 2, &a), s).is_err());
        }
    }
}
