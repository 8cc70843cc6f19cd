#!/usr/bin/env python3
"""How much of the terrain a stacks mesh keeps (issue 41, docs/stacks.md "Fidelity").

For each scene, `relief mesh` at the finest level (`--lod 0`) and at the camera's levels
(`--lod auto`, tau = 10 px), at the defaults:
- the solid's and the water's enclosed volume against the stacks' (`--stats`: solid_m3,
  water_m3, stacks_solid_m3, stacks_water_m3);
- the faces;
- features kept: every connected piece of the finest mesh (solid and water, read back by
  trimesh from the .glb) must have a piece at the camera's levels whose box overlaps its own
  (grown by the coarsest cell drawn); the pieces that have none are counted as missing.

Scenes: the `combined` MLHM scene (arches, cave, chasm, overhangs, water), the MLHM reference
scene (../shared/data/ngwm24-scene, MIT, where present), a `relief generate stacks` terrain,
and random two-layer scenes with a broad overhanging shelf, a sand cover of 0.3-0.5 m and
ponds (cells of 1 m, layers 3 m thick), written as .stacks files.

    cargo build --release
    python3 bench/stacks_fidelity.py --dir /tmp/relief-fidelity [--extra-args "--sigma 0.5"]
"""

import argparse
import json
import os
import shlex
import struct
import subprocess

import numpy as np
import trimesh

HERE = os.path.dirname(os.path.abspath(__file__))
RELIEF = os.path.join(HERE, "..", "target", "release", "relief")
SHARED_SCENE = os.path.join(HERE, "..", "..", "shared", "data", "ngwm24-scene", "scene.json")


def run(cmd):
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)}: {proc.stderr.strip()}")
    return proc.stderr


def write_stacks(path, width, height, stacks):
    """relief's .stacks format (docs/stacks.md), the default palette."""
    materials = [(0, (120, 110, 100), b"bedrock"), (0, (200, 180, 120), b"sand"),
                 (1, (40, 90, 160), b"water")]
    out = bytearray(b"RELIEFSTK\0")
    out += struct.pack("<HII", 1, width, height)
    out += struct.pack("<dddd", 1.0, 1.0, 0.0, 0.0)
    out += struct.pack("<H", len(materials))
    for kind, colour, name in materials:
        out += struct.pack("<B3BH", kind, *colour, len(name)) + name
    layers = [layer for stack in stacks for layer in stack]
    out += struct.pack("<Q", len(layers))
    offset = 0
    offsets = [0]
    for stack in stacks:
        offset += len(stack)
        offsets.append(offset)
    out += struct.pack(f"<{len(offsets)}I", *offsets)
    for start, end, material in layers:
        out += struct.pack("<ffB", start, end, material)
    with open(path, "wb") as f:
        f.write(out)


def shelf_scene(path, seed, size=128):
    """Rolling ground with a sand cover of 0.3-0.5 m, ponds in its lows, and a broad rock
    shelf 3 m thick overhanging an air gap (cells of 1 m)."""
    rng = np.random.default_rng(seed)
    y, x = np.mgrid[0:size, 0:size].astype(np.float64)
    phase = rng.uniform(0, 6.3, 4)
    ground = 3.0 + 1.5 * np.sin(x / 9.0 + phase[0]) * np.cos(y / 13.0 + phase[1]) \
        + 0.8 * np.sin((x + y) / 5.0 + phase[2])
    sand = rng.uniform(0.3, 0.5)
    pond_level = 3.0 + rng.uniform(-0.5, 0.5)
    cx, cy = rng.uniform(0.3, 0.7, 2) * size
    r = rng.uniform(0.2, 0.3) * size
    shelf = (np.abs(x - cx) < r) & (np.abs(y - cy) < 0.6 * r)
    stacks = []
    for j in range(size):
        for i in range(size):
            g = float(ground[j, i])
            layers = [(0.0, g, 0), (g, g + sand, 1)]
            top = g + sand
            if top < pond_level:
                layers.append((top, pond_level, 2))
                top = pond_level
            if shelf[j, i]:
                start = max(top, 8.0) + 2.0
                layers.append((start, start + 3.0, 0))
            stacks.append(layers)
    write_stacks(path, size, size, stacks)


