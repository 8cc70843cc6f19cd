//! The smooth implicit-surface tracer on scenes whose answers are known: a flat map rendered
//! as its plane, nonsense options refused, soft shadows darkening near edges only, and hits
//! carrying the material of the surface, with the media as the smooth surface sees them.

mod common;

use common::mlhm_reference::Rng;
use proptest::prelude::*;
use relief_core::{DVec2, DVec3, Mlhm, MlhmColumn, Ray};
use relief_trace::{
    Medium, MlhmMaterial, MlhmMode, MlhmNormalScheme, MlhmSmoothOptions, MlhmSmoothTracer,
    MlhmTracer, TraceError, Tracer,
};
use std::sync::Arc;

/// A `size x size` map of cell size `s`, every cell bedrock up to `z0`.
fn flat_map(size: usize, s: f64, z0: f32) -> Arc<Mlhm> {
    let mut map = Mlhm::new(size, size, 1, s).unwrap();
    for y in 0..size {
        for x in 0..size {
            map.set_cell(x, y, &[MlhmColumn::new(z0, 0.0, 0.0, f32::INFINITY)]).unwrap();
        }
    }
    Arc::new(map)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, ..ProptestConfig::default() })]

    /// (c) A flat map's smooth surface is its plane: rays from above hit it at `z0` (within
    /// the 0.01 σ the 99 % hit test leaves, which the corrective step shrinks) with normal
    /// `+z`, in the solids and solids + water modes, with every normal scheme and direction
    /// lengths other than 1.
    #[test]
    fn a_flat_map_renders_as_its_plane(
        seed in any::<u64>(),
        cell_index in 0usize..3,
        radius_cells in 0.5f64..2.0,
        scheme in 0usize..3,
        hierarchy in any::<bool>(),
    ) {
        let mut rng = Rng::new(seed);
        let s = [0.5, 1.0, 2.0][cell_index];
        let (size, z0) = (32, 3.25f32);
        let map = flat_map(size, s, z0);
        let radius = radius_cells * s;
        let origin = DVec2::new(100.0, -40.0);
        let normals = MlhmNormalScheme::ALL[scheme];
        let options = MlhmSmoothOptions {
            radius: Some(radius),
            normals,
            normal_spacing: (normals != MlhmNormalScheme::Forward).then_some(0.5 * radius),
            hierarchy,
            ..MlhmSmoothOptions::default()
        };
        let tracer = MlhmSmoothTracer::with_options(map, origin, options).unwrap();
        // Aim well inside the edges, where the cubes of the normals stay over the grid.
        let margin = 3.0 * radius;
        let extent = size as f64 * s;
        for i in 0..8 {
            let target = origin.extend(z0 as f64)
                + DVec3::new(rng.range(margin, extent - margin), rng.range(margin, extent - margin), 0.0);
            let mut d = rng.unit();
            d.z = -d.z.abs().max(0.3);
            let d = if i == 0 { -DVec3::Z } else { d.normalize() };
            let scale = rng.range(0.3, 3.0);
            let o = target - d * rng.range(2.0, 12.0);
            // Rays that would pass over the grid's edges before the target are not at issue.
            let ray = Ray::new(o, d * scale);
            for mode in MlhmMode::ALL {
                if mode == MlhmMode::SolidsAir {
                    continue; // rays from air stop at once: no water to be in
                }
                let hit = tracer.intersect_mode(&ray, mode).unwrap();
                // Inside from 0.01 σ above the plane on; the corrective step moves towards
                // it, never past it.
                let z = hit.hit.position.z - z0 as f64;
                prop_assert!(
                    -1e-9 <= z && z <= 0.01 * radius + 1e-9,
                    "{mode}: {z} above the plane for {ray:?}"
                );
                prop_assert!((hit.hit.normal - DVec3::Z).length() < 1e-6, "{}", hit.hit.normal);
                prop_assert_eq!(hit.material, MlhmMaterial::Bedrock);
            }
        }
    }
}

