#!/usr/bin/env python3
"""Which way rvt-py counts its directions: a flat DEM (row 0 north) with high ground on one
side, and rvt-py's anisotropic SVF with all the weight on one of four directions (polynomial
8, minimum weight 0): the direction whose value drops is the one that looks at the high ground.

    python3 bench/gis/rvt_directions.py      (needs rvt-py: pip install --no-deps rvt-py)
"""

import numpy as np
import rvt.vis


def main():
    print("| high ground | rvt direction 0 | 90 | 180 | 270 |")
    print("|---|---|---|---|---|")
    sides = {"north": (slice(0, 15), slice(None)), "east": (slice(None), slice(26, None)),
             "south": (slice(26, None), slice(None)), "west": (slice(None), slice(0, 15))}
    for side, region in sides.items():
        dem = np.zeros((41, 41), np.float32)
        dem[region] = 10.0
        values = []
        for main_direction in (0, 90, 180, 270):
            out = rvt.vis.sky_view_factor_compute(dem, radius_max=10, num_directions=4, compute_svf=False,
                                                  compute_asvf=True, a_main_direction=main_direction,
                                                  a_poly_level=8, a_min_weight=0.0)
            values.append(f"{out['asvf'][20, 20]:.3f}")
        print(f"| {side} | " + " | ".join(values) + " |")


if __name__ == "__main__":
    main()
