#!/usr/bin/env python3
"""Makes the picture of docs/tiles.md, "Ortho photos: texture pyramid and anisotropic
filtering": a generated DEM of gentle hills (1024 x 1024 samples of 1 m) under a generated
photo of 2 m checks (4096 x 4096 pixels of 0.25 m, tinted slowly across the terrain), tiled
into a store with its texture pyramid, rendered from 28 m above the ground looking across it
with `--texture-filter bilinear` and with `anisotropic` (the default), side by side, with
enlarged crops of the middle distance below. Prints the renders' stage timings as a table.

Run from the repository's root after `cargo build --release`, with numpy and Pillow:
    python3 bench/tiles_texture.py
"""
import json
import subprocess
import tempfile
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw, ImageFont

RELIEF = "target/release/relief"
OUT = Path("docs/tiles")
VIEW = ["--eye", "120,60,28", "--target", "620,700,0", "--fov", "55", "--size", "960x540"]
# The enlarged crop: x, y, width, height of the rendered picture, and its zoom.
CROP, ZOOM = (330, 250, 240, 90), 2


def make_inputs(work):
    """The DEM (.npy, spacing 1) and the photo (PNG, spanning the DEM exactly)."""
    n = 1024
    y, x = np.mgrid[0:n, 0:n].astype(np.float64)
    heights = 10 * np.sin(x / 95) * np.cos(y / 140) + 5 * np.sin((x + 1.3 * y) / 60) + 0.01 * x
    np.save(work / "dem.npy", heights.astype(np.float32))
    m = 4096
    yy, xx = np.mgrid[0:m, 0:m]
    checks = ((xx // 8 + yy // 8) % 2)[..., None] > 0
    tint_r = 0.5 + 0.5 * np.sin(xx / 700.0)
    tint_b = 0.5 + 0.5 * np.cos(yy / 900.0)
    light = np.stack([230 * tint_r + 20, 200 - 100 * tint_b, 40 + 160 * tint_b], -1)
    dark = np.stack([25 + 0 * xx, 40 + 60 * tint_r, 90 + 0 * xx], -1)
    photo = np.where(checks, light, dark).clip(0, 255).astype(np.uint8)
    Image.fromarray(photo).save(work / "ortho.png")


def run(*args):
    subprocess.run([RELIEF, *map(str, args)], check=True)


def labelled(picture, text):
    """`picture` with `text` on a white band above it."""
    font = ImageFont.load_default(size=20)
    out = Image.new("RGB", (picture.width, picture.height + 30), "white")
    out.paste(picture, (0, 30))
    ImageDraw.Draw(out).text((6, 4), text, fill="black", font=font)
    return out


def main():
    OUT.mkdir(parents=True, exist_ok=True)
    work = Path(tempfile.mkdtemp(prefix="relief-tiles-texture-"))
    make_inputs(work)
    run("tile", work / "dem.npy", "-o", work / "store", "--tile", "256", "--texture",
        work / "ortho.png")
    columns, rows = [], []
    for name, title in [("bilinear", "bilinear (level 0)"),
                        ("anisotropic", "anisotropic (up to 16 trilinear samples)")]:
        picture, stats = work / f"{name}.png", work / f"{name}.json"
        run("render", work / "store", *VIEW, "--texture-filter", name, "-o", picture,
            "--stats", stats)
        image = Image.open(picture).convert("RGB")
        x, y, w, h = CROP
        crop = image.crop((x, y, x + w, y + h)).resize((w * ZOOM, h * ZOOM), Image.NEAREST)
        outline = image.copy()
        ImageDraw.Draw(outline).rectangle((x, y, x + w, y + h), outline="white", width=2)
        column = Image.new("RGB", (image.width, image.height + 30 + crop.height + 4), "white")
        column.paste(labelled(outline, title), (0, 0))
        column.paste(crop, ((image.width - crop.width) // 2, image.height + 34))
        columns.append(column)
        s = json.loads(stats.read_text())
        rows.append((name, s["trace_ms"], s["texture_ms"], s["shade_ms"], s["texture_tiles"],
                     s["resident_texture_bytes"] / 2**20))
    gap = 8
    sheet = Image.new("RGB", (sum(c.width for c in columns) + gap, columns[0].height), "white")
    sheet.paste(columns[0], (0, 0))
    sheet.paste(columns[1], (columns[0].width + gap, 0))
    sheet.save(OUT / "texture-filtering.png", optimize=True)
    print("| filter | trace ms | texture ms | shade ms | texture tiles | texture MiB |")
    print("|---|---:|---:|---:|---:|---:|")
    for name, trace, texture, shade, tiles, mib in rows:
        print(f"| {name} | {trace:.0f} | {texture:.0f} | {shade:.0f} | {tiles} | {mib:.1f} |")


if __name__ == "__main__":
    main()
