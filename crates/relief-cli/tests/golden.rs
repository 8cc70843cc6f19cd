//! A small golden image of the default pipeline, compared with a tolerance.
//!
//! Regenerate after an intended change of the picture with:
//! `RELIEF_BLESS=1 cargo test -p relief-cli --test golden`

use std::path::Path;
use std::process::Command;

const GOLDEN: &str = "tests/golden/fbm-96x64.png";

fn decode(path: &Path) -> (u32, u32, Vec<u8>) {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    buf.truncate(info.buffer_size());
    (info.width, info.height, buf)
}

#[test]
fn default_pipeline_matches_the_golden_image() {
    let out_path = std::env::temp_dir().join(format!("relief-golden-{}.png", std::process::id()));
    let out = Command::new(env!("CARGO_BIN_EXE_relief"))
        .args(["render", "--fbm-size", "64", "--seed", "7", "--size", "96x64", "-o"])
        .arg(&out_path)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let golden = Path::new(env!("CARGO_MANIFEST_DIR")).join(GOLDEN);
    if std::env::var_os("RELIEF_BLESS").is_some() {
        std::fs::copy(&out_path, &golden).unwrap();
        eprintln!("blessed {}", golden.display());
        return;
    }
    let (w, h, got) = decode(&out_path);
    let (gw, gh, want) = decode(&golden);
    assert_eq!((w, h), (gw, gh));
    let diffs: Vec<u32> = got.iter().zip(&want).map(|(a, b)| a.abs_diff(*b) as u32).collect();
    let mean = diffs.iter().sum::<u32>() as f64 / diffs.len() as f64;
    let max = diffs.iter().copied().max().unwrap_or(0);
    assert!(
        mean <= 0.5 && max <= 16,
        "image differs from {GOLDEN}: mean {mean:.2}, max {max} levels (RELIEF_BLESS=1 to regenerate)"
    );
}
