#!/usr/bin/env python3
"""Times `relief viewshed` beside gdal_viewshed (Debian's gdal-bin) and xarray-spatial's
viewshed on one observer over a 3601^2 DEM at 10 m (the seeded fBm terrain written as a
projected GeoTIFF), reports how far their answers agree with relief's and where they differ,
times a cumulative viewshed of 100 observers with relief, and prints the Markdown tables of
docs/gis.md (section Viewsheds).

Installs its anchors first (apt-get install gdal-bin, pip install xarray-spatial rasterio).
Run after `cargo build --release -p relief-cli`, on an otherwise idle machine:
    python3 bench/viewshed_compare.py [--relief target/release/relief] [--dir /tmp/relief-viewshed]
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

SIDE = 3601
CELL = 10.0
WEST, NORTH = 500000.0, 4100000.0
EYE = 1.7


def install():
    """The anchors: gdal_viewshed from gdal-bin, xarray-spatial (numba comes with it)."""
    if not shutil.which("gdal_viewshed"):
        subprocess.run(["apt-get", "update"], check=True, stdout=subprocess.DEVNULL)
        subprocess.run(["apt-get", "install", "-y", "gdal-bin"], check=True,
                       stdout=subprocess.DEVNULL)
    try:
        import xrspatial  # noqa: F401
        import rasterio  # noqa: F401
    except ImportError:
        subprocess.run([sys.executable, "-m", "pip", "install", "xarray-spatial", "rasterio"],
                       check=True, stdout=subprocess.DEVNULL)


def timed(command):
    start = time.perf_counter()
    done = subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if done.returncode != 0:
        raise SystemExit(f"{' '.join(command)} failed: {done.stderr}")
    return time.perf_counter() - start


def make_dem(relief, work):
    """The fBm terrain as a float32 GeoTIFF, UTM 33N, 10 m cells, north-up."""
    import numpy as np
    import rasterio
    from rasterio.transform import from_origin

    npy = os.path.join(work, "fbm.npy")
    tif = os.path.join(work, "dem.tif")
    subprocess.run([relief, "generate", "fbm", "--size", str(SIDE), "-o", npy], check=True,
                   stderr=subprocess.DEVNULL)
    # A .npy's row 0 is the south edge; a north-up GeoTIFF's row 0 is the north edge.
    heights = np.flipud(np.load(npy)).astype(np.float32)
    with rasterio.open(tif, "w", driver="GTiff", width=SIDE, height=SIDE, count=1,
                       dtype="float32", crs="EPSG:32633",
                       transform=from_origin(WEST, NORTH, CELL, CELL)) as f:
        f.write(heights, 1)
    return tif, heights


def centre(col, row):
    """The CRS coordinates of the centre of the file's cell (col, row)."""
    return WEST + (col + 0.5) * CELL, NORTH - (row + 0.5) * CELL


def read(path):
    import rasterio
    with rasterio.open(path) as f:
        return f.read(1)


def boundary_share(visible, differ):
    """The share of the differing cells that lie next to a change of relief's answer."""
    import numpy as np
    v = visible.astype(bool)
    edge = np.zeros_like(v)
    edge[1:, :] |= v[1:, :] != v[:-1, :]
    edge[:-1, :] |= v[1:, :] != v[:-1, :]
    edge[:, 1:] |= v[:, 1:] != v[:, :-1]
    edge[:, :-1] |= v[:, 1:] != v[:, :-1]
    return (differ & edge).sum() / max(differ.sum(), 1)


def main():
    import numpy as np

    parser = argparse.ArgumentParser()
    parser.add_argument("--relief", default="target/release/relief")
    parser.add_argument("--dir", default=None)
    parser.add_argument("--observers", type=int, default=100)
    args = parser.parse_args()
    install()
    import xarray as xr
    from xrspatial import viewshed as xrs_viewshed

    work = args.dir or tempfile.mkdtemp(prefix="relief-viewshed-")
    os.makedirs(work, exist_ok=True)
    dem, heights = make_dem(args.relief, work)
    col = row = SIDE // 2
    x, y = centre(col, row)
    rows = []

    out = os.path.join(work, "relief.tif")
    stats = os.path.join(work, "stats.json")
    seconds = timed([args.relief, "viewshed", dem, "-o", out, "--stats", stats,
                     "--observer", f"{x},{y},{EYE}"])
    trace = json.load(open(stats))["trace_ms"] / 1e3
    ours = read(out)
    rows.append(("relief viewshed (exact, triangles)", seconds, trace, ours))

    gdal_out = os.path.join(work, "gdal.tif")
    # -cc 0: no earth curvature, as relief; visible 1, invisible 0, out of range 0.
    command = ["gdal_viewshed", "-ox", str(x), "-oy", str(y), "-oz", str(EYE), "-tz", "0",
               "-cc", "0", "-vv", "1", "-iv", "0", "-ov", "0", dem, gdal_out]
    seconds = timed(command)
    rows.append(("gdal_viewshed -cc 0", seconds, None, read(gdal_out).astype(np.float32)))

    ys = NORTH - (np.arange(SIDE) + 0.5) * CELL
    xs = WEST + (np.arange(SIDE) + 0.5) * CELL
    raster = xr.DataArray(heights, coords={"y": ys, "x": xs}, dims=("y", "x"))
    xrs_viewshed(raster, x=x, y=y, observer_elev=EYE, target_elev=0.0)  # numba compiles
    start = time.perf_counter()
    angles = xrs_viewshed(raster, x=x, y=y, observer_elev=EYE, target_elev=0.0)
    seconds = time.perf_counter() - start
    theirs = (np.asarray(angles) != -1).astype(np.float32)
    rows.append(("xarray-spatial viewshed (second call)", seconds, None, theirs))

    print(f"One observer {EYE} m above the centre of a {SIDE}² DEM at {CELL:g} m "
          f"({ours.mean() * 100:.1f} % of it seen by relief):\n")
    print("| tool | whole run s | viewshed s | cells seen | differ from relief | "
          "of those, next to relief's visibility edge |")
    print("|---|---|---|---|---|---|")
    for name, seconds, trace, values in rows:
        differ = values != ours
        trace_text = f"{trace:.2f}" if trace is not None else ""
        print(f"| {name} | {seconds:.2f} | {trace_text} | {int(values.sum()):,} | "
              f"{differ.mean() * 100:.2f} % | {boundary_share(ours, differ) * 100:.0f} % |")
        if name.startswith("relief"):
            continue
        only_them = (values > ours).sum()
        only_us = (values < ours).sum()
        print(f"|  | | | | seen only by it: {only_them:,}; only by relief: {only_us:,} | |")

    rng = np.random.default_rng(38)
    picks = rng.integers(0, SIDE, size=(args.observers, 2))
    observers = []
    for c, r in picks:
        ox, oy = centre(c, r)
        observers += ["--observer", f"{ox},{oy},{EYE}"]
    out = os.path.join(work, "cumulative.tif")
    seconds = timed([args.relief, "viewshed", dem, "-o", out, "--stats", stats] + observers)
    trace = json.load(open(stats))["trace_ms"] / 1e3
    counts = read(out)
    print(f"\n| relief, {args.observers} observers (cumulative) | whole run s | viewshed s | "
          "mean observers per cell |")
    print("|---|---|---|---|")
    print(f"| seeded random observers, {EYE} m | {seconds:.2f} | {trace:.2f} | "
          f"{counts.mean():.2f} |")


if __name__ == "__main__":
    main()
