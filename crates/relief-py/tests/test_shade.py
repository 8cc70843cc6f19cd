"""relief.shade gives the layers `relief shade` writes for the same heights and options (the
GeoTIFF read back with rasterio), keeps voids as NaN, and refuses bad options with the
command line's messages."""

import numpy as np
import pytest

import relief

rasterio = pytest.importorskip("rasterio")

LAYERS = ["shadow", "sky", "hillshade", "combined", "sky-aniso", "openness-pos", "openness-neg",
          "sky-illumination", "hillshade-multi"]
OPTIONS = dict(layers=LAYERS, suns=[(250.0, 15.0)], azimuths=12, observer_height=0.5,
               sky_model="uniform", spacing=(2.0, 3.0), z_scale=1.5)
ARGS = ["--layers", ",".join(LAYERS), "--sun", "250,15", "--azimuths", "12",
        "--observer-height", "0.5", "--sky-model", "uniform", "--spacing", "2,3",
        "--z-scale", "1.5"]


def test_shade_equals_the_command_line(tmp_path, run_relief, terrain):
    layers = relief.shade(terrain, **OPTIONS)
    assert list(layers) == LAYERS
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


def test_the_horizon_layer_is_a_band_per_direction(tmp_path, run_relief, terrain):
    got = relief.shade(terrain, layers=["horizon"], azimuths=8, spacing=(2.0, 3.0))["horizon"]
    assert got.shape == (8,) + terrain.shape and got.dtype == np.float32
    np.save(tmp_path / "h.npy", np.flipud(terrain))
    run_relief("shade", tmp_path / "h.npy", "-o", tmp_path / "s.tif", "--layers", "horizon",
               "--azimuths", "8", "--spacing", "2,3")
    with rasterio.open(tmp_path / "s.tif") as cli:
        assert cli.descriptions == tuple(f"horizon-{45.0 * k:05.1f}" for k in range(8))
        np.testing.assert_array_equal(cli.read(), got)
    # A direction's horizon is never below the slope down to the neighbour that way, nor
    # above 90 degrees.
    assert np.nanmax(got) < 90 and np.nanmin(got) > -90


def test_a_flat_plane_is_open_and_lit():
    layers = relief.shade(np.full((12, 10), 7.0), layers=["sky", "hillshade", "openness-pos"],
                          suns=[(0, 30)])
    np.testing.assert_array_equal(layers["sky"], 1.0)
    np.testing.assert_allclose(layers["hillshade"], 0.5, atol=1e-6)
    np.testing.assert_allclose(layers["openness-pos"], 90.0, atol=0.6)


def test_voids_are_nan_in_every_layer(terrain):
    holed = terrain.copy()
    holed[5:8, 10:14] = np.nan
    for voids in ("fill", "hole"):
        layers = relief.shade(holed, layers=["shadow", "sky", "hillshade"], azimuths=4,
                              voids=voids)
        for name, values in layers.items():
            np.testing.assert_array_equal(np.isnan(values), np.isnan(holed), err_msg=name)


def test_views_and_orders_give_the_same_layers(terrain):
    expected = relief.shade(np.ascontiguousarray(terrain[::2, ::3]), layers=["sky"], azimuths=6)
    for view in (terrain[::2, ::3], np.asfortranarray(terrain)[::2, ::3],
                 terrain.astype(np.float64)[::2, ::3]):
        got = relief.shade(view, layers=["sky"], azimuths=6)
        np.testing.assert_array_equal(got["sky"], expected["sky"])


@pytest.mark.parametrize("kwargs, message", [
    (dict(layers=["shadows"]), "unknown layer 'shadows' (expected one of shadow, sky, hillshade,"),
    (dict(layers=[]), "no layer asked for"),
    (dict(suns=[(10.0, 0.0)]), "sun elevation"),
    (dict(azimuths=0), "azimuths"),
    (dict(layers=["sky"], observer_height=-1.0), "observer height"),
    (dict(layers=["sky"], radius=0.0), "radius"),
    (dict(layers=["sky"], earth_curvature=1.5), "refraction coefficient"),
    (dict(layers=["sky-illumination"], sky_model="cloudy"), "unknown sky model 'cloudy'"),
    (dict(layers=["sky"], surface="boxes"), "exact for the triangles surface only"),
    (dict(sun_radius=-1.0), "sun radius"),
    (dict(surface="cubes"), "cubes"),
])
def test_bad_options_raise_relief_errors(terrain, kwargs, message):
    with pytest.raises(relief.ReliefError, match=message.replace("(", r"\(").replace(")", r"\)")):
        relief.shade(terrain, **kwargs)


def test_insolation_over_a_day_equals_the_command_line(tmp_path, run_relief, terrain):
    when = dict(date="2026-06-21", timezone="+02:00", step="30m", latitude=46.5, longitude=7.9)
    layers = relief.shade(terrain, layers=["insolation", "sun-hours"], azimuths=8,
                          spacing=(2.0, 3.0), **when)
    np.save(tmp_path / "h.npy", np.flipud(terrain))
    run_relief("shade", tmp_path / "h.npy", "-o", tmp_path / "s.tif", "--layers",
               "insolation,sun-hours", "--azimuths", "8", "--spacing", "2,3", "--date",
               "2026-06-21", "--timezone", "+02:00", "--step", "30m", "--lat", "46.5",
               "--lon", "7.9")
    with rasterio.open(tmp_path / "s.tif") as cli:
        np.testing.assert_array_equal(cli.read(1), layers["insolation"])
        np.testing.assert_array_equal(cli.read(2), layers["sun-hours"])
    # Midsummer in the Alps: at most the day's length of sun, some of it hidden here.
    hours = layers["sun-hours"]
    assert hours.max() <= 16.0 and hours.min() < hours.max()


def test_the_sun_of_one_instant_and_bad_dates():
    flat = np.full((6, 5), 3.0)
    lit = relief.shade(flat, layers=["hillshade"], date="2026-06-21", time="12:00",
                       latitude=0.0, longitude=0.0)["hillshade"]
    # Near the zenith at noon on the equator in June (the sun 23.4 degrees north of it).
    np.testing.assert_allclose(lit, np.sin(np.radians(90 - 23.4)), atol=0.01)
    with pytest.raises(relief.ReliefError, match="2026-02-30 does not exist"):
        relief.shade(flat, layers=["insolation"], date="2026-02-30", latitude=0, longitude=0)
    with pytest.raises(relief.ReliefError, match="below the horizon"):
        relief.shade(flat, layers=["shadow"], date="2026-06-21", time="00:00", latitude=0,
                     longitude=0)
    with pytest.raises(relief.ReliefError, match="latitude and longitude"):
        relief.shade(flat, layers=["insolation"], date="2026-06-21")
