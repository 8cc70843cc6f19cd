"""Native Embree beside relief, fair on both sides: the second anchor of bench/compare_embree.py.

Issue 37's "The anchors": native Embree 3 (Debian's libembree-dev) with packets of 16
(rtcIntersect16 / rtcOccluded16, coherent context, high build quality, non-robust) on the same
triangles as the Open3D anchor, relief's walls included, and the same premade rays.

- Premade rays: the camera rays of relief bench's views and the shadow rays from Open3D's hits
  towards the benchmark's sun, as compare_embree.py makes them, written as raw float32 (six a
  ray) in relief's tile order (16x16 tiles left to right, top to bottom, Morton inside a tile),
  so that 16 consecutive rays are a 4x4 block of pixels and 256 a tile.
- bench/embree_native.c traces them; crates/relief-bench/benches/trace_rays.rs traces the same
  files through relief's mipmap tracer (batches of 256 with rayon). Both read and allocate
  before the clock, write distance and normal (or occlusion) into preallocated buffers, use the
  same thread count, and run alternately (relief, Embree, relief, Embree, ...); each figure is
  the median of the runs with their spread (min..max).
- crates/relief-bench/benches/shade_hits.rs shades Embree's hits with relief's deferred pass
  (no shadows, `relief render`'s light) and writes the PNG, for "native Embree plus the same
  shading" against the whole `relief render` beyond a 192x108 render.

The harness is compiled with gcc into target/; libembree-dev is installed with apt-get when
its headers are missing. Nothing here is a dependency of relief.
"""

import json
import os
import resource
import subprocess
import sys
import time

import numpy as np

HARNESS_SOURCE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "embree_native.c")
TILE = 16


def build_harness(out_dir):
    """Installs libembree-dev if needed and compiles bench/embree_native.c into out_dir;
    returns the binary's path, or None (with the reason on stderr) when either fails."""
    if not os.path.exists("/usr/include/embree3/rtcore.h"):
        for cmd in (["apt-get", "update"], ["apt-get", "install", "-y", "libembree-dev"]):
            if subprocess.run(cmd, capture_output=True).returncode != 0:
                print(f"native Embree skipped: {' '.join(cmd)} failed", file=sys.stderr)
                return None
    os.makedirs(out_dir, exist_ok=True)
    binary = os.path.join(out_dir, "embree_native")
    cmd = ["gcc", "-O3", "-march=native", "-fopenmp", HARNESS_SOURCE, "-lembree3", "-lm", "-o", binary]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        print(f"native Embree skipped: {' '.join(cmd)} failed:\n{proc.stderr}", file=sys.stderr)
        return None
    return binary


