#!/usr/bin/env python3
"""Shade rasters at any scale (docs/scale.md): a generated fBm DEM of SIZE^2 at 10 m shaded
(shadow and sky) out of core with `relief shade STORE --max-memory BUDGET`, against the
in-memory rate on a REF^2 crop of it; then the same through `relief.dask.shade` on a
LocalCluster of 1 and of 2 worker processes (one thread each), against the CLI on one thread.

Reports per run: wall time, samples per second, peak memory (the process's, or the largest
worker's), and the ratios the issue's targets name. Needs the relief binary (cargo build
--release) and module (pip install .); installs dask, distributed, xarray and rioxarray.

    python3 bench/scale.py --size 32768 --ref 8192 --budget 1G     # the issue's benchmark
    python3 bench/scale.py --size 4096 --ref 2048 --budget 200M    # a quick one
"""

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
RELIEF = str(ROOT / "target" / "release" / "relief")


def pip(*packages):
    subprocess.run([sys.executable, "-m", "pip", "install", "--quiet",
                    "--disable-pip-version-check", *packages], check=True)


def run(args, threads=None):
    """Runs relief; returns (seconds, peak resident bytes, stderr)."""
    env = dict(os.environ)
    if threads:
        env["RAYON_NUM_THREADS"] = str(threads)
    start = time.perf_counter()
    child = subprocess.Popen([RELIEF, *args], stderr=subprocess.PIPE, stdout=subprocess.DEVNULL,
                             env=env)
    _, status, usage = os.wait4(child.pid, 0)
    seconds = time.perf_counter() - start
    stderr = child.stderr.read().decode()
    if status != 0:
        sys.exit(f"relief {' '.join(args)} failed:\n{stderr}")
    return seconds, usage.ru_maxrss * 1024, stderr


def generate(size, work):
    """`relief generate fbm` of size^2 as a GeoTIFF at 10 m (UTM 16N), written band by band."""
    import rasterio
    from rasterio.transform import from_origin
    from rasterio.windows import Window

    path = work / f"fbm{size}.tif"
    if path.exists():
        return path
    npy = work / f"fbm{size}.npy"
    subprocess.run([RELIEF, "generate", "fbm", "--size", str(size), "-o", str(npy)], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    heights = np.load(npy, mmap_mode="r")
    transform = from_origin(500000.0, 3600000.0 + size * 10.0, 10.0, 10.0)
    with rasterio.open(path, "w", driver="GTiff", width=size, height=size, count=1,
                       dtype="float32", crs="EPSG:32616", transform=transform, tiled=True,
                       blockxsize=512, blockysize=512) as f:
        for top in range(0, size, 2048):
            rows = min(2048, size - top)
            # .npy row 0 is south; the GeoTIFF's row 0 is north.
            south = size - top - rows
            band = np.ascontiguousarray(heights[south:south + rows][::-1], dtype=np.float32)
            f.write(band, 1, window=Window(0, top, size, rows))
    del heights
    os.remove(npy)
    return path


def crop(dem, size, work):
    """The north-west size^2 of `dem`, as its own GeoTIFF."""
    import rasterio
    from rasterio.windows import Window

    path = work / f"{dem.stem}-crop{size}.tif"
    if path.exists():
        return path
    with rasterio.open(dem) as src:
        profile = src.profile
        profile.update(width=size, height=size, transform=src.window_transform(
            Window(0, 0, size, size)))
        with rasterio.open(path, "w", **profile) as out:
            out.write(src.read(1, window=Window(0, 0, size, size)), 1)
    return path


def dask_run(store, workers, options, out):
    """relief.dask.shade of the store on a LocalCluster of `workers` processes, one thread
    each, written with rioxarray; returns (seconds, largest worker peak bytes)."""
    import dask
    import relief.dask
    from distributed import Client, LocalCluster, Lock

    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True) as cluster, \
            Client(cluster) as client:
        start = time.perf_counter()
        dataset = relief.dask.shade(str(store), chunks=2048, **options)
        dataset.rio.to_raster(out, tiled=True, lock=Lock("scale-bench"), compute=True)
        seconds = time.perf_counter() - start

        def peak():
            import resource
            return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024

        peaks = client.run(peak)
    del dask
    return seconds, max(peaks.values())


