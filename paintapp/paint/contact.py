"""How far a pressed tip's contact with the paint reaches from its apex, in the canvas plane.

The tip's whole body (a round brush's belly) reaches far wider than the part of it pressed into
the paint. :func:`contact_radius_m` measures the latter: the largest distance from the axis of
any point of the tip's cut at the pressed height (:class:`brushes.Section`, in the tip's body
frame, the cut the bristle texture takes as the footprint), sampled on :data:`DIRECTIONS` rays of
:data:`RAY_SAMPLES` points out to ``reach_m``, the farthest sample inside plus one sample's
spacing: an upper bound on the cut's extent along the rays, over it by less than
``reach_m / (RAY_SAMPLES - 1)``. A cut with no sample inside (a tip lifted clear) has radius 0.
"""

from __future__ import annotations

import numpy as np

from brushes import Section, TipShape

#: Rays and points along each ray of the contact's sampling.
DIRECTIONS = 32
RAY_SAMPLES = 64


def _ray_points(reach_m: float) -> tuple[np.ndarray, np.ndarray]:
    """The sample points (DIRECTIONS * RAY_SAMPLES, 2) and each one's distance from the axis."""
    angles = np.linspace(0.0, 2.0 * np.pi, DIRECTIONS, endpoint=False)
    radii = np.linspace(0.0, reach_m, RAY_SAMPLES)
    points = np.stack(
        [np.outer(np.cos(angles), radii).ravel(), np.outer(np.sin(angles), radii).ravel()], axis=1
    )
    return points, np.tile(radii, DIRECTIONS)


def contact_radius_m(tip: TipShape, height_m: float, reach_m: float) -> float:
    """The contact's radius (module docstring), m, of ``tip`` cut ``height_m`` above its apex,
    sampled out to ``reach_m`` (at least the cut's true extent, e.g. the body's lateral
    extent)."""
    if not (reach_m > 0.0 and height_m >= 0.0):
        return 0.0
    points, radii = _ray_points(reach_m)
    inside = Section(tip, height_m).sdf(points) <= 0.0
    if not inside.any():
        return 0.0
    step = reach_m / (RAY_SAMPLES - 1)
    return min(float(radii[inside].max()) + step, reach_m)
