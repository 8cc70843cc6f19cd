"""Type stubs of relief's native module (re-exported by the package ``relief``)."""

from collections.abc import Mapping
from os import PathLike
from typing import Any, Literal, Optional, Sequence, Tuple, TypedDict, Union

import numpy as np
import numpy.typing as npt

__version__: str

class ReliefError(ValueError):
    """An argument relief cannot use, with the command line's message."""

class DegreeSpacing(TypedDict):
    """A georeference given in degrees, converted to metres at ``latitude``."""

    dlon: float
    dlat: float
    latitude: float

class Georeference(TypedDict):
    """Where a grid read from a file sits in relief's world and in its own CRS, and what the
    file said.

    ``spacing`` and ``origin`` are in relief's world (metres); ``geotransform`` (GDAL's
    order) and ``transform`` (rasterio's ``Affine`` order) place the north-up array in the
    file's own CRS and units, as GDAL reads it; ``world_geotransform`` in relief's world.
    ``crs`` is ``"EPSG:<code>"`` (or the CRS's name, or ``None``), ``crs_wkt`` its ESRI WKT
    where relief can write it. ``height_unit`` is ``"metre"``, ``"foot"`` or
    ``"US survey foot"``, ``z_scale`` the metres in one unit.
    """

    spacing: Tuple[float, float]
    origin: Tuple[float, float]
    geotransform: Tuple[float, float, float, float, float, float]
    transform: Tuple[float, float, float, float, float, float]
    world_geotransform: Tuple[float, float, float, float, float, float]
    crs: Optional[str]
    epsg: Optional[int]
    crs_wkt: Optional[str]
    height_unit: Literal["metre", "foot", "US survey foot"]
    height_unit_reason: str
    z_scale: float
    nodata: Optional[float]
    format: str
    sample_type: str
    georeferenced: bool
    from_degrees: Optional[DegreeSpacing]

class Camera(TypedDict, total=False):
    """A pinhole camera: ``eye`` and ``target`` together, ``up`` and ``fov`` optional."""

    eye: Sequence[float]
    target: Sequence[float]
    up: Sequence[float]
    fov: float

Spacing = Union[float, Tuple[float, float], Mapping[str, Any], None]
Surface = Literal["triangles", "boxes"]
TracerName = Literal["mipmap", "naive"]
Voids = Literal["fill", "hole"]
ColourMapName = Literal["terrain", "bathymetry", "greys", "viridis", "cividis", "magma"]
ShadingNormalsName = Literal["smooth", "faceted"]

def read(
    path: Union[str, PathLike[str]],
    *,
    array: Optional[str] = None,
    png_encoding: Literal["grey", "terrain-rgb", "terrarium"] = "grey",
    max_memory: Optional[int] = None,
    z_unit: Optional[Literal["m", "ft", "us-ft"]] = None,
) -> Tuple[npt.NDArray[np.float32], Georeference]:
    """Read a height file as ``(heights, georeference)``.

    ``heights`` is float32 of shape (rows, columns) with row 0 the north edge and NaN for
    voids, in the file's height unit (``georeference["height_unit"]``; ``z_unit`` overrides
    it); ``relief.render(*relief.read(path))`` draws what ``relief render PATH`` draws. A
    .npy/.npz grid's row 0 is relief's south edge, so its heights are
    ``numpy.flipud(numpy.load(path))``. Raises ``OSError`` (``FileNotFoundError``, ...)
    with relief's message.
    """

def render(
    heights: npt.ArrayLike,
    spacing: Spacing = None,
    *,
    origin: Optional[Tuple[float, float]] = None,
    z_scale: float = 1.0,
    camera: Optional[Camera] = None,
    size: Tuple[int, int] = (1280, 720),
    surface: Surface = "triangles",
    tracer: TracerName = "mipmap",
    sun: Tuple[float, float] = (315.0, 35.0),
    shadows: bool = True,
    exposure: float = 1.0,
    voids: Voids = "fill",
    colormap: Optional[ColourMapName] = None,
    height_range: Optional[Tuple[float, float]] = None,
    sea_level: Optional[float] = None,
    legend: bool = False,
    scale_bar: bool = False,
    north_arrow: bool = False,
    shading_normals: Optional[ShadingNormalsName] = None,
) -> Tuple[npt.NDArray[np.uint8], npt.NDArray[np.float32]]:
    """Render a north-up heights array as ``relief render`` does: ``(rgb, depth)``.

    ``rgb`` is uint8 (height, width, 3); ``depth`` float32 (height, width), row 0 the top
    row, the distance from the eye along each pixel's unit ray, +inf for a miss.
    ``spacing`` is a number, ``(dx, dy)`` or the georeference dict ``read`` returns.
    ``camera`` is ``None`` (automatic framing) or ``{eye, target, up, fov}``.
    ``colormap`` over ``height_range`` (metres before ``z_scale``; default the terrain's
    own), ``sea_level`` for ``bathymetry`` (default 0), and the ``legend``, ``scale_bar``
    (orthographic cameras only: ``relief.open(...).render``) and ``north_arrow`` as
    ``relief render``'s ``--colormap``, ``--height-range``, ``--sea-level``, ``--legend``,
    ``--scale-bar`` and ``--north-arrow``. ``shading_normals``: ``"smooth"`` (the default
    for triangles) or ``"faceted"``, as ``--shading-normals``; boxes are always faceted.
    """

