//! Smooth implicit-surface ray marching of an MLHM (Nilles & Müller 2025, 4.3-4.6): a 2D DDA
//! per level of a padded [`MlhmHierarchy`] down to level 1 and adaptive ray marching inside the
//! level-1 nodes the ray meets; the hit's normal, the medium and the soft shadows are in
//! [`super::smooth_shading`].

use super::cells::{ray_to_cells, world_box};
use super::walk::HierarchyWalk;
use crate::{
    Hit, MlhmBacktrack, MlhmFieldSample, MlhmHierarchy, MlhmImplicit, MlhmMode, MlhmNormalScheme,
    MlhmTracer, TraceError, Tracer,
};
use relief_core::{Aabb, DVec2, DVec3, Mlhm, MlhmHeights, Precision, Ray, Surface};
use std::sync::Arc;

/// The options of an [`MlhmSmoothTracer`]; [`Default`] gives the paper's settings
/// (`σ = σ_n = h` = one cell, exit stack, padded hierarchy, soft shadows) but for the
/// normals, the gradient of the volume averaged over the cube of half-size h
/// ([`MlhmNormalScheme::Smoothed`]) instead of the paper's forward differences, whose
/// normals turn in jumps at every cell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MlhmSmoothOptions {
    /// The smoothing radius σ, metres: the half-size of the cube whose material volume
    /// defines the surface. Larger radii round edges more and blur detail finer than σ.
    /// `None`: one cell.
    pub radius: Option<f64>,
    /// The smoothing radius σ_n of the volumes normals are computed from, metres: larger is
    /// smoother. `None`: σ.
    pub normal_radius: Option<f64>,
    /// The spacing h of the normals' finite differences, metres. `h = σ_n` is smoother,
    /// `h = 0.5 σ_n` (with central differences) follows the terrain more closely. `None`: σ_n.
    pub normal_spacing: Option<f64>,
    /// Forward (3 volume evaluations besides the hit's) or central (6) differences of the
    /// volume, or of the volume averaged over the cube of half-size h (6, smooth).
    pub normals: MlhmNormalScheme,
    /// How the hierarchical traversal climbs back to coarser levels.
    pub backtrack: MlhmBacktrack,
    /// Whether to traverse the padded hierarchy (`true`), marching only inside level-1 nodes
    /// whose padded bounds the ray meets, or to march the ray's whole part over the grid
    /// (`false`, the baseline: the same surface, many more steps).
    pub hierarchy: bool,
    /// The precision the hierarchy's bounds are stored at (rounded outward at f16).
    pub precision: Precision,
    /// Whether [`MlhmTracer::light_visibility`] returns soft shadows (eq. 8) or hard ones.
    pub soft_shadows: bool,
}

impl Default for MlhmSmoothOptions {
    fn default() -> Self {
        MlhmSmoothOptions {
            radius: None,
            normal_radius: None,
            normal_spacing: None,
            normals: MlhmNormalScheme::Smoothed,
            backtrack: MlhmBacktrack::ExitStack,
            hierarchy: true,
            precision: Precision::F32,
            soft_shadows: true,
        }
    }
}

/// Most level-1 node intervals marched apart; a node with more is marched over their hull.
const MAX_PARTS: usize = 16;

