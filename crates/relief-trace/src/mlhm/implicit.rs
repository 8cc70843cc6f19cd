//! The smooth implicit surface of a multi-layered height map (Nilles & Müller 2025, sections
//! 3.3 and 4.3-4.5): the volume of material in a cube around a point, the isosurface at half
//! the cube, the hit test, the adaptive step heuristic `H` and normals by finite differences.

use crate::{MlhmMode, TraceError};
use relief_core::{BlurredBox, DVec3, MaterialVolumes, Mlhm};
use std::fmt;
use std::str::FromStr;

/// The share of the [target](MlhmImplicit::target) volume at which a point counts as inside
/// the surface (the paper's 99 %: adaptive steps approach the isosurface but never reach it).
pub const HIT_FRACTION: f64 = 0.99;

/// Which material's volume an implicit function measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum MlhmField {
    /// Bedrock and sand.
    Solid,
    /// Bedrock, sand and water.
    SolidWater,
    /// Air: the part of the cube inside the grid's footprint that holds no bedrock, sand or
    /// water. Outside the footprint the cube holds neither material nor air.
    Air,
}

/// The implicit function of one [`MlhmMode`] at a point: the larger of the volumes the mode
/// stops at, and which one it is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MlhmFieldSample {
    /// The volume, cubic metres.
    pub volume: f64,
    /// The material it measures: [`MlhmField::Solid`] for [`MlhmMode::Solids`],
    /// [`MlhmField::SolidWater`] for [`MlhmMode::SolidsWater`], and for
    /// [`MlhmMode::SolidsAir`] the larger of [`MlhmField::Solid`] and [`MlhmField::Air`].
    pub field: MlhmField,
}

/// How normals are computed from the volume field: `n = -grad V / |grad V|`, the gradient by
/// finite differences of spacing `h` (Nilles & Müller 2025, 4.4), or of `V` blurred over `h`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum MlhmNormalScheme {
    /// Forward differences `(V(p + h e_i) - V(p)) / h`: 3 evaluations besides `V(p)`.
    Forward,
    /// Central differences `(V(p + h e_i) - V(p - h e_i)) / 2h`: 6 evaluations, closer to
    /// the surface (best with `h = 0.5 σ_n`).
    Central,
    /// The exact gradient of `V` averaged twice over the cube of half-size `h` (`V`
    /// convolved with two normalised cubes of half-size `h`), in one pass over the cells a
    /// box reaching `σ_n + 2h` covers ([`Mlhm::blurred_volume_gradient`]). Over box-shaped columns `V` has a kink wherever a face of
    /// the cube crosses a cell edge or a column top, so plain differences turn the normal
    /// in jumps at every cell, and on slopes steeper than about one cell per cell the
    /// surface's ledges (one per cell) swing it by 15-20°: ribs. Averaged twice, the
    /// gradient is continuously differentiable and swings by about 1° there. The default.
    #[default]
    Smoothed,
}

impl MlhmNormalScheme {
    /// Every scheme, in a fixed order.
    pub const ALL: [MlhmNormalScheme; 3] =
        [MlhmNormalScheme::Forward, MlhmNormalScheme::Central, MlhmNormalScheme::Smoothed];

    /// The name used in reports and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            MlhmNormalScheme::Forward => "forward",
            MlhmNormalScheme::Central => "central",
            MlhmNormalScheme::Smoothed => "smoothed",
        }
    }
}

impl fmt::Display for MlhmNormalScheme {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(self.name())
    }
}

impl FromStr for MlhmNormalScheme {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        MlhmNormalScheme::ALL.into_iter().find(|n| n.name() == s).ok_or_else(|| {
            format!("unknown normal scheme '{s}' (expected forward, central or smoothed)")
        })
    }
}

