#!/usr/bin/env python3
"""The out-of-core benchmark of docs/tiles.md (Dick et al. 2009, sections 3.4 and 4).

- build: a synthetic SIZE^2 fBm terrain generated to disk (`relief generate fbm`, streamed), and
  its tile store (`relief tile`): build time, input MB/s, peak memory of the whole process;
- mosaic: a mosaic of 16 SRTM .hgt tiles (4 x 4, 3601^2 each) written by `relief convert` from
  pieces of a 14401^2 fBm terrain, tiled together: the same figures;
- render: `relief render STORE --cache-mb 512` at 1920x1080 from the default view and from the
  fly-through's first camera: peak memory of the whole process;
- flight: a 300-frame fly-through at 1920x1080 over the store (`relief flythrough --stats`):
  frame time, tiles drawn, resident memory and IO wait per frame, as a plot
  (docs/tiles/flythrough.png), against the same flight scaled onto an in-memory 4096^2 fBm
  terrain (its median frame is the reference of the "within 2x" target).

Peak memory is the whole process's peak resident set (VmHWM, read from /proc while it runs),
so it counts everything: code, buffers, caches. The plot needs matplotlib
(`pip install matplotlib`). Not part of the tests; the 65536^2 run needs about 40 GB of disk.

    cargo build --release
    python3 bench/tiles.py --dir /tmp/relief-tiles
    python3 bench/tiles.py --dir /tmp/relief-tiles --size 16384 --parts build,render,flight
"""

import argparse
import json
import math
import os
import shutil
import statistics
import subprocess
import tempfile
import time

RELIEF = os.path.join(os.path.dirname(__file__), "..", "target", "release", "relief")
PLOT = os.path.join(os.path.dirname(__file__), "..", "docs", "tiles", "flythrough.png")
FRAMES = 300
IMAGE = "1920x1080"


def run_measured(cmd):
    """Runs `cmd`; returns (seconds, peak RSS bytes of that process, stderr).

    The peak is the process's own VmHWM, read from /proc while it runs: the rusage of a child
    would also count this Python process's memory at the fork."""
    started = time.monotonic()
    with tempfile.TemporaryFile(mode="w+") as err:
        proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=err, text=True)
        peak = 0
        while proc.poll() is None:
            peak = max(peak, vm_hwm(proc.pid))
            time.sleep(0.02)
        seconds = time.monotonic() - started
        err.seek(0)
        text = err.read()
    if proc.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)}: {text.strip()}")
    return seconds, peak, text


def vm_hwm(pid):
    """The peak resident memory of process `pid` so far, in bytes (0 once it is gone)."""
    try:
        with open(f"/proc/{pid}/status") as f:
            line = next(l for l in f if l.startswith("VmHWM:"))
        return int(line.split()[1]) * 1024
    except (OSError, StopIteration):
        return 0


def mb(n):
    return n / 1e6


def build_row(name, inputs, store, samples):
    """Tiles `inputs` into `store`; one table row."""
    shutil.rmtree(store, ignore_errors=True)
    seconds, peak, _ = run_measured([RELIEF, "tile", *inputs, "-o", store])
    input_bytes = sum(os.path.getsize(p) for p in inputs)
    store_bytes = sum(os.path.getsize(os.path.join(store, f)) for f in os.listdir(store))
    return (f"| {name} | {input_bytes / 2**30:.2f} GiB | {samples * 4 / 1e6:,.0f} MB | "
            f"{seconds:.1f} s | {mb(samples * 4) / seconds:.0f} MB/s | {peak / 2**20:.0f} MiB | "
            f"{store_bytes / 2**30:.2f} GiB |")


def build(args):
    big = os.path.join(args.dir, f"fbm-{args.size}.tif")
    if not os.path.exists(big):
        seconds, peak, _ = run_measured([RELIEF, "generate", "fbm", "--size", str(args.size),
                                         "-o", big])
        print(f"`relief generate fbm --size {args.size}`: {seconds:.0f} s, "
              f"peak {peak / 2**20:.0f} MiB, {os.path.getsize(big) / 2**30:.2f} GiB\n")
    print(BUILD_HEADER)
    print(build_row(f"fBm {args.size}^2 GeoTIFF", [big], store_path(args), args.size**2))


