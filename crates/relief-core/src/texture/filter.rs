//! Filtering a mip-mapped texture over a pixel's footprint: plain bilinear sampling of one
//! level, or anisotropic filtering (Dick et al. 2009, section 3.3, which hands the footprint to
//! the GPU's anisotropic sampler; this is that sampler on the CPU).
//!
//! Anisotropic filtering takes the footprint's parallelogram in texel space (the pixel's steps
//! along the image's x and y), finds its principal axes (the singular vectors of the 2 x 2
//! matrix the two steps make), chooses the mip level whose texels are as wide as the minor
//! axis, and averages several trilinear samples spread evenly along the major axis, one per
//! minor-axis width. At most `max_anisotropy` samples are taken: a footprint longer than that
//! uses a coarser level, whose texels are the major axis divided by `max_anisotropy` wide, so
//! that it never aliases.

use crate::DVec2;
use crate::DVec3;

/// A texture with mip levels, sampled bilinearly on one level at a time.
pub trait MipTexture {
    /// Levels: 0 the finest, each next one half the size of the one below (2x2 averages).
    fn level_count(&self) -> u32;

    /// The linear colour of `level` interpolated bilinearly at `(s, t)`, given in texels of
    /// level 0 from the texture's lower-left corner (a texel of level `l` spans `2^l` of them;
    /// its centre is where it is sampled exactly), the edge texels extended beyond the edges.
    fn bilinear(&self, level: u32, s: f64, t: f64) -> DVec3;
}

/// How a texture is filtered over a pixel's footprint.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TextureFilter {
    /// One bilinear sample of the finest level allowed, whatever the footprint: aliases where
    /// a pixel covers many texels.
    Bilinear,
    /// The footprint's minor axis picks the level; up to `max_anisotropy` trilinear samples
    /// along its major axis.
    Anisotropic {
        /// The most samples per pixel (at least 1).
        max_anisotropy: u32,
    },
}

/// The maximum anisotropy of [`TextureFilter::Anisotropic`] by default, as GPUs offer.
pub const DEFAULT_MAX_ANISOTROPY: u32 = 16;

impl Default for TextureFilter {
    /// Anisotropic, up to [`DEFAULT_MAX_ANISOTROPY`] samples.
    fn default() -> Self {
        TextureFilter::Anisotropic { max_anisotropy: DEFAULT_MAX_ANISOTROPY }
    }
}

/// A pixel's footprint in the texel space of level 0: its centre and its steps along the
/// image's x and y axes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TexelFootprint {
    /// The hit, in texels from the texture's lower-left corner.
    pub centre: DVec2,
    /// Texels crossed by one pixel step along the image's x axis.
    pub along_x: DVec2,
    /// Texels crossed by one pixel step along the image's y axis.
    pub along_y: DVec2,
}

/// The principal axes of a [`TexelFootprint`]: the half-axes of the ellipse its parallelogram
/// stands for, doubled (a pixel's full extent along each).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FootprintAxes {
    /// The longest extent, as a vector in texels.
    pub major: DVec2,
    /// The shortest extent in texels, perpendicular to the major axis.
    pub minor: f64,
}

impl TexelFootprint {
    /// The principal axes: the singular values and the first singular vector of the matrix
    /// whose columns are the two steps. Non-finite when a step is.
    pub fn axes(&self) -> FootprintAxes {
        let (a, b) = (self.along_x, self.along_y);
        if !(a.is_finite() && b.is_finite()) {
            return FootprintAxes { major: DVec2::splat(f64::INFINITY), minor: f64::INFINITY };
        }
        // M M^T of M = [a b]: [[p, q], [q, r]].
        let p = a.x * a.x + b.x * b.x;
        let q = a.x * a.y + b.x * b.y;
        let r = a.y * a.y + b.y * b.y;
        let mean = 0.5 * (p + r);
        let spread = (0.25 * (p - r) * (p - r) + q * q).sqrt();
        let (large, small) = (mean + spread, (mean - spread).max(0.0));
        let direction = if q != 0.0 {
            DVec2::new(q, large - p).normalize()
        } else if p >= r {
            DVec2::X
        } else {
            DVec2::Y
        };
        FootprintAxes { major: direction * large.sqrt(), minor: small.sqrt() }
    }
}

/// The colour of `texture` over `footprint` with `filter`, on levels `min_level` and coarser
/// (0 for the full resolution; a renderer short of memory raises it).
pub fn filter_texture<T: MipTexture + ?Sized>(
    texture: &T,
    footprint: &TexelFootprint,
    filter: TextureFilter,
    min_level: u32,
) -> DVec3 {
    let last = texture.level_count().saturating_sub(1);
    let min_level = min_level.min(last);
    let centre = footprint.centre;
    let max_anisotropy = match filter {
        TextureFilter::Bilinear => return texture.bilinear(min_level, centre.x, centre.y),
        TextureFilter::Anisotropic { max_anisotropy } => max_anisotropy.max(1),
    };
    let axes = footprint.axes();
    let major = axes.major.length();
    if !major.is_finite() {
        // The footprint reaches the horizon: the whole texture's average.
        return texture.bilinear(last, centre.x, centre.y);
    }
    let minor = axes.minor.max(major / max_anisotropy as f64);
    let samples =
        if minor > 0.0 { (major / minor).ceil().clamp(1.0, max_anisotropy as f64) } else { 1.0 };
    let level = minor.log2().max(min_level as f64);
    let n = samples as u32;
    let mut sum = DVec3::ZERO;
    for k in 0..n {
        let at = centre + axes.major * ((k as f64 + 0.5) / samples - 0.5);
        sum += trilinear(texture, level, at, last);
    }
    sum / samples
}

