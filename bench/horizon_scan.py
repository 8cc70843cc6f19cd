#!/usr/bin/env python3
"""An independent reference for horizon angles and the layers built on them, in NumPy.

Written from the definitions, not from relief's code. The terrain is the `triangles` surface
of the DEM (docs: vertices at the samples; each square between four samples split along the
diagonal whose two end heights have the smaller sum, the diagonal from the south-west corner
to the north-east one on a tie). Along one azimuth the terrain's profile under the observer's
vertical half-plane is piecewise linear, with corners only where the line of sight crosses a
grid line or a square's diagonal. On each straight piece the slope (z(t) - z0) / t seen from
the observer is monotonic in t, so its maximum over the whole profile is attained at one of
those crossings. The scan computes every crossing of the line with every grid line and every
diagonal line (vectorised over all the crossings of all the azimuths of one point), evaluates
the surface there and takes the largest slope: the exact horizon of that surface, to the edge
of the data (no radius), with the observer 0.01 m above the sample. Where no terrain lies
ahead (a sample on the border looking out) the horizon is 0.

From the horizon angles h_k of A azimuths (k * 360 / A degrees clockwise from north):
  - sky-view factor (Zaksek et al. 2011):   SVF = 1 - mean_k sin(max(h_k, 0))
  - positive openness (Yokoyama et al. 2002): 90 - mean_k h_k, in degrees
  - negative openness: the same on the inverted DEM (heights negated, the same triangulation)
  - anisotropic SVF (RVT): sum_k w_k (1 - sin(max(h_k, 0))) / sum_k w_k with
    w_k = (1 - m) cos((az_k - main) / 2)^p + m, main 315 (compass degrees), p 4, m 0.4

Use:
    python3 bench/horizon_scan.py --self-test
    python3 bench/horizon_scan.py DEM.tif --points 60 --seed 1 --azimuths 180 -o ref.json

Rows: the DEM array is as a raster stores it (row 0 north); points are (row, col) of it.
Spacing dx (east-west) and dy (north-south) in metres.
"""

import argparse
import json
import math
import sys

import numpy as np

OBSERVER_HEIGHT = 0.01
# WGS84, for DEMs in degrees (metres per degree at the centre latitude).
WGS84_A = 6378137.0
WGS84_F = 1 / 298.257223563


def metres_per_degree(latitude_deg):
    """Metres per degree of longitude and of latitude at a latitude, on the WGS84 ellipsoid."""
    e2 = WGS84_F * (2 - WGS84_F)
    phi = math.radians(latitude_deg)
    w = math.sqrt(1 - e2 * math.sin(phi) ** 2)
    east = WGS84_A / w * math.cos(phi)  # prime vertical radius times cos(latitude)
    north = WGS84_A * (1 - e2) / w**3  # meridional radius of curvature
    return east * math.pi / 180, north * math.pi / 180


class TriangleSurface:
    """The `triangles` surface of a grid stored row 0 south, sample (c, r) at (c dx, r dy)."""

    def __init__(self, heights_south_up, invert=False):
        h = np.asarray(heights_south_up, dtype=np.float64)
        self.rows, self.cols = h.shape
        # The split of each square, from the heights as given (the inverted DEM keeps it).
        s00, s11 = h[:-1, :-1], h[1:, 1:]
        s10, s01 = h[:-1, 1:], h[1:, :-1]
        self.main_diagonal = (s00 + s11) <= (s10 + s01)  # (c,r)-(c+1,r+1)
        self.z = -h if invert else h

    def height_at(self, c, r):
        """Heights of the surface at grid positions (c, r) (arrays) inside the sample grid."""
        ci = np.clip(np.floor(c).astype(np.int64), 0, self.cols - 2)
        ri = np.clip(np.floor(r).astype(np.int64), 0, self.rows - 2)
        u, v = c - ci, r - ri
        z = self.z
        h00, h10 = z[ri, ci], z[ri, ci + 1]
        h01, h11 = z[ri + 1, ci], z[ri + 1, ci + 1]
        main = self.main_diagonal[ri, ci]
        # Main diagonal: triangles (00,10,11) below u = v and (00,01,11) above it.
        lower = h00 + u * (h10 - h00) + v * (h11 - h10)
        upper = h00 + v * (h01 - h00) + u * (h11 - h01)
        z_main = np.where(u >= v, lower, upper)
        # Anti-diagonal: triangles (00,10,01) below u + v = 1 and (10,01,11) above it.
        near = h00 + u * (h10 - h00) + v * (h01 - h00)
        far = h11 + (1 - u) * (h01 - h11) + (1 - v) * (h10 - h11)
        z_anti = np.where(u + v <= 1, near, far)
        return np.where(main, z_main, z_anti)


