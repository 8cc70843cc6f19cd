#!/usr/bin/env python3
"""relief against Embree on the same surface, the same rays and the same machine, in one run.

For each terrain size this script
  1. generates the seeded fBm terrain with `relief generate fbm`;
  2. runs `relief bench --input` on it (triangles surface; the mipmap tracer, and with
     --tracers any other exact tracer) and `relief render` at the same resolution, for
     relief's throughput, build time, depth images and peak memory;
  3. builds Embree's BVH through Open3D's RaycastingScene over exactly the triangles of the
     `triangles` surface (the lower diagonal of every square) plus the side walls and bottom of
     the solid that relief's surface stands for, in the same world coordinates;
  4. casts exactly the camera rays of relief bench's views (DESIGN.md's camera) and the shadow
     rays from their hits towards the benchmark's sun;
  5. prints, for Embree and relief: build seconds, Mrays/s, peak memory, the ratios, and the
     fraction of pixels whose depth differs by more than 1e-4 relative.

Both sides trace every view --repeat times and report the fastest run: relief bench into one
G-buffer allocated beforehand, Embree through repeated cast_rays / test_occlusions calls.

With --native (the default; skipped when libembree-dev does not install) it then sets native
Embree 3 with packets of 16 beside relief on the same premade rays, alternating runs, and
relief's shading of Embree's hits beside the whole `relief render` (bench/native_anchor.py),
and prints those tables in markdown:

    python3 bench/compare_embree.py --sizes 4096 --res 1920x1080 --tracers mipmap --native

Not part of the tests. Needs the Debian packages libusb-1.0-0 and libgomp1 and the PyPI
packages open3d, plotly, dash and numpy:

    apt-get install -y libusb-1.0-0 libgomp1 && pip install open3d plotly dash numpy
    cargo build --release
    python3 bench/compare_embree.py --sizes 1024 4096 --res 1920x1080

Compare figures only within one run: load on a shared machine changes both sides.
"""

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time

import numpy as np

import native_anchor


def run_child(cmd):
    """Runs cmd and returns its standard output; exits on failure."""
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed:\n{proc.stderr}")
    return proc.stdout


def peak_of(cmd):
    """Runs cmd under GNU time; returns (stdout, the command's own peak resident set in MiB).

    (A child forked from this Python process would count Open3D's pages as its own.)"""
    with tempfile.NamedTemporaryFile(mode="r") as report:
        out = run_child(["/usr/bin/time", "-f", "%M", "-o", report.name] + cmd)
        return out, int(report.read().split()[-1]) / 1024.0


def solid_triangles(h):
    """Vertices and triangles of relief's `triangles` surface of grid h (rows = y), with the
    solid's walls and bottom, at world (col + 0.5, row + 0.5, h) for spacing 1."""
    rows, cols = h.shape
    zmin = float(h.min())
    ys, xs = np.meshgrid(np.arange(rows, dtype=np.float32) + 0.5, np.arange(cols, dtype=np.float32) + 0.5, indexing="ij")
    top = np.stack([xs.ravel(), ys.ravel(), h.astype(np.float32).ravel()], axis=1)
    idx = np.arange(rows * cols, dtype=np.uint32).reshape(rows, cols)
    v00, v10 = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel()
    v01, v11 = idx[1:, :-1].ravel(), idx[1:, 1:].ravel()
    h00, h10 = h[:-1, :-1].ravel(), h[:-1, 1:].ravel()
    h01, h11 = h[1:, :-1].ravel(), h[1:, 1:].ravel()
    main = (h00.astype(np.float64) + h11) <= (h10.astype(np.float64) + h01)
    t1 = np.where(main[:, None], np.stack([v00, v10, v11], 1), np.stack([v00, v10, v01], 1))
    t2 = np.where(main[:, None], np.stack([v00, v11, v01], 1), np.stack([v10, v11, v01], 1))
    tris = [t1, t2]
    # Walls under the four edges and the bottom, as relief's solid has them.
    floor_base = top.shape[0]
    floor = top.copy()
    floor[:, 2] = zmin
    border = [idx[0, :], idx[:, -1], idx[-1, ::-1], idx[::-1, 0]]
    for edge in border:
        a, b = edge[:-1], edge[1:]
        tris.append(np.stack([a + floor_base, b + floor_base, b], 1))
        tris.append(np.stack([a + floor_base, b, a], 1))
    c = [idx[0, 0], idx[0, -1], idx[-1, -1], idx[-1, 0]]
    tris.append(np.array([[c[0], c[2], c[1]], [c[0], c[3], c[2]]], dtype=np.uint32) + floor_base)
    vertices = np.concatenate([top, floor]).astype(np.float32)
    return vertices, np.concatenate(tris).astype(np.uint32)