def bytes_of(text):
    units = {"K": 1 << 10, "M": 1 << 20, "G": 1 << 30}
    return int(float(text[:-1]) * units[text[-1]]) if text[-1] in units else int(text)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=32768)
    parser.add_argument("--ref", type=int, default=8192, help="side of the in-memory run")
    parser.add_argument("--budget", default="1G")
    parser.add_argument("--azimuths", type=int, default=32)
    parser.add_argument("--work", type=Path, default=Path("/tmp/relief-scale"))
    parser.add_argument("--workers", default="1,2")
    parser.add_argument("--skip-dask", action="store_true")
    args = parser.parse_args()
    pip("rasterio")
    args.work.mkdir(parents=True, exist_ok=True)
    layers = ["--layers", "shadow,sky", "--azimuths", str(args.azimuths)]
    rows = []

    dem = generate(args.size, args.work)
    ref = crop(dem, min(args.ref, args.size), args.work)
    seconds, peak, _ = run(["shade", str(ref), "-o", str(args.work / "ref.tif"), *layers])
    ref_rate = args.ref ** 2 / seconds
    rows.append((f"in memory, {args.ref}^2, 2 threads", seconds, ref_rate, peak))

    store = args.work / f"fbm{args.size}.store"
    tile_s, _, _ = run(["tile", str(dem), "-o", str(store)])
    samples = args.size ** 2
    out = args.work / "ooc.tif"
    seconds, peak, stderr = run(["shade", str(store), "-o", str(out), "--max-memory",
                                 args.budget, "--stats", str(args.work / "ooc.json"), *layers])
    rows.append((f"out of core, {args.size}^2, 2 threads, --max-memory {args.budget}", seconds,
                 samples / seconds, peak))
    ooc_rate = samples / seconds
    one_s, one_peak, _ = run(["shade", str(store), "-o", str(out), "--max-memory", args.budget,
                              *layers], threads=1)
    rows.append((f"out of core, {args.size}^2, 1 thread", one_s, samples / one_s, one_peak))

    dask_rates = {}
    if not args.skip_dask:
        pip("dask[distributed]", "xarray", "rioxarray")
        options = dict(layers=["shadow", "sky"], azimuths=args.azimuths)
        for workers in [int(w) for w in args.workers.split(",")]:
            seconds, peak = dask_run(store, workers, options, args.work / f"dask{workers}.tif")
            dask_rates[workers] = samples / seconds
            rows.append((f"relief.dask.shade, {workers} worker(s) x 1 thread", seconds,
                         samples / seconds, peak))

    print(f"\n{args.size}^2 DEM at 10 m, shadow and sky ({args.azimuths} azimuths); "
          f"relief tile took {tile_s:.1f} s\n")
    print("| run | time (s) | Msamples/s | peak memory (MiB) |")
    print("|---|---|---|---|")
    for name, seconds, rate, peak in rows:
        print(f"| {name} | {seconds:.1f} | {rate / 1e6:.3f} | {peak / 2**20:.0f} |")
    budget = bytes_of(args.budget)
    print("\n| target | measured |")
    print("|---|---|")
    print(f"| peak memory within the budget + 10% | {rows[1][3] / budget:.2f} x the budget |")
    print(f"| out-of-core rate >= 0.7 x in-memory | {ooc_rate / ref_rate:.2f} x |")
    if 1 in dask_rates and 2 in dask_rates:
        print(f"| 2 workers >= 1.7 x 1 worker | {dask_rates[2] / dask_rates[1]:.2f} x |")
    if 1 in dask_rates:
        print(f"| Dask overhead <= 10% over the CLI on one thread | "
              f"{(samples / dask_rates[1]) / one_s - 1:+.0%} |")
    print(json.dumps({"rows": rows}), file=sys.stderr)


if __name__ == "__main__":
    main()