def tile_order(width, height):
    """Row-major pixel indices in relief's renderer order: 16x16 tiles row by row, Morton
    inside a tile (x in the even bits, as relief_shade's MORTON), clipped to the image."""
    k = np.arange(TILE * TILE)
    morton = np.zeros((TILE, TILE), dtype=np.int64)
    i = sum(((k >> (2 * b)) & 1) << b for b in range(4))
    j = sum(((k >> (2 * b + 1)) & 1) << b for b in range(4))
    morton[j, i] = k
    ys, xs = np.meshgrid(np.arange(height), np.arange(width), indexing="ij")
    tiles_across = (width + TILE - 1) // TILE
    key = ((ys // TILE) * tiles_across + xs // TILE) * TILE * TILE + morton[ys % TILE, xs % TILE]
    return np.argsort(key.ravel(), kind="stable")


def write_rays(path, origins, directions):
    """Writes rays as raw float32, six a ray."""
    np.concatenate([origins, directions], axis=1).astype(np.float32).tofile(path)


def write_view_rays(folder, view, eye, dirs, t_hit, hit, origins, sun, order):
    """Writes a view's camera rays and the shadow rays of its hits (from `origins`, towards
    `sun`), both in tile order; returns the two paths."""
    primary = os.path.join(folder, f"{view}-primary.f32")
    shadow = os.path.join(folder, f"{view}-shadow.f32")
    write_rays(primary, np.broadcast_to(eye, dirs.shape)[order], dirs[order])
    lit = hit[order]
    write_rays(shadow, origins[order][lit], np.broadcast_to(sun, (int(lit.sum()), 3)))
    return primary, shadow


class LineProgram:
    """A benchmark program that prints a JSON line after starting and one per command."""

    def __init__(self, cmd):
        self.cmd = cmd
        self.proc = subprocess.Popen(cmd, stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True, bufsize=1)
        self.started = self._reply()

    def _reply(self):
        while True:
            line = self.proc.stdout.readline()
            if not line:
                sys.exit(f"{' '.join(self.cmd)} ended early (exit {self.proc.wait()})")
            if line.startswith("{"):
                return json.loads(line)

    def run(self, kind, rays, out="-"):
        """One timed run of kind over the ray file rays; its JSON line."""
        self.proc.stdin.write(f"{kind} {rays} {out}\n")
        return self._reply()

    def close(self):
        self.proc.stdin.close()
        self.proc.wait()


def summary(runs, threads):
    """Median and spread of a list of runs' JSON lines; cpu_mrays is the rate from the median
    CPU seconds of all threads, as if the threads had the cores to themselves."""
    rays = runs[0]["rays"]
    rates = sorted(rays / r["seconds"] / 1e6 for r in runs)
    seconds = sorted(r["seconds"] for r in runs)
    cpu = sorted(r["cpu_seconds"] for r in runs)
    return {"rays": rays, "mrays": rates[len(rates) // 2], "min": rates[0], "max": rates[-1],
            "median_s": seconds[len(seconds) // 2], "runs": len(runs),
            "cpu_mrays": rays * threads / cpu[len(cpu) // 2] / 1e6}


def read_tile_ordered(path, order, dtype=np.float32, width=1):
    """A tile-ordered raw output file back in row-major pixel order."""
    values = np.fromfile(path, dtype=dtype).reshape(len(order), width)
    row_major = np.empty_like(values)
    row_major[order] = values
    return row_major.squeeze()


def depth_differs(a, b):
    """The fraction of pixels whose depths differ: hit against miss, or more than 1e-4
    relative."""
    a, b = a.astype(np.float64), b.astype(np.float64)
    both = np.isfinite(a) & np.isfinite(b)
    with np.errstate(invalid="ignore"):
        far = np.abs(a - b) > 1e-4 * np.maximum(a, b)
    return float(((np.isfinite(a) != np.isfinite(b)) | (both & far)).mean())


def children_cpu_seconds():
    """User and system seconds of the finished children of this process."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def timed_wall(cmd):
    """Wall and CPU seconds cmd takes; exits on failure."""
    cpu_started, started = children_cpu_seconds(), time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed:\n{proc.stderr}")
    return time.perf_counter() - started, children_cpu_seconds() - cpu_started


def median(values):
    return sorted(values)[len(values) // 2]


def whole_render(relief, terrain, width, height, runs, folder):
    """`relief render --no-shadows` at 192x108 and width x height, alternately, runs times
    each: medians and the rate of the rays beyond the small render."""
    times = {"192x108": [], f"{width}x{height}": []}
    png = os.path.join(folder, "render.png")
    for _ in range(runs):
        for size, runs_of_size in times.items():
            runs_of_size.append(timed_wall([relief, "render", terrain, "--size", size, "--no-shadows", "-o", png]))
    small, large = times.values()
    beyond = median([t for t, _ in large]) - median([t for t, _ in small])
    cpu_beyond = median([c for _, c in large]) - median([c for _, c in small])
    pixels = width * height - 192 * 108
    return {"small_s": median([t for t, _ in small]), "large_s": median([t for t, _ in large]),
            "beyond_s": beyond, "mrays": pixels / beyond / 1e6, "cpu_beyond_s": cpu_beyond,
            "large_spread": (min(large)[0], max(large)[0]), "small_spread": (min(small)[0], max(small)[0])}


def native_comparison(args, work, terrain, h, views, width, height, solid_triangles):
    """Runs the native Embree harness and relief's trace_rays alternately on every view's
    premade rays, shades Embree's hits, times the whole render; returns the results."""
    binary = build_harness(os.path.join("target", "embree-native"))
    if binary is None:
        return None
    folder = os.path.join(work, "native")
    os.makedirs(folder, exist_ok=True)
    vertices, triangles = solid_triangles(h)
    vertices_path, triangles_path = os.path.join(folder, "vertices.f32"), os.path.join(folder, "triangles.u32")
    vertices.astype(np.float32).tofile(vertices_path)
    triangles.astype(np.uint32).tofile(triangles_path)
    del vertices, triangles
    threads = str(args.threads)
    embree = LineProgram([binary, vertices_path, triangles_path, threads])
    relief = LineProgram(["cargo", "bench", "-q", "-p", "relief-bench", "--bench", "trace_rays", "--",
                          terrain, threads])
    results = {"threads": args.threads,
               "embree_build_s": embree.started["seconds"], "relief_build_s": relief.started["seconds"],
               "embree_version": embree.started["embree"], "views": {}}
    for view, v in views.items():
        runs = {"relief primary": [], "embree primary": [], "relief shadow": [], "embree shadow": [],
                "embree single": []}
        for kind in ("primary", "shadow"):
            rays = v[kind]
            for k in range(args.runs):
                first = k == 0
                runs[f"relief {kind}"].append(relief.run(kind, rays, os.path.join(folder, f"{view}-relief") if first else "-"))
                runs[f"embree {kind}"].append(embree.run(kind, rays, os.path.join(folder, f"{view}-embree") if first else "-"))
        for _ in range(args.runs):
            runs["embree single"].append(embree.run("single", v["primary"]))
        order = v["order"]
        embree_depth = read_tile_ordered(os.path.join(folder, f"{view}-embree.distance.f32"), order)
        relief_depth = read_tile_ordered(os.path.join(folder, f"{view}-relief.distance.f32"), order)
        normals = read_tile_ordered(os.path.join(folder, f"{view}-embree.normal.f32"), order, width=3)
        distance_path = os.path.join(folder, f"{view}-embree-rows.distance.f32")
        normal_path = os.path.join(folder, f"{view}-embree-rows.normal.f32")
        embree_depth.astype(np.float32).tofile(distance_path)
        normals.astype(np.float32).tofile(normal_path)
        row = {kind: summary(r, args.threads) for kind, r in runs.items()}
        row["embree_vs_relief_bench_differ"] = depth_differs(embree_depth, v["relief_bench_depth"])
        row["embree_vs_relief_premade_differ"] = depth_differs(embree_depth, relief_depth)
        row["shadow_blocked_differ"] = float(
            (np.fromfile(os.path.join(folder, f"{view}-embree.occluded.u8"), dtype=np.uint8)
             != np.fromfile(os.path.join(folder, f"{view}-relief.occluded.u8"), dtype=np.uint8)).mean())
        row["embree_peak_mib"] = runs["embree single"][-1]["peak_mib"]
        row["relief_peak_mib"] = runs["relief shadow"][-1]["peak_mib"]
        row["shade"] = json.loads(subprocess.run(
            ["cargo", "bench", "-q", "-p", "relief-bench", "--bench", "shade_hits", "--", terrain, view,
             f"{width}x{height}", distance_path, normal_path, str(args.runs), os.path.join(folder, f"{view}-embree.png")],
            capture_output=True, text=True, check=True).stdout.strip().splitlines()[-1])
        results["views"][view] = row
    embree.close()
    relief.close()
    results["whole_render"] = whole_render(args.relief, terrain, width, height, args.runs, folder)
    return results


def spread_text(s):
    return f"{s['mrays']:.1f} ({s['min']:.1f}..{s['max']:.1f})"


def print_native_tables(n, native, open3d_rows, width, height):
    """Prints the native comparison of terrain size n as markdown tables."""
    by_view = {r["view"]: r for r in open3d_rows if r["size"] == n}
    print(f"\n### {n}^2, {width}x{height}: native Embree {native['embree_version']} (packets of 16) "
          f"and Open3D against relief, Mrays/s, median of the runs (min..max)\n")
    print("| view | Open3D primary / shadow | Embree16 primary | Embree16 shadow | Embree1 primary "
          "| relief bench primary / shadow | relief premade primary | relief premade shadow "
          "| primary: bench / E16, premade / E16, bench / Open3D | shadow: bench / E16, premade / E16, bench / Open3D "
          "| depth differs E16 vs relief bench, premade | shadow answers differ |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for view, v in native["views"].items():
        o = by_view[view]
        e16p, e16s = v["embree primary"]["mrays"], v["embree shadow"]["mrays"]
        rp, rs = v["relief primary"]["mrays"], v["relief shadow"]["mrays"]
        print(f"| {view} | {o['embree_primary']:.1f} / {o['embree_shadow']:.1f} "
              f"| {spread_text(v['embree primary'])} | {spread_text(v['embree shadow'])} "
              f"| {spread_text(v['embree single'])} "
              f"| {o['relief_primary']:.1f} / {o['relief_shadow']:.1f} "
              f"| {spread_text(v['relief primary'])} | {spread_text(v['relief shadow'])} "
              f"| {o['relief_primary'] / e16p:.2f}x, {rp / e16p:.2f}x, {o['relief_primary'] / o['embree_primary']:.2f}x "
              f"| {o['relief_shadow'] / e16s:.2f}x, {rs / e16s:.2f}x, {o['relief_shadow'] / o['embree_shadow']:.2f}x "
              f"| {v['embree_vs_relief_bench_differ']:.2e}, {v['embree_vs_relief_premade_differ']:.2e} "
              f"| {v['shadow_blocked_differ']:.2e} |")
    print("\nThe same runs as rays per CPU second of all threads, times the thread count (what the "
          "threads would reach with the cores to themselves; less sensitive to other load):\n")
    print("| view | Embree16 primary | Embree16 shadow | Embree1 primary | relief premade primary "
          "| relief premade shadow | primary relief / E16 | shadow relief / E16 |")
    print("|---|---|---|---|---|---|---|---|")
    for view, v in native["views"].items():
        c = {kind: v[kind]["cpu_mrays"] for kind in v if isinstance(v[kind], dict) and "cpu_mrays" in v[kind]}
        print(f"| {view} | {c['embree primary']:.1f} | {c['embree shadow']:.1f} | {c['embree single']:.1f} "
              f"| {c['relief primary']:.1f} | {c['relief shadow']:.1f} "
              f"| {c['relief primary'] / c['embree primary']:.2f}x | {c['relief shadow'] / c['embree shadow']:.2f}x |")
    first = next(iter(native["views"].values()))
    o = next(iter(by_view.values()))
    print("\n| | Open3D | native Embree16 | relief (bench) | relief (premade rays) |")
    print("|---|---|---|---|---|")
    print(f"| build s | {o['embree_build_s']:.2f} | {native['embree_build_s']:.2f} "
          f"| {o['relief_build_s']:.3f} | {native['relief_build_s']:.3f} |")
    print(f"| peak MiB | {o['embree_peak_mib']:.0f} (Python process) | {first['embree_peak_mib']:.0f} "
          f"| {o['relief_bench_peak_mib']:.0f} (render {o['relief_render_peak_mib']:.0f}) "
          f"| {first['relief_peak_mib']:.0f} |")
    w = native["whole_render"]
    print(f"\n`relief render --no-shadows`, {width}x{height} minus 192x108 (medians): "
          f"{w['large_s']:.3f} s - {w['small_s']:.3f} s = {w['beyond_s']:.3f} s, {w['mrays']:.1f} Mrays/s\n")
    print("| view | Embree16 cast s | relief shading s | PNG s | Embree16 + shading Mr/s "
          "| relief render / (Embree16 + shading) | relief render / Open3D cast |")
    print("|---|---|---|---|---|---|---|")
    for view, v in native["views"].items():
        cast, shade, png = v["embree primary"]["median_s"], v["shade"]["shade"]["median_s"], v["shade"]["png"]["median_s"]
        rate = v["embree primary"]["rays"] / (cast + shade + png) / 1e6
        print(f"| {view} | {cast:.3f} | {shade:.3f} | {png:.3f} | {rate:.1f} | {w['mrays'] / rate:.2f}x "
              f"| {w['mrays'] / by_view[view]['embree_primary']:.2f}x |")
    threads = native["threads"]
    relief_cpu_rate = (width * height - 192 * 108) * threads / w["cpu_beyond_s"] / 1e6
    print(f"\nPer CPU second of all threads times {threads}: `relief render` beyond 192x108 "
          f"{w['cpu_beyond_s']:.3f} CPU s, {relief_cpu_rate:.1f} Mrays/s\n")
    print("| view | Embree16 cast CPU s | shading CPU s | PNG CPU s | Embree16 + shading Mr/s "
          "| relief render / (Embree16 + shading) |")
    print("|---|---|---|---|---|---|")
    for view, v in native["views"].items():
        cast = v["embree primary"]["rays"] * threads / v["embree primary"]["cpu_mrays"] / 1e6
        shade, png = v["shade"]["shade"]["cpu_median_s"], v["shade"]["png"]["cpu_median_s"]
        rate = v["embree primary"]["rays"] * threads / (cast + shade + png) / 1e6
        print(f"| {view} | {cast:.3f} | {shade:.3f} | {png:.3f} | {rate:.1f} | {relief_cpu_rate / rate:.2f}x |")