/// Ray marching of the smooth implicit surface of an [`Mlhm`] ([`MlhmImplicit`]), in every
/// [`MlhmMode`].
///
/// The surface of a mode is where the cube of half-size σ around a point holds half its
/// volume of the mode's material (for [`MlhmMode::SolidsAir`], of solids or of air); a point
/// is inside once the cube holds 99 % of that. The surface is clipped to the grid's
/// footprint, as the boxes are (it would reach about 0.01 σ past the edges), and ends at the
/// map's [base](Mlhm::base) as they do (the volumes end there): the solid is a block with
/// rounded edges, not a pillar. The field changes with height only in a slab: from σ below
/// the base (below, the cube holds nothing) or, for a map without a base, 2σ below the
/// lowest bedrock top (below, the cube over the grid is all bedrock) to σ above the highest
/// solid (water) top (above, it holds nothing), or 2σ above the highest water top for
/// [`MlhmMode::SolidsAir`] (above, only air). The ray's part over the footprint is marched inside the slab; beyond it, the
/// tracer evaluates the field once where the ray enters the footprint (below the slab, or
/// above it for solids + air) and once where it leaves the slab through its bottom (or, for
/// solids + air, its top), which decides the rest of the ray but near the grid's corners.
///
/// Traversal: the ray's part inside the slab walks the padded hierarchy
/// ([`MlhmHierarchy::build_padded`], whose level-1 node bounds enclose the surface) from the
/// coarsest level by a 2D DDA per level, slab-testing node layer intervals as
/// [`MlhmHierarchyTracer`](crate::MlhmHierarchyTracer) does and climbing back by
/// [`MlhmBacktrack`]. Where the box tracer would descend from level 1 to the cells, it
/// marches the ray's parts inside the level-1 node's intervals instead: from each part's
/// start, it evaluates the mode's volume `V`, stops when `V >= 0.99 target`, and otherwise
/// advances by the step heuristic `H(target - V)` (eq. 5, 6), which moves the cube by no
/// more than the volume missing to the isosurface in any direction: it never steps over a
/// point where `V` exceeds the target. A hit takes one corrective step `H(target - V)`
/// (eq. 7); its normal is `-grad V` by finite differences (radius σ_n, spacing h), facing
/// against the ray, and its material is water where the solids alone would not be inside
/// (in [`MlhmMode::SolidsWater`]), air where the ray leaves the water (in
/// [`MlhmMode::SolidsAir`]), else bedrock or sand, whichever fills more of the cube.
/// Without the hierarchy ([`MlhmSmoothOptions::hierarchy`]) it marches the whole part.
///
/// Hits are approximate, as the paper's: within the last step and the corrective step of the
/// first crossing of `V >= 0.99 target`, and possibly past a stretch where `V` stays between
/// 0.99 and 1 times the target. Steps counted are the nodes visited plus the volume
/// evaluations of the march.
///
/// ```
/// use std::sync::Arc;
/// use relief_core::{DVec2, DVec3, Mlhm, Ray};
/// use relief_trace::{MlhmMaterial, MlhmMode, MlhmSmoothTracer, MlhmTracer};
/// let map = Arc::new(Mlhm::new(16, 16, 1, 1.0)?); // flat bedrock at z = 0
/// let tracer = MlhmSmoothTracer::new(map, DVec2::ZERO);
/// let down = Ray::new(DVec3::new(8.0, 8.0, 10.0), -DVec3::Z);
/// let hit = tracer.intersect_mode(&down, MlhmMode::SolidsWater).unwrap();
/// // The flat ground's smooth surface is its plane; the march stops within 0.01 σ of it.
/// assert!(hit.hit.position.z >= 0.0 && hit.hit.position.z < 0.01);
/// assert!((hit.hit.normal - DVec3::Z).length() < 1e-9);
/// assert_eq!(hit.material, MlhmMaterial::Bedrock);
/// # Ok::<(), relief_core::CoreError>(())
/// ```
#[derive(Debug, Clone)]
pub struct MlhmSmoothTracer {
    pub(super) map: Arc<Mlhm>,
    pub(super) origin: DVec2,
    pub(super) implicit: MlhmImplicit,
    pub(super) normal_implicit: MlhmImplicit,
    pub(super) normal_spacing: f64,
    pub(super) options: MlhmSmoothOptions,
    pub(super) hierarchy: Option<MlhmHierarchy>,
    pub(super) heights: MlhmHeights,
    pub(super) mode: MlhmMode,
}

/// Where a march stopped: the sample inside the surface.
#[derive(Debug, Clone, Copy)]
pub(super) struct Marched {
    pub(super) t: f64,
    pub(super) sample: MlhmFieldSample,
}

/// What to evaluate along a ray (parameters of its part over the grid's footprint): a
/// probe where it enters the footprint beyond the heights where the field changes with
/// height, the march between those heights, a probe where it leaves them through the
/// bottom (or, for solids + air, the top) over the footprint.
#[derive(Debug, Clone, Copy)]
struct Plan {
    probe_first: Option<f64>,
    march: Option<(f64, f64)>,
    probe_last: Option<f64>,
}

/// A world ray in the grid-local metres the volumes are computed in.
#[derive(Debug, Clone, Copy)]
struct LocalRay {
    origin: DVec3,
    dir: DVec3,
    /// `|dir|`: metres per unit of `t`.
    speed: f64,
}

impl LocalRay {
    #[inline]
    fn at(&self, t: f64) -> DVec3 {
        self.origin + t * self.dir
    }
}

