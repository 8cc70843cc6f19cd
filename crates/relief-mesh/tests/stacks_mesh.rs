//! Stacks meshes: closed and edge-manifold at one level and across levels, vertices on the
//! smoothed density's iso-surface, the enclosed volume against the stacks' solid volume.

use proptest::prelude::*;
use relief_core::{Camera, DVec2, DVec3, MaterialStacks, StackLayer, StackMaterial, StacksMipmap};
use relief_mesh::{MeshPart, Smoothing, StacksMeshParams, StacksMesher};
use std::collections::HashMap;

/// Random stacks with overhangs: ground, sometimes sand on it, sometimes a rock layer above
/// an air gap, sometimes water.
fn random_stacks(w: usize, h: usize, seed: u64) -> MaterialStacks {
    let mut state = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    let mut next = move || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((state >> 33) as f64) / (1u64 << 31) as f64
    };
    let mut stacks = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let ground =
                2.0 + 3.0 * ((x as f64 * 0.7).sin() + (y as f64 * 0.5).cos()).abs() + 2.0 * next();
            let mut layers = vec![StackLayer::new(0.0, ground as f32, 0)];
            let mut top = ground;
            if next() < 0.4 {
                let sand = top + 0.5 + next();
                layers.push(StackLayer::new(top as f32, sand as f32, 1));
                top = sand;
            }
            if next() < 0.3 {
                let water = top + 0.5 + next() * 1.5;
                layers.push(StackLayer::new(top as f32, water as f32, 2));
                top = water;
            }
            if next() < 0.35 {
                let start = top + 1.0 + 2.0 * next();
                let end = start + 0.8 + 2.0 * next();
                layers.push(StackLayer::new(start as f32, end as f32, 0));
            }
            stacks.push(layers);
        }
    }
    MaterialStacks::from_stacks(w, h, DVec2::ONE, DVec2::ZERO, StackMaterial::defaults(), &stacks)
        .unwrap()
}

/// Every edge of the triangulated part used by exactly two faces, once in each direction:
/// closed, edge-manifold and consistently oriented. Returns the offending edge if not.
fn closed_and_manifold(part: &MeshPart) -> Result<(), String> {
    let mut directed: HashMap<(u32, u32), usize> = HashMap::new();
    for t in part.triangulated() {
        for k in 0..3 {
            *directed.entry((t[k], t[(k + 1) % 3])).or_default() += 1;
        }
    }
    for (&(a, b), &count) in &directed {
        let back = directed.get(&(b, a)).copied().unwrap_or(0);
        if count != 1 || back != 1 {
            return Err(format!(
                "edge {a}-{b} ({:?} to {:?}) used {count} times forward and {back} back",
                part.positions[a as usize], part.positions[b as usize]
            ));
        }
    }
    Ok(())
}

/// The volume a closed, outward-wound part encloses (divergence theorem).
fn enclosed_volume(part: &MeshPart) -> f64 {
    part.triangulated()
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| part.positions[v as usize]);
            a.dot(b.cross(c)) / 6.0
        })
        .sum()
}

#[test]
fn a_slab_meshes_closed_with_its_volume() {
    let stacks = MaterialStacks::from_stacks(
        40,
        30,
        DVec2::ONE,
        DVec2::ZERO,
        StackMaterial::defaults(),
        &vec![vec![StackLayer::new(0.0, 8.0, 0)]; 1200],
    )
    .unwrap();
    let mesher = StacksMesher::new(
        StacksMipmap::new(stacks).unwrap(),
        StacksMeshParams { node_cells: 4, ..Default::default() },
    )
    .unwrap();
    let (mesh, _) = mesher.mesh_level(0).unwrap();
    let solid = mesh.part("solid").unwrap();
    closed_and_manifold(solid).unwrap();
    let volume = enclosed_volume(solid);
    // The smoothing and the dual vertices round the slab's edges off: about a cell's
    // chamfer along each of them.
    assert!((volume - 9600.0).abs() < 0.05 * 9600.0, "volume {volume}");
    // The Sobel normals of the flat top point up, those of the walls sideways.
    let (mut top, mut wall) = (0, 0);
    for (p, n) in solid.positions.iter().zip(&solid.normals) {
        if p.z > 7.99 && (3.0..37.0).contains(&p.x) && (3.0..27.0).contains(&p.y) {
            assert!(n[2] > 0.999, "normal {n:?} at {p}");
            top += 1;
        }
        if p.x < 0.01 && (3.0..5.0).contains(&p.z) && (3.0..27.0).contains(&p.y) {
            assert!(n[0] < -0.999, "normal {n:?} at {p}");
            wall += 1;
        }
    }
    assert!(top > 500 && wall > 20, "{top} top and {wall} wall vertices checked");
    assert!(mesh.part("water").unwrap().is_empty());
}

