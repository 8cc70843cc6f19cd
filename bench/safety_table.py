#!/usr/bin/env python3
"""Baboud et al. 2011, Table 1, on this machine: precomputation time and rendering speed of
the safety-shape variants next to the naive and max-mipmap tracers.

Runs `relief bench` on the seeded fBm terrain at each size, 1280x1024 pixels, on the `cover`
view (the terrain fills the image; every ray looks down at least 45 degrees), without and with
phi max = -45 degrees, and prints a Markdown table. Measurements, not assertions: run it on an
otherwise idle machine. Usage:

    cargo build --release
    python3 bench/safety_table.py [--sizes 256,512,1024] [--exterior-up-to 512] [--relief PATH]
"""
import argparse
import json
import subprocess

PLAIN = ["naive", "mipmap"]
SAFETY = ["cyl_all", "cyl_all+cone_all", "cyl_ext", "cyl_ext+cone_all", "cyl_ext+cone_ext"]


def bench(relief, size, tracers, extra):
    """One `relief bench --json` run: {tracer: measurement}."""
    cmd = [relief, "bench", "--size", str(size), "--res", "1280x1024", "--views", "cover",
           "--surfaces", "triangles", "--tracers", ",".join(tracers), "--json"] + extra
    print("#", " ".join(cmd), flush=True)
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    rows = [json.loads(line) for line in out.splitlines() if line.startswith("{")]
    return {row["tracer"]: row for row in rows}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="256,512,1024")
    parser.add_argument("--exterior-up-to", type=int, default=512,
                        help="largest size for the exterior (cyl_ext) variants")
    parser.add_argument("--relief", default="target/release/relief")
    args = parser.parse_args()
    sizes = [int(s) for s in args.sizes.split(",")]
    free, bounded = {}, {}
    for size in sizes:
        variants = [v for v in SAFETY if size <= args.exterior_up_to or not v.startswith("cyl_ext")]
        free[size] = bench(args.relief, size, PLAIN + variants, [])
        bounded[size] = bench(args.relief, size, variants, ["--phi-max", "-45"])

    def mrays(row):
        return row["primary_rays"] / row["primary_s"] / 1e6

    head = "| tracer | " + " | ".join(f"precompute {s}² s (φmax)" for s in sizes) + " | " + \
        " | ".join(f"{s}² Mrays/s (φmax)" for s in sizes) + " |"
    print()
    print(head)
    print("|" + "---|" * (1 + 2 * len(sizes)))
    for tracer in PLAIN + SAFETY:
        cells = []
        for size in sizes:
            row, phi = free[size].get(tracer), bounded[size].get(tracer)
            if row is None:
                cells.append("–")
            elif phi is None:
                cells.append("none")
            else:
                cells.append(f"{row['build_ms'] / 1e3:.2f} ({phi['build_ms'] / 1e3:.2f})")
        for size in sizes:
            row, phi = free[size].get(tracer), bounded[size].get(tracer)
            if row is None:
                cells.append("–")
            elif phi is None:
                cells.append(f"{mrays(row):.2f}")
            else:
                cells.append(f"{mrays(row):.2f} ({mrays(phi):.2f})")
        print(f"| {tracer} | " + " | ".join(cells) + " |")
    print()
    print("Shadow rays (Mrays/s, sun 315°/35°; φmax shapes trace them from the light):")
    for size in sizes:
        parts = [f"{t} {free[size][t]['shadow_rays'] / free[size][t]['shadow_s'] / 1e6:.2f}"
                 for t in PLAIN + SAFETY if t in free[size]]
        print(f"- {size}²: " + ", ".join(parts))


if __name__ == "__main__":
    main()