impl MlhmSmoothTracer {
    /// A tracer of `map` placed with its south-west corner at world `origin`, with the default
    /// options ([`MlhmSmoothOptions::default`]); intersects [`MlhmMode::SolidsWater`] as a
    /// [`Tracer`].
    ///
    /// # Panics
    /// When the map's cell size is so large (beyond 1e102 m) that the cube's volume
    /// overflows; [`with_options`](MlhmSmoothTracer::with_options) returns an error then.
    pub fn new(map: Arc<Mlhm>, origin: DVec2) -> Self {
        Self::with_options(map, origin, MlhmSmoothOptions::default())
            .expect("a smoothing radius of one cell")
    }

    /// A tracer of `map` at `origin` with `options`; builds the padded hierarchy when they ask
    /// for it. Fails when a radius or the spacing is given but is not a finite number > 0.
    pub fn with_options(
        map: Arc<Mlhm>,
        origin: DVec2,
        options: MlhmSmoothOptions,
    ) -> Result<Self, TraceError> {
        let positive = |name: &str, v: Option<f64>| match v {
            Some(v) if !(v > 0.0 && v.is_finite()) => {
                Err(TraceError::Options(format!("{name} {v} m: expected a finite number > 0")))
            }
            _ => Ok(()),
        };
        positive("smoothing radius", options.radius)?;
        positive("normal smoothing radius", options.normal_radius)?;
        positive("normal spacing", options.normal_spacing)?;
        let radius = options.radius.unwrap_or(map.cell_size());
        let implicit = MlhmImplicit::new(radius)?;
        let normal_implicit = MlhmImplicit::new(options.normal_radius.unwrap_or(radius))?;
        let normal_spacing = options.normal_spacing.unwrap_or(normal_implicit.radius());
        let hierarchy =
            options.hierarchy.then(|| MlhmHierarchy::build_padded(&map, radius, options.precision));
        let heights = map.heights();
        Ok(MlhmSmoothTracer {
            map,
            origin,
            implicit,
            normal_implicit,
            normal_spacing,
            options,
            hierarchy,
            heights,
            mode: MlhmMode::SolidsWater,
        })
    }

    /// The same tracer intersecting `mode` when used as a [`Tracer`].
    pub fn with_mode(self, mode: MlhmMode) -> Self {
        MlhmSmoothTracer { mode, ..self }
    }

    /// The same tracer climbing back up by `backtrack`.
    pub fn with_backtrack(self, backtrack: MlhmBacktrack) -> Self {
        let options = MlhmSmoothOptions { backtrack, ..self.options };
        MlhmSmoothTracer { options, ..self }
    }

    /// The mode intersected as a [`Tracer`].
    pub fn mode(&self) -> MlhmMode {
        self.mode
    }

    /// The options it was built with.
    pub fn options(&self) -> &MlhmSmoothOptions {
        &self.options
    }

    /// The implicit surface traced (its radius is σ).
    pub fn implicit(&self) -> &MlhmImplicit {
        &self.implicit
    }

    /// The padded hierarchy walked, `None` when it marches without one.
    pub fn hierarchy(&self) -> Option<&MlhmHierarchy> {
        self.hierarchy.as_ref()
    }

    /// The heights between which the field of `mode` changes with height (see
    /// [`MlhmSmoothTracer`]) and whether the cube below them is all bedrock: above `top` the
    /// cube holds no solid (no water) or, for [`MlhmMode::SolidsAir`], only air; below
    /// `bottom` it is all bedrock over the grid where the map has no base, and holds no
    /// solid where it has one (`bottom` is then a radius below the base).
    fn heights(&self, mode: MlhmMode) -> (f64, f64, bool) {
        let r = self.implicit.radius();
        let top = match mode {
            MlhmMode::Solids => self.heights.solid_max + r,
            MlhmMode::SolidsWater => self.heights.water_max + r,
            MlhmMode::SolidsAir => self.heights.water_max + 2.0 * r,
        };
        let base = f64::from(self.map.base());
        if base.is_finite() {
            (base - r, top, false)
        } else {
            (self.heights.bedrock_min - 2.0 * r, top, true)
        }
    }

