#!/usr/bin/env python3
"""The material-stacks benchmark of docs/stacks.md (Löffler et al. 2011, section 4).

- mesh: the `combined` MLHM scene (arches, caves, chasm, overhangs, water) at SIZE^2 cells
  (`relief generate mlhm`), meshed whole at the finest level (`relief mesh --lod 0 --stats`),
  on all cores and on one: the meshing time (target: 1024^2 in under 5 s), the time per 17^3
  node (target: at most 1.4 ms on the 2 cores, the paper's GPU figure) and quads per second;
- memory: the paper's data size, 2048 x 4096 stacks with heights up to 768 m
  (`relief generate stacks`), its LOD mipmap against the voxel grid it stands for
  (`relief info`; the paper: 106 MB against 20 GB);
- flight: a fly-through of FRAMES frames at 1920x1080 with tau = 10 px over that terrain
  (`relief flythrough --mode mesh --stats`): frame time (node meshes cached across frames,
  their meshing amortised by --node-budget), nodes drawn, meshed and waiting per frame,
  triangles, and the median time of each stage (from each frame's note).

Each figure is the best (mesh) or the median (flight) of the runs. Not part of the tests.

    cargo build --release
    python3 bench/stacks.py --dir /tmp/relief-stacks
    python3 bench/stacks.py --dir /tmp/relief-stacks --parts flight [--node-budget all]
"""

import argparse
import json
import os
import re
import statistics
import subprocess
import time

RELIEF = os.path.join(os.path.dirname(__file__), "..", "target", "release", "relief")
IMAGE = "1920x1080"


def run(cmd, env=None):
    """Runs `cmd`, failing loudly; returns (seconds, stderr)."""
    started = time.monotonic()
    proc = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if proc.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)}: {proc.stderr.strip()}")
    return time.monotonic() - started, proc.stderr + proc.stdout


def mesh_figures(directory, size, repeat):
    scene = os.path.join(directory, f"combined-{size}.json")
    if not os.path.exists(scene):
        run([RELIEF, "generate", "mlhm", "--scene", "combined", "--size", str(size), "-o", scene])
    rows = []
    for threads in [None, 1]:
        env = dict(os.environ)
        if threads:
            env["RAYON_NUM_THREADS"] = str(threads)
        best = None
        for _ in range(repeat):
            stats_path = os.path.join(directory, "mesh-stats.json")
            out = os.path.join(directory, f"combined-{size}.ply")
            run([RELIEF, "mesh", scene, "--lod", "0", "-o", out, "--stats", stats_path], env)
            stats = json.load(open(stats_path))
            if best is None or stats["mesh_ms"] < best["mesh_ms"]:
                best = stats
        rows.append(best)
    return rows


def memory_figures(directory, width, height):
    path = os.path.join(directory, f"stacks-{width}x{height}.stacks")
    generate_s = None
    if not os.path.exists(path):
        generate_s, _ = run([RELIEF, "generate", "stacks", "--width", str(width), "--height",
                             str(height), "-o", path])
    _, info = run([RELIEF, "info", path])
    return path, generate_s, info


def flight_path(path, width_m, height_m, top_m):
    """A low flight along the terrain's long axis, looking ahead and down."""
    keys = []
    steps = 20
    for k in range(steps + 1):
        f = k / steps
        x = width_m * (0.2 + 0.6 * f)
        y = height_m * (0.1 + 0.8 * f)
        eye = [x, y, top_m + 150.0]
        target = [x + 0.1 * width_m, y + 0.12 * height_m, top_m * 0.4]
        keys.append({"time_s": 30.0 * f, "eye": eye, "target": target,
                     "up": [0.0, 0.0, 1.0], "fov_deg": 45.0})
    with open(path, "w") as f:
        json.dump({"format": "relief-camera-path", "version": 1, "keys": keys}, f)