ShadeLayer = Literal["shadow", "sky", "hillshade", "combined", "horizon", "sky-aniso",
                     "openness-pos", "openness-neg", "sky-illumination", "hillshade-multi",
                     "insolation", "sun-hours"]

def shade_window(
    source: Union[str, "PathLike[str]"],
    window: Tuple[int, int, int, int],
    *,
    layers: Sequence[ShadeLayer] = ("combined",),
    suns: Sequence[Tuple[float, float]] = ((315.0, 45.0),),
    sun_radius: float = 0.0,
    sun_rays: int = 16,
    azimuths: int = 32,
    observer_height: float = 0.01,
    radius: Optional[float] = None,
    earth_curvature: Optional[float] = None,
    sky_model: Literal["overcast", "uniform"] = "overcast",
    date: Optional[str] = None,
    time: Optional[str] = None,
    timezone: str = "Z",
    step: str = "15m",
    latitude: Optional[float] = None,
    longitude: Optional[float] = None,
    surface: Surface = "triangles",
    max_memory: Optional[int] = None,
    threads: Optional[int] = None,
) -> dict[str, npt.NDArray[np.float32]]:
    """The shade layers of the window ``(col_off, row_off, width, height)`` (north-up pixels)
    of a tile store or height file, bit for bit what ``relief shade SOURCE`` writes there."""
    ...

def source_info(
    source: Union[str, "PathLike[str]"], *, max_memory: Optional[int] = None
) -> dict[str, Any]:
    """The size, tile side and georeference of a tile store or height file."""
    ...

def shade(
    heights: npt.ArrayLike,
    spacing: Spacing = None,
    *,
    origin: Optional[Tuple[float, float]] = None,
    z_scale: float = 1.0,
    layers: Sequence[ShadeLayer] = ("combined",),
    suns: Sequence[Tuple[float, float]] = ((315.0, 45.0),),
    sun_radius: float = 0.0,
    sun_rays: int = 16,
    azimuths: int = 32,
    observer_height: float = 0.01,
    radius: Optional[float] = None,
    earth_curvature: Optional[float] = None,
    sky_model: Literal["overcast", "uniform"] = "overcast",
    date: Optional[str] = None,
    time: Optional[str] = None,
    timezone: str = "Z",
    step: str = "15m",
    latitude: Optional[float] = None,
    longitude: Optional[float] = None,
    surface: Surface = "triangles",
    voids: Voids = "fill",
    threads: Optional[int] = None,
) -> dict[str, npt.NDArray[np.float32]]:
    """The shade layers of ``heights``, each shaped like it (north-up, NaN at its voids); the
    horizon a ``(azimuths, rows, columns)`` array of degrees.

    ``shadow``: the fraction of the suns each sample sees (exact cast shadows); ``sky``: the
    sky-view factor from exact horizons in ``azimuths`` directions; ``hillshade``: Lambert's
    cosine with Horn's gradient; ``combined``: the map layer; ``horizon``, ``sky-aniso``,
    ``openness-pos``, ``openness-neg`` (degrees), ``sky-illumination``, ``hillshade-multi``,
    ``insolation`` (Wh/m²) and ``sun-hours`` over ``date`` (a day or ``"FROM..TO"``, every
    ``step``, clocks ``timezone``, seen from ``latitude``, ``longitude``) as ``relief shade``
    writes them; ``date`` with ``time`` places the one sun of the shadow layers.
    """

def viewshed(
    heights: npt.ArrayLike,
    spacing: Spacing = None,
    *,
    origin: Optional[Tuple[float, float]] = None,
    z_scale: float = 1.0,
    observers: Sequence[Sequence[float]] = (),
    target_height: float = 0.0,
    radius: Optional[float] = None,
    surface: Surface = "triangles",
    voids: Voids = "fill",
) -> npt.NDArray[np.float32]:
    """Per sample of ``heights`` (north-up, NaN at its voids), how many of ``observers``
    see it: 0 or 1 for one observer. Each observer is ``(x, y)`` or ``(x, y, height)`` in
    world coordinates, the eye ``height`` (default 1.7) metres above the ground; a sample is
    seen when the segment from the eye to its point raised by ``target_height`` does not
    pass below the surface, within ``radius`` metres when given, as ``relief viewshed``.
    """

