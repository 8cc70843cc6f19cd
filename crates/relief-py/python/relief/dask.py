"""relief on Dask: shade rasters of any size chunk by chunk, and render fly-throughs a frame a
task, on a laptop's cores or on a cluster (dask.distributed).

It needs Dask, xarray and rioxarray, which relief itself does not::

    pip install "dask[distributed]" xarray rioxarray

- ``shade(store_or_raster, chunks=...)``: the exact shade layers of a tile store (made by
  ``relief tile``) or of a raster file, lazily, as an ``xarray.Dataset`` of Dask arrays with
  the raster's coordinates and CRS; each chunk shaded by a worker reading the store from a
  filesystem every worker sees, the values those ``relief shade`` writes, bit for bit.
- ``shade(array, spacing=..., radius=R)``: the layers that reach only ``R`` metres, of any
  Dask (or NumPy) array, by ``dask.array.map_overlap`` with the halo ``R`` needs.
- ``flythrough(input, path, frames, output)``: the frames of a camera path, one Dask task a
  frame, the PNGs ``relief flythrough`` writes.

See docs/scale.md for a whole run, from ``relief tile`` to a Slurm cluster.
"""

from __future__ import annotations

import functools
import math
import os
import threading
from collections.abc import Mapping
from typing import Any, List, Tuple, Union

import numpy as np

import relief
from relief import ReliefError

try:
    import dask
    import dask.array as da
    import xarray
    import rioxarray  # noqa: F401  (the .rio accessor)
    from affine import Affine
    from rioxarray.rioxarray import affine_to_coords
except ImportError as missing:  # pragma: no cover (the tests need them)
    raise ImportError(
        f"relief.dask needs Dask, xarray and rioxarray ({missing}): "
        'pip install "dask[distributed]" xarray rioxarray'
    ) from missing

__all__ = ["flythrough", "shade", "RADIUS_HALO_MARGIN", "UNBOUNDED_LAYERS"]

#: Chunks, samples a side, when none are given: a multiple of a store's tile near this.
DEFAULT_CHUNK = 2048
#: Samples added to a radius's halo: the triangles' cells a line at the radius ends in, and
#: the 3 x 3 neighbourhood of the hillshade's gradient.
RADIUS_HALO_MARGIN = 2
#: The layers whose value at a sample depends on terrain at any distance (their sun rays are
#: traced to the edge of the data): the radius form refuses them.
UNBOUNDED_LAYERS = ("shadow", "combined", "sky-illumination")
#: relief.write_png's compressions, as --png-compression.
_PNG_COMPRESSIONS = ("none", "fast", "balanced", "high")
#: Keywords a store or raster file gives itself (its georeference).
_PLACEMENT = ("spacing", "origin", "z_scale")


Chunks = Union[int, Tuple[int, int], None]


