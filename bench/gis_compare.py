#!/usr/bin/env python3
"""relief's terrain-visibility layers beside rvt-py, gdaldem and xarray-spatial, timed on the
same DEMs and measured against an independent exact horizon scan, in one run.

For each DEM (the seeded fBm terrain of `relief generate` at 10 m, written as a GeoTIFF in
UTM zone 16N, and the real Jacksboro fault DEM, geographic, whose metric spacing is taken at
its centre latitude on the WGS84 ellipsoid) this script
  1. draws 60 random samples (seeded) and computes there, with bench/horizon_scan.py, the
     exact horizons of the `triangles` surface along 180 azimuths to the edge of the data and
     from them the sky-view factor, both opennesses and the anisotropic sky-view factor;
  2. runs `relief shade` for each layer it has (the sky layer by rays as it is today; the
     horizon engine's layers where this build of relief has them) and reads the bands back;
  3. runs rvt-py's sky_view_factor (16 directions at r_max 10 and 100 cells, and 64 directions
     at a larger r_max), its openness on the DEM and on the inverted DEM, and its anisotropic
     SVF; gdaldem hillshade -multidirectional against relief's hillshade-multi, and
     xarray-spatial's hillshade against relief's hillshade where they compute the same thing;
  4. prints a markdown table (time, mean and largest absolute error at the points) and writes
     every figure to a JSON file.

    python3 bench/gis_compare.py                      # 3601^2 and the real DEM; about 15 min
    python3 bench/gis_compare.py --sizes 401 --points 20 --rvt-rmax 30   # a quick check

Run from the repository's root after `cargo build --release -p relief-cli`. It installs the
anchors it misses (rvt-py, xarray-spatial, rasterio with pip; gdal-bin with apt-get). The
DEMs and layer files go to a temporary folder removed at the end, unless --work DIR is given.
Every figure of one table comes from one run; the machine is shared, so compare within a run.
"""

import argparse
import json
import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import horizon_scan  # noqa: E402
from gis import anchors  # noqa: E402

REAL_DEM = "/work/shared/data/jacksboro_fault_dem.tif"
# Where the generated DEM is placed (UTM 16N, the zone of the real DEM), and its latitude and
# longitude for the sun.
UTM16N = "EPSG:32616"
UTM_ORIGIN = (500000.0, 4000000.0)
GENERATED_LAT_LON = (36.14, -87.0)
# The order of the summary tables.
LAYER_ORDER = ["reference", "horizon", "sky", "openness-pos", "openness-neg", "sky-aniso",
               "hillshade-multi", "hillshade"]


