#!/usr/bin/env python3
"""Makes the pictures of docs/gis.md from the Jacksboro fault DEM (the repository's fixture):
`gdaldem hillshade` beside relief's shadow, sky and combined layers, a map composed in
Python from relief's layers and a colour ramp of the heights, and one small picture of each
layer of `relief shade` (docs/images/gis/LAYER.png, a colour map with its scale).

Run from the repository's root after `cargo build --release` and `python3 -m pip install .`,
with gdal-bin and matplotlib installed (`apt-get install gdal-bin`, `pip install matplotlib`):
    python3 bench/gis_pictures.py               # every picture
    python3 bench/gis_pictures.py --layers-only # only docs/images/gis/
"""
import argparse
import shutil
import subprocess
import tempfile
from pathlib import Path

import numpy as np
import rasterio
from PIL import Image

import relief

DEM = "crates/relief-io/tests/fixtures/jacksboro_fault_dem.tif"
OUT = Path("docs/gis")
LAYER_PICTURES = Path("docs/images/gis")
# Each layer's colour map, value range (None: the 1st to 99th percentile) and unit.
LAYER_STYLES = {
    "shadow": ("gray", (0, 1), "fraction of the sun seen"),
    "sky": ("gray", None, "sky-view factor"),
    "hillshade": ("gray", (0, 1), "cosine of the sun's incidence"),
    "combined": ("gray", (0, 1), "0..1"),
    "sky-aniso": ("gray", None, "anisotropic sky-view factor"),
    "openness-pos": ("viridis", None, "positive openness, degrees"),
    "openness-neg": ("viridis", None, "negative openness, degrees"),
    "sky-illumination": ("gray", None, "diffuse light, 1 on an open plane"),
    "hillshade-multi": ("gray", (0, 1), "0..1"),
    "insolation": ("inferno", None, "Wh/m² of direct beam, 2026-06-21"),
    "sun-hours": ("inferno", None, "hours of direct sun, 2026-06-21"),
    "horizon-000.0": ("RdBu_r", "symmetric", "horizon angle towards the north, degrees"),
}
PROBE_LAYERS = ["shadow", "sky", "hillshade", "combined", "horizon", "sky-aniso", "openness-pos",
                "openness-neg", "sky-illumination", "hillshade-multi", "insolation", "sun-hours"]
RELIEF = "target/release/relief"


def grey(values):
    """0..1 floats (NaN for voids) as an 8-bit grey picture."""
    return Image.fromarray((np.nan_to_num(values, nan=0.0).clip(0, 1) * 255).round().astype(np.uint8))


def layers_of_this_relief(work):
    """The layers this build of `relief shade` makes (each tried on a small DEM)."""
    tiny = work / "probe.npy"
    np.save(tiny, np.random.default_rng(0).random((9, 9), dtype=np.float32))
    found = []
    for name in PROBE_LAYERS:
        extra = ["--date", "2026-06-21", "--lat", "36", "--lon", "-87"] if name in ("insolation", "sun-hours") else []
        proc = subprocess.run([RELIEF, "shade", str(tiny), "-o", str(work / "probe.tif"), "--layers", name] + extra,
                              capture_output=True)
        if proc.returncode == 0:
            found.append(name)
    return found


def layer_pictures(work):
    """One picture per layer of the real DEM, from the bands of one `relief shade` GeoTIFF."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    LAYER_PICTURES.mkdir(parents=True, exist_ok=True)
    layers = layers_of_this_relief(work)
    # The sun of --sun for most layers; the sun over midsummer day (from --date, which
    # replaces --sun) for insolation and sun hours: two runs.
    over_a_day = [name for name in layers if name in ("insolation", "sun-hours")]
    runs = [([name for name in layers if name not in over_a_day], ["--sun", "315,20"]),
            (over_a_day, ["--date", "2026-06-21", "--step", "15m", "--timezone", "-05:00"])]
    bands = {}
    for run, (names, options) in enumerate(runs):
        if not names:
            continue
        out = work / f"layers{run}.tif"
        subprocess.run([RELIEF, "shade", DEM, "-o", str(out), "--layers", ",".join(names)] + options,
                       check=True)
        with rasterio.open(out) as f:
            bands.update({name: f.read(band) for band, name in enumerate(f.descriptions, start=1)})
    drawn = 0
    for name, values in bands.items():
        if name not in LAYER_STYLES:
            continue
        colour_map, span, unit = LAYER_STYLES[name]
        finite = values[np.isfinite(values)]
        if span is None:
            span = tuple(np.percentile(finite, [1, 99]))
        elif span == "symmetric":
            edge = float(np.percentile(np.abs(finite), 99))
            span = (-edge, edge)
        figure, axes = plt.subplots(figsize=(4.0, 3.9), dpi=100)
        image = axes.imshow(values, cmap=colour_map, vmin=span[0], vmax=span[1], interpolation="nearest")
        axes.set_axis_off()
        axes.set_title(name, fontsize=10)
        bar = figure.colorbar(image, ax=axes, orientation="horizontal", fraction=0.05, pad=0.03)
        bar.set_label(unit, fontsize=8)
        bar.ax.tick_params(labelsize=7)
        # One horizon band stands for the layer: docs/images/gis/horizon.png.
        file_name = "horizon" if name.startswith("horizon-") else name
        figure.savefig(LAYER_PICTURES / f"{file_name}.png", bbox_inches="tight")
        drawn += 1
        plt.close(figure)
        print(f"{name}: {span[0]:.4g} .. {span[1]:.4g} {unit}")
    print(f"wrote {drawn} layer pictures into {LAYER_PICTURES}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--layers-only", action="store_true", help="only the pictures of each layer")
    args = parser.parse_args()
    work = Path(tempfile.mkdtemp(prefix="relief-gis-"))
    try:
        layer_pictures(work)
        if not args.layers_only:
            comparison_and_map(work)
    finally:
        shutil.rmtree(work)


def comparison_and_map(work):
    """gdaldem's hillshade beside relief's layers (docs/gis/comparison.png) and the map composed
    in Python (docs/gis/map.png)."""
    OUT.mkdir(parents=True, exist_ok=True)
    # 1. gdaldem's hillshade (local slope only), and relief's layers from the command line.
    subprocess.run(["gdaldem", "hillshade", DEM, str(work / "gdaldem.tif"), "-compute_edges", "-s",
                    "111120", "-alt", "20", "-q"],
                   check=True)
    with rasterio.open(work / "gdaldem.tif") as f:
        grey(f.read(1) / 255.0).save(work / "gdaldem-hillshade.png")
    subprocess.run([RELIEF, "shade", DEM, "-o", str(work / "shade.tif"), "--layers",
                    "shadow,sky,hillshade,combined", "--sun", "315,20", "--azimuths", "64"],
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
                          suns=[(315.0, 20.0)], sun_radius=0.27, azimuths=32)
    low, high = np.nanmin(heights), np.nanmax(heights)
    t = ((heights - low) / (high - low))[..., None]
    ramp = (1 - t) * np.array([0.42, 0.58, 0.36]) + t * np.array([0.93, 0.87, 0.74])
    light = 0.55 * layers["hillshade"] * layers["shadow"] + 0.45 * layers["sky"]
    picture = (ramp * (0.25 + 0.95 * light[..., None])).clip(0, 1)
    Image.fromarray((picture * 255).round().astype(np.uint8)).save(OUT / "map.png")
    print(f"wrote the pictures into {OUT}")


if __name__ == "__main__":
    main()
