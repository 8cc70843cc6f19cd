//! End-to-end tests of `relief generate stacks`: a small terrain is written as a `.stacks`
//! file that reads back to the library's terrain, with overhangs; bad input is refused.

mod common;

use common::{assert_refused, relief, scratch};
use relief_io::read_stacks;
use relief_sim::{stacks_terrain, StacksTerrainParams};

#[test]
fn a_small_terrain_reads_back_with_overhangs() {
    let path = scratch("small.stacks");
    let out = relief(&[
        "generate",
        "stacks",
        "--width",
        "64",
        "--height",
        "32",
        "--seed",
        "3",
        "-o",
        path.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains("wrote") && stderr.contains("stacks with overhangs"), "{stderr}");
    let stacks = read_stacks(&path).unwrap();
    assert_eq!((stacks.width(), stacks.height()), (64, 32));
    assert_eq!(stacks.spacing().x, 2.0);
    assert_eq!(stacks, stacks_terrain(64, 32, 3, &StacksTerrainParams::default()).unwrap());
    let water = relief_core::StackMaterial::WATER;
    let overhangs = (0..64 * 32)
        .filter(|i| {
            let layers = stacks.stack(i % 64, i / 64);
            layers.windows(2).any(|p| p[1].start > p[0].end && p[1].material != water)
        })
        .count();
    assert!(overhangs > 0, "no stack has rock above air");
}

#[test]
fn options_reach_the_terrain() {
    let path = scratch("options.stacks");
    let out = relief(&[
        "generate",
        "stacks",
        "--width",
        "40",
        "--height",
        "24",
        "--spacing",
        "1.5",
        "--max-height",
        "300",
        "-o",
        path.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let params =
        StacksTerrainParams { spacing: 1.5, max_height: 300.0, ..StacksTerrainParams::default() };
    assert_eq!(read_stacks(&path).unwrap(), stacks_terrain(40, 24, 1, &params).unwrap());
}

#[test]
fn bad_input_is_refused_with_exit_code_2_and_writes_nothing() {
    let cases: [(&[&str], &str, &str); 6] = [
        (&["--width", "16", "--height", "16"], "terrain.npy", ".stacks file"),
        (&["--width", "16", "--height", "16"], "terrain", ".stacks file"),
        (&["--width", "0", "--height", "16"], "a.stacks", "between 1 and 65536"),
        (&["--width", "16", "--height", "70000"], "b.stacks", "between 1 and 65536"),
        (&["--width", "16", "--height", "16", "--spacing", "0"], "c.stacks", "positive length"),
        (
            &["--width", "4096", "--height", "4096", "--max-memory", "1M"],
            "d.stacks",
            "memory limit",
        ),
    ];
    for (args, name, mentions) in cases {
        let path = scratch(name);
        let mut all = vec!["generate", "stacks", "-o", path.to_str().unwrap()];
        all.extend(args);
        assert_refused(&relief(&all), mentions);
        assert!(!path.exists(), "{name} written");
    }
}