/// The smooth implicit surface of an [`Mlhm`] at smoothing radius `σ` (metres).
///
/// `V(p)` is the exact volume of a material (see [`MlhmField`]) inside the axis-aligned cube
/// of half-size `σ` centred at `p` ([`Mlhm::material_volumes`]); the surface is where `V`
/// is half the cube, the [target](MlhmImplicit::target) `0.5 (2σ)³`, and a point is inside
/// once `V >= 0.99 target` ([`hit_volume`](MlhmImplicit::hit_volume)). Points are in
/// grid-local metres: x and y from the grid's south-west corner, z absolute.
///
/// A flat half-space's surface is its plane: `V = (2σ)² (z0 - z + σ)` near it, half the cube
/// exactly at `z = z0`.
///
/// ```
/// use relief_core::{DVec3, Mlhm};
/// use relief_trace::{MlhmField, MlhmImplicit};
/// let map = Mlhm::new(8, 8, 1, 1.0)?; // flat bedrock at z = 0
/// let implicit = MlhmImplicit::new(1.0).unwrap();
/// let on_plane = DVec3::new(4.0, 4.0, 0.0);
/// assert_eq!(implicit.field_volume(&map, on_plane, MlhmField::Solid), implicit.target());
/// // Half a metre above, a quarter of the cube is rock: the surface is 0.5 m away, and the
/// // heuristic, safe in every direction, steps less than that.
/// let above = DVec3::new(4.0, 4.0, 0.5);
/// let v = implicit.field_volume(&map, above, MlhmField::Solid);
/// assert_eq!(v, 2.0);
/// let step = implicit.step(implicit.target() - v);
/// assert!(0.3 < step && step <= 0.5);
/// # Ok::<(), relief_core::CoreError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MlhmImplicit {
    radius: f64,
    /// `(2σ)³`.
    cube: f64,
    /// `0.5 (2σ)³`.
    target: f64,
}

impl MlhmImplicit {
    /// The implicit surface of smoothing radius `radius` (σ, metres); fails unless it is a
    /// finite number > 0 whose cube is finite and positive.
    pub fn new(radius: f64) -> Result<Self, TraceError> {
        let cube = (2.0 * radius).powi(3);
        if !(radius > 0.0 && cube.is_finite() && cube > 0.0) {
            return Err(TraceError::Options(format!(
                "smoothing radius {radius} m: expected a finite number > 0"
            )));
        }
        Ok(MlhmImplicit { radius, cube, target: 0.5 * cube })
    }

    /// The smoothing radius σ, metres.
    #[inline]
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// The cube's volume `(2σ)³`.
    #[inline]
    pub fn cube_volume(&self) -> f64 {
        self.cube
    }

    /// The isosurface's volume, half the cube: `0.5 (2σ)³`.
    #[inline]
    pub fn target(&self) -> f64 {
        self.target
    }

    /// The volume from which a point counts as inside: `0.99` [target](MlhmImplicit::target).
    #[inline]
    pub fn hit_volume(&self) -> f64 {
        HIT_FRACTION * self.target
    }

    /// Whether a point of volume `volume` counts as inside the surface.
    #[inline]
    pub fn is_inside(&self, volume: f64) -> bool {
        volume >= self.hit_volume()
    }

    /// The volumes of bedrock, sand and water in the cube around `p`.
    #[inline]
    pub fn volumes(&self, map: &Mlhm, p: DVec3) -> MaterialVolumes {
        map.material_volumes(p - self.radius, p + self.radius)
    }

    /// The volume of `field` in the cube around `p`.
    #[inline]
    pub fn field_volume(&self, map: &Mlhm, p: DVec3, field: MlhmField) -> f64 {
        match field {
            MlhmField::Solid => map.solid_volume(p - self.radius, p + self.radius),
            MlhmField::SolidWater => self.volumes(map, p).total(),
            MlhmField::Air => self.air_volume(map, p, &self.volumes(map, p)),
        }
    }

    /// The volume of `field` in the cube around `p`, from the cube's material `volumes`.
    #[inline]
    pub fn field_volume_from(
        &self,
        map: &Mlhm,
        p: DVec3,
        field: MlhmField,
        volumes: &MaterialVolumes,
    ) -> f64 {
        match field {
            MlhmField::Solid => volumes.solid(),
            MlhmField::SolidWater => volumes.total(),
            MlhmField::Air => self.air_volume(map, p, volumes),
        }
    }