def mesh(scene, out, lod, extra):
    stats_path = out + ".json"
    run([RELIEF, "mesh", scene, "-o", out, "--lod", lod, "--stats", stats_path] + extra)
    return json.load(open(stats_path))


def pieces(glb):
    """Per part, the boxes of its connected pieces."""
    loaded = trimesh.load(glb, force="scene", process=False)
    out = {}
    for name, geometry in loaded.geometry.items():
        g = geometry.copy()
        g.merge_vertices()
        labels = trimesh.graph.connected_component_labels(g.face_adjacency, len(g.faces))
        boxes = []
        for label in np.unique(labels):
            v = g.vertices[np.unique(g.faces[labels == label])]
            boxes.append((v.min(axis=0), v.max(axis=0)))
        out[name.split(".")[0]] = boxes
    return out


def missing(fine, coarse, margin):
    count = 0
    for part, boxes in fine.items():
        others = coarse.get(part, [])
        for lo, hi in boxes:
            if not any(np.all(lo - margin <= ohi) and np.all(olo <= hi + margin)
                       for olo, ohi in others):
                count += 1
    return count


def pct(mesh_v, stacks_v):
    return 100.0 * (mesh_v / stacks_v - 1.0) if stacks_v > 0 else float("nan")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--dir", default="/tmp/relief-fidelity")
    parser.add_argument("--extra-args", default="", help="more options for relief mesh")
    parser.add_argument("--shelves", type=int, default=3)
    args = parser.parse_args()
    os.makedirs(args.dir, exist_ok=True)
    extra = shlex.split(args.extra_args)
    scenes = []
    combined = os.path.join(args.dir, "combined.json")
    if not os.path.exists(combined):
        run([RELIEF, "generate", "mlhm", "--scene", "combined", "--size", "256", "-o", combined])
    scenes.append(("combined 256", combined, ["--eye", "-40,-70,80", "--target", "128,128,0",
                                              "--size", "960x540"]))
    if os.path.exists(SHARED_SCENE):
        scenes.append(("reference ngwm24", SHARED_SCENE, []))
    generated = os.path.join(args.dir, "generated.stacks")
    if not os.path.exists(generated):
        run([RELIEF, "generate", "stacks", "--width", "256", "--height", "256", "-o", generated])
    scenes.append(("generate stacks 256", generated, []))
    for seed in range(args.shelves):
        path = os.path.join(args.dir, f"shelf-{seed}.stacks")
        if not os.path.exists(path):
            shelf_scene(path, seed)
        scenes.append((f"shelf seed {seed}", path, []))

    print("| scene | solid lod 0 | water lod 0 | faces lod 0 | solid camera | water camera | "
          "faces camera | pieces lod 0 | missing at camera |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, path, camera in scenes:
        tag = os.path.join(args.dir, name.replace(" ", "-"))
        fine = mesh(path, tag + "-lod0.glb", "0", extra)
        cam = mesh(path, tag + "-auto.glb", "auto", extra + camera)
        fine_pieces = pieces(tag + "-lod0.glb")
        cam_pieces = pieces(tag + "-auto.glb")
        coarsest = max(i for i, n in enumerate(cam["nodes_per_level"]) if n > 0)
        margin = 2.0 ** coarsest  # the coarsest cell drawn, in cells of 1 m
        lost = missing(fine_pieces, cam_pieces, margin)
        n_fine = sum(len(b) for b in fine_pieces.values())
        print(f"| {name} | {pct(fine['solid_m3'], fine['stacks_solid_m3']):+.2f} % | "
              f"{pct(fine['water_m3'], fine['stacks_water_m3']):+.2f} % | "
              f"{fine['solid_faces'] + fine['water_faces']} | "
              f"{pct(cam['solid_m3'], cam['stacks_solid_m3']):+.2f} % | "
              f"{pct(cam['water_m3'], cam['stacks_water_m3']):+.2f} % | "
              f"{cam['solid_faces'] + cam['water_faces']} | {n_fine} | {lost} |", flush=True)


if __name__ == "__main__":
    main()