def flight_figures(directory, stacks, frames, width_m, height_m, top_m, extra):
    path = os.path.join(directory, "flight.json")
    flight_path(path, width_m, height_m, top_m)
    stats_path = os.path.join(directory, "flight-stats.json")
    out = os.path.join(directory, "frames")
    os.makedirs(out, exist_ok=True)
    run([RELIEF, "flythrough", stacks, "--path", path, "--frames", str(frames), "-o", out,
         "--size", IMAGE, "--stats", stats_path] + extra)
    return json.load(open(stats_path))["frames"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--dir", required=True, help="scratch folder for the inputs")
    parser.add_argument("--size", type=int, default=1024, help="MLHM scene cells a side")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--frames", type=int, default=120)
    parser.add_argument("--parts", default="mesh,memory,flight")
    parser.add_argument("--node-budget", help="the flight's --node-budget (N or all) "
                        "[default: relief's]")
    parser.add_argument("--relief", help="the relief binary [default: target/release/relief]")
    args = parser.parse_args()
    global RELIEF
    if args.relief:
        RELIEF = args.relief
    os.makedirs(args.dir, exist_ok=True)
    parts = args.parts.split(",")

    if "mesh" in parts:
        print(f"## Meshing the combined MLHM scene, {args.size}^2 cells, finest level\n")
        print("| threads | nodes | quads | mesh ms | nodes ms | join ms | ms a node | quads a second |")
        print("|---|---|---|---|---|---|---|---|")
        for stats in mesh_figures(args.dir, args.size, args.repeat):
            quads = stats["solid_faces"] + stats["water_faces"]
            print(f"| {stats['threads']} | {stats['nodes']} | {quads} | {stats['mesh_ms']:.0f} "
                  f"| {stats['nodes_ms']:.0f} | {stats['join_ms']:.0f} | {stats['node_ms']:.3f} "
                  f"| {quads / stats['nodes_ms'] * 1e3 / 1e6:.1f} M |")
        print()

    width, height = 2048, 4096
    path = os.path.join(args.dir, f"stacks-{width}x{height}.stacks")
    if "memory" in parts or "flight" in parts:
        path, generate_s, info = memory_figures(args.dir, width, height)
        if "memory" in parts:
            print(f"## The paper's data size: {width} x {height} stacks\n")
            if generate_s is not None:
                print(f"generated in {generate_s:.1f} s\n")
            print("```\n" + info.strip() + "\n```\n")
    if "flight" in parts:
        heights = re.search(r"heights:\s+([-\d.]+) \.\. ([-\d.]+) m", info)
        top = float(heights.group(2)) if heights else 700.0
        extra = ["--node-budget", args.node_budget] if args.node_budget else []
        frames = flight_figures(args.dir, path, args.frames, 2.0 * width, 2.0 * height, top, extra)
        times = [f["time_ms"] for f in frames]
        later = times[1:]
        notes = [f.get("note") or "" for f in frames]
        nodes = [int(m.group(1)) for m in (re.search(r"(\d+) nodes", n) for n in notes) if m]
        meshed = [int(m.group(1)) for m in (re.search(r"\((\d+) meshed", n) for n in notes) if m]
        waiting = [int(m.group(1)) for m in (re.search(r"(\d+) waiting", n) for n in notes) if m]
        tris = [int(m.group(1)) for m in (re.search(r"(\d+) triangles", n) for n in notes) if m]
        print(f"## Fly-through, {len(frames)} frames at {IMAGE}, tau 10 px\n")
        print("| first frame ms | median frame ms | frames a second (median) | slowest ms "
              "| nodes (median) | meshed a frame (median) | waiting (median) | triangles (median) |")
        print("|---|---|---|---|---|---|---|---|")
        print(f"| {times[0]:.0f} | {statistics.median(later):.0f} "
              f"| {1e3 / statistics.median(later):.2f} | {max(later):.0f} "
              f"| {statistics.median(nodes):.0f} | {statistics.median(meshed):.0f} "
              f"| {statistics.median(waiting) if waiting else 0:.0f} "
              f"| {statistics.median(tris):.0f} |")
        # The stages of each frame after the first, as the frame's note gives them.
        stages = ["select", "mesh", "append", "raster", "resolve and shade"]
        times_of = {s: [] for s in stages}
        for note in notes[1:]:
            for stage in stages:
                m = re.search(rf"{stage} (\d+) ms", note)
                if m:
                    times_of[stage].append(int(m.group(1)))
        present = [s for s in stages if times_of[s]]
        # What the frame spent outside the stages its note names.
        rest = []
        for f, note in zip(frames[1:], notes[1:]):
            named = [int(m.group(1)) for m in
                     (re.search(rf"{stage} (\d+) ms", note) for stage in present) if m]
            if len(named) == len(present):
                rest.append(f["time_ms"] - sum(named))
        if rest:
            times_of["rest"] = rest
            present.append("rest")
        if present:
            print("\nStage medians over the frames after the first, ms (rest: the frame's time "
                  "outside the named stages):\n")
            print("| " + " | ".join(present) + " |")
            print("|" + "---|" * len(present))
            print("| " + " | ".join(f"{statistics.median(times_of[s]):.0f}" for s in present)
                  + " |")


if __name__ == "__main__":
    main()