BUILD_HEADER = ("| input | file size | input samples | build time | input MB/s | peak memory "
                "| store size |\n|---|---|---|---|---|---|---|")


def store_path(args):
    return os.path.join(args.dir, f"fbm-{args.size}.store")


def mosaic(args):
    """16 .hgt tiles written by `relief convert` from a 14401^2 terrain, tiled together."""
    import numpy as np

    side = 4 * 3600 + 1
    source = os.path.join(args.dir, f"fbm-{side}.npy")
    if not os.path.exists(source):
        run_measured([RELIEF, "generate", "fbm", "--size", str(side), "--seed", "7", "-o", source])
    heights = np.load(source, mmap_mode="r")
    hgt_dir = os.path.join(args.dir, "hgt")
    os.makedirs(hgt_dir, exist_ok=True)
    tiles = []
    for i in range(4):  # south to north
        for j in range(4):  # west to east
            name = os.path.join(hgt_dir, f"N{45 + i:02d}E{6 + j:03d}.hgt")
            if not os.path.exists(name):
                # relief's .npy rows are grid rows: row 0 is the southernmost.
                r0 = i * 3600
                piece = np.ascontiguousarray(heights[r0:r0 + 3601, j * 3600:j * 3600 + 3601])
                npy = name[:-4] + ".npy"
                np.save(npy, piece.astype(np.float32))
                run_measured([RELIEF, "convert", npy, name])
                os.remove(npy)
            tiles.append(name)
    print(BUILD_HEADER)
    print(build_row("16 SRTM .hgt tiles (4 x 4 of 3601^2)", tiles,
                    os.path.join(args.dir, "hgt.store"), side * side))


def flight_path(size, top, frames, path):
    """A low flight across the terrain's middle, looking ahead and down, as a camera path."""
    keys = []
    for k in range(frames):
        s = k / (frames - 1)
        # From the south-west quarter north-east, curving gently.
        x = size * (0.25 + 0.5 * s)
        y = size * (0.3 + 0.4 * s + 0.05 * math.sin(math.pi * s))
        heading = math.atan2(0.4 + 0.05 * math.pi * math.cos(math.pi * s), 0.5)
        ahead = 0.15 * size
        eye = [x, y, top * 1.1]
        target = [x + ahead * math.cos(heading), y + ahead * math.sin(heading), top * 0.5]
        keys.append({"time_s": k / 30, "eye": eye, "target": target, "up": [0, 0, 1],
                     "fov_deg": 50.0})
    with open(path, "w") as f:
        json.dump({"format": "relief-camera-path", "version": 1, "keys": keys}, f)
    return keys


def top_of(store_or_file):
    """The highest sample, from `relief info`."""
    out = subprocess.run([RELIEF, "info", store_or_file], capture_output=True, text=True,
                         check=True).stdout
    line = next(l for l in out.splitlines() if l.startswith("values:"))
    return float(line.split("..")[1].split()[0])


def render(args):
    store = store_path(args)
    top = top_of(store)
    keys = flight_path(args.size, top, args.frames, os.path.join(args.dir, "path.json"))
    print("| view | tiles drawn | error bound used | render time | peak memory |")
    print("|---|---|---|---|---|")
    for name, camera in [("default (whole terrain)", []),
                         ("the fly-through's first camera", camera_args(keys[0]))]:
        stats = os.path.join(args.dir, "render-stats.json")
        seconds, peak, _ = run_measured([RELIEF, "render", store, "--cache-mb", "512", "--size",
                                         IMAGE, "-o", os.path.join(args.dir, "still.png"),
                                         "--stats", stats, *camera])
        figures = json.load(open(stats))
        print(f"| {name} | {figures['tiles_drawn']} | {figures['max_error_px']:.2f} px | "
              f"{seconds:.1f} s | {peak / 2**20:.0f} MiB |")
    print()


def camera_args(key):
    fmt = lambda v: ",".join(f"{c:.6g}" for c in v)
    return ["--eye", fmt(key["eye"]), "--target", fmt(key["target"]), "--up", fmt(key["up"]),
            "--fov", f"{key['fov_deg']}"]


