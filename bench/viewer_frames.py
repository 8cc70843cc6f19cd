#!/usr/bin/env python3
"""Frame times of `relief view`: the table of docs/viewer.md.

For a 4096^2 fBm DEM and the carved MLHM scene `combined` (512^2 cells of 0.5 m, boxes at the
mid preset), at 640x360 and 1280x720, this script runs the viewer through its real window and
event loop (under Xvfb when no DISPLAY is set) with a scripted flight: orbiting round the scene
from the framing view, 30 degrees up, for MOVING frames (two thirds of a turn), then at rest
until FRAMES frames were shown. `--stats` records every frame; the table gives, while moving,
the median render time, the median time from one frame shown to the next and the frames per
second that is, and the two sizes the progressive scheduler chose most within the 50 ms frame
budget; at rest, the median render time of the full frame. Not part of the tests.

    cargo build --release
    python3 bench/viewer_frames.py
    python3 bench/viewer_frames.py --sizes 640x360 --budget 33
"""

import argparse
import collections
import json
import os
import shutil
import statistics
import subprocess
import tempfile

RELIEF = os.path.join(os.path.dirname(__file__), "..", "target", "release", "relief")
MOVING = 120
FRAMES = 140


def run(cmd):
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)}: {done.stderr.strip()}")
    return done


def scenes(work):
    dem = os.path.join(work, "fbm-4096.tif")
    if not os.path.exists(dem):
        run([RELIEF, "generate", "fbm", "--size", "4096", "-o", dem])
    mlhm = os.path.join(work, "combined-512.mlhm")
    if not os.path.exists(mlhm):
        run([RELIEF, "generate", "mlhm", "--scene", "combined", "--size", "512", "-o", mlhm])
    return [("4096^2 fBm DEM (mipmap, triangles)", dem), ("combined MLHM 512^2 (boxes, mid)", mlhm)]


def measure(scene, size, budget, work):
    stats = os.path.join(work, "frames.json")
    cmd = [RELIEF, "view", scene, "--size", size, "--frames", str(FRAMES),
           "--script", f"{MOVING}:A", "--frame-budget", str(budget),
           "--stats", stats, "--output-dir", work,
           "--screenshot", os.path.join(work, f"{os.path.basename(scene)}-{size}.png")]
    if not os.environ.get("DISPLAY"):
        if not shutil.which("xvfb-run"):
            raise SystemExit("no DISPLAY and no xvfb-run: apt-get install xvfb")
        cmd = ["xvfb-run", "-a", "-s", "-screen 0 1920x1080x24"] + cmd
    run(cmd)
    frames = json.load(open(stats))["frames"]
    moving = [f for f in frames if f["moving"]]
    full = max(f["width"] * f["height"] for f in frames)
    rest = [f for f in frames if not f["moving"] and f["width"] * f["height"] == full]
    sizes = collections.Counter(f"{f['width']}x{f['height']}" for f in moving).most_common(2)
    intervals = [f["interval_ms"] for f in moving if f["interval_ms"] is not None]
    interval = statistics.median(intervals)
    return {
        "moving_ms": statistics.median(f["render_ms"] for f in moving),
        "interval_ms": interval,
        "fps": 1e3 / interval,
        "sizes": ", ".join(f"{s} ({n})" for s, n in sizes),
        "rest_ms": statistics.median(f["render_ms"] for f in rest),
        "rest_n": len(rest),
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", nargs="+", default=["640x360", "1280x720"])
    parser.add_argument("--budget", type=int, default=50, help="--frame-budget, ms")
    parser.add_argument("--work", default=os.path.join(tempfile.gettempdir(), "relief-viewer-bench"))
    args = parser.parse_args()
    os.makedirs(args.work, exist_ok=True)
    print(f"| scene | window | moving: render ms | moving: shown every ms | moving: frames/s "
          f"| moving: sizes (frames) | at rest: full frame ms |")
    print("|---|---|---|---|---|---|---|")
    for name, scene in scenes(args.work):
        for size in args.sizes:
            m = measure(scene, size, args.budget, args.work)
            print(f"| {name} | {size} | {m['moving_ms']:.1f} | {m['interval_ms']:.1f} | "
                  f"{m['fps']:.1f} | {m['sizes']} | {m['rest_ms']:.0f} ({m['rest_n']} frames) |")


if __name__ == "__main__":
    main()
