"""What part of the canvas is shown, and how the scene is lit.

:class:`ViewRect` is an upright rectangle of the canvas (exports, tests); the painting window's
zoomed, panned and turned view is :class:`paintapp.render.view_transform.CanvasView`. The renderer
takes either: both give the matrix to clip space, the size of an output pixel and the canvas
rectangle in sight.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class ViewRect:
    """The rectangle of canvas space, metres, that fills the output (x0 < x1, y0 < y1)."""

    x0_m: float
    y0_m: float
    x1_m: float
    y1_m: float

    @classmethod
    def whole(cls, size_m: tuple[float, float]) -> ViewRect:
        """The whole canvas of size (w, h) metres."""
        return cls(0.0, 0.0, float(size_m[0]), float(size_m[1]))

    def matrix(self) -> np.ndarray:
        """3x3 matrix taking (x_m, y_m, 1) to clip coordinates (row-major, as maths writes it)."""
        sx = 2.0 / (self.x1_m - self.x0_m)
        sy = 2.0 / (self.y1_m - self.y0_m)
        m = np.array(
            [[sx, 0.0, -1.0 - sx * self.x0_m], [0.0, sy, -1.0 - sy * self.y0_m], [0.0, 0.0, 1.0]]
        )
        return m.astype(np.float32)

    def metres_per_pixel(self, size: tuple[int, int]) -> float:
        """Larger of the x and y extents of one output pixel, metres, for an output (W, H)."""
        return max((self.x1_m - self.x0_m) / size[0], (self.y1_m - self.y0_m) / size[1])

    def visible_box_m(self) -> tuple[float, float, float, float]:
        """The canvas rectangle (x0, y0, x1, y1), metres, that the output shows."""
        return self.x0_m, self.y0_m, self.x1_m, self.y1_m


@dataclass(frozen=True)
class Lighting:
    """A directional light over the canvas and how the paint relief and wetness show.

    Attributes:
        azimuth_deg: where the light comes from, counter-clockwise from +x (135 = upper left).
        elevation_deg: angle of the light above the canvas plane, (0, 90].
        ambient: share of the light that ignores relief, [0, 1]. Flat paint always shows its
            Kubelka-Munk colour; slopes towards the light are brighter, away darker.
        relief: exaggeration of the paint height for shading (1 = true geometry).
        specular: highlight strength of fully wet paint (dry paint is matte).
        shininess: Blinn-Phong exponent of the wet highlight.
        enabled: False renders the unlit Kubelka-Munk colour.
    """

    azimuth_deg: float = 135.0
    elevation_deg: float = 45.0
    ambient: float = 0.35
    relief: float = 1.0
    specular: float = 0.4
    shininess: float = 48.0
    enabled: bool = True

    def __post_init__(self) -> None:
        values = (self.azimuth_deg, self.elevation_deg, self.ambient, self.relief, self.specular)
        if not all(math.isfinite(v) for v in (*values, self.shininess)):
            raise ValueError("lighting parameters must be finite")
        if not 0.0 < self.elevation_deg <= 90.0:
            raise ValueError(f"elevation must be in (0, 90] degrees, got {self.elevation_deg}")
        if not 0.0 <= self.ambient <= 1.0:
            raise ValueError(f"ambient must be in [0, 1], got {self.ambient}")

    def direction(self) -> np.ndarray:
        """Unit vector from the canvas towards the light, canvas frame, shape (3,)."""
        az, el = math.radians(self.azimuth_deg), math.radians(self.elevation_deg)
        return np.array([math.cos(el) * math.cos(az), math.cos(el) * math.sin(az), math.sin(el)])
