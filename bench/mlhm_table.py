#!/usr/bin/env python3
"""MLHM rendering per preset: the tables of docs/mlhm.md (after Nilles & Müller 2025, Figs. 6-8).

For every scene (RiversRain at each size, the carved `combined` scene with arches, a cave, a
chasm, overhangs and water, and optionally the reference simulator's real scene), every image
size and every preset, this script runs `relief render SCENE --mode MODE --preset P --size WxH`
with the hierarchy (stack back-tracking) and with the baseline: the naive 2D DDA for boxes,
marching the whole ray without the padded hierarchy for the smooth surface. It prints one
markdown table: hierarchy build ms, render ms of both, the hierarchy's speedup, rays per pixel
and steps per camera ray; with --shares also the share of the render time spent on AO and on
shadow rays (from renders with --no-ao and --no-shadows). Every figure is what `relief render`
itself reports on stderr (build and render only: reading the scene is not timed), seen from
one fixed view (EYE and TARGET below). Not part of the tests.

    cargo build --release
    python3 bench/mlhm_table.py --sizes 1024 2048 4096 --res 1280x720 1920x1080
    python3 bench/mlhm_table.py --mode smooth --real ../shared/data/ngwm24-scene/scene.json --shares

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


def render(path, args, res, preset, tracer, extra=(), mode=None):
    """(build ms or None, render ms, rays per pixel, steps per camera ray) of one render."""
    png = os.path.join(args.work, "out.png")
    mode = mode or args.mode
    cmd = [RELIEF, "render", path, "--mode", mode, "--size", res, "--preset", preset]
    cmd += ["--tracer", tracer, "--eye", EYE, "--target", TARGET, "--fov", "60", *extra]
    match = REPORT.search(run(cmd + ["-o", png]))
    build = float(match["build"]) if match["build"] else None
    return build, float(match["render"]), float(match["rays"]), float(match["steps"])


def share(full, without):
    """The share of `full` ms that `without` ms saves, as a percentage."""
    return f"{max(full - without, 0.0) / full * 100:.0f}%"


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--mode", choices=["boxes", "smooth"], default="boxes")
    p.add_argument("--sizes", type=int, nargs="+", default=[1024, 2048, 4096])
    p.add_argument("--overhangs", type=int, default=1024, help="size of `combined`, 0 for none")
    p.add_argument("--real", help="also the reference scene at this path (its .json)")
    p.add_argument("--res", nargs="+", default=["1280x720", "1920x1080"])
    p.add_argument("--presets", nargs="+", default=["low", "mid", "high", "max"])
    p.add_argument("--baseline-up-to", type=int, default=1 << 30,
                   help="run the baseline only on scenes of at most this many cells a side")
    p.add_argument("--shares", action="store_true", help="time shares of AO and shadows")
    p.add_argument("--boxes-too", action="store_true",
                   help="in smooth mode, also the boxes' render ms (hierarchy) in the same run")
    p.add_argument("--work", default="/tmp/relief-mlhm-bench")
    args = p.parse_args()
    os.makedirs(args.work, exist_ok=True)

    scenes = [(f"rivers-rain {s}²", scene(args.work, "rivers-rain", s), s) for s in args.sizes]
    if args.overhangs:
        path = scene(args.work, "combined", args.overhangs)
        scenes.append((f"combined {args.overhangs}²", path, args.overhangs))
    if args.real:
        scenes.append(("real scene 256²", args.real, 256))
    baseline_tracer = "naive"
    print(
        "| scene | resolution | preset | build ms | hierarchy ms | baseline ms | speedup "
        "| rays/pixel | steps hierarchy | steps baseline |"
        + (" AO | shadows |" if args.shares else "")
        + (" boxes ms |" if args.boxes_too else "")
    )
    print(
        "|---|---|---|---:|---:|---:|---:|---:|---:|---:|"
        + ("---:|---:|" if args.shares else "")
        + ("---:|" if args.boxes_too else "")
    )
    for label, path, size in scenes:
        for res in args.res:
            for preset in args.presets:
                build, fast, rays, steps = render(path, args, res, preset, "hierarchy")
                slow, speedup, slow_steps = "–", "–", "–"
                if size <= args.baseline_up_to:
                    _, ms, _, base_steps = render(path, args, res, preset, baseline_tracer)
                    slow, speedup, slow_steps = f"{ms:.0f}", f"{ms / fast:.1f}x", f"{base_steps:.0f}"
                row = (
                    f"| {label} | {res} | {preset} | {build:.1f} | {fast:.0f} | {slow} | "
                    f"{speedup} | {rays:.2f} | {steps:.0f} | {slow_steps} |"
                )
                if args.shares:
                    no_ao = render(path, args, res, preset, "hierarchy", ["--no-ao"])[1]
                    no_shadows = render(path, args, res, preset, "hierarchy", ["--no-shadows"])[1]
                    row += f" {share(fast, no_ao)} | {share(fast, no_shadows)} |"
                if args.boxes_too:
                    row += f" {render(path, args, res, preset, 'hierarchy', mode='boxes')[1]:.0f} |"
                print(row, flush=True)


if __name__ == "__main__":
    main()
