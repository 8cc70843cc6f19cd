"""Bad arguments raise Python exceptions (never crash the interpreter), with the messages the
relief command line gives for the same mistakes."""

import numpy as np
import pytest

import relief

FLAT = np.zeros((8, 8), np.float32)
RAY = (np.array([[4.0, 4.0, 10.0]]), np.array([[0.0, 0.0, -1.0]]))


def test_relief_error_is_a_value_error():
    assert issubclass(relief.ReliefError, ValueError)


@pytest.mark.parametrize(
    "heights, message",
    [
        (np.zeros(5, np.float32), "heights must be a 2-D array (rows, columns), got a 1-D array of shape (5,)"),
        (np.zeros((2, 3, 4)), "got a 3-D array of shape (2, 3, 4)"),
        (np.zeros((0, 5)), "heights: raster of 5 x 0 samples is empty"),
        (np.zeros((5, 0), np.int16), "heights: raster of 0 x 5 samples is empty"),
        (np.array([[1.0, 2.0, 3.0], [4.0, 5.0, np.inf]]), "heights: sample at column 2, row 1 is inf"),
        (np.full((3, 3), np.nan), "heights: invalid data: every sample is a void (nodata)"),
        (np.zeros((3, 3), np.complex64), "heights: dtype complex64 is not a real number type"),
        (np.zeros((3, 3), bool), "heights: dtype bool is not a real number type"),
        (np.array([["a", "b"]]), "is not a real number type"),
        ([[1, 2], [3]], "heights is not an array of numbers"),
        ("not an array", "is not a real number type"),
    ],
)
def test_bad_heights(heights, message):
    with pytest.raises(relief.ReliefError) as caught:
        relief.render(heights, size=(8, 8))
    assert message in str(caught.value)
    with pytest.raises(relief.ReliefError) as caught:
        relief.intersect(heights, *RAY)
    assert message in str(caught.value)


# (Python keyword arguments of render, relief render's arguments, what both messages say)
SAME_MISTAKES = [
    (dict(spacing=0), ["--spacing", "0"], "must be positive, within 1e-6..10000000 world units"),
    (dict(spacing=(1, 1e300)), ["--spacing", "1,1e300"], "must be positive, within 1e-6..10000000 world units"),
    (dict(z_scale=-3), ["--z-scale", "-3"], "z scale -3 is outside 1e-6..10000000"),
    (dict(camera={"fov": 0}), ["--fov", "0"], "field of view 0 is outside 0.01..179 degrees"),
    (dict(camera={"fov": 180}), ["--fov", "180"], "field of view 180 is outside 0.01..179 degrees"),
    (dict(exposure=-1), ["--exposure", "-1"], "exposure -1 is outside 0.0001..10000"),
    (dict(sun=(0, 95)), ["--sun", "0,95"], "is outside -90..90 degrees"),
    (dict(sun=(400, 10)), ["--sun", "400,10"], "is outside -360..360 degrees"),
    (dict(size=(0, 10)), ["--size", "0x10"], "is not an image dimension between 1 and 32768"),
    (dict(size=(10, 40000)), ["--size", "10x40000"], "is not an image dimension between 1 and 32768"),
    (dict(surface="spheres"), ["--surface", "spheres"], "unknown surface 'spheres'"),
    (dict(tracer="bogus"), ["--tracer", "bogus"], "unknown tracer 'bogus'"),
    (
        dict(camera={"eye": (1, 2, 3), "target": (1, 2, 3)}),
        ["--eye", "1,2,3", "--target", "1,2,3"],
        "eye and target are the same point",
    ),
    (
        dict(camera={"eye": (1e10, 0, 0), "target": (0, 0, 0)}),
        ["--eye", "1e10,0,0", "--target", "0,0,0"],
        "is farther than 1e9 m from the origin on an axis",
    ),
    (
        dict(camera={"eye": (0, 0, 9), "target": (1, 1, 1), "up": (0, 0, 0)}),
        ["--eye", "0,0,9", "--target", "1,1,1", "--up", "0,0,0"],
        "is not a direction (its length must be finite and not 0)",
    ),
]


@pytest.mark.parametrize("kwargs, cli, message", SAME_MISTAKES, ids=lambda v: str(v)[:40])
def test_option_errors_say_what_the_command_line_says(tmp_path, run_relief, kwargs, cli, message):
    with pytest.raises(relief.ReliefError) as caught:
        relief.render(FLAT, **{"size": (8, 8), **kwargs})
    assert message in str(caught.value)
    np.save(tmp_path / "flat.npy", FLAT)
    size = [] if "--size" in cli else ["--size", "8x8"]
    done = run_relief(
        "render", tmp_path / "flat.npy", *size, "-o", tmp_path / "o.png", *cli, check=False
    )
    assert done.returncode != 0 and message in done.stderr, done.stderr