def fly(args, terrain, size, name, extra=()):
    top = top_of(terrain)
    path = os.path.join(args.dir, f"path-{size}.json")
    flight_path(size, top, args.frames, path)
    frames = os.path.join(args.dir, f"frames-{size}")
    shutil.rmtree(frames, ignore_errors=True)
    stats = os.path.join(args.dir, f"flight-{name}.json")
    seconds, peak, _ = run_measured([RELIEF, "flythrough", terrain, "--path", path, "--frames",
                                     str(args.frames), "--size", IMAGE, "-o", frames, "--stats",
                                     stats, *extra])
    return json.load(open(stats))["frames"], seconds, peak


def flight(args):
    store = store_path(args)
    tiled, seconds, peak = fly(args, store, args.size, "store", ["--cache-mb", "512"])
    small = os.path.join(args.dir, "fbm-4096.tif")
    if not os.path.exists(small):
        run_measured([RELIEF, "generate", "fbm", "--size", "4096", "-o", small])
    memory, mem_seconds, mem_peak = fly(args, small, 4096, "memory")
    med = lambda frames, key: statistics.median(f[key] for f in frames)
    print("| fly-through (1920x1080) | frames | median frame | 90th percentile | median tiles "
          "drawn | median error bound | max resident tiles | total IO wait | peak memory |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, frames, peak in [(f"{args.size}^2 store, --cache-mb 512", tiled, peak),
                               ("4096^2 in memory, the same flight scaled", memory, mem_peak)]:
        times = sorted(f["time_ms"] for f in frames)
        p90 = times[int(0.9 * (len(times) - 1))]
        drawn = med(frames, "tiles_drawn") if "tiles_drawn" in frames[0] else "-"
        bound = f"{med(frames, 'max_error_px'):.2f} px" if "max_error_px" in frames[0] else "-"
        resident = max(f.get("resident_bytes", 0) for f in frames)
        wait = sum(f.get("io_wait_ms", 0) for f in frames)
        print(f"| {name} | {len(frames)} | {statistics.median(times):.0f} ms | {p90:.0f} ms | "
              f"{drawn} | {bound} | {resident / 2**20:.0f} MiB | {wait:.0f} ms | {peak / 2**20:.0f} MiB |")
    ratio = med(tiled, "time_ms") / med(memory, "time_ms")
    print(f"\nmedian frame of the store / of the in-memory terrain: {ratio:.2f}\n")
    plot(tiled, args)


def plot(frames, args):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    x = [f["frame"] for f in frames]
    fig, axes = plt.subplots(4, 1, figsize=(9, 9), sharex=True)
    series = [("frame time (ms)", [f["time_ms"] for f in frames]),
              ("tiles drawn", [f["tiles_drawn"] for f in frames]),
              ("resident tiles (MiB)", [f["resident_bytes"] / 2**20 for f in frames]),
              ("IO wait (ms)", [f["io_wait_ms"] for f in frames])]
    for ax, (label, y) in zip(axes, series):
        ax.plot(x, y, linewidth=1)
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel("frame")
    fig.suptitle(f"Fly-through over a {args.size}^2 tile store, 1920x1080, --cache-mb 512")
    fig.tight_layout()
    os.makedirs(os.path.dirname(PLOT), exist_ok=True)
    fig.savefig(PLOT, dpi=100)
    print(f"plot: {os.path.relpath(PLOT)}")


def main():
    global RELIEF
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--relief", default=RELIEF)
    parser.add_argument("--dir", required=True, help="work folder (inputs and stores)")
    parser.add_argument("--size", type=int, default=65536)
    parser.add_argument("--frames", type=int, default=FRAMES)
    parser.add_argument("--parts", default="build,mosaic,render,flight")
    args = parser.parse_args()
    RELIEF = args.relief
    os.makedirs(args.dir, exist_ok=True)
    parts = {"build": build, "mosaic": mosaic, "render": render, "flight": flight}
    for part in args.parts.split(","):
        parts[part](args)


if __name__ == "__main__":
    main()
