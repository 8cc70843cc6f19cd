//! What a stacks mesh keeps of its terrain at the defaults: the solid's and the water's
//! volume at the finest level and at a camera's levels, every piece of the finest mesh present
//! at the camera's levels, the footprint at every level, thin sand covers in the colours.

use proptest::prelude::*;
use relief_core::{Camera, DVec2, DVec3, MaterialStacks, StackLayer, StackMaterial, StacksMipmap};
use relief_mesh::{StacksMeshParams, StacksMesher, TerrainMesh};

/// Rolling ground under a sand cover `sand` m thick, ponds in its lows, and a broad rock
/// shelf 3 m thick overhanging an air gap (cells of 1 m): the scenes of issue 41.
fn shelf_scene(size: usize, seed: u64, sand: f32) -> MaterialStacks {
    let phase = [seed as f64 * 0.7, seed as f64 * 1.3, seed as f64 * 2.1];
    let pond_level = 3.0 + 0.3 * (seed as f64).sin();
    let (cx, cy, r) = (size as f64 * 0.5, size as f64 * 0.45, size as f64 * 0.25);
    let mut stacks = Vec::new();
    for y in 0..size {
        for x in 0..size {
            let (xf, yf) = (x as f64, y as f64);
            let ground = 3.0
                + 1.5 * (xf / 9.0 + phase[0]).sin() * (yf / 13.0 + phase[1]).cos()
                + 0.8 * ((xf + yf) / 5.0 + phase[2]).sin();
            let top = ground + sand as f64;
            let mut layers = vec![
                StackLayer::new(0.0, ground as f32, StackMaterial::BEDROCK),
                StackLayer::new(ground as f32, top as f32, StackMaterial::SAND),
            ];
            if top < pond_level {
                layers.push(StackLayer::new(top as f32, pond_level as f32, StackMaterial::WATER));
            }
            if (xf - cx).abs() < r && (yf - cy).abs() < 0.6 * r {
                let start = (top.max(pond_level)).max(8.0) as f32 + 2.0;
                layers.push(StackLayer::new(start, start + 3.0, StackMaterial::BEDROCK));
            }
            stacks.push(layers);
        }
    }
    MaterialStacks::from_stacks(
        size,
        size,
        DVec2::ONE,
        DVec2::ZERO,
        StackMaterial::defaults(),
        &stacks,
    )
    .unwrap()
}

fn volumes(mesh: &TerrainMesh) -> (f64, f64) {
    let v = |name: &str| mesh.part(name).unwrap().enclosed_volume();
    (v("solid"), v("water"))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(8))]

    /// At the defaults, the targets: the solid within 2 % of the stacks' at the
    /// finest level and within 4 % at the levels of a camera far from the scene, the water
    /// within 5 % at both (measured over 200 of these 96 x 96 scenes of shallow ponds: the
    /// water -3.1 % to +4.0 % and -4.0 % to +2.6 %, the solid -1.1 % to -1.0 % and -1.7 % to
    /// -1.1 %); no piece of the finest mesh missing at the camera's levels (slivers of less
    /// than a hundredth of a cubic cell, which the finest mesh makes at the domain's sides,
    /// left out); the footprint the domain's at both.
    #[test]
    fn meshes_keep_the_volume_and_the_pieces_of_their_terrain(
        seed in 0u64..1000,
        sand in 0.3f32..0.5,
        eye_x in -40.0f64..40.0,
    ) {
        let stacks = shelf_scene(96, seed, sand);
        let solid = stacks.volume(|m| !m.is_liquid());
        let water = stacks.volume(|m| m.is_liquid());
        let mut mesher =
            StacksMesher::new(StacksMipmap::new(stacks).unwrap(), StacksMeshParams::default())
                .unwrap();
        let (fine, _) = mesher.mesh_level(0).unwrap();
        let camera = Camera::look_at(
            DVec3::new(eye_x, -120.0, 70.0),
            DVec3::new(48.0, 48.0, 0.0),
            DVec3::Z,
            45.0,
            1280,
            720,
        )
        .unwrap();
        let (coarse, stats) = mesher.mesh_for_camera(&camera, 10.0);
        prop_assert!(stats.per_level.iter().filter(|&&n| n > 0).count() >= 2);
        for (mesh, solid_bound, water_bound, label) in
            [(&fine, 0.02, 0.05, "finest"), (&coarse, 0.04, 0.05, "camera")]
        {
            let (mesh_solid, mesh_water) = volumes(mesh);
            prop_assert!((mesh_solid / solid - 1.0).abs() < solid_bound,
                "{label}: solid {mesh_solid:.1} of {solid:.1} m3");
            prop_assert!((mesh_water / water - 1.0).abs() < water_bound,
                "{label}: water {mesh_water:.1} of {water:.1} m3");
            let part = mesh.part("solid").unwrap();
            let (lo, hi) = part.positions.iter().fold(
                (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
                |(lo, hi), p| (lo.min(*p), hi.max(*p)),
            );
            prop_assert!(lo.x == 0.0 && lo.y == 0.0 && hi.x == 96.0 && hi.y == 96.0,
                "{label}: footprint {lo} to {hi}");
        }
        let coarsest = stats.per_level.iter().rposition(|&n| n > 0).unwrap();
        let margin = (1u64 << coarsest) as f64;
        for name in ["solid", "water"] {
            let drawn = coarse.part(name).unwrap().components();
            for piece in fine.part(name).unwrap().components().into_iter().filter(|p| p.volume.abs() >= 0.01) {
                prop_assert!(drawn.iter().any(|d| d.overlaps(&piece, margin)),
                    "{name}: the piece {:?} of the finest mesh is missing at the camera's levels",
                    piece);
            }
        }
    }
}

#[test]
fn a_thin_sand_cover_shows_as_sand() {
    let stacks = shelf_scene(48, 3, 0.15);
    let sand = srgb_to_linear(stacks.materials()[StackMaterial::SAND as usize].color);
    let rock = srgb_to_linear(stacks.materials()[StackMaterial::BEDROCK as usize].color);
    let mesher =
        StacksMesher::new(StacksMipmap::new(stacks).unwrap(), StacksMeshParams::default()).unwrap();
    let (mesh, _) = mesher.mesh_level(0).unwrap();
    let solid = mesh.part("solid").unwrap();
    let (mut tops, mut sandy) = (0, 0);
    for ((p, n), c) in solid.positions.iter().zip(&solid.normals).zip(&solid.colors) {
        // The ground's top, away from the sides and from under the shelf.
        let open = (4.0..44.0).contains(&p.x) && (4.0..44.0).contains(&p.y) && p.z < 7.0;
        if open && n[2] > 0.9 {
            tops += 1;
            let distance = |m: [f32; 3]| (0..3).map(|k| (c[k] - m[k]).powi(2)).sum::<f32>();
            if distance(sand) < distance(rock) {
                sandy += 1;
            }
        }
    }
    assert!(tops > 500, "{tops} top vertices");
    assert!(sandy as f64 > 0.95 * tops as f64, "{sandy} of {tops} top vertices look like sand");
}

fn srgb_to_linear(c: [u8; 3]) -> [f32; 3] {
    c.map(|v| {
        let v = v as f32 / 255.0;
        if v <= 0.04045 {
            v / 12.92
        } else {
            ((v + 0.055) / 1.055).powf(2.4)
        }
    })
}