def azimuths_deg(count):
    """count directions evenly spaced clockwise from north, in degrees."""
    return np.arange(count) * 360.0 / count


def point_horizons(surface, row_s, col, dx, dy, azimuths, observer_height=OBSERVER_HEIGHT):
    """Horizon angles (radians) from sample (col, row_s) (row_s counted from the south) along
    each compass azimuth in degrees: the largest elevation angle of the surface seen from
    the sample raised by observer_height, to the edge of the data."""
    phi = np.radians(np.asarray(azimuths, dtype=np.float64))
    # Grid units per metre along the line of sight, in c (east) and r (north).
    # Exact zeros along the grid's axes (sin(pi) is 1.2e-16, not 0): a line of sight along a
    # border line runs over the surface's border edge, not off the grid.
    east, north = np.sin(phi), np.cos(phi)
    east[np.abs(east) < 1e-12] = 0.0
    north[np.abs(north) < 1e-12] = 0.0
    sc, sr = east / dx, north / dy
    last_c, last_r = surface.cols - 1, surface.rows - 1
    with np.errstate(divide="ignore", invalid="ignore"):
        exit_c = np.where(sc > 0, (last_c - col) / sc, np.where(sc < 0, col / -sc, np.inf))
        exit_r = np.where(sr > 0, (last_r - row_s) / sr, np.where(sr < 0, row_s / -sr, np.inf))
    t_exit = np.minimum(exit_c, exit_r)
    # Families of lines crossed at every t = j / |rate|: c = k, r = k, c - r = k, c + r = k,
    # and the exit point (rate 1 / t_exit, one crossing).
    rates = np.abs(np.stack([sc, sr, sc - sr, sc + sr], axis=1))
    counts = np.floor(t_exit[:, None] * rates + 1e-9).astype(np.int64)
    counts[rates == 0] = 0
    with np.errstate(divide="ignore", invalid="ignore"):
        rates = np.concatenate([rates, (1.0 / t_exit)[:, None]], axis=1)
    counts = np.concatenate([counts, (t_exit > 0).astype(np.int64)[:, None]], axis=1)
    flat_counts = counts.ravel()  # azimuth-major: each azimuth's crossings are contiguous
    total = int(flat_counts.sum())
    starts = np.cumsum(flat_counts) - flat_counts
    j = np.arange(total) - np.repeat(starts, flat_counts) + 1
    t = j / np.repeat(rates.ravel(), flat_counts)
    which = np.repeat(np.repeat(np.arange(len(phi)), rates.shape[1]), flat_counts)
    t = np.minimum(t, t_exit[which])
    c = np.clip(col + t * sc[which], 0, last_c)
    r = np.clip(row_s + t * sr[which], 0, last_r)
    z0 = surface.z[row_s, col] + observer_height
    slope = (surface.height_at(c, r) - z0) / t
    per_azimuth = counts.sum(axis=1)
    best = np.zeros(len(phi))
    has = per_azimuth > 0
    if total:
        offsets = np.cumsum(per_azimuth) - per_azimuth
        maxima = np.maximum.reduceat(slope, offsets[has])
        best[has] = np.arctan(maxima)
    return best


def horizons(dem, dx, dy, points, azimuth_count=180, observer_height=OBSERVER_HEIGHT, invert=False):
    """Horizon angles (radians), shape (points, azimuths), of a raster DEM (row 0 north) at
    points given as (row, col) of the raster."""
    south_up = np.asarray(dem, dtype=np.float64)[::-1]
    surface = TriangleSurface(south_up, invert=invert)
    az = azimuths_deg(azimuth_count)
    out = np.empty((len(points), azimuth_count))
    for i, (row, col) in enumerate(points):
        row_s = surface.rows - 1 - int(row)
        out[i] = point_horizons(surface, row_s, int(col), dx, dy, az, observer_height)
    return out


def sky_view_factor(h):
    """Zaksek et al. 2011: 1 - mean over azimuths of sin(max(h, 0)); h in radians, (..., A)."""
    return 1.0 - np.mean(np.sin(np.maximum(h, 0.0)), axis=-1)


def openness(h):
    """Yokoyama et al. 2002 with unlimited radius: 90 - mean horizon angle, in degrees."""
    return 90.0 - np.degrees(np.mean(h, axis=-1))