def ratio(a, b):
    """a / b as a factor: two decimals below 10, none above."""
    r = a / b
    return f"{r:.2f}x" if r < 10 else f"{r:.0f}x"


def camera_rays(cam):
    """DESIGN.md's pinhole camera: unit directions of every pixel, row 0 the top row."""
    eye, target, up = (np.array(cam[k], dtype=np.float64) for k in ("eye", "target", "up"))
    w, h = cam["width"], cam["height"]
    forward = target - eye
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, up)
    right /= np.linalg.norm(right)
    true_up = np.cross(right, forward)
    t = np.tan(np.radians(cam["fov_deg"]) / 2)
    i = (np.arange(w) + 0.5)[None, :]
    j = (np.arange(h) + 0.5)[:, None]
    sx = (2 * i / w - 1) * t * w / h
    sy = (1 - 2 * j / h) * t
    d = forward + sx[..., None] * right + sy[..., None] * true_up
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    return eye, d.reshape(-1, 3)


def sun_direction(azimuth_deg, elevation_deg):
    az, el = np.radians(azimuth_deg), np.radians(elevation_deg)
    return np.array([np.sin(az) * np.cos(el), np.cos(az) * np.cos(el), np.sin(el)])


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[1024, 4096])
    parser.add_argument("--res", default="1920x1080")
    parser.add_argument("--relief", default="target/release/relief")
    parser.add_argument("--work", default=None, help="folder for terrains and depth images")
    parser.add_argument("--tracers", default="mipmap",
                        help="relief tracers, comma-separated (mipmap, naive, cyl_all+cone_all, ...)")
    parser.add_argument("--repeat", type=int, default=3, help="runs per view; the fastest counts")
    parser.add_argument("--native", action=argparse.BooleanOptionalAction, default=True,
                        help="also native Embree (packets of 16) and relief on the same premade rays "
                             "(bench/native_anchor.py); skipped when libembree-dev does not install")
    parser.add_argument("--runs", type=int, default=5,
                        help="native comparison: alternating runs per side; the median counts")
    parser.add_argument("--threads", type=int, default=2, help="native comparison: threads of each side")
    args = parser.parse_args()
    import open3d as o3d  # imported late so --help works without it

    # Without --work, the terrains, depth images and ray files (about 1.4 GB at 4096^2) go to a
    # temporary folder removed at the end.
    temporary = None if args.work else tempfile.TemporaryDirectory(prefix="relief-vs-embree-")
    work = args.work or temporary.name
    os.makedirs(work, exist_ok=True)
    width, height = (int(v) for v in args.res.lower().split("x"))
    print(f"relief vs Embree (Open3D {o3d.__version__}), {args.res}, threads: {os.cpu_count()}, work: {work}")
    rows = []
    natives = {}
    for n in args.sizes:
        terrain = os.path.join(work, f"fbm-{n}.npy")
        run_child([args.relief, "generate", "fbm", "--size", str(n), "--seed", "1", "-o", terrain])
        depth_dir = os.path.join(work, f"depth-{n}")
        bench_out, relief_bench_peak = peak_of([
            args.relief, "bench", "--input", terrain, "--res", args.res, "--tracers", args.tracers,
            "--surfaces", "triangles", "--json", "--depth-dir", depth_dir,
            "--repeat", str(args.repeat)])
        relief = [json.loads(line) for line in bench_out.splitlines() if line.startswith("{")]
        _, relief_render_peak = peak_of([
            args.relief, "render", terrain, "--size", args.res, "-o", os.path.join(work, f"render-{n}.png")])

        h = np.load(terrain).astype(np.float32)
        started = time.perf_counter()
        vertices, triangles = solid_triangles(h)
        scene = o3d.t.geometry.RaycastingScene()
        scene.add_triangles(o3d.core.Tensor(vertices), o3d.core.Tensor(triangles))
        # Open3D builds the BVH lazily, on the first query: include it in the build time.
        scene.cast_rays(o3d.core.Tensor(np.zeros((1, 6), dtype=np.float32)))
        embree_build = time.perf_counter() - started
        del vertices
        embree_views = {}
        native_views = {}
        order = native_anchor.tile_order(width, height) if args.native else None
        for r in relief:
            if r["view"] in embree_views:
                continue
            eye, dirs = camera_rays(r["camera"])
            rays = np.concatenate([np.broadcast_to(eye, dirs.shape), dirs], axis=1).astype(np.float32)
            rays_t = o3d.core.Tensor(rays)
            primary_s = float("inf")
            for _ in range(args.repeat):
                started = time.perf_counter()
                hits = scene.cast_rays(rays_t)
                primary_s = min(primary_s, time.perf_counter() - started)
            t_hit = hits["t_hit"].numpy().astype(np.float64)
            normals = hits["primitive_normals"].numpy().astype(np.float64)
            hit = np.isfinite(t_hit)
            # Shadow rays from the hits, offset along the normal as relief does (1e-5 of the distance).
            facing = np.where((normals * dirs).sum(1, keepdims=True) > 0, -normals, normals)
            with np.errstate(invalid="ignore"):  # misses: inf * 0
                origins = eye + dirs * t_hit[:, None] + facing * (1e-5 * t_hit[:, None])
            sun = sun_direction(r["sun"]["azimuth_deg"], r["sun"]["elevation_deg"])
            shadow = o3d.core.Tensor(
                np.concatenate([origins[hit], np.broadcast_to(sun, (hit.sum(), 3))], 1).astype(np.float32))
            shadow_s = float("inf")
            for _ in range(args.repeat):
                started = time.perf_counter()
                scene.test_occlusions(shadow)
                shadow_s = min(shadow_s, time.perf_counter() - started)
            embree_views[r["view"]] = (t_hit, hit, len(rays) / primary_s / 1e6,
                                       len(shadow) / shadow_s / 1e6)
            if args.native:
                primary_path, shadow_path = native_anchor.write_view_rays(
                    work, r["view"], eye, dirs, t_hit, hit, origins, sun, order)
                depth_name = f"{r['view']}-triangles-{r['tracer']}.npy"
                native_views[r["view"]] = {
                    "primary": primary_path, "shadow": shadow_path, "order": order,
                    "relief_bench_depth": np.load(os.path.join(depth_dir, depth_name)).ravel()}
        embree_peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
        for r in relief:
            t_hit, hit, embree_primary, embree_shadow = embree_views[r["view"]]
            name = f"{r['view']}-triangles-{r['tracer']}.npy"
            depth = np.load(os.path.join(depth_dir, name)).astype(np.float64).ravel()
            both = np.isfinite(depth) & hit
            with np.errstate(invalid="ignore"):
                far_apart = np.abs(depth - t_hit) > 1e-4 * np.maximum(depth, t_hit)
            differ = (np.isfinite(depth) != hit) | (both & far_apart)
            rows.append({
                "size": n, "view": r["view"], "tracer": r["tracer"], "simd": r.get("simd", ""),
                "hit_pct": 100.0 * hit.mean(),
                "embree_build_s": embree_build, "relief_build_s": r["build_ms"] / 1e3,
                "embree_primary": embree_primary,
                "relief_primary": r["primary_rays"] / r["primary_s"] / 1e6,
                "embree_shadow": embree_shadow,
                "relief_shadow": r["shadow_rays"] / r["shadow_s"] / 1e6,
                "embree_peak_mib": embree_peak, "relief_render_peak_mib": relief_render_peak,
                "relief_bench_peak_mib": relief_bench_peak,
                "differ_fraction": differ.mean(),
            })
        del scene
        if args.native:
            native = native_anchor.native_comparison(
                args, work, terrain, h, native_views, width, height, solid_triangles)
            if native is not None:
                natives[n] = native

    header = ("size", "view", "tracer", "hit %", "build s E/r", "ratio", "primary Mr/s E/r", "ratio",
              "shadow Mr/s E/r", "ratio", "peak MiB E/r", "ratio", "depth differs")
    print(" | ".join(header))
    for x in rows:
        print(" | ".join([
            f"{x['size']}", x["view"], x["tracer"], f"{x['hit_pct']:.1f}",
            f"{x['embree_build_s']:.2f} / {x['relief_build_s']:.3f}",
            ratio(x["embree_build_s"], x["relief_build_s"]) if x["relief_build_s"] >= 1e-4 else "none",
            f"{x['embree_primary']:.2f} / {x['relief_primary']:.2f}", f"{x['relief_primary'] / x['embree_primary']:.2f}x",
            f"{x['embree_shadow']:.2f} / {x['relief_shadow']:.2f}", f"{x['relief_shadow'] / x['embree_shadow']:.2f}x",
            f"{x['embree_peak_mib']:.0f} / {x['relief_render_peak_mib']:.0f}",
            f"{x['embree_peak_mib'] / x['relief_render_peak_mib']:.1f}x",
            f"{x['differ_fraction']:.2e}",
        ]))
    for n, native in natives.items():
        native_anchor.print_native_tables(n, native, rows, width, height)
    with open(os.path.join(work, "results.json"), "w") as f:
        json.dump({"open3d": rows, "native": natives}, f, indent=1)


if __name__ == "__main__":
    main()