def shade(source: Union[str, os.PathLike, da.Array, np.ndarray, xarray.DataArray],
          chunks: Chunks = None, **options: Any) -> xarray.Dataset:
    """The shade layers of a tile store, a raster file or an array, lazily, chunk by chunk,
    as an ``xarray.Dataset`` of Dask arrays: one variable per layer, as ``relief.shade``
    returns a dict, float32, NaN at voids, dims ``(y, x)``; the
    ``horizon`` dims ``(azimuth, y, x)`` with the directions in degrees clockwise from north.
    Computing it (``ds.compute()``, ``ds.rio.to_raster(...)``, ...) shades the chunks on the
    current Dask scheduler: a ``distributed.Client``'s workers where one is connected. Each
    chunk is shaded once, whatever the number of layers asked for. On a ``distributed``
    worker a chunk is shaded on one thread (``threads=1`` unless ``options`` say otherwise),
    since the worker runs a task on each of its threads: a worker of ``nthreads`` threads
    uses that many cores. Elsewhere (no ``Client``) the chunks share the process's threads.

    **A store or a raster file** (``source`` a path: a folder written by ``relief tile``, or
    any raster ``relief shade`` reads): the layers ``relief shade SOURCE`` writes, exactly,
    bit for bit; each chunk is ``relief.shade_window(source, window, **options)``, computed
    by a worker that reads ``source`` itself, so every worker must see it at the same path
    (a shared filesystem). The x and y coordinates are the pixels' centres, as
    ``rioxarray.open_rasterio`` gives them for ``relief shade``'s output, with the source's
    CRS and transform attached (``ds.rio.crs``, ``ds.rio.transform()``; write with
    ``rio.to_raster(..., recalc_transform=False)`` to keep the transform exactly rather than
    recompute it from the coordinates), and the source's nodata as the value a file gets at
    voids (``rio.encoded_nodata``; NaN where the source has none), each band's name as
    ``relief shade`` names it (``long_name``): ``ds.rio.to_raster`` writes the values,
    georeference, nodata and band names ``relief shade`` writes. ``chunks``: samples
    a side, an int or ``(rows, columns)``, at least the store's tile (``relief tile
    --tile``; a multiple of it reads each tile for one chunk only); default the multiple of
    the tile nearest 2048 (2048 for a raster file). ``options``: the keywords of
    ``relief.shade`` (``layers``, ``suns``, ``azimuths``, ``radius``, ``date``, ...) but
    ``spacing``, ``origin`` and ``z_scale``, which the source's georeference gives, and with
    ``max_memory``, the most bytes a raster file may take in a worker.

    **An array** (``source`` a ``dask.array.Array``, a NumPy array or a 2-D
    ``xarray.DataArray``, north-up, heights as ``relief.shade`` takes them) with ``radius``
    (metres, required) and ``spacing``, ``origin``, ``z_scale`` as ``relief.shade`` takes
    them: each chunk (``chunks`` rechunks the array first) is shaded by ``relief.shade``
    together with a halo of ``ceil(radius / spacing) + 2`` samples of its neighbours on each
    side (``dask.array.map_overlap``, boundary ``"none"``: none beyond the array's edges),
    then cut back to the chunk. The layers built on horizons searched to ``radius`` (``horizon``,
    ``sky``, ``sky-aniso``, ``openness-pos``, ``openness-neg``, ``insolation``,
    ``sun-hours``) and the hillshades (``hillshade``, ``hillshade-multi``) see no farther
    than the halo, so they equal ``relief.shade(whole_array, radius=radius)`` exactly, bit for
    bit. The layers with cast shadows (``shadow``, ``combined``, ``sky-illumination``) depend
    on terrain at any distance and are refused: shade a store for them. With
    ``voids="fill"`` (the default) a void is filled from the valid samples of its chunk and
    halo, so a void wider than the halo may differ from the whole array's; ``voids="hole"``
    is exact. A ``DataArray``'s coordinates and CRS are kept.

    Raises ``relief.ReliefError`` for chunks smaller than the store's tile, a halo deeper than
    a chunk, a missing radius or a layer of unbounded reach (each message with the limit), and
    for options ``relief.shade`` refuses; ``OSError`` when the source cannot be read.
    """
    if isinstance(source, (str, os.PathLike)):
        return _shade_source(os.path.abspath(source), chunks, options)
    return _shade_array(source, chunks, options)


def flythrough(input: Union[str, os.PathLike, None], path: Union[str, os.PathLike],
               frames: int, output: Union[str, os.PathLike], *,
               size: Tuple[int, int] = (1280, 720), png_compression: str = "fast",
               compute: bool = True, **options: Any) -> List[Any]:
    """Renders the ``frames`` frames of the camera path ``path`` (JSON, docs/camera-path.md)
    over ``input`` as Dask tasks, one frame a task, writing ``output/frame-00000.png``, ...:
    the files ``relief flythrough INPUT --path PATH --frames N -o OUTPUT`` writes, the same
    names and the same bytes.

    ``input`` is what ``relief.open`` opens (a height file, an MLHM scene, a tile store), with
    ``options`` its keyword arguments (``z_scale``, ``surface``, ``tracer``, ``sun``,
    ``shadows``, ``exposure``, ...: ``relief flythrough``'s options of the scene, tracer and
    light); every worker opens it once, so it must be at the same path on every worker.
    ``size`` is ``(width, height)`` as ``--size``, ``png_compression`` as
    ``--png-compression``. The frames' cameras are ``relief flythrough``'s (the path's keys
    interpolated at evenly spread times, by the same code, ``relief.flight_plan``). A tile
    store's frames are those of ``relief flythrough --wait``: each waits for its tiles.

    With ``compute=True`` (the default) the frames are rendered on the current Dask scheduler
    and the list of the files written is returned; with ``compute=False`` the list of
    ``dask.delayed`` tasks, each returning its file, to compute later. The path and its
    cameras are checked before any task (``relief.ReliefError``, naming the frame), and the
    folder ``output`` is created.
    """
    plan = relief.flight_plan(path, frames)
    if png_compression not in _PNG_COMPRESSIONS:
        raise ReliefError(f"unknown PNG compression '{png_compression}' (expected none, fast, "
                          "balanced or high)")
    width, height = size
    output = os.path.abspath(output)
    os.makedirs(output, exist_ok=True)
    digits = max(5, len(str(frames - 1)))
    input = None if input is None else os.path.abspath(input)
    token = dask.base.tokenize(input, os.path.abspath(path), frames, output, size,
                               png_compression, options)
    tasks = []
    for index, frame in enumerate(plan):
        file = os.path.join(output, f"frame-{index:0{digits}d}.png")
        render = dask.delayed(_render_frame, pure=True)
        tasks.append(render(input, options, frame["camera"], (width, height), file,
                            png_compression, dask_key_name=f"relief-frame-{index}-{token}"))
    if not compute:
        return tasks
    return list(dask.compute(*tasks))


