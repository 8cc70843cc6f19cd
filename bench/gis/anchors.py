"""The tools relief's GIS layers are compared with (rvt-py, xarray-spatial, gdaldem): how they
install here and how each is called, timed, on a DEM held as a raster array (row 0 north)."""

import importlib
import shutil
import subprocess
import sys
import time

import numpy as np

PIP = [sys.executable, "-m", "pip", "install", "--quiet", "--disable-pip-version-check",
       "--root-user-action=ignore"]


def install_anchors():
    """Installs what is missing: rvt-py (without its GDAL requirement, which does not build
    without gdal-config), xarray-spatial, rasterio, and Debian's gdal-bin for gdaldem."""
    def missing(module):
        try:
            importlib.import_module(module)
            return False
        except ImportError:
            return True

    if missing("rasterio") or missing("scipy") or missing("matplotlib"):
        subprocess.run(PIP + ["numpy", "scipy", "matplotlib", "rasterio"], check=True)
    if missing("rvt.vis"):
        subprocess.run(PIP + ["--no-deps", "rvt-py"], check=True)
    if missing("xrspatial"):
        subprocess.run(PIP + ["xarray-spatial"], check=True)
    if not shutil.which("gdaldem"):
        env = {"DEBIAN_FRONTEND": "noninteractive", "PATH": "/usr/sbin:/usr/bin:/sbin:/bin"}
        subprocess.run(["apt-get", "update", "-qq"], check=True, env=env)
        subprocess.run(["apt-get", "install", "-y", "-qq", "gdal-bin"], check=True, env=env,
                       stdout=subprocess.DEVNULL)


def timed(function, *args, **kwargs):
    """(seconds, result) of one call."""
    start = time.perf_counter()
    result = function(*args, **kwargs)
    return time.perf_counter() - start, result


def rvt_horizon_layers(dem, resolution, directions, r_max, svf=True, opns=False, asvf=False,
                       asvf_dir=315.0):
    """rvt-py's sky_view_factor (noise removal off, anisotropy level 1: polynomial 4, minimum
    weight 0.4) on a float32 copy of dem; returns (seconds, {"svf", "opns", "asvf"}).

    RVT counts its directions counter-clockwise from north (its 90 looks west: checked on a
    wall), so its asvf_dir 315 is the compass's 45; pass 360 - compass for a compass direction."""
    import rvt.vis

    heights = np.asarray(dem, dtype=np.float32)
    return timed(rvt.vis.sky_view_factor, heights, resolution, compute_svf=svf, compute_opns=opns,
                 compute_asvf=asvf, svf_n_dir=directions, svf_r_max=r_max, asvf_dir=asvf_dir,
                 asvf_level=1)


def xrspatial_hillshade(dem, spacing, azimuth, altitude):
    """xarray-spatial's hillshade of dem (heights divided by the square cell's spacing, since it
    takes one cell as one unit), timed on its second call (the first compiles); returns
    (seconds, max(0, cosine of the sun's incidence)): it returns (cosine + 1) / 2 from central
    differences, without clamping."""
    import xarray as xr
    import xrspatial

    grid = xr.DataArray(np.asarray(dem, dtype=np.float32) / spacing, dims=["y", "x"])
    xrspatial.hillshade(grid, azimuth=azimuth, angle_altitude=altitude)
    seconds, shade = timed(xrspatial.hillshade, grid, azimuth=azimuth, angle_altitude=altitude)
    return seconds, np.maximum(0.0, 2.0 * np.asarray(shade.data, dtype=np.float64) - 1.0)


def gdaldem_hillshade(dem_path, out_path, multidirectional=True, azimuth=315.0, altitude=45.0):
    """`gdaldem hillshade` of a projected DEM in metres; returns (seconds, the 8-bit band, 0 for
    its nodata border)."""
    import rasterio

    command = ["gdaldem", "hillshade", str(dem_path), str(out_path), "-q", "-alt", str(altitude)]
    command += ["-multidirectional"] if multidirectional else ["-az", str(azimuth)]
    seconds, _ = timed(subprocess.run, command, check=True)
    with rasterio.open(out_path) as f:
        return seconds, f.read(1)
