"""relief.open opens every input `relief render` takes as a Scene whose pictures are the
command line's, pixel for pixel (the PNG read back with Pillow, the depth .npy exactly); its
info says what it is, its shade layers are relief.shade's, and bad input raises
relief.ReliefError (or OSError for a file that cannot be read)."""

import numpy as np
import pytest

import relief

Image = pytest.importorskip("PIL.Image")


def cli_render(run_relief, tmp_path, input_args, args):
    png, depth = tmp_path / "cli.png", tmp_path / "cli-depth.npy"
    run_relief("render", *input_args, "-o", png, "--depth", depth, *args)
    return np.asarray(Image.open(png).convert("RGB")), np.load(depth)


def assert_same_picture(scene_picture, cli_picture, at_least_hits=50):
    (rgb, depth), (cli_rgb, cli_depth) = scene_picture, cli_picture
    assert rgb.dtype == np.uint8 and depth.dtype == np.float32
    assert rgb.shape == cli_rgb.shape and depth.shape == cli_depth.shape
    assert np.array_equal(rgb, cli_rgb)
    assert np.array_equal(depth, cli_depth)
    assert np.isfinite(depth).sum() >= at_least_hits


# (open's options, Scene.render's camera, relief render's arguments)
HEIGHT_FILE_CASES = [
    (dict(), None, []),
    (dict(north_up=True), {"eye": (-20.0, -30.0, 45.0), "target": (24.0, 20.0, 4.0)},
     ["--north-up", "--eye", "-20,-30,45", "--target", "24,20,4"]),
    (dict(spacing=(2.0, 3.0), z_scale=1.5, surface="boxes", tracer="naive", shadows=False),
     {"fov": 30.0},
     ["--spacing", "2,3", "--z-scale", "1.5", "--surface", "boxes", "--tracer", "naive",
      "--no-shadows", "--fov", "30"]),
    (dict(sun=(90.0, 10.0), exposure=2.0), {"view": (120.0, 40.0)},
     ["--sun", "90,10", "--exposure", "2", "--view", "120,40"]),
    (dict(), {"ortho": True, "view": (200.0, 60.0)}, ["--ortho", "--view", "200,60"]),
    (dict(tracer="hybrid"), None, ["--tracer", "hybrid"]),
    (dict(tracer="clipmap"), None, ["--tracer", "clipmap"]),
    (dict(mode="mesh"), None, ["--mode", "mesh"]),
]


@pytest.mark.parametrize(
    "options, camera, args", HEIGHT_FILE_CASES,
    ids=["framed", "camera", "boxes-naive", "view", "ortho", "hybrid", "clipmap", "mesh"],
)
def test_a_height_file_renders_as_the_command_line(tmp_path, run_relief, terrain, options,
                                                   camera, args):
    np.save(tmp_path / "h.npy", terrain)
    scene = relief.open(tmp_path / "h.npy", **options)
    picture = scene.render(camera, size=(64, 48))
    cli = cli_render(run_relief, tmp_path, [tmp_path / "h.npy"], ["--size", "64x48", *args])
    assert_same_picture(picture, cli)


def test_the_safety_tracer_renders_as_the_command_line(tmp_path, run_relief, terrain):
    np.save(tmp_path / "h.npy", terrain)
    cache = tmp_path / "shapes"
    scene = relief.open(tmp_path / "h.npy", tracer="safety", cache_dir=cache)
    picture = scene.render(size=(48, 32))
    cli = cli_render(run_relief, tmp_path, [tmp_path / "h.npy"],
                     ["--size", "48x32", "--tracer", "safety", "--cache-dir", cache])
    assert_same_picture(picture, cli)


def test_the_default_fbm_terrain_renders_as_the_command_line(tmp_path, run_relief):
    scene = relief.open(fbm_size=64, seed=3)
    assert scene.info["kind"] == "height_field" and scene.info["path"] is None
    assert scene.info["size"] == (64, 64)
    cli = cli_render(run_relief, tmp_path, [], ["--fbm-size", "64", "--seed", "3",
                                                "--size", "48x32"])
    assert_same_picture(scene.render(size=(48, 32)), cli)


