"""relief.read: north-up heights with NaN voids and a georeference that matches GDAL's
(through rasterio)."""

import numpy as np
import pytest

import relief

rasterio = pytest.importorskip("rasterio")
from rasterio.crs import CRS  # noqa: E402
from rasterio.transform import Affine  # noqa: E402


def write_geotiff(path, heights, west, north, dx, dy, nodata=None, crs="EPSG:32633"):
    rows, cols = heights.shape
    with rasterio.open(
        path, "w", driver="GTiff", width=cols, height=rows, count=1, dtype=heights.dtype,
        crs=CRS.from_string(crs), transform=Affine(dx, 0.0, west, 0.0, -dy, north), nodata=nodata,
    ) as out:
        out.write(heights, 1)


def test_a_geotiff_written_by_rasterio(tmp_path, terrain):
    heights = terrain.copy()
    heights[3, 5] = -9999.0
    path = tmp_path / "dem.tif"
    write_geotiff(path, heights, 500000.0, 4100000.0, 30.0, 20.0, nodata=-9999.0)

    read, georeference = relief.read(path)
    assert read.dtype == np.float32 and read.shape == heights.shape
    assert np.isnan(read[3, 5]) and np.isnan(read).sum() == 1
    valid = ~np.isnan(read)
    assert np.array_equal(read[valid], heights[valid])

    with rasterio.open(path) as dataset:
        transform, bounds = dataset.transform, dataset.bounds
        assert np.array_equal(dataset.read(1)[valid], read[valid])
    assert georeference["spacing"] == (transform.a, -transform.e) == (30.0, 20.0)
    assert georeference["origin"] == (bounds.left, bounds.bottom)
    assert georeference["geotransform"] == transform.to_gdal()
    assert georeference["nodata"] == -9999.0
    assert georeference["format"] == "GeoTIFF"
    assert georeference["sample_type"] == "float32"
    assert georeference["georeferenced"] is True
    assert georeference["from_degrees"] is None


def test_integer_samples_and_no_nodata(tmp_path):
    heights = (np.arange(12, dtype=np.int16).reshape(3, 4) * 7) - 20
    write_geotiff(tmp_path / "int.tif", heights, 0.0, 300.0, 10.0, 10.0)
    read, georeference = relief.read(tmp_path / "int.tif")
    assert np.array_equal(read, heights.astype(np.float32))
    assert georeference["sample_type"] == "int16" and georeference["nodata"] is None
    assert georeference["origin"] == (0.0, 270.0)


def test_a_geographic_geotiff_is_converted_to_metres(tmp_path, terrain):
    write_geotiff(tmp_path / "geo.tif", terrain, 7.0, 46.5, 1 / 3600, 1 / 3600, crs="EPSG:4326")
    _, georeference = relief.read(tmp_path / "geo.tif")
    degrees = georeference["from_degrees"]
    assert degrees["dlon"] == pytest.approx(1 / 3600) and degrees["dlat"] == pytest.approx(1 / 3600)
    assert 46.4 < degrees["latitude"] < 46.5
    dx, dy = georeference["spacing"]
    assert 20 < dx < 22 and 30 < dy < 31


def test_npy_rows_are_relief_rows_so_read_flips_them(tmp_path, terrain):
    np.save(tmp_path / "h.npy", terrain)
    read, georeference = relief.read(tmp_path / "h.npy")
    assert np.array_equal(read, np.flipud(terrain))
    assert georeference["georeferenced"] is False
    assert georeference["spacing"] == (1.0, 1.0) and georeference["origin"] == (0.0, 0.0)
    assert georeference["format"] == "NumPy .npy"


def test_npz_arrays_by_name(tmp_path, terrain):
    np.savez(tmp_path / "h.npz", first=terrain, second=terrain * 2)
    first, _ = relief.read(tmp_path / "h.npz")
    second, _ = relief.read(tmp_path / "h.npz", array="second")
    assert np.array_equal(first * 2, second)


@pytest.mark.parametrize(
    "crs, west, north, dx",
    [
        ("EPSG:4326", -84.5, 36.75, 1 / 1200),
        ("EPSG:32617", 500000.0, 4000000.0, 30.0),
        ("EPSG:2274", 1700010.0, 600000.0, 30.0),
    ],
)
def test_the_georeference_is_the_files_own_as_rasterio_reads_it(tmp_path, terrain, crs, west, north, dx):
    path = tmp_path / "dem.tif"
    write_geotiff(path, terrain, west, north, dx, dx, crs=crs)
    heights, georeference = relief.read(path)
    with rasterio.open(path) as dataset:
        assert georeference["geotransform"] == pytest.approx(dataset.transform.to_gdal(), rel=1e-12)
        assert georeference["transform"] == pytest.approx(tuple(dataset.transform)[:6], rel=1e-12)
        assert georeference["epsg"] == dataset.crs.to_epsg()
        assert georeference["crs"] == crs
        assert CRS.from_wkt(georeference["crs_wkt"]).to_epsg(confidence_threshold=20) == dataset.crs.to_epsg()
        assert np.array_equal(heights, dataset.read(1))
    feet = crs == "EPSG:2274"
    assert georeference["height_unit"] == ("US survey foot" if feet else "metre")
    assert georeference["z_scale"] == pytest.approx(1200 / 3937 if feet else 1.0)
    assert "EPSG:2274" in georeference["height_unit_reason"] if feet else True
    # relief's own world stays in metres.
    west_m, _, _, north_m, _, _ = georeference["world_geotransform"]
    assert georeference["origin"][0] == west_m
    if feet:
        assert west_m == pytest.approx(west * 1200 / 3937)


def test_a_dem_in_feet_renders_as_the_same_dem_in_metres(tmp_path, terrain):
    feet = 1200 / 3937
    in_feet = (terrain * 50 / feet).astype(np.float32)
    write_geotiff(tmp_path / "ft.tif", in_feet, 1700010.0, 600000.0, 30.0, 30.0, crs="EPSG:2274")
    _, ft = relief.read(tmp_path / "ft.tif")
    metres = (in_feet.astype(np.float64) * feet).astype(np.float32)
    camera = {"eye": (ft["origin"][0] - 200, ft["origin"][1] - 200, 2000.0),
              "target": (ft["origin"][0] + 200, ft["origin"][1] + 200, 200.0)}
    _, depth_ft = relief.render(*relief.read(tmp_path / "ft.tif"), camera=camera, size=(64, 48))
    _, depth_m = relief.render(metres, (30 * feet, 30 * feet), origin=ft["origin"], camera=camera, size=(64, 48))
    finite = np.isfinite(depth_m)
    assert finite.any() and np.array_equal(finite, np.isfinite(depth_ft))
    assert np.allclose(depth_ft[finite], depth_m[finite], rtol=1e-4)
    with pytest.raises(relief.ReliefError):
        relief.read(tmp_path / "ft.tif", z_unit="yards")
    heights, told = relief.read(tmp_path / "ft.tif", z_unit="m")
    assert told["z_scale"] == 1.0 and told["height_unit"] == "metre"
