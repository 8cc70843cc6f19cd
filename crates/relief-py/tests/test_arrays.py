"""NumPy round trips: every real dtype, C and Fortran order, strided views and nested lists
give the result their contiguous float32 copy gives."""

import numpy as np
import pytest

import relief

SMALL = dict(size=(32, 24))


def rays(n=200, seed=3):
    """Rays from above the test terrain towards points of its footprint (most hit it)."""
    rng = np.random.default_rng(seed)
    origins = np.column_stack(
        [rng.uniform(-5, 50, n), rng.uniform(-5, 45, n), rng.uniform(15, 40, n)]
    )
    targets = np.column_stack([rng.uniform(2, 46, n), rng.uniform(2, 38, n), np.zeros(n)])
    return origins, targets - origins


@pytest.mark.parametrize(
    "dtype", [np.float64, np.float16, np.int8, np.int16, np.int32, np.int64, np.uint8,
              np.uint16, np.uint32, np.uint64]
)
def test_every_real_dtype_is_read_as_its_float32_values(terrain, dtype):
    heights = (terrain * 3).astype(dtype)
    origins, directions = rays()
    expected = relief.intersect(heights.astype(np.float32), origins, directions)
    assert np.array_equal(relief.intersect(heights, origins, directions), expected)


def test_render_reads_integers_as_their_values(terrain):
    ints = np.round(terrain * 10).astype(np.int16)
    rgb, depth = relief.render(ints, **SMALL)
    rgb32, depth32 = relief.render(ints.astype(np.float32), **SMALL)
    assert np.array_equal(rgb, rgb32) and np.array_equal(depth, depth32)


@pytest.mark.parametrize(
    "view",
    [
        lambda a: np.asfortranarray(a),
        lambda a: a.T.copy().T,
        lambda a: np.repeat(np.repeat(a, 2, 0), 3, 1)[::2, ::3],
        lambda a: a[::-1][::-1],
        lambda a: np.ascontiguousarray(a[:, ::-1])[:, ::-1],
        lambda a: a.tolist(),
    ],
    ids=["fortran", "transposed-twice", "strided", "reversed-twice", "negative-strides", "list"],
)
def test_layouts_give_the_contiguous_result(terrain, view):
    arranged = view(terrain)
    if isinstance(arranged, np.ndarray):
        assert np.array_equal(arranged, terrain)
    rgb, depth = relief.render(arranged, **SMALL)
    rgb_c, depth_c = relief.render(terrain, **SMALL)
    assert np.array_equal(rgb, rgb_c) and np.array_equal(depth, depth_c)


def test_views_are_read_in_their_logical_order(terrain):
    big = np.repeat(terrain, 2, axis=0)
    origins, directions = rays()
    for view in [big[::2, ::3], big.T, big[5:30, 7:][::-1]]:
        copy = np.ascontiguousarray(view)
        assert not view.flags.c_contiguous
        assert np.array_equal(
            relief.intersect(view, origins, directions), relief.intersect(copy, origins, directions)
        )


def test_ray_arrays_of_any_layout_and_dtype(terrain):
    origins, directions = rays()
    expected = relief.intersect(terrain, origins, directions)
    assert expected.dtype == np.float64 and expected.shape == (200,)
    assert np.isfinite(expected).sum() > 150
    for o, d in [
        (np.asfortranarray(origins), np.asfortranarray(directions)),
        (np.ascontiguousarray(origins.T).T, directions.tolist()),
        (np.repeat(origins, 2, axis=0)[::2], np.repeat(directions, 2, axis=0)[::2]),
    ]:
        assert np.array_equal(relief.intersect(terrain, o, d), expected)
    t32 = relief.intersect(terrain, origins.astype(np.float32), directions.astype(np.float32))
    o32, d32 = origins.astype(np.float32).astype(np.float64), directions.astype(np.float32)
    assert np.array_equal(t32, relief.intersect(terrain, o32, d32.astype(np.float64)))


def test_no_rays_give_an_empty_array(terrain):
    t = relief.intersect(terrain, np.zeros((0, 3)), np.zeros((0, 3)))
    assert t.shape == (0,) and t.dtype == np.float64


def test_outputs_have_the_documented_shapes_and_dtypes(terrain):
    rgb, depth = relief.render(terrain, size=(40, 30))
    assert rgb.shape == (30, 40, 3) and rgb.dtype == np.uint8
    assert depth.shape == (30, 40) and depth.dtype == np.float32
    assert rgb.flags.c_contiguous and depth.flags.c_contiguous
    assert np.isinf(depth).any() and np.isfinite(depth).any()


def test_the_input_array_is_left_untouched(terrain):
    before = terrain.copy()
    relief.render(terrain, **SMALL)
    assert np.array_equal(terrain, before)


def test_renders_are_deterministic(terrain):
    a = relief.render(terrain, **SMALL)
    b = relief.render(terrain, **SMALL)
    assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])