/// `texture` at `at` between the two levels around `level` (at least 0, at most `last`).
fn trilinear<T: MipTexture + ?Sized>(texture: &T, level: f64, at: DVec2, last: u32) -> DVec3 {
    if level <= 0.0 {
        return texture.bilinear(0, at.x, at.y);
    }
    let below = level.floor();
    let fine = below as u32;
    if fine >= last {
        return texture.bilinear(last, at.x, at.y);
    }
    let weight = level - below;
    let colour = texture.bilinear(fine, at.x, at.y);
    if weight == 0.0 {
        return colour;
    }
    colour.lerp(texture.bilinear(fine + 1, at.x, at.y), weight)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cell::RefCell;

    /// Records every sample asked for; level `l` is the colour `(l, s, t)`.
    #[derive(Default)]
    struct Probe {
        calls: RefCell<Vec<(u32, f64, f64)>>,
    }

    impl MipTexture for Probe {
        fn level_count(&self) -> u32 {
            8
        }
        fn bilinear(&self, level: u32, s: f64, t: f64) -> DVec3 {
            self.calls.borrow_mut().push((level, s, t));
            DVec3::new(level as f64, s, t)
        }
    }

    fn footprint(along_x: DVec2, along_y: DVec2) -> TexelFootprint {
        TexelFootprint { centre: DVec2::new(100.0, 50.0), along_x, along_y }
    }

    #[test]
    fn axes_are_the_singular_values_of_the_steps() {
        let f = footprint(DVec2::new(3.0, 0.0), DVec2::new(0.0, -12.0));
        let axes = f.axes();
        assert!((axes.major.length() - 12.0).abs() < 1e-12 && axes.major.x.abs() < 1e-12);
        assert!((axes.minor - 3.0).abs() < 1e-12);
        // A sheared footprint: the area (|det|) is the product of the axes.
        let f = footprint(DVec2::new(2.0, 1.0), DVec2::new(4.0, 3.0));
        let axes = f.axes();
        let det = (2.0f64 * 3.0 - 1.0 * 4.0).abs();
        assert!((axes.major.length() * axes.minor - det).abs() < 1e-9);
        assert!(axes.major.length() >= (DVec2::new(4.0, 3.0)).length());
    }

    #[test]
    fn anisotropic_samples_spread_along_the_major_axis_on_the_minor_axis_level() {
        let probe = Probe::default();
        let filter = TextureFilter::Anisotropic { max_anisotropy: 16 };
        // 4 texels wide, 16 long along y: level 2, four samples 4 texels apart.
        let f = footprint(DVec2::new(4.0, 0.0), DVec2::new(0.0, 16.0));
        filter_texture(&probe, &f, filter, 0);
        let calls = probe.calls.take();
        assert_eq!(calls.len(), 4, "{calls:?}");
        for (k, &(level, s, t)) in calls.iter().enumerate() {
            assert_eq!(level, 2);
            assert_eq!(s, 100.0);
            assert!((t - (50.0 + (k as f64 - 1.5) * 4.0)).abs() < 1e-9, "{t}");
        }
        // 1 by 64 with at most 16 samples: the level of 64 / 16 = 4 texels.
        let f = footprint(DVec2::new(64.0, 0.0), DVec2::new(0.0, 1.0));
        filter_texture(&probe, &f, filter, 0);
        let calls = probe.calls.take();
        assert_eq!(calls.len(), 16);
        assert!(calls.iter().all(|c| c.0 == 2 && c.2 == 50.0));
        // Between levels: both, weighted.
        let f = footprint(DVec2::new(3.0, 0.0), DVec2::new(0.0, 3.0));
        let colour = filter_texture(&probe, &f, filter, 0);
        assert!((colour.x - 3f64.log2()).abs() < 1e-12);
        // A magnified texture: one sample of level 0; bilinear: level 0 (or the minimum).
        let f = footprint(DVec2::new(0.1, 0.0), DVec2::new(0.0, 0.1));
        assert_eq!(filter_texture(&probe, &f, filter, 0), DVec3::new(0.0, 100.0, 50.0));
        let wide = footprint(DVec2::new(64.0, 0.0), DVec2::new(0.0, 64.0));
        assert_eq!(filter_texture(&probe, &wide, TextureFilter::Bilinear, 0).x, 0.0);
        assert_eq!(filter_texture(&probe, &wide, TextureFilter::Bilinear, 3).x, 3.0);
        // Up to the horizon: the coarsest level.
        let endless = footprint(DVec2::new(1.0, 0.0), DVec2::splat(f64::INFINITY));
        assert_eq!(filter_texture(&probe, &endless, filter, 0).x, 7.0);
    }
}