def intersect(
    heights: npt.ArrayLike,
    origins: npt.ArrayLike,
    directions: npt.ArrayLike,
    spacing: Spacing = None,
    *,
    origin: Optional[Tuple[float, float]] = None,
    z_scale: float = 1.0,
    surface: Surface = "triangles",
    tracer: TracerName = "mipmap",
    voids: Voids = "fill",
) -> npt.NDArray[np.float64]:
    """The ray parameter ``t`` (N,) of each ray's first hit, +inf for a miss.

    ``origins`` and ``directions`` have shape (N, 3) in world coordinates; directions need
    not be unit: the hit is at ``origins + t[:, None] * directions``.
    """

def write_png(
    path: Union[str, PathLike[str]],
    rgb: npt.NDArray[np.uint8],
    *,
    compression: Literal["none", "fast", "balanced", "high"] = "fast",
) -> None:
    """Write a uint8 (height, width, 3) picture, as ``render`` returns it, as an RGB PNG,
    compressed as ``relief render --png-compression`` (the same bytes).

    Raises ``ReliefError`` for another dtype or shape, ``OSError`` when the file cannot be
    written.
    """

class FlightCamera(TypedDict):
    """A fly-through frame's camera, as ``Scene.render`` takes it."""

    eye: Tuple[float, float, float]
    target: Tuple[float, float, float]
    up: Tuple[float, float, float]
    fov: float

class FlightFrame(TypedDict):
    """A frame of a fly-through: its number, its time on the camera path, its camera."""

    frame: int
    time_s: float
    camera: FlightCamera

def flight_plan(path: Union[str, PathLike[str]], frames: int) -> list[FlightFrame]:
    """The frames of a ``frames``-frame fly-through of the camera path ``path`` as ``relief
    flythrough`` plays it: times spread evenly over the path, cameras interpolated between
    its keys by the command line's code. Raises ``ReliefError`` for a file that is not a
    camera path, frames outside 1 to 100000 or an unusable camera (naming the frame),
    ``OSError`` when the file cannot be read.
    """

class SunPosition(TypedDict):
    """The sun at each time given, float64 arrays in degrees."""

    azimuth: npt.NDArray[np.float64]
    elevation: npt.NDArray[np.float64]
    apparent_elevation: npt.NDArray[np.float64]

def sun_position(
    latitude: float,
    longitude: float,
    times: Union[Sequence[Any], npt.NDArray[np.datetime64]],
    *,
    elevation: float = 0.0,
    pressure: float = 1013.25,
    temperature: float = 12.0,
    delta_t: float = 67.0,
) -> SunPosition:
    """The sun seen from ``latitude``, ``longitude`` (degrees) at each of ``times`` by NREL's
    solar position algorithm: ISO-8601 strings with an offset (``"2026-06-21T09:30:00+02:00"``),
    timezone-aware datetimes, or numpy datetime64 (UTC). ``azimuth`` clockwise from north,
    ``elevation`` without refraction, ``apparent_elevation`` with it (``pressure`` in mbar,
    ``temperature`` in C); ``elevation`` (the keyword) in metres, ``delta_t`` in seconds.
    """

class SceneCamera(TypedDict, total=False):
    """A scene's camera, as ``relief render``'s options: ``eye`` and ``target`` together (or
    ``target`` with ``view``), ``up``, ``fov``; ``view`` frames the scene from ``(azimuth,
    elevation)`` or ``(azimuth, elevation, distance)``; ``ortho`` and ``ortho_height`` make
    it orthographic."""

    eye: Sequence[float]
    target: Sequence[float]
    up: Sequence[float]
    fov: float
    view: Sequence[float]
    ortho: bool
    ortho_height: float

class SceneInfo(TypedDict, total=False):
    """What a scene is. ``size`` and ``spacing`` are ``None`` for a stacks terrain, ``crs``
    and ``epsg`` where the input names none; ``surface`` and ``tracer`` are a height field's,
    ``layers`` and ``step`` an MLHM scene's."""

    kind: Literal["height_field", "mlhm", "stacks", "tile_store"]
    description: str
    path: Optional[str]
    size: Optional[Tuple[int, int]]
    spacing: Optional[Tuple[float, float]]
    bounds: Tuple[Tuple[float, float, float], Tuple[float, float, float]]
    crs: Optional[str]
    epsg: Optional[int]
    warnings: list[str]
    surface: str
    tracer: str
    layers: int
    step: int

