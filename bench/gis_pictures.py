#!/usr/bin/env python3
"""Makes the pictures of docs/gis.md from the Jacksboro fault DEM (the repository's fixture):
`gdaldem hillshade` beside relief's shadow, sky and combined layers, and a map composed in
Python from relief's layers and a colour ramp of the heights.

Run from the repository's root after `cargo build --release` and `python3 -m pip install .`,
with gdal-bin installed (`apt-get install gdal-bin`):
    python3 bench/gis_pictures.py
"""
import subprocess
import tempfile
from pathlib import Path

import numpy as np
import rasterio
from PIL import Image

import relief

DEM = "crates/relief-io/tests/fixtures/jacksboro_fault_dem.tif"
OUT = Path("docs/gis")
RELIEF = "target/release/relief"


def grey(values):
    """0..1 floats (NaN for voids) as an 8-bit grey picture."""
    return Image.fromarray((np.nan_to_num(values, nan=0.0).clip(0, 1) * 255).round().astype(np.uint8))


def main():
    OUT.mkdir(parents=True, exist_ok=True)
    work = Path(tempfile.mkdtemp(prefix="relief-gis-"))
    # 1. gdaldem's hillshade (local slope only), and relief's layers from the command line.
    subprocess.run(["gdaldem", "hillshade", DEM, str(work / "gdaldem.tif"), "-compute_edges", "-s",
                    "111120", "-alt", "20", "-q"],
                   check=True)
    with rasterio.open(work / "gdaldem.tif") as f:
        grey(f.read(1) / 255.0).save(work / "gdaldem-hillshade.png")
    subprocess.run([RELIEF, "shade", DEM, "-o", str(work / "shade.tif"), "--layers",
                    "shadow,sky,hillshade,combined", "--sun", "315,20", "--sky-rays", "64"],
                   check=True)
    with rasterio.open(work / "shade.tif") as f:
        for band, name in enumerate(f.descriptions, start=1):
            grey(f.read(band)).save(work / f"relief-{name}.png")
    names = ["gdaldem-hillshade", "relief-hillshade", "relief-shadow", "relief-sky", "relief-combined"]
    pictures = [Image.open(work / f"{name}.png").convert("L") for name in names]
    gap = 6
    row = Image.new("L", (sum(p.width for p in pictures) + gap * (len(pictures) - 1),
                          max(p.height for p in pictures)), 255)
    x = 0
    for picture in pictures:
        row.paste(picture, (x, 0))
        x += picture.width + gap
    row.save(OUT / "comparison.png")
    # 2. A map composed in Python: a colour ramp of the heights lit by relief's layers.
    heights, georeference = relief.read(DEM)
    layers = relief.shade(heights, georeference, layers=["shadow", "sky", "hillshade"],
                          suns=[(315.0, 20.0)], sun_radius=0.27, sky_rays=64)
    low, high = np.nanmin(heights), np.nanmax(heights)
    t = ((heights - low) / (high - low))[..., None]
    ramp = (1 - t) * np.array([0.42, 0.58, 0.36]) + t * np.array([0.93, 0.87, 0.74])
    light = 0.55 * layers["hillshade"] * layers["shadow"] + 0.45 * layers["sky"]
    picture = (ramp * (0.25 + 0.95 * light[..., None])).clip(0, 1)
    Image.fromarray((picture * 255).round().astype(np.uint8)).save(OUT / "map.png")
    print(f"wrote the pictures into {OUT}")


if __name__ == "__main__":
    main()
