"""relief.dask on a distributed.LocalCluster of two worker processes: a store's shade layers
equal `relief shade`'s bit for bit, with rioxarray's coordinates and CRS, and write back with
rioxarray; the radius form over any Dask array equals relief.shade of the whole array for the
layers that reach no farther than the radius; a fly-through's frames are `relief
flythrough`'s bytes; bad chunks, halos and layers are refused with the limit in the message."""

import json
import math

import numpy as np
import pytest

import relief

from conftest import hills

rasterio = pytest.importorskip("rasterio")
distributed = pytest.importorskip("distributed")
xarray = pytest.importorskip("xarray")
rioxarray = pytest.importorskip("rioxarray")
dask_array = pytest.importorskip("dask.array")
import relief.dask  # noqa: E402  (after the skips: it needs dask, xarray and rioxarray)

ROWS, COLS, TILE, CHUNKS = 300, 400, 64, 128
SUNS = [(250.0, 15.0)]
LAYERS = ["shadow", "sky", "hillshade", "horizon"]
OPTIONS = dict(layers=LAYERS, suns=SUNS, azimuths=8)
CLI_OPTIONS = ["--layers", ",".join(LAYERS), "--sun", "250,15", "--azimuths", "8"]


@pytest.fixture(scope="module")
def client():
    with distributed.LocalCluster(n_workers=2, processes=True, threads_per_worker=1,
                                  dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            yield client


@pytest.fixture(scope="module")
def dem(tmp_path_factory, client):
    """A georeferenced 300 x 400 GeoTIFF DEM (UTM 33N, 10 m), its tile store (64-sample
    tiles, made by `relief tile`), and the folder they are in."""
    folder = tmp_path_factory.mktemp("dask")
    path = folder / "dem.tif"
    transform = rasterio.transform.from_origin(500000.0, 4200000.0, 10.0, 10.0)
    with rasterio.open(path, "w", driver="GTiff", width=COLS, height=ROWS, count=1,
                       dtype="float32", crs="EPSG:32633", transform=transform) as file:
        file.write(hills(ROWS, COLS) * 20.0, 1)
    return folder, path


@pytest.fixture(scope="module")
def store(dem, client, relief_bin):
    import subprocess

    folder, path = dem
    store = folder / "dem.store"
    subprocess.run([str(relief_bin), "tile", str(path), "-o", str(store), "--tile", str(TILE)],
                   check=True, capture_output=True)
    return store


@pytest.fixture(scope="module")
def cli_shade(dem, store, relief_bin):
    """`relief shade` of the store, written as a GeoTIFF."""
    import subprocess

    folder, _ = dem
    out = folder / "cli.tif"
    subprocess.run([str(relief_bin), "shade", str(store), "-o", str(out), *CLI_OPTIONS],
                   check=True, capture_output=True)
    return out


def test_a_store_shades_as_the_command_line_bit_for_bit(client, store, cli_shade):
    ds = relief.dask.shade(store, chunks=CHUNKS, **OPTIONS)
    assert list(ds.data_vars) == LAYERS
    assert ds["sky"].dims == ("y", "x") and ds["sky"].shape == (ROWS, COLS)
    assert ds["horizon"].dims == ("azimuth", "y", "x")
    np.testing.assert_array_equal(ds["azimuth"], np.arange(8) * 45.0)
    assert ds["sky"].data.chunks == ((128, 128, 44), (128, 128, 128, 16))
    assert all(ds[name].dtype == np.float32 for name in LAYERS)
    # One task a chunk shades every layer: the layers' graphs share it.
    tasks = {key for key in ds.__dask_graph__() if "relief-shade" in str(key)}
    assert len(tasks) == 3 * 4
    computed = ds.compute()
    with rasterio.open(cli_shade) as cli:
        bands = cli.read()
    expected = {"shadow": bands[0], "sky": bands[1], "hillshade": bands[2],
                "horizon": bands[3:]}
    for name in LAYERS:
        np.testing.assert_array_equal(computed[name].values, expected[name], err_msg=name)
    assert (computed["shadow"] == 0).any() and (computed["shadow"] == 1).any()


def test_coordinates_and_crs_are_rioxarrays(store, cli_shade):
    ds = relief.dask.shade(store, chunks=(192, 256), layers=["hillshade"])
    cli = rioxarray.open_rasterio(cli_shade)
    np.testing.assert_array_equal(ds["x"].values, cli["x"].values)
    np.testing.assert_array_equal(ds["y"].values, cli["y"].values)
    assert ds.rio.crs == cli.rio.crs and ds.rio.crs.to_epsg() == 32633
    assert ds.rio.transform() == cli.rio.transform()
    assert ds["hillshade"].rio.crs == cli.rio.crs
    assert np.isnan(ds["hillshade"].attrs["_FillValue"])


def test_the_layers_write_with_rioxarray_and_a_lock(client, store, cli_shade, tmp_path):
    ds = relief.dask.shade(store, chunks=(128, 256), **OPTIONS)
    out = tmp_path / "shade.tif"
    lock = distributed.Lock("relief-test-write")
    ds[["shadow", "sky", "hillshade"]].rio.to_raster(
        out, tiled=True, blockxsize=128, blockysize=128, lock=lock, compute=True,
        recalc_transform=False)
    horizon = tmp_path / "horizon.tif"
    ds["horizon"].rio.to_raster(horizon, tiled=True, lock=lock, recalc_transform=False)
    with rasterio.open(out) as written, rasterio.open(cli_shade) as cli:
        assert written.crs == cli.crs and written.transform == cli.transform
        assert written.descriptions == cli.descriptions[:3]
        assert written.block_shapes[0] == (128, 128)
        np.testing.assert_array_equal(written.read(), cli.read([1, 2, 3]))
    with rasterio.open(horizon) as written, rasterio.open(cli_shade) as cli:
        np.testing.assert_array_equal(written.read(), cli.read(list(range(4, 12))))


def test_a_raster_file_with_voids_writes_as_the_command_line(client, run_relief, tmp_path):
    heights = hills(150, 170) * 20.0
    heights[60:66, 70:90] = -9999.0
    dem = tmp_path / "voids.tif"
    transform = rasterio.transform.from_origin(-84.4, 36.7, 1 / 1200, 1 / 1200)
    with rasterio.open(dem, "w", driver="GTiff", width=170, height=150, count=1,
                       dtype="float32", crs="EPSG:4326", transform=transform,
                       nodata=-9999.0) as file:
        file.write(heights, 1)
    run_relief("shade", dem, "-o", tmp_path / "cli.tif", "--layers", "sky,hillshade,horizon",
               "--azimuths", "4")
    ds = relief.dask.shade(dem, chunks=(64, 100), layers=["sky", "hillshade", "horizon"],
                           azimuths=4)
    assert np.isnan(ds["sky"].values[62, 80]), "voids are NaN in memory"
    lock = distributed.Lock("relief-test-voids")
    ds[["sky", "hillshade"]].rio.to_raster(tmp_path / "ours.tif", lock=lock,
                                           recalc_transform=False)
    ds["horizon"].rio.to_raster(tmp_path / "horizon.tif", lock=lock, recalc_transform=False)
    with rasterio.open(tmp_path / "ours.tif") as ours, \
            rasterio.open(tmp_path / "horizon.tif") as horizon, \
            rasterio.open(tmp_path / "cli.tif") as cli:
        assert ours.nodata == horizon.nodata == cli.nodata == -9999.0
        assert ours.crs == cli.crs and ours.transform == cli.transform == horizon.transform
        assert ours.descriptions + horizon.descriptions == cli.descriptions
        assert (cli.read(1) == -9999.0).sum() == 6 * 20
        np.testing.assert_array_equal(ours.read(), cli.read([1, 2]))
        np.testing.assert_array_equal(horizon.read(), cli.read([3, 4, 5, 6]))


def test_corrupt_and_incomplete_stores_are_refused_with_the_tile_named(client, store, tmp_path):
    import shutil

    bad = tmp_path / "bad.store"
    shutil.copytree(store, bad)
    data = bad / "tiles.data"
    corrupt = bytearray(data.read_bytes())
    corrupt[4 * 300] ^= 0x55
    data.write_bytes(bytes(corrupt))
    with pytest.raises(relief.ReliefError, match="tile .*checksum|checksum.*tile"):
        relief.dask.shade(bad, chunks=CHUNKS, layers=["hillshade"]).compute()
    index = bad / "index.json"
    index.write_text(index.read_text().replace('"complete": true', '"complete": false'))
    with pytest.raises(relief.ReliefError, match="incomplete|not complete"):
        relief.dask.shade(bad, chunks=CHUNKS, layers=["hillshade"])


def test_chunks_smaller_than_a_tile_and_array_options_are_refused(store):
    with pytest.raises(relief.ReliefError, match=r"smaller than the store's 64-sample tiles"):
        relief.dask.shade(store, chunks=(64, 32))
    with pytest.raises(relief.ReliefError, match="at least 64"):
        relief.dask.shade(store, chunks=48)
    with pytest.raises(relief.ReliefError, match="spacing, origin and z_scale are for arrays"):
        relief.dask.shade(store, spacing=2.0)
    with pytest.raises(relief.ReliefError, match="unknown layer 'shadows'"):
        relief.dask.shade(store, layers=["shadows"])
    with pytest.raises(relief.ReliefError, match="chunks must be a positive"):
        relief.dask.shade(store, chunks=(0, 128))


# The radius form.

RADIUS = 25.0
SPACING = (2.0, 3.0)
BOUNDED = ["horizon", "sky", "sky-aniso", "openness-pos", "openness-neg", "hillshade",
           "hillshade-multi"]


def rough(rows=300, cols=400):
    """Hills with noise: horizons that change from sample to sample."""
    noise = np.random.default_rng(7).random((rows, cols)).astype(np.float32)
    return hills(rows, cols) * 3.0 + noise * 2.0


def test_the_radius_form_equals_the_whole_array_bit_for_bit(client):
    heights = rough()
    options = dict(spacing=SPACING, radius=RADIUS, layers=BOUNDED, azimuths=16,
                   suns=[(200.0, 30.0)])
    chunked = dask_array.from_array(heights, chunks=(100, 120))
    ds = relief.dask.shade(chunked, **options)
    assert ds["sky"].data.chunks == chunked.chunks
    computed = ds.compute()
    whole = relief.shade(heights, **options)
    for name in BOUNDED:
        np.testing.assert_array_equal(computed[name].values, whole[name], err_msg=name)
    # A NumPy array is wrapped with the chunks asked for; the sun over a day too.
    sunny = dict(spacing=SPACING, radius=RADIUS, layers=["insolation", "sun-hours"],
                 azimuths=16, date="2024-06-21", latitude=46.0, longitude=7.0, step="1h")
    ds = relief.dask.shade(heights, chunks=(64, 200), **sunny)
    assert ds["insolation"].data.chunks == ((64,) * 4 + (44,), (200, 200))
    whole = relief.shade(heights, **sunny)
    for name in sunny["layers"]:
        np.testing.assert_array_equal(ds[name].values, whole[name], err_msg=name)


def test_the_halo_is_what_the_radius_needs(client):
    # A halo one sample short of the radius's misses terrain that raises horizons: the
    # check that the halo above is not larger than it needs to be exact by chance.
    heights = rough(120, 160)
    halo = (math.ceil(RADIUS / SPACING[1]), math.ceil(RADIUS / SPACING[0]))
    whole = relief.shade(heights, SPACING, radius=RADIUS, layers=["horizon"], azimuths=16)
    r0, c0 = 40, 50
    for short in (0, 1):
        rows, cols = halo[0] - short, halo[1] - short
        block = heights[r0 - rows:r0 + 40 + rows, c0 - cols:c0 + 40 + cols]
        part = relief.shade(block, SPACING, radius=RADIUS, layers=["horizon"], azimuths=16)
        same = np.array_equal(part["horizon"][:, rows:rows + 40, cols:cols + 40],
                              whole["horizon"][:, r0:r0 + 40, c0:c0 + 40])
        assert same == (short == 0)


def test_a_data_array_keeps_its_coordinates_and_crs(client, dem):
    _, path = dem
    heights = rioxarray.open_rasterio(path, chunks={"y": 150, "x": 200}).squeeze("band", drop=True)
    ds = relief.dask.shade(heights, spacing=10.0, radius=100.0, layers=["sky"], azimuths=8)
    assert ds.rio.crs == heights.rio.crs
    np.testing.assert_array_equal(ds["x"].values, heights["x"].values)
    np.testing.assert_array_equal(ds["y"].values, heights["y"].values)
    whole = relief.shade(heights.values, 10.0, radius=100.0, layers=["sky"], azimuths=8)
    np.testing.assert_array_equal(ds["sky"].values, whole["sky"])


@pytest.mark.parametrize("kwargs, message", [
    (dict(layers=["sky"]), r"needs radius= \(metres\)"),
    (dict(radius=25.0, layers=["sky", "shadow"]), "shadow: cast shadows reach terrain at any"),
    (dict(radius=25.0, layers=["combined"]), "combined: cast shadows"),
    (dict(radius=25.0, layers=["sky-illumination"]), "sky-illumination: cast shadows"),
    (dict(radius=100.0, layers=["sky"]),
     r"a radius of 100.0 m needs a halo of 36 rows .* deeper than a chunk of 32 rows: give "
     r"chunks of at least 36 x 52 samples"),
    (dict(radius=25.0, layers=["sky"], azimuths=0), "azimuths"),
])
def test_the_radius_form_refuses_what_it_cannot_make_exactly(kwargs, message):
    heights = dask_array.from_array(rough(64, 120), chunks=(32, 60))
    with pytest.raises(relief.ReliefError, match=message):
        relief.dask.shade(heights, spacing=SPACING, **kwargs)


# The fly-through.


def camera_path(folder, bounds):
    """A camera path over the terrain of ``bounds``: three keys around it, the last looking
    straight down (its up vector along y)."""
    (x0, y0, z0), (x1, y1, z1) = bounds
    cx, cy, cz = (x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 2
    span = max(x1 - x0, y1 - y0)
    key = lambda t, eye, up, fov: {"time_s": t, "eye": eye, "target": [cx, cy, cz],
                                   "up": up, "fov_deg": fov}
    path = folder / "path.json"
    path.write_text(json.dumps({"format": "relief-camera-path", "version": 1, "keys": [
        key(0.0, [x0 - 0.3 * span, y0 - 0.2 * span, z1 + 0.4 * span], [0, 0, 1], 45.0),
        key(0.7, [x1 + 0.1 * span, y0 - 0.3 * span, z1 + 0.3 * span], [0, 0.1, 1], 50.0),
        key(1.3, [cx, cy, z1 + 0.6 * span], [0, 1, 0], 40.0),
    ]}))
    return path


@pytest.mark.parametrize("kind", ["raster", "store"])
def test_flythrough_frames_are_the_command_lines_bytes(client, dem, store, run_relief,
                                                       tmp_path, kind):
    _, raster = dem
    source = raster if kind == "raster" else store
    path = camera_path(tmp_path, relief.open(source).info["bounds"])
    wait = ["--wait"] if kind == "store" else []
    run_relief("flythrough", source, "--path", path, "--frames", 7, "-o", tmp_path / "cli",
               "--size", "96x64", "--sun", "200,25", *wait)
    files = relief.dask.flythrough(source, path, 7, tmp_path / "dask", size=(96, 64),
                                   sun=(200.0, 25.0))
    assert [f.rsplit("/", 1)[1] for f in files] == [f"frame-{i:05d}.png" for i in range(7)]
    for name in (f"frame-{i:05d}.png" for i in range(7)):
        cli, ours = (tmp_path / "cli" / name).read_bytes(), (tmp_path / "dask" / name).read_bytes()
        assert cli == ours, name
    assert len({(tmp_path / "cli" / f"frame-{i:05d}.png").read_bytes() for i in range(7)}) == 7


def test_flythrough_tasks_are_one_a_frame_and_compute_later(client, dem, tmp_path):
    _, raster = dem
    path = camera_path(tmp_path, relief.open(raster).info["bounds"])
    tasks = relief.dask.flythrough(raster, path, 3, tmp_path / "frames", size=(32, 24),
                                   png_compression="high", compute=False)
    assert len(tasks) == 3 and not (tmp_path / "frames" / "frame-00000.png").exists()
    files = client.compute(tasks, sync=True)
    assert [f.rsplit("/", 1)[1] for f in files] == ["frame-00000.png", "frame-00001.png",
                                                     "frame-00002.png"]
    with pytest.raises(relief.ReliefError, match="unknown PNG compression 'best'"):
        relief.dask.flythrough(raster, path, 3, tmp_path / "frames", png_compression="best")
    with pytest.raises(relief.ReliefError, match="frames 0 must be 1 to 100000"):
        relief.dask.flythrough(raster, path, 0, tmp_path / "frames")
    (tmp_path / "bad.json").write_text('{"format": "x", "version": 1, "keys": []}')
    with pytest.raises(relief.ReliefError, match="not a relief-camera-path"):
        relief.dask.flythrough(raster, tmp_path / "bad.json", 3, tmp_path / "frames")
    with pytest.raises(FileNotFoundError):
        relief.flight_plan(tmp_path / "missing.json", 3)
