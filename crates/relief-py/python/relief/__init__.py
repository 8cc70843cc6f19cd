"""relief: exact, fast ray casting of terrain, from NumPy.

Render a height field to a picture and its depth, make its shade layers (cast shadows, the
sky-view factor, the hillshade) on its own grid, read height files as north-up arrays with
their georeference, and trace arrays of rays against a terrain's surface, with the same
conventions, defaults and messages as the ``relief`` command line:

>>> import relief
>>> heights, georeference = relief.read("dem.tif")          # doctest: +SKIP
>>> rgb, depth = relief.render(heights, georeference, size=(640, 360))  # doctest: +SKIP
>>> relief.write_png("dem.png", rgb)                         # doctest: +SKIP

World coordinates: x east, y north, z up, in the units of the spacing (metres for a
georeferenced file). Arrays of heights have row 0 at the north edge. Bad arguments raise
``relief.ReliefError`` (a ``ValueError``); files that cannot be read raise ``OSError``.
"""

from ._relief import ReliefError, __version__, intersect, read, render, shade, write_png

__all__ = ["ReliefError", "__version__", "intersect", "read", "render", "shade", "write_png"]