#[test]
fn random_terrains_with_overhangs_mesh_closed_at_the_finest_level() {
    for seed in 0..6 {
        let stacks = random_stacks(14, 11, seed);
        let solid_volume = stacks.volume(|m| !m.is_liquid());
        let mesher = StacksMesher::new(
            StacksMipmap::new(stacks).unwrap(),
            StacksMeshParams { node_cells: 5, ..Default::default() },
        )
        .unwrap();
        let (mesh, _) = mesher.mesh_level(0).unwrap();
        for part in &mesh.parts {
            closed_and_manifold(part)
                .map_err(|e| format!("seed {seed}, {}: {e}", part.name))
                .unwrap();
        }
        let volume = enclosed_volume(mesh.part("solid").unwrap());
        println!("seed {seed}: mesh {volume:.1} m3, stacks {solid_volume:.1} m3");
    }
}

#[test]
fn meshes_for_a_camera_join_across_levels_without_cracks() {
    for seed in 0..8 {
        let stacks = random_stacks(40, 33, seed);
        let mut mesher = StacksMesher::new(
            StacksMipmap::new(stacks).unwrap(),
            StacksMeshParams { node_cells: 4, ..Default::default() },
        )
        .unwrap();
        let eye = DVec3::new(-3.0 + seed as f64, 2.0, 9.0);
        let camera =
            Camera::look_at(eye, DVec3::new(30.0, 25.0, 0.0), DVec3::Z, 60.0, 160, 120).unwrap();
        let (mesh, stats) = mesher.mesh_for_camera(&camera, 20.0);
        let levels = stats.per_level.iter().filter(|&&n| n > 0).count();
        println!(
            "seed {seed}: nodes per level {:?}, {} faces",
            &stats.per_level[..5],
            mesh.face_count()
        );
        assert!(levels >= 3, "seed {seed}: fewer than three levels: {:?}", stats.per_level);
        for part in &mesh.parts {
            closed_and_manifold(part)
                .map_err(|e| format!("seed {seed}, {}: {e}", part.name))
                .unwrap();
        }
    }
}

/// A 64 x 64 terrain of rolling ground with a rock bridge over an air gap, a sand bank and a
/// pond: features several cells thick.
fn bridge_terrain() -> MaterialStacks {
    let mut stacks = Vec::new();
    for y in 0..64 {
        for x in 0..64 {
            let (xf, yf) = (x as f32, y as f32);
            let ground = 10.0 + 3.0 * (xf / 9.0).sin() * (yf / 11.0).cos();
            let mut layers = vec![StackLayer::new(0.0, ground, 0)];
            let mut top = ground;
            if x > 40 {
                layers.push(StackLayer::new(top, top + 2.5, 1));
                top += 2.5;
            }
            if (8..24).contains(&x) && (40..56).contains(&y) {
                layers.push(StackLayer::new(top, top + 3.0, 2));
                top += 3.0;
            }
            if (20..44).contains(&x) && (10..50).contains(&y) {
                let start = top.max(ground) + 5.0;
                layers.push(StackLayer::new(start.max(19.0), 24.0, 0));
            }
            stacks.push(layers);
        }
    }
    MaterialStacks::from_stacks(64, 64, DVec2::ONE, DVec2::ZERO, StackMaterial::defaults(), &stacks)
        .unwrap()
}

