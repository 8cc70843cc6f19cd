#!/usr/bin/env python3
"""Times `relief shade` per layer on SRTM-size tiles (1201^2 and 3601^2, the seeded fBm terrain
written as .hgt), beside `gdaldem hillshade` (Debian's gdal-bin) on the same DEM, and prints
the Markdown table of docs/gis.md.

Run after `cargo build --release`, on an otherwise idle machine:
    python3 bench/shade_maps.py [--relief target/release/relief] [--dir /tmp/relief-shade-bench]
"""
import argparse
import json
import os
import shutil
import subprocess
import tempfile
import time

RUNS = [
    ("shadow, 1 sun", ["--layers", "shadow"]),
    ("shadow, 1 sun of 0.27°, 16 rays", ["--layers", "shadow", "--sun-radius", "0.27", "--sun-rays", "16"]),
    ("hillshade", ["--layers", "hillshade"]),
    ("sky, 16 directions", ["--layers", "sky", "--azimuths", "16"]),
    ("sky, 64 directions", ["--layers", "sky", "--azimuths", "64"]),
    ("combined (1 sun, horizons in 32 directions)", ["--layers", "combined"]),
]


def timed(command):
    start = time.perf_counter()
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - start


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--relief", default="target/release/relief")
    parser.add_argument("--dir", default=None)
    args = parser.parse_args()
    work = args.dir or tempfile.mkdtemp(prefix="relief-shade-bench-")
    os.makedirs(work, exist_ok=True)
    print("| DEM | layer | whole run s | tracing s | rays | Mrays/s |")
    print("|---|---|---|---|---|---|")
    for side in (1201, 3601):
        dem = os.path.join(work, f"N36W085-{side}.hgt")
        # relief names an .hgt tile by its south-west corner: write it under the tile's name.
        tile = os.path.join(work, "N36W085.hgt")
        subprocess.run([args.relief, "generate", "fbm", "--size", str(side), "-o", tile],
                       check=True, stderr=subprocess.DEVNULL)
        shutil.move(tile, dem)
        link = os.path.join(work, "N36W085.hgt")
        shutil.copy(dem, link)
        for name, options in RUNS:
            out = os.path.join(work, "shade.tif")
            stats = os.path.join(work, "stats.json")
            seconds = timed([args.relief, "shade", link, "-o", out, "--stats", stats] + options)
            s = json.load(open(stats))
            print(f"| {side}² | {name} | {seconds:.2f} | {s['trace_ms'] / 1e3:.2f} | "
                  f"{s['rays']:,} | {s['rays_per_s'] / 1e6:.1f} |")
        if shutil.which("gdaldem"):
            out = os.path.join(work, "gdaldem.tif")
            seconds = timed(["gdaldem", "hillshade", link, out, "-s", "111120"])
            print(f"| {side}² | gdaldem hillshade (local slope, no shadows) | {seconds:.2f} | | | |")


if __name__ == "__main__":
    main()
