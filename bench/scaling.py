#!/usr/bin/env python3
"""How relief's mipmap tracer scales: with terrain size, image size, threads, SIMD and packets.

Runs `relief bench` (triangles surface, mipmap tracer, fastest of --repeat runs) and prints
Markdown tables of primary and shadow Mrays/s and node visits per ray:
  1. terrain size: the seeded fBm terrain at each of --sizes, at --res;
  2. image size: the --pixels-size terrain at 480x270 up to 3840x2160;
  3. threads: 1 and 2 (RAYON_NUM_THREADS), and the portable kernel and single rays beside the
     AVX2 packets, on the --pixels-size terrain at --res.

Not part of the tests. Measure on an otherwise idle machine and compare only within one run:

    cargo build --release
    python3 bench/scaling.py --sizes 256 1024 4096 16384
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile

VIEWS = "three-quarter,flight,top-down"


def bench(relief, terrain, res, repeat, extra=(), env=None):
    """The JSON lines of one `relief bench` run, keyed by view."""
    cmd = [relief, "bench", "--input", terrain, "--res", res, "--tracers", "mipmap",
           "--surfaces", "triangles", "--views", VIEWS, "--json", "--repeat", str(repeat), *extra]
    proc = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if proc.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed:\n{proc.stderr}")
    rows = [json.loads(line) for line in proc.stdout.splitlines() if line.startswith("{")]
    return {r["view"]: r for r in rows}


def rates(r):
    """Primary Mrays/s, visits per ray, shadow Mrays/s, visits per shadow ray."""
    return (r["primary_rays"] / r["primary_s"] / 1e6, r["primary_mean_steps"],
            r["shadow_rays"] / r["shadow_s"] / 1e6, r["shadow_mean_steps"])


def table(title, label, runs):
    """Prints one Markdown table: a row per (label value, view)."""
    print(f"\n### {title}\n")
    print(f"| {label} | view | primary Mr/s | visits/ray | shadow Mr/s | visits/ray | peak MiB |")
    print("|---|---|---:|---:|---:|---:|---:|")
    for value, by_view in runs:
        for view, r in by_view.items():
            p, ps, s, ss = rates(r)
            print(f"| {value} | {view} | {p:.2f} | {ps:.1f} | {s:.2f} | {ss:.1f} | {r['peak_mib']:.0f} |")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[256, 1024, 4096, 16384])
    parser.add_argument("--pixels-size", type=int, default=4096)
    parser.add_argument("--res", default="1920x1080")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--relief", default="target/release/relief")
    parser.add_argument("--work", default=None, help="folder for the terrains")
    args = parser.parse_args()
    work = args.work or tempfile.mkdtemp(prefix="relief-scaling-")
    os.makedirs(work, exist_ok=True)

    def terrain(n):
        path = os.path.join(work, f"fbm-{n}.npy")
        if not os.path.exists(path):
            subprocess.run([args.relief, "generate", "fbm", "--size", str(n), "--seed", "1",
                            "-o", path], check=True, capture_output=True)
        return path

    print(f"relief scaling, work: {work}, fastest of {args.repeat}")
    table(f"Terrain size ({args.res})", "terrain",
          [(f"{n}²", bench(args.relief, terrain(n), args.res, args.repeat)) for n in args.sizes])
    big = terrain(args.pixels_size)
    table(f"Image size ({args.pixels_size}² terrain)", "image",
          [(res, bench(args.relief, big, res, args.repeat))
           for res in ["480x270", "960x540", "1920x1080", "3840x2160"]])
    variants = [
        ("2 threads, AVX2 packets", {}, ()),
        ("1 thread, AVX2 packets", {"RAYON_NUM_THREADS": "1"}, ()),
        ("2 threads, portable packets", {}, ("--simd", "portable")),
        ("2 threads, single rays", {}, ("--single-rays",)),
    ]
    table(f"Threads, SIMD and packets ({args.pixels_size}² terrain, {args.res})", "run",
          [(name, bench(args.relief, big, args.res, args.repeat, extra, {**os.environ, **env}))
           for name, env, extra in variants])


if __name__ == "__main__":
    main()