# The store or raster form.


def _shade_source(source, chunks, options):
    """``shade`` of a store or raster file at ``source``."""
    given = [key for key in _PLACEMENT if key in options]
    if given:
        raise ReliefError(
            f"{', '.join(given)}: a store or raster file is placed by its own georeference; "
            "spacing, origin and z_scale are for arrays"
        )
    bands = _layer_bands(options)
    memory = {"max_memory": options["max_memory"]} if "max_memory" in options else {}
    info = relief.source_info(source, **memory)
    width, height, tile = info["width"], info["height"], info.get("tile")
    rows, cols = _source_chunks(chunks, tile)
    row_chunks, col_chunks = _split(height, rows), _split(width, cols)
    count = sum(n for _, n in bands)
    token = dask.base.tokenize(source, _modified(source), options, rows, cols)
    if "date" not in options:
        _check_options(options)
    block = functools.partial(_shade_window_block, source=source,
                              layers=[name for name, _ in bands], options=options)
    stacked = da.map_blocks(
        block,
        chunks=((count,), row_chunks, col_chunks),
        dtype=np.float32,
        meta=np.empty((0, 0, 0), np.float32),
        name=f"relief-shade-{token}",
    )
    x, y = _pixel_centres(info["transform"], width, height)
    dataset = _dataset(stacked, bands, {"y": y, "x": x}, ("y", "x"), info.get("nodata"))
    crs = _crs(info)
    if crs is not None:
        dataset = dataset.rio.write_crs(crs)
    return dataset.rio.write_transform(Affine(*info["transform"]))


def _shade_window_block(*, source, layers, options, block_info=None):
    """One chunk of the store or raster at ``source``: its layers stacked, (bands, rows,
    columns), computed by ``relief.shade_window`` (on a worker)."""
    (row0, row1), (col0, col1) = block_info[None]["array-location"][1:]
    window = (col0, row0, col1 - col0, row1 - row0)
    shaded = relief.shade_window(source, window, **{"threads": _task_threads(), **options})
    return _stack(shaded, layers, row1 - row0, col1 - col0)


def _task_threads():
    """The threads a task shades or draws with: one on a ``distributed`` worker, which runs a
    task on each of its threads (so that its ``nthreads`` are the cores it uses); else None,
    the process's shared pool."""
    try:
        from distributed import get_worker

        get_worker()
    except (ImportError, ValueError):
        return None
    return 1


def _source_chunks(chunks, tile):
    """``chunks`` as (rows, columns), refused smaller than ``tile`` (None for a raster)."""
    if chunks is None:
        side = DEFAULT_CHUNK if not tile else tile * max(1, round(DEFAULT_CHUNK / tile))
        return side, side
    rows, cols = _pair(chunks, "chunks")
    if tile and (rows < tile or cols < tile):
        raise ReliefError(
            f"chunks ({rows}, {cols}) are smaller than the store's {tile}-sample tiles: give "
            f"chunks of at least {tile} samples a side (a multiple of {tile} reads each tile "
            "once)"
        )
    return rows, cols


def _modified(path):
    """When ``path`` (a file, or a store's folder) last changed, so that a store rewritten at
    the same path makes new tasks."""
    try:
        return os.stat(path).st_mtime_ns
    except OSError:
        return None


def _pixel_centres(transform, width, height):
    """The x and y coordinates of the pixels' centres, as ``rioxarray.open_rasterio`` makes
    them from the same transform."""
    coords = affine_to_coords(Affine(*transform), width, height)
    return coords["x"], coords["y"]


def _crs(info):
    """The source's CRS as rioxarray takes it, or None."""
    if info.get("epsg"):
        return f"EPSG:{info['epsg']}"
    return info.get("crs_wkt") or info.get("crs")


# The radius form.