@pytest.mark.parametrize(
    "kwargs, message",
    [
        (dict(camera={"eye": (1, 2, 3)}), "camera: 'eye' and 'target' go together"),
        (dict(camera={"up": (0, 1, 0)}), "camera: 'up' needs 'eye' and 'target'"),
        (dict(camera={"position": (1, 2, 3)}), "camera: unknown key 'position' (expected eye, target, up, fov)"),
        (dict(camera={"eye": (1, 2), "target": (0, 0, 0)}), "camera['eye'] must be three numbers"),
        (dict(camera={"eye": (0, 0, float("nan")), "target": (0, 0, 0)}), "camera['eye'] (0, 0, NaN)"),
        (dict(spacing="wide"), "spacing must be a number, a pair (dx, dy) or the georeference dict"),
        (dict(spacing={"origin": (0, 0)}), "the georeference dict has no 'spacing'"),
        (dict(origin=(float("inf"), 0)), "origin (inf, 0) is farther than"),
        (dict(voids="ignore"), "unknown voids 'ignore' (expected fill or hole)"),
        (dict(tracer="safety"), "the safety tracer is not offered by the Python module"),
    ],
)
def test_other_bad_options(kwargs, message):
    with pytest.raises(relief.ReliefError) as caught:
        relief.render(FLAT, **{"size": (8, 8), **kwargs})
    assert message in str(caught.value)


def test_wrong_types_raise_type_errors():
    with pytest.raises(TypeError):
        relief.render(FLAT, size="8x8")
    with pytest.raises(TypeError):
        relief.render(FLAT, shadows="yes please")
    with pytest.raises(TypeError):
        relief.render(FLAT, camera=[1, 2, 3])


@pytest.mark.parametrize(
    "origins, directions, message",
    [
        (np.zeros((2, 3)), np.zeros((3, 3)) + 1, "same number of rays, got 2 and 3"),
        (np.zeros((2, 2)), np.ones((2, 2)), "origins must be an array of shape (N, 3), got shape (2, 2)"),
        (np.zeros(3), np.ones(3), "origins must be an array of shape (N, 3), got shape (3,)"),
        (np.zeros((2, 3)), [[0, 0, -1], [0, 0, 0]], "directions: row 1 is zero, not a direction"),
        (np.array([[0, np.nan, 1.0]]), np.ones((1, 3)), "origins: row 0 (0, NaN, 1) is not finite"),
        (np.zeros((1, 3)), np.array([[0, 0, -np.inf]]), "directions: row 0 (0, 0, -inf) is not finite"),
        (np.zeros((1, 3), complex), np.ones((1, 3)), "origins: dtype complex128 is not a real number type"),
    ],
)
def test_bad_rays(origins, directions, message):
    with pytest.raises(relief.ReliefError) as caught:
        relief.intersect(FLAT, origins, directions)
    assert message in str(caught.value)


def test_file_errors_are_os_errors_with_relief_messages(tmp_path, run_relief):
    missing = tmp_path / "missing.tif"
    with pytest.raises(FileNotFoundError) as caught:
        relief.read(missing)
    message = str(caught.value)
    assert str(missing) in message
    done = run_relief("info", missing, check=False)
    assert done.returncode != 0 and message in done.stderr, (message, done.stderr)

    (tmp_path / "heights.xyz").write_text("1 2 3")
    with pytest.raises(OSError, match="unsupported file type: expected .tif"):
        relief.read(tmp_path / "heights.xyz")

    (tmp_path / "broken.npy").write_bytes(b"\x93NUMPY garbage")
    with pytest.raises(OSError, match="broken.npy: unsupported .npy format version"):
        relief.read(str(tmp_path / "broken.npy"))

    (tmp_path / "folder.npy").mkdir()
    with pytest.raises(OSError, match="folder.npy"):
        relief.read(tmp_path / "folder.npy")

    np.save(tmp_path / "big.npy", np.zeros((64, 64), np.float32))
    with pytest.raises(OSError, match="over the 0 MiB memory limit"):
        relief.read(tmp_path / "big.npy", max_memory=1000)


def test_read_option_errors():
    with pytest.raises(relief.ReliefError, match="unknown png_encoding 'rgb'"):
        relief.read("x.png", png_encoding="rgb")
    with pytest.raises(relief.ReliefError, match="max_memory must be at least 1 byte"):
        relief.read("x.npy", max_memory=0)
    with pytest.raises(OverflowError):
        relief.read("x.npy", max_memory=-1)


def test_an_up_along_the_view_is_replaced_with_a_warning():
    camera = {"eye": (4, 4, 50), "target": (4, 4, 0)}
    with pytest.warns(UserWarning, match="is parallel to the view; using 0,1,0"):
        rgb, depth = relief.render(FLAT, size=(8, 8), camera=camera)
    assert np.isfinite(depth).any()
