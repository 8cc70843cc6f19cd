#!/usr/bin/env python3
"""What anti-aliasing costs: `relief render` at 1920x1080 of the default terrain and of a
generated MLHM scene with `--aa off`, the adaptive default, `--aa 2` and `--aa 4`, runs
alternating mode by mode, the median of --repeat (default 5) with the spread.

Each run's time is the render's own: trace, shade and the anti-aliasing passes (the
`--stats` file's total_ms less load_ms and write_ms, so that the terrain's generation and
the PNG's compression, the same in every mode, do not water the ratios down), and the whole
command's wall time beside it. Prints a markdown table (docs/pictures.md) and writes the
pictures into --out:

    python3 bench/antialiasing.py --relief target/release/relief --out /tmp/aa-bench \
        --docs docs/images/pictures

Not part of the tests; needs only Python 3.
"""

import argparse
import json
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

MODES = ["off", "adaptive", "2", "4"]


def run(relief, args, stats):
    started = time.perf_counter()
    subprocess.run([relief, *args, "--stats", str(stats)], check=True, capture_output=True)
    wall = (time.perf_counter() - started) * 1e3
    s = json.loads(Path(stats).read_text())
    return s["total_ms"] - s["load_ms"] - s["write_ms"], wall, s


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--relief", default="target/release/relief")
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--size", default="1920x1080")
    parser.add_argument("--out", default=None, help="folder for the pictures")
    parser.add_argument("--docs", default=None, help="folder for the close-ups of the docs")
    a = parser.parse_args()
    out = Path(a.out or tempfile.mkdtemp(prefix="relief-aa-"))
    out.mkdir(parents=True, exist_ok=True)
    scene = out / "combined.mlhm"
    subprocess.run([a.relief, "generate", "mlhm", "--scene", "combined", "--size", "256",
                    "-o", str(scene)], check=True, capture_output=True)
    cases = {
        "default terrain (fBm 1024²)": [],
        "MLHM combined 256², boxes, mid": [str(scene)],
    }
    print(f"| picture ({a.size}) | --aa | render ms (median, spread) | x off | whole command ms "
          "| pixels sampled again |")
    print("|---|---|---|---|---|---|")
    for name, inputs in cases.items():
        times = {m: [] for m in MODES}
        walls = {m: [] for m in MODES}
        shares = {}
        for rep in range(a.repeat):
            for mode in MODES:
                png = out / f"{'mlhm' if inputs else 'fbm'}-aa-{mode}.png"
                args = ["render", *inputs, "--size", a.size, "--aa", mode, "-o", str(png)]
                render_ms, wall, stats = run(a.relief, args, out / "stats.json")
                times[mode].append(render_ms)
                walls[mode].append(wall)
                shares[mode] = stats.get("aa_edge_share")
        off = statistics.median(times["off"])
        for mode in MODES:
            t = times[mode]
            med = statistics.median(t)
            share = shares[mode]
            shown = f"{100 * share:.1f} %" if share is not None else ("all" if mode != "off" else "none")
            print(f"| {name} | {mode} | {med:.0f} ({min(t):.0f}-{max(t):.0f}) | "
                  f"{med / off:.2f} | {statistics.median(walls[mode]):.0f} | {shown} |")
    print(f"\npictures in {out}")
    if a.docs:
        crops(out, Path(a.docs))


def crops(out, docs):
    """Close-ups (a 320 x 180 crop of each 1920 x 1080 picture, drawn twice as large, pixel
    for pixel) for docs/pictures.md; needs Pillow."""
    from PIL import Image

    docs.mkdir(parents=True, exist_ok=True)
    boxes = {"fbm": (760, 120, 1080, 300), "mlhm": (800, 420, 1120, 600)}
    for scene, box in boxes.items():
        for mode in MODES:
            picture = Image.open(out / f"{scene}-aa-{mode}.png").crop(box)
            picture.resize((640, 360), Image.NEAREST).save(docs / f"aa-{scene}-{mode}.png")


if __name__ == "__main__":
    main()