class SceneState(TypedDict):
    """An MLHM scene's erosion state. Planes are float32 ``(L, H, W)`` indexed
    ``[layer, y, x]`` with row 0 the south edge (as the scene file stores them); ``fluxes``
    is ``(L, H, W, 4)`` (right, up, left, down); ``layer_counts`` uint8 ``(H, W)``."""

    bedrock: npt.NDArray[np.float32]
    sand: npt.NDArray[np.float32]
    water: npt.NDArray[np.float32]
    ceiling: npt.NDArray[np.float32]
    sediment: npt.NDArray[np.float32]
    damage: npt.NDArray[np.float32]
    stability: npt.NDArray[np.float32]
    fluxes: npt.NDArray[np.float32]
    layer_counts: npt.NDArray[np.uint8]
    step: int
    cell_size: float

class Scene:
    """An input opened by ``relief.open``: a height field, an MLHM scene, a stacks terrain
    or a tile store."""

    def render(
        self,
        camera: Optional[SceneCamera] = None,
        size: Tuple[int, int] = (1280, 720),
        *,
        legend: bool = False,
        scale_bar: bool = False,
        north_arrow: bool = False,
        aa: Union[Literal["adaptive", "off"], int, None] = None,
        threads: Optional[int] = None,
    ) -> Tuple[npt.NDArray[np.uint8], npt.NDArray[np.float32]]:
        """``(rgb, depth)`` as ``relief render`` draws the scene: uint8 (height, width, 3) and
        float32 (height, width), +inf for a miss, pixel for pixel the command line's; with
        its ``--legend``, ``--scale-bar`` (orthographic cameras), ``--north-arrow`` and
        ``--aa`` (``"adaptive"``, the default, ``"off"`` or N); drawn on ``threads`` threads
        (None: the process's shared pool), the same picture for any."""
    def shade(
        self,
        layers: Sequence[ShadeLayer] = ("combined",),
        suns: Sequence[Tuple[float, float]] = ((315.0, 45.0),),
        sun_radius: float = 0.0,
        sun_rays: int = 16,
        azimuths: int = 32,
        observer_height: float = 0.01,
        radius: Optional[float] = None,
        earth_curvature: Optional[float] = None,
        sky_model: Literal["overcast", "uniform"] = "overcast",
        date: Optional[str] = None,
        time: Optional[str] = None,
        timezone: str = "Z",
        step: str = "15m",
        latitude: Optional[float] = None,
        longitude: Optional[float] = None,
    ) -> dict[str, npt.NDArray[np.float32]]:
        """A height field's shade layers, north-up; ``ReliefError`` for any other scene."""
    @property
    def info(self) -> SceneInfo:
        """What the scene is: kind, size, spacing, bounds, CRS, ..."""
    def state(self) -> SceneState:
        """An MLHM scene's erosion state as arrays (``ReliefError`` for any other scene)."""
    def write(self, path: Union[str, PathLike[str]]) -> None:
        """Write an MLHM scene's state as ``relief simulate -o path`` does (.json or .mlhm)."""

def open(
    path: Union[str, PathLike[str], None] = None,
    *,
    spacing: Union[float, Tuple[float, float], None] = None,
    north_up: bool = False,
    z_scale: float = 1.0,
    voids: Optional[Voids] = None,
    max_memory: Optional[int] = None,
    png_encoding: Literal["grey", "terrain-rgb", "terrarium"] = "grey",
    array: Optional[str] = None,
    z_unit: Optional[Literal["m", "ft", "us-ft"]] = None,
    fbm_size: Optional[int] = None,
    seed: Optional[int] = None,
    surface: Optional[Surface] = None,
    tracer: Optional[str] = None,
    mode: Optional[Literal["boxes", "smooth", "mesh"]] = None,
    sigma: Optional[float] = None,
    preset: Optional[Literal["low", "mid", "high", "max"]] = None,
    ao: bool = True,
    tau: Optional[float] = None,
    voxel_height: Optional[float] = None,
    max_error_px: Optional[float] = None,
    cache_mb: Optional[int] = None,
    sun: Tuple[float, float] = (315.0, 35.0),
    shadows: bool = True,
    exposure: float = 1.0,
    texture: Union[str, PathLike[str], None] = None,
    cache_dir: Union[str, PathLike[str], None] = None,
    no_cache: bool = False,
    colormap: Optional[ColourMapName] = None,
    height_range: Optional[Tuple[float, float]] = None,
    sea_level: Optional[float] = None,
    shading_normals: Optional[ShadingNormalsName] = None,
) -> Scene:
    """Open any input ``relief render`` takes (``None``: the default fBm terrain) as a scene,
    with ``relief render``'s options and defaults. Raises ``ReliefError`` for options relief
    cannot use, ``OSError`` for an input that cannot be read."""

def simulate(
    scene: Scene,
    steps: int,
    *,
    seed: int = 1,
    rain: Optional[float] = None,
    evaporation: Optional[float] = None,
    dt: Optional[float] = None,
) -> int:
    """Step an MLHM scene's erosion as ``relief simulate`` does (the GIL released); returns
    the steps simulated in all. ``scene.write`` then writes the bytes ``relief simulate``
    writes after as many steps with the same seed."""