#[test]
fn the_finest_mesh_encloses_the_stacks_volume_within_a_few_percent() {
    let stacks = bridge_terrain();
    let solid = stacks.volume(|m| !m.is_liquid());
    let water = stacks.volume(|m| m.is_liquid());
    let mesher =
        StacksMesher::new(StacksMipmap::new(stacks).unwrap(), StacksMeshParams::default()).unwrap();
    let (mesh, _) = mesher.mesh_level(0).unwrap();
    for part in &mesh.parts {
        closed_and_manifold(part).unwrap();
    }
    let mesh_solid = enclosed_volume(mesh.part("solid").unwrap());
    let mesh_water = enclosed_volume(mesh.part("water").unwrap());
    println!(
        "solid {mesh_solid:.3} of {solid:.3} m3 ({:+.4} %), water {mesh_water:.3} of {water:.3} m3 \
         ({:+.4} %)",
        100.0 * (mesh_solid / solid - 1.0),
        100.0 * (mesh_water / water - 1.0)
    );
    // Measured: solid 49026.848 of 49335.988 m3, 0.63 % short (the Gaussian's rounding of the
    // edges the filter may round; it carves out no point inside). It was 1.91 % short with
    // the voxel-coverage density.
    assert!((mesh_solid - solid).abs() < 0.02 * solid, "solid {mesh_solid} against {solid}");
    // Measured: water 688.927 of 768 m3, 10.3 % short (18.6 % with the voxel-coverage
    // density). The pond is a box 3 m deep with vertical walls: the filter (sigma one cell)
    // rounds its 64 m rim (4.0 % of the water of the reference scene, 2 % of the ponds of
    // docs/stacks.md's scenes, whose shores slope).
    assert!((mesh_water - water).abs() < 0.12 * water, "water {mesh_water} against {water}");
}