@pytest.fixture
def arches(tmp_path, run_relief):
    path = tmp_path / "arches.json"
    run_relief("generate", "mlhm", "--scene", "arches", "--size", "16", "-o", path)
    return path


@pytest.mark.parametrize(
    "options, args",
    [(dict(), []), (dict(mode="smooth", preset="low"), ["--mode", "smooth", "--preset", "low"]),
     (dict(tracer="naive", ao=False), ["--tracer", "naive", "--no-ao"])],
    ids=["boxes", "smooth", "naive"],
)
def test_an_mlhm_scene_renders_as_the_command_line(tmp_path, run_relief, arches, options, args):
    scene = relief.open(arches, **options)
    info = scene.info
    assert info["kind"] == "mlhm" and info["size"] == (16, 16) and info["step"] == 0
    assert info["layers"] >= 2 and info["crs"] is None
    cli = cli_render(run_relief, tmp_path, [arches], ["--size", "64x48", *args])
    assert_same_picture(scene.render(size=(64, 48)), cli)


def test_a_stacks_file_renders_as_the_command_line(tmp_path, run_relief):
    path = tmp_path / "t.stacks"
    run_relief("generate", "stacks", "--width", "24", "--height", "24", "--max-height", "30",
               "-o", path)
    scene = relief.open(path)
    assert scene.info["kind"] == "stacks" and scene.info["size"] is None
    cli = cli_render(run_relief, tmp_path, [path], ["--size", "48x32"])
    assert_same_picture(scene.render(size=(48, 32)), cli)


def test_a_tile_store_renders_as_the_command_line(tmp_path, run_relief, terrain):
    rasterio = pytest.importorskip("rasterio")
    from rasterio.transform import Affine

    tif, store = tmp_path / "dem.tif", tmp_path / "store"
    heights = np.tile(terrain, (2, 2))
    with rasterio.open(
        tif, "w", driver="GTiff", width=96, height=80, count=1, dtype="float32",
        crs="EPSG:32633", transform=Affine(2.0, 0.0, 500000.0, 0.0, -2.0, 4100000.0),
    ) as out:
        out.write(heights, 1)
    run_relief("tile", tif, "-o", store, "--tile", "32")
    scene = relief.open(store)
    info = scene.info
    assert info["kind"] == "tile_store" and info["size"] == (96, 80)
    assert info["spacing"] == (2.0, 2.0)
    cli = cli_render(run_relief, tmp_path, [store], ["--size", "48x32"])
    assert_same_picture(scene.render(size=(48, 32)), cli)
    # The GeoTIFF itself names its CRS.
    dem = relief.open(tif).info
    assert dem["crs"] == "EPSG:32633" and dem["epsg"] == 32633
    assert dem["size"] == (96, 80) and dem["spacing"] == (2.0, 2.0)
    (x0, y0, _), (x1, y1, _) = dem["bounds"]
    assert (x1 - x0, y1 - y0) == pytest.approx((190.0, 158.0))


def test_a_height_field_scene_shades_as_relief_shade(tmp_path, terrain):
    np.save(tmp_path / "h.npy", terrain)
    scene = relief.open(tmp_path / "h.npy", north_up=True)
    layers = ["shadow", "hillshade"]
    shaded = scene.shade(layers=layers, suns=[(200.0, 20.0)])
    expected = relief.shade(terrain, layers=layers, suns=[(200.0, 20.0)])
    assert list(shaded) == layers
    for name in layers:
        assert shaded[name].shape == terrain.shape
        assert np.array_equal(shaded[name], expected[name]), name


def test_shade_is_refused_where_it_does_not_apply(arches):
    with pytest.raises(relief.ReliefError, match="shade layers of height fields; this is a 16x16 MLHM scene"):
        relief.open(arches).shade()


