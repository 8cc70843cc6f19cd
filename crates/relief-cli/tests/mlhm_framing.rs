//! The default framings of every generated MLHM scene kind show the whole block of terrain:
//! the solid ends a little below the lowest terrain (its base), so the three-quarter view and
//! a view from the side at 1 degree show every surface, base included, with sky all around
//! (the image's border rows and columns all miss), not a pillar cut off by the image's edge,
//! in box and in smooth mode.

mod common;

use common::{relief, render_depth, scratch};
use std::path::PathBuf;

/// Every scene `relief generate mlhm` makes.
const KINDS: [&str; 6] = ["rivers-rain", "arches", "cave", "chasm", "overhangs", "combined"];

/// The scene `kind` at 32 x 32 cells, as `.mlhm`.
fn generated(kind: &str) -> PathBuf {
    let path = scratch(&format!("framing-{kind}.mlhm"));
    let out = relief(
        &["generate", "mlhm", "--scene", kind, "--size", "32", "-o"]
            .into_iter()
            .chain([path.to_str().unwrap()])
            .collect::<Vec<_>>(),
    );
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    path
}

/// Asserts that the depth image (`width` x `height`) has hits, and misses on its whole
/// border: the block is entirely inside the picture.
fn assert_framed(name: &str, depth: &[f32], width: usize, height: usize) {
    assert_eq!(depth.len(), width * height);
    let hits = depth.iter().filter(|d| d.is_finite()).count();
    assert!(hits > width * height / 20, "{name}: only {hits} pixels hit");
    for j in 0..height {
        for i in 0..width {
            if i == 0 || j == 0 || i + 1 == width || j + 1 == height {
                let d = depth[i + j * width];
                assert!(d.is_infinite(), "{name}: border pixel ({i}, {j}) hits at {d}");
            }
        }
    }
}

#[test]
fn every_scene_kind_is_framed_whole_from_the_default_view_and_from_the_side() {
    for kind in KINDS {
        let scene = generated(kind);
        let scene = scene.to_str().unwrap();
        let (w, h) = (64, 36);
        // The smooth surface ends at the same base as the boxes (a pillar reaching down
        // forever would hit the bottom rows).
        for mode in ["boxes", "smooth"] {
            for (view, extra) in [
                ("default", vec![]),
                ("side", vec!["--view", "0,1", "--ortho"]),
                ("map", vec!["--view", "0,90", "--ortho"]),
            ] {
                let name = format!("framing-{kind}-{mode}-{view}");
                let mut args = vec![scene, "--size", "64x36", "--preset", "low", "--mode", mode];
                args.extend(extra);
                let (shape, depth, _) = render_depth(&name, &args);
                assert_eq!(shape, vec![h, w]);
                assert_framed(&name, &depth, w, h);
            }
        }
    }
}