    /// The air in the cube around `p`, from its material `volumes`: the cube's part over the
    /// grid's footprint less the material in it (every vertical line over the grid is
    /// bedrock, sand, water or air).
    #[inline]
    fn air_volume(&self, map: &Mlhm, p: DVec3, volumes: &MaterialVolumes) -> f64 {
        let s = map.cell_size();
        let overlap = |centre: f64, cells: usize| {
            let (lo, hi) =
                ((centre - self.radius).max(0.0), (centre + self.radius).min(cells as f64 * s));
            (hi - lo).max(0.0)
        };
        let area = overlap(p.x, map.width()) * overlap(p.y, map.height());
        (area * 2.0 * self.radius - volumes.total()).max(0.0)
    }

    /// The implicit function of `mode` at `p`: for [`MlhmMode::Solids`] the solid volume,
    /// for [`MlhmMode::SolidsWater`] the solid and water volume, and for
    /// [`MlhmMode::SolidsAir`] (rays inside water, which stop at solids or where they leave
    /// the water) the larger of the solid and the air volume.
    #[inline]
    pub fn sample(&self, map: &Mlhm, p: DVec3, mode: MlhmMode) -> MlhmFieldSample {
        match mode {
            MlhmMode::Solids => MlhmFieldSample {
                volume: self.field_volume(map, p, MlhmField::Solid),
                field: MlhmField::Solid,
            },
            MlhmMode::SolidsWater => MlhmFieldSample {
                volume: self.volumes(map, p).total(),
                field: MlhmField::SolidWater,
            },
            MlhmMode::SolidsAir => {
                let volumes = self.volumes(map, p);
                let (solid, air) = (volumes.solid(), self.air_volume(map, p, &volumes));
                if solid >= air {
                    MlhmFieldSample { volume: solid, field: MlhmField::Solid }
                } else {
                    MlhmFieldSample { volume: air, field: MlhmField::Air }
                }
            }
        }
    }

    /// The step heuristic `H(ΔV)` (eq. 5): the distance a point may move, in any direction,
    /// while its volume changes by at most `ΔV`:
    /// `min(ΔV / (2σ)², √3 (2σ - cbrt((2σ)³ - ΔV)))`, the first term the bound for axis
    /// directions and the second for diagonals. `ΔV` is clamped to `[0, (2σ)³]`; the
    /// bound holds for every direction while `ΔV <= 0.5 (2σ)³`, which is all the tracer asks.
    #[inline]
    pub fn step(&self, delta_volume: f64) -> f64 {
        let side = 2.0 * self.radius;
        // `max` first: it maps NaN to 0.
        let dv = delta_volume.max(0.0).min(self.cube);
        let axis = dv / (side * side);
        let diagonal = 3f64.sqrt() * (side - (self.cube - dv).cbrt());
        axis.min(diagonal).max(0.0)
    }

    /// The gradient of `field`'s volume at `p` by finite differences of spacing `spacing`
    /// (metres) in `scheme`.
    pub fn gradient(
        &self,
        map: &Mlhm,
        p: DVec3,
        field: MlhmField,
        spacing: f64,
        scheme: MlhmNormalScheme,
    ) -> DVec3 {
        let base = match scheme {
            MlhmNormalScheme::Forward => self.field_volume(map, p, field),
            MlhmNormalScheme::Central | MlhmNormalScheme::Smoothed => 0.0,
        };
        self.gradient_with_base(map, p, field, spacing, scheme, base)
    }

    /// [`gradient`](MlhmImplicit::gradient), given `field`'s volume at `p` (`base`, used by
    /// forward differences only).
    pub(crate) fn gradient_with_base(
        &self,
        map: &Mlhm,
        p: DVec3,
        field: MlhmField,
        spacing: f64,
        scheme: MlhmNormalScheme,
        base: f64,
    ) -> DVec3 {
        if scheme == MlhmNormalScheme::Smoothed {
            // V averaged twice over the cube of half-size h.
            return self.blurred_field_gradient(map, p, field, [[spacing; 2]; 3]);
        }
        let v = |q: DVec3| self.field_volume(map, q, field);
        let mut g = DVec3::ZERO;
        for axis in 0..3 {
            let mut e = DVec3::ZERO;
            e[axis] = spacing;
            g[axis] = match scheme {
                MlhmNormalScheme::Forward => (v(p + e) - base) / spacing,
                MlhmNormalScheme::Central => (v(p + e) - v(p - e)) / (2.0 * spacing),
                MlhmNormalScheme::Smoothed => unreachable!("returned above"),
            };
        }
        g
    }

