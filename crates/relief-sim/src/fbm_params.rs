//! The parameters of fBm terrain: octaves, their frequency and amplitude progression.

use relief_core::CoreError;

/// Most octaves accepted: beyond this the finest octave is far below a texel for any grid that
/// fits in memory.
pub const MAX_OCTAVES: u32 = 32;

/// Parameters of [`fbm_terrain`](crate::fbm_terrain): a sum of `octaves` noise layers, layer
/// `k` with wavelength `wavelength / lacunarity^k` texels and amplitude
/// `amplitude * gain^k` sample units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FbmParams {
    /// Number of noise layers, 1 to [`MAX_OCTAVES`].
    pub octaves: u32,
    /// Frequency ratio between successive octaves, > 1 (usually 2).
    pub lacunarity: f64,
    /// Amplitude ratio between successive octaves, in (0, 1] (usually 0.5).
    pub gain: f64,
    /// Wavelength of the first (coarsest) octave in texels, > 0.
    pub wavelength: f64,
    /// Amplitude of the first octave in sample units, > 0.
    pub amplitude: f64,
}

impl FbmParams {
    /// Mountains sized for a `width x height` grid: the first octave's wavelength is a third of
    /// the longer side, octaves continue down to about 2 texels (at most 14), gain 0.5,
    /// lacunarity 2, and the amplitude makes the total relief about 0.15 times the longer side.
    pub fn for_size(width: usize, height: usize) -> Self {
        let side = width.max(height).max(1) as f64;
        let wavelength = (side / 3.0).max(2.0);
        let octaves = ((wavelength / 2.0).log2().floor() as u32 + 1).clamp(1, 14);
        FbmParams {
            octaves,
            lacunarity: 2.0,
            gain: 0.5,
            wavelength,
            amplitude: RELIEF_FRACTION * side / RELIEF_PER_AMPLITUDE,
        }
    }

    /// Checks every field's range; the error names the first field out of range.
    pub fn validate(&self) -> Result<(), CoreError> {
        let refuse = |name, reason: String| Err(CoreError::Parameter { name, reason });
        if !(1..=MAX_OCTAVES).contains(&self.octaves) {
            return refuse("octaves", format!("{} is not in 1..={MAX_OCTAVES}", self.octaves));
        }
        if !(self.lacunarity.is_finite() && self.lacunarity > 1.0) {
            return refuse("lacunarity", format!("{} is not a finite number > 1", self.lacunarity));
        }
        if !(self.gain > 0.0 && self.gain <= 1.0) {
            return refuse("gain", format!("{} is not in (0, 1]", self.gain));
        }
        // Below 1e-6 texels the finest lattice coordinates lose all precision.
        if !(self.wavelength.is_finite() && self.wavelength >= 1e-6) {
            return refuse(
                "wavelength",
                format!("{} is not a finite number >= 1e-6", self.wavelength),
            );
        }
        // Heights are stored as f32: keep the total well inside its range.
        if !(self.amplitude.is_finite() && self.amplitude > 0.0 && self.amplitude <= 1e30) {
            return refuse("amplitude", format!("{} is not in (0, 1e30]", self.amplitude));
        }
        Ok(())
    }
}

/// Total relief of [`FbmParams::for_size`] as a fraction of the grid's longer side.
const RELIEF_FRACTION: f64 = 0.15;

/// Typical total relief (max - min) of a terrain per unit of first-octave amplitude, measured
/// on grids made with [`FbmParams::for_size`].
pub(crate) const RELIEF_PER_AMPLITUDE: f64 = 0.87;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn for_size_follows_the_documented_rules() {
        let p = FbmParams::for_size(4096, 1024);
        assert!((p.wavelength - 4096.0 / 3.0).abs() < 1e-9);
        let finest = p.wavelength / p.lacunarity.powi(p.octaves as i32 - 1);
        assert!((2.0..4.0).contains(&finest), "finest octave {finest} texels");
        assert_eq!((p.gain, p.lacunarity), (0.5, 2.0));
        assert_eq!(FbmParams::for_size(1 << 30, 1).octaves, 14);
        for (w, h) in [(0, 0), (1, 1), (1, 7), (3, 2)] {
            FbmParams::for_size(w, h).validate().unwrap();
        }
    }

    #[test]
    fn validate_names_the_field_out_of_range() {
        let good = FbmParams::for_size(64, 64);
        let cases: [(&str, FbmParams); 7] = [
            ("octaves", FbmParams { octaves: 0, ..good }),
            ("octaves", FbmParams { octaves: MAX_OCTAVES + 1, ..good }),
            ("lacunarity", FbmParams { lacunarity: 1.0, ..good }),
            ("gain", FbmParams { gain: f64::NAN, ..good }),
            ("wavelength", FbmParams { wavelength: 0.0, ..good }),
            ("amplitude", FbmParams { amplitude: f64::INFINITY, ..good }),
            ("amplitude", FbmParams { amplitude: -1.0, ..good }),
        ];
        for (name, params) in cases {
            match params.validate() {
                Err(CoreError::Parameter { name: found, .. }) => assert_eq!(found, name),
                other => panic!("{params:?} gave {other:?}, expected an error on {name}"),
            }
        }
    }
}