def _shade_array(array, chunks, options):
    """``shade`` of an array with a radius, by ``map_overlap``."""
    radius = options.get("radius")
    if radius is None:
        raise ReliefError(
            "radius: an array is shaded chunk by chunk with a halo of the radius the horizons "
            "are searched to, so it needs radius= (metres); shade a store (relief tile) for "
            "horizons to the edge of the data"
        )
    bands = _layer_bands(options)
    unbounded = [name for name, _ in bands if name in UNBOUNDED_LAYERS]
    if unbounded:
        raise ReliefError(
            f"{', '.join(unbounded)}: cast shadows reach terrain at any distance, beyond any "
            f"halo, so an array is not shaded with them chunk by chunk (only the layers built "
            f"on horizons and the hillshades); shade a store (relief tile) for them"
        )
    coords, dims, keep_crs = {}, ("y", "x"), None
    if isinstance(array, xarray.DataArray):
        if array.ndim != 2:
            raise ReliefError(f"the heights must be 2-D, (rows, columns): dims {array.dims}")
        dims = array.dims
        coords = {name: array.coords[name] for name in dims if name in array.coords}
        keep_crs = array.rio.crs
        array = array.data
    if not isinstance(array, da.Array):
        array = np.asarray(array)
        array = da.from_array(array, chunks=_array_chunks(chunks, array.shape))
    elif chunks is not None:
        array = array.rechunk(_array_chunks(chunks, array.shape))
    if array.ndim != 2:
        raise ReliefError(f"the heights must be 2-D, (rows, columns): shape {array.shape}")

    dx, dy = _spacing(options.get("spacing"))
    depth = (math.ceil(radius / dy) + RADIUS_HALO_MARGIN,
             math.ceil(radius / dx) + RADIUS_HALO_MARGIN)
    for axis, (halo, sizes, what) in enumerate(zip(depth, array.chunks, ("rows", "columns"))):
        if len(sizes) > 1 and min(sizes) < halo:
            raise ReliefError(
                f"a radius of {radius} m needs a halo of {halo} {what} (ceil(radius / spacing) + "
                f"{RADIUS_HALO_MARGIN}), deeper than a chunk of {min(sizes)} {what}: give chunks "
                f"of at least {depth[0]} x {depth[1]} samples"
            )
    _check_options(options)
    count = sum(n for _, n in bands)
    block = functools.partial(_shade_overlapped_block, layers=[name for name, _ in bands],
                              depth=depth, options=options)
    stacked = da.map_overlap(
        block,
        array,
        depth={0: depth[0], 1: depth[1]},
        boundary="none",
        trim=False,
        allow_rechunk=False,
        new_axis=0,
        chunks=((count,),) + array.chunks,
        dtype=np.float32,
        meta=np.empty((0, 0, 0), np.float32),
        token="relief-shade-radius",
    )
    dataset = _dataset(stacked, bands, coords, dims)
    if keep_crs is not None:
        dataset = dataset.rio.write_crs(keep_crs)
    return dataset


def _shade_overlapped_block(block, layers, depth, options, block_info=None):
    """One chunk with its halo, shaded by ``relief.shade``, its layers stacked and cut back to
    the chunk: (bands, rows, columns)."""
    out = block_info[None]
    _, row, col = out["chunk-location"]
    _, rows, cols = out["num-chunks"]
    _, height, width = out["chunk-shape"]
    top = depth[0] if row > 0 else 0
    left = depth[1] if col > 0 else 0
    shaded = relief.shade(block, **{"threads": _task_threads(), **options})
    stacked = _stack(shaded, layers, *block.shape)
    return stacked[:, top:top + height, left:left + width]


def _array_chunks(chunks, shape):
    """``chunks`` (an int, a pair, or None: 2048) as dask takes them for ``shape``."""
    rows, cols = _pair(DEFAULT_CHUNK if chunks is None else chunks, "chunks")
    return (min(rows, max(shape[0], 1)), min(cols, max(shape[1], 1)))


def _spacing(spacing):
    """The grid's (dx, dy) in metres from ``relief.shade``'s ``spacing`` (a number, a pair or
    the georeference dict of ``relief.read``; None: 1)."""
    if spacing is None:
        return 1.0, 1.0
    if isinstance(spacing, Mapping):
        spacing = spacing.get("spacing")
    try:
        if np.ndim(spacing) == 0:
            dx = dy = float(spacing)
        else:
            dx, dy = (float(v) for v in spacing)
    except (TypeError, ValueError):
        raise ReliefError(
            "spacing must be a number, a pair (dx, dy) or the georeference dict read() returns"
        ) from None
    if not (dx > 0 and dy > 0 and math.isfinite(dx) and math.isfinite(dy)):
        raise ReliefError(f"spacing ({dx}, {dy}) must be positive")
    return dx, dy


