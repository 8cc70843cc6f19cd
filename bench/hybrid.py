#!/usr/bin/env python3
"""The hybrid renderer's benchmark (docs/hybrid.md): the hybrid paper's Tables 1 and 2 and
Figures 6, 7 and 11 (Ammann et al. 2010) on this machine, as Markdown tables.

- speed: frame times at a grazing flight view (the flight view of `relief bench`) for the
  mipmap ray caster, the hybrid renderer with levels of precision and with the exact far
  field, the full mesh rasterized and geometry clipmaps, at 1024x768 and 1920x1080 on 2048^2
  and 4096^2 fBm terrains (Table 1), with the depth error of each against the exact tracer;
- cells: the hybrid renderer's time for cells of 16 to 256 samples (Figure 6);
- levels: its time and error for 2 to 10 levels of precision (Table 2);
- flight: PSNR and wrong pixels against speed along a fly-through, for the hybrid renderer
  at several k and T and for clipmaps (Figure 7);
- dynamic: frame times while stamping, waves and erosion rewrite the terrain (Figure 11).

Run after `cargo build --release`, on an otherwise idle machine:
    python3 bench/hybrid.py [--relief target/release/relief] [--dir DIR] [--parts speed,cells,...]
"""
import argparse
import json
import math
import os
import subprocess
import tempfile

FLIGHT_FRAMES = 8


def run(command):
    out = subprocess.run(command, check=True, capture_output=True, text=True)
    return out.stdout


def bench(args, field, res, tracers, extra=(), depth_dir=None, repeat=3):
    """`relief bench --json` on the flight view: one JSON object per tracer."""
    command = [args.relief, "bench", "--input", field, "--res", res, "--tracers", tracers,
               "--views", "flight", "--surfaces", "triangles", "--repeat", str(repeat), "--json"]
    command += list(extra)
    if depth_dir:
        command += ["--depth-dir", depth_dir]
    return [json.loads(line) for line in run(command).splitlines() if line.startswith("{")]


def compare(args, reference, test, field):
    return json.loads(run([args.relief, "compare", reference, test, "--terrain", field, "--json"]))


def psnr(m):
    return "identical" if m["psnr_db"] is None else f"{m['psnr_db']:.1f}"


def speed(args, work, fields):
    print("### Speed at the flight view (Table 1)\n")
    print("| terrain | image | renderer | trace ms | Hz | PSNR dB | wrong pixels % |")
    print("|---|---|---|---|---|---|---|")
    renderers = [
        ("mipmap ray caster", "mipmap", []),
        ("hybrid, levels of precision (k 1.3, T 70)", "hybrid", ["--far", "lop"]),
        ("hybrid, exact far field", "hybrid", ["--far", "exact"]),
        ("full mesh rasterized", "hybrid", ["--far", "exact", "--threshold", "1e-9"]),
        ("geometry clipmaps (n 511, 11 levels)", "clipmap", []),
    ]
    for side, field in fields:
        for res in ("1024x768", "1920x1080"):
            reference = None
            for name, tracer, extra in renderers:
                depth = os.path.join(work, f"speed-{side}-{res}-{len(name)}-{tracer}")
                m = bench(args, field, res, tracer, extra, depth)[0]
                path = os.path.join(depth, f"flight-triangles-{tracer}.npy")
                reference = reference or path
                error = compare(args, reference, path, field)
                ms = m["primary_s"] * 1e3
                print(f"| {side}² | {res} | {name} | {ms:.0f} | {1e3 / ms:.1f} | {psnr(error)} | "
                      f"{100 * error['wrong_pixel_fraction']:.3f} |")
    print()


def cells(args, work, field):
    print("### Cell size (Figure 6): 4096², 1024x768, flight view\n")
    print("| cell | levels of precision ms | exact far field ms |")
    print("|---|---|---|")
    for cell in (16, 32, 64, 128, 256):
        row = []
        for far in ("lop", "exact"):
            m = bench(args, field, "1024x768", "hybrid", ["--cell", str(cell), "--far", far])[0]
            row.append(f"{m['primary_s'] * 1e3:.0f}")
        print(f"| {cell} | {row[0]} | {row[1]} |")
    print()


def levels(args, work, field):
    print("### Levels of precision (Table 2): 4096², 1024x768, flight view\n")
    print("| levels | trace ms | PSNR dB | wrong pixels % |")
    print("|---|---|---|---|")
    ref_dir = os.path.join(work, "levels-ref")
    bench(args, field, "1024x768", "mipmap", depth_dir=ref_dir, repeat=1)
    reference = os.path.join(ref_dir, "flight-triangles-mipmap.npy")
    for count in (2, 4, 6, 8, 10):
        depth = os.path.join(work, f"levels-{count}")
        m = bench(args, field, "1024x768", "hybrid", ["--far", "lop", "--lop", str(count)], depth)[0]
        error = compare(args, reference, os.path.join(depth, "flight-triangles-hybrid.npy"), field)
        print(f"| {count} | {m['primary_s'] * 1e3:.0f} | {psnr(error)} | "
              f"{100 * error['wrong_pixel_fraction']:.3f} |")
    print()


