"""relief.shade gives the layers `relief shade` writes for the same heights and options (the
GeoTIFF read back with rasterio), keeps voids as NaN, and refuses bad options with the
command line's messages."""

import numpy as np
import pytest

import relief

rasterio = pytest.importorskip("rasterio")

OPTIONS = dict(layers=["shadow", "sky", "hillshade", "combined"], suns=[(250.0, 15.0)],
               sky_rays=12, spacing=(2.0, 3.0), z_scale=1.5)
ARGS = ["--layers", "shadow,sky,hillshade,combined", "--sun", "250,15", "--sky-rays", "12",
        "--spacing", "2,3", "--z-scale", "1.5"]


def test_shade_equals_the_command_line(tmp_path, run_relief, terrain):
    layers = relief.shade(terrain, **OPTIONS)
    assert list(layers) == ["shadow", "sky", "hillshade", "combined"]
    # A .npy is read with row 0 south: hand the command line the array flipped.
    np.save(tmp_path / "h.npy", np.flipud(terrain))
    run_relief("shade", tmp_path / "h.npy", "-o", tmp_path / "s.tif", *ARGS)
    with rasterio.open(tmp_path / "s.tif") as cli:
        assert cli.descriptions == tuple(layers)
        for band, (name, values) in enumerate(layers.items(), start=1):
            assert values.dtype == np.float32 and values.shape == terrain.shape
            np.testing.assert_array_equal(values, cli.read(band), err_msg=name)
    shadow = layers["shadow"]
    assert (shadow == 0).any() and (shadow == 1).any(), "a low sun casts shadows here"


def test_a_flat_plane_is_open_and_lit():
    layers = relief.shade(np.full((12, 10), 7.0), layers=["sky", "hillshade"], suns=[(0, 30)])
    np.testing.assert_array_equal(layers["sky"], 1.0)
    np.testing.assert_allclose(layers["hillshade"], 0.5, atol=1e-6)


def test_voids_are_nan_in_every_layer(terrain):
    holed = terrain.copy()
    holed[5:8, 10:14] = np.nan
    for voids in ("fill", "hole"):
        layers = relief.shade(holed, layers=["shadow", "sky", "hillshade"], sky_rays=4,
                              voids=voids)
        for name, values in layers.items():
            np.testing.assert_array_equal(np.isnan(values), np.isnan(holed), err_msg=name)


def test_views_and_orders_give_the_same_layers(terrain):
    expected = relief.shade(np.ascontiguousarray(terrain[::2, ::3]), layers=["sky"], sky_rays=6)
    for view in (terrain[::2, ::3], np.asfortranarray(terrain)[::2, ::3],
                 terrain.astype(np.float64)[::2, ::3]):
        got = relief.shade(view, layers=["sky"], sky_rays=6)
        np.testing.assert_array_equal(got["sky"], expected["sky"])


@pytest.mark.parametrize("kwargs, message", [
    (dict(layers=["shadows"]), "unknown layer 'shadows' (expected shadow, sky, hillshade or combined)"),
    (dict(layers=[]), "no layer asked for"),
    (dict(suns=[(10.0, 0.0)]), "sun elevation"),
    (dict(sky_rays=0), "sky rays"),
    (dict(sun_radius=-1.0), "sun radius"),
    (dict(surface="cubes"), "cubes"),
])
def test_bad_options_raise_relief_errors(terrain, kwargs, message):
    with pytest.raises(relief.ReliefError, match=message.replace("(", r"\(").replace(")", r"\)")):
        relief.shade(terrain, **kwargs)