def anisotropy_weights(azimuth_count, main_deg=315.0, poly_level=4, min_weight=0.4):
    """RVT's anisotropy weights of the azimuths (compass degrees): (1 - m) cos((a - main)/2)^p + m."""
    a = np.radians(azimuths_deg(azimuth_count))
    return (1 - min_weight) * np.cos((a - np.radians(main_deg)) / 2) ** poly_level + min_weight


def anisotropic_sky_view_factor(h, main_deg=315.0, poly_level=4, min_weight=0.4):
    """RVT's anisotropic SVF: the weighted mean of 1 - sin(max(h, 0)) over the azimuths."""
    w = anisotropy_weights(h.shape[-1], main_deg, poly_level, min_weight)
    return np.sum((1.0 - np.sin(np.maximum(h, 0.0))) * w, axis=-1) / w.sum()


def reference_layers(dem, dx, dy, points, azimuth_count=180):
    """Every reference layer at the points: sky, sky-aniso, openness-pos, openness-neg (and
    the horizons in degrees, shape (points, azimuths))."""
    up = horizons(dem, dx, dy, points, azimuth_count)
    down = horizons(dem, dx, dy, points, azimuth_count, invert=True)
    return {
        "sky": sky_view_factor(up),
        "sky-aniso": anisotropic_sky_view_factor(up),
        "openness-pos": openness(up),
        "openness-neg": openness(down),
        "horizon_deg": np.degrees(up),
    }