#[test]
fn nonsense_options_are_refused() {
    let map = flat_map(4, 1.0, 0.0);
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        for options in [
            MlhmSmoothOptions { radius: Some(bad), ..MlhmSmoothOptions::default() },
            MlhmSmoothOptions { normal_radius: Some(bad), ..MlhmSmoothOptions::default() },
            MlhmSmoothOptions { normal_spacing: Some(bad), ..MlhmSmoothOptions::default() },
        ] {
            let result = MlhmSmoothTracer::with_options(map.clone(), DVec2::ZERO, options);
            assert!(matches!(result, Err(TraceError::Options(_))), "{options:?}");
        }
    }
    let tracer = MlhmSmoothTracer::new(map, DVec2::ZERO);
    assert_eq!(tracer.implicit().radius(), 1.0);
    assert_eq!(tracer.name(), "mlhm-smooth");
    // Rays that cannot be traced miss.
    for ray in [
        Ray::new(DVec3::new(2.0, 2.0, 5.0), DVec3::ZERO),
        Ray::new(DVec3::new(f64::NAN, 2.0, 5.0), -DVec3::Z),
        Ray::new(DVec3::new(2.0, 2.0, 5.0), -DVec3::Z).with_range(3.0, 1.0),
    ] {
        assert!(tracer.intersect_mode(&ray, MlhmMode::SolidsWater).is_none());
    }
}

/// A 64 x 8 map of unit cells: flat ground at 0 with a wall, cells 40..44 along x, up to 4 m.
fn wall_map() -> Arc<Mlhm> {
    let mut map = Mlhm::new(64, 8, 1, 1.0).unwrap();
    for y in 0..8 {
        for x in 40..44 {
            map.set_cell(x, y, &[MlhmColumn::new(4.0, 0.0, 0.0, f32::INFINITY)]).unwrap();
        }
    }
    Arc::new(map)
}

/// (d) Soft shadows: 0 where the shadow ray meets the surface, 1 far above open ground,
/// in between, growing with the clearance, for rays that pass just over an edge.
#[test]
fn soft_shadows_darken_near_edges_only() {
    let map = wall_map();
    for hierarchy in [true, false] {
        let options = MlhmSmoothOptions { hierarchy, ..MlhmSmoothOptions::default() };
        let tracer = MlhmSmoothTracer::with_options(map.clone(), DVec2::ZERO, options).unwrap();
        let visibility = |ray: &Ray| tracer.light_visibility(ray, &mut 0);
        // Far above open ground, towards the sky.
        let up = Ray::new(DVec3::new(10.0, 4.0, 20.0), DVec3::new(0.3, 0.1, 1.0).normalize());
        assert_eq!(visibility(&up), 1.0);
        // From the ground in front of the wall, through it: the hard shadow.
        let ground = Ray::new(DVec3::new(5.5, 4.0, 10.0), -DVec3::Z);
        let on_ground = tracer.intersect_mode(&ground, MlhmMode::Solids).unwrap().hit.position;
        let through = Ray::new(on_ground, DVec3::new(1.0, 0.0, 0.05).normalize());
        assert!(tracer.intersect_mode(&through, MlhmMode::Solids).is_some());
        assert_eq!(visibility(&through), 0.0);
        // From the ground, steeply up into open sky: the surface point itself is lit.
        let lit = Ray::new(on_ground, DVec3::new(-1.0, 0.0, 1.0).normalize());
        assert_eq!(visibility(&lit), 1.0);
        // Horizontal rays from 30 m before the wall, clearing its top (4 m) by a fraction of
        // σ: darker the closer they pass, lit from a clearance of σ on.
        let pass = |clearance: f64| {
            visibility(&Ray::new(DVec3::new(10.0, 4.0, 4.0 + clearance), DVec3::X))
        };
        let (near, mid, far) = (pass(0.1), pass(0.3), pass(0.6));
        assert!(0.0 < near && near < mid && mid < far && far < 1.0, "{near} {mid} {far}");
        assert_eq!(pass(1.05), 1.0);
        // Through the wall's top corner: the hard shadow.
        assert_eq!(pass(-0.2), 0.0);
        // Hard shadows only when asked.
        let hard = MlhmSmoothTracer::with_options(
            map.clone(),
            DVec2::ZERO,
            MlhmSmoothOptions { soft_shadows: false, hierarchy, ..MlhmSmoothOptions::default() },
        )
        .unwrap();
        let ray = Ray::new(DVec3::new(10.0, 4.0, 4.1), DVec3::X);
        assert_eq!(hard.light_visibility(&ray, &mut 0), 1.0);
    }
}