    /// What to evaluate along the cell-space `ray` in `mode`; `None` when it misses the
    /// grid's footprint.
    fn plan(&self, ray: &Ray, mode: MlhmMode) -> Option<Plan> {
        let (w, h) = (self.map.width() as f64, self.map.height() as f64);
        let footprint =
            Aabb::new(DVec3::new(0.0, 0.0, f64::NEG_INFINITY), DVec3::new(w, h, f64::INFINITY));
        // Finite: the footprint is along x and y, and the ray moves along one of them or,
        // moving along z only, is cut to the slab below.
        let clip = footprint.clip(ray)?;
        let (bottom, top, solid_below) = self.heights(mode);
        let (oz, dz) = (ray.origin.z, ray.dir.z);
        let probe_above = mode == MlhmMode::SolidsAir;
        let (mut t0, mut t1) = (clip.t_enter, clip.t_exit);
        if dz != 0.0 {
            let (a, b) = ((bottom - oz) / dz, (top - oz) / dz);
            t0 = t0.max(a.min(b));
            t1 = t1.min(a.max(b));
        } else if !(bottom <= oz && oz <= top) {
            (t0, t1) = (f64::INFINITY, f64::NEG_INFINITY);
        }
        let march = (t0 <= t1).then_some((t0, t1));
        let z_enter = oz + clip.t_enter * dz;
        let beyond = (solid_below && z_enter < bottom) || (probe_above && z_enter > top);
        let probe_first =
            (beyond && march.is_none_or(|(t0, _)| clip.t_enter < t0)).then_some(clip.t_enter);
        // Leaving the slab through its bottom (above bedrock) or, for solids + air, its top
        // over the grid.
        let probe_last = march.and_then(|(_, t1)| {
            let through = (dz < 0.0 && solid_below) || (dz > 0.0 && probe_above);
            (t1 < clip.t_exit && through).then_some(t1)
        });
        Some(Plan { probe_first, march, probe_last })
    }

    /// The first sample of `world_ray` inside the surface of `mode`, counting nodes and
    /// samples into `steps` and showing every sample `(t, V)` to `observe`.
    pub(super) fn trace(
        &self,
        world_ray: &Ray,
        mode: MlhmMode,
        steps: &mut u32,
        observe: &mut impl FnMut(f64, f64),
    ) -> Option<Marched> {
        let ray = ray_to_cells(&self.map, self.origin, world_ray)?;
        let plan = self.plan(&ray, mode)?;
        let local = LocalRay {
            origin: world_ray.origin - self.origin.extend(0.0),
            dir: world_ray.dir,
            speed: world_ray.dir.length(),
        };
        let marcher = Marcher { tracer: self, ray: local, mode };
        if let Some(t) = plan.probe_first {
            if let Some(hit) = marcher.probe(t, steps, observe) {
                return Some(hit);
            }
        }
        if let Some((t0, t1)) = plan.march {
            let hit = match &self.hierarchy {
                None => marcher.march(t0, t1, steps, observe),
                Some(hierarchy) => self.traverse(hierarchy, &ray, &marcher, t0, t1, steps, observe),
            };
            if hit.is_some() {
                return hit;
            }
        }
        plan.probe_last.and_then(|t| marcher.probe(t, steps, observe))
    }

    /// The hierarchical traversal of the clipped cell-space `ray` over `[t_enter, t_exit]`,
    /// marching inside the level-1 nodes it reaches ([`HierarchyWalk`], as the box tracer
    /// walks down to the cells).
    #[allow(clippy::too_many_arguments)]
    fn traverse(
        &self,
        hierarchy: &MlhmHierarchy,
        ray: &Ray,
        marcher: &Marcher<'_>,
        t_enter: f64,
        t_exit: f64,
        steps: &mut u32,
        observe: &mut impl FnMut(f64, f64),
    ) -> Option<Marched> {
        let walk = HierarchyWalk {
            hierarchy,
            leaf_level: 1,
            backtrack: self.options.backtrack,
            mode: marcher.mode,
        };
        let inv = DVec3::ONE / ray.dir;
        walk.walk(ray, inv, t_enter, t_exit, steps, |nx, ny, span, steps| {
            Self::march_node(
                hierarchy,
                nx,
                ny,
                &|lo, hi| span.part(lo, hi),
                marcher,
                steps,
                observe,
            )
        })
    }

