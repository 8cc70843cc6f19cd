#!/usr/bin/env python3
"""relief.dask.flythrough on a LocalCluster of 1 and of 2 worker processes of one thread each
(docs/scale.md, "Fly-throughs"): 16 frames of 1280x720 over a height file, after two
warm-up frames that open the scene on every worker. Not part of the tests.

    python3 -m pip install . dask distributed
    python3 bench/dask_flythrough.py HEIGHTS.npy [--spacing 10] [--dir /tmp/relief-dask-fly]
"""

import argparse
import json
import os
import time

from distributed import Client, LocalCluster

import relief
import relief.dask


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("heights")
    parser.add_argument("--spacing", type=float, default=10.0)
    parser.add_argument("--frames", type=int, default=16)
    parser.add_argument("--dir", default="/tmp/relief-dask-fly")
    args = parser.parse_args()
    os.makedirs(args.dir, exist_ok=True)
    (x0, y0, z0), (x1, y1, z1) = relief.open(args.heights, spacing=args.spacing).info["bounds"]
    centre = [(x0 + x1) / 2, (y0 + y1) / 2, z0]
    height = z1 + (x1 - x0) / 2
    keys = [{"time_s": t, "eye": eye, "target": centre, "up": [0, 0, 1], "fov_deg": 45.0}
            for t, eye in [(0.0, [x0 - (x1 - x0) / 5, y0 - (y1 - y0) / 5, height]),
                           (10.0, [x1 + (x1 - x0) / 5, y0 - (y1 - y0) / 5, height])]]
    path = os.path.join(args.dir, "path.json")
    with open(path, "w") as file:
        json.dump({"format": "relief-camera-path", "version": 1, "keys": keys}, file)
    for workers in (1, 2):
        with LocalCluster(n_workers=workers, threads_per_worker=1) as cluster, Client(cluster):
            warm = os.path.join(args.dir, f"warm-{workers}")
            relief.dask.flythrough(args.heights, path, 2, warm, size=(320, 180),
                                   spacing=args.spacing)
            started = time.perf_counter()
            relief.dask.flythrough(args.heights, path, args.frames,
                                   os.path.join(args.dir, f"frames-{workers}"),
                                   size=(1280, 720), spacing=args.spacing)
            print(f"{workers} worker(s): {time.perf_counter() - started:.2f} s", flush=True)


if __name__ == "__main__":
    main()
