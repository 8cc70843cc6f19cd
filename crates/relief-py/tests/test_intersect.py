"""relief.intersect against rays known analytically (flat and tilted planes) and against
render's depth for the camera's own rays (DESIGN.md's pinhole camera)."""

import numpy as np
import pytest

import relief


def test_a_flat_plane_from_above_below_and_inside():
    heights = np.full((20, 20), 5.0, np.float32)
    heights[19, 19] = 0.0  # the solid then reaches down to 0 (the south-east corner is low)
    origins = np.array([[10.0, 10.0, 9.0], [3.0, 4.0, 25.0], [10.0, 10.0, 9.0], [10.0, 10.0, 2.0],
                        [-10.0, 10.0, 9.0], [10.0, 10.0, 9.0]])
    directions = np.array([[0.0, 0.0, -1.0], [0.0, 0.0, -4.0], [0.0, 0.0, 1.0], [0.3, 0.1, -1.0],
                           [-1.0, 0.0, -0.1], [1.0, 0.5, -1.0]])
    for surface in ["triangles", "boxes"]:
        t = relief.intersect(heights, origins, directions, surface=surface)
        # Straight down: 4 units; a direction 4 units long: t = 20 / 4; up: a miss; a start
        # inside the solid: 0; pointing away: a miss; oblique: the plane at z = 5, t = 4.
        assert t.tolist() == [4.0, 5.0, np.inf, 0.0, np.inf, 4.0], surface


def test_spacing_z_scale_and_origin_place_the_plane():
    heights = np.full((10, 10), 2.0, np.float32)
    origins = np.array([[1000.0 + 15.0, -500.0 + 35.0, 20.0]])
    t = relief.intersect(heights, origins, [[0, 0, -1]], (3.0, 7.0), origin=(1000.0, -500.0),
                         z_scale=4.0, surface="boxes")
    assert t.tolist() == [12.0]
    miss = relief.intersect(heights, [[15.0, 35.0, 20.0]], [[0, 0, -1]], (3.0, 7.0),
                            origin=(1000.0, -500.0))
    assert miss.tolist() == [np.inf]


@pytest.mark.parametrize("tracer", ["mipmap", "naive"])
def test_a_tilted_plane_hit_at_its_analytic_distance(tracer):
    rows, cols, dx, dy = 30, 40, 2.0, 1.5
    # z = a x + b y + c, with samples exact in float32.
    a, b, c = 0.25, -0.5, 20.0
    # Sample centres: array row r (from the north) is grid row rows - 1 - r.
    x = (np.arange(cols) + 0.5) * dx
    y = (rows - 1 - np.arange(rows) + 0.5) * dy
    heights = (a * x[None, :] + b * y[:, None] + c).astype(np.float64)
    rng = np.random.default_rng(7)
    n = 500
    # Hit points well inside the samples' hull, rays from 30 units above the plane.
    hx = rng.uniform(1.5 * dx, (cols - 1.5) * dx, n)
    hy = rng.uniform(1.5 * dy, (rows - 1.5) * dy, n)
    hz = a * hx + b * hy + c
    directions = np.column_stack([rng.uniform(-0.3, 0.3, n), rng.uniform(-0.3, 0.3, n),
                                  -rng.uniform(0.5, 2.0, n)])
    # Plane normal (-a, -b, 1): the start is 30 units above the plane along the normal's z.
    t_true = rng.uniform(0.5, 2.0, n)
    origins = np.column_stack([hx, hy, hz]) - t_true[:, None] * directions
    t = relief.intersect(heights, origins, directions, (dx, dy), tracer=tracer)
    np.testing.assert_allclose(t, t_true, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(origins + t[:, None] * directions, np.column_stack([hx, hy, hz]),
                               atol=1e-8)


def camera_rays(eye, target, up, fov, width, height):
    """The unit pixel directions of DESIGN.md's pinhole camera, row 0 the top row."""
    eye, target, up = (np.asarray(v, np.float64) for v in (eye, target, up))
    forward = (target - eye) / np.linalg.norm(target - eye)
    right = np.cross(forward, up)
    right /= np.linalg.norm(right)
    true_up = np.cross(right, forward)
    t = np.tan(np.radians(fov) / 2)
    j, i = np.mgrid[0:height, 0:width]
    sx = (2 * (i + 0.5) / width - 1) * t * width / height
    sy = (1 - 2 * (j + 0.5) / height) * t
    d = forward + sx[..., None] * right + sy[..., None] * true_up
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    return np.broadcast_to(eye, d.shape).reshape(-1, 3), d.reshape(-1, 3)


@pytest.mark.parametrize("surface", ["triangles", "boxes"])
def test_intersect_agrees_with_the_depth_render_returns(terrain, surface):
    eye, target, up, fov, (w, h) = (-20.0, -30.0, 45.0), (24.0, 20.0, 4.0), (0, 0, 1), 45.0, (64, 48)
    _, depth = relief.render(terrain, size=(w, h), surface=surface,
                             camera={"eye": eye, "target": target, "fov": fov})
    origins, directions = camera_rays(eye, target, up, fov, w, h)
    t = relief.intersect(terrain, origins, directions, surface=surface).reshape(h, w)
    both = np.isfinite(t) & np.isfinite(depth)
    assert both.sum() > 0.2 * w * h
    # Ties at silhouettes may go either way between two roundings of one ray.
    assert (np.isfinite(t) != np.isfinite(depth)).sum() <= 3
    close = np.isclose(t[both], depth[both], rtol=1e-5)
    assert (~close).sum() <= 3
