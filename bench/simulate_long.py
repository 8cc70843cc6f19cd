#!/usr/bin/env python3
"""The erosion simulation run for long: the reference simulator's NGWM24 scene, 10,000 steps.

Runs `relief simulate` on ../shared/data/ngwm24-scene/scene.json (256 x 256 cells, saved by
the reference CUDA simulator at its step 1484) with the scene's rain and settings, checking
the terrain's invariants after every step as every run does (and with --check-stages after
every stage), a checkpoint every --checkpoint steps, and prints one Markdown table row: steps,
wall time, median step milliseconds, splits and collapses, the step reached, and whether the
written scene reads back valid (`relief info`).

Not part of the tests. Measure on an otherwise idle machine:

    cargo build --release -p relief-cli
    python3 bench/simulate_long.py --steps 10000
"""

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--relief", default=os.path.join(ROOT, "target", "release", "relief"))
    parser.add_argument("--scene", default=os.path.join(ROOT, "..", "shared", "data", "ngwm24-scene",
                                                        "scene.json"))
    parser.add_argument("--steps", type=int, default=10000)
    parser.add_argument("--checkpoint", type=int, default=1000)
    parser.add_argument("--check-stages", action="store_true",
                        help="check the invariants after every stage, not only every step")
    parser.add_argument("--keep", help="folder for the output (default: a temporary one)")
    args = parser.parse_args()
    if not os.path.isfile(args.scene):
        sys.exit(f"{args.scene} is absent (../shared is not beside the repository)")

    folder = args.keep or tempfile.mkdtemp(prefix="relief-simulate-long-")
    os.makedirs(folder, exist_ok=True)
    out = os.path.join(folder, f"ngwm24-{args.steps}.json")
    stats = os.path.join(folder, f"ngwm24-{args.steps}-stats.json")
    cmd = [args.relief, "simulate", args.scene, "--steps", str(args.steps), "-o", out,
           "--stats", stats, "--checkpoint", str(args.checkpoint)]
    if args.check_stages:
        cmd.append("--check-stages")
    print(" ".join(cmd), file=sys.stderr)
    start = time.monotonic()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.monotonic() - start
    if proc.returncode != 0:
        sys.exit(f"failed after {wall:.0f} s (exit {proc.returncode}):\n{proc.stderr}")
    s = json.load(open(stats))
    step = re.search(r"now at step (\d+)", proc.stderr)
    info = subprocess.run([args.relief, "info", out], capture_output=True, text=True)
    valid = "yes" if info.returncode == 0 else f"no: {info.stderr.strip()}"
    print("| steps | from step | to step | wall s | median step ms | splits | collapses | "
          "reads back valid |")
    print("|---:|---:|---:|---:|---:|---:|---:|---|")
    print(f"| {s['steps']} | {s['first_step']} | {step.group(1) if step else '?'} | {wall:.0f} | "
          f"{s['median_step_ms']:.2f} | {s['splits']} | {s['collapses']} | {valid} |")


if __name__ == "__main__":
    main()