#[test]
fn a_camera_mesh_encloses_about_the_finest_mesh_volume() {
    let stacks = bridge_terrain();
    let solid = stacks.volume(|m| !m.is_liquid());
    let mut mesher = StacksMesher::new(
        StacksMipmap::new(stacks).unwrap(),
        StacksMeshParams { node_cells: 8, ..Default::default() },
    )
    .unwrap();
    let camera = Camera::look_at(
        DVec3::new(-10.0, -10.0, 30.0),
        DVec3::new(32.0, 32.0, 10.0),
        DVec3::Z,
        50.0,
        320,
        240,
    )
    .unwrap();
    let (mesh, stats) = mesher.mesh_for_camera(&camera, 8.0);
    assert!(stats.per_level.iter().filter(|&&n| n > 0).count() >= 2, "{:?}", stats.per_level);
    closed_and_manifold(mesh.part("solid").unwrap()).unwrap();
    let volume = enclosed_volume(mesh.part("solid").unwrap());
    println!(
        "camera mesh {volume:.3} of {solid:.3} m3 ({:+.4} %), nodes {:?}",
        100.0 * (volume / solid - 1.0),
        &stats.per_level[..4]
    );
    // Measured: 48937.835 of 49335.988 m3, 0.81 % short (5.49 % with the voxel-coverage
    // density, whose smoothing doubled in metres at every level).
    assert!((volume - solid).abs() < 0.02 * solid, "{volume} against {solid}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Random terrains, cameras anywhere (inside the terrain's box, outside the domain,
    /// looking up), any tau and either filter: the camera's mesh is closed and edge-manifold.
    #[test]
    fn camera_meshes_of_random_terrains_are_closed(
        seed in 0u64..10_000,
        eye in (-15.0f64..55.0, -15.0f64..45.0, 1.0f64..30.0),
        target in (0.0f64..40.0, 0.0f64..33.0, -5.0f64..20.0),
        tau in 2.0f64..40.0,
        box_filter in any::<bool>(),
    ) {
        let eye = DVec3::new(eye.0, eye.1, eye.2);
        let target = DVec3::new(target.0, target.1, target.2);
        prop_assume!(eye.distance(target) > 1.0);
        let smoothing =
            if box_filter { Smoothing::Box { radius: 1 } } else { Smoothing::Gaussian { sigma: 1.0 } };
        let mut mesher = StacksMesher::new(
            StacksMipmap::new(random_stacks(40, 33, seed)).unwrap(),
            StacksMeshParams { node_cells: 4, smoothing, ..Default::default() },
        )
        .unwrap();
        let camera = Camera::look_at(eye, target, DVec3::Z, 60.0, 160, 120);
        prop_assume!(camera.is_ok(), "a view along the up vector");
        let (mesh, _) = mesher.mesh_for_camera(&camera.unwrap(), tau);
        for part in &mesh.parts {
            if let Err(e) = closed_and_manifold(part) {
                return Err(TestCaseError::fail(format!("{}: {e}", part.name)));
            }
        }
    }
}

/// A random multi-layered height map with overhangs: per cell one to three columns of bedrock,
/// sand and water under air gaps.
fn random_mlhm(w: usize, h: usize, seed: u64) -> relief_core::Mlhm {
    use relief_core::{Mlhm, MlhmColumn};
    let mut state = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut map = Mlhm::new(w, h, 3, 1.0).unwrap();
    for y in 0..h {
        for x in 0..w {
            let ground = 3.0 + 2.0 * ((x as f64 / 4.0).sin() + (y as f64 / 5.0).cos()) + next();
            let mut columns = Vec::new();
            let layers = 1 + (next() * 3.0) as usize;
            let mut bedrock = ground;
            for k in 0..layers.min(3) {
                let sand = if next() < 0.5 { next() * 1.5 } else { 0.0 };
                let water = if next() < 0.3 { next() * 2.0 } else { 0.0 };
                let top = k + 1 == layers.min(3);
                let ceiling =
                    if top { f64::INFINITY } else { bedrock + sand + water + 1.0 + 2.0 * next() };
                columns.push(MlhmColumn::new(
                    bedrock as f32,
                    sand as f32,
                    water as f32,
                    ceiling as f32,
                ));
                bedrock = ceiling + 1.0 + 2.0 * next();
            }
            map.set_cell(x, y, &columns).unwrap();
        }
    }
    map
}

#[test]
fn random_mlhms_with_overhangs_mesh_closed_at_one_level_and_across_levels() {
    for seed in 0..4 {
        let stacks = MaterialStacks::from_mlhm(&random_mlhm(36, 30, seed)).unwrap();
        let mut mesher = StacksMesher::new(
            StacksMipmap::new(stacks).unwrap(),
            StacksMeshParams { node_cells: 4, ..Default::default() },
        )
        .unwrap();
        let (mesh, _) = mesher.mesh_level(0).unwrap();
        for part in &mesh.parts {
            closed_and_manifold(part)
                .map_err(|e| format!("seed {seed}, {}: {e}", part.name))
                .unwrap();
        }
        let camera = Camera::look_at(
            DVec3::new(-4.0, -3.0, 14.0),
            DVec3::new(25.0, 20.0, 2.0),
            DVec3::Z,
            60.0,
            160,
            120,
        )
        .unwrap();
        let (mesh, stats) = mesher.mesh_for_camera(&camera, 12.0);
        assert!(stats.per_level.iter().filter(|&&n| n > 0).count() >= 2, "{:?}", stats.per_level);
        for part in &mesh.parts {
            closed_and_manifold(part)
                .map_err(|e| format!("seed {seed}, {}: {e}", part.name))
                .unwrap();
        }
    }
}

#[test]
fn meshes_are_the_same_whatever_the_thread_count() {
    let mesh = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let mut mesher = StacksMesher::new(
                StacksMipmap::new(random_stacks(40, 33, 7)).unwrap(),
                StacksMeshParams { node_cells: 4, ..Default::default() },
            )
            .unwrap();
            let camera = Camera::look_at(
                DVec3::new(-3.0, 2.0, 9.0),
                DVec3::new(30.0, 25.0, 0.0),
                DVec3::Z,
                60.0,
                160,
                120,
            )
            .unwrap();
            (mesher.mesh_level(0).unwrap().0, mesher.mesh_for_camera(&camera, 20.0).0)
        })
    };
    assert_eq!(mesh(1), mesh(3));
}