def flight_cameras(args, work, field):
    """The flight view, then moved forward frame by frame, the eye kept as high above the
    ground under it as the flight view's is (the field is a .npy grid, spacing 1)."""
    import numpy
    heights = numpy.load(field)
    m = bench(args, field, "1024x768", "mipmap", repeat=1)[0]
    eye, target = m["camera"]["eye"], m["camera"]["target"]
    ground = lambda x, y: float(heights[int(y), int(x)])
    clearance = eye[2] - ground(eye[0], eye[1])
    step = [(t - e) / (2.5 * FLIGHT_FRAMES) for e, t in zip(eye, target)]
    for k in range(FLIGHT_FRAMES):
        x, y = eye[0] + k * step[0], eye[1] + k * step[1]
        z = max(eye[2], ground(x, y) + clearance)
        yield ([x, y, z], [target[0] + k * step[0], target[1] + k * step[1], target[2]])


def flight(args, work, field):
    print(f"### Along a fly-through (Figure 7): 4096², 1024x768, {FLIGHT_FRAMES} frames\n")
    print("| renderer | frame ms (median) | PSNR dB (min / median) | wrong pixels % (median / max) |")
    print("|---|---|---|---|")
    configs = [
        ("hybrid k 1.0, T 100", "hybrid", ["--far", "lop", "--k", "1.0", "--threshold", "100"]),
        ("hybrid k 1.3, T 70", "hybrid", ["--far", "lop"]),
        ("hybrid k 1.5, T 100", "hybrid", ["--far", "lop", "--k", "1.5", "--threshold", "100"]),
        ("hybrid, exact far field", "hybrid", ["--far", "exact"]),
        ("geometry clipmaps", "clipmap", []),
    ]
    cameras = list(flight_cameras(args, work, field))
    for name, tracer, extra in configs:
        times, psnrs, wrong = [], [], []
        for k, (eye, target) in enumerate(cameras):
            def render(tracer, extra, tag):
                depth = os.path.join(work, f"fly-{tag}-{k}.npy")
                stats = os.path.join(work, f"fly-{tag}-{k}.json")
                run([args.relief, "render", field, "--eye", ",".join(map(str, eye)), "--target",
                     ",".join(map(str, target)), "--fov", "60", "--size", "1024x768",
                     "--no-shadows", "--tracer", tracer, "-o", os.path.join(work, "fly.png"),
                     "--depth", depth, "--stats", stats] + extra)
                return depth, json.load(open(stats))
            reference, _ = render("mipmap", [], "ref")
            depth, stats = render(tracer, extra, f"{tracer}-{len(name)}")
            error = compare(args, reference, depth, field)
            times.append(stats["trace_ms"])
            psnrs.append(math.inf if error["psnr_db"] is None else error["psnr_db"])
            wrong.append(100 * error["wrong_pixel_fraction"])
        times.sort(), psnrs.sort(), wrong.sort()
        mid = len(times) // 2
        print(f"| {name} | {times[mid]:.0f} | {psnrs[0]:.1f} / {psnrs[mid]:.1f} | "
              f"{wrong[mid]:.3f} / {wrong[-1]:.3f} |")
    print()


def dynamic(args, work, fields):
    print("### Dynamic terrain (Figure 11): 1280x720, flight view, medians over 20 frames\n")
    print("| terrain | change | far field | shadows | change ms | update ms | render ms | shade ms | frame ms | frames/s |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for side, field in fields:
        for kind in ("stamp", "waves", "erosion"):
            for far, shadows in (("exact", True), ("exact", False), ("lop", False)):
                command = [args.relief, "bench", "--input", field, "--res", "1280x720",
                           "--dynamic", kind, "--frames", "20", "--far", far, "--json"]
                if not shadows:
                    command.append("--no-shadows")
                s = [json.loads(line) for line in run(command).splitlines()][-1]
                print(f"| {side}² | {kind} | {far} | {'on' if shadows else 'off'} | "
                      f"{s['median_change_ms']:.1f} | {s['median_update_ms']:.1f} | "
                      f"{s['median_render_ms']:.1f} | {s['median_shade_ms']:.1f} | "
                      f"{s['median_frame_ms']:.1f} | {s['frames_per_s']:.1f} |")
    print()


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--relief", default="target/release/relief")
    parser.add_argument("--dir", default=None)
    parser.add_argument("--parts", default="speed,cells,levels,flight,dynamic")
    parser.add_argument("--sizes", default="2048,4096")
    args = parser.parse_args()
    work = args.dir or tempfile.mkdtemp(prefix="relief-hybrid-bench-")
    os.makedirs(work, exist_ok=True)
    fields = []
    for side in map(int, args.sizes.split(",")):
        path = os.path.join(work, f"fbm{side}.npy")
        if not os.path.exists(path):
            run([args.relief, "generate", "fbm", "--size", str(side), "-o", path])
        fields.append((side, path))
    largest = fields[-1][1]
    parts = args.parts.split(",")
    if "speed" in parts:
        speed(args, work, fields)
    if "cells" in parts:
        cells(args, work, largest)
    if "levels" in parts:
        levels(args, work, largest)
    if "flight" in parts:
        flight(args, work, largest)
    if "dynamic" in parts:
        dynamic(args, work, fields)


if __name__ == "__main__":
    main()
