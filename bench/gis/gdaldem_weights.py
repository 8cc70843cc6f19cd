#!/usr/bin/env python3
"""Which weighting `gdaldem hillshade -multidirectional` gives its four suns (azimuths 225, 270,
315 and 360 degrees, 45 degrees up): on tilted planes of known aspect it prints gdaldem's byte
beside 1 + 254 x the weighted Lambert cosine, with each sun weighted by cos^2 and by sin^2 of
(aspect - azimuth), the aspect being the compass direction the slope faces.

    python3 bench/gis/gdaldem_weights.py      (needs gdal-bin, rasterio, numpy)
"""

import math
import subprocess
import tempfile
from pathlib import Path

import numpy as np
import rasterio
from rasterio.transform import from_origin

SUNS = (225.0, 270.0, 315.0, 360.0)


def sun_direction(azimuth_deg, elevation_deg=45.0):
    """Unit vector towards a sun (x east, y north, z up)."""
    a, e = math.radians(azimuth_deg), math.radians(elevation_deg)
    return np.array([math.sin(a) * math.cos(e), math.cos(a) * math.cos(e), math.sin(e)])


def weighted_shade(normal, weight):
    """1 + 254 x the mean of the suns' Lambert cosines, each weighted by weight(aspect - az)."""
    aspect = math.atan2(normal[0], normal[1])
    weights = [weight(aspect - math.radians(az)) for az in SUNS]
    lit = [max(0.0, float(normal @ sun_direction(az))) for az in SUNS]
    return 1 + 254 * sum(w * v for w, v in zip(weights, lit)) / sum(weights)


def gdaldem_on_plane(work, east_gradient, north_gradient):
    """gdaldem's multidirectional byte at the centre of a 10 m plane of the given gradients."""
    cols = np.arange(20) * 10.0
    rows = (19 - np.arange(20)) * 10.0  # row 0 north
    x, y = np.meshgrid(cols, rows)
    dem, out = Path(work) / "plane.tif", Path(work) / "shade.tif"
    with rasterio.open(dem, "w", driver="GTiff", width=20, height=20, count=1, dtype="float32",
                       crs="EPSG:32616", transform=from_origin(0, 200, 10, 10)) as f:
        f.write((east_gradient * x + north_gradient * y).astype(np.float32), 1)
    subprocess.run(["gdaldem", "hillshade", str(dem), str(out), "-multidirectional", "-q"], check=True)
    with rasterio.open(out) as f:
        return int(f.read(1)[10, 10])


def main():
    print("| dz/dx | dz/dy | aspect | gdaldem | cos² weights | sin² weights |")
    print("|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as work:
        for gx, gy in ((0.5, 0.0), (0.0, -0.4), (0.3, 0.3), (-0.2, 0.5)):
            normal = np.array([-gx, -gy, 1.0]) / math.sqrt(1 + gx * gx + gy * gy)
            aspect = math.degrees(math.atan2(normal[0], normal[1])) % 360
            byte = gdaldem_on_plane(work, gx, gy)
            cos2 = weighted_shade(normal, lambda d: math.cos(d) ** 2)
            sin2 = weighted_shade(normal, lambda d: math.sin(d) ** 2)
            print(f"| {gx} | {gy} | {aspect:.1f} | {byte} | {cos2:.1f} | {sin2:.1f} |")


if __name__ == "__main__":
    main()
