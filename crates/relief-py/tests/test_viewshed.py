"""relief.viewshed gives the raster `relief viewshed` writes for the same heights and
observers (the GeoTIFF read back with rasterio), counts several observers as the sum of
single viewsheds, keeps voids as NaN, and refuses bad observers with relief.ReliefError."""

import numpy as np
import pytest

import relief

rasterio = pytest.importorskip("rasterio")


def test_viewshed_equals_the_command_line(tmp_path, run_relief, terrain):
    observers = [(10.5, 30.5, 2.0), (40.0, 8.0)]
    for count in (1, 2):
        got = relief.viewshed(terrain, (2.0, 3.0), observers=observers[:count],
                              target_height=0.5)
        assert got.dtype == np.float32 and got.shape == terrain.shape
        # A .npy is read with row 0 south: hand the command line the array flipped.
        np.save(tmp_path / "h.npy", np.flipud(terrain))
        args = []
        for x, y, *h in observers[:count]:
            args += ["--observer", ",".join(str(v) for v in (x, y, *h))]
        run_relief("viewshed", tmp_path / "h.npy", "-o", tmp_path / "v.tif", "--spacing", "2,3",
                   "--target-height", "0.5", *args)
        with rasterio.open(tmp_path / "v.tif") as cli:
            assert cli.descriptions == (("visible",) if count == 1 else ("observers",))
            np.testing.assert_array_equal(got, cli.read(1))
        assert (got == 0).any() and (got == count).any(), "the bump hides part of the terrain"


def test_several_observers_count_as_the_sum_of_single_ones(terrain):
    observers = [(5.0, 5.0, 1.0), (20.0, 30.0, 3.0), (47.9, 0.1, 0.0)]
    total = relief.viewshed(terrain, observers=observers, target_height=1.0)
    singles = [relief.viewshed(terrain, observers=[o], target_height=1.0) for o in observers]
    np.testing.assert_array_equal(total, sum(singles))
    assert set(np.unique(singles[0])) <= {0.0, 1.0}


def test_a_flat_plane_is_seen_whole_and_a_radius_limits_it():
    flat = np.full((12, 10), 3.0, dtype=np.float32)
    np.testing.assert_array_equal(relief.viewshed(flat, observers=[(5.0, 6.0)]), 1.0)
    near = relief.viewshed(flat, observers=[(5.0, 6.0, 1.0)], radius=2.0)
    # Row r of the north-up array is grid row 11 - r; sample centres at col + 0.5.
    rows, cols = np.mgrid[0:12, 0:10]
    d = np.hypot(cols + 0.5 - 5.0, (11 - rows) + 0.5 - 6.0)
    np.testing.assert_array_equal(near, (d <= 2.0).astype(np.float32))


def test_voids_are_nan(terrain):
    holed = terrain.copy()
    holed[5:8, 10:14] = np.nan
    for voids in ("fill", "hole"):
        got = relief.viewshed(holed, observers=[(30.0, 30.0, 1.7)], voids=voids)
        np.testing.assert_array_equal(np.isnan(got), np.isnan(holed))


@pytest.mark.parametrize("kwargs, message", [
    (dict(observers=[]), "at least one"),
    (dict(observers=[(100.0, 5.0)]), "outside the DEM"),
    (dict(observers=[(5.0, 5.0, -1.0)]), "observer height"),
    (dict(observers=[(5.0, 5.0, float("nan"))]), "observer height"),
    (dict(observers=[(5.0,)]), "(x, y) or (x, y, height)"),
    (dict(observers=[(5.0, 5.0)], target_height=-1.0), "target height"),
    (dict(observers=[(5.0, 5.0)], radius=0.0), "radius"),
])
def test_bad_input_is_refused(terrain, kwargs, message):
    with pytest.raises(relief.ReliefError, match=message.replace("(", r"\(").replace(")", r"\)")):
        relief.viewshed(terrain, **kwargs)