def write_generated(relief, size, work):
    """`relief generate fbm` of size^2 as a GeoTIFF at 10 m in UTM 16N; returns its path."""
    import rasterio
    from rasterio.transform import from_origin

    npy = Path(work) / f"fbm{size}.npy"
    subprocess.run([relief, "generate", "fbm", "--size", str(size), "-o", str(npy)], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    heights = np.load(npy)[::-1]  # .npy row 0 is south; a GeoTIFF's row 0 is north
    os.remove(npy)
    path = Path(work) / f"fbm{size}-10m-utm16n.tif"
    west, south = UTM_ORIGIN
    transform = from_origin(west, south + size * 10.0, 10.0, 10.0)
    with rasterio.open(path, "w", driver="GTiff", width=size, height=size, count=1,
                       dtype="float32", crs=UTM16N, transform=transform) as f:
        f.write(np.ascontiguousarray(heights, dtype=np.float32), 1)
    return path


def write_metric_copy(dem, dx, dy, work, name):
    """The same samples georeferenced in metres (UTM 16N, cells dx by dy), for the tools that
    need a projected grid (gdaldem); the DEM is not resampled."""
    import rasterio
    from rasterio.transform import from_origin

    path = Path(work) / f"{name}-metric.tif"
    rows, cols = dem.shape
    west, south = UTM_ORIGIN
    with rasterio.open(path, "w", driver="GTiff", width=cols, height=rows, count=1,
                       dtype="float32", crs=UTM16N,
                       transform=from_origin(west, south + rows * dy, dx, dy)) as f:
        f.write(dem.astype(np.float32), 1)
    return path


def relief_capabilities(relief, work):
    """The horizon-engine layers this build of `relief shade` has (each tried on a small DEM),
    and whether it takes --azimuths."""
    tiny = Path(work) / "probe.npy"
    np.save(tiny, np.random.default_rng(0).random((9, 9), dtype=np.float32))
    out = Path(work) / "probe.tif"
    place = ["--date", "2026-06-21", "--lat", "36", "--lon", "-87"]
    layers = set()
    for name in ("horizon", "sky-aniso", "openness-pos", "openness-neg", "sky-illumination",
                 "hillshade-multi", "insolation", "sun-hours"):
        extra = place if name in ("insolation", "sun-hours") else []
        proc = subprocess.run([relief, "shade", str(tiny), "-o", str(out), "--layers", name] + extra,
                              capture_output=True, text=True)
        if proc.returncode == 0:
            layers.add(name)
        else:
            reason = (proc.stderr.strip().splitlines() or ["(no message)"])[0]
            print(f"left out: relief shade --layers {name}: {reason}", file=sys.stderr)
    help_text = subprocess.run([relief, "shade", "--help"], capture_output=True, text=True).stdout
    for path in (tiny, out):
        if path.exists():
            os.remove(path)
    return layers, "--azimuths" in help_text, "--sky-rays" in help_text


def run_relief(relief, dem, out, options, work):
    """One `relief shade` run: (whole seconds, {band name: array}, its --stats)."""
    import rasterio

    stats = Path(work) / "stats.json"
    command = [relief, "shade", str(dem), "-o", str(out), "--stats", str(stats)] + options
    start = time.perf_counter()
    proc = subprocess.run(command, capture_output=True, text=True)
    seconds = time.perf_counter() - start
    if proc.returncode != 0:
        raise RuntimeError(f"{' '.join(command)}: {proc.stderr.strip()}")
    with rasterio.open(out) as f:
        bands = {name: f.read(i) for i, name in enumerate(f.descriptions, start=1)}
    os.remove(out)
    return seconds, bands, json.loads(stats.read_text())


def errors(values, reference):
    """Mean and largest absolute difference, ignoring nothing (a NaN shows as NaN)."""
    d = np.abs(np.asarray(values, dtype=np.float64) - np.asarray(reference, dtype=np.float64))
    return float(np.mean(d)), float(np.max(d))


def at(grid, points):
    """Values of a raster-ordered grid at (row, col) points."""
    rows, cols = zip(*points)
    return np.asarray(grid)[list(rows), list(cols)]


class Table:
    """Rows of one DEM's comparison: printed as markdown and kept for the JSON. The load column
    is the machine's 1-minute load average as the row's timing ended."""

    def __init__(self, dem_name):
        self.dem_name, self.rows = dem_name, []

    def add(self, layer, tool, settings, seconds, error=None, unit="", note=""):
        row = {"layer": layer, "tool": tool, "settings": settings, "seconds": seconds,
               "mean_abs_error": None if error is None else error[0],
               "max_abs_error": None if error is None else error[1], "unit": unit, "note": note,
               "load_average_1min": round(os.getloadavg()[0], 2)}
        self.rows.append(row)
        print(self.line(row), flush=True)

    @staticmethod
    def header():
        return ("| layer | tool | settings | time s | load | mean abs error | max error | unit |\n"
                "|---|---|---|---|---|---|---|---|")

    @staticmethod
    def line(row):
        def number(v, digits):
            return "" if v is None else f"{v:.{digits}g}" if abs(v) < 1e-3 and v != 0 else f"{v:.{digits}f}"
        seconds = "" if row["seconds"] is None else f"{row['seconds']:.2f}"
        note = f" ({row['note']})" if row["note"] else ""
        load = "" if row["seconds"] is None else f"{row['load_average_1min']:.1f}"
        return (f"| {row['layer']} | {row['tool']} | {row['settings']}{note} | {seconds} | {load} | "
                f"{number(row['mean_abs_error'], 4)} | {number(row['max_abs_error'], 4)} | {row['unit']} |")


def compare_dem(args, name, dem_path, work, lat_lon):
    """Every comparison on one DEM; returns its table's rows and the reference's facts."""
    dem, dx, dy = horizon_scan.read_dem(dem_path)
    points = horizon_scan.random_points(dem.shape, args.points, args.seed)
    print(f"\n### {name}: {dem.shape[1]} x {dem.shape[0]} samples, cells {dx:.2f} x {dy:.2f} m, "
          f"{args.points} points (seed {args.seed}); load average {os.getloadavg()[0]:.1f} on "
          f"{os.cpu_count()} cores\n", flush=True)
    start = time.perf_counter()
    ref = horizon_scan.reference_layers(dem, dx, dy, points, args.ref_azimuths)
    ref_seconds = time.perf_counter() - start
    table = Table(name)
    print(Table.header())
    table.add("reference", "horizon_scan.py", f"{args.ref_azimuths} azimuths, both ways, exact",
              ref_seconds, note="at the points only")
    layers, horizon_engine, sky_rays = relief_capabilities(args.relief, work)
    out = Path(work) / "shade.tif"
    place = ["--lat", str(lat_lon[0]), "--lon", str(lat_lon[1])] if lat_lon else []

    def relief_row(layer, label, options, reference=None, unit="", band=None):
        try:
            seconds, bands, _ = run_relief(args.relief, dem_path, out, options, work)
        except RuntimeError as e:
            print(f"relief failed: {e}", file=sys.stderr)
            return None
        error = None if reference is None else errors(at(bands[band or layer], points), reference)
        table.add(layer, "relief", label, seconds, error, unit)
        return bands

    # Sky-view factor.
    if sky_rays and not horizon_engine:
        for rays in (16, 64):
            relief_row("sky", f"{rays} rays (the sky layer by rays)", ["--layers", "sky", "--sky-rays", str(rays)],
                       ref["sky"])
    if horizon_engine:
        for n in (16, 64):
            relief_row("sky", f"{n} azimuths (horizons)", ["--layers", "sky", "--azimuths", str(n)], ref["sky"])
    # rvt-py: one call computes SVF, openness and the anisotropic SVF from the same horizon
    # search, which is what costs; the inverted DEM needs a second call for negative openness.
    resolution = float(np.sqrt(dx * dy))
    filled = np.where(np.isnan(dem), np.nanmean(dem), dem)
    square = "" if abs(dx - dy) < 1e-6 * dx else f"cells {dx:.1f} x {dy:.1f} m given as {resolution:.1f} m"
    seconds, rvt = anchors.rvt_horizon_layers(filled, resolution, 16, 10, asvf=True, asvf_dir=315.0)
    table.add("sky", "rvt-py", "16 directions, r_max 10 cells (its defaults)", seconds,
              errors(at(rvt["svf"], points), ref["sky"]), note=square)
    sky_aniso_default = errors(at(rvt["asvf"], points), ref["sky-aniso"])
    runs = ((16, 100), (64, args.rvt_rmax))
    for directions, r_max in runs:
        settings = f"{directions} directions, r_max {r_max} cells"
        seconds, rvt = anchors.rvt_horizon_layers(filled, resolution, directions, r_max, opns=True,
                                                  asvf=True, asvf_dir=45.0)
        table.add("sky", "rvt-py", settings, seconds, errors(at(rvt["svf"], points), ref["sky"]),
                  note=", ".join(filter(None, ["one call with openness-pos and sky-aniso", square])))
        table.add("openness-pos", "rvt-py", settings, None, errors(at(rvt["opns"], points), ref["openness-pos"]),
                  "degrees", "the same call")
        table.add("sky-aniso", "rvt-py", settings + ", asvf_dir 45 (the compass's 315)", None,
                  errors(at(rvt["asvf"], points), ref["sky-aniso"]), note="the same call")
    table.add("sky-aniso", "rvt-py", "16 directions, r_max 10 cells, asvf_dir 315 (its default: the compass's 45)",
              None, sky_aniso_default, note="the first call")
    seconds, neg = anchors.rvt_horizon_layers(-filled, resolution, 16, 100, svf=False, opns=True)
    table.add("openness-neg", "rvt-py", "16 directions, r_max 100 cells, inverted DEM", seconds,
              errors(at(neg["opns"], points), ref["openness-neg"]), "degrees", square)
    # relief's openness both ways and anisotropic SVF.
    if {"openness-pos", "openness-neg"} <= layers:
        n = str(args.azimuths)
        bands = relief_row("openness-pos", f"{n} azimuths", ["--layers", "openness-pos,openness-neg",
                           "--azimuths", n], ref["openness-pos"], "degrees")
        if bands is not None:
            table.rows[-1]["note"] = "both opennesses in this run"
            table.add("openness-neg", "relief", f"{n} azimuths (the same run)", None,
                      errors(at(bands["openness-neg"], points), ref["openness-neg"]), "degrees")
    if "sky-aniso" in layers:
        relief_row("sky-aniso", f"{args.azimuths} azimuths, main 315",
                   ["--layers", "sky-aniso", "--azimuths", str(args.azimuths)],
                   ref["sky-aniso"])
    # Horizon angles at relief's own azimuths: a direct check of exactness.
    if "horizon" in layers:
        bands = relief_row("horizon", "16 azimuths", ["--layers", "horizon", "--azimuths", "16"])
        if bands is not None:
            ref16 = np.degrees(horizon_scan.horizons(dem, dx, dy, points, 16))
            names = sorted(n for n in bands if n.startswith("horizon-"))
            got = np.stack([at(bands[n], points) for n in names], axis=1)
            table.rows[-1].update(zip(("mean_abs_error", "max_abs_error"), errors(got, ref16)))
            table.rows[-1]["unit"] = "degrees (against the scan at the same 16 azimuths)"
            print(Table.line(table.rows[-1]))
    # Hillshades.
    metric = write_metric_copy(dem, dx, dy, work, name.split()[0])
    seconds_gdal, gdal = anchors.gdaldem_hillshade(metric, Path(work) / "gdaldem.tif")
    table.add("hillshade-multi", "gdaldem", "-multidirectional, altitude 45", seconds_gdal)
    if "hillshade-multi" in layers:
        bands = relief_row("hillshade-multi", "altitude 45", ["--layers", "hillshade-multi"])
        if bands is not None:
            inner = (slice(1, -1), slice(1, -1))
            steps = np.abs(gdal[inner].astype(np.float64) - (1 + 254 * bands["hillshade-multi"][inner]))
            table.rows[-1].update(mean_abs_error=float(steps.mean()), max_abs_error=float(steps.max()),
                                  unit="8-bit steps from gdaldem, every inner sample")
            table.rows[-1]["note"] = f"{np.mean(steps < 0.5) * 100:.1f}% within half a step"
            print(Table.line(table.rows[-1]))
    if abs(dx - dy) < 1e-6 * dx:
        sun = (225.0, 25.0)  # xarray-spatial's defaults
        seconds, xrs = anchors.xrspatial_hillshade(filled, dx, *sun)
        bands = relief_row("hillshade", f"sun {sun[0]:g},{sun[1]:g}", ["--layers", "hillshade", "--sun",
                           f"{sun[0]:g},{sun[1]:g}"])
        if bands is not None:
            inner = (slice(1, -1), slice(1, -1))
            diff = errors(xrs[inner], bands["hillshade"][inner])
            table.add("hillshade", "xarray-spatial", f"sun {sun[0]:g},{sun[1]:g}, heights / {dx:g} m", seconds,
                      diff, "0..1, difference from relief's (central differences, not Horn's)")
    # The one-run targets.
    if {"horizon", "sky-illumination", "openness-pos", "openness-neg"} <= layers:
        relief_row("horizon + sky + openness-pos + openness-neg + sky-illumination", "16 azimuths, one run",
                   ["--layers", "horizon,sky,openness-pos,openness-neg,sky-illumination", "--azimuths", "16"])
    if "insolation" in layers:
        relief_row("insolation", "2026-06-21, 15-minute steps, 32 azimuths",
                   ["--layers", "insolation", "--date", "2026-06-21", "--step", "15m"] + place)
    return table.rows, {"dx": dx, "dy": dy, "shape": list(dem.shape), "points": points,
                        "reference_seconds": ref_seconds}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", type=int, nargs="*", default=[3601],
                        help="sides of the generated DEMs (10 m cells)")
    parser.add_argument("--real", default=REAL_DEM, help="the real DEM ('' to leave it out)")
    parser.add_argument("--points", type=int, default=60)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--ref-azimuths", type=int, default=180)
    parser.add_argument("--rvt-rmax", type=int, default=100,
                        help="r_max in cells of rvt-py's run at 64 directions")
    parser.add_argument("--azimuths", type=int, default=32,
                        help="relief's directions for openness and sky-aniso (sky runs at 16 and 64)")
    parser.add_argument("--relief", default="target/release/relief")
    parser.add_argument("--work", default=None, help="keep the DEMs here")
    parser.add_argument("--json", default="gis_compare.json", help="where to write every figure")
    parser.add_argument("--no-install", action="store_true", help="do not install missing anchors")
    parser.add_argument("--summary", metavar="JSON", help="only print the tables of an earlier run's JSON")
    args = parser.parse_args()
    if args.summary:
        with open(args.summary) as f:
            print_summary(json.load(f))
        return
    if not args.no_install:
        anchors.install_anchors()
    # A stop by SIGTERM still removes the temporary folder.
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))
    temporary = None if args.work else tempfile.TemporaryDirectory(prefix="relief-gis-")
    work = args.work or temporary.name
    os.makedirs(work, exist_ok=True)
    results = {"command": " ".join(sys.argv), "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
               "cores": os.cpu_count(), "dems": {}}
    try:
        dems = [(f"generated {s}^2 at 10 m", write_generated(args.relief, s, work), GENERATED_LAT_LON)
                for s in args.sizes]
        if args.real:
            dems.append(("Jacksboro fault (real, 3 arc-seconds)", Path(args.real), None))
        for name, path, lat_lon in dems:
            rows, facts = compare_dem(args, name, path, work, lat_lon)
            results["dems"][name] = {"file": str(path), **facts, "rows": rows}
            with open(args.json, "w") as f:
                json.dump(results, f, indent=1)
    finally:
        if temporary is not None:
            temporary.cleanup()
    print("\n## Summary, layer by layer")
    print_summary(results)
    print(f"\nwrote {args.json}")


def print_summary(results):
    """Each DEM's table in layer order, as markdown."""
    for name, dem in results["dems"].items():
        print(f"\n{name}: {dem['shape'][1]} x {dem['shape'][0]} samples, cells {dem['dx']:.2f} x "
              f"{dem['dy']:.2f} m\n\n{Table.header()}")
        for row in sorted(dem["rows"], key=lambda r: LAYER_ORDER.index(r["layer"])
                          if r["layer"] in LAYER_ORDER else len(LAYER_ORDER)):
            print(Table.line(row))


if __name__ == "__main__":
    main()
