"""relief: exact, fast ray casting of terrain, from NumPy.

Open any input relief takes as a ``Scene`` (a height file, an MLHM scene, a material-stacks
file, a tile store, or the default fBm terrain) and render it as ``relief render`` does; step
an MLHM scene's erosion as ``relief simulate`` does and read its state as arrays; render a
height field given as an array to a picture and its depth, make its shade layers (cast
shadows, the sky-view factor, the hillshade) on its own grid, read height files as north-up
arrays with their georeference, and trace arrays of rays against a terrain's surface, with
the same conventions, defaults and messages as the ``relief`` command line:

>>> import relief
>>> scene = relief.open("dem.tif")                          # doctest: +SKIP
>>> rgb, depth = scene.render(size=(640, 360))              # doctest: +SKIP
>>> relief.write_png("dem.png", rgb)                         # doctest: +SKIP
>>> heights, georeference = relief.read("dem.tif")          # doctest: +SKIP
>>> rgb, depth = relief.render(heights, georeference, size=(640, 360))  # doctest: +SKIP
>>> valley = relief.open("valley.json")                      # doctest: +SKIP
>>> relief.simulate(valley, 100, seed=1)                     # doctest: +SKIP
>>> water = valley.state()["water"]                          # doctest: +SKIP

World coordinates: x east, y north, z up, in the units of the spacing (metres for a
georeferenced file). Arrays of heights have row 0 at the north edge. Bad arguments raise
``relief.ReliefError`` (a ``ValueError``); files that cannot be read raise ``OSError``.
"""

from ._relief import (
    ReliefError,
    Scene,
    __version__,
    flight_plan,
    intersect,
    open,
    read,
    render,
    shade,
    shade_window,
    simulate,
    source_info,
    sun_position,
    viewshed,
    write_png,
)

__all__ = [
    "ReliefError",
    "Scene",
    "__version__",
    "flight_plan",
    "intersect",
    "open",
    "read",
    "render",
    "shade",
    "shade_window",
    "simulate",
    "source_info",
    "sun_position",
    "viewshed",
    "write_png",
]
