#!/usr/bin/env python3
"""MLHM box rendering per preset: the table of docs/mlhm.md (after Nilles & Müller 2025, Figs. 6-8).

For every scene (RiversRain at each size, and the carved `combined` scene with arches, a cave,
a chasm, overhangs and water), every image size and every preset, this script runs
`relief render scene.json --preset P --size WxH` with the hierarchy tracer (stack
back-tracking) and with the naive 2D DDA, and prints one markdown table: hierarchy build ms,
render ms of both tracers, rays per pixel and the hierarchy's speedup. Every figure is what
`relief render` itself reports on stderr (build and render only: reading the scene is not
timed), seen from one fixed view (EYE and TARGET below). Not part of the tests.

    cargo build --release
    python3 bench/mlhm_table.py --sizes 1024 2048 4096 --res 1280x720 1920x1080

Scenes are generated once into --work (default: a directory under /tmp) as .mlhm files and
reused.
"""

import argparse
import os
import re
import subprocess
import sys

# The view: from 40 m south of the 256 m square scene, 70 m up, across it and down 19 degrees,
# as the simulator's saved camera looks (60 degree field of view): terrain fills the lower
# three quarters of the image, sky the rest.
EYE, TARGET = "128,-40,70", "128,140,8"
RELIEF = os.path.join(os.path.dirname(__file__), "..", "target", "release", "relief")
REPORT = re.compile(
    r"(?:built in (?P<build>[\d.]+) ms; )?rendered in (?P<render>[\d.]+) ms, "
    r"(?P<rays>[\d.]+) rays per pixel, (?P<steps>[\d.]+) steps per camera ray"
)


def run(cmd):
    """Runs cmd; returns its stderr, or exits with it on failure."""
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed:\n{proc.stderr}")
    return proc.stderr


def scene(work, name, size):
    """The path of scene `name` at `size` cells, generated on first use."""
    path = os.path.join(work, f"{name}-{size}.mlhm")
    if not os.path.exists(path):
        run([RELIEF, "generate", "mlhm", "--scene", name, "--size", str(size), "-o", path])
    return path


def render(path, res, preset, tracer, work):
    """(build ms or None, render ms, rays per pixel, steps per camera ray) of one render."""
    png = os.path.join(work, "out.png")
    cmd = [RELIEF, "render", path, "--size", res, "--preset", preset, "--tracer", tracer]
    cmd += ["--eye", EYE, "--target", TARGET, "--fov", "60"]
    match = REPORT.search(run(cmd + ["-o", png]))
    build = float(match["build"]) if match["build"] else None
    return build, float(match["render"]), float(match["rays"]), float(match["steps"])


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--sizes", type=int, nargs="+", default=[1024, 2048, 4096])
    p.add_argument("--overhangs", type=int, default=1024, help="size of the combined scene")
    p.add_argument("--res", nargs="+", default=["1280x720", "1920x1080"])
    p.add_argument("--presets", nargs="+", default=["low", "mid", "high", "max"])
    p.add_argument("--no-naive", action="store_true", help="skip the naive DDA")
    p.add_argument("--work", default="/tmp/relief-mlhm-bench")
    args = p.parse_args()
    os.makedirs(args.work, exist_ok=True)

    scenes = [("rivers-rain", s) for s in args.sizes] + [("combined", args.overhangs)]
    print(
        "| scene | resolution | preset | build ms | hierarchy ms | naive ms | speedup "
        "| rays/pixel | steps hierarchy | steps naive |"
    )
    print("|---|---|---|---:|---:|---:|---:|---:|---:|---:|")
    for name, size in scenes:
        path = scene(args.work, name, size)
        for res in args.res:
            for preset in args.presets:
                build, fast, rays, steps = render(path, res, preset, "hierarchy", args.work)
                naive, speedup, naive_steps = "–", "–", "–"
                if not args.no_naive:
                    _, slow, _, slow_steps = render(path, res, preset, "naive", args.work)
                    naive, speedup = f"{slow:.0f}", f"{slow / fast:.1f}x"
                    naive_steps = f"{slow_steps:.0f}"
                print(
                    f"| {name} {size}² | {res} | {preset} | {build:.1f} | {fast:.0f} | "
                    f"{naive} | {speedup} | {rays:.2f} | {steps:.0f} | {naive_steps} |",
                    flush=True,
                )


if __name__ == "__main__":
    main()