    /// Marches the ray's parts inside the intervals of level-1 node `(nx, ny)` (`part` gives
    /// the part inside one, if any), in order, merged where they overlap.
    fn march_node(
        hierarchy: &MlhmHierarchy,
        nx: usize,
        ny: usize,
        part: &impl Fn(f64, f64) -> Option<(f64, f64)>,
        marcher: &Marcher<'_>,
        steps: &mut u32,
        observe: &mut impl FnMut(f64, f64),
    ) -> Option<Marched> {
        let mut parts = [(0.0, 0.0); MAX_PARTS];
        let mut n = 0;
        let mut hull = (f64::INFINITY, f64::NEG_INFINITY);
        hierarchy.for_each_interval(1, nx, ny, marcher.mode, |lo, hi| {
            if let Some(p) = part(lo, hi) {
                hull = (hull.0.min(p.0), hull.1.max(p.1));
                if n < MAX_PARTS {
                    parts[n] = p;
                }
                n += 1;
            }
            false
        });
        let parts: &mut [(f64, f64)] = if n > MAX_PARTS {
            parts[0] = hull;
            &mut parts[..1]
        } else {
            &mut parts[..n]
        };
        parts.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
        let mut current: Option<(f64, f64)> = None;
        for &(a, b) in parts.iter() {
            match current {
                Some((s, e)) if a <= e => current = Some((s, e.max(b))),
                _ => {
                    if let Some((s, e)) = current {
                        let hit = marcher.march(s, e, steps, observe);
                        if hit.is_some() {
                            return hit;
                        }
                    }
                    current = Some((a, b));
                }
            }
        }
        current.and_then(|(s, e)| marcher.march(s, e, steps, observe))
    }
}

/// Marching along one ray in one mode.
struct Marcher<'a> {
    tracer: &'a MlhmSmoothTracer,
    ray: LocalRay,
    mode: MlhmMode,
}

impl Marcher<'_> {
    /// The sample at `t` when it is inside the surface.
    fn probe(
        &self,
        t: f64,
        steps: &mut u32,
        observe: &mut impl FnMut(f64, f64),
    ) -> Option<Marched> {
        *steps = steps.saturating_add(1);
        let sample = self.tracer.implicit.sample(&self.tracer.map, self.ray.at(t), self.mode);
        observe(t, sample.volume);
        self.tracer.implicit.is_inside(sample.volume).then_some(Marched { t, sample })
    }

    /// The first sample inside the surface over `[t0, t1]`: samples from `t0`, each step the
    /// heuristic's safe distance for the volume missing to the target.
    #[inline]
    fn march(
        &self,
        t0: f64,
        t1: f64,
        steps: &mut u32,
        observe: &mut impl FnMut(f64, f64),
    ) -> Option<Marched> {
        let implicit = &self.tracer.implicit;
        let map = &*self.tracer.map;
        let mut t = t0;
        loop {
            *steps = steps.saturating_add(1);
            let sample = implicit.sample(map, self.ray.at(t), self.mode);
            observe(t, sample.volume);
            if implicit.is_inside(sample.volume) {
                return Some(Marched { t, sample });
            }
            let next = t + implicit.step(implicit.target() - sample.volume) / self.ray.speed;
            // `next <= t`: a step lost to rounding at an enormous `t`; give up.
            if next <= t || next.is_nan() || next > t1 {
                return None;
            }
            t = next;
        }
    }
}

impl Tracer for MlhmSmoothTracer {
    fn name(&self) -> &'static str {
        "mlhm-smooth"
    }

    /// [`Surface`] names no smooth surface; this one smooths the MLHM's boxes.
    fn surface(&self) -> Surface {
        Surface::Boxes
    }

    /// The footprint, from a radius below the map's [base](Mlhm::base) (from minus infinity
    /// where it has none: below the slab the field is all bedrock) up to the top of the slab
    /// where the field changes, or to infinity for [`MlhmMode::SolidsAir`] (air above the
    /// slab is hit too).
    fn bounds(&self) -> Aabb {
        let (bottom, top, solid_below) = self.heights(self.mode);
        let top = if self.mode == MlhmMode::SolidsAir { f64::INFINITY } else { top };
        let bottom = if solid_below { f64::NEG_INFINITY } else { bottom };
        let boxed = world_box(&self.map, self.origin, top);
        Aabb::new(boxed.min.truncate().extend(bottom), boxed.max)
    }

    fn intersect_counted(&self, ray: &Ray, steps: &mut u32) -> Option<Hit> {
        self.intersect_mode_counted(ray, self.mode, steps).map(|h| h.hit)
    }
}