    /// The gradient of [`blurred_field_volume`](Self::blurred_field_volume) at `p`, exact
    /// ([`Mlhm::blurred_volume_gradient`]).
    pub fn blurred_field_gradient(
        &self,
        map: &Mlhm,
        p: DVec3,
        field: MlhmField,
        blurs: [[f64; 2]; 3],
    ) -> DVec3 {
        let kernel = blurs.map(|blurs| BlurredBox { half: self.radius, blurs });
        let g = map.blurred_volume_gradient(p, kernel);
        let solid = DVec3::new(g[0].solid(), g[1].solid(), g[2].solid());
        let total = DVec3::new(g[0].total(), g[1].total(), g[2].total());
        match field {
            MlhmField::Solid => solid,
            MlhmField::SolidWater => total,
            MlhmField::Air => {
                // The cube's part over the grid, less the material in it.
                let s = map.cell_size();
                let over = |a: usize, cells: usize| {
                    let (lo, hi) = (-p[a], cells as f64 * s - p[a]);
                    (kernel[a].weight(lo, hi), kernel[a].density(lo) - kernel[a].density(hi))
                };
                let ((wx, dx), (wy, dy)) = (over(0, map.width()), over(1, map.height()));
                let side = 2.0 * self.radius;
                DVec3::new(dx * wy * side, wx * dy * side, 0.0) - total
            }
        }
    }

