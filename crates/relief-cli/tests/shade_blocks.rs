//! `relief shade` of rasters larger than `--max-memory` and of tile stores, block by block: the
//! cloud-optimised GeoTIFF it writes equals the in-memory result bit for bit for every layer,
//! seams and corners included, within the budget (peak memory measured); a killed run leaves
//! no file under the output's name and the same command resumes it; incomplete and corrupt
//! stores are refused with the tile named. Read back with GDAL through rasterio.

mod common;

use common::{clients, python, relief, scratch};
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn main() {
    clients::run(vec![
        clients::trial!(a_raster_over_the_budget_gives_the_in_memory_bits, Rasterio),
        clients::trial!(a_killed_run_leaves_no_output_and_resumes, Rasterio),
        clients::trial!(a_store_is_shaded_and_bad_stores_are_refused, Rasterio),
    ]);
}

/// Every layer, with few directions and an hour's step to keep the test short.
const LAYERS: &[&str] = &[
    "--layers",
    "shadow,sky,hillshade,combined,horizon,sky-aniso,openness-pos,openness-neg,\
     sky-illumination,hillshade-multi,insolation,sun-hours",
    "--azimuths",
    "4",
    "--date",
    "2026-06-21",
    "--step",
    "60m",
];

/// A rough float32 UTM DEM of `side` x `side` samples at 10 m.
fn dem(dir: &Path, side: usize) -> std::path::PathBuf {
    std::fs::create_dir_all(dir).unwrap();
    let path = dir.join("dem.tif");
    let made = python(
        "rasterio",
        &format!(
            r#"import numpy as np, rasterio
from rasterio.transform import from_origin
rng = np.random.default_rng(5)
n = {side}
z = np.zeros((n, n))
for k in range(1, 8):
    f = 2 ** k
    coarse = rng.standard_normal((n // f + 2, n // f + 2)) * 60.0 / k ** 1.6
    z += np.kron(coarse, np.ones((f, f)))[:n, :n]
y, x = np.mgrid[0:n, 0:n]
z += 40 * np.sin(x / 37.0) * np.cos(y / 53.0)
with rasterio.open(r'{}', 'w', driver='GTiff', width=n, height=n, count=1, dtype='float32',
        crs='EPSG:32633', transform=from_origin(500000, 4100000, 10, 10)) as f:
    f.write(z.astype('float32'), 1)
print('made')"#,
            path.display()
        ),
    );
    assert_eq!(made.as_deref(), Some("made"));
    path
}

/// Runs relief with `args`, polling its peak resident memory (VmHWM, kB) until it exits;
/// fails with its error output unless it succeeded. Returns the peak in bytes and its stderr.
fn run_measured(args: &[&str]) -> (u64, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_relief"))
        .args(args)
        .stderr(Stdio::piped())
        .stdout(Stdio::null())
        .spawn()
        .unwrap();
    let status = format!("/proc/{}/status", child.id());
    let mut peak = 0;
    while child.try_wait().unwrap().is_none() {
        if let Ok(text) = std::fs::read_to_string(&status) {
            if let Some(line) = text.lines().find(|l| l.starts_with("VmHWM:")) {
                let kb: u64 = line.split_whitespace().nth(1).unwrap().parse().unwrap();
                peak = peak.max(kb * 1024);
            }
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(out.status.success(), "{args:?}: {stderr}");
    (peak, stderr)
}

/// Runs relief; it must succeed.
fn ok(args: &[&str]) -> String {
    let out = relief(args);
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(out.status.success(), "{args:?}: {stderr}");
    stderr
}

/// Whether two GeoTIFFs hold the same bands bit for bit on the same grid, and what the block
/// by block one is: tiled, with overviews (prints "same tiled overviews").
fn same_bits(a: &Path, b: &Path) {
    let report = python(
        "rasterio",
        &format!(
            r#"import numpy as np, rasterio
a, b = rasterio.open(r'{}'), rasterio.open(r'{}')
assert a.count == b.count and a.shape == b.shape, (a.count, b.count, a.shape, b.shape)
assert a.transform == b.transform and a.crs == b.crs and a.descriptions == b.descriptions
for i in range(1, a.count + 1):
    x, y = a.read(i), b.read(i)
    differ = np.argwhere(x.view(np.uint32) != y.view(np.uint32))
    assert len(differ) == 0, (a.descriptions[i - 1], len(differ), differ[:4].tolist())
tiled = b.profile.get('tiled') and b.block_shapes[0] == (512, 512)
print('same', 'tiled' if tiled else 'striped', 'overviews' if b.overviews(1) else 'none')"#,
            a.display(),
            b.display()
        ),
    );
    assert_eq!(report.as_deref(), Some("same tiled overviews"));
}

fn a_raster_over_the_budget_gives_the_in_memory_bits() {
    let dir = scratch("shade blocks");
    let dem = dem(&dir, 2048);
    let (whole, blocks) = (dir.join("whole.tif"), dir.join("blocks.tif"));
    let (dem, whole_s, blocks_s) =
        (dem.to_str().unwrap(), whole.to_str().unwrap(), blocks.to_str().unwrap());
    let mut args = vec!["shade", dem, "-o", whole_s];
    args.extend(LAYERS);
    ok(&args);
    // 2048^2 samples of 15 bands need about 490 MB in memory; 200 MiB forces blocks of 512.
    let stats = dir.join("stats.json");
    let mut args = vec!["shade", dem, "-o", blocks_s, "--max-memory", "200M"];
    args.extend(["--stats", stats.to_str().unwrap()]);
    args.extend(LAYERS);
    let (peak, stderr) = run_measured(&args);
    let stats = std::fs::read_to_string(&stats).unwrap();
    assert!(stats.contains("\"blocks\": 16"), "{stats}\n{stderr}");
    assert!(peak <= 220 << 20, "peak {} MiB over 200 MiB and 10%", peak >> 20);
    same_bits(&whole, &blocks);
    // The store it tiled into is gone.
    assert!(!dir.join(".blocks.tif.store").exists());
}

fn a_killed_run_leaves_no_output_and_resumes() {
    let dir = scratch("shade killed");
    let dem = dem(&dir, 1536);
    let (whole, blocks) = (dir.join("whole.tif"), dir.join("blocks.tif"));
    let (dem, whole_s, blocks_s) =
        (dem.to_str().unwrap(), whole.to_str().unwrap(), blocks.to_str().unwrap());
    let layers = ["--layers", "shadow,sky,openness-neg", "--azimuths", "8"];
    let mut args = vec!["shade", dem, "-o", whole_s];
    args.extend(layers);
    ok(&args);
    let mut args = vec!["shade", dem, "-o", blocks_s, "--max-memory", "100M"];
    args.extend(layers);
    // Killed once the journal holds a written block (its header line and one more).
    let mut child = Command::new(env!("CARGO_BIN_EXE_relief"))
        .args(&args)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let journal = dir.join(".blocks.tif.cog-journal");
    let start = Instant::now();
    loop {
        let lines = std::fs::read_to_string(&journal).map_or(0, |t| t.lines().count());
        if lines >= 2 || start.elapsed() > Duration::from_secs(300) {
            break;
        }
        if child.try_wait().unwrap().is_some() {
            let out = child.wait_with_output().unwrap();
            panic!("the run ended before it was killed: {}", String::from_utf8_lossy(&out.stderr));
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(!blocks.exists(), "a killed run left {}", blocks.display());
    let stderr = ok(&args);
    assert!(stderr.contains("resuming"), "{stderr}");
    same_bits(&whole, &blocks);
}

fn a_store_is_shaded_and_bad_stores_are_refused() {
    let dir = scratch("shade store");
    let dem = dem(&dir, 700);
    let store = dir.join("dem.store");
    let (whole, blocks) = (dir.join("whole.tif"), dir.join("blocks.tif"));
    let (dem, store_s) = (dem.to_str().unwrap(), store.to_str().unwrap());
    ok(&["tile", dem, "-o", store_s, "--tile", "128"]);
    let layers = ["--layers", "shadow,sky,hillshade", "--azimuths", "8"];
    let mut args = vec!["shade", dem, "-o", whole.to_str().unwrap()];
    args.extend(layers);
    ok(&args);
    let mut args = vec!["shade", store_s, "-o", blocks.to_str().unwrap()];
    args.extend(layers);
    ok(&args);
    same_bits(&whole, &blocks);

    // A corrupt tile is named.
    let data = store.join("tiles.data");
    let mut bytes = std::fs::read(&data).unwrap();
    bytes[4 * 300] ^= 0x55;
    std::fs::write(&data, &bytes).unwrap();
    let out = relief(&["shade", store_s, "-o", dir.join("bad.tif").to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("tile") && stderr.contains("checksum"), "{stderr}");
    assert!(!dir.join("bad.tif").exists());

    // An incomplete one says how far it got.
    let index = store.join("index.json");
    let text = std::fs::read_to_string(&index).unwrap();
    std::fs::write(&index, text.replace("\"complete\": true", "\"complete\": false")).unwrap();
    let out = relief(&["shade", store_s, "-o", dir.join("bad.tif").to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("incomplete") || stderr.contains("not complete"), "{stderr}");
}