def _check_options(options):
    """Raises relief.shade's error for ``options`` it refuses (with the command line's
    message), on a tiny array, before any task (``max_memory``, a source's, left out)."""
    relief.shade(np.zeros((3, 3), np.float32),
                 **{key: value for key, value in options.items() if key != "max_memory"})


# Shared by both forms.


def _layer_bands(options):
    """The layers asked for by ``options``, each with its number of bands (the horizon's
    directions, 1 for the others)."""
    defaults = _shade_defaults()
    layers = options.get("layers", defaults["layers"])
    if isinstance(layers, str):
        raise ReliefError(f"layers must be a list of layer names, not the string {layers!r}")
    azimuths = options.get("azimuths", defaults["azimuths"])
    return [(name, azimuths if name == "horizon" else 1) for name in layers]


def _shade_defaults():
    """``relief.shade``'s default layers and azimuths."""
    import inspect

    parameters = inspect.signature(relief.shade).parameters
    azimuths = parameters["azimuths"].default
    return {"layers": ["combined"], "azimuths": azimuths}


def _stack(shaded, layers, rows, cols):
    """The arrays of ``shaded`` (``relief.shade``'s dict) of ``layers``, stacked as one
    float32 (bands, rows, cols) array."""
    return np.concatenate(
        [np.asarray(shaded[name], np.float32).reshape(-1, rows, cols) for name in layers]
    )


def _dataset(stacked, bands, coords, dims, nodata=None):
    """The Dataset of ``stacked`` (bands, rows, cols): a variable per layer of ``bands``,
    sharing its chunks' tasks, with ``coords`` on ``dims``; each variable's ``long_name`` its
    bands' names as ``relief shade`` describes them, NaN at voids, written to a file as
    ``nodata`` (the source's; None: NaN)."""
    variables, first = {}, 0
    coords = dict(coords)
    for name, n in bands:
        if name == "horizon":
            data, var_dims = stacked[first:first + n], ("azimuth",) + tuple(dims)
            azimuths = np.arange(n, dtype=np.float64) * 360.0 / n
            coords["azimuth"] = azimuths
            long_name = tuple(f"horizon-{azimuth:05.1f}" for azimuth in azimuths)
        else:
            data, var_dims, long_name = stacked[first], tuple(dims), name
        first += n
        variables[name] = xarray.Variable(var_dims, data, {"long_name": long_name})
    dataset = xarray.Dataset(variables, coords=coords)
    if "azimuth" in dataset.coords:
        dataset["azimuth"].attrs.update(units="degrees", long_name="clockwise from north")
    for name in dataset.data_vars:
        if nodata is None or np.isnan(nodata):
            dataset[name].rio.write_nodata(np.float32(np.nan), inplace=True)
        else:
            # NaN in memory, the source's nodata in a file (xarray's encoding), as relief
            # shade writes the voids.
            dataset[name].rio.write_nodata(np.float32(nodata), encoded=True, inplace=True)
    return dataset


def _pair(value, what):
    """An int or a pair of ints as (rows, columns), each at least 1."""
    try:
        if np.ndim(value) == 0:
            pair = (int(value), int(value))
            exact = pair[0] == value
        else:
            rows, cols = value
            pair = (int(rows), int(cols))
            exact = pair == (rows, cols)
    except (TypeError, ValueError):
        exact = False
    if not exact or min(pair) < 1:
        raise ReliefError(f"{what} must be a positive number of samples or a pair (rows, columns)")
    return pair


def _split(total, size):
    """The sizes of the chunks of ``size`` that cover ``total``."""
    full, rest = divmod(total, size)
    return (size,) * full + ((rest,) if rest else ())


# The fly-through.

_scenes = {}
_scenes_lock = threading.Lock()


def _render_frame(input, options, camera, size, file, png_compression):
    """Renders one frame of a fly-through to ``file`` (on a worker, on one thread of it: see
    ``_task_threads``); returns the file. The scene is opened once per worker process and
    shared by its threads."""
    key = (input, dask.base.tokenize(options))
    with _scenes_lock:
        scene = _scenes.get(key)
        if scene is None:
            scene = _scenes[key] = relief.open(input, **options)
    rgb, _ = scene.render(camera, size, aa="off", threads=_task_threads())
    relief.write_png(file, rgb, compression=png_compression)
    return file