    /// The volume of `field` weighted by the cube around `p` blurred along each axis by
    /// the shifts `blurs` ([`BlurredBox::blurs`], [`Mlhm::blurred_volumes`]): the mean of
    /// [`field_volume`](Self::field_volume) over the shifts of `p` by up to them.
    pub fn blurred_field_volume(
        &self,
        map: &Mlhm,
        p: DVec3,
        field: MlhmField,
        blurs: [[f64; 2]; 3],
    ) -> f64 {
        let kernel = blurs.map(|blurs| BlurredBox { half: self.radius, blurs });
        let volumes = map.blurred_volumes(p, kernel);
        match field {
            MlhmField::Solid => volumes.solid(),
            MlhmField::SolidWater => volumes.total(),
            MlhmField::Air => {
                let s = map.cell_size();
                let over =
                    |a: usize, cells: usize| kernel[a].weight(-p[a], cells as f64 * s - p[a]);
                let area = over(0, map.width()) * over(1, map.height());
                (area * 2.0 * self.radius - volumes.total()).max(0.0)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief_core::MlhmColumn;

    #[test]
    fn radius_must_be_finite_and_positive() {
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY, 1e200] {
            assert!(MlhmImplicit::new(bad).is_err(), "{bad}");
        }
        let implicit = MlhmImplicit::new(0.5).unwrap();
        assert_eq!((implicit.cube_volume(), implicit.target()), (1.0, 0.5));
        assert_eq!(implicit.hit_volume(), 0.495);
    }

    #[test]
    fn step_is_the_axis_bound_for_large_and_the_diagonal_bound_for_small_changes() {
        let implicit = MlhmImplicit::new(1.0).unwrap();
        // Axis: a 4 m² face moved 0.5 m sweeps 2 m³; the diagonal bound is smaller.
        let diagonal = 3f64.sqrt() * (2.0 - (8.0f64 - 2.0).cbrt());
        assert_eq!(implicit.step(2.0), 0.5f64.min(diagonal));
        assert!(implicit.step(0.1) < 0.1 / 4.0);
        assert_eq!(implicit.step(-1.0), 0.0);
        assert_eq!(implicit.step(f64::NAN), 0.0);
        assert_eq!(implicit.step(100.0), 2.0);
    }

    #[test]
    fn step_never_sweeps_more_than_the_change_it_was_given() {
        // The cube moved by `step(dv)` along any direction sweeps in at most `dv`.
        let implicit = MlhmImplicit::new(1.0).unwrap();
        let side = 2.0;
        for i in 1..=50 {
            let dv = implicit.target() * i as f64 / 50.0;
            let step = implicit.step(dv);
            for j in 0..=20 {
                for k in 0..=20 {
                    let quarter = std::f64::consts::FRAC_PI_2;
                    let (theta, phi) = (j as f64 / 20.0 * quarter, k as f64 / 20.0 * quarter);
                    let u = DVec3::new(theta.cos() * phi.cos(), theta.sin() * phi.cos(), phi.sin());
                    let kept: f64 = (0..3).map(|a| (side - step * u[a]).max(0.0)).product();
                    assert!(implicit.cube_volume() - kept <= dv * (1.0 + 1e-9), "{dv} {u}");
                }
            }
        }
    }

    #[test]
    fn solids_air_takes_the_larger_of_solid_and_air() {
        let mut map = Mlhm::new(4, 4, 1, 1.0).unwrap();
        for y in 0..4 {
            for x in 0..4 {
                map.set_cell(x, y, &[MlhmColumn::new(0.0, 0.0, 4.0, f32::INFINITY)]).unwrap();
            }
        }
        let implicit = MlhmImplicit::new(0.5).unwrap();
        let deep = implicit.sample(&map, DVec3::new(2.0, 2.0, 2.0), MlhmMode::SolidsAir);
        assert_eq!(deep.volume, 0.0);
        let surface = implicit.sample(&map, DVec3::new(2.0, 2.0, 4.25), MlhmMode::SolidsAir);
        assert_eq!((surface.volume, surface.field), (0.75, MlhmField::Air));
        let bottom = implicit.sample(&map, DVec3::new(2.0, 2.0, 0.25), MlhmMode::SolidsAir);
        assert_eq!((bottom.volume, bottom.field), (0.25, MlhmField::Solid));
        // At the grid's edge half the cube is outside: neither air nor water.
        let edge = implicit.field_volume(&map, DVec3::new(0.0, 2.0, 6.0), MlhmField::Air);
        assert_eq!(edge, 0.5);
    }

    #[test]
    fn gradients_of_a_plane_point_down() {
        let map = Mlhm::new(8, 8, 1, 1.0).unwrap();
        let implicit = MlhmImplicit::new(1.0).unwrap();
        let p = DVec3::new(4.3, 3.7, 0.1);
        for scheme in MlhmNormalScheme::ALL {
            let g = implicit.gradient(&map, p, MlhmField::Solid, 0.5, scheme);
            // The cube's face (4 m²) moving through the plane; blurred, the plane meets the
            // cube shifted by up to 2 h less often than the plain cube 0.1 m off its centre.
            let z = match scheme {
                MlhmNormalScheme::Smoothed => {
                    -4.0 * relief_core::BlurredBox { half: 1.0, blurs: [0.5; 2] }.density(-0.1)
                }
                _ => -4.0,
            };
            assert!((g - DVec3::new(0.0, 0.0, z)).length() < 1e-12, "{scheme}: {g}");
            assert!(z < -3.5, "{scheme}: {z}");
        }
        // The air's gradient is the solid's, reversed, away from the grid's edges.
        let air = implicit.gradient(&map, p, MlhmField::Air, 0.5, MlhmNormalScheme::Smoothed);
        let solid = implicit.gradient(&map, p, MlhmField::Solid, 0.5, MlhmNormalScheme::Smoothed);
        assert!((air + solid).length() < 1e-12, "{air} {solid}");
        assert_eq!("central".parse(), Ok(MlhmNormalScheme::Central));
        assert_eq!("smoothed".parse(), Ok(MlhmNormalScheme::Smoothed));
        assert!("upwind".parse::<MlhmNormalScheme>().is_err());
    }
}
