"""Colour maps and map furniture from Python: relief.render and relief.open(...).render give
the pixels `relief render --colormap ... --legend --scale-bar --north-arrow` writes, and
refuse what the command line refuses, as relief.ReliefError."""

import re

import numpy as np
import pytest

import relief

Image = pytest.importorskip("PIL.Image")

CAMERA = {"eye": (-20.0, -30.0, 45.0), "target": (24.0, 20.0, 4.0)}


def cli_picture(run_relief, tmp_path, args):
    png = tmp_path / "cli.png"
    run_relief("render", *args, "-o", png)
    return np.asarray(Image.open(png).convert("RGB"))


@pytest.mark.parametrize(
    "kwargs, args",
    [
        (dict(colormap="viridis"), ["--colormap", "viridis"]),
        (
            dict(colormap="bathymetry", height_range=(-2.0, 14.0), sea_level=5.0, z_scale=2.0,
                 legend=True, north_arrow=True),
            ["--colormap", "bathymetry", "--height-range=-2,14", "--sea-level", "5",
             "--z-scale", "2", "--legend", "--north-arrow"],
        ),
    ],
    ids=["viridis", "bathymetry-furniture"],
)
def test_render_colours_as_the_command_line(tmp_path, run_relief, terrain, kwargs, args):
    np.save(tmp_path / "h.npy", terrain)
    rgb, _ = relief.render(terrain, size=(96, 64), camera=CAMERA, **kwargs)
    cli = cli_picture(
        run_relief, tmp_path,
        [tmp_path / "h.npy", "--north-up", "--size", "96x64", "--eye", "-20,-30,45",
         "--target", "24,20,4", *args],
    )
    assert np.array_equal(rgb, cli)
    plain, _ = relief.render(terrain, size=(96, 64), camera=CAMERA)
    assert not np.array_equal(rgb, plain)


def test_scene_render_draws_a_scale_bar_on_a_map(tmp_path, run_relief, terrain):
    np.save(tmp_path / "h.npy", terrain)
    scene = relief.open(tmp_path / "h.npy", spacing=10.0, colormap="magma")
    camera = {"view": (0.0, 90.0), "ortho": True, "ortho_height": 400.0}
    rgb, _ = scene.render(camera, size=(160, 90), legend=True, scale_bar=True, north_arrow=True)
    cli = cli_picture(
        run_relief, tmp_path,
        [tmp_path / "h.npy", "--spacing", "10", "--colormap", "magma", "--view", "0,90",
         "--ortho", "--ortho-height", "400", "--size", "160x90", "--legend", "--scale-bar",
         "--north-arrow"],
    )
    assert np.array_equal(rgb, cli)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        (dict(colormap="jet"), "unknown colour map 'jet' (known: terrain, bathymetry, greys"),
        (dict(height_range=(5.0, 1.0)), "the lower first"),
        (dict(height_range=(0.0, 2e7)), "outside"),
        (dict(colormap="greys", sea_level=1.0), "bathymetry colour map only, not to greys"),
        (dict(scale_bar=True), "a scale bar needs an orthographic camera"),
    ],
)
def test_bad_colours_and_furniture_raise_relief_errors(terrain, kwargs, message):
    with pytest.raises(relief.ReliefError, match=re.escape(message)):
        relief.render(terrain, size=(32, 18), **kwargs)


def test_open_refuses_a_colour_map_for_an_mlhm_scene(tmp_path, run_relief):
    run_relief("generate", "mlhm", "--scene", "arches", "--size", "32", "-o", tmp_path / "s.mlhm")
    with pytest.raises(relief.ReliefError, match="not to MLHM scenes"):
        relief.open(tmp_path / "s.mlhm", colormap="viridis")
    scene = relief.open(tmp_path / "s.mlhm")
    with pytest.raises(relief.ReliefError, match="a legend shows a colour map of heights"):
        scene.render(size=(32, 18), legend=True)


def test_shading_normals_as_the_command_line(tmp_path, run_relief, terrain):
    """Smooth normals are the default of the triangles surface; faceted is the other way, and
    both give `relief render --shading-normals`'s pixels."""
    np.save(tmp_path / "h.npy", terrain)
    base = [tmp_path / "h.npy", "--north-up", "--size", "96x64", "--eye", "-20,-30,45",
            "--target", "24,20,4"]
    smooth, depth_smooth = relief.render(terrain, size=(96, 64), camera=CAMERA)
    faceted, depth_faceted = relief.render(
        terrain, size=(96, 64), camera=CAMERA, shading_normals="faceted")
    assert np.array_equal(smooth, cli_picture(run_relief, tmp_path, base))
    assert np.array_equal(
        faceted, cli_picture(run_relief, tmp_path, [*base, "--shading-normals", "faceted"]))
    assert not np.array_equal(smooth, faceted)
    assert np.array_equal(depth_smooth, depth_faceted)
    scene = relief.open(tmp_path / "h.npy", north_up=True, shading_normals="faceted")
    rgb, _ = scene.render(CAMERA, size=(96, 64))
    assert np.array_equal(rgb, faceted)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        (dict(shading_normals="flat"), "unknown shading normals 'flat' (expected smooth or faceted)"),
        (dict(shading_normals="smooth", surface="boxes"), "boxes are always faceted"),
    ],
)
def test_bad_shading_normals_raise_relief_errors(terrain, kwargs, message):
    with pytest.raises(relief.ReliefError, match=re.escape(message)):
        relief.render(terrain, size=(32, 18), **kwargs)