def random_points(shape, count, seed):
    """count distinct (row, col) samples of a raster of shape, drawn uniformly with a seed."""
    rng = np.random.default_rng(seed)
    flat = rng.choice(shape[0] * shape[1], size=count, replace=False)
    return [(int(i // shape[1]), int(i % shape[1])) for i in flat]


def read_dem(path):
    """A GeoTIFF's first band (row 0 north, float64, NaN for nodata) and its metric spacing
    (dx, dy): the transform's for a projected CRS, WGS84 metres at the centre latitude for a
    geographic one."""
    import rasterio

    with rasterio.open(path) as f:
        dem = f.read(1).astype(np.float64)
        if f.nodata is not None:
            dem[dem == f.nodata] = np.nan
        dx, dy = abs(f.transform.a), abs(f.transform.e)
        if f.crs is not None and f.crs.is_geographic:
            centre = f.bounds.bottom + 0.5 * (f.bounds.top - f.bounds.bottom)
            east, north = metres_per_degree(centre)
            dx, dy = dx * east, dy * north
        elif f.crs is not None and f.crs.linear_units_factor is not None:
            unit = f.crs.linear_units_factor[1]
            dx, dy = dx * unit, dy * unit
    return dem, dx, dy


# --- self-test: analytic cases and an independent edge-by-edge check ----------------------


def edge_scan(south_up, dx, dy, row_s, col, azimuth, observer_height=OBSERVER_HEIGHT, split_by=None):
    """Brute force over every edge of every triangle: the horizon slope along one azimuth,
    from the 3D edges' crossings with the vertical half-plane (no grid look-ups). The squares
    are split by the heights split_by (the heights themselves unless given)."""
    h = np.asarray(south_up, dtype=np.float64)
    g = h if split_by is None else np.asarray(split_by, dtype=np.float64)
    rows, cols = h.shape
    phi = math.radians(azimuth)
    d = np.array([math.sin(phi), math.cos(phi)])
    p0 = np.array([col * dx, row_s * dy])
    z0 = h[row_s, col] + observer_height
    best = -math.inf
    found = False
    for r in range(rows - 1):
        for c in range(cols - 1):
            corners = {(0, 0): h[r, c], (1, 0): h[r, c + 1], (0, 1): h[r + 1, c], (1, 1): h[r + 1, c + 1]}
            if g[r, c] + g[r + 1, c + 1] <= g[r, c + 1] + g[r + 1, c]:
                edges = [((0, 0), (1, 0)), ((1, 0), (1, 1)), ((1, 1), (0, 1)), ((0, 1), (0, 0)), ((0, 0), (1, 1))]
            else:
                edges = [((0, 0), (1, 0)), ((1, 0), (1, 1)), ((1, 1), (0, 1)), ((0, 1), (0, 0)), ((1, 0), (0, 1))]
            for a, b in edges:
                pa = np.array([(c + a[0]) * dx, (r + a[1]) * dy])
                pb = np.array([(c + b[0]) * dx, (r + b[1]) * dy])
                e = pb - pa
                m = np.array([[d[0], -e[0]], [d[1], -e[1]]])
                det = np.linalg.det(m)
                if abs(det) < 1e-12:
                    # Parallel: the edge's end points, where they lie on the line of sight.
                    for q, zq in ((pa, corners[a]), (pb, corners[b])):
                        w = q - p0
                        t = float(w @ d)
                        if t > 1e-9 and abs(w[0] * d[1] - w[1] * d[0]) < 1e-9 * max(dx, dy):
                            best, found = max(best, (zq - z0) / t), True
                    continue
                t, s = np.linalg.solve(m, pa - p0)
                if t > 1e-9 and -1e-12 <= s <= 1 + 1e-12:
                    z = corners[a] + s * (corners[b] - corners[a])
                    best, found = max(best, (z - z0) / t), True
    return math.atan(best) if found else 0.0


def self_test():
    """Checks the scan on analytic cases and against the edge-by-edge brute force."""
    failures = []

    def check(name, got, want, tol):
        err = float(np.max(np.abs(np.asarray(got) - np.asarray(want))))
        status = "ok" if err <= tol else "FAILED"
        print(f"{status:6} {name}: max |error| {err:.3e} (tolerance {tol:g})")
        if err > tol:
            failures.append(name)

    # 1. A flat plane: the horizon is the far edge's depression under the raised observer,
    # atan(-0.01 / t_exit); SVF 1; openness 90 degrees (within that depression).
    rows, cols, dx, dy = 41, 61, 10.0, 7.5
    flat = np.full((rows, cols), 123.0)
    pts = [(20, 30), (3, 55), (40, 0)]
    az = azimuths_deg(36)
    h = horizons(flat, dx, dy, pts, 36)
    want = np.empty_like(h)
    for i, (row, col) in enumerate(pts):
        row_s = rows - 1 - row
        phi = np.radians(az)
        sc, sr = np.sin(phi) / dx, np.cos(phi) / dy
        with np.errstate(divide="ignore", invalid="ignore"):
            ec = np.where(sc > 1e-15, (cols - 1 - col) / sc, np.where(sc < -1e-15, col / -sc, np.inf))
            er = np.where(sr > 1e-15, (rows - 1 - row_s) / sr, np.where(sr < -1e-15, row_s / -sr, np.inf))
        te = np.minimum(ec, er)
        want[i] = np.where(te > 0, np.arctan(-OBSERVER_HEIGHT / np.where(te > 0, te, 1)), 0.0)
    check("flat plane: horizon = atan(-0.01 / distance to the edge)", h, want, 1e-12)
    check("flat plane: SVF = 1", sky_view_factor(h), 1.0, 1e-15)
    check("flat plane: openness = 90 deg + the mean depression", openness(h),
          90.0 - np.degrees(want.mean(axis=1)), 1e-12)
    check("flat plane: negative openness the same",
          openness(horizons(flat, dx, dy, pts, 36, invert=True)), openness(h), 1e-12)

    # 2. A cylindrical pit of radius R and depth D in a plane, seen from its centre: along the
    # grid lines the wall ends at the first sample beyond R, k cells out; elsewhere the
    # horizon lies between atan((D - 0.01) / (R + one diagonal)) and atan((D - 0.01) / R).
    n, cell, radius, depth = 81, 2.0, 17.0, 9.0
    yy, xx = np.mgrid[0:n, 0:n]
    centre = n // 2
    dist = np.hypot((xx - centre) * cell, (yy - centre) * cell)
    pit = np.where(dist <= radius, -depth, 0.0)
    h = horizons(pit, cell, cell, [(centre, centre)], 72)[0]
    k = math.floor(radius / cell) + 1
    axis = [0, 18, 36, 54]  # 0, 90, 180, 270 degrees of 72 azimuths
    check("pit: horizon along the grid lines = atan((D - 0.01) / (k dx))", h[axis],
          math.atan((depth - OBSERVER_HEIGHT) / (k * cell)), 1e-12)
    low = math.atan((depth - OBSERVER_HEIGHT) / (radius + cell * math.sqrt(2)))
    high = math.atan((depth - OBSERVER_HEIGHT) / radius)
    inside = float(np.mean((h >= low - 1e-12) & (h <= high + 1e-12)))
    check("pit: every horizon between the rim's bounds (fraction outside)", 1 - inside, 0.0, 0.0)
    check("pit: SVF between 1 - sin of the bounds", 0.0 if 1 - math.sin(high) <= sky_view_factor(h)
          <= 1 - math.sin(low) else 1.0, 0.0, 0.0)
    # Negative openness at the centre of a pit: the inverted pit is a mesa, seen from its top
    # the terrain only falls away, so every horizon is below 0 and openness above 90.
    down = horizons(pit, cell, cell, [(centre, centre)], 72, invert=True)[0]
    check("pit: inverted horizons all below 0 (count above)", np.sum(down >= 0), 0, 0)

    # 3. An infinite slope z = s y (rising north) on cells of dx != dy: the profile along azimuth
    # phi is straight, z0' + s cos(phi) t, so the horizon is atan(s cos(phi) - 0.01 / t_exit).
    rows, cols, dx, dy, s = 51, 71, 5.0, 8.0, 0.3
    plane = s * (rows - 1 - np.arange(rows))[:, None] * dy + np.zeros((1, cols))
    row, col = 25, 35
    h = horizons(plane, dx, dy, [(row, col)], 64)[0]
    phi = np.radians(azimuths_deg(64))
    sc, sr = np.sin(phi) / dx, np.cos(phi) / dy
    row_s = rows - 1 - row
    with np.errstate(divide="ignore", invalid="ignore"):
        ec = np.where(sc > 1e-15, (cols - 1 - col) / sc, np.where(sc < -1e-15, col / -sc, np.inf))
        er = np.where(sr > 1e-15, (rows - 1 - row_s) / sr, np.where(sr < -1e-15, row_s / -sr, np.inf))
    te = np.minimum(ec, er)
    check("slope: horizon = atan(s cos(az) - 0.01 / t_exit)", h,
          np.arctan(s * np.cos(phi) - OBSERVER_HEIGHT / te), 1e-12)
    check("slope: SVF = 1 - mean sin(max(atan(s cos az), 0)) (within the lift)", sky_view_factor(h),
          1 - np.mean(np.sin(np.maximum(np.arctan(s * np.cos(phi)), 0))), 1e-4)

    # 4. Random rough terrains (cliffs, spikes, ties of the diagonal sums): the vectorised scan
    # against the edge-by-edge brute force, both diagonals of every square in use.
    rng = np.random.default_rng(7)
    for trial in range(3):
        rows, cols = rng.integers(6, 11, size=2)
        dem = rng.normal(0, 5, size=(rows, cols)).round(1)
        dem[rng.random((rows, cols)) < 0.1] += 30.0  # spikes and cliffs
        dx, dy = float(rng.uniform(1, 20)), float(rng.uniform(1, 20))
        pts = random_points(dem.shape, 6, seed=trial)
        az = np.concatenate([azimuths_deg(24), rng.uniform(0, 360, 8)])
        south_up = dem[::-1]
        surface = TriangleSurface(south_up)
        for row, col in pts:
            row_s = rows - 1 - row
            fast = point_horizons(surface, row_s, col, dx, dy, az)
            slow = [edge_scan(south_up, dx, dy, row_s, col, a) for a in az]
            check(f"random terrain {trial}, point ({row}, {col}): scan = edge-by-edge", fast, slow, 1e-9)
        inverted = TriangleSurface(south_up, invert=True)
        row, col = pts[0]
        fast = point_horizons(inverted, rows - 1 - row, col, dx, dy, az)
        # The inverted DEM keeps the original's split of the squares.
        slow = [edge_scan(-south_up, dx, dy, rows - 1 - row, col, a, split_by=south_up) for a in az]
        check(f"random terrain {trial}, inverted: scan = edge-by-edge", fast, slow, 1e-9)

    # 5. RVT's anisotropy weights: 1 towards the main direction, the minimum weight opposite.
    w = anisotropy_weights(8)
    check("anisotropy weights at 315 and 135 degrees", [w[7], w[3]], [1.0, 0.4], 1e-12)
    print(f"{'all passed' if not failures else f'{len(failures)} FAILED'}")
    return 0 if not failures else 1


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("dem", nargs="?", help="a GeoTIFF DEM")
    parser.add_argument("--self-test", action="store_true", help="run the analytic checks")
    parser.add_argument("--points", type=int, default=60)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--azimuths", type=int, default=180)
    parser.add_argument("-o", "--output", help="JSON of the points and their reference layers")
    args = parser.parse_args()
    if args.self_test:
        return self_test()
    if not args.dem:
        parser.error("give a DEM or --self-test")
    dem, dx, dy = read_dem(args.dem)
    points = random_points(dem.shape, args.points, args.seed)
    layers = reference_layers(dem, dx, dy, points, args.azimuths)
    result = {"dem": args.dem, "dx": dx, "dy": dy, "azimuths": args.azimuths, "points": points,
              **{k: np.asarray(v).tolist() for k, v in layers.items()}}
    text = json.dumps(result)
    if args.output:
        with open(args.output, "w") as f:
            f.write(text)
    else:
        print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