def test_scenes_say_what_they_are(tmp_path, terrain):
    np.save(tmp_path / "h.npy", terrain)
    scene = relief.open(tmp_path / "h.npy", spacing=2.0, surface="boxes")
    info = scene.info
    assert info["kind"] == "height_field" and info["size"] == (48, 40)
    assert info["spacing"] == (2.0, 2.0) and info["crs"] is None and info["epsg"] is None
    assert info["surface"] == "boxes" and info["tracer"] == "mipmap"
    assert info["bounds"][0][:2] == (0.0, 0.0) and info["bounds"][1][:2] == (96.0, 80.0)
    assert info["warnings"] == []
    assert "48x40 height field" in repr(scene)


@pytest.mark.parametrize(
    "options, message",
    [
        (dict(colour="red"), "open: unknown option 'colour'"),
        (dict(tracer="bogus"), "unknown tracer 'bogus'"),
        (dict(tracer="hierarchy"), "the hierarchy tracer renders MLHM scenes"),
        (dict(mode="spheres"), "unknown mode 'spheres' (expected boxes, smooth or mesh)"),
        (dict(preset="ultra"), "unknown preset 'ultra'"),
        (dict(spacing=0), "must be positive, within 1e-6..10000000 world units"),
        (dict(z_scale=-3), "z scale -3 is outside 1e-6..10000000"),
        (dict(sun=(0, 95)), "is outside -90..90 degrees"),
        (dict(exposure=-1), "exposure -1 is outside 0.0001..10000"),
        (dict(voids="ignore"), "unknown voids 'ignore'"),
        (dict(sigma=-1), "open: sigma must be a positive number"),
        (dict(fbm_size=64), "fbm_size applies to the default fBm terrain"),
        (dict(max_memory=0), "max_memory must be at least 1 byte"),
    ],
)
def test_bad_options_raise_relief_errors(tmp_path, terrain, options, message):
    np.save(tmp_path / "h.npy", terrain)
    with pytest.raises(relief.ReliefError) as caught:
        relief.open(tmp_path / "h.npy", **options).render(size=(8, 8))
    assert message in str(caught.value)


def test_bad_cameras_and_inputs_raise(tmp_path, terrain):
    with pytest.raises(FileNotFoundError):
        relief.open(tmp_path / "missing.tif")
    np.save(tmp_path / "h.npy", terrain)
    scene = relief.open(tmp_path / "h.npy")
    for camera, message in [
        ({"view": (0, 0)}, "view elevation 0 must be more than 0"),
        ({"view": (400, 30)}, "view azimuth 400 is outside -360..360 degrees"),
        ({"ortho": True, "fov": 30}, "camera['fov'] applies to perspective cameras"),
        ({"ortho_height": 10}, "camera['ortho_height'] applies to 'ortho' cameras only"),
        ({"eye": (1, 2, 3)}, "camera: 'eye' and 'target' go together"),
        ({"position": (1, 2, 3)}, "camera: unknown key 'position'"),
    ]:
        with pytest.raises(relief.ReliefError) as caught:
            scene.render(camera, size=(8, 8))
        assert message in str(caught.value), camera
    with pytest.raises(relief.ReliefError, match="is not an image dimension"):
        scene.render(size=(0, 8))
    small = relief.open(tmp_path / "h.npy", max_memory=1_000_000)
    with pytest.raises(relief.ReliefError, match=r"a 2000x2000 image needs .* over the 976.6 KiB"
                       r" memory limit \(relief.open\(..., max_memory=N\)\)"):
        small.render(size=(2000, 2000))
    with pytest.warns(UserWarning, match="is parallel to the view"):
        scene.render({"eye": (24, 20, 80), "target": (24, 20, 0)}, size=(8, 8))


def test_renders_of_one_scene_from_several_threads_give_the_picture_of_one(tmp_path, terrain):
    import threading

    np.save(tmp_path / "h.npy", terrain)
    scene = relief.open(tmp_path / "h.npy")
    alone = scene.render(size=(48, 32))
    results = [None] * 4

    def run(k):
        results[k] = scene.render(size=(48, 32))

    threads = [threading.Thread(target=run, args=(k,)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for rgb, depth in results:
        assert np.array_equal(rgb, alone[0]) and np.array_equal(depth, alone[1])