/// Materials at hits: water where the solids alone are not inside, air where a ray leaves the
/// water, the larger of bedrock and sand else.
#[test]
fn hits_carry_the_material_of_the_surface() {
    let mut map = Mlhm::new(16, 16, 1, 1.0).unwrap();
    for y in 0..16 {
        for x in 0..16 {
            let sand = if x < 8 { 0.0 } else { 1.5 };
            map.set_cell(x, y, &[MlhmColumn::new(1.0, sand, 4.0, f32::INFINITY)]).unwrap();
        }
    }
    let tracer = MlhmSmoothTracer::new(Arc::new(map), DVec2::ZERO);
    let down = |x: f64| Ray::new(DVec3::new(x, 8.0, 10.0), -DVec3::Z);
    let water = tracer.intersect_mode(&down(4.0), MlhmMode::SolidsWater).unwrap();
    assert_eq!(water.material, MlhmMaterial::Water);
    let near = |z: f64, plane: f64| (z - plane).abs() <= 0.01;
    assert!(near(water.hit.position.z, 5.0));
    let rock = tracer.intersect_mode(&down(4.0), MlhmMode::Solids).unwrap();
    assert_eq!(rock.material, MlhmMaterial::Bedrock);
    assert!(near(rock.hit.position.z, 1.0));
    let sand = tracer.intersect_mode(&down(12.0), MlhmMode::Solids).unwrap();
    assert_eq!(sand.material, MlhmMaterial::Sand);
    assert!(near(sand.hit.position.z, 2.5));
    // From inside the water: up into air, down onto the bed.
    let inside = DVec3::new(4.0, 8.0, 3.0);
    let out = tracer.intersect_mode(&Ray::new(inside, DVec3::Z), MlhmMode::SolidsAir).unwrap();
    assert_eq!(out.material, MlhmMaterial::Air);
    assert!(near(out.hit.position.z, 5.0));
    assert!((out.hit.normal + DVec3::Z).length() < 1e-9);
    let bed = tracer.intersect_mode(&Ray::new(inside, -DVec3::Z), MlhmMode::SolidsAir).unwrap();
    assert_eq!(bed.material, MlhmMaterial::Bedrock);
    assert!(near(bed.hit.position.z, 1.0));
    // Secondary rays from a hit, off it by the surface offset, do not find it again: a
    // reflection off the water goes up into the sky, a refraction down to the bed.
    let offset = tracer.surface_offset();
    assert_eq!(offset, 0.03);
    let (p, n) = (water.hit.position, water.hit.normal);
    let slant = DVec3::new(0.3, 0.0, 1.0).normalize();
    assert!(tracer
        .intersect_mode(&Ray::new(p + offset * n, slant), MlhmMode::SolidsWater)
        .is_none());
    let refracted = Ray::new(p - offset * n, DVec3::new(0.3, 0.0, -1.0).normalize());
    let floor = tracer.intersect_mode(&refracted, MlhmMode::SolidsAir).unwrap();
    assert_eq!(floor.material, MlhmMaterial::Bedrock);
    // The media as the smooth surfaces see them.
    let medium = |z: f64| tracer.medium(DVec3::new(4.0, 8.0, z));
    assert_eq!(medium(0.0), Medium::Solid);
    let Medium::Water { depth } = medium(3.0) else { panic!("{:?}", medium(3.0)) };
    assert!(near(depth, 2.0), "{depth}");
    assert_eq!(medium(7.0), Medium::Air);
    assert_eq!(tracer.medium(DVec3::new(-1.0, 8.0, 3.0)), Medium::Air);
}
