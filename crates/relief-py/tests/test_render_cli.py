"""relief.render gives the pixels and depth `relief render` writes for the same heights,
camera and options (the PNG read back with Pillow, the depth .npy exactly)."""

import numpy as np
import pytest

import relief

Image = pytest.importorskip("PIL.Image")

CAMERA = {"eye": (-20.0, -30.0, 45.0), "target": (24.0, 20.0, 4.0)}


def cli_render(run_relief, tmp_path, heights_file, args):
    png, depth = tmp_path / "cli.png", tmp_path / "cli-depth.npy"
    run_relief("render", heights_file, "-o", png, "--depth", depth, *args)
    return np.asarray(Image.open(png).convert("RGB")), np.load(depth)


CASES = [
    (dict(camera=CAMERA), ["--eye", "-20,-30,45", "--target", "24,20,4"]),
    (dict(), []),
    (
        dict(spacing=(2.0, 3.0), z_scale=1.5, camera={"fov": 30.0}, surface="boxes",
             tracer="naive", shadows=False),
        ["--spacing", "2,3", "--z-scale", "1.5", "--fov", "30", "--surface", "boxes",
         "--tracer", "naive", "--no-shadows"],
    ),
    (
        dict(spacing=2.5, origin=(100.0, -50.0), sun=(90.0, 10.0), exposure=2.0,
             camera={"eye": (60.0, 140.0, 80.0), "target": (160.0, 0.0, 0.0),
                     "up": (0.0, 0.3, 1.0), "fov": 60.0}),
        ["--spacing", "2.5", "--sun", "90,10", "--exposure", "2", "--eye", "60,140,80",
         "--target", "160,0,0", "--up", "0,0.3,1", "--fov", "60"],
    ),
    (dict(camera=CAMERA, aa=3), ["--eye", "-20,-30,45", "--target", "24,20,4", "--aa", "3"]),
    (dict(aa="off"), ["--aa", "off"]),
]


@pytest.mark.parametrize(
    "kwargs, args", CASES, ids=["camera", "framed", "boxes-naive", "placed", "aa-3", "aa-off"]
)
def test_render_equals_the_command_line(tmp_path, run_relief, terrain, kwargs, args):
    np.save(tmp_path / "h.npy", terrain)
    if "origin" in kwargs:
        # The command line takes a .npy's origin as 0: shift the camera instead.
        ox, oy = kwargs["origin"]
        cam = kwargs["camera"]
        args = list(args)
        args[args.index("--eye") + 1] = ",".join(
            str(v) for v in np.subtract(cam["eye"], (ox, oy, 0)))
        args[args.index("--target") + 1] = ",".join(
            str(v) for v in np.subtract(cam["target"], (ox, oy, 0)))
    rgb, depth = relief.render(terrain, size=(64, 48), **kwargs)
    cli_rgb, cli_depth = cli_render(
        run_relief, tmp_path, tmp_path / "h.npy", ["--north-up", "--size", "64x48", *args]
    )
    assert cli_rgb.shape == rgb.shape == (48, 64, 3)
    assert np.array_equal(rgb, cli_rgb)
    assert cli_depth.dtype == depth.dtype == np.float32
    assert np.array_equal(depth, cli_depth)
    assert np.isfinite(depth).sum() > 100


def test_render_of_read_equals_the_command_line_on_a_geotiff(tmp_path, run_relief, terrain):
    rasterio = pytest.importorskip("rasterio")
    from rasterio.transform import Affine

    heights = terrain.copy()
    heights[10:13, 20:24] = -32768.0
    path = tmp_path / "dem.tif"
    with rasterio.open(
        path, "w", driver="GTiff", width=48, height=40, count=1, dtype="float32",
        crs="EPSG:32633", transform=Affine(2.0, 0.0, 500000.0, 0.0, -2.0, 4100000.0), nodata=-32768.0,
    ) as out:
        out.write(heights, 1)
    read = relief.read(path)
    assert np.isnan(read[0]).sum() == 12
    for voids in ["fill", "hole"]:
        rgb, depth = relief.render(*read, size=(64, 48), voids=voids)
        cli_rgb, cli_depth = cli_render(
            run_relief, tmp_path, path, ["--size", "64x48", "--voids", voids]
        )
        assert np.array_equal(rgb, cli_rgb), voids
        assert np.array_equal(depth, cli_depth), voids


def test_render_of_a_read_npy_equals_the_command_line(tmp_path, run_relief, terrain):
    np.save(tmp_path / "h.npy", terrain)
    rgb, depth = relief.render(*relief.read(tmp_path / "h.npy"), size=(48, 32))
    cli_rgb, cli_depth = cli_render(run_relief, tmp_path, tmp_path / "h.npy", ["--size", "48x32"])
    assert np.array_equal(rgb, cli_rgb) and np.array_equal(depth, cli_depth)


def test_anti_aliasing_changes_only_the_edges_and_keeps_the_depth(terrain):
    off, depth_off = relief.render(terrain, size=(64, 48), aa="off")
    adaptive, depth = relief.render(terrain, size=(64, 48))
    grid, depth_grid = relief.render(terrain, size=(64, 48), aa=4)
    assert np.array_equal(depth, depth_off) and np.array_equal(depth_grid, depth_off)
    changed = (adaptive != off).any(axis=2)
    assert 0 < changed.mean() < 0.5, "some pixels, not most"
    assert (grid != off).any(axis=2).mean() > changed.mean()
    for bad in ["fast", 0, 9, 2.5]:
        with pytest.raises(relief.ReliefError):
            relief.render(terrain, size=(8, 8), aa=bad)
